//! Paths by exact replays, for tracks the field model cannot follow.
//!
//! **When.** The field model (`super::model`) leaves out the cycles a
//! part takes to reach its periodic orbit after each join. On a schedule
//! whose segments last a few cycles each (the shipped sink: four line
//! sinks of ten cycles each, played in turn) those transients are much of
//! the motion, and the field model misses even noise-free tracks by more
//! than the camera's noise. [`super::calibrate`] tells the two cases apart
//! on the tracks themselves: each part's residual at its own best μ on the
//! field model's lattice, pooled, against the tracks' own noise
//! (`super::Tracks::noise`); beyond [`FIELD_MISS`] × the noise the field
//! cannot serve and the paths are replayed.
//!
//! **Model.** Each part is put down at rest on the plate at r₀ when the
//! schedule starts (t = 0) and played through the schedule by the exact
//! simulator (`super::simulate`: every segment, the joins, rest) under
//! θ; its positions at its frames' times are its path. Every frame is
//! fitted, the start-up transient included. No field and no model bias to
//! remove: the replay is the point-part model itself, each segment
//! integrated whole on its fixed-step grid with its plate kinematics
//! tabulated once (`super::simulate::play_on_grid`; what a calibration
//! costs: `docs/calibrate.md`).
//! Fewer steps than the schedule's serve where their error is far below
//! the camera's noise: [`steps_for`] halves them while a replay stays
//! within [`STEP_ERROR`] of the noise of the finer one, and
//! `steps_hold` checks that again at the estimate (at 0.2 mm of noise:
//! 16 of 64 on the shipped sink, 32 on squeeze_trans).
//!
//! **Fit.** The least squares of `super::estimate` (the same noise model
//! and RSS, each track's start a nuisance), by Gauss–Newton over θ's free
//! parameters and every track's r₀ at once. The paths' sensitivities are
//! forward differences, one replay per parameter and track. The starts
//! are eliminated track by track (the normal equations' Schur
//! complement): with A_i and B_i track i's sensitivities to its start and
//! to θ, e_i its residual and B̃_i = (I − A_i(A_iᵀA_i)⁻¹A_iᵀ)B_i,
//! S = Σ_i B̃_iᵀB̃_i and the step is δθ = S⁻¹ Σ_i B̃_iᵀe_i, each start's
//! δr₀ = (A_iᵀA_i)⁻¹A_iᵀ(e_i − B_i δθ). A step that raises the RSS is
//! halved. The iteration stops when every free parameter's step is below
//! [`STEP_TOL`] of its standard error; that last step is taken on the
//! linearised paths (no replay). After a step that stays within θ's 95 %
//! confidence region (s²·δθᵀSδθ/σ̂² ≤ χ²_p(0.95), [`CHI2_95`]) the next
//! one reuses the sensitivities (the chord method: only the paths are
//! replayed): the intervals already take the paths as linear in θ over
//! that region, so its sensitivities are the same to their precision. A
//! chord step that lowers no RSS is taken again from fresh
//! sensitivities. The covariance is σ̂²S⁻¹, σ̂² = RSS/dof,
//! widened by the tracks' own scatter as the field fit's is
//! (`super::estimate`: each track's score B̃_iᵀẽ_i a cluster).

use nalgebra::{DMatrix, DVector, Matrix2, Vector2};
use rayon::prelude::*;

use super::estimate::{robust_widening, BOUNDS};
use super::model::{friction, Theta, SCALE};
use super::simulate::{play_on_grid, schedule_motion};
use super::tracks::Track;
use crate::dynamics::{MIN_STEPS_PER_CYCLE, V2};
use crate::error::{Error, Result};
use crate::schedule::Schedule;

/// The field model serves while its pooled residual on the μ lattice is
/// at most this many times the tracks' own noise (a model error of up to
/// 0.75 σ added in quadrature); beyond it the paths are replayed.
pub const FIELD_MISS: f64 = 1.25;

/// A class's Gauss–Newton stops when every free parameter's step is below
/// this fraction of its standard error.
pub const STEP_TOL: f64 = 0.05;

/// A part's own fit stops at steps below this fraction of its standard
/// error: its estimate only sorts it into a class and starts the class's
/// fit.
pub const OWN_STEP_TOL: f64 = 0.5;

/// Gauss–Newton iterations at most.
const MAX_ITERATIONS: usize = 12;

/// Halvings of a step that raises the RSS, at most.
const HALVINGS: usize = 6;

/// A replay's discretisation error is held to this fraction of the
/// tracks' own noise: an independent error that size adds 10⁻⁴ of the
/// noise's variance to the residual ([`steps_for`]).
pub const STEP_ERROR: f64 = 0.01;

/// 95 % quantiles of χ² with 1, 2 and 3 degrees of freedom: 1.96², −2 ln
/// 0.05, and the root of erf(√(x/2)) − √(2x/π)·e^(−x/2) = 0.95.
pub const CHI2_95: [f64; 3] = [
    3.841_458_820_694_124,
    5.991_464_547_107_979,
    7.814_727_903_251_178,
];

/// Forward-difference step of a start (m).
const START_STEP: f64 = 1e-6;

/// Forward-difference steps of θ (μ_k, μ_s − μ_k, scale): the paths are
/// smooth in θ far below these.
const THETA_STEP: Theta = [1e-4, 1e-3, 1e-4];

/// A part put down at rest at `r0` at t = 0 and played through `schedule`
/// under θ: its positions at `times`, flattened (x₀, y₀, x₁, …); `None`
/// where it loses contact with the plate.
///
/// # Errors
/// θ's scale cannot be played.
pub(crate) fn path(
    schedule: &Schedule,
    theta: &Theta,
    r0: [f64; 2],
    times: &[f64],
) -> Result<Option<Vec<f64>>> {
    let sm = schedule_motion(schedule, theta[SCALE])?;
    match play_on_grid(schedule, &sm, friction(theta), V2::from(r0), times) {
        Ok(p) => Ok(Some(p.iter().flat_map(|r| [r.x, r.y]).collect())),
        Err(Error::ContactLost(_)) => Ok(None),
        Err(e) => Err(e),
    }
}

/// `schedule` with the fewest RK4 steps per cycle its replays need, and
/// the replays this cost.
///
/// RK4's error at n steps per cycle is about 16 times its error at 2n,
/// so the gap between the two replays, |r_n − r_2n| ≈ (15/16)·err_n, is
/// the error of the coarser one. From the schedule's own steps, halved
/// while the halved replay of `probe` (the track observed longest: the
/// error grows with time) under θ, put down at its first observed
/// position, stays within [`STEP_ERROR`] × `noise` of the finer one on
/// each axis at every frame (`within_error`), and the schedule stays
/// valid (at least 8 steps per period of its highest harmonic). The
/// schedule as it is without a noise estimate.
///
/// ```
/// use platefield::calibrate::replay::steps_for;
/// use platefield::calibrate::tracks::Frame;
/// use platefield::calibrate::Track;
/// use platefield::schedule::Schedule;
/// let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
/// let frames = (0..300).map(|k| Frame { t: k as f64 / 30.0, r: [0.01, 0.0], line: 0 }).collect();
/// let probe = Track { part: "a".into(), frames };
/// // At 0.2 mm of noise 32 steps per cycle are within 2 µm of 64.
/// let (coarse, _) = steps_for(&schedule, &probe, &[0.23, 0.0, 1.0], Some(2e-4))?;
/// assert_eq!(coarse.settings.numerics.steps_per_cycle, 32);
/// // Without a noise estimate the schedule's own steps are kept.
/// let (same, replays) = steps_for(&schedule, &probe, &[0.23, 0.0, 1.0], None)?;
/// assert_eq!((same.settings.numerics.steps_per_cycle, replays), (64, 0));
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// θ's scale cannot be played.
pub fn steps_for(
    schedule: &Schedule,
    probe: &Track,
    theta: &Theta,
    noise: Option<f64>,
) -> Result<(Schedule, usize)> {
    let mut out = schedule.clone();
    let Some(noise) = noise else {
        return Ok((out, 0));
    };
    let mut replays = 0;
    loop {
        let mut coarser = out.clone();
        coarser.settings.numerics.steps_per_cycle /= 2;
        if coarser.settings.numerics.steps_per_cycle < MIN_STEPS_PER_CYCLE
            || coarser.validate().is_err()
        {
            return Ok((out, replays));
        }
        replays += 2;
        if !within_error(&coarser, &out, probe, theta, noise)? {
            return Ok((out, replays));
        }
        out = coarser;
    }
}

/// `coarse` with its RK4 steps per cycle doubled, up to `own`, until its
/// replay of `probe` under θ stays within [`STEP_ERROR`] × `noise` of the
/// replay at twice as many: [`steps_for`]'s test, held at the estimate a
/// fit ends at, where the replays' accuracy matters (the error grows
/// where parts slip more: on squeeze_trans the gap between 32 and 64 steps
/// is 1 µm at μ 0.2 and 13 µm at μ 1). The schedule it holds at, and the
/// replays this cost.
///
/// # Errors
/// θ's scale cannot be played.
pub(crate) fn steps_hold(
    coarse: &Schedule,
    own: usize,
    probe: &Track,
    theta: &Theta,
    noise: Option<f64>,
) -> Result<(Schedule, usize)> {
    let mut out = coarse.clone();
    let Some(noise) = noise else {
        return Ok((out, 0));
    };
    let mut replays = 0;
    while out.settings.numerics.steps_per_cycle < own {
        let mut finer = out.clone();
        finer.settings.numerics.steps_per_cycle =
            (2 * out.settings.numerics.steps_per_cycle).min(own);
        replays += 2;
        if within_error(&out, &finer, probe, theta, noise)? {
            break;
        }
        out = finer;
    }
    Ok((out, replays))
}

/// Whether `coarse`'s replay of `probe` under θ (put down at its first
/// observed position) stays within [`STEP_ERROR`] × `noise` of `fine`'s
/// on each axis at every frame; not where either loses contact.
fn within_error(
    coarse: &Schedule,
    fine: &Schedule,
    probe: &Track,
    theta: &Theta,
    noise: f64,
) -> Result<bool> {
    let times: Vec<f64> = probe.frames.iter().map(|f| f.t).collect();
    let r0 = probe.frames.first().map_or([0.0; 2], |f| f.r);
    let (a, b) = rayon::join(
        || path(coarse, theta, r0, &times),
        || path(fine, theta, r0, &times),
    );
    Ok(match (a?, b?) {
        (Some(a), Some(b)) => a
            .iter()
            .zip(&b)
            .all(|(p, q)| (p - q).abs() <= STEP_ERROR * noise),
        _ => false,
    })
}

/// Each track's path, flattened (`None`: it loses contact).
pub type Paths = Vec<Option<Vec<f64>>>;

/// A track's frame times and observed coordinates, flattened.
struct Observed {
    times: Vec<f64>,
    coords: Vec<f64>,
}

impl Observed {
    fn new(track: &Track) -> Observed {
        Observed {
            times: track.frames.iter().map(|f| f.t).collect(),
            coords: track.frames.iter().flat_map(|f| f.r).collect(),
        }
    }

    /// Σ |observed − path|².
    fn rss(&self, path: &[f64]) -> f64 {
        self.coords
            .iter()
            .zip(path)
            .map(|(o, p)| (o - p).powi(2))
            .sum()
    }
}

/// A track's residual at the current point and its path's sensitivities.
struct Linear {
    /// The path at the current point.
    path: Vec<f64>,
    /// Observed − path.
    e: Vec<f64>,
    /// ∂path/∂r₀ (x, y).
    a: [Vec<f64>; 2],
    /// ∂path/∂θ_j per free parameter.
    b: Vec<Vec<f64>>,
}

impl Linear {
    /// The same sensitivities about a moved point whose path is `path`.
    fn moved(self, path: Vec<f64>, obs: &Observed) -> Linear {
        let e = obs.coords.iter().zip(&path).map(|(o, p)| o - p).collect();
        Linear { path, e, ..self }
    }
}

/// (moved − base)/step.
fn column(base: &[f64], moved: &[f64], step: f64) -> Vec<f64> {
    moved
        .iter()
        .zip(base)
        .map(|(m, b)| (m - b) / step)
        .collect()
}

/// Track `obs`'s linearisation about (θ, r₀), its path there `base`:
/// `None` where a shifted replay loses contact.
fn linearise(
    schedule: &Schedule,
    theta: &Theta,
    free: &[usize],
    r0: [f64; 2],
    obs: &Observed,
    base: Vec<f64>,
) -> Result<Option<Linear>> {
    let mut a = [Vec::new(), Vec::new()];
    for (k, col) in a.iter_mut().enumerate() {
        let mut r = r0;
        r[k] += START_STEP;
        match path(schedule, theta, r, &obs.times)? {
            Some(p) => *col = column(&base, &p, START_STEP),
            None => return Ok(None),
        }
    }
    let mut b = Vec::with_capacity(free.len());
    for &j in free {
        let mut t = *theta;
        t[j] += THETA_STEP[j];
        match path(schedule, &t, r0, &obs.times)? {
            Some(p) => b.push(column(&base, &p, THETA_STEP[j])),
            None => return Ok(None),
        }
    }
    let e = obs.coords.iter().zip(&base).map(|(o, p)| o - p).collect();
    Ok(Some(Linear {
        path: base,
        e,
        a,
        b,
    }))
}

fn dot(u: &[f64], v: &[f64]) -> f64 {
    u.iter().zip(v).map(|(a, b)| a * b).sum()
}

/// A track's normal equations with its start eliminated.
struct Reduced {
    /// B̃ᵀB̃.
    s: DMatrix<f64>,
    /// B̃ᵀe: the track's score.
    u: DVector<f64>,
    /// (AᵀA)⁻¹.
    naa_inv: Matrix2<f64>,
    /// AᵀB (2 × p).
    nab: DMatrix<f64>,
    /// Aᵀe.
    ga: Vector2<f64>,
}

impl Reduced {
    /// `None` when the path does not depend on the start (AᵀA singular).
    fn new(lin: &Linear) -> Option<Reduced> {
        let p = lin.b.len();
        let naa = Matrix2::from_fn(|r, c| dot(&lin.a[r], &lin.a[c]));
        let naa_inv = naa
            .try_inverse()
            .filter(|m| m.iter().all(|v| v.is_finite()))?;
        let nab = DMatrix::from_fn(2, p, |r, c| dot(&lin.a[r], &lin.b[c]));
        let nbb = DMatrix::from_fn(p, p, |r, c| dot(&lin.b[r], &lin.b[c]));
        let ga = Vector2::from_fn(|r, _| dot(&lin.a[r], &lin.e));
        let gb = DVector::from_fn(p, |r, _| dot(&lin.b[r], &lin.e));
        let inv = DMatrix::from_fn(2, 2, |r, c| naa_inv[(r, c)]);
        let ga_d = DVector::from_column_slice(ga.as_slice());
        let s = &nbb - nab.transpose() * &inv * &nab;
        let u = gb - nab.transpose() * &inv * ga_d;
        Some(Reduced {
            s,
            u,
            naa_inv,
            nab,
            ga,
        })
    }

    /// The start's step given θ's.
    fn start_step(&self, dtheta: &DVector<f64>) -> Vector2<f64> {
        let nab_dt = &self.nab * dtheta;
        self.naa_inv * (self.ga - Vector2::new(nab_dt[0], nab_dt[1]))
    }
}

/// A group of tracks fitted by replays.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ReplayFit {
    /// θ̂ (fixed parameters at their given values).
    pub theta: Theta,
    /// The free parameters (indices into θ).
    pub free: Vec<usize>,
    /// Covariance of θ̂ over the free parameters, widened by the tracks'
    /// scatter.
    pub covariance: Vec<Vec<f64>>,
    /// The noise model's covariance σ̂²S⁻¹, not widened.
    pub classical: Vec<Vec<f64>>,
    /// Each track's fitted start (m, at t = 0).
    pub starts: Vec<[f64; 2]>,
    /// Each track's fitted path at its frames.
    pub paths: Vec<Vec<[f64; 2]>>,
    /// Σ RSS (m²).
    pub rss: f64,
    /// Degrees of freedom: coordinates − 2·tracks − free parameters.
    pub dof: usize,
    /// Replays run.
    pub replays: usize,
}

/// The paths of every track at (θ, its start), in parallel; `None` for a
/// track that loses contact.
fn paths(
    schedule: &Schedule,
    theta: &Theta,
    starts: &[[f64; 2]],
    obs: &[Observed],
) -> Result<Paths> {
    obs.par_iter()
        .zip(starts)
        .map(|(o, &r0)| path(schedule, theta, r0, &o.times))
        .collect()
}

/// Σ RSS of `paths` (infinite when a track lost contact).
fn total_rss(obs: &[Observed], paths: &Paths) -> f64 {
    obs.iter()
        .zip(paths)
        .map(|(o, p)| p.as_ref().map_or(f64::INFINITY, |p| o.rss(p)))
        .sum()
}

/// θ + s·δθ over `free`, held to [`BOUNDS`].
fn stepped(theta: &Theta, free: &[usize], dtheta: &DVector<f64>, s: f64) -> Theta {
    let mut t = *theta;
    for (k, &j) in free.iter().enumerate() {
        t[j] = (t[j] + s * dtheta[k]).clamp(BOUNDS[j][0], BOUNDS[j][1]);
    }
    t
}

/// A Gauss–Newton step: δθ, each start's step, S⁻¹ and the tracks'
/// reduced equations.
type Step = (DVector<f64>, Vec<Vector2<f64>>, DMatrix<f64>, Vec<Reduced>);

/// The Gauss–Newton step of the module's doc at a linearisation; `None`
/// when a start or θ is not determined (a singular block).
fn gauss_newton(lin: &[Linear], p: usize) -> Option<Step> {
    let reduced: Vec<Reduced> = lin.iter().map(Reduced::new).collect::<Option<_>>()?;
    let mut s = DMatrix::zeros(p, p);
    let mut h = DVector::zeros(p);
    for r in &reduced {
        s += &r.s;
        h += &r.u;
    }
    let s_inv = s
        .try_inverse()
        .filter(|m| m.iter().all(|v| v.is_finite()))?;
    let dtheta = &s_inv * h;
    let dstarts = reduced.iter().map(|r| r.start_step(&dtheta)).collect();
    Some((dtheta, dstarts, s_inv, reduced))
}

/// Fits θ over `free` and every track's start to `tracks` by replays, from
/// `theta0` and `starts` (`base`: the tracks' paths there, when already
/// replayed), until every step is below `tol` of its standard error.
/// `None` when the replays cannot follow the tracks from there: a track
/// loses contact, or its start or θ is not determined.
///
/// # Errors
/// θ's scale cannot be played.
pub(crate) fn fit(
    schedule: &Schedule,
    tracks: &[&Track],
    theta0: Theta,
    free: &[usize],
    starts: Vec<[f64; 2]>,
    base: Option<Paths>,
    tol: f64,
) -> Result<Option<ReplayFit>> {
    let obs: Vec<Observed> = tracks.iter().map(|t| Observed::new(t)).collect();
    let p = free.len();
    let n: usize = obs.iter().map(|o| o.coords.len()).sum();
    let dof = n.saturating_sub(2 * obs.len() + p).max(1);
    let (mut theta, mut starts) = (theta0, starts);
    let mut replays = 0;
    let mut current = match base {
        Some(b) => b,
        None => {
            replays += obs.len();
            paths(schedule, &theta, &starts, &obs)?
        }
    };
    let mut rss = total_rss(&obs, &current);
    // The last linearisation's sensitivities while the steps since stay
    // within the confidence region (the chord step: module docs).
    let mut kept: Option<Vec<Linear>> = None;
    let mut iteration = 0;
    loop {
        iteration += 1;
        let Some(base) = current.into_iter().collect::<Option<Vec<Vec<f64>>>>() else {
            return Ok(None);
        };
        let chord = kept.is_some();
        let lin = match kept.take() {
            Some(old) => old
                .into_iter()
                .zip(base)
                .zip(&obs)
                .map(|((l, b), o)| l.moved(b, o))
                .collect(),
            None => {
                replays += obs.len() * (2 + p);
                let lin: Option<Vec<Linear>> = obs
                    .par_iter()
                    .zip(base)
                    .zip(&starts)
                    .map(|((o, b), &r0)| linearise(schedule, &theta, free, r0, o, b))
                    .collect::<Result<Vec<_>>>()?
                    .into_iter()
                    .collect();
                let Some(lin) = lin else { return Ok(None) };
                lin
            }
        };
        let Some((dtheta, dstarts, s_inv, reduced)) = gauss_newton(&lin, p) else {
            return Ok(None);
        };
        let sigma2 = rss / dof as f64;
        let small = (0..p).all(|k| dtheta[k].abs() <= tol * (sigma2 * s_inv[(k, k)]).sqrt());
        if small || iteration >= MAX_ITERATIONS {
            let step = Taken {
                theta: &theta,
                starts: &starts,
                dtheta: &dtheta,
                dstarts: &dstarts,
            };
            return Ok(Some(finish(
                &step, free, &lin, &reduced, &s_inv, dof, replays,
            )));
        }
        let mut accepted = None;
        let mut s = 1.0;
        for _ in 0..HALVINGS {
            let t = stepped(&theta, free, &dtheta, s);
            let r: Vec<[f64; 2]> = starts
                .iter()
                .zip(&dstarts)
                .map(|(r, d)| [r[0] + s * d[0], r[1] + s * d[1]])
                .collect();
            replays += obs.len();
            let trial = paths(schedule, &t, &r, &obs)?;
            let trial_rss = total_rss(&obs, &trial);
            if trial_rss < rss {
                accepted = Some((t, r, trial, trial_rss, s));
                break;
            }
            s *= 0.5;
        }
        let Some((t, r, trial, trial_rss, s)) = accepted else {
            if chord {
                // The kept sensitivities lead nowhere: linearise afresh
                // at the same point.
                current = lin.into_iter().map(|l| Some(l.path)).collect();
                continue;
            }
            // No step lowers the RSS: the current point is the minimum to
            // the replays' precision.
            let zero = DVector::zeros(p);
            let still = vec![Vector2::zeros(); obs.len()];
            let step = Taken {
                theta: &theta,
                starts: &starts,
                dtheta: &zero,
                dstarts: &still,
            };
            return Ok(Some(finish(
                &step, free, &lin, &reduced, &s_inv, dof, replays,
            )));
        };
        if within_confidence(&dtheta, s, &reduced, sigma2) {
            kept = Some(lin);
        }
        (theta, starts, current, rss) = (t, r, trial, trial_rss);
    }
}

/// Whether the step s·δθ lies within θ's 95 % confidence region about
/// the point it was taken from: s²·δθᵀSδθ/σ² ≤ χ²_p(0.95), with
/// Sδθ = Σ_i B̃_iᵀe_i (the step's own equations).
fn within_confidence(dtheta: &DVector<f64>, s: f64, reduced: &[Reduced], sigma2: f64) -> bool {
    let p = dtheta.len();
    let h = reduced
        .iter()
        .fold(DVector::zeros(p), |acc: DVector<f64>, r| acc + &r.u);
    let d2 = s * s * dtheta.dot(&h) / sigma2;
    CHI2_95.get(p - 1).is_some_and(|&q| d2 <= q)
}

/// The point a fit ends at: the current one and the last step, taken on
/// the linearised paths.
struct Taken<'a> {
    theta: &'a Theta,
    starts: &'a [[f64; 2]],
    dtheta: &'a DVector<f64>,
    dstarts: &'a [Vector2<f64>],
}

/// The fit after the last step `step` on the linearised paths: θ̂, the
/// starts, the paths, the RSS and the covariance (widened by the tracks'
/// scores there).
fn finish(
    step: &Taken<'_>,
    free: &[usize],
    lin: &[Linear],
    reduced: &[Reduced],
    s_inv: &DMatrix<f64>,
    dof: usize,
    replays: usize,
) -> ReplayFit {
    let p = free.len();
    let mut rss = 0.0;
    let mut paths = Vec::with_capacity(lin.len());
    for (l, d) in lin.iter().zip(step.dstarts) {
        let moved: Vec<f64> = (0..l.path.len())
            .map(|c| {
                l.path[c]
                    + l.a[0][c] * d[0]
                    + l.a[1][c] * d[1]
                    + (0..p).map(|k| l.b[k][c] * step.dtheta[k]).sum::<f64>()
            })
            .collect();
        rss +=
            l.e.iter()
                .zip(&l.path)
                .zip(&moved)
                .map(|((e, b), m)| (e + b - m).powi(2))
                .sum::<f64>();
        paths.push(moved.chunks(2).map(|q| [q[0], q[1]]).collect());
    }
    let sigma2 = rss / dof as f64;
    let classical = s_inv.scale(sigma2);
    let scores: Vec<Vec<f64>> = reduced
        .iter()
        .map(|r| (&r.u - &r.s * step.dtheta).iter().copied().collect())
        .collect();
    let widen = robust_widening(&classical, s_inv, &scores);
    let rows = |m: &DMatrix<f64>, f: f64| -> Vec<Vec<f64>> {
        (0..p)
            .map(|a| (0..p).map(|b| f * m[(a, b)]).collect())
            .collect()
    };
    ReplayFit {
        theta: stepped(step.theta, free, step.dtheta, 1.0),
        free: free.to_vec(),
        covariance: rows(&classical, widen),
        classical: rows(&classical, 1.0),
        starts: step
            .starts
            .iter()
            .zip(step.dstarts)
            .map(|(r, d)| [r[0] + d[0], r[1] + d[1]])
            .collect(),
        paths,
        rss,
        dof,
        replays,
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `calibrate::replay::steps_hold`.
    #[test]
    fn example_steps_hold() -> Result<(), crate::Error> {
        use crate::calibrate::replay::steps_hold;
        use crate::calibrate::tracks::Frame;
        use crate::calibrate::Track;
        use crate::schedule::Schedule;
        let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
        let mut coarse = schedule.clone();
        coarse.settings.numerics.steps_per_cycle = 32;
        let frames = (0..300)
            .map(|k| Frame {
                t: k as f64 / 30.0,
                r: [0.01, 0.0],
                line: 0,
            })
            .collect();
        let probe = Track {
            part: "a".into(),
            frames,
        };
        let steps = |mu: f64| -> crate::Result<usize> {
            let (held, _) = steps_hold(&coarse, 64, &probe, &[mu, 0.0, 1.0], Some(2e-4))?;
            Ok(held.settings.numerics.steps_per_cycle)
        };
        // 32 steps hold at μ 0.23; at μ 1 they are refined to the schedule's 64.
        assert_eq!((steps(0.23)?, steps(1.0)?), (32, 64));
        Ok(())
    }

    /// A worked example of `calibrate::replay::fit`.
    #[test]
    fn example_fit() -> Result<(), crate::Error> {
        use crate::calibrate::replay::{fit, path};
        use crate::calibrate::tracks::Frame;
        use crate::calibrate::Track;
        use crate::schedule::Schedule;
        let schedule = Schedule::load(std::path::Path::new("results/sink/schedule.json"))?;
        // Noise-free tracks replayed at μ 0.3: the fit returns μ 0.3.
        let times: Vec<f64> = (0..60).map(|k| k as f64 / 30.0).collect();
        let tracks: Vec<Track> = [[0.02, 0.01], [-0.015, -0.02]]
            .iter()
            .map(|&r| {
                let p = path(&schedule, &[0.3, 0.0, 1.0], r, &times)?.expect("in contact");
                let frames = times
                    .iter()
                    .zip(p.chunks(2))
                    .map(|(&t, q)| Frame {
                        t,
                        r: [q[0], q[1]],
                        line: 0,
                    })
                    .collect();
                Ok(Track {
                    part: "a".into(),
                    frames,
                })
            })
            .collect::<crate::Result<_>>()?;
        let refs: Vec<&Track> = tracks.iter().collect();
        let starts = vec![[0.0201, 0.0099], [-0.0149, -0.0201]];
        let f = fit(&schedule, &refs, [0.27, 0.0, 1.0], &[0], starts, None, 0.05)?.expect("a fit");
        assert!((f.theta[0] - 0.3).abs() < 1e-6, "{:?}", f.theta);
        assert!((f.starts[0][0] - 0.02).abs() < 1e-8, "{:?}", f.starts);
        Ok(())
    }
}
