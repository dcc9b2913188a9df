//! Tests of the 1-D fast path: slips on a motion's line
//! ([`Motion::slip_axis`]) skip the 2-D checks without changing a bit.

use super::*;
use crate::dynamics::{Model, Numerics, PartPhysics};
use crate::motion::{Motion, Screw, Waveform, V3};

const PERIOD: f64 = 0.03;

thread_local! {
    /// Starts from rest on a line taken by the Radau step (this thread).
    pub(super) static LINE_RADAU: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

fn screw(axis: [f64; 3], point: [f64; 3], rotation: f64, translation: f64) -> Motion {
    let wave = |a: f64| {
        if a == 0.0 {
            Waveform::Zero
        } else {
            Waveform::RestToRest { amplitude: a }
        }
    };
    Motion::Screw(Screw {
        axis,
        point,
        period: PERIOD,
        rotation: wave(rotation),
        translation: wave(translation),
    })
}

/// Motions with a slip axis: the LineSink (x), a translation along x, the
/// LineSink turned onto y (rotation about x, translation along y), and a
/// Square-wave translation along y (breakpoints, exact steps).
fn lines() -> Vec<(Motion, usize)> {
    vec![
        (screw([0.0, 1.0, 0.0], [0.0, 0.0, -0.05], 0.004, 0.0), 0),
        (screw([1.0, 0.0, 0.0], [0.0, 0.0, 0.0], 0.0, 3e-4), 0),
        (screw([-2.0, 0.0, 0.0], [0.01, 0.0, 0.05], 0.004, 0.0), 1),
        (
            Motion::Screw(Screw {
                axis: [0.0, 1.0, 0.0],
                point: [0.0; 3],
                period: PERIOD,
                rotation: Waveform::Zero,
                translation: Waveform::Square { accel: 5.0 },
            }),
            1,
        ),
    ]
}

/// Screws without one: the SkewSink (rotation about y, translation along
/// y), a rotation about the vertical, a LineSink turned by 30°.
#[test]
fn slip_axis_only_for_lines() {
    for (motion, axis) in lines() {
        assert_eq!(motion.slip_axis(), Some(axis), "{motion:?}");
    }
    let none = [
        screw([0.0, 1.0, 0.0], [0.0, 0.0, -0.05], 0.004, 3e-4),
        screw([0.0, 0.0, 1.0], [0.0; 3], 0.05, 0.0),
        lines()[0].0.transformed(30f64.to_radians(), [0.0, 0.0]),
    ];
    for motion in none {
        assert_eq!(motion.slip_axis(), None, "{motion:?}");
    }
}

/// The claim itself, sampled: under every model switch, at points across
/// the plate and slip velocities along the axis, a_free has no component
/// across it at any instant (exactly).
#[test]
fn free_acceleration_stays_on_the_line() {
    for (motion, i) in lines() {
        let model = Model::FULL;
        for step in 0..97 {
            let t = PERIOD * step as f64 / 97.0;
            let k = motion.kinematics_piece(t, t, 9.81, model.tilt);
            for (x, y) in [(-0.04, 0.03), (0.0, 0.0), (0.02, -0.05)] {
                for v in [-0.3, 0.0, 0.1] {
                    let mut u = V2::zeros();
                    u[i] = v;
                    let (_, free) = model.point_forces(&k, &V3::new(x, y, 0.0), &u);
                    assert_eq!(free[1 - i], 0.0, "{motion:?} t {t} at ({x}, {y})");
                }
            }
        }
    }
}

/// Whole cycles on the fast path and on the general one (the axis
/// forgotten) are bitwise identical: state, stuck time, events and RK4
/// steps, from rest and from slips along the axis, at 8 and 64 steps, in
/// both stiff schemes, with starts from rest that take the Radau step
/// (a_free reversing within the step) among them.
#[test]
fn line_fast_path_is_bitwise_the_general_path() {
    for (motion, i) in lines() {
        for slip in [SlipScheme::Regularised, SlipScheme::Stiff] {
            for steps in [8, 64] {
                let numerics = Numerics {
                    steps_per_cycle: steps,
                    slip,
                    ..Numerics::default()
                };
                let fast = Simulator::new(&motion, PartPhysics::full(0.3), numerics);
                let mut general = fast.clone();
                general.line = None;
                assert_eq!(fast.line, Some(i));
                for phase in 0..7 {
                    let t0 = PERIOD * phase as f64 / 7.0;
                    for (x0, v0) in [(-0.03, 0.0), (0.01, 0.02), (0.035, -0.05)] {
                        let mut r = V2::new(0.004, -0.002);
                        r[i] = x0;
                        let mut u = V2::zeros();
                        u[i] = v0;
                        let run = |sim: &Simulator| {
                            let mut state = PartState::new(r, u);
                            sim.advance(t0, t0 + 3.0 * PERIOD, &mut state, &r, None)
                        };
                        let (a, b) = (run(&fast), run(&general));
                        assert_eq!(a, b, "{motion:?} {slip:?} {steps} steps from {x0}, {v0}");
                        let a = a.unwrap();
                        assert_eq!(a.state.u[1 - i], 0.0);
                    }
                }
            }
        }
    }
    let radau = LINE_RADAU.with(|c| c.get());
    assert!(radau > 0, "no start from rest took the Radau step");
    println!("starts from rest on a line taken by Radau: {radau}");
}
