//! The sections of [`DesignOptions`] with their defaults and range
//! checks, run before any library build, so a count or a shift from the
//! command line can neither overflow nor ask for hours of simulation
//! without a word. Each check names the option's path
//! (`schedule.total_cycles`, `basis.shifts`).

use std::path::PathBuf;

use super::DesignOptions;
use crate::basis::PrimitiveKind;
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::field::FieldKind;
use crate::fit::FitMode;
use crate::schedule::{DEFAULT_MIN_CYCLES, DEFAULT_QUANTIZATION_TOL, MAX_SEGMENT_CYCLES};

/// Largest basis shift (m) along either axis: the plate regions the
/// primitives are built for span a few centimetres, and the library grid
/// grows with the shift (a 1 m shift asked for 4.4 M samples per primitive).
pub(crate) const MAX_SHIFT_M: f64 = 0.1;

/// The primitive basis the fit chooses from (`basis.*`).
#[derive(Debug, Clone)]
pub struct BasisSection {
    /// Basis field kind (default velocity).
    pub kind: FieldKind,
    /// Rotation step of the basis copies (degrees, default 15).
    pub rotation_step_deg: f64,
    /// Horizontal shifts of the basis copies (default: none, `[[0, 0]]`).
    pub shifts: Vec<[f64; 2]>,
    /// Keep basis columns that are invalid somewhere in the region.
    pub keep_invalid: bool,
    /// Primitive kinds allowed in the basis (default: all eight).
    pub kinds: Vec<PrimitiveKind>,
    /// Six-signal motions added to the basis as columns, with their labels
    /// (e.g. a motion synthesized for the target, so the fit can mix it
    /// with primitives): each column is the motion's own field of the
    /// basis kind, simulated on the target's sampling grid.
    pub motions: Vec<(String, crate::motion::Signals)>,
    /// Basis cache folder (default `.platefield-cache`; `None`: no cache).
    pub cache_dir: Option<PathBuf>,
}

impl Default for BasisSection {
    fn default() -> Self {
        BasisSection {
            kind: FieldKind::Velocity,
            rotation_step_deg: 15.0,
            shifts: vec![[0.0, 0.0]],
            keep_invalid: false,
            kinds: PrimitiveKind::ALL.to_vec(),
            motions: Vec::new(),
            cache_dir: Some(PathBuf::from(".platefield-cache")),
        }
    }
}

impl BasisSection {
    /// Checks `basis.shifts` and `basis.rotation_step_deg`.
    pub(crate) fn validate(&self) -> Result<()> {
        for s in &self.shifts {
            if !s.iter().all(|v| v.is_finite() && v.abs() <= MAX_SHIFT_M) {
                return Err(Error::invalid(
                    "basis.shifts",
                    format!(
                        "each coordinate must be in [-{MAX_SHIFT_M}, {MAX_SHIFT_M}] m, got {:.3e},{:.3e}",
                        s[0], s[1]
                    ),
                ));
            }
        }
        rotation_step(self.rotation_step_deg)
    }
}

/// The fit of time fractions to the target (`fit.*`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FitSection {
    /// Fit mode (default `shape`).
    pub mode: FitMode,
    /// At most this many segments (default: no limit).
    pub max_primitives: Option<usize>,
}

impl FitSection {
    /// Checks `fit.max_primitives` (at least 1 when given).
    pub(crate) fn validate(&self) -> Result<()> {
        if self.max_primitives == Some(0) {
            return Err(Error::invalid("fit.max_primitives", "must be ≥ 1"));
        }
        Ok(())
    }
}

/// Whole cycles per segment and the segment order (`schedule.*`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScheduleSection {
    /// Minimum cycles per segment.
    pub min_cycles: u32,
    /// Total cycles (default: the shortest within the quantisation tolerance).
    pub total_cycles: Option<u32>,
    /// Tolerance on the field's quantisation error.
    pub quantization_tol: f64,
    /// After scheduling, search the segment order and rest insertions that
    /// best realise the prediction ([`super::order`]) and play the
    /// schedule in that order.
    pub order_search: bool,
}

impl Default for ScheduleSection {
    fn default() -> Self {
        ScheduleSection {
            min_cycles: DEFAULT_MIN_CYCLES,
            total_cycles: None,
            quantization_tol: DEFAULT_QUANTIZATION_TOL,
            order_search: false,
        }
    }
}

impl ScheduleSection {
    /// Checks `schedule.total_cycles` and `schedule.min_cycles`.
    pub(crate) fn validate(&self) -> Result<()> {
        if let Some(n) = self.total_cycles {
            if !(1..=MAX_SEGMENT_CYCLES).contains(&n) {
                return Err(Error::invalid(
                    "schedule.total_cycles",
                    format!("must be in 1..={MAX_SEGMENT_CYCLES}, got {n}"),
                ));
            }
        }
        if !(1..=MAX_SEGMENT_CYCLES).contains(&self.min_cycles) {
            return Err(Error::invalid(
                "schedule.min_cycles",
                format!(
                    "must be in 1..={MAX_SEGMENT_CYCLES}, got {}",
                    self.min_cycles
                ),
            ));
        }
        Ok(())
    }
}

/// The model every candidate schedule is played and judged at (`model`):
/// the judge, its friction table, the shaker-tolerance draws and the
/// model `verify` plays by default (the schedule's `settings.model`). The
/// basis and the synthesis are simulated at [`DesignOptions::settings`]'
/// own model whatever this says: the basis is cached under it, and a rung
/// can only be chosen for a motion once it exists.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum PlayModel {
    /// The settings' own model (full by default): no choice.
    #[default]
    Own,
    /// This model (`design --model full` or a rung).
    Fixed(Model),
    /// Per candidate schedule, the rung [`crate::schedule::Schedule::rungs`]
    /// chooses within this relative L2 tolerance of `full` on 5 × 5 points
    /// over the target's region, at the nominal friction: the cheapest rung
    /// that moves the part and holds for every moving segment. The choice
    /// is recorded in the schedule's `rungs`.
    Auto {
        /// Largest accepted relative L2 error against `full`.
        tolerance: f64,
    },
}

impl PlayModel {
    /// Checks `model`'s tolerance (finite, ≥ 0).
    pub(crate) fn validate(&self) -> Result<()> {
        if let PlayModel::Auto { tolerance } = self {
            crate::error::non_negative("model", *tolerance)?;
        }
        Ok(())
    }

    /// `schedule` set to be played at this model: its `settings.model`,
    /// and under [`PlayModel::Auto`] the choice in its `rungs`.
    pub(crate) fn apply(
        &self,
        mut schedule: crate::schedule::Schedule,
    ) -> crate::schedule::Schedule {
        match *self {
            PlayModel::Own => {}
            PlayModel::Fixed(m) => schedule.settings.model = m,
            PlayModel::Auto { tolerance } => {
                let region = schedule.region();
                let n = crate::scene::RUNG_POINTS;
                let grid = crate::field::Grid {
                    n: [n, n],
                    ..region
                };
                let r = schedule.rungs(&grid, &schedule.settings, tolerance);
                schedule.settings.model = r.model;
                schedule.rungs = Some(r.record());
            }
        }
        schedule
    }
}

impl DesignOptions {
    /// Checks every section against its allowed ranges, naming the
    /// option's path (`schedule.total_cycles`, `closed_loop.stride`) in
    /// the error.
    pub(crate) fn validate(&self) -> Result<()> {
        self.schedule.validate()?;
        self.basis.validate()?;
        self.model.validate()?;
        self.fit.validate()
    }
}

/// Smallest basis rotation step (degrees). The rotated copies are not
/// simulated but held and fitted: their memory and the fit's time grow as
/// 1/step² (on the sink, about fourfold per halved step), and a step
/// of 1e-9° would ask for 2.9 TB and abort.
pub(crate) const MIN_ROTATION_STEP_DEG: f64 = 1.0;

/// The rotation step (`--rotation-step`) must divide 360: the basis holds 360/step rotated
/// copies of each primitive, and a step that does not divide 360 would be
/// rounded to the nearest whole number of copies without a word (7 would
/// become 7.0588°, 51 copies; the sink's LineSinks fall out of that basis
/// and the fit's error grows manyfold). A step is accepted when 360/step is within
/// 1e-9 of a whole number; otherwise the error names the nearest steps
/// below and above that divide 360 and are written with at most three
/// decimals (7: 6 and 7.2). The step must also lie in
/// [[`MIN_ROTATION_STEP_DEG`], 360].
fn rotation_step(step: f64) -> Result<()> {
    if !(MIN_ROTATION_STEP_DEG..=360.0).contains(&step) {
        return Err(Error::invalid(
            "basis.rotation_step_deg",
            format!(
                "must be in [{MIN_ROTATION_STEP_DEG}, 360] degrees (at most 360 rotated copies of each primitive), got {}",
                crate::input::num(step)
            ),
        ));
    }
    let copies = 360.0 / step;
    if (copies - copies.round()).abs() <= 1e-9 {
        return Ok(());
    }
    // Steps 360/n in [1, 360] written with at most three decimals.
    let nice: Vec<f64> = (1..=360)
        .map(|n| 360.0 / f64::from(n))
        .filter(|s| ((s * 1000.0).round() - s * 1000.0).abs() < 1e-6)
        .collect();
    let below = nice
        .iter()
        .copied()
        .filter(|s| *s < step)
        .max_by(f64::total_cmp);
    let above = nice
        .iter()
        .copied()
        .filter(|s| *s > step)
        .min_by(f64::total_cmp);
    let nearest: Vec<String> = [below, above]
        .into_iter()
        .flatten()
        .map(|s| crate::input::num((s * 1000.0).round() / 1000.0))
        .collect();
    Err(Error::invalid(
        "basis.rotation_step_deg",
        format!(
            "{} does not divide 360 (360/{} = {:.4} rotated copies; a whole number is needed); nearest steps that divide 360: {}",
            crate::input::num(step),
            crate::input::num(step),
            copies,
            nearest.join(", ")
        ),
    ))
}

#[cfg(test)]
mod tests {
    /// A worked example of `design::options::PlayModel::apply`.
    #[test]
    fn example_playmodel_apply() -> Result<(), crate::Error> {
        use crate::design::PlayModel;
        use crate::field::rung::DEFAULT_RUNG_TOLERANCE;
        use crate::schedule::Schedule;
        let s = Schedule::load("results/sequenced/sink/schedule.json".as_ref())?;
        assert!(PlayModel::Own.apply(s.clone()).rungs.is_none());
        let auto = PlayModel::Auto {
            tolerance: DEFAULT_RUNG_TOLERANCE,
        }
        .apply(s);
        let r = auto.rungs.as_ref().unwrap();
        // LineSinks tilt the plate: no rung below centripetal and tilt.
        assert_eq!(r.played, "paper+moving+centripetal+tilt");
        assert_eq!(auto.settings.model.coriolis, false);
        Ok(())
    }
}
