//! Fields reduced by the motion's own invariance (`motion::Invariance`,
//! `field::Orbits`) against direct simulation of every grid point.
//!
//! A screw about a horizontal axis moves the points of each line along the
//! axis alike, one about a vertical axis the points of each circle about it
//! (turned with them), a translation every point alike: the reduced field
//! must equal the directly simulated one to the integrator's round-off
//! sensitivity (≈ 1e-11 relative, `results/library_speed.md`), with the same
//! validity everywhere.

use crate::basis::{Primitive, PrimitiveKind};
use crate::field::{Field, FieldKind, FieldSettings, Grid, Orbits};
use crate::motion::{Axes, FourierTerm, Invariance, Motion, Signals};

/// 7 × 7 over ±4 cm.
const GRID7: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [7, 7],
};

fn settings() -> FieldSettings {
    let mut s = FieldSettings {
        phases: 6,
        ..FieldSettings::default()
    };
    s.numerics.steps_per_cycle = 32;
    s
}

fn primitive(kind: PrimitiveKind, rotation_deg: f64, shift: [f64; 2]) -> Motion {
    Primitive {
        rotation_deg,
        shift,
        ..Primitive::new(kind)
    }
    .motion()
}

/// Largest |reduced − direct| over the largest direct magnitude, after
/// checking that the validity agrees at every point.
fn worst_difference(motion: &Motion, kind: FieldKind) -> f64 {
    let s = settings();
    let reduced = Field::compute(motion, &GRID7, kind, &s, &|| {});
    let direct = Field::compute_by(motion, &GRID7, kind, &s, Invariance::None, &|| {});
    assert_eq!(reduced.validity, direct.validity, "{motion:?} {kind:?}");
    assert!(direct.valid_count() > 0);
    let scale = direct.max_magnitude();
    assert!(scale > 0.0);
    reduced
        .vectors
        .iter()
        .zip(&direct.vectors)
        .map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1]) / scale)
        .fold(0.0, f64::max)
}

/// The number of distinct values of the integer `key(i, j)` over the
/// 7 × 7 grid's indices: the family count in exact arithmetic (GRID7's
/// points are (−3 + i, −3 + j) · 4/300 m).
fn exact_families(key: impl Fn(i64, i64) -> i64) -> usize {
    let mut keys: Vec<i64> = (0..7)
        .flat_map(|j| (0..7).map(move |i| (i, j)))
        .map(|(i, j)| key(i, j))
        .collect();
    keys.sort_unstable();
    keys.dedup();
    keys.len()
}

fn families(motion: &Motion) -> usize {
    Orbits::of(&GRID7.points(), motion.invariance())
        .representatives
        .len()
}

#[test]
fn lines_along_a_horizontal_axis_move_alike() {
    // Columns i; anti-diagonals i + j (the axis turned 45°).
    let columns = exact_families(|i, _| i);
    let diagonals = exact_families(|i, j| i + j);
    assert_eq!((columns, diagonals), (7, 13));
    for (rotation, shift, expect) in [
        (0.0, [0.0, 0.0], columns),
        (45.0, [0.005, -0.005], diagonals),
    ] {
        for kind in [PrimitiveKind::LineSink, PrimitiveKind::SkewSource] {
            let m = primitive(kind, rotation, shift);
            assert!(matches!(m.invariance(), Invariance::Along(_)));
            assert_eq!(families(&m), expect, "{kind:?} at {rotation}°");
            for field in [FieldKind::Force, FieldKind::Velocity] {
                let d = worst_difference(&m, field);
                assert!(d <= 1e-9, "{kind:?} {rotation}° {field:?}: {d:e}");
            }
        }
    }
}

#[test]
fn circles_about_a_vertical_axis_move_alike_turned() {
    // Squared radii in units of (1/300 m)²: about the centre, and about
    // (1 cm, 0) = (3/300 m, 0).
    let centred = exact_families(|i, j| (4 * i - 12).pow(2) + (4 * j - 12).pow(2));
    let shifted = exact_families(|i, j| (4 * i - 15).pow(2) + (4 * j - 12).pow(2));
    assert_eq!((centred, shifted), (10, 24));
    for (kind, shift, expect) in [
        (PrimitiveKind::ScaledCircle, [0.0, 0.0], centred),
        (PrimitiveKind::Circle, [0.0, 0.0], centred),
        (PrimitiveKind::ScaledCircle, [0.01, 0.0], shifted),
    ] {
        let m = primitive(kind, 20.0, shift);
        assert_eq!(m.invariance(), Invariance::About(shift));
        assert_eq!(families(&m), expect, "{kind:?} about {shift:?}");
        for field in [FieldKind::Force, FieldKind::Velocity] {
            let d = worst_difference(&m, field);
            assert!(d <= 1e-9, "{kind:?} about {shift:?} {field:?}: {d:e}");
        }
    }
}

#[test]
fn a_translation_moves_every_point_alike() {
    let trans = primitive(PrimitiveKind::Trans, 30.0, [0.01, 0.0]);
    let term = |amplitude, phase, harmonic| FourierTerm {
        amplitude,
        phase,
        harmonic,
    };
    let shaken = Motion::Signals(Signals {
        period: 0.05,
        linear: Axes {
            x: vec![term(10.0, 1.37, 1), term(4.0, 0.3, 2)],
            y: vec![term(10.0, -0.17, 1)],
            z: vec![term(2.0, 0.5, 1)],
        },
        angular: Axes::default(),
    });
    for m in [trans, shaken] {
        assert_eq!(m.invariance(), Invariance::Uniform);
        assert_eq!(families(&m), 1);
        for field in [FieldKind::Force, FieldKind::Velocity] {
            let d = worst_difference(&m, field);
            assert!(d <= 1e-9, "{m:?} {field:?}: {d:e}");
        }
    }
}

#[test]
fn six_signal_motions_turning_about_one_axis() {
    let term = |amplitude, phase, harmonic| FourierTerm {
        amplitude,
        phase,
        harmonic,
    };
    let signals = |linear: Axes, angular: Axes| {
        Motion::Signals(Signals {
            period: 0.03,
            linear,
            angular,
        })
    };
    // Tilting about x (any linear signals): lines along x; the rows.
    let about_x = signals(
        Axes {
            x: vec![term(3.0, 0.4, 2)],
            y: vec![term(10.9, 1.57, 1)],
            z: vec![term(0.5, 0.0, 1)],
        },
        Axes {
            x: vec![term(218.4, 1.57, 1)],
            ..Axes::default()
        },
    );
    // Turning about z with vertical translation only: circles.
    let about_z = signals(
        Axes {
            z: vec![term(1.0, 0.3, 1)],
            ..Axes::default()
        },
        Axes {
            z: vec![term(900.0, 0.0, 1), term(450.0, 0.7, 2)],
            ..Axes::default()
        },
    );
    let rows = exact_families(|_, j| j);
    let centred = exact_families(|i, j| (i - 3).pow(2) + (j - 3).pow(2));
    for (m, invariance, expect) in [
        (about_x, Invariance::Along([1.0, 0.0]), rows),
        (about_z, Invariance::About([0.0, 0.0]), centred),
    ] {
        assert_eq!(m.invariance(), invariance);
        assert_eq!(families(&m), expect);
        for field in [FieldKind::Force, FieldKind::Velocity] {
            let d = worst_difference(&m, field);
            assert!(d <= 1e-9, "{invariance:?} {field:?}: {d:e}");
        }
    }
}

#[test]
fn tilted_axes_and_six_signal_tilts_are_simulated_everywhere() {
    let div = primitive(PrimitiveKind::DivCircle, 0.0, [0.0, 0.0]);
    let six = Motion::Signals(Signals::example());
    for m in [div, six] {
        assert_eq!(m.invariance(), Invariance::None);
        assert_eq!(families(&m), 49);
    }
}
