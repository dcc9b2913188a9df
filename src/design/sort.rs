//! Sorting parts by friction: one schedule for every part class of a
//! target (`crate::request::PartClass`), each class's field matched at
//! its own friction.
//!
//! **Physics.** A part slips when the friction it needs to follow the plate
//! exceeds μ_s N; its slip direction leads the plate velocity by
//! δ = asin(μg/A), so one plate motion gives parts of different μ different
//! fields. The strongest difference is the threshold itself: under an
//! *in-plane* motion (N = g exactly) whose plate acceleration stays below
//! μ_s g everywhere, a part placed at rest never slips: its field is
//! zero, while a part of lower friction slips and is carried (simulated
//! from rest, the held part creeps near the threshold: below 0.01 mm/s at
//! 0.75 of it, 0.3 mm/s at 0.9).
//! So besides the paper's primitives the basis holds **gentle copies** of
//! the in-plane translation (Trans) at [`GENTLE_FRACTIONS`] of the
//! stickier class's threshold: peak plate acceleration 1.5 d₀ω² (the
//! asymmetric waveform's peak) = f · μ_s,low g of the stickier class, where
//! μ_s,low is the low end of its static range. They move only the parts of
//! lower friction (measured: 1.9–2.7 mm/s for μ 0.2 against below
//! 0.01 and 0.3 mm/s for μ 0.45 at ω = 209 rad/s), and the fit uses them to push those parts
//! away from where the strong primitives gather the others.
//!
//! **Fit.** Every class's basis is simulated at the class's nominal
//! friction; the columns present in every class are stacked into one
//! matrix (class after class), the class targets likewise, and one set of
//! time fractions w ≥ 0 is fitted by the design's conic fit
//! ([`super::design`]'s `shape` then strongest within
//! `super::SHAPE_SLACK`). A stickier class is reached by the strong
//! columns only and so is faster; each class's target may therefore take
//! its own scale: every class after the first is scaled by each of
//! `CLASS_SCALES` in turn (one pass, class after class) and the scales
//! whose worst per-class shape error is lowest are kept. Each class's
//! predicted strength and shape error are its own rows' least-squares
//! scale and relative error.
//!
//! **Judged by playing**: every class's swarm is played
//! (`verify::sort_play`); where its parts end is the measure.

use nalgebra::DVector;
use serde::Serialize;

use super::basis::{self as dbasis, DesignBasis};
use super::stages::{self, BasisStage};
use super::{strongest, DesignOptions};
use crate::basis::{symmetry, FieldLibrary, Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::fit::{FitOptions, FitProblem};
use crate::request::{SampledTarget, Target};
use crate::schedule::Schedule;

/// Peak plate accelerations of the gentle Trans copies, as fractions of
/// the stickier class's μ_s g (both below 1: that class never slips).
pub const GENTLE_FRACTIONS: [f64; 2] = [0.75, 0.9];

/// Scales tried for each class's target after the first.
pub(crate) const CLASS_SCALES: [f64; 7] = [0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0];

/// A class's fitted field.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClassFit {
    /// The class's name.
    pub name: String,
    /// Its nominal static and kinetic friction.
    pub friction: [f64; 2],
    /// Scale of its target in the stacked fit.
    pub scale: f64,
    /// Predicted strength: least-squares scale of the whole-cycle field on
    /// the class's target.
    pub strength: f64,
    /// Predicted shape error at that strength (weighted relative L2).
    pub shape_error: f64,
}

/// A sort design: one schedule, every class's predicted field.
#[derive(Debug, Clone)]
pub struct SortDesign {
    /// The schedule (its settings hold the first class's friction).
    pub schedule: Schedule,
    /// Per class, in the target's order.
    pub classes: Vec<ClassFit>,
    /// The gentle columns offered to the fit (labels).
    pub gentle: Vec<String>,
}

/// Designs one schedule for all of `target`'s classes (see the module
/// docs). Errors when the target has no classes.
///
/// ```no_run
/// use platefield::design::{sort::design_sort, DesignOptions};
/// use platefield::request::Target;
/// let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
/// let d = design_sort(&target, &DesignOptions::default())?;
/// for c in &d.classes {
///     println!("{}: shape {:.1} %", c.name, 100.0 * c.shape_error);
/// }
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn design_sort(target: &Target, opts: &DesignOptions) -> Result<SortDesign> {
    if target.classes.len() < 2 {
        return Err(Error::invalid(
            "target.classes",
            "a sort needs at least 2 part classes",
        ));
    }
    opts.runtime.admit(&sort_estimate(target, opts)?)?;
    let gentle = gentle_primitives(target, opts);
    let mut bases = Vec::new();
    let mut sampled = Vec::new();
    let progress = crate::progress::Progress::new(
        "sort: libraries",
        "classes",
        target.classes.len() as u64,
        opts.runtime.progress(),
    );
    for i in 0..target.classes.len() {
        let ct = target.class_target(i);
        progress.set_message(format!("class {}", target.classes[i].name));
        let copts = opts.for_target(&ct);
        let stage = stages::basis_stage(&ct, &copts)?;
        let mut basis = stages::assemble_stage(&stage, &copts)?;
        append_gentle(&mut basis, &stage, &gentle, &copts);
        bases.push(basis);
        sampled.push(stage.sampled);
        progress.inc(1);
    }
    progress.finish();
    let basis = stack_bases(&bases);
    if basis.columns.is_empty() {
        return Err(Error::Physical(
            "no basis column is usable at every class's friction".into(),
        ));
    }
    let scales = choose_scales(&basis, &sampled)?;
    let stacked = stack_targets(&sampled, &scales);
    let opts0 = opts.for_target(&target.class_target(0));
    let fit = stages::fit_basis(basis, &stacked, &opts0)?;
    let (schedule, achieved) = stages::schedule_stage(target, &stacked, &fit, &opts0)?;
    let classes = class_fits(target, &sampled, &scales, &achieved)?;
    Ok(SortDesign {
        schedule,
        classes,
        gentle: gentle.iter().map(dbasis::label).collect(),
    })
}

/// The work of designing the sort of `target` ([`crate::work`]), stated
/// before it starts: each class's library when the cache does not hold it
/// (a library per class: each is simulated at its class's friction), and
/// each class's judge (counted, as a design's, at
/// `SYNTH_SEGMENT_CYCLES` cycles per period); the swarms are estimated
/// once the schedule is known (`crate::verify::sort_play::play_estimate`).
///
/// ```
/// use platefield::design::{sort::sort_estimate, DesignOptions};
/// use platefield::request::Target;
/// let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
/// let e = sort_estimate(&target, &DesignOptions::default())?;
/// assert!(e.terms.iter().any(|t| t.label.starts_with("class mu_0.45")));
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// A class whose target cannot be sampled.
pub fn sort_estimate(target: &Target, opts: &DesignOptions) -> Result<crate::work::Estimate> {
    let mut e = crate::work::Estimate::new(
        "target",
        "designing the sort",
        "fewer classes, a smaller target grid n, or a larger --rotation-step",
    );
    for (i, class) in target.classes.iter().enumerate() {
        let ct = target.class_target(i);
        let copts = opts.for_target(&ct);
        let sampled = ct.sample()?;
        if let Some(library) = stages::cold_library_estimate(&ct, &sampled, &copts) {
            e.terms.extend(library.terms.into_iter().map(|mut t| {
                t.label = format!("class {}: {}", class.name, t.label);
                t
            }));
        }
        e = e.plus(
            super::judge::judge_term(
                &ct,
                &sampled,
                super::method::sequenced_cycles(&copts),
                copts.settings.numerics.steps_per_cycle,
            )
            .named(&format!("class {}: judge", class.name)),
        );
    }
    Ok(e)
}

/// The gentle Trans copies for `target`'s classes: for every class
/// stickier than another, [`GENTLE_FRACTIONS`] of its threshold μ_s,low g
/// (module docs), as translation amplitudes d₀ = a / (1.5 ω²).
pub fn gentle_primitives(target: &Target, opts: &DesignOptions) -> Vec<Primitive> {
    let g = target.physics(&opts.settings).gravity;
    let lows: Vec<f64> = target.classes.iter().map(|c| c.friction.stat.lo).collect();
    let least = lows.iter().copied().fold(f64::INFINITY, f64::min);
    let mut out = Vec::new();
    for &mu in lows.iter().filter(|&&mu| mu > least) {
        for f in GENTLE_FRACTIONS {
            let p = Primitive::new(PrimitiveKind::Trans);
            let d0 = f * mu * g / (1.5 * p.omega * p.omega);
            let p = Primitive {
                translation: Some(d0),
                ..p
            };
            if !out.contains(&p) {
                out.push(p);
            }
        }
    }
    out
}

/// Appends `gentle`'s columns (simulated at the class's physics, rotated
/// like the library) to `basis`.
fn append_gentle(
    basis: &mut DesignBasis,
    stage: &BasisStage,
    gentle: &[Primitive],
    opts: &DesignOptions,
) {
    if gentle.is_empty() {
        return;
    }
    let sampled = &stage.sampled;
    let region = dbasis::sampling_grid(stage.target_grid.as_ref(), &sampled.points);
    let rad: Vec<f64> = stage.angles.iter().map(|a| a.to_radians()).collect();
    let source = symmetry::source_grid(&region, &rad, &opts.basis.shifts);
    let lib = FieldLibrary::build(gentle, &source, &opts.settings, opts.basis.kind, true);
    let extra = stages::assemble_library(&lib, stage, opts);
    basis.columns.extend(extra.columns);
    basis.excluded.extend(extra.excluded);
}

/// One basis of the columns usable in every class (matched by label), each
/// column's vectors the classes' vectors one after the other.
fn stack_bases(bases: &[DesignBasis]) -> DesignBasis {
    let mut out = DesignBasis {
        kind: bases[0].kind,
        columns: Vec::new(),
        excluded: Vec::new(),
    };
    for col in &bases[0].columns {
        let label = col.source.label();
        let found: Option<Vec<_>> = bases
            .iter()
            .map(|b| b.columns.iter().find(|c| c.source.label() == label))
            .collect();
        let Some(found) = found else {
            continue;
        };
        let mut c = col.clone();
        c.vectors.clear();
        c.invalid_points.clear();
        for f in found {
            let offset = c.vectors.len();
            c.invalid_points
                .extend(f.invalid_points.iter().map(|k| k + offset));
            c.vectors.extend_from_slice(&f.vectors);
        }
        out.columns.push(c);
    }
    for b in bases {
        for e in &b.excluded {
            if !out.excluded.iter().any(|x| x.label == e.label) {
                out.excluded.push(e.clone());
            }
        }
    }
    out
}

/// The classes' sampled targets one after the other, class i's vectors
/// times `scales[i]`.
fn stack_targets(sampled: &[SampledTarget], scales: &[f64]) -> SampledTarget {
    let mut out = SampledTarget {
        points: Vec::new(),
        vectors: Vec::new(),
        weights: Vec::new(),
    };
    for (s, k) in sampled.iter().zip(scales) {
        out.points.extend_from_slice(&s.points);
        out.vectors
            .extend(s.vectors.iter().map(|v| [k * v[0], k * v[1]]));
        out.weights.extend_from_slice(&s.weights);
    }
    out
}

/// The class scales (first class 1) whose stacked fit has the lowest worst
/// per-class shape error: each later class over [`CLASS_SCALES`] in turn.
fn choose_scales(basis: &DesignBasis, sampled: &[SampledTarget]) -> Result<Vec<f64>> {
    let n: usize = sampled.iter().map(|s| s.len()).sum();
    let a = stages::basis_matrix(basis, n);
    let worst = |scales: &[f64]| -> Result<f64> {
        let stacked = stack_targets(sampled, scales);
        let (t, d) = stages::stacked_target(&stacked);
        let problem = FitProblem {
            a: &a,
            t: &t,
            row_weights: Some(&d),
        };
        let sol = strongest(&problem, &FitOptions::default())?;
        let achieved = stages::unstack(&(&a * DVector::from_column_slice(&sol.fractions)));
        let errors = class_errors(sampled, &achieved);
        Ok(errors.iter().map(|e| e.1).fold(0.0, f64::max))
    };
    let mut scales = vec![1.0; sampled.len()];
    let mut best = worst(&scales)?;
    for i in 1..sampled.len() {
        for k in CLASS_SCALES {
            let mut trial = scales.clone();
            trial[i] = k;
            let e = worst(&trial)?;
            if e < best - 1e-12 {
                best = e;
                scales = trial;
            }
        }
    }
    Ok(scales)
}

/// Per class: (strength, shape error) of its rows of `achieved` against
/// its own (unscaled) target, weighted.
fn class_errors(sampled: &[SampledTarget], achieved: &[[f64; 2]]) -> Vec<(f64, f64)> {
    let mut start = 0;
    sampled
        .iter()
        .map(|s| {
            let a = &achieved[start..start + s.len()];
            start += s.len();
            let (mut at, mut tt) = (0.0, 0.0);
            for ((v, t), w) in a.iter().zip(&s.vectors).zip(&s.weights) {
                at += w * (v[0] * t[0] + v[1] * t[1]);
                tt += w * (t[0] * t[0] + t[1] * t[1]);
            }
            let sigma = if tt > 0.0 { at / tt } else { 0.0 };
            let (mut r, mut st) = (0.0, 0.0);
            for ((v, t), w) in a.iter().zip(&s.vectors).zip(&s.weights) {
                let e = [v[0] - sigma * t[0], v[1] - sigma * t[1]];
                r += w * (e[0] * e[0] + e[1] * e[1]);
                st += w * sigma * sigma * (t[0] * t[0] + t[1] * t[1]);
            }
            let shape = if sigma > 0.0 && st > 0.0 {
                (r / st).sqrt()
            } else {
                1.0
            };
            (sigma, shape)
        })
        .collect()
}

/// The classes' [`ClassFit`]s from the whole-cycle field `achieved`.
fn class_fits(
    target: &Target,
    sampled: &[SampledTarget],
    scales: &[f64],
    achieved: &[[f64; 2]],
) -> Result<Vec<ClassFit>> {
    Ok(class_errors(sampled, achieved)
        .into_iter()
        .zip(&target.classes)
        .zip(scales)
        .map(|(((strength, shape_error), c), &scale)| {
            let f = c.friction.nominal();
            ClassFit {
                name: c.name.clone(),
                friction: [f.stat, f.kinetic],
                scale,
                strength,
                shape_error,
            }
        })
        .collect())
}
