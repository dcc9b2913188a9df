//! Friction from camera tracks: μ_s, μ_k and the motion's amplitude scale
//! estimated from parts observed moving under a known schedule.
//!
//! A lab plays a schedule, films parts on the plate and tracks them
//! (`tracks`: `t_s,part,x_m,y_m`). [`calibrate`] first fits each part
//! alone over a lattice of μ by the played motion's **steady-state
//! velocity field** as a function of position and of θ = (μ_k, μ_s − μ_k,
//! scale) (`model`: a path costs a few thousand field look-ups, a replay
//! of one part over 10 s some 10 000 RK4 steps), by least squares
//! on the observed positions (`estimate`: the noise model, the
//! intervals). Where that fit's residual is within [`replay::FIELD_MISS`] ×
//! the tracks' own noise the field serves: the parts are sorted into
//! friction classes (`classes`) by their own estimates, each class is
//! fitted as one on the field, and the model's own bias at the estimate is
//! measured on noise-free tracks replayed by the exact simulator and
//! removed (indirect inference, `estimate::binding`: two replays of the
//! class's parts and two more fits on the same fields, no new field).
//! Beyond it the field cannot follow the tracks (a schedule of short
//! segments, whose joins' transients it leaves out), and the parts and
//! classes are fitted by **exact replays** instead ([`replay`]). The
//! calibration says which, and why. Parameters the tracks do not determine
//! are named: μ_s when the parts never stick (the fields or the replays do
//! not change with it), any parameter whose interval is wider than
//! [`WEAK`], any pair whose estimates are correlated beyond
//! [`CORRELATED`].
//!
//! [`simulate_tracks`] makes tracks by the exact simulator (the full
//! replay): what the tests and the coverage study check the estimator
//! against.

pub mod classes;
pub mod estimate;
pub(crate) mod model;
pub mod replay;
pub mod simulate;
pub mod tracks;

pub(crate) use model::PlayedMotion;
pub use simulate::simulate_tracks;
pub use simulate::TrackSimulation;
pub use tracks::{Track, Tracks};

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::field::Grid;
use crate::scene::{FrictionSpec, Interval};
use crate::schedule::Schedule;
use classes::cluster;
use estimate::{fit_class, parabola_minimum, scan, ClassFit};
use model::{EXCESS, MU_K, SCALE};

/// A 95 % interval wider than this (in μ or in scale) names its parameter
/// as weakly determined.
pub const WEAK: f64 = 0.1;

/// Estimates correlated beyond |ρ| = this are named as not separated.
pub const CORRELATED: f64 = 0.95;

/// The μ lattice of the part-by-part scan: 0.05 to 1.0 in steps of 0.05.
pub(crate) fn lattice() -> Vec<f64> {
    (1..=20).map(|k| 0.05 * f64::from(k)).collect()
}

/// Frames before this time (s, from the schedule's start) are left out
/// of the fit: the start-up transient (about three cycles of 30 ms).
pub const SETTLE: f64 = 0.3;

/// Stencil steps of θ (μ_k, μ_s − μ_k, scale).
const STEPS: model::Theta = [0.02, 0.02, 0.02];

/// A change of μ_s that moves no field sample by more than this (m/s) is
/// no change: the parts never stick.
const STICK_SENSITIVITY: f64 = 1e-9;

/// 97.5 % quantile of the standard normal.
const Z95: f64 = 1.959_963_984_540_054;

/// How to calibrate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CalibrateOptions {
    /// Also estimate the amplitude scale of the delivered motion.
    pub scale: bool,
    /// Grid points per side of the fields over the plate region.
    pub grid: usize,
    /// How long the motion was played (s), when known: frames after it
    /// are refused.
    pub played: Option<f64>,
}

impl Default for CalibrateOptions {
    fn default() -> Self {
        CalibrateOptions {
            scale: false,
            grid: 17,
            played: None,
        }
    }
}

/// One parameter's estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ParamEstimate {
    /// The estimate; `None` when the tracks do not determine it.
    pub value: Option<f64>,
    /// Standard error.
    pub standard_error: Option<f64>,
    /// 95 % interval.
    pub interval: Option<[f64; 2]>,
    /// Whether the parameter was estimated (false: fixed or not
    /// determined; see `note`).
    pub estimated: bool,
    /// Why it is fixed or undetermined, or how weakly it is determined.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// One part's own estimate (μ_s = μ_k, scale 1): from the field model's
/// lattice scan, or from its own fit by replays.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartEstimate {
    /// The part's label.
    pub part: String,
    /// Frames observed.
    pub frames: usize,
    /// Its μ.
    pub mu: f64,
    /// Its standard error (`None` at the lattice's end, or where its
    /// replays cannot follow it).
    pub standard_error: Option<f64>,
    /// Its class (index into `classes`).
    pub class: usize,
}

/// One friction class's fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ClassEstimate {
    /// The parts of the class.
    pub parts: Vec<String>,
    /// μ_k.
    pub mu_k: ParamEstimate,
    /// μ_s.
    pub mu_s: ParamEstimate,
    /// Amplitude scale of the delivered motion.
    pub scale: ParamEstimate,
    /// Correlations of the estimated parameters: (name, name, ρ).
    pub correlations: Vec<(String, String, f64)>,
    /// RMS residual per coordinate (m).
    pub residual_rms_m: f64,
    /// Residual standard deviation over the tracks' own noise estimate
    /// (about 1 when the model explains the tracks to their noise).
    pub residual_over_noise: Option<f64>,
    /// Coordinates fitted, and the fit's degrees of freedom.
    pub coordinates: usize,
    /// Degrees of freedom.
    pub dof: usize,
    /// What the tracks of this class do not determine.
    pub not_separable: Vec<String>,
    /// The field model's bias removed from the fit, per estimated
    /// parameter: (name, θ̂ − θ̃) (see `estimate`'s doc; empty for a
    /// class fitted by replays, which have none).
    #[serde(default)]
    pub model_bias: Vec<(String, f64)>,
    /// The slope β′ of the model's fit against the truth, per estimated
    /// parameter, from the bias correction's two replays (1: a constant
    /// bias; the standard errors are divided by it).
    #[serde(default)]
    pub model_slope: Vec<(String, f64)>,
    /// Parts whose own fit does not determine their μ, joined to this
    /// class (the nearest) and left out of its fit (`classes`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub joined: Vec<String>,
}

/// A calibration: what `platefield calibrate` prints and writes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Calibration {
    /// The schedule's target.
    pub target: String,
    /// The tracks file.
    pub tracks: String,
    /// Parts and frames.
    pub parts: usize,
    /// Frames.
    pub frames: usize,
    /// The model the paths were predicted by: the field, or exact
    /// replays.
    pub model: String,
    /// Why that model: the field model's residual against the tracks' own
    /// noise ([`replay`]'s doc).
    #[serde(default)]
    pub model_reason: String,
    /// Position noise σ per axis estimated from the tracks alone (m).
    pub noise_m: Option<f64>,
    /// Friction classes, by increasing μ.
    pub classes: Vec<ClassEstimate>,
    /// Each part's own estimate.
    pub per_part: Vec<PartEstimate>,
    /// The field model's lattice scan, per class: (μ, Δχ² = ΔRSS/σ̂²)
    /// with μ_s = μ_k (empty for a class fitted by replays).
    pub likelihood: Vec<Vec<[f64; 2]>>,
    /// The fine profile about each class's estimate: (μ_k, Δχ²) (by
    /// replays: the Gauss–Newton quadratic, its curvature the noise
    /// model's).
    pub profile: Vec<Vec<[f64; 2]>>,
    /// Velocity fields computed.
    pub fields_computed: usize,
    /// Parts replayed by the exact simulator (each replay one part over its
    /// track).
    #[serde(default)]
    pub replays: usize,
    /// RK4 steps per cycle of the simulations the classes are fitted by:
    /// on the field, the schedule's own; by replays, the fewest whose error
    /// stays within [`replay::STEP_ERROR`] of the tracks' noise at the
    /// estimate ([`replay::steps_for`], `replay::steps_hold`).
    #[serde(default)]
    pub steps_per_cycle: usize,
}

impl Calibration {
    /// Reads a `calibration.json` written by `platefield calibrate`.
    ///
    /// # Errors
    /// The file cannot be read or is not a calibration (names the file
    /// and the JSON path).
    pub fn load(path: &std::path::Path) -> Result<Calibration> {
        let name = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: name.clone(),
            source,
        })?;
        let de = &mut serde_json::Deserializer::from_str(&text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            Error::invalid(
                format!("{name}: {}", e.path()),
                format!(
                    "not a calibration written by `platefield calibrate`: {}",
                    e.inner()
                ),
            )
        })
    }

    /// Class `class`'s friction as a design's friction range: μ_k's 95 %
    /// interval, and μ_s's when the tracks determined it (else μ_s = μ_k
    /// over μ_k's interval: the tracks bound μ_s only from below).
    ///
    /// ```
    /// use platefield::calibrate::{Calibration, ClassEstimate, ParamEstimate};
    /// let p = |v: f64, lo: f64, hi: f64| ParamEstimate {
    ///     value: Some(v), standard_error: None, interval: Some([lo, hi]), estimated: true, note: None,
    /// };
    /// let none = ParamEstimate { value: None, standard_error: None, interval: None, estimated: false, note: None };
    /// let class = ClassEstimate {
    ///     parts: vec![], mu_k: p(0.23, 0.22, 0.24), mu_s: none.clone(), scale: none,
    ///     correlations: vec![], residual_rms_m: 2e-4, residual_over_noise: None,
    ///     coordinates: 0, dof: 0, not_separable: vec![], model_bias: vec![],
    ///     model_slope: vec![], joined: vec![],
    /// };
    /// let c = Calibration {
    ///     target: "sink".into(), tracks: "t.csv".into(), parts: 1, frames: 3, model: String::new(),
    ///     model_reason: String::new(), noise_m: None, classes: vec![class], per_part: vec![],
    ///     likelihood: vec![], profile: vec![], fields_computed: 0, replays: 0, steps_per_cycle: 64,
    /// };
    /// let spec = c.friction_spec(0)?;
    /// assert!(spec.tied && spec.kinetic.lo == 0.22 && spec.kinetic.hi == 0.24);
    /// assert!(c.friction_spec(1).is_err());
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// No such class, or its μ_k was not estimated.
    pub fn friction_spec(&self, class: usize) -> Result<FrictionSpec> {
        let c = self.classes.get(class).ok_or_else(|| {
            Error::invalid(
                "--class",
                format!(
                    "the calibration has {} class(es) (0 to {}), no class {class}",
                    self.classes.len(),
                    self.classes.len().saturating_sub(1)
                ),
            )
        })?;
        let k = c.mu_k.interval.ok_or_else(|| {
            Error::invalid(format!("classes[{class}].mu_k"), "μ_k was not estimated")
        })?;
        let kinetic = Interval {
            lo: k[0].max(0.001),
            hi: k[1].min(2.0),
        };
        let spec = match c.mu_s.interval {
            Some(s) => FrictionSpec {
                stat: Interval {
                    lo: s[0].max(kinetic.lo),
                    hi: s[1].min(2.0).max(kinetic.hi),
                },
                kinetic,
                tied: false,
            },
            None => FrictionSpec::range(kinetic.lo, kinetic.hi),
        };
        spec.validate_driven(&format!("classes[{class}]"))?;
        Ok(spec)
    }
}

/// One track's label, observed positions and fitted path at its frames.
pub type TrackPaths = (String, Vec<[f64; 2]>, Vec<[f64; 2]>);

/// The calibration and what its report draws.
#[derive(Debug, Clone)]
pub struct CalibrationRun {
    /// The summary.
    pub calibration: Calibration,
    /// Per track: observed frames and the fitted path at the same times.
    pub paths: Vec<TrackPaths>,
}

/// Calibrates the friction (and the scale, if asked) of the parts in
/// `tracks`, observed under `schedule`.
///
/// ```
/// use platefield::calibrate::{calibrate, simulate_tracks, CalibrateOptions, TrackSimulation};
/// use platefield::dynamics::Friction;
/// use platefield::schedule::Schedule;
/// let schedule = Schedule::load(std::path::Path::new("results/squeeze_trans/schedule.json"))?;
/// let region = schedule.region();
/// let mut sim = TrackSimulation::new(Friction::uniform(0.25), 4, 3);
/// sim.seconds = 3.0;
/// let tracks = simulate_tracks(&schedule, &region, &sim)?;
/// let run = calibrate(&schedule, &tracks, &CalibrateOptions { grid: 9, ..Default::default() })?;
/// let mu = run.calibration.classes[0].mu_k.value.unwrap();
/// assert!((mu - 0.25).abs() < 0.05, "{mu}");
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// Tracks outside the plate region or not fitting the schedule's
/// duration (naming the file, line and column), an invalid schedule, a
/// field the paths cannot follow.
pub fn calibrate(
    schedule: &Schedule,
    tracks: &Tracks,
    options: &CalibrateOptions,
) -> Result<CalibrationRun> {
    if !(3..=Grid::MAX_N).contains(&options.grid) {
        return Err(Error::invalid(
            "--grid",
            format!("must be within [3, {}], got {}", Grid::MAX_N, options.grid),
        ));
    }
    let region = schedule.region();
    tracks.check_region(&region)?;
    let grid = Grid {
        n: [options.grid, options.grid],
        ..region
    };
    let motion = PlayedMotion::from_schedule(schedule, grid)?;
    tracks.check_duration(motion.period(), options.played)?;
    let noise = tracks.noise();
    // Frames of the start-up transient are left out of the field model's
    // fit: a part put at rest on the plate reaches its periodic orbit
    // within a few cycles, with a jump of up to millimetres the
    // mean-velocity model does not follow.
    let settled = settled(tracks)?;
    let all: Vec<&Track> = settled.iter().collect();
    let mus = lattice();
    let scanned = scan(&motion, &all, &mus, 0.0, 1.0);
    let curves: Vec<Vec<f64>> = (0..all.len())
        .map(|i| {
            scanned
                .iter()
                .map(|s| s.as_ref().map_or(f64::INFINITY, |v| v[i]))
                .collect()
        })
        .collect();
    let lattice_fields = mus.len() * motion_fields(&motion);
    let choice = choose(&motion, &all, &mus, &curves, noise)?;
    let check_fields = if noise.is_some() {
        motion_fields(&motion)
    } else {
        0
    };
    let context = Context {
        schedule,
        region,
        motion,
        noise,
        options,
    };
    let fitted = if choice.replay {
        let raw = all
            .iter()
            .map(|t| tracks.tracks.iter().find(|r| r.part == t.part))
            .collect::<Option<Vec<&Track>>>()
            .ok_or_else(|| Error::Unreachable("a settled track without its part".into()))?;
        by_replay(&context, &raw, &mus, &curves)?
    } else {
        by_field(&context, &all, &mus, &curves, choice.checked)?
    };
    Ok(CalibrationRun {
        calibration: Calibration {
            target: schedule.target.clone(),
            tracks: tracks.source.clone(),
            parts: all.len(),
            frames: tracks.frames(),
            model: fitted.model,
            model_reason: choice.reason,
            noise_m: noise,
            classes: fitted.classes,
            per_part: fitted.per_part,
            likelihood: fitted.likelihood,
            profile: fitted.profile,
            fields_computed: lattice_fields + check_fields + fitted.fields,
            replays: fitted.replays,
            steps_per_cycle: fitted.steps_per_cycle,
        },
        paths: fitted.paths,
    })
}

/// What every class's fit shares.
struct Context<'a> {
    schedule: &'a Schedule,
    region: Grid,
    motion: PlayedMotion,
    noise: Option<f64>,
    options: &'a CalibrateOptions,
}

impl Context<'_> {
    /// The noise scale of the optimiser's cost (m).
    fn sigma_ref(&self) -> f64 {
        self.noise.unwrap_or(1e-4).max(1e-7)
    }
}

/// The classes fitted by one model, and what the report draws.
struct Fitted {
    model: String,
    classes: Vec<ClassEstimate>,
    per_part: Vec<PartEstimate>,
    likelihood: Vec<Vec<[f64; 2]>>,
    profile: Vec<Vec<[f64; 2]>>,
    paths: Vec<TrackPaths>,
    /// Fields computed beyond the lattice's.
    fields: usize,
    replays: usize,
    /// RK4 steps per cycle of the fit's simulations.
    steps_per_cycle: usize,
}

impl Fitted {
    /// A calibration by `model` before any class is fitted: the parts'
    /// own estimates, `n` empty path slots and the replays spent so far.
    fn new(model: String, per_part: Vec<PartEstimate>, n: usize, replays: usize) -> Self {
        Self {
            model,
            classes: Vec::new(),
            per_part,
            likelihood: Vec::new(),
            profile: Vec::new(),
            paths: vec![(String::new(), Vec::new(), Vec::new()); n],
            fields: 0,
            replays,
            steps_per_cycle: 0,
        }
    }
}

/// Which model predicts the paths, and why; the field set the field model
/// was checked on, at θ = (μ₀, 0, 1), for its fit to start from.
struct Choice {
    replay: bool,
    reason: String,
    checked: Option<(model::Theta, model::FieldSet)>,
}

/// The field model while its residual on the tracks is within
/// [`replay::FIELD_MISS`] × the tracks' own noise; exact replays beyond it
/// ([`replay`]'s doc). The residual is the field model's at the lowest
/// local minimum μ₀ of the parts' summed lattice curves (`curves`: each
/// part's RSS over `mus`), every part's start fitted and the periodic
/// orbits' excursions included, per degree of freedom.
///
/// # Errors
/// A field cannot be computed.
fn choose(
    motion: &PlayedMotion,
    tracks: &[&Track],
    mus: &[f64],
    curves: &[Vec<f64>],
    noise: Option<f64>,
) -> Result<Choice> {
    let miss = replay::FIELD_MISS;
    let Some(noise) = noise else {
        return Ok(Choice {
            replay: false,
            reason: "the field, unchecked: the tracks' noise cannot be estimated (no three evenly spaced frames), so the field model's residual cannot be held against it".into(),
            checked: None,
        });
    };
    let cannot = |why: String| Choice {
        replay: true,
        reason: format!("exact replays: {why}"),
        checked: None,
    };
    let Some(&mu0) = local_minima(mus, &summed(curves)).first() else {
        return Ok(cannot(
            "the field model cannot follow every part at any μ of the lattice".into(),
        ));
    };
    let theta0 = [mu0, 0.0, 1.0];
    let set = motion.centre(&theta0)?;
    let Ok(starts) = estimate::fit_starts(motion, &set, tracks, None) else {
        return Ok(cannot(format!(
            "the field model cannot follow every part at μ {mu0:.3}"
        )));
    };
    let coords: usize = tracks.iter().map(|t| 2 * t.frames.len()).sum();
    let dof = coords.saturating_sub(2 * tracks.len() + 1).max(1);
    let rss: f64 = starts.iter().map(|s| s.rss).sum();
    let ratio = (rss / dof as f64).sqrt() / noise;
    if ratio.is_nan() || ratio > miss {
        return Ok(cannot(format!(
            "the field model's residual at μ {mu0:.3} is {ratio:.2} × the tracks' own noise, beyond {miss}: the field model cannot follow these tracks to their noise"
        )));
    }
    Ok(Choice {
        replay: false,
        reason: format!(
            "the field: its residual at μ {mu0:.3} is {ratio:.2} × the tracks' own noise, within {miss}"
        ),
        checked: Some((theta0, set)),
    })
}

/// The parts' lattice curves summed, μ by μ.
fn summed(curves: &[Vec<f64>]) -> Vec<f64> {
    let n = curves.first().map_or(0, Vec::len);
    (0..n).map(|m| curves.iter().map(|c| c[m]).sum()).collect()
}

/// The local minima of a sampled curve, each refined by the parabola
/// through it and its neighbours, lowest first.
fn local_minima(x: &[f64], y: &[f64]) -> Vec<f64> {
    let mut found: Vec<(f64, f64)> = (0..y.len())
        .filter(|&i| {
            let lower = |j: Option<usize>| j.and_then(|j| y.get(j)).is_none_or(|&v| y[i] < v);
            y[i].is_finite() && lower(i.checked_sub(1)) && lower(Some(i + 1))
        })
        .map(|i| {
            let (lo, hi) = (i.saturating_sub(1), (i + 2).min(y.len()));
            let at = parabola_minimum(&x[lo..hi], &y[lo..hi]).map_or(x[i], |m| m.0);
            (y[i], at)
        })
        .collect();
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    found.into_iter().map(|m| m.1).collect()
}

/// The classes by the field model: each part's own μ from its lattice
/// curve, the classes, each class fitted on the field stencil and its
/// model bias removed by replays.
fn by_field(
    context: &Context<'_>,
    all: &[&Track],
    mus: &[f64],
    curves: &[Vec<f64>],
    mut checked: Option<(model::Theta, model::FieldSet)>,
) -> Result<Fitted> {
    let motion = &context.motion;
    // Pooled σ̂² at each part's own minimum: the scale of its curvature.
    let coords: usize = all.iter().map(|t| 2 * t.frames.len()).sum();
    let rss_min: f64 = curves
        .iter()
        .map(|c| c.iter().copied().fold(f64::INFINITY, f64::min))
        .sum();
    let lattice_dof = coords.saturating_sub(3 * all.len()).max(1);
    let sigma2 = rss_min / lattice_dof as f64;
    let own = own_estimates(curves, mus, all, sigma2)?;
    let class_of = cluster(&own);
    let n_classes = class_of.iter().map(|c| c.0).max().map_or(0, |m| m + 1);
    let model = format!(
        "steady-state velocity fields of the schedule's {} segment(s) on a {}×{} grid over the plate region, interpolated in μ and scale by a quadratic stencil; paths by RK4 (not a full replay)",
        motion_fields(motion),
        context.options.grid,
        context.options.grid
    );
    let mut fitted = Fitted::new(model, per_part(all, &own, &class_of), all.len(), 0);
    fitted.steps_per_cycle = context.schedule.settings.numerics.steps_per_cycle;
    for c in 0..n_classes {
        let (members, joined) = split_class(&class_of, c);
        let class_tracks: Vec<&Track> = members.iter().map(|&i| all[i]).collect();
        let curve: Vec<f64> = (0..mus.len())
            .map(|m| members.iter().map(|&i| curves[i][m]).sum())
            .collect();
        let (mut fit, stick, fields) =
            fit_one(context, &class_tracks, mus, &curve, checked.take())?;
        let (bias, slope) = correct_bias(context, &mut fit, &class_tracks)?;
        fitted.fields += fields;
        fitted.replays += 2 * class_tracks.len();
        let s2 = fit.sigma().powi(2);
        let lattice_curve: Vec<[f64; 2]> = mus.iter().zip(&curve).map(|(m, v)| [*m, *v]).collect();
        fitted.likelihood.push(delta_chi2(&lattice_curve, s2));
        fitted.profile.push(delta_chi2(&fit.profile, s2));
        for (k, &i) in members.iter().enumerate() {
            fitted.paths[i] = fitted_path(motion, &fit.set, fit.starts[k].start, all[i])?;
        }
        for &i in &joined {
            let start = estimate::fit_start(motion, &fit.set, all[i], all[i].frames[0].r)?;
            fitted.paths[i] = fitted_path(motion, &fit.set, start.start, all[i])?;
        }
        let solution = Solution::of_field(&fit);
        let mut estimate = class_estimate(&solution, &class_tracks, context, stick);
        let named = |v: &model::Theta| -> Vec<(String, f64)> {
            fit.free
                .iter()
                .map(|&j| (model::NAMES[j].to_string(), v[j]))
                .collect()
        };
        estimate.model_bias = named(&bias);
        estimate.model_slope = named(&slope);
        for (j, s) in &estimate.model_slope {
            if !(SLOPE[0] < *s && *s < SLOPE[1]) {
                estimate.not_separable.push(format!(
                    "{j} (the model's fit responds to it by a slope outside {SLOPE:?}: the bias correction is not reliable)"
                ));
            }
        }
        estimate.joined = joined.iter().map(|&i| all[i].part.clone()).collect();
        fitted.classes.push(estimate);
    }
    Ok(fitted)
}

/// The parts of class `c`: those fitted with it, and those joined to it.
fn split_class(class_of: &[(usize, bool)], c: usize) -> (Vec<usize>, Vec<usize>) {
    let of = |fitted: bool| -> Vec<usize> {
        (0..class_of.len())
            .filter(|&i| class_of[i] == (c, fitted))
            .collect()
    };
    (of(true), of(false))
}

/// Each part's own estimate and class.
fn per_part(all: &[&Track], own: &[classes::Own], class_of: &[(usize, bool)]) -> Vec<PartEstimate> {
    all.iter()
        .enumerate()
        .map(|(i, tr)| PartEstimate {
            part: tr.part.clone(),
            frames: tr.frames.len(),
            mu: own[i].0,
            standard_error: own[i].1,
            class: class_of[i].0,
        })
        .collect()
}

/// A change of μ_s − μ_k by 2 stencil steps that moves no replayed
/// position by more than this (m) is no change: the parts never stick.
const STICK_POSITION: f64 = 1e-9;

/// The classes by exact replays ([`replay`]): each part fitted alone from
/// the best of the field lattice's local minima (μ_s = μ_k, scale 1), the
/// classes, each class fitted as one. The replays run at the fewest RK4
/// steps per cycle [`replay::steps_for`] finds at the lowest minimum, each
/// class's fit refined to more where [`replay::steps_hold`] says its
/// estimate needs them.
fn by_replay(
    context: &Context<'_>,
    raw: &[&Track],
    mus: &[f64],
    curves: &[Vec<f64>],
) -> Result<Fitted> {
    let own_steps = context.schedule.settings.numerics.steps_per_cycle;
    let candidates = candidates(mus, curves, context.schedule.settings.friction.kinetic);
    let (coarse, probed) = replay::steps_for(
        context.schedule,
        longest(raw)?,
        &[candidates[0], 0.0, 1.0],
        context.noise,
    )?;
    let first: Vec<[f64; 2]> = raw.iter().map(|t| t.frames[0].r).collect();
    let own_fits = raw
        .par_iter()
        .zip(&first)
        .map(|(t, &r0)| own_fit(&coarse, t, r0, &candidates, context.noise))
        .collect::<Result<Vec<_>>>()?;
    let replays = probed + own_fits.iter().map(|f| f.2).sum::<usize>();
    let own: Vec<classes::Own> = own_fits
        .iter()
        .map(|(mu, fit, _)| match fit {
            Some(f) => (f.theta[MU_K], Some(f.classical[0][0].max(0.0).sqrt())),
            None => (*mu, None),
        })
        .collect();
    let class_of = cluster(&own);
    let n_classes = class_of.iter().map(|c| c.0).max().map_or(0, |m| m + 1);
    let model = "exact replays: each part put down at rest at a fitted start when the schedule starts (t = 0) and played through every segment and join by the stick-slip simulator, every frame fitted (not the field)";
    let mut fitted = Fitted::new(
        model.into(),
        per_part(raw, &own, &class_of),
        raw.len(),
        replays,
    );
    fitted.steps_per_cycle = coarse.settings.numerics.steps_per_cycle;
    for c in 0..n_classes {
        let (members, joined) = split_class(&class_of, c);
        let class_tracks: Vec<&Track> = members.iter().map(|&i| raw[i]).collect();
        let mu0 = classes::pooled(&members, &own).0;
        let mut starts: Vec<[f64; 2]> = members
            .iter()
            .map(|&i| own_fits[i].1.as_ref().map_or(first[i], |f| f.starts[0]))
            .collect();
        let (stick, base, checked) = sticks(&coarse, &class_tracks, mu0, &starts)?;
        fitted.replays += checked;
        let mut free = vec![MU_K];
        let mut theta0 = [mu0, 0.0, 1.0];
        let mut base = Some(base);
        if stick {
            free.push(EXCESS);
            theta0[EXCESS] = 2.0 * STEPS[EXCESS];
            base = None;
        }
        if context.options.scale {
            free.push(SCALE);
        }
        let mut schedule = coarse.clone();
        let fit = loop {
            let fit = class_fit(&schedule, &class_tracks, theta0, &free, starts, base.take())?;
            fitted.replays += fit.replays;
            let (held, checked) = replay::steps_hold(
                &schedule,
                own_steps,
                longest(&class_tracks)?,
                &fit.theta,
                context.noise,
            )?;
            fitted.replays += checked;
            if held.settings.numerics.steps_per_cycle == schedule.settings.numerics.steps_per_cycle
            {
                break fit;
            }
            // Refitted from the estimate at the steps that hold there.
            (schedule, theta0, starts) = (held, fit.theta, fit.starts);
        };
        fitted.steps_per_cycle = fitted
            .steps_per_cycle
            .max(schedule.settings.numerics.steps_per_cycle);
        fitted.likelihood.push(Vec::new());
        fitted
            .profile
            .push(quadratic_profile(fit.theta[MU_K], fit.classical[0][0]));
        for (k, &i) in members.iter().enumerate() {
            fitted.paths[i] = (
                raw[i].part.clone(),
                raw[i].frames.iter().map(|f| f.r).collect(),
                fit.paths[k].clone(),
            );
        }
        for &i in &joined {
            let r0 = own_fits[i].1.as_ref().map_or(first[i], |f| f.starts[0]);
            let times: Vec<f64> = raw[i].frames.iter().map(|f| f.t).collect();
            let p = replay::path(&schedule, &fit.theta, r0, &times)?.unwrap_or_default();
            fitted.replays += 1;
            fitted.paths[i] = (
                raw[i].part.clone(),
                raw[i].frames.iter().map(|f| f.r).collect(),
                p.chunks(2).map(|q| [q[0], q[1]]).collect(),
            );
        }
        let solution = Solution::of_replay(&fit);
        let mut estimate = class_estimate(&solution, &class_tracks, context, stick);
        estimate.joined = joined.iter().map(|&i| raw[i].part.clone()).collect();
        fitted.classes.push(estimate);
    }
    Ok(fitted)
}

/// Where the parts' own fits by replays may start: the local minima of
/// the parts' summed lattice curves (lowest first), and the median of the
/// parts' own lowest minima inside the lattice when it is more than a
/// lattice step from each of those. The summed curve is dominated by the
/// parts the field model misses most (at a sink's centre its minimum can
/// sit at the lattice's end, a bound rather than a minimum); the median
/// is the parts' own view, robust to those. `fallback` (the schedule's
/// μ_k) when there is none.
fn candidates(mus: &[f64], curves: &[Vec<f64>], fallback: f64) -> Vec<f64> {
    let mut out = local_minima(mus, &summed(curves));
    let (lo, hi) = (mus[0], mus[mus.len() - 1]);
    let mut inside: Vec<f64> = curves
        .iter()
        .filter_map(|c| local_minima(mus, c).first().copied())
        .filter(|&m| lo < m && m < hi)
        .collect();
    inside.sort_by(f64::total_cmp);
    if let Some(&median) = inside.get(inside.len() / 2) {
        let step = mus[1] - mus[0];
        if out.iter().all(|&c| (c - median).abs() > step) {
            out.push(median);
        }
    }
    if out.is_empty() {
        out.push(fallback);
    }
    out
}

/// The track observed longest (its last frame the latest): where a
/// replay's error has grown most.
fn longest<'a>(tracks: &[&'a Track]) -> Result<&'a Track> {
    let last = |t: &Track| t.frames.last().map_or(0.0, |f| f.t);
    tracks
        .iter()
        .copied()
        .max_by(|a, b| last(a).total_cmp(&last(b)))
        .ok_or_else(|| Error::Unreachable("no track to replay".into()))
}

/// One class's fit by replays ([`replay::fit`] to [`replay::STEP_TOL`]).
///
/// # Errors
/// The replays cannot follow the class: a part loses contact, or its start
/// is not determined by its track.
fn class_fit(
    schedule: &Schedule,
    tracks: &[&Track],
    theta0: model::Theta,
    free: &[usize],
    starts: Vec<[f64; 2]>,
    base: Option<replay::Paths>,
) -> Result<replay::ReplayFit> {
    replay::fit(schedule, tracks, theta0, free, starts, base, replay::STEP_TOL)?.ok_or_else(|| {
        Error::Unreachable(format!(
            "the exact replays cannot follow the class of parts {} (a part loses contact, or its start is not determined by its track)",
            tracks.iter().map(|t| t.part.as_str()).collect::<Vec<_>>().join(", ")
        ))
    })
}

/// A part's own fit by replays (μ_s = μ_k, scale 1) from its first frame
/// `r0`: from the candidate μ whose replay fits its track best, then, while
/// the fit's residual is beyond [`replay::FIELD_MISS`] × the tracks' noise
/// (a false minimum), from the next candidates, keeping the least
/// residual. The μ it started from, the fit (`None`: the replays cannot
/// follow it), the replays run.
fn own_fit(
    schedule: &Schedule,
    track: &Track,
    r0: [f64; 2],
    candidates: &[f64],
    noise: Option<f64>,
) -> Result<(f64, Option<replay::ReplayFit>, usize)> {
    let times: Vec<f64> = track.frames.iter().map(|f| f.t).collect();
    let mut tried = Vec::with_capacity(candidates.len());
    for &mu in candidates {
        let p = replay::path(schedule, &[mu, 0.0, 1.0], r0, &times)?;
        let rss = p.as_ref().map_or(f64::INFINITY, |p| {
            track
                .frames
                .iter()
                .zip(p.chunks(2))
                .map(|(f, q)| (f.r[0] - q[0]).powi(2) + (f.r[1] - q[1]).powi(2))
                .sum()
        });
        tried.push((rss, mu, p));
    }
    tried.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut replays = candidates.len();
    let mut best: (f64, Option<replay::ReplayFit>) = (tried.first().map_or(0.3, |c| c.1), None);
    for (_, mu, base) in tried {
        let fit = replay::fit(
            schedule,
            &[track],
            [mu, 0.0, 1.0],
            &[MU_K],
            vec![r0],
            Some(vec![base]),
            replay::OWN_STEP_TOL,
        )?;
        let Some(fit) = fit else { continue };
        replays += fit.replays;
        let sigma = (fit.rss / fit.dof as f64).sqrt();
        if best.1.as_ref().is_none_or(|b| fit.rss < b.rss) {
            best = (mu, Some(fit));
        }
        if noise.is_none_or(|n| sigma <= replay::FIELD_MISS * n) {
            break;
        }
    }
    Ok((best.0, best.1, replays))
}

/// Whether μ_s matters to the replays of `tracks` at μ_k = `mu` from
/// `starts`: μ_s − μ_k = 0 against 2 stencil steps moves some replayed
/// position by more than [`STICK_POSITION`]. Also the paths at μ_s = μ_k
/// (those at the larger μ_s when it matters: where the fit starts), and
/// the replays run.
fn sticks(
    schedule: &Schedule,
    tracks: &[&Track],
    mu: f64,
    starts: &[[f64; 2]],
) -> Result<(bool, replay::Paths, usize)> {
    let replay_at = |excess: f64| -> Result<replay::Paths> {
        tracks
            .par_iter()
            .zip(starts)
            .map(|(t, &r0)| {
                let times: Vec<f64> = t.frames.iter().map(|f| f.t).collect();
                replay::path(schedule, &[mu, excess, 1.0], r0, &times)
            })
            .collect()
    };
    let (tied, apart) = (replay_at(0.0)?, replay_at(2.0 * STEPS[EXCESS])?);
    let moved = tied.iter().zip(&apart).any(|(a, b)| match (a, b) {
        (Some(a), Some(b)) => a.iter().zip(b).any(|(p, q)| (p - q).abs() > STICK_POSITION),
        _ => a.is_some() != b.is_some(),
    });
    let base = if moved { apart } else { tied };
    Ok((moved, base, 2 * tracks.len()))
}

/// Δχ² of a linearised fit along μ_k about `mu` (the other parameters
/// profiled out), `var` μ_k's variance under the noise model: (μ − μ̂)²/var
/// over ±4 standard errors.
fn quadratic_profile(mu: f64, var: f64) -> Vec<[f64; 2]> {
    let se = var.max(0.0).sqrt();
    (-10..=10)
        .map(|k| {
            let z = 0.4 * f64::from(k);
            [mu + z * se, z * z]
        })
        .collect()
}

/// One class fitted from its summed lattice curve's minimum (`checked`:
/// the field set at θ = (μ₀, 0, 1) when computed): the fit, whether μ_s
/// matters, the fields computed.
fn fit_one(
    context: &Context<'_>,
    tracks: &[&Track],
    mus: &[f64],
    curve: &[f64],
    checked: Option<(model::Theta, model::FieldSet)>,
) -> Result<(ClassFit, bool, usize)> {
    let motion = &context.motion;
    let mu0 = parabola_minimum(mus, curve).map_or(0.3, |m| m.0);
    let theta0 = [mu0, 0.0, 1.0];
    let checked = checked.filter(|c| c.0 == theta0);
    let (free, stick, computed) =
        free_parameters(motion, mu0, context.options.scale, checked.as_ref())?;
    let theta0 = [mu0, if stick { STEPS[EXCESS] } else { 0.0 }, 1.0];
    let fit = fit_class(
        motion,
        tracks,
        theta0,
        STEPS,
        &free,
        context.sigma_ref(),
        checked,
    )?;
    let fields = (computed + fit.fields) * motion_fields(motion);
    Ok((fit, stick, fields))
}

/// Slopes β′ of the binding function beyond this range make the bias
/// correction untrustworthy: held to it and named.
pub const SLOPE: [f64; 2] = [0.5, 2.0];

/// A correction shorter than this (in θ's units) is below any standard
/// error: the slope is not measured over it (taken as 1).
const SECANT_MIN: f64 = 1e-4;

/// Removes the field model's bias from `fit` (indirect inference,
/// [`estimate`]'s doc): the class's parts are replayed noise-free by the
/// exact simulator, each put down at rest at t = 0 where the model's path
/// at θ̂ puts its fitted start back by the time of its first frame,
/// observed at the same frames, at θ̂ and at θ₁ = θ̂ − b(θ̂); one secant
/// step solves β(θ̃) = θ̂. θ̃ is reported, its covariance divided by the
/// slopes, the profile mapped through the same line; the fitted paths stay
/// the model's at θ̂. Returns θ̂ − θ̃ and the slopes β′ (1 for parameters
/// not fitted).
fn correct_bias(
    context: &Context<'_>,
    fit: &mut ClassFit,
    tracks: &[&Track],
) -> Result<(model::Theta, model::Theta)> {
    let (schedule, region, motion) = (context.schedule, &context.region, &context.motion);
    let sigma_ref = context.sigma_ref();
    let parts = tracks
        .iter()
        .zip(&fit.starts)
        .map(|(tr, s)| {
            let times: Vec<f64> = tr.frames.iter().map(|f| f.t).collect();
            let there = motion.advance(&fit.set, s.start, 0.0, times[0])?;
            let r0 = [
                (2.0 * s.start[0] - there[0]).clamp(region.x[0], region.x[1]),
                (2.0 * s.start[1] - there[1]).clamp(region.y[0], region.y[1]),
            ];
            Ok((tr.part.clone(), r0, times))
        })
        .collect::<Result<Vec<_>>>()?;
    let fitted: &ClassFit = fit;
    let beta = |theta: &model::Theta| -> Result<model::Theta> {
        let replayed = simulate::replay_tracks(
            schedule,
            region,
            model::friction(theta),
            theta[SCALE],
            &parts,
        )?;
        let refs: Vec<&Track> = replayed.iter().collect();
        estimate::binding(motion, fitted, &refs, sigma_ref)
    };
    let bound = |j: usize, v: f64| v.clamp(estimate::BOUNDS[j][0], estimate::BOUNDS[j][1]);
    let hat = fit.theta;
    let b0 = beta(&hat)?;
    let mut t1 = hat;
    for &j in &fit.free {
        t1[j] = bound(j, 2.0 * hat[j] - b0[j]);
    }
    let b1 = beta(&t1)?;
    let (mut slope, mut corrected) = ([1.0; 3], hat);
    for &j in &fit.free {
        let d = t1[j] - hat[j];
        if d.abs() > SECANT_MIN {
            slope[j] = ((b1[j] - b0[j]) / d).clamp(SLOPE[0], SLOPE[1]);
        }
        corrected[j] = bound(j, t1[j] + (hat[j] - b1[j]) / slope[j]);
    }
    for (a, &ja) in fit.free.iter().enumerate() {
        for (b, &jb) in fit.free.iter().enumerate() {
            fit.covariance[a][b] /= slope[ja] * slope[jb];
        }
    }
    for p in &mut fit.profile {
        p[0] = corrected[MU_K] + (p[0] - hat[MU_K]) / slope[MU_K];
    }
    fit.theta = corrected;
    let mut bias = [0.0; 3];
    for &j in &fit.free {
        bias[j] = hat[j] - corrected[j];
    }
    Ok((bias, slope))
}

/// A track's label, observed positions and path in `set` from `start`.
fn fitted_path(
    motion: &PlayedMotion,
    set: &model::FieldSet,
    start: [f64; 2],
    track: &Track,
) -> Result<TrackPaths> {
    let times: Vec<f64> = track.frames.iter().map(|f| f.t).collect();
    let fitted = motion.path(set, start, times[0], &times)?;
    Ok((
        track.part.clone(),
        track.frames.iter().map(|f| f.r).collect(),
        fitted,
    ))
}

/// The tracks without the frames of the start-up transient (t <
/// [`SETTLE`]); tracks left with fewer than three frames are dropped.
fn settled(tracks: &Tracks) -> Result<Vec<Track>> {
    let settled: Vec<Track> = tracks
        .tracks
        .iter()
        .map(|t| Track {
            part: t.part.clone(),
            frames: t.frames.iter().filter(|f| f.t >= SETTLE).copied().collect(),
        })
        .filter(|t| t.frames.len() >= tracks::MIN_FRAMES)
        .collect();
    if settled.is_empty() {
        return Err(Error::invalid(
            tracks.source.clone(),
            format!(
                "no part has {} frames after the start-up transient (t ≥ {SETTLE} s)",
                tracks::MIN_FRAMES
            ),
        ));
    }
    Ok(settled)
}

/// Each part's own μ and standard error from its residual `curves[i]`
/// over the lattice `mus` (σ̂² the pooled residual variance).
fn own_estimates(
    curves: &[Vec<f64>],
    mus: &[f64],
    tracks: &[&Track],
    sigma2: f64,
) -> Result<Vec<(f64, Option<f64>)>> {
    curves
        .iter()
        .zip(tracks)
        .map(|(curve, tr)| {
            let (mu, curv) = parabola_minimum(mus, curve).ok_or_else(|| {
                Error::Unreachable(format!(
                    "part \"{}\": the field cannot follow it at any μ of the lattice",
                    tr.part
                ))
            })?;
            Ok((mu, curv.map(|c| (2.0 * sigma2 / c).sqrt())))
        })
        .collect()
}

/// The parameters to fit about μ = `mu0`: μ_k; μ_s − μ_k when the fields
/// change with it (μ_s = μ_k against μ_k + 2h: some part sticks); the
/// scale when asked. Also whether μ_s matters, and the field sets computed
/// (`at`: the set at μ_s = μ_k when already computed).
fn free_parameters(
    motion: &PlayedMotion,
    mu0: f64,
    scale: bool,
    at: Option<&(model::Theta, model::FieldSet)>,
) -> Result<(Vec<usize>, bool, usize)> {
    let fresh;
    let (a, computed) = match at {
        Some((_, set)) => (set, 1),
        None => {
            fresh = motion.fields(&[mu0, 0.0, 1.0])?;
            (&fresh, 2)
        }
    };
    let b = motion.fields(&[mu0, 2.0 * STEPS[EXCESS], 1.0])?;
    let stick = a.max_difference(&b) > STICK_SENSITIVITY;
    let mut free = vec![MU_K];
    if stick {
        free.push(EXCESS);
    }
    if scale {
        free.push(SCALE);
    }
    Ok((free, stick, computed))
}

/// A residual curve (x, RSS) as (x, Δχ² = (RSS − min RSS)/σ̂²), its
/// non-finite points left out.
fn delta_chi2(curve: &[[f64; 2]], sigma2: f64) -> Vec<[f64; 2]> {
    let lo = curve.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
    curve
        .iter()
        .filter(|p| p[1].is_finite())
        .map(|p| [p[0], (p[1] - lo) / sigma2])
        .collect()
}

/// A class's fit, whichever model: θ̂, its free parameters and their
/// covariance, the residual.
struct Solution<'a> {
    theta: model::Theta,
    free: &'a [usize],
    covariance: &'a [Vec<f64>],
    rss: f64,
    dof: usize,
}

impl Solution<'_> {
    fn of_field(fit: &ClassFit) -> Solution<'_> {
        Solution {
            theta: fit.theta,
            free: &fit.free,
            covariance: &fit.covariance,
            rss: fit.rss,
            dof: fit.dof,
        }
    }

    fn of_replay(fit: &replay::ReplayFit) -> Solution<'_> {
        Solution {
            theta: fit.theta,
            free: &fit.free,
            covariance: &fit.covariance,
            rss: fit.rss,
            dof: fit.dof,
        }
    }

    /// σ̂ (m): the residual's standard deviation per coordinate.
    fn sigma(&self) -> f64 {
        (self.rss / self.dof.max(1) as f64).sqrt()
    }
}

/// The correlations of the fitted parameters, each pair beyond
/// [`CORRELATED`] named in `not_separable`.
fn correlations(fit: &Solution<'_>, not_separable: &mut Vec<String>) -> Vec<(String, String, f64)> {
    let var = |a: usize, b: usize| fit.covariance[a][b];
    let mut out = Vec::new();
    for a in 0..fit.free.len() {
        for b in 0..a {
            let rho = var(a, b) / (var(a, a) * var(b, b)).sqrt();
            let (na, nb) = (
                model::NAMES[fit.free[a]].to_string(),
                model::NAMES[fit.free[b]].to_string(),
            );
            if rho.abs() > CORRELATED {
                not_separable.push(format!("{nb} from {na} (correlation {rho:.3})"));
            }
            out.push((nb, na, rho));
        }
    }
    out
}

/// Moving segments of the played motion (fields per θ).
fn motion_fields(motion: &PlayedMotion) -> usize {
    motion.moving_segments()
}

/// A class's fitted θ as named estimates, with what is not separable.
fn class_estimate(
    fit: &Solution<'_>,
    tracks: &[&Track],
    context: &Context<'_>,
    stick: bool,
) -> ClassEstimate {
    let (noise, scale) = (context.noise, context.options.scale);
    let index = |j: usize| fit.free.iter().position(|&f| f == j);
    let var = |a: usize, b: usize| fit.covariance[a][b];
    let estimate = |value: f64, v: f64| {
        let se = v.max(0.0).sqrt();
        let weak = 2.0 * Z95 * se > WEAK;
        ParamEstimate {
            value: Some(value),
            standard_error: Some(se),
            interval: Some([value - Z95 * se, value + Z95 * se]),
            estimated: true,
            note: weak
                .then(|| format!("weakly determined: its 95 % interval is wider than {WEAK}")),
        }
    };
    let k = index(MU_K).unwrap_or(0);
    let mu_k = estimate(fit.theta[MU_K], var(k, k));
    let mu_s = match index(EXCESS) {
        Some(e) => estimate(
            fit.theta[MU_K] + fit.theta[EXCESS],
            var(k, k) + var(e, e) + 2.0 * var(k, e),
        ),
        None => ParamEstimate {
            value: None,
            standard_error: None,
            interval: None,
            estimated: false,
            note: (!stick).then(|| {
                format!(
                    "not determined: the parts never stick on this motion between μ_s = μ_k and μ_k + {} (the field does not change with μ_s), so the tracks bound only μ_s ≥ μ_k",
                    2.0 * STEPS[EXCESS]
                )
            }),
        },
    };
    let scale_estimate = match index(SCALE) {
        Some(s) => estimate(fit.theta[SCALE], var(s, s)),
        None => ParamEstimate {
            value: Some(1.0),
            standard_error: None,
            interval: None,
            estimated: false,
            note: (!scale)
                .then(|| "fixed at 1 (the motion as sent); --scale estimates it".to_string()),
        },
    };
    let mut not_separable = Vec::new();
    if mu_s.value.is_none() {
        not_separable.push("mu_s (the parts never stick)".to_string());
    }
    let correlations = correlations(fit, &mut not_separable);
    for (name, p) in [("mu_k", &mu_k), ("mu_s", &mu_s), ("scale", &scale_estimate)] {
        if p.estimated && p.note.is_some() {
            not_separable.push(format!("{name} (95 % interval wider than {WEAK})"));
        }
    }
    let coordinates: usize = tracks.iter().map(|t| 2 * t.frames.len()).sum();
    ClassEstimate {
        parts: tracks.iter().map(|t| t.part.clone()).collect(),
        mu_k,
        mu_s,
        scale: scale_estimate,
        correlations,
        residual_rms_m: (fit.rss / coordinates.max(1) as f64).sqrt(),
        residual_over_noise: noise.map(|n| fit.sigma() / n),
        coordinates,
        dof: fit.dof,
        not_separable,
        model_bias: Vec::new(),
        model_slope: Vec::new(),
        joined: Vec::new(),
    }
}

#[cfg(test)]
#[path = "../../tests/unit/calibrate.rs"]
mod calibrate_tests;
