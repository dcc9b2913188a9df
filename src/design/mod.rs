//! Inverse design: a target field in, a verified
//! schedule of primitive plate motions out.
//!
//! 1. **Basis** ([`basis`]): the primitive library simulated once on a grid
//!    that covers the target region under every rotation, then rotated (every
//!    15° by default) and shifted by symmetry. Steady-state velocity fields by
//!    default — what parts follow, and what combines under sequencing.
//! 2. **Fit** ([`crate::fit`]): time fractions w ≥ 0, Σw ≤ 1 (the plate at
//!    rest is the zero field) by a verified conic program; `shape` (the
//!    strongest field of the target's shape) by default.
//! 3. **Schedule** ([`crate::schedule`]): whole cycles per segment, a
//!    minimum per segment, an order; exportable as controller signals
//!    ([`crate::schedule::export`]).
//! 4. **Order** (optional, [`ScheduleSection::order_search`]): the segment
//!    order and rest insertions that best realise the prediction in
//!    closed-loop simulation ([`order`]).
//! 5. **Refine** ([`refine`], a library step `design` does not call yet;
//!    `platefield study synthesis` uses it): the primitives' cycles, rotations
//!    and amplitudes tuned by Nelder–Mead on the played realised error.
//!
//! Each step is one named stage function in `stages.rs`
//! (`basis_stage` → `fit_stage` → `schedule_stage` → `order_stage`), and
//! [`design`] composes them.
//!
//! A target file is designed through [`crate::inverse::run`], which
//! chooses between these designs and that of a part's pose
//! ([`crate::pose::design`]).

pub mod basis;
pub mod closed_loop;
pub mod judge;
pub mod method;
pub mod mirror;
mod options;
pub mod order;
pub mod polish;
pub mod refine;
pub mod replay;
mod rule;
pub mod sort;
pub mod stacked;
mod stages;
pub mod tolerance;

use std::time::Instant;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::field::FieldSettings;
use crate::fit::{self, FitMode, FitOptions, FitProblem, FitSolution};
use crate::request::{SampledTarget, Target};
use crate::schedule::Schedule;
use crate::work::Runtime;
use order::OrderSearch;

pub(crate) use basis::DesignBasis;
pub(crate) use method::MethodDesign;
pub use method::{Choice, Method};
pub use options::BasisSection;
pub use options::FitSection;
pub use options::PlayModel;
pub use options::ScheduleSection;

/// Options of [`design`] and [`crate::inverse::run`], in sections (each
/// range-checked by its own `validate`, all of them by
/// `DesignOptions::validate`, whose errors name the option path:
/// `schedule.min_cycles`, `basis.rotation_step_deg`,
/// `closed_loop.max_iterations`).
#[derive(Debug, Clone, Default)]
pub struct DesignOptions {
    /// Simulation settings (the physics and numerics) of the basis, the
    /// synthesis and every play.
    pub settings: FieldSettings,
    /// The primitive basis the fit chooses from.
    pub basis: BasisSection,
    /// The fit of time fractions to the target.
    pub fit: FitSection,
    /// Whole cycles per segment and the segment order.
    pub schedule: ScheduleSection,
    /// How [`crate::inverse::run`] designs (default [`Method::Auto`];
    /// [`design`] always sequences).
    pub method: Method,
    /// Settings of the synthesis [`crate::inverse::run`] makes for the
    /// methods that synthesize.
    pub synthesis: crate::synth::SynthOptions,
    /// [`crate::inverse::run`] closes the loop on the sequenced design
    /// with these options ([`closed_loop`]; `None`: open loop).
    pub closed_loop: Option<closed_loop::LoopOptions>,
    /// Progress output and the long-run guard.
    pub runtime: Runtime,
    /// The parts' friction, replacing the target's `friction` (`design
    /// --friction`; [`crate::inverse::TargetFile::set_friction`]); `None`:
    /// the target's.
    pub friction: Option<crate::scene::FrictionSpec>,
    /// The model the candidates are played and judged at (`design
    /// --model`; a design by method only, [`crate::inverse::run`]).
    pub model: PlayModel,
}

impl DesignOptions {
    /// The default options with the basis cached in `cache` and no
    /// progress output (the studies' and tests' designs).
    pub fn cached_quiet(cache: &std::path::Path) -> DesignOptions {
        DesignOptions {
            basis: BasisSection {
                cache_dir: Some(cache.to_path_buf()),
                ..BasisSection::default()
            },
            runtime: Runtime::QUIET,
            ..DesignOptions::default()
        }
    }

    /// These options designing by `method` with `synthesis`
    /// ([`crate::inverse::run`]).
    pub fn by_method(
        &self,
        method: Method,
        synthesis: &crate::synth::SynthOptions,
    ) -> DesignOptions {
        DesignOptions {
            method,
            synthesis: *synthesis,
            ..self.clone()
        }
    }

    /// These options with the physics `target` states in `settings`: its
    /// nominal friction and its gravity ([`Target::physics`]). Every
    /// design entry point applies it first, so the basis (whose cache key
    /// holds the settings), the synthesis, the plays and `schedule.json`
    /// all use the target's parts.
    pub(crate) fn for_target(&self, target: &Target) -> DesignOptions {
        DesignOptions {
            settings: target.physics(&self.settings),
            ..self.clone()
        }
    }
}

/// One row of the fewer-primitives table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SparsityRow {
    /// Segments allowed.
    pub k: usize,
    /// Relative L2 error of the best fit found with at most k segments.
    pub relative_error: f64,
    /// The segments used.
    pub labels: Vec<String>,
}

/// A finished design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The schedule.
    pub schedule: Schedule,
    /// The sampled target.
    pub target: SampledTarget,
    /// Achieved field of the continuous fractions at the target points.
    pub achieved: Vec<[f64; 2]>,
    /// Achieved field of the whole-cycle schedule.
    pub achieved_quantized: Vec<[f64; 2]>,
    /// The fit's verified solution.
    pub solution: FitSolution,
    /// Error against the number of segments.
    pub sparsity: Vec<SparsityRow>,
    /// The basis used.
    pub basis: DesignBasis,
    /// Basis cache outcome.
    pub cache_status: crate::basis::CacheStatus,
    /// Seconds spent obtaining the basis (simulation or cache).
    pub basis_time_s: f64,
    /// Seconds spent fitting, verifying and scheduling.
    pub fit_time_s: f64,
    /// The order search, when [`ScheduleSection::order_search`] was set.
    pub order_search: Option<OrderSearch>,
    /// Seconds spent in the order search.
    pub order_time_s: f64,
}

/// Start points per side of the order search's grid over the target region.
pub(crate) const ORDER_SEARCH_POINTS: usize = 5;

impl From<crate::request::TargetError> for Error {
    fn from(e: crate::request::TargetError) -> Self {
        let (field, message) = e.located();
        Error::invalid(field, message)
    }
}

/// The rotations of the basis copies (degrees).
pub(crate) fn rotations(step: f64) -> Vec<f64> {
    let n = (360.0 / step).round().max(1.0) as usize;
    (0..n).map(|i| i as f64 * 360.0 / n as f64).collect()
}

/// Slack (absolute, on the relative L2 error) allowed when `shape` looks
/// for the strongest schedule: two percentage points.
pub(crate) const SHAPE_SLACK: f64 = 0.02;

/// Solves the fit. In `shape` mode, min ‖D(Aw − t)‖ over w ≥ 0 has many
/// minimisers whenever some basis fields cancel (Trans at opposite angles
/// sum to zero), and an interior-point solver returns one that spends time
/// on them: its strength 1/Σw is needlessly low. So `shape` is solved in two
/// stages: the best relative error e* first, then the strongest field within
/// e* + [`SHAPE_SLACK`] by the `budget` cone program. A tighter slack buys
/// fractions of a percent with fields that cancel (LineSinks against
/// LineSources), which are weak and which moving parts do not average as
/// predicted (closed-loop verification showed it).
/// If that second stage fails its checks, the first-stage answer stands.
pub(crate) fn strongest(problem: &FitProblem, options: &FitOptions) -> Result<FitSolution> {
    let first = fit::solve(problem, options)?;
    if options.mode != FitMode::Shape || first.unreachable {
        return Ok(first);
    }
    let eps = (first.relative_error + SHAPE_SLACK).min(0.99);
    let budget = FitOptions {
        mode: FitMode::Budget { rel_error: eps },
        ..*options
    };
    match fit::solve(problem, &budget) {
        Ok(mut second) if second.strength >= first.strength => {
            second.status = format!(
                "{} (shape: best error {:.4}, then strongest within {:.4})",
                second.status, first.relative_error, eps
            );
            Ok(second)
        }
        _ => Ok(first),
    }
}

/// A subset of the full fit's segments is used instead of all of them when
/// its relative error is within this of the full fit's.
pub(crate) const COMPACT_SLACK: f64 = 0.005;

/// Runs the inverse design for `target`: the open-loop pipeline
/// `basis_stage` → `fit_stage` → `schedule_stage` → `order_stage` (in
/// `design/stages.rs`), then the
/// [`Design`] assembled from their products.
pub fn design(target: &Target, opts: &DesignOptions) -> Result<Design> {
    let opts = &opts.for_target(target);
    opts.validate()?;
    let basis = stages::basis_stage(target, opts)?;
    let t_fit = Instant::now();
    // Over a friction range: one set of weights, worst case over the range.
    let fit = match stacked::ranged(target) {
        Some(spec) => stacked::fit_stage(target, &basis, spec, opts)?,
        None => stages::fit_stage(&basis, opts)?,
    };
    let (schedule, achieved_quantized) =
        stages::schedule_stage(target, &basis.sampled, &fit, opts)?;
    let fit_time_s = t_fit.elapsed().as_secs_f64();
    let t_order = Instant::now();
    let (schedule, order_search) = stages::order_stage(schedule, &basis.sampled, opts)?;
    let order_time_s = t_order.elapsed().as_secs_f64();
    Ok(Design {
        schedule,
        target: basis.sampled,
        achieved: fit.achieved,
        achieved_quantized,
        solution: fit.solution,
        sparsity: fit.sparsity,
        basis: fit.basis,
        cache_status: basis.cache_status,
        basis_time_s: basis.basis_time_s,
        fit_time_s,
        order_search,
        order_time_s,
    })
}

#[cfg(test)]
#[path = "../../tests/unit/design_speed.rs"]
mod speed_tests;
