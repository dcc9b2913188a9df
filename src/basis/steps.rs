//! How many integrator steps per cycle each primitive of a library is
//! simulated with.
//!
//! One count for every primitive has to be the count of the primitive
//! that needs the most: the Circle, whose zero-velocity force field is
//! within 1e-4 (relative L2, against 512 steps per cycle) only from 64
//! steps per cycle (its error is the plate frame's fictitious forces,
//! README, "The forward model"), while DivCircle — the costliest of the
//! library's primitives — is within 1e-4 from 24. [`StepsPlan::Calibrated`] simulates each
//! primitive's force field with the fewest steps per cycle at which the
//! default primitive's force field on the default grid was measured within
//! 1e-4 ([`PrimitiveKind::force_steps`]); `tests/library_steps.rs` checks
//! the table against a 512-step library, and `platefield study speed` reports
//! the plan's time and error beside every uniform count.

use serde::{Deserialize, Serialize};

use super::primitives::{Primitive, PrimitiveKind};
use crate::field::{FieldKind, FieldSettings, Grid};

/// The largest relative L2 error the calibrated steps allow.
pub const CALIBRATED_ERROR: f64 = 1e-4;

/// The step counts the calibration tries, fewest first.
pub const LADDER: [usize; 7] = [8, 16, 24, 32, 40, 48, 64];

/// Steps per cycle for each primitive of a library build.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum StepsPlan {
    /// Every field at the settings' `numerics.steps_per_cycle`.
    Uniform,
    /// The force field of a default primitive ([`Primitive::new`]) on the
    /// default grid under the default settings (steps per cycle aside) at
    /// its kind's [`PrimitiveKind::force_steps`], where it was calibrated;
    /// every other field at the settings' count.
    Calibrated,
}

impl StepsPlan {
    /// Steps per cycle for `primitive`'s `field` on `grid` under `settings`.
    pub fn steps(
        &self,
        primitive: &Primitive,
        field: FieldKind,
        grid: &Grid,
        settings: &FieldSettings,
    ) -> usize {
        let requested = settings.numerics.steps_per_cycle;
        if *self == StepsPlan::Uniform || field != FieldKind::Force {
            return requested;
        }
        let mut defaults = FieldSettings::default();
        defaults.numerics.steps_per_cycle = requested;
        let calibrated = *primitive == Primitive::new(primitive.kind)
            && *grid == Grid::DEFAULT
            && *settings == defaults;
        if calibrated {
            primitive.kind.force_steps()
        } else {
            requested
        }
    }

    /// `settings` with [`StepsPlan::steps`].
    pub fn settings(
        &self,
        primitive: &Primitive,
        field: FieldKind,
        grid: &Grid,
        settings: &FieldSettings,
    ) -> FieldSettings {
        let mut s = *settings;
        s.numerics.steps_per_cycle = self.steps(primitive, field, grid, settings);
        s
    }
}

impl PrimitiveKind {
    /// The fewest steps per cycle of [`LADDER`] at which this kind's
    /// default zero-velocity force field (21×21 over ±4 cm, 30 phases,
    /// default settings) is within [`CALIBRATED_ERROR`] of the 512-step
    /// field, as measured by `platefield study speed` (each kind's error at
    /// every count: `results/library_speed.md`).
    ///
    /// Other parameters, grids or settings were not calibrated, and
    /// [`StepsPlan::Calibrated`] leaves them at the requested count.
    pub fn force_steps(&self) -> usize {
        match self {
            PrimitiveKind::Trans => 32,
            PrimitiveKind::ScaledCircle => 40,
            PrimitiveKind::Circle => 64,
            PrimitiveKind::DivCircle => 24,
            PrimitiveKind::LineSink | PrimitiveKind::LineSource => 8,
            PrimitiveKind::SkewSink | PrimitiveKind::SkewSource => 32,
        }
    }
}
