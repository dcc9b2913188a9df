//! The calibrated steps per cycle of the default force library
//! (`src/basis/steps.rs`): each primitive's force field at its
//! `force_steps` is within 1e-4 (relative L2) of its 512-step field, one
//! rung fewer is not (the count is the fewest of the ladder), and the plan
//! leaves every field it was not calibrated for at the requested count.
//! The default run checks every primitive but the DivCircle; the DivCircle
//! runs with `-- --ignored`.

use platefield::basis::steps::{CALIBRATED_ERROR, LADDER};
use platefield::basis::{FieldLibrary, Library, Primitive, PrimitiveKind, StepsPlan};
use platefield::field::rung::relative_l2;
use platefield::field::{FieldKind, FieldSettings, Grid};
use platefield::progress::ProgressMode;

fn at(steps: usize) -> FieldSettings {
    let mut s = FieldSettings::default();
    s.numerics.steps_per_cycle = steps;
    s
}

/// Every primitive but the DivCircle, whose 1225-sample field at 512
/// steps is two thirds of the whole check's CPU (6 s of 9): it runs with
/// `-- --ignored`, [`the_div_circles_calibrated_force_steps_are_the_fewest`].
#[test]
fn calibrated_force_steps_are_the_fewest_within_tolerance() {
    fewest_within_tolerance(&|k| k != PrimitiveKind::DivCircle);
}

/// [`calibrated_force_steps_are_the_fewest_within_tolerance`] for the
/// DivCircle.
#[test]
#[ignore = "about 6 s of CPU: cargo test --release -p platefield-studies --test library_steps -- --ignored"]
fn the_div_circles_calibrated_force_steps_are_the_fewest() {
    fewest_within_tolerance(&|k| k == PrimitiveKind::DivCircle);
}

/// The check of the module docs on the default primitives whose kind
/// `keep` accepts.
fn fewest_within_tolerance(keep: &dyn Fn(PrimitiveKind) -> bool) {
    let prims: Vec<Primitive> = Library::default_primitives()
        .into_iter()
        .filter(|p| keep(p.kind))
        .collect();
    assert!(!prims.is_empty());
    let force = FieldKind::Force;
    let build = |plan, steps| {
        FieldLibrary::build_with(
            &prims,
            &Grid::DEFAULT,
            &at(steps),
            force,
            plan,
            ProgressMode::Quiet,
        )
    };
    let reference = build(StepsPlan::Uniform, 512);
    let calibrated = build(StepsPlan::Calibrated, 64);
    for (c, r) in calibrated.entries.iter().zip(&reference.entries) {
        let kind = c.primitive.kind;
        assert_eq!(c.steps_per_cycle, kind.force_steps(), "{}", kind.name());
        let (e, n) = relative_l2(&c.field, &r.field);
        eprintln!(
            "{}: {} steps, error {e:.3e}",
            kind.name(),
            c.steps_per_cycle
        );
        assert_eq!(n, Grid::DEFAULT.len(), "{}: invalid samples", kind.name());
        assert!(e <= CALIBRATED_ERROR, "{}: error {e:.3e}", kind.name());
        let rung = LADDER.iter().position(|&s| s == kind.force_steps());
        let rung = rung.unwrap_or_else(|| panic!("{}: count off the ladder", kind.name()));
        if rung > 0 {
            let fewer = LADDER[rung - 1];
            let field = platefield::field::Field::compute(
                &c.primitive.motion(),
                &Grid::DEFAULT,
                force,
                &at(fewer),
                &|| {},
            );
            let (e, _) = relative_l2(&field, &r.field);
            assert!(
                e > CALIBRATED_ERROR,
                "{}: {fewer} steps are within {CALIBRATED_ERROR:e} too ({e:.3e}): \
                 recalibrate `PrimitiveKind::force_steps` with `platefield study speed`",
                kind.name()
            );
        }
    }
}

/// Fields the calibration was not measured for keep the requested count:
/// velocity fields, a shifted or rotated primitive, another grid, other
/// settings.
#[test]
fn calibration_applies_only_where_it_was_measured() {
    let plan = StepsPlan::Calibrated;
    let s = at(48);
    let grid = Grid::DEFAULT;
    let p = Primitive::new(PrimitiveKind::DivCircle);
    assert_eq!(plan.steps(&p, FieldKind::Force, &grid, &s), 24);
    assert_eq!(plan.steps(&p, FieldKind::Velocity, &grid, &s), 48);
    assert_eq!(
        StepsPlan::Uniform.steps(&p, FieldKind::Force, &grid, &s),
        48
    );
    let mut shifted = p.clone();
    shifted.shift[0] = 0.01;
    assert_eq!(plan.steps(&shifted, FieldKind::Force, &grid, &s), 48);
    let mut rotated = p.clone();
    rotated.rotation_deg = 30.0;
    assert_eq!(plan.steps(&rotated, FieldKind::Force, &grid, &s), 48);
    let small = Grid {
        n: [9, 9],
        ..Grid::DEFAULT
    };
    assert_eq!(plan.steps(&p, FieldKind::Force, &small, &s), 48);
    let mut other = s;
    other.phases = 12;
    assert_eq!(plan.steps(&p, FieldKind::Force, &grid, &other), 48);
}
