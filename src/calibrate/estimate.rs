//! The estimator: least squares on the tracks' positions.
//!
//! **Noise model.** Each observed position is the part's true position
//! plus independent Gaussian noise of one standard deviation σ per axis
//! and frame (the camera's). Positions, not finite-difference velocities,
//! are fitted: differences of noisy positions share their noise with the
//! neighbouring difference and are correlated, positions are not. Each
//! track has its own unknown start position (two nuisance parameters),
//! and θ is common to the tracks of a class, so that
//!
//! RSS(θ) = Σ_tracks min_{r₀} Σ_frames |r_obs(t) − r(t; r₀, θ)|²,
//!
//! the path r(t; r₀, θ) from `super::model::PlayedMotion::path`, is −2σ²
//! times the profile log-likelihood up to a constant. The start is fitted
//! per track by Gauss–Newton (finite-difference sensitivity of the path to
//! r₀), θ by Nelder–Mead (argmin) on the field's quadratic surrogate
//! (`super::model::Stencil`), re-centred until the minimum lies within
//! half a step of the stencil's centre.
//!
//! **Intervals.** σ² is estimated by RSS/(n − 2·tracks − p) at the
//! minimum (n: coordinates observed, p: free parameters), so that a model
//! that misses part of the motion widens the intervals instead of
//! understating them; the covariance of θ̂ is 2σ̂²H⁻¹ with H the Hessian of
//! RSS at θ̂ (central differences on the surrogate), widened when the
//! tracks' own scores scatter more than independent noise makes them (a
//! model error correlated along a track: `robust_widening`); 95 %
//! intervals are θ̂ ± 1.96 standard errors.
//!
//! **Model bias (indirect inference).** The paths are the field model's,
//! not the plate's: without noise θ̂ tends not to the truth θ but to the
//! binding function β(θ), the model's best fit of the exact tracks at θ,
//! and b(θ) = β(θ) − θ is the model's bias (a few thousandths of μ where
//! the field's swirl or a join's transient is missed). With noise,
//! θ̂ = β(θ) + ε. `binding` evaluates β on noise-free tracks the exact
//! simulator replays at a given θ from the fitted starts at the observed
//! frames, fitted by the same least squares on the same stencil. The
//! reported estimate θ̃ solves β(θ̃) = θ̂, per parameter, by one secant
//! step: θ₁ = θ̂ − (β(θ̂) − θ̂), then θ̃ = θ₁ + (θ̂ − β(θ₁))/β′ with the
//! slope β′ = (β(θ₁) − β(θ̂))/(θ₁ − θ̂) (1 where the bias is constant:
//! then θ̃ = θ̂ − b(θ̂) exactly). Since θ̃ = β⁻¹(θ̂), its covariance is
//! θ̂'s divided by β′_a β′_b (the delta method): a model that responds to
//! the truth by less than one for one widens the intervals. A slope
//! outside [0.5, 2] says the model's error is not a smooth function of θ
//! and the correction cannot be trusted; it is held to that range and
//! stated.

use std::sync::Mutex;

use rayon::prelude::*;

use super::model::{FieldSet, PlayedMotion, Stencil, Theta};
use super::tracks::Track;
use crate::error::{Error, Result};

/// Relative step of the finite-difference sensitivity of a path to its
/// start (m).
const START_STEP: f64 = 1e-6;

/// A track's fitted start and squared residual.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StartFit {
    /// The fitted position at the track's first frame (m).
    pub start: [f64; 2],
    /// Σ |r_obs − r|² over the track's frames (m²).
    pub rss: f64,
}

/// The track's observed positions.
fn observed(track: &Track) -> Vec<[f64; 2]> {
    track.frames.iter().map(|f| f.r).collect()
}

/// The track's path from `start` at its first frame, at its frames.
fn path(
    motion: &PlayedMotion,
    set: &FieldSet,
    track: &Track,
    start: [f64; 2],
) -> Result<Vec<[f64; 2]>> {
    let times: Vec<f64> = track.frames.iter().map(|f| f.t).collect();
    motion.path(set, start, times[0], &times)
}

fn residual_sum(obs: &[[f64; 2]], p: &[[f64; 2]]) -> f64 {
    obs.iter()
        .zip(p)
        .map(|(o, q)| (o[0] - q[0]).powi(2) + (o[1] - q[1]).powi(2))
        .sum()
}

/// Fits `track`'s start in `set` by Gauss–Newton from `from`.
///
/// # Errors
/// A path crosses an invalid field sample.
pub(crate) fn fit_start(
    motion: &PlayedMotion,
    set: &FieldSet,
    track: &Track,
    from: [f64; 2],
) -> Result<StartFit> {
    let obs = observed(track);
    let mut s = from;
    let mut p = path(motion, set, track, s)?;
    for _ in 0..8 {
        let px = path(motion, set, track, [s[0] + START_STEP, s[1]])?;
        let py = path(motion, set, track, [s[0], s[1] + START_STEP])?;
        // Normal equations of the 2-column least squares J δ = r.
        let (mut a, mut b, mut c, mut gx, mut gy) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for k in 0..obs.len() {
            for x in 0..2 {
                let jx = (px[k][x] - p[k][x]) / START_STEP;
                let jy = (py[k][x] - p[k][x]) / START_STEP;
                let r = obs[k][x] - p[k][x];
                a += jx * jx;
                b += jx * jy;
                c += jy * jy;
                gx += jx * r;
                gy += jy * r;
            }
        }
        let det = a * c - b * b;
        if det == 0.0 || det.is_nan() {
            break;
        }
        let d = [(c * gx - b * gy) / det, (a * gy - b * gx) / det];
        s = [s[0] + d[0], s[1] + d[1]];
        p = path(motion, set, track, s)?;
        if d[0].hypot(d[1]) < 1e-9 {
            break;
        }
    }
    Ok(StartFit {
        start: s,
        rss: residual_sum(&obs, &p),
    })
}

/// Every track's start fitted in `set` (from `warm` when given, else its
/// first observed frame), in track order.
///
/// # Errors
/// As `fit_start`.
pub(crate) fn fit_starts(
    motion: &PlayedMotion,
    set: &FieldSet,
    tracks: &[&Track],
    warm: Option<&[StartFit]>,
) -> Result<Vec<StartFit>> {
    tracks
        .par_iter()
        .enumerate()
        .map(|(i, tr)| {
            let from = warm.map_or(tr.frames[0].r, |w| w[i].start);
            fit_start(motion, set, tr, from)
        })
        .collect()
}

/// The fit of one class: θ̂, its covariance over the free parameters and
/// the residual.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ClassFit {
    /// θ̂ (fixed parameters at their given values).
    pub theta: Theta,
    /// The free parameters (indices into θ).
    pub free: Vec<usize>,
    /// Covariance of θ̂ over the free parameters, row-major.
    pub covariance: Vec<Vec<f64>>,
    /// Per track: fitted start and residual.
    pub starts: Vec<StartFit>,
    /// Σ RSS (m²).
    pub rss: f64,
    /// Degrees of freedom: coordinates − 2·tracks − free parameters.
    pub dof: usize,
    /// Fields computed.
    pub fields: usize,
    /// RSS along μ_k about θ̂ (other parameters at θ̂): (μ_k, RSS).
    pub profile: Vec<[f64; 2]>,
    /// The field sets at θ̂ (for the report's simulated paths).
    pub set: FieldSet,
    /// The stencil θ̂ was found on.
    pub stencil: Stencil,
}

impl ClassFit {
    /// σ̂ (m): the residual's standard deviation per coordinate.
    pub(crate) fn sigma(&self) -> f64 {
        (self.rss / self.dof.max(1) as f64).sqrt()
    }
}

/// Bounds of θ: μ_k within [0.001, 2], μ_s − μ_k within [0, 2], the scale
/// within [0.2, 5].
pub const BOUNDS: [[f64; 2]; 3] = [[0.001, 2.0], [0.0, 2.0], [0.2, 5.0]];

/// Fits θ over `free` for `tracks`, from `theta0`, with stencil steps `h`.
/// `sigma_ref` (m) scales the cost for the optimiser. `first` is the field
/// set (with its excursions) at `first.0` when already computed: the first
/// stencil's centre when it is there.
///
/// # Errors
/// A field cannot be computed or followed, or the optimiser fails.
pub(crate) fn fit_class(
    motion: &PlayedMotion,
    tracks: &[&Track],
    theta0: Theta,
    h: Theta,
    free: &[usize],
    sigma_ref: f64,
    mut first: Option<(Theta, FieldSet)>,
) -> Result<ClassFit> {
    let problem = Problem {
        motion,
        tracks,
        free,
        h,
        norm: 1.0 / (sigma_ref * sigma_ref),
    };
    // The stencil's centre keeps its nodes within the bounds.
    let centred = |t: Theta| -> Theta {
        let mut c = t;
        for &j in free {
            c[j] = c[j].clamp(BOUNDS[j][0] + h[j], BOUNDS[j][1] - h[j]);
        }
        c
    };
    let mut center = centred(theta0);
    let (mut fields, mut rounds) = (0, 0);
    let mut warm: Option<Vec<StartFit>> = None;
    let (stencil, best) = loop {
        rounds += 1;
        let stencil = match first.take() {
            Some((at, base)) if at == center => {
                fields += 2 * free.len();
                Stencil::around(motion, base, center, h, free)?
            }
            _ => {
                fields += 1 + 2 * free.len();
                Stencil::compute(motion, center, h, free)?
            }
        };
        let (best, inside, w) = problem.round(&stencil, warm.take())?;
        warm = w;
        let next = centred(best);
        if inside || next == center || rounds >= 8 {
            break (stencil, best);
        }
        center = next;
    };
    let rss_at = |t: &Theta| -> Result<f64> {
        let set = stencil.at(t);
        Ok(fit_starts(motion, &set, tracks, warm.as_deref())?
            .iter()
            .map(|f| f.rss)
            .sum())
    };
    let hess = hessian(&rss_at, best, free, h)?;
    let set = stencil.at(&best);
    let starts = fit_starts(motion, &set, tracks, warm.as_deref())?;
    let rss: f64 = starts.iter().map(|f| f.rss).sum();
    let p = free.len();
    let n: usize = tracks.iter().map(|t| 2 * t.frames.len()).sum();
    let dof = n.saturating_sub(2 * tracks.len() + p).max(1);
    let sigma2 = rss / dof as f64;
    let hm = nalgebra::DMatrix::from_fn(p, p, |a, b| hess[a][b]);
    let covariance = match hm.try_inverse() {
        Some(inv) => {
            let classical = inv.scale(2.0 * sigma2);
            let scores = track_scores(motion, &stencil, tracks, best, free, h, warm.as_deref())?;
            let widen = robust_widening(&classical, &inv, &scores);
            (0..p)
                .map(|a| (0..p).map(|b| widen * classical[(a, b)]).collect())
                .collect()
        }
        None => vec![vec![f64::INFINITY; p]; p],
    };
    let profile = profile(&rss_at, best, stencil.center, free, h)?;
    Ok(ClassFit {
        theta: best,
        free: free.to_vec(),
        covariance,
        starts,
        rss,
        dof,
        fields,
        profile,
        set,
        stencil,
    })
}

/// The binding function β(θ) of the module's doc: the same fit as `fit`'s
/// (same stencil, same optimiser from the same point) of `replayed`,
/// noise-free tracks of the class's parts played by the exact simulator at
/// θ ([`super::simulate::replay_tracks`]); β(θ) − θ is the model's bias at
/// θ. Equal to `fit.theta`, to the optimiser's tolerance, when `replayed`
/// are the model's own paths at `fit.theta`: no bias where the model is
/// exact.
///
/// # Errors
/// A path crosses an invalid field sample, or the optimiser fails.
pub(crate) fn binding(
    motion: &PlayedMotion,
    fit: &ClassFit,
    replayed: &[&Track],
    sigma_ref: f64,
) -> Result<Theta> {
    let problem = Problem {
        motion,
        tracks: replayed,
        free: &fit.free,
        h: fit.stencil.h,
        norm: 1.0 / (sigma_ref * sigma_ref),
    };
    Ok(problem.round(&fit.stencil, None)?.0)
}

/// Fewest tracks for the tracks' own scatter to widen the covariance.
pub const ROBUST_MIN_TRACKS: usize = 5;

/// Each track's score: the gradient of its own residual (its start fitted)
/// over the free parameters at `best`, by central differences of a quarter
/// stencil step on the surrogate.
fn track_scores(
    motion: &PlayedMotion,
    stencil: &Stencil,
    tracks: &[&Track],
    best: Theta,
    free: &[usize],
    h: Theta,
    warm: Option<&[StartFit]>,
) -> Result<Vec<Vec<f64>>> {
    let mut scores = vec![vec![0.0; free.len()]; tracks.len()];
    for (a, &j) in free.iter().enumerate() {
        let step = 0.25 * h[j];
        let at = |sign: f64| -> Result<Vec<StartFit>> {
            let mut t = best;
            t[j] += sign * step;
            fit_starts(motion, &stencil.at(&t), tracks, warm)
        };
        let (plus, minus) = (at(1.0)?, at(-1.0)?);
        for (i, g) in scores.iter_mut().enumerate() {
            g[a] = (plus[i].rss - minus[i].rss) / (2.0 * step);
        }
    }
    Ok(scores)
}

/// The factor (≥ 1) by which the tracks' own scatter widens the classical
/// covariance `classical` = 2σ̂²H⁻¹: the largest ratio over the parameters of
/// the cluster-robust variance (each track a cluster: H⁻¹ (Σ_i g_i g_iᵀ)
/// H⁻¹ · G/(G − 1), g_i track i's score, G the tracks) to the classical one.
/// Under the noise model the two agree (E g_i g_iᵀ = 4σ² J_iᵀJ_i and
/// H = 2JᵀJ); a model error that is correlated along a track, or differs
/// from part to part, shows in the scores' scatter and widens the
/// intervals rather than leaving them too narrow. 1 with fewer than
/// [`ROBUST_MIN_TRACKS`] tracks (too few clusters to estimate it).
pub(crate) fn robust_widening(
    classical: &nalgebra::DMatrix<f64>,
    inv: &nalgebra::DMatrix<f64>,
    scores: &[Vec<f64>],
) -> f64 {
    let (g, p) = (scores.len(), classical.nrows());
    if g < ROBUST_MIN_TRACKS {
        return 1.0;
    }
    let mut meat = nalgebra::DMatrix::zeros(p, p);
    for s in scores {
        let v = nalgebra::DVector::from_column_slice(s);
        meat += &v * v.transpose();
    }
    let robust = inv * meat * inv * (g as f64 / (g - 1) as f64);
    (0..p)
        .map(|a| robust[(a, a)] / classical[(a, a)])
        .filter(|r| r.is_finite())
        .fold(1.0, f64::max)
}

/// One class's least squares over the free parameters.
struct Problem<'a> {
    motion: &'a PlayedMotion,
    tracks: &'a [&'a Track],
    free: &'a [usize],
    h: Theta,
    /// 1/σ_ref²: the cost in units of the noise.
    norm: f64,
}

/// A poisoned lock (a panicking worker) as an error.
fn poisoned<T>(_: T) -> Error {
    Error::NotConverged("calibration: poisoned state".into())
}

impl Problem<'_> {
    /// θ at normalised coordinates x_j = (θ_j − θ_c,j)/h_j about the
    /// stencil's centre, held to the box |x_j| ≤ 2 and the bounds, and the
    /// squared distance outside (the penalty's measure).
    fn theta_at(&self, center: &Theta, x: &[f64]) -> (Theta, f64) {
        let mut t = *center;
        let mut out = 0.0;
        for (k, &j) in self.free.iter().enumerate() {
            let lo = (-2.0f64).max((BOUNDS[j][0] - center[j]) / self.h[j]);
            let hi = 2.0f64.min((BOUNDS[j][1] - center[j]) / self.h[j]);
            let xc = x[k].clamp(lo, hi);
            out += (x[k] - xc).powi(2);
            t[j] = center[j] + xc * self.h[j];
        }
        (t, out)
    }

    /// One Nelder–Mead minimisation over the stencil (argmin): θ̂, whether
    /// it lies within half a step of the centre, the tracks' last starts.
    fn round(
        &self,
        stencil: &Stencil,
        warm: Option<Vec<StartFit>>,
    ) -> Result<(Theta, bool, Option<Vec<StartFit>>)> {
        let last = Mutex::new(warm);
        let found = Mutex::new((f64::INFINITY, vec![0.0; self.free.len()]));
        let cost = |x: &[f64]| -> Result<f64> {
            let (t, out) = self.theta_at(&stencil.center, x);
            let set = stencil.at(&t);
            let w = last.lock().map_err(poisoned)?.clone();
            let fits = fit_starts(self.motion, &set, self.tracks, w.as_deref())?;
            let rss: f64 = fits.iter().map(|f| f.rss).sum();
            *last.lock().map_err(poisoned)? = Some(fits);
            let c = rss * self.norm * (1.0 + out);
            let mut f = found.lock().map_err(poisoned)?;
            if c < f.0 {
                *f = (c, x.to_vec());
            }
            Ok(c)
        };
        crate::synth::multistart::nelder_mead(
            &vec![0.0; self.free.len()],
            0.5,
            usize::MAX,
            cost,
            || false,
            "calibration Nelder–Mead",
            None,
        )?;
        let (_, x) = found.into_inner().map_err(poisoned)?;
        let warm = last.into_inner().map_err(poisoned)?;
        let best = self.theta_at(&stencil.center, &x).0;
        Ok((best, x.iter().all(|v| v.abs() <= 0.5), warm))
    }
}

/// RSS along μ_k over ±2 stencil steps about `center` in fifths of a step (the other
/// parameters at `best`): (μ_k, RSS); empty when μ_k is not free.
fn profile(
    rss_at: &dyn Fn(&Theta) -> Result<f64>,
    best: Theta,
    center: Theta,
    free: &[usize],
    h: Theta,
) -> Result<Vec<[f64; 2]>> {
    let j = super::model::MU_K;
    if !free.contains(&j) {
        return Ok(Vec::new());
    }
    let mut out = Vec::new();
    for k in -10..=10 {
        let mut t = best;
        t[j] = center[j] + f64::from(k) * 0.2 * h[j];
        if t[j] >= BOUNDS[j][0] {
            out.push([t[j], rss_at(&t)?]);
        }
    }
    Ok(out)
}

/// The Hessian of `rss_at` at `best` over the free parameters, by central
/// differences of a quarter stencil step.
fn hessian(
    rss_at: &dyn Fn(&Theta) -> Result<f64>,
    best: Theta,
    free: &[usize],
    h: Theta,
) -> Result<Vec<Vec<f64>>> {
    let p = free.len();
    let step: Vec<f64> = free.iter().map(|&j| 0.25 * h[j]).collect();
    let shifted = |pairs: &[(usize, f64)]| -> Theta {
        let mut t = best;
        for &(k, s) in pairs {
            t[free[k]] += s * step[k];
        }
        t
    };
    let f0 = rss_at(&best)?;
    let mut hess = vec![vec![0.0; p]; p];
    for a in 0..p {
        let fp = rss_at(&shifted(&[(a, 1.0)]))?;
        let fm = rss_at(&shifted(&[(a, -1.0)]))?;
        hess[a][a] = (fp - 2.0 * f0 + fm) / (step[a] * step[a]);
        for b in 0..a {
            let pp = rss_at(&shifted(&[(a, 1.0), (b, 1.0)]))?;
            let pm = rss_at(&shifted(&[(a, 1.0), (b, -1.0)]))?;
            let mp = rss_at(&shifted(&[(a, -1.0), (b, 1.0)]))?;
            let mm = rss_at(&shifted(&[(a, -1.0), (b, -1.0)]))?;
            let v = (pp - pm - mp + mm) / (4.0 * step[a] * step[b]);
            hess[a][b] = v;
            hess[b][a] = v;
        }
    }
    Ok(hess)
}

/// Each track's residual over a lattice of μ (μ_s − μ_k and the scale
/// fixed): `out[m][i]` for μ `mus[m]` and track i, `None` where the
/// field cannot be followed.
pub(crate) fn scan(
    motion: &PlayedMotion,
    tracks: &[&Track],
    mus: &[f64],
    excess: f64,
    scale: f64,
) -> Vec<Option<Vec<f64>>> {
    mus.iter()
        .map(|&mu| {
            let set = motion.fields(&[mu, excess, scale]).ok()?;
            let fits = fit_starts(motion, &set, tracks, None).ok()?;
            Some(fits.iter().map(|f| f.rss).collect())
        })
        .collect()
}

/// The minimum of a sampled curve `(x, y)` by the parabola through the
/// lowest sample and its neighbours: (x̂, curvature d²y/dx²); at an end
/// of the lattice, that end and no curvature.
pub(crate) fn parabola_minimum(x: &[f64], y: &[f64]) -> Option<(f64, Option<f64>)> {
    let (i, _) = y
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    if i == 0 || i + 1 == y.len() || !y[i - 1].is_finite() || !y[i + 1].is_finite() {
        return Some((x[i], None));
    }
    let h = x[i + 1] - x[i];
    let (a, b, c) = (y[i - 1], y[i], y[i + 1]);
    let curv = (a - 2.0 * b + c) / (h * h);
    if curv.is_nan() || curv <= 0.0 {
        return Some((x[i], None));
    }
    let shift = (a - c) / (2.0 * (a - 2.0 * b + c));
    Some((x[i] + shift * h, Some(curv)))
}

#[cfg(test)]
mod tests {
    /// A worked example of `calibrate::estimate::binding`.
    #[test]
    fn example_binding() -> Result<(), crate::Error> {
        use crate::calibrate::estimate::{binding, fit_class, fit_starts};
        use crate::calibrate::tracks::Frame;
        use crate::calibrate::{PlayedMotion, Track};
        use crate::schedule::Schedule;
        let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
        let mut grid = schedule.region();
        grid.n = [7, 7];
        let motion = PlayedMotion::from_schedule(&schedule, grid)?;
        // Tracks that are the model's own paths at μ 0.3: the model is exact.
        let truth = motion.fields(&[0.3, 0.0, 1.0])?;
        let times: Vec<f64> = (10..100).map(|k| k as f64 / 30.0).collect();
        let tracks: Vec<Track> = [[-0.02, 0.01], [0.02, -0.01]]
            .iter()
            .map(|&r| {
                let p = motion.path(&truth, r, times[0], &times)?;
                let frames = times
                    .iter()
                    .zip(p)
                    .map(|(&t, r)| Frame { t, r, line: 0 })
                    .collect();
                Ok(Track {
                    part: "a".into(),
                    frames,
                })
            })
            .collect::<crate::Result<_>>()?;
        let refs: Vec<&Track> = tracks.iter().collect();
        let fit = fit_class(
            &motion,
            &refs,
            [0.28, 0.0, 1.0],
            [0.02; 3],
            &[0],
            1e-4,
            None,
        )?;
        // The model's paths at θ̂ replayed: no bias.
        let starts = fit_starts(&motion, &fit.set, &refs, None)?;
        let replayed: Vec<Track> = refs
            .iter()
            .zip(&starts)
            .map(|(tr, s)| {
                let t: Vec<f64> = tr.frames.iter().map(|f| f.t).collect();
                let p = motion.path(&fit.set, s.start, t[0], &t)?;
                let frames = t
                    .iter()
                    .zip(p)
                    .map(|(&t, r)| Frame { t, r, line: 0 })
                    .collect();
                Ok(Track {
                    part: tr.part.clone(),
                    frames,
                })
            })
            .collect::<crate::Result<_>>()?;
        let beta = binding(&motion, &fit, &replayed.iter().collect::<Vec<_>>(), 1e-4)?;
        assert!(
            (beta[0] - fit.theta[0]).abs() < 1e-5,
            "{beta:?} against {:?}",
            fit.theta
        );
        Ok(())
    }
}
