//! The sequenced design over a friction range: one set of time fractions
//! fitted against the basis built at each friction sample, minimising the
//! worst shape error over the samples (`crate::fit::worst`).
//!
//! A primitive's field depends on the parts' friction (the slip direction
//! leads the plate velocity by δ = asin(μg/A)), so a schedule fitted at the
//! middle of a range can turn its field at the ends. The library is
//! therefore simulated at the ends and the middle of the range
//! ([`FrictionSpec::values`] with 3 per range), every column kept at all of
//! them is fitted with one set of weights against all three bases, and the
//! fit's worst error is checked at the values halfway between the samples:
//! where one of them is worse than the worst sample by more than
//! `REFINE_TOL`, the samples are doubled (5, then 9 per range) and the fit
//! repeated. The schedule records the nominal (middle) basis's field; the
//! solver status records the worst case and the samples.

use std::collections::HashMap;

use nalgebra::{DMatrix, DVector};

use super::stages::{self, basis_matrix, metrics, stacked_target, unstack, BasisStage, FitStage};
use super::{DesignBasis, DesignOptions, SHAPE_SLACK};
use crate::dynamics::Friction;
use crate::error::Result;
use crate::field::FieldSettings;
use crate::fit::worst::{shape_and_strength, solve_worst_case, WorstCaseFit, WorstCaseOptions};
use crate::fit::{FitProblem, FitSolution, UNREACHABLE_REL_ERROR};
use crate::request::{FrictionSpec, Target};

/// Samples are added where the fit's error halfway between two samples
/// exceeds its worst sampled error by more than this (absolute, 0.2 %).
pub(crate) const REFINE_TOL: f64 = 0.002;

/// Most samples per range (3, 5, then 9).
pub(crate) const MAX_SAMPLES: usize = 9;

/// The friction range a target states, when it is a range.
pub(crate) fn ranged(target: &Target) -> Option<FrictionSpec> {
    target.friction.filter(|f| !f.is_exact())
}

/// The fit stage over `spec`'s range (see the module docs): the nominal
/// basis of `stage` (built at the middle of the range) restricted to the
/// columns usable at every sample, and the stacked worst-case fit.
pub(crate) fn fit_stage(
    target: &Target,
    stage: &BasisStage,
    spec: FrictionSpec,
    opts: &DesignOptions,
) -> Result<FitStage> {
    let nominal = stages::assemble_stage(stage, opts)?;
    let mut n = 3;
    let mut bases = bases_at(target, opts, &spec.values(n), Vec::new())?;
    loop {
        let (basis, matrices) = common_columns(&nominal, &bases, stage.sampled.len());
        let (t, d) = stacked_target(&stage.sampled);
        let fit = solve_worst_case(&matrices, &t, Some(&d), &worst_options())?;
        if n < MAX_SAMPLES {
            let finer = spec.values(2 * n - 1);
            let more = bases_at(target, opts, &finer, bases.clone())?;
            let (still, all) = common_columns(&basis, &more, stage.sampled.len());
            // A column lost at a new sample, or a worse error between the
            // samples: fit again on the finer samples.
            let lost = still.columns.len() != basis.columns.len();
            if lost || worst_between(&all, &t, &d, &fit) > fit.worst() + REFINE_TOL {
                (n, bases) = (2 * n - 1, more);
                continue;
            }
        }
        return finish(basis, &stage.sampled, fit, &bases);
    }
}

fn worst_options() -> WorstCaseOptions {
    WorstCaseOptions {
        slack: SHAPE_SLACK,
        ..WorstCaseOptions::default()
    }
}

/// The basis assembled at each of `values` (library simulated or read
/// from the cache at that friction), reusing those in `have`.
fn bases_at(
    target: &Target,
    opts: &DesignOptions,
    values: &[Friction],
    have: Vec<(Friction, DesignBasis)>,
) -> Result<Vec<(Friction, DesignBasis)>> {
    let close = |a: Friction, b: Friction| {
        (a.stat - b.stat).abs() < 1e-12 && (a.kinetic - b.kinetic).abs() < 1e-12
    };
    values
        .iter()
        .map(|&f| {
            if let Some((_, b)) = have.iter().find(|(g, _)| close(*g, f)) {
                return Ok((f, b.clone()));
            }
            let at = DesignOptions {
                settings: FieldSettings {
                    friction: f,
                    ..opts.settings
                },
                ..opts.clone()
            };
            let stage = stages::basis_stage(target, &at)?;
            Ok((f, stages::assemble_stage(&stage, &at)?))
        })
        .collect()
}

/// `nominal` without the columns missing at some sample (listed as
/// excluded with the reason that sample gave), and the matrix of the kept
/// columns at each sample.
fn common_columns(
    nominal: &DesignBasis,
    bases: &[(Friction, DesignBasis)],
    n: usize,
) -> (DesignBasis, Vec<DMatrix<f64>>) {
    let index: Vec<HashMap<String, usize>> = bases
        .iter()
        .map(|(_, b)| {
            let mut map = HashMap::new();
            for (j, c) in b.columns.iter().enumerate() {
                map.entry(c.source.label()).or_insert(j);
            }
            map
        })
        .collect();
    let mut kept = nominal.clone();
    kept.columns.clear();
    for c in &nominal.columns {
        let label = c.source.label();
        match index.iter().position(|m| !m.contains_key(&label)) {
            None => kept.columns.push(c.clone()),
            Some(k) => kept.excluded.extend(
                bases[k]
                    .1
                    .excluded
                    .iter()
                    .find(|e| e.label == label)
                    .cloned(),
            ),
        }
    }
    let matrices = index
        .iter()
        .zip(bases)
        .map(|(map, (_, b))| {
            let mut at = kept.clone();
            at.columns = kept
                .columns
                .iter()
                .map(|c| b.columns[map[&c.source.label()]].clone())
                .collect();
            basis_matrix(&at, n)
        })
        .collect();
    (kept, matrices)
}

/// The worst relative error of `fit`'s fractions over the samples of `all`.
fn worst_between(
    all: &[DMatrix<f64>],
    t: &DVector<f64>,
    d: &DVector<f64>,
    fit: &WorstCaseFit,
) -> f64 {
    all.iter()
        .map(|a| {
            let p = FitProblem {
                a,
                t,
                row_weights: Some(d),
            };
            shape_and_strength(&p, &fit.fractions).0
        })
        .fold(0.0, f64::max)
}

/// The [`FitStage`] of the worst-case fit: the field at the nominal basis.
fn finish(
    basis: DesignBasis,
    sampled: &crate::request::SampledTarget,
    fit: WorstCaseFit,
    bases: &[(Friction, DesignBasis)],
) -> Result<FitStage> {
    let a = basis_matrix(&basis, sampled.len());
    let achieved_vec = &a * DVector::from_column_slice(&fit.fractions);
    let achieved = unstack(&achieved_vec);
    // The prediction at the nominal friction: its least-squares strength.
    let (t, d) = stacked_target(sampled);
    let nominal = FitProblem {
        a: &a,
        t: &t,
        row_weights: Some(&d),
    };
    let strength = shape_and_strength(&nominal, &fit.fractions).1;
    let fit_metrics = metrics(sampled, &achieved, strength)?;
    let at: Vec<String> = bases
        .iter()
        .zip(&fit.errors)
        .map(|((f, _), e)| format!("{} {e:.4}", mu_text(*f)))
        .collect();
    let worst = fit.worst();
    let solution = FitSolution {
        fractions: fit.fractions,
        strength,
        objective: worst,
        relative_error: worst,
        status: format!("{}; relative error at μ {}", fit.status, at.join(", ")),
        iterations: fit.solves,
        solve_time_s: 0.0,
        total_time_s: 0.0,
        kkt_residual: 0.0,
        independent_gap: fit.best_worst - fit.bounds[0],
        unreachable: worst > UNREACHABLE_REL_ERROR,
        active_set: false,
        independent_kept: false,
    };
    Ok(FitStage {
        basis,
        a,
        solution,
        sparsity: Vec::new(),
        achieved,
        achieved_vec,
        fit_metrics,
    })
}

/// `0.300`, or `0.300/0.250` (static/kinetic) when they differ.
fn mu_text(f: Friction) -> String {
    if f.stat == f.kinetic {
        format!("{:.3}", f.kinetic)
    } else {
        format!("{:.3}/{:.3}", f.stat, f.kinetic)
    }
}
