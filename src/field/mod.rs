//! Fields sampled on a grid: what a plate motion does to point parts.
//!
//! * **Zero-velocity force field** F(x): a unit-mass point part starts at x
//!   at rest in the inertial frame (slip velocity u = −v_s(x)) at each of
//!   n_phase start phases spread evenly over the cycle, moves freely for one
//!   cycle, and F is the mean over phases of its inertial velocity change
//!   divided by T (m/s²).
//! * **Steady-state velocity field** V(x): the mean velocity over one cycle of
//!   the periodic motion (see [`crate::dynamics::SteadyState`]), frozen or
//!   free by the model's `moving` switch (m/s).
//!
//! Every sample carries its validity: contact lost, not converged, not
//! finite, or (for frozen velocity fields) the frozen-position assumption
//! broken — the part's
//! excursion within a cycle is not small against the grid spacing. The
//! large-amplitude Circle is the case in point: its plate moves at about
//! 0.4 m/s at 4 cm, and its frozen field shows a spurious radial velocity
//! of about 0.3 m/s, so that primitive needs the free variant.
//!
//! A motion that moves whole families of points alike
//! ([`crate::motion::Invariance`]: lines along a horizontal screw axis,
//! circles about a vertical one, every point of a translation) is simulated
//! at one point per family ([`Orbits`]) and the sample mapped to the rest:
//! the default library's 21 × 21 force fields simulate 21 points for a
//! LineSink or SkewSink, 61 for a ScaledCircle or Circle and 1 for Trans
//! (`tests/unit/invariance.rs` holds them against simulating every point).
//!
//! Points are computed in parallel with rayon and collected in grid order,
//! so the result is bitwise identical for any number of threads.

mod force;
mod grid;
mod json;
mod orbits;
pub mod rung;
mod velocity;

pub use grid::Grid;
pub(crate) use json::FieldStats;
pub use orbits::Orbits;

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::dynamics::{Friction, KinematicsTable, Model, Numerics, PartPhysics, Simulator};
use crate::motion::{Invariance, Motion};

/// Which field to compute.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Hash)]
#[serde(rename_all = "snake_case")]
pub enum FieldKind {
    /// Zero-velocity force field (m/s²).
    Force,
    /// Steady-state velocity field (m/s).
    Velocity,
}

/// Validity of one sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Validity {
    /// Valid.
    Ok,
    /// The part leaves the plate (N < 0) somewhere in the cycle.
    ContactLost,
    /// The steady state did not converge.
    NotConverged,
    /// Frozen field whose within-cycle excursion is not small against the
    /// grid spacing: use the free variant.
    FrozenInvalid,
    /// Resampled by symmetry ([`crate::basis::symmetry`]) at a point whose
    /// interpolation stencil falls outside the simulated region.
    OutsideSource,
    /// The computed sample is not finite (NaN or ±∞ in a component, from
    /// arithmetic overflow in the integrator); its vector is set to zero.
    NonFinite,
}

impl std::fmt::Display for Validity {
    /// In words, for messages and reports: "valid", "contact lost", "not
    /// converged", "frozen invalid", "outside source", "non-finite".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Validity::Ok => "valid",
            Validity::ContactLost => "contact lost",
            Validity::NotConverged => "not converged",
            Validity::FrozenInvalid => "frozen invalid",
            Validity::OutsideSource => "outside source",
            Validity::NonFinite => "non-finite",
        })
    }
}

/// Everything that determines a field besides the motion.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FieldSettings {
    /// Friction coefficients.
    pub friction: Friction,
    /// Gravity (m/s²).
    pub gravity: f64,
    /// Model switches.
    pub model: Model,
    /// Integrator settings.
    pub numerics: Numerics,
    /// Start phases for force fields.
    pub phases: usize,
    /// Frozen velocity samples are flagged when the within-cycle excursion
    /// exceeds this fraction of the grid spacing.
    pub frozen_excursion: f64,
}

impl FieldSettings {
    /// The point-part simulator of `motion` under these physics.
    pub fn simulator<'a>(&self, motion: &'a Motion) -> Simulator<'a> {
        Simulator::new(motion, self.physics(), self.numerics)
    }

    /// The part physics (friction, gravity, model) of these settings.
    pub fn physics(&self) -> PartPhysics {
        PartPhysics::new(self.friction, self.gravity, self.model)
    }
}

impl Default for FieldSettings {
    fn default() -> Self {
        FieldSettings {
            friction: Friction::uniform(0.3),
            gravity: 9.81,
            model: Model::FULL,
            numerics: Numerics::default(),
            phases: 30,
            frozen_excursion: 0.25,
        }
    }
}

/// The grid points [`Field::compute`] simulates for `motion` on `grid`: one
/// per family of points the motion moves alike (what a work estimate
/// counts).
pub(crate) fn simulated_points(motion: &Motion, grid: &Grid) -> usize {
    Orbits::count(&grid.points(), motion.invariance())
}

/// One sampled field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Field {
    /// Sampling grid.
    pub grid: Grid,
    /// Force or velocity.
    pub kind: FieldKind,
    /// Vectors, row-major (y outer, x inner).
    pub vectors: Vec<[f64; 2]>,
    /// Validity per sample.
    pub validity: Vec<Validity>,
}

impl Field {
    /// Computes `kind` for `motion` on `grid`, simulating one point per
    /// family of points the motion moves alike ([`Motion::invariance`],
    /// [`Orbits`]) and mapping its sample to the others. `progress` is
    /// called once per grid point (from worker threads).
    pub fn compute(
        motion: &Motion,
        grid: &Grid,
        kind: FieldKind,
        settings: &FieldSettings,
        progress: &(dyn Fn() + Sync),
    ) -> Field {
        Self::compute_by(motion, grid, kind, settings, motion.invariance(), progress)
    }

    /// [`Field::compute`] simulating one point per family of points that
    /// `invariance` moves alike: the motion's own ([`Motion::invariance`])
    /// in [`Field::compute`]; [`Invariance::None`] simulates every grid
    /// point, the reference the reduction by invariance is tested against.
    ///
    /// ```
    /// use platefield::basis::{Primitive, PrimitiveKind};
    /// use platefield::field::{Field, FieldKind, FieldSettings, Grid};
    /// use platefield::motion::Invariance;
    /// let motion = Primitive::new(PrimitiveKind::Circle).motion();
    /// let grid = Grid { x: [-0.02, 0.02], y: [-0.02, 0.02], n: [3, 3] };
    /// let mut settings = FieldSettings::default();
    /// settings.numerics.steps_per_cycle = 16;
    /// let every = Field::compute_by(&motion, &grid, FieldKind::Force, &settings, Invariance::None, &|| {});
    /// assert_eq!(every.vectors.len(), 9);
    /// ```
    pub fn compute_by(
        motion: &Motion,
        grid: &Grid,
        kind: FieldKind,
        settings: &FieldSettings,
        invariance: Invariance,
        progress: &(dyn Fn() + Sync),
    ) -> Field {
        let direct = settings.simulator(motion);
        // The plate kinematics depend on time only: tabulated once on the
        // integrator's time grid and shared by every point.
        let table = match kind {
            FieldKind::Force => KinematicsTable::phases(&direct, settings.phases),
            FieldKind::Velocity => KinematicsTable::cycle(&direct),
        };
        let sim = direct.with_table(&table);
        let frames = match kind {
            FieldKind::Force => force::phase_frames(&sim, settings.phases),
            FieldKind::Velocity => Vec::new(),
        };
        let points = grid.points();
        let orbits = Orbits::of(&points, invariance);
        let sizes = orbits.sizes();
        let spacing = grid.spacing();
        let samples: Vec<([f64; 2], Validity)> = orbits
            .representatives
            .par_iter()
            .zip(&sizes)
            .map(|(&i, &members)| {
                let p = points[i];
                let mut s = match kind {
                    FieldKind::Force => force::sample(&sim, p, &frames),
                    FieldKind::Velocity => {
                        velocity::sample(&sim, p, spacing * settings.frozen_excursion)
                    }
                };
                if !(s.0[0].is_finite() && s.0[1].is_finite()) {
                    s = ([0.0, 0.0], Validity::NonFinite);
                }
                for _ in 0..members {
                    progress();
                }
                s
            })
            .collect();
        Field {
            grid: *grid,
            kind,
            vectors: (0..points.len())
                .map(|i| orbits.map(i, samples[orbits.members[i].0].0))
                .collect(),
            validity: orbits.members.iter().map(|m| samples[m.0].1).collect(),
        }
    }

    /// Bilinear interpolation of the field at `p` (point-sampled targets
    /// without a grid, paths through a field); outside the grid `OutsideSource`, next to an
    /// invalid node that node's own flag (a LineSink rotated so that a corner
    /// of the region lies where it lifts the part off reads "contact lost",
    /// not "outside source").
    pub(crate) fn bilinear(&self, p: [f64; 2]) -> Result<[f64; 2], Validity> {
        let nodes = self
            .grid
            .bilinear_weights(p)
            .ok_or(Validity::OutsideSource)?;
        let mut out = [0.0; 2];
        for (k, w) in nodes {
            if self.validity[k] != Validity::Ok {
                return Err(self.validity[k]);
            }
            out[0] += w * self.vectors[k][0];
            out[1] += w * self.vectors[k][1];
        }
        Ok(out)
    }

    /// Number of valid samples.
    pub fn valid_count(&self) -> usize {
        self.validity.iter().filter(|v| **v == Validity::Ok).count()
    }

    /// Largest vector magnitude over valid samples.
    pub fn max_magnitude(&self) -> f64 {
        self.vectors
            .iter()
            .zip(&self.validity)
            .filter(|(_, v)| **v == Validity::Ok)
            .map(|(f, _)| f[0].hypot(f[1]))
            .fold(0.0, f64::max)
    }
}
