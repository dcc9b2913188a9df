//! The open-loop pipeline of [`super::design`] as named stages, each run
//! once in this order:
//!
//! [`basis_stage`] → [`fit_stage`] → [`schedule_stage`] → [`order_stage`],
//! after which [`super::design`] assembles the [`super::Design`].

use std::time::Instant;

use nalgebra::{DMatrix, DVector};

use super::basis::ColumnSource;
use super::order::{self, choose_order, OrderOptions, OrderSearch};
use super::{basis, strongest, DesignBasis, DesignOptions, SparsityRow};
use super::{COMPACT_SLACK, ORDER_SEARCH_POINTS};
use crate::basis::cache::BasisCache;
use crate::basis::{symmetry, FieldLibrary, Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::field::{Field, FieldKind, Grid};
use crate::fit::{self, FitMetrics, FitMode, FitOptions, FitProblem, FitSolution};
use crate::play::PlayOptions;
use crate::request::{SampledTarget, Target};
use crate::schedule::export::peaks::KinematicPeaks;
use crate::schedule::{
    self, BasisInfo, ExcludedColumn, ExclusionReason, KeptColumn, Schedule, Segment,
};
use crate::synth::ShakerLimits;
use crate::work::Estimate;

/// What [`basis_stage`] produces.
pub(crate) struct BasisStage {
    /// The sampled target.
    pub sampled: SampledTarget,
    /// The target's own grid, if it has one.
    pub target_grid: Option<Grid>,
    /// Rotations of the basis copies (degrees).
    pub angles: Vec<f64>,
    /// The simulated (or cached) primitive library on the source grid.
    pub library: FieldLibrary,
    /// Basis cache outcome.
    pub cache_status: crate::basis::CacheStatus,
    /// Seconds spent obtaining the library.
    pub basis_time_s: f64,
    /// The target's `shaker` limits (defaults filled in), when it gives
    /// them: columns over a limit are left out.
    pub limits: Option<ShakerLimits>,
}

/// Basis stage: checks the rotation step, samples `target`, and simulates
/// the allowed primitives once (or reads them from the cache) on a source
/// grid that covers the target region under every rotation and shift.
/// Consumes the target and the options; produces the sampled target and
/// the unrotated field library.
pub(crate) fn basis_stage(target: &Target, opts: &DesignOptions) -> Result<BasisStage> {
    // The options' own checks (the rotation step among them) run here too:
    // a library caller may come straight to the basis.
    opts.validate()?;
    let sampled = target.sample()?;
    let target_grid = target.grid;
    let angles = super::rotations(opts.basis.rotation_step_deg);
    let (primitives, source) = library_source(target_grid.as_ref(), &sampled, opts);

    let estimate = library_estimate(&primitives, &source, opts);
    let check = || opts.runtime.check(&estimate);
    let t_basis = Instant::now();
    let (library, cache_status) = match &opts.basis.cache_dir {
        Some(dir) => {
            let (lib, status) = BasisCache::new(dir).get_or_build(
                &primitives,
                &source,
                &opts.settings,
                opts.basis.kind,
                opts.runtime.progress(),
                check,
            )?;
            (lib, status)
        }
        None => {
            check()?;
            let lib = FieldLibrary::build(
                &primitives,
                &source,
                &opts.settings,
                opts.basis.kind,
                opts.runtime.progress(),
            );
            (lib, crate::basis::CacheStatus::NoCache)
        }
    };
    Ok(BasisStage {
        sampled,
        target_grid,
        angles,
        library,
        cache_status,
        basis_time_s: t_basis.elapsed().as_secs_f64(),
        limits: target
            .shaker
            .as_ref()
            .map(|s| ShakerLimits::from_spec(Some(s))),
    })
}

/// The primitives and the source grid the basis stage simulates for a
/// target of grid `target_grid` sampled as `sampled`: a grid that covers
/// the target region under every rotation and shift of `opts`.
fn library_source(
    target_grid: Option<&Grid>,
    sampled: &SampledTarget,
    opts: &DesignOptions,
) -> (Vec<Primitive>, Grid) {
    let region = basis::sampling_grid(target_grid, &sampled.points);
    let angles_rad: Vec<f64> = super::rotations(opts.basis.rotation_step_deg)
        .iter()
        .map(|a| a.to_radians())
        .collect();
    let source = symmetry::source_grid(&region, &angles_rad, &opts.basis.shifts);
    let primitives = opts
        .basis
        .kinds
        .iter()
        .map(|k| Primitive::new(*k))
        .collect();
    (primitives, source)
}

/// The work of the basis stage's library for `target` when the cache does
/// not hold it (no cache folder, or no entry under its key: a cold
/// build); `None` when it will be read from the cache.
pub(crate) fn cold_library_estimate(
    target: &Target,
    sampled: &SampledTarget,
    opts: &DesignOptions,
) -> Option<Estimate> {
    let grid = target.grid;
    let (primitives, source) = library_source(grid.as_ref(), sampled, opts);
    let cached = opts.basis.cache_dir.as_ref().is_some_and(|dir| {
        let key = BasisCache::key(&primitives, &source, &opts.settings, opts.basis.kind);
        BasisCache::new(dir).path(&key).is_file()
    });
    (!cached).then(|| library_estimate(&primitives, &source, opts))
}

/// The work of building the design's library of `primitives` on `source`
/// ([`crate::work`]).
pub(crate) fn library_estimate(
    primitives: &[Primitive],
    source: &Grid,
    opts: &DesignOptions,
) -> Estimate {
    let what = match opts.basis.kind {
        FieldKind::Force => "building the force library",
        FieldKind::Velocity => "building the velocity library",
    };
    // One term per primitive: the points it simulates (one per family of
    // points its motion moves alike, `crate::field::simulated_points`).
    primitives.iter().fold(
        Estimate::new(
            "target",
            what,
            "a smaller target region or grid n, a larger --rotation-step, fewer --shift or --primitives",
        ),
        |estimate, p| {
            estimate.plus(crate::work::field_term(
                p.kind.name(),
                1.0,
                "field",
                crate::field::simulated_points(&p.motion(), source) as f64,
                opts.basis.kind,
                &opts.settings,
            ))
        },
    )
}

/// What [`fit_stage`] produces.
pub(crate) struct FitStage {
    /// The basis columns at the target points.
    pub basis: DesignBasis,
    /// The basis matrix: column j is basis field j stacked as [x…, y…].
    pub a: DMatrix<f64>,
    /// The fit's verified solution (possibly on a compact subset).
    pub solution: FitSolution,
    /// Error against the number of segments.
    pub sparsity: Vec<SparsityRow>,
    /// Achieved field of the continuous fractions at the target points.
    pub achieved: Vec<[f64; 2]>,
    /// `achieved` as a stacked vector (A·w).
    pub achieved_vec: DVector<f64>,
    /// Metrics of `achieved` against the target.
    pub fit_metrics: FitMetrics,
}

/// Fit stage: rotates and shifts the library into basis columns at the
/// target points, then fits time fractions w ≥ 0, Σw ≤ 1 to the weighted
/// target ([`strongest`]), and replaces the fit by its smallest subset as
/// good within [`COMPACT_SLACK`] ([`compact_stage`]). Consumes the
/// [`BasisStage`]; produces the basis, the fractions and their field.
pub(crate) fn fit_stage(stage: &BasisStage, opts: &DesignOptions) -> Result<FitStage> {
    fit_basis(assemble_stage(stage, opts)?, &stage.sampled, opts)
}

/// The basis columns of [`fit_stage`] at the target points: the library
/// rotated and shifted, the options' motions appended, columns over the
/// shaker limits left out; an error when none is usable.
pub(crate) fn assemble_stage(stage: &BasisStage, opts: &DesignOptions) -> Result<DesignBasis> {
    let mut basis = assemble_library(&stage.library, stage, opts);
    add_motion_columns(&mut basis, stage, opts);
    if let Some(limits) = &stage.limits {
        leave_out_over_limit(&mut basis, limits);
    }
    if basis.columns.is_empty() {
        return Err(Error::Unreachable(no_usable_basis(&basis.excluded)));
    }
    Ok(basis)
}

/// Why no basis column is left, from the columns left out: the count and
/// first example of each cause, and only the remedies that address one.
/// Rotated copies of an isotropic primitive are left out because their
/// original is in the basis; they are never why none is usable, so they
/// are neither an example nor a reason to pass `--keep-invalid`.
pub(crate) fn no_usable_basis(excluded: &[ExcludedColumn]) -> String {
    let of = |pick: fn(&ExclusionReason) -> bool| -> (usize, String) {
        let mut hits = excluded.iter().filter(|e| pick(&e.reason));
        let first = hits
            .next()
            .map_or(String::new(), |e| format!("{}: {}", e.label, e.reason));
        (usize::from(!first.is_empty()) + hits.count(), first)
    };
    let invalid = of(|r| matches!(r, ExclusionReason::Invalid(_)));
    let over = of(|r| matches!(r, ExclusionReason::OverLimit { .. }));
    let mut causes = Vec::new();
    let mut remedies = Vec::new();
    if invalid.0 > 0 {
        causes.push(format!(
            "{} invalid somewhere in the target region (e.g. {})",
            invalid.0, invalid.1
        ));
        remedies.push("shrink the region or pass --keep-invalid");
    }
    if over.0 > 0 {
        causes.push(format!(
            "{} over the target's shaker limits (e.g. {})",
            over.0, over.1
        ));
        remedies.push("raise target.shaker's limits");
    }
    let copies = excluded.len() - invalid.0 - over.0;
    let copies = if copies > 0 {
        format!("; {copies} more are rotated copies of those (isotropic primitives)")
    } else {
        String::new()
    };
    format!(
        "no basis field is usable: every one is left out, {}{copies}; {}",
        causes.join(", "),
        remedies.join(", or ")
    )
}

/// `library`'s columns at `stage`'s target points: every entry at every
/// rotation and shift of the stage and the options ([`basis::assemble`]).
pub(crate) fn assemble_library(
    library: &FieldLibrary,
    stage: &BasisStage,
    opts: &DesignOptions,
) -> DesignBasis {
    let sampled = &stage.sampled;
    basis::assemble(
        library,
        &stage.angles,
        &opts.basis.shifts,
        stage.target_grid.as_ref(),
        &sampled.points,
        &sampled.weights,
        opts.basis.keep_invalid,
    )
}

/// The basis matrix of `basis` at the `n` points of `sampled`: column j is
/// basis field j stacked as [x…, y…].
pub(crate) fn basis_matrix(basis: &DesignBasis, n: usize) -> DMatrix<f64> {
    DMatrix::from_fn(2 * n, basis.columns.len(), |i, j| {
        let v = basis.columns[j].vectors[i % n];
        if i < n {
            v[0]
        } else {
            v[1]
        }
    })
}

/// The weighted target of `sampled` and its row weights, stacked.
pub(crate) fn stacked_target(sampled: &SampledTarget) -> (DVector<f64>, DVector<f64>) {
    let t = stack(&sampled.vectors);
    let d = stack(
        &sampled
            .weights
            .iter()
            .map(|w| [w.sqrt(), w.sqrt()])
            .collect::<Vec<_>>(),
    );
    (t, d)
}

/// The fit of [`fit_stage`] on an assembled `basis` whose columns hold
/// their fields at the points of `sampled`: time fractions w ≥ 0 by
/// [`strongest`], replaced by their smallest subset as good within
/// [`COMPACT_SLACK`] ([`compact_stage`]).
pub(crate) fn fit_basis(
    basis: DesignBasis,
    sampled: &SampledTarget,
    opts: &DesignOptions,
) -> Result<FitStage> {
    let a = basis_matrix(&basis, sampled.len());
    let (t, d) = stacked_target(sampled);
    let problem = FitProblem {
        a: &a,
        t: &t,
        row_weights: Some(&d),
    };
    let options = FitOptions {
        mode: opts.fit.mode,
        max_primitives: opts.fit.max_primitives,
        ..FitOptions::default()
    };
    let full = strongest(&problem, &options)?;
    let (solution, sparsity) = compact_stage(full, &problem, &options, &basis)?;
    let achieved_vec = &a * DVector::from_column_slice(&solution.fractions);
    let achieved = unstack(&achieved_vec);
    let fit_metrics = metrics(sampled, &achieved, solution.strength)?;
    Ok(FitStage {
        basis,
        a,
        solution,
        sparsity,
        achieved,
        achieved_vec,
        fit_metrics,
    })
}

/// Appends a column for each of [`BasisSection::motions`](super::BasisSection::motions): the motion's
/// field of the basis kind, simulated on the target's sampling grid with
/// the design's settings (left out, and listed, where it is invalid).
fn add_motion_columns(basis: &mut DesignBasis, stage: &BasisStage, opts: &DesignOptions) {
    let sampled = &stage.sampled;
    let grid = basis::sampling_grid(stage.target_grid.as_ref(), &sampled.points);
    for (label, signals) in &opts.basis.motions {
        let source = ColumnSource::Motion {
            label: label.clone(),
            signals: signals.clone(),
        };
        let field = Field::compute(&source.motion(), &grid, basis.kind, &opts.settings, &|| {});
        match basis::column(
            source,
            &field,
            stage.target_grid.is_some(),
            &sampled.points,
            &sampled.weights,
            opts.basis.keep_invalid,
        ) {
            Ok(c) => basis.columns.push(c),
            Err(e) => basis.excluded.push(e),
        }
    }
}

/// Leaves out (and lists) the basis columns whose primitive commands a
/// per-axis peak acceleration, velocity or stroke above `limits`
/// ([`ShakerLimits::first_excess`] of the exact [`KinematicPeaks`], world
/// axes, so a rotated copy is judged by its own x and y peaks). A primitive cannot be
/// scaled down without re-simulating its field, so it is left out whole.
fn leave_out_over_limit(basis: &mut DesignBasis, limits: &ShakerLimits) {
    let mut kept = Vec::with_capacity(basis.columns.len());
    for c in basis.columns.drain(..) {
        let peaks = KinematicPeaks::of_motion(&c.source.motion(), 1);
        match limits.first_excess(&peaks) {
            Some((axis, peak, limit)) => basis.excluded.push(ExcludedColumn {
                label: c.source.label(),
                invalid_samples: 0,
                reason: ExclusionReason::OverLimit { axis, peak, limit },
            }),
            None => kept.push(c),
        }
    }
    basis.columns = kept;
}

/// Fewer primitives (part of the fit stage): the error against the number
/// of segments over the columns the full fit `solution` uses; and, unless
/// `--max-primitives` was given, the smallest subset that is as good as the
/// full fit (within [`COMPACT_SLACK`]), refitted for the strongest field,
/// which makes shorter schedules with fewer joins. Consumes the full fit;
/// produces the fit to schedule and the sparsity table.
fn compact_stage(
    mut solution: FitSolution,
    problem: &FitProblem,
    options: &FitOptions,
    basis: &DesignBasis,
) -> Result<(FitSolution, Vec<SparsityRow>)> {
    let m = basis.columns.len();
    let support: Vec<usize> = (0..m).filter(|&j| solution.fractions[j] > 1e-9).collect();
    let mut sparsity = Vec::new();
    let has_field = !support.is_empty() && solution.strength > 0.0;
    if !has_field {
        return Ok((solution, sparsity));
    }
    let sub = problem.a.select_columns(&support);
    let sub_problem = FitProblem {
        a: &sub,
        ..*problem
    };
    let path = fit::sparsity_path(&sub_problem, &options.mode, support.len())?;
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
                .map(|&c| basis.columns[support[c]].source.label())
                .collect(),
        });
    }
    if let (Some((cols, err)), None) = (compact, options.max_primitives) {
        // The strongest field on the subset within the full fit's error
        // (or just above the subset's best, if that is larger).
        let sub = problem.a.select_columns(&cols);
        let sub_problem = FitProblem {
            a: &sub,
            ..*problem
        };
        let eps = target_error.max(err + 1e-4).min(0.99);
        let budget = FitOptions {
            mode: FitMode::Budget { rel_error: eps },
            ..*options
        };
        if let (FitMode::Shape, Ok(mut small)) = (options.mode, fit::solve(&sub_problem, &budget)) {
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
    Ok((solution, sparsity))
}

/// Metrics of `field` against the sampled target at fit strength
/// `strength`. Metrics are defined whenever the fit produced a field; a
/// `shape` fit that found nothing pointing the target's way (strength ≤ 0)
/// has none, and gets the no-field values.
pub(crate) fn metrics(
    sampled: &SampledTarget,
    field: &[[f64; 2]],
    strength: f64,
) -> Result<FitMetrics> {
    if strength <= 0.0 {
        return Ok(FitMetrics {
            relative_l2_error: 1.0,
            mean_angle_error_deg: 90.0,
            max_error: sampled.max_norm(),
            strength: 0.0,
        });
    }
    Ok(fit::field_metrics(
        &sampled.vectors,
        field,
        strength.max(f64::MIN_POSITIVE),
        Some(&sampled.weights),
    )?)
}

/// Schedule stage: quantises the fractions to whole cycles per segment
/// (at least `min_cycles` each, the plate at rest filling the remainder),
/// orders the segments by cycles (then label), and fills in the
/// Scalings [`ramps_within`] tries before it keeps the factor found.
const RAMP_SCALINGS: usize = 4;

/// A ramped six-signal segment's signals scaled by the largest factor ≤ 1
/// (found in up to [`RAMP_SCALINGS`] steps) whose whole segment, ramps
/// included, keeps within `limits`: the plate's peaks
/// ([`KinematicPeaks::within_scale`], what an export of it holds) and,
/// over `grid` when the target has one, the contact margin (the least
/// normal force per unit mass of a part at rest, N ≥ m g:
/// [`crate::synth::contact::kinematic_least_normal`] over the segment's
/// span; N − g is linear in the signals to first order, so the factor
/// 0.995 (1 − m) g / (g − N_min) lifts it to the margin). The label then
/// ends with the factor, as 1 − its shortfall. A ramp over R cycles multiplies the steady pose
/// by a smoothstep w(t), adding 2ẇẋ + ẅx to the steady acceleration, about
/// 2e-4 of it at R = 10 and 10–20 % at R = 1 (ẇ ∝ 1/R), which the steady
/// motion's synthesis did not budget: a vertical drive at the margin would
/// lift parts off the plate during the ramp. Returns the factor (1 for any
/// other segment).
fn ramps_within(
    seg: &mut Segment,
    limits: &ShakerLimits,
    grid: Option<&Grid>,
    settings: &crate::field::FieldSettings,
) -> f64 {
    use crate::motion::{Motion, Ramped};
    let (Some(ramp), Some(signals)) = (seg.ramp_cycles, seg.motion.clone()) else {
        return 1.0;
    };
    let ramped = |k: f64| {
        Motion::Ramped(Ramped {
            signals: signals.scaled(k),
            ramp,
            cycles: seg.cycles,
        })
    };
    let highest = signals.highest_harmonic();
    let spec = limits.to_spec();
    let mut k =
        KinematicPeaks::within_scale(|k| KinematicPeaks::of_plate(&ramped(k), highest), &spec);
    if let Some(grid) = grid {
        let (gravity, floor) = (settings.gravity, limits.contact_margin * settings.gravity);
        for _ in 0..RAMP_SCALINGS {
            let least = crate::synth::contact::kinematic_least_normal(&ramped(k), grid, settings);
            if least >= floor || least >= gravity {
                break;
            }
            k *= (0.995 * (gravity - floor) / (gravity - least)).clamp(0.0, 1.0);
        }
    }
    if k < 1.0 {
        seg.motion = Some(signals.scaled(k));
        seg.label = format!(
            "{} × (1 − {:.1e}) (its ramps within the shaker limits)",
            seg.label,
            1.0 - k
        );
    }
    k
}

/// [`Schedule`] with its fit, solver and basis records. Consumes the
/// target and the [`FitStage`]; produces the schedule and the field of
/// its whole-cycle fractions at the target points.
pub(crate) fn schedule_stage(
    target: &Target,
    sampled: &SampledTarget,
    fit: &FitStage,
    opts: &DesignOptions,
) -> Result<(Schedule, Vec<[f64; 2]>)> {
    let (basis, a, solution) = (&fit.basis, &fit.a, &fit.solution);
    let m = basis.columns.len();
    let periods: Vec<f64> = basis.columns.iter().map(|c| c.source.period()).collect();
    let rest_period = Primitive::new(PrimitiveKind::LineSink).period();
    let norm = fit.achieved_vec.norm().max(f64::MIN_POSITIVE);
    let field_error = |q: &[f64]| -> f64 {
        let dq = DVector::from_fn(m, |j, _| q[j] - solution.fractions[j]);
        (a * dq).norm() / norm
    };
    let quant = schedule::quantize(
        &solution.fractions,
        &periods,
        rest_period,
        opts.schedule.min_cycles,
        opts.schedule.total_cycles,
        opts.schedule.quantization_tol,
        &field_error,
    );
    let mut order: Vec<usize> = (0..m).filter(|&j| quant.cycles[j] > 0).collect();
    // A given total too short for any segment to reach its minimum cycles
    // leaves no moving segment: name --cycles, not the empty schedule.
    let largest = solution.fractions.iter().copied().fold(0.0, f64::max);
    if let (Some(n), true, true) = (opts.schedule.total_cycles, order.is_empty(), largest > 0.0) {
        let need = (0.5 * f64::from(opts.schedule.min_cycles.max(1)) / largest).ceil();
        return Err(Error::invalid(
            "--cycles",
            format!(
                "{n} cycles leave no segment of at least --min-cycles {} cycles (the fit's largest time fraction is {largest:.3}): give --cycles ≥ {need} or a smaller --min-cycles",
                opts.schedule.min_cycles
            ),
        ));
    }
    // Six-signal segments ramp in and out when they share the schedule.
    let mixed = order.len() > 1;
    order.sort_by(|&i, &j| {
        quant.cycles[j].cmp(&quant.cycles[i]).then_with(|| {
            basis.columns[i]
                .source
                .label()
                .cmp(&basis.columns[j].source.label())
        })
    });
    let mut segments: Vec<Segment> = order
        .iter()
        .map(|&j| {
            basis.columns[j]
                .source
                .segment(solution.fractions[j], quant.cycles[j], mixed)
        })
        .collect();
    // Ramps are a transform the steady motion's synthesis did not budget:
    // each ramped segment is scaled into the target's limits.
    let limits = crate::synth::ShakerLimits::from_spec(target.shaker.as_ref());
    for seg in &mut segments {
        ramps_within(seg, &limits, target.grid.as_ref(), &opts.settings);
    }
    if quant.rest_cycles > 0 {
        segments.push(Segment {
            label: "Rest".into(),
            primitive: None,
            motion: None,
            ramp_cycles: None,
            weight: (1.0 - solution.fractions.iter().sum::<f64>()).max(0.0),
            cycles: quant.rest_cycles,
            duration_s: f64::from(quant.rest_cycles) * rest_period,
        });
    }
    // The ramp cycles a mixed schedule's six-signal segment is given on top
    // of its quantised cycles lengthen the period and dilute every segment's
    // share: the whole-cycle field and its strength are scaled by it (1 for
    // schedules of primitives).
    let period: f64 = segments.iter().map(|s| s.duration_s).sum();
    let ramps: f64 = segments
        .iter()
        .map(|s| f64::from(s.ramp_cycles.unwrap_or(0)) * s.cycle_period().unwrap_or(0.0))
        .sum();
    let dilution = if ramps > 0.0 {
        (period - ramps) / period
    } else {
        1.0
    };
    let achieved_quantized =
        unstack(&(a * DVector::from_column_slice(&quant.fractions) * dilution));
    let fit_quantized = metrics(sampled, &achieved_quantized, solution.strength * dilution)?;
    let mut schedule = Schedule {
        target: target.name.clone(),
        target_spec: Some(target.clone()),
        total_cycles: 0,
        period_s: 0.0,
        segments,
        min_cycles: opts.schedule.min_cycles,
        fit: fit.fit_metrics,
        fit_quantized,
        quantization_error: quant.error,
        poor_fit: solution.unreachable
            || fit.fit_metrics.relative_l2_error > fit::UNREACHABLE_REL_ERROR,
        solver: schedule::SolverInfo {
            mode: opts.fit.mode.name().into(),
            status: if solution.independent_kept {
                format!(
                    "{}, its weights replaced by the independent NNLS optimum",
                    solution.status
                )
            } else {
                solution.status.clone()
            },
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
                    label: c.source.label(),
                })
                .collect(),
            kind: basis.kind,
            rotation_step_deg: opts.basis.rotation_step_deg,
            shifts: opts.basis.shifts.clone(),
        },
        settings: opts.settings,
        played: None,
        rungs: None,
    };
    schedule.derive();
    Ok((schedule, achieved_quantized))
}

/// Order stage (only with [`ScheduleSection::order_search`](super::ScheduleSection::order_search)): runs the order
/// search on `schedule` with the design's physics on
/// [`ORDER_SEARCH_POINTS`]² points over the bounding box of the target's
/// weighted points, and returns the schedule in the order found with the
/// search's record. Without the option, or for a schedule without a moving
/// segment, the schedule is returned as it is with no record.
pub(crate) fn order_stage(
    schedule: Schedule,
    target: &SampledTarget,
    opts: &DesignOptions,
) -> Result<(Schedule, Option<OrderSearch>)> {
    if !opts.schedule.order_search || schedule.segments.iter().all(|s| !s.is_moving()) {
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
    let order_opts = OrderOptions {
        progress: opts.runtime.progress(),
        ..OrderOptions::new(verify, points)
    };
    let (reordered, search) = choose_order(&schedule, &order_opts)?;
    Ok((reordered, Some(search)))
}

/// Stacks 2-D vectors as [x₀ … x_{n−1}, y₀ … y_{n−1}].
fn stack(v: &[[f64; 2]]) -> DVector<f64> {
    let n = v.len();
    DVector::from_fn(2 * n, |i, _| if i < n { v[i][0] } else { v[i - n][1] })
}

/// The inverse of [`stack`].
pub(crate) fn unstack(v: &DVector<f64>) -> Vec<[f64; 2]> {
    let n = v.len() / 2;
    (0..n).map(|i| [v[i], v[i + n]]).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::Validity;

    fn left_out(label: &str, reason: ExclusionReason) -> ExcludedColumn {
        ExcludedColumn {
            invalid_samples: 0,
            label: label.into(),
            reason,
        }
    }

    /// With every column over the shaker limit and the isotropic
    /// copies listed first, the message names an over-limit column, counts
    /// the copies, and does not suggest --keep-invalid (which does not
    /// help); with invalid columns it does.
    #[test]
    fn no_usable_basis_names_the_cause_not_a_copy() {
        let copy = left_out(
            "ScaledCircle@15°",
            ExclusionReason::IsotropicCopy {
                copy_of: "ScaledCircle@0°".into(),
                rotation_change: 1e-12,
            },
        );
        let over = left_out(
            "LineSink@0°",
            ExclusionReason::OverLimit {
                axis: "angular.y".into(),
                peak: 120.0,
                limit: 100.0,
            },
        );
        let m = no_usable_basis(&[copy.clone(), over.clone(), over.clone()]);
        assert!(
            m.contains("2 over the target's shaker limits (e.g. LineSink@0°"),
            "{m}"
        );
        assert!(m.contains("1 more are rotated copies"), "{m}");
        assert!(!m.contains("ScaledCircle@15°"), "{m}");
        assert!(!m.contains("--keep-invalid"), "{m}");
        let invalid = left_out("Trans@0°", ExclusionReason::Invalid(Validity::ContactLost));
        let m = no_usable_basis(&[copy, invalid]);
        assert!(
            m.contains("1 invalid somewhere in the target region (e.g. Trans@0°"),
            "{m}"
        );
        assert!(m.contains("--keep-invalid") && !m.contains("shaker"), "{m}");
    }
}
