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
//! 4. **Order** (optional, [`DesignOptions::order_search`]): the segment
//!    order and rest insertions that best realise the prediction in
//!    closed-loop simulation ([`order`]).

pub mod basis;
pub mod closed_loop;
pub mod order;

use std::path::PathBuf;
use std::time::Instant;

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

use crate::basis::cache::BasisCache;
use crate::basis::{symmetry, Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::field::{FieldKind, FieldSettings, Grid};
use crate::fit::{self, FitMetrics, FitMode, FitOptions, FitProblem, FitSolution};
use crate::play::PlayOptions;
use crate::request::{SampledTarget, Target};
use crate::schedule::{self, BasisInfo, KeptColumn, Schedule, Segment};
use order::{choose_order, OrderOptions, OrderSearch};

pub use basis::DesignBasis;

/// Options of [`design`].
#[derive(Debug, Clone)]
pub struct DesignOptions {
    /// Fit mode (default `shape`).
    pub mode: FitMode,
    /// Basis field kind (default velocity).
    pub kind: FieldKind,
    /// Rotation step of the basis copies (degrees, default 15).
    pub rotation_step_deg: f64,
    /// Horizontal shifts of the basis copies (default: none).
    pub shifts: Vec<[f64; 2]>,
    /// Keep basis columns that are invalid somewhere in the region.
    pub keep_invalid: bool,
    /// At most this many segments.
    pub max_primitives: Option<usize>,
    /// Minimum cycles per segment.
    pub min_cycles: u32,
    /// Total cycles (default: the shortest within the quantisation tolerance).
    pub total_cycles: Option<u32>,
    /// Tolerance on the field's quantisation error.
    pub quantization_tol: f64,
    /// Primitive kinds allowed in the basis (default: all eight).
    pub kinds: Vec<PrimitiveKind>,
    /// Simulation settings of the basis.
    pub settings: FieldSettings,
    /// Basis cache folder (`None`: no cache).
    pub cache_dir: Option<PathBuf>,
    /// No progress bar.
    pub quiet: bool,
    /// After scheduling, search the segment order and rest insertions that
    /// best realise the prediction ([`order`]) and play the
    /// schedule in that order.
    pub order_search: bool,
}

impl Default for DesignOptions {
    fn default() -> Self {
        DesignOptions {
            mode: FitMode::Shape,
            kind: FieldKind::Velocity,
            rotation_step_deg: 15.0,
            shifts: vec![[0.0, 0.0]],
            keep_invalid: false,
            max_primitives: None,
            min_cycles: schedule::DEFAULT_MIN_CYCLES,
            total_cycles: None,
            quantization_tol: schedule::DEFAULT_QUANTIZATION_TOL,
            kinds: PrimitiveKind::ALL.to_vec(),
            settings: FieldSettings::default(),
            cache_dir: Some(PathBuf::from(".platefield-cache")),
            quiet: false,
            order_search: false,
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
    pub cache_status: String,
    /// Seconds spent obtaining the basis (simulation or cache).
    pub basis_time_s: f64,
    /// Seconds spent fitting, verifying and scheduling.
    pub fit_time_s: f64,
    /// The order search, when [`DesignOptions::order_search`] was set.
    pub order_search: Option<OrderSearch>,
    /// Seconds spent in the order search.
    pub order_time_s: f64,
}

/// Start points per side of the order search's grid over the target region.
pub const ORDER_SEARCH_POINTS: usize = 5;

/// Runs the order search on `schedule` with the design's physics on
/// [`ORDER_SEARCH_POINTS`]² points over the bounding box of the target's
/// weighted points; a schedule without a moving segment is left as it is.
fn search_order(
    schedule: Schedule,
    target: &SampledTarget,
    opts: &DesignOptions,
) -> Result<(Schedule, Option<OrderSearch>)> {
    if schedule.segments.iter().all(|s| s.primitive.is_none()) {
        return Ok((schedule, None));
    }
    let region: Vec<[f64; 2]> = target
        .points
        .iter()
        .zip(&target.weights)
        .filter(|(_, w)| **w > 0.0)
        .map(|(p, _)| *p)
        .collect();
    let points = order::region_grid(&region, ORDER_SEARCH_POINTS);
    let verify = PlayOptions::from_settings(&opts.settings);
    let (reordered, search) = choose_order(&schedule, &OrderOptions::new(verify, points))?;
    Ok((reordered, Some(search)))
}

impl From<crate::request::TargetError> for Error {
    fn from(e: crate::request::TargetError) -> Self {
        let (field, message) = e.located();
        Error::invalid(field, message)
    }
}

impl From<fit::FitError> for Error {
    fn from(e: fit::FitError) -> Self {
        Error::NotConverged(format!("fit: {e}"))
    }
}

/// Stacks 2-D vectors as [x₀ … x_{n−1}, y₀ … y_{n−1}].
fn stack(v: &[[f64; 2]]) -> DVector<f64> {
    let n = v.len();
    DVector::from_fn(2 * n, |i, _| if i < n { v[i][0] } else { v[i - n][1] })
}

fn unstack(v: &DVector<f64>) -> Vec<[f64; 2]> {
    let n = v.len() / 2;
    (0..n).map(|i| [v[i], v[i + n]]).collect()
}

/// The rotations of the basis copies (degrees).
pub fn rotations(step: f64) -> Vec<f64> {
    let n = (360.0 / step).round().max(1.0) as usize;
    (0..n).map(|i| i as f64 * 360.0 / n as f64).collect()
}

/// Slack (absolute, on the relative L2 error) allowed when `shape` looks
/// for the strongest schedule: two percentage points.
pub const SHAPE_SLACK: f64 = 0.02;

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
pub const COMPACT_SLACK: f64 = 0.005;

/// Runs the inverse design for `target`.
pub fn design(target: &Target, opts: &DesignOptions) -> Result<Design> {
    if !(opts.rotation_step_deg > 0.0 && opts.rotation_step_deg <= 360.0) {
        return Err(Error::invalid(
            "--rotation-step",
            format!(
                "must be in (0, 360] degrees, got {}",
                opts.rotation_step_deg
            ),
        ));
    }
    let sampled = target.sample()?;
    let target_grid = target.grid.as_ref().map(|g| Grid {
        x: g.x,
        y: g.y,
        n: g.n,
    });
    let angles = rotations(opts.rotation_step_deg);
    let region = basis::sampling_grid(target_grid.as_ref(), &sampled.points);
    let angles_rad: Vec<f64> = angles.iter().map(|a| a.to_radians()).collect();
    let source = symmetry::source_grid(&region, &angles_rad, &opts.shifts);
    let primitives: Vec<Primitive> = opts.kinds.iter().map(|k| Primitive::new(*k)).collect();

    let t_basis = Instant::now();
    let (lib, cache_status) = match &opts.cache_dir {
        Some(dir) => {
            let (lib, status) = BasisCache::new(dir).get_or_build(
                &primitives,
                &source,
                &opts.settings,
                opts.kind,
                opts.quiet,
            )?;
            (lib, format!("{status:?}"))
        }
        None => (
            crate::basis::FieldLibrary::build(
                &primitives,
                &source,
                &opts.settings,
                opts.kind,
                opts.quiet,
            ),
            "no cache".to_string(),
        ),
    };
    let basis_time_s = t_basis.elapsed().as_secs_f64();

    let t_fit = Instant::now();
    let basis = basis::assemble(
        &lib,
        &angles,
        &opts.shifts,
        target_grid.as_ref(),
        &sampled.points,
        &sampled.weights,
        opts.keep_invalid,
    );
    if basis.columns.is_empty() {
        return Err(Error::Physical(format!(
            "no basis field is valid over the whole target region ({} left out, e.g. {}); shrink the region or pass --keep-invalid",
            basis.excluded.len(),
            basis.excluded.first().map_or(String::new(), |e| format!("{} ({:?})", e.label, e.reason))
        )));
    }
    let m = basis.columns.len();
    let a = DMatrix::from_fn(2 * sampled.len(), m, |i, j| {
        let n = sampled.len();
        let v = basis.columns[j].vectors[i % n];
        if i < n {
            v[0]
        } else {
            v[1]
        }
    });
    let t = stack(&sampled.vectors);
    let d = stack(
        &sampled
            .weights
            .iter()
            .map(|w| [w.sqrt(), w.sqrt()])
            .collect::<Vec<_>>(),
    );
    let problem = FitProblem {
        a: &a,
        t: &t,
        row_weights: Some(&d),
    };
    let options = FitOptions {
        mode: opts.mode,
        max_primitives: opts.max_primitives,
        ..FitOptions::default()
    };
    let mut solution = strongest(&problem, &options)?;

    // Fewer primitives: the error against the number of segments, over the
    // columns the full fit uses; and, unless --max-primitives was given, the
    // smallest subset that is as good as the full fit (within
    // COMPACT_SLACK), which makes shorter schedules with fewer joins.
    let support: Vec<usize> = (0..m).filter(|&j| solution.fractions[j] > 1e-9).collect();
    let mut sparsity = Vec::new();
    if !support.is_empty() && solution.strength > 0.0 {
        let sub = a.select_columns(&support);
        let sub_problem = FitProblem {
            a: &sub,
            t: &t,
            row_weights: Some(&d),
        };
        let path = fit::sparsity_path(&sub_problem, &opts.mode, support.len())?;
        let target_error = solution.relative_error;
        let compact = path
            .iter()
            .find(|row| row.k < support.len() && row.relative_error <= target_error + COMPACT_SLACK)
            .map(|row| {
                (
                    row.columns
                        .iter()
                        .map(|&c| support[c])
                        .collect::<Vec<usize>>(),
                    row.relative_error,
                )
            });
        for row in &path {
            sparsity.push(SparsityRow {
                k: row.k,
                relative_error: row.relative_error,
                labels: row
                    .columns
                    .iter()
                    .map(|&c| basis::label(&basis.columns[support[c]].primitive))
                    .collect(),
            });
        }
        if let (Some((cols, err)), None) = (compact, opts.max_primitives) {
            // The strongest field on the subset within the full fit's error
            // (or just above the subset's best, if that is larger).
            let sub = a.select_columns(&cols);
            let sub_problem = FitProblem {
                a: &sub,
                t: &t,
                row_weights: Some(&d),
            };
            let eps = target_error.max(err + 1e-4).min(0.99);
            let budget = FitOptions {
                mode: FitMode::Budget { rel_error: eps },
                ..options
            };
            if let (FitMode::Shape, Ok(mut small)) = (opts.mode, fit::solve(&sub_problem, &budget))
            {
                if small.strength > 0.0 {
                    let mut fractions = vec![0.0; m];
                    for (k, &j) in cols.iter().enumerate() {
                        fractions[j] = small.fractions[k];
                    }
                    small.status = format!(
                        "{} (shape: {} of {} segments, strongest within {:.4})",
                        small.status,
                        cols.len(),
                        support.len(),
                        eps
                    );
                    solution = FitSolution { fractions, ..small };
                }
            }
        }
    }
    let f = DVector::from_column_slice(&solution.fractions);
    let achieved_vec = &a * &f;
    let achieved = unstack(&achieved_vec);
    let strength = solution.strength;
    let metrics = |field: &[[f64; 2]]| -> Result<FitMetrics> {
        Ok(fit::field_metrics(
            &sampled.vectors,
            field,
            strength.max(f64::MIN_POSITIVE),
            Some(&sampled.weights),
        )?)
    };
    // Metrics are defined whenever the fit produced a field; a `shape` fit
    // that found nothing pointing the target's way has none.
    let degenerate = strength <= 0.0;
    let none = FitMetrics {
        relative_l2_error: 1.0,
        mean_angle_error_deg: 90.0,
        max_error: sampled.max_norm(),
        strength: 0.0,
    };
    let fit_metrics = if degenerate {
        none
    } else {
        metrics(&achieved)?
    };

    // Whole cycles.
    let periods: Vec<f64> = basis.columns.iter().map(|c| c.primitive.period()).collect();
    let rest_period = Primitive::new(PrimitiveKind::LineSink).period();
    let norm = achieved_vec.norm().max(f64::MIN_POSITIVE);
    let field_error = |q: &[f64]| -> f64 {
        let dq = DVector::from_fn(m, |j, _| q[j] - solution.fractions[j]);
        (&a * dq).norm() / norm
    };
    let quant = schedule::quantize(
        &solution.fractions,
        &periods,
        rest_period,
        opts.min_cycles,
        opts.total_cycles,
        opts.quantization_tol,
        &field_error,
    );
    let achieved_quantized = unstack(&(&a * DVector::from_column_slice(&quant.fractions)));
    let fit_quantized = if degenerate {
        none
    } else {
        metrics(&achieved_quantized)?
    };

    let mut order: Vec<usize> = (0..m).filter(|&j| quant.cycles[j] > 0).collect();
    order.sort_by(|&i, &j| {
        quant.cycles[j].cmp(&quant.cycles[i]).then_with(|| {
            basis::label(&basis.columns[i].primitive)
                .cmp(&basis::label(&basis.columns[j].primitive))
        })
    });
    let mut segments: Vec<Segment> = order
        .iter()
        .map(|&j| Segment {
            label: basis::label(&basis.columns[j].primitive),
            primitive: Some(basis.columns[j].primitive.clone()),
            weight: solution.fractions[j],
            cycles: quant.cycles[j],
            duration_s: f64::from(quant.cycles[j]) * periods[j],
        })
        .collect();
    if quant.rest_cycles > 0 {
        segments.push(Segment {
            label: "Rest".into(),
            primitive: None,
            weight: (1.0 - solution.fractions.iter().sum::<f64>()).max(0.0),
            cycles: quant.rest_cycles,
            duration_s: f64::from(quant.rest_cycles) * rest_period,
        });
    }
    let fit_time_s = t_fit.elapsed().as_secs_f64();
    let mut schedule = Schedule {
        target: target.name.clone(),
        target_spec: Some(target.clone()),
        total_cycles: 0,
        period_s: 0.0,
        segments,
        min_cycles: opts.min_cycles,
        fit: fit_metrics,
        fit_quantized,
        quantization_error: quant.error,
        poor_fit: solution.unreachable
            || fit_metrics.relative_l2_error > fit::UNREACHABLE_REL_ERROR,
        solver: schedule::SolverInfo {
            mode: opts.mode.name().into(),
            status: solution.status.clone(),
            iterations: solution.iterations,
            kkt_residual: solution.kkt_residual,
            independent_gap: solution.independent_gap,
        },
        basis: BasisInfo {
            columns: m,
            excluded: basis.excluded.clone(),
            kept_with_invalid_points: basis
                .columns
                .iter()
                .filter(|c| !c.invalid_points.is_empty())
                .map(|c| KeptColumn {
                    invalid_points: c.invalid_points.clone(),
                    label: basis::label(&c.primitive),
                })
                .collect(),
            kind: basis.kind,
            rotation_step_deg: opts.rotation_step_deg,
            shifts: opts.shifts.clone(),
        },
        settings: opts.settings,
    };
    schedule.derive();
    let t_order = Instant::now();
    let (schedule, order_search) = if opts.order_search {
        search_order(schedule, &sampled, opts)?
    } else {
        (schedule, None)
    };
    let order_time_s = t_order.elapsed().as_secs_f64();
    Ok(Design {
        schedule,
        target: sampled,
        achieved,
        achieved_quantized,
        solution,
        sparsity,
        basis,
        cache_status,
        basis_time_s,
        fit_time_s,
        order_search,
        order_time_s,
    })
}
