//! `synthesize`: seed, refine on a coarse grid, re-simulate the winner on
//! the full grid and check it before it is reported.

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::calibrate::calibrate;
use super::contact::{kinematic_least_normal, orbit_least_normal};
use super::least_squares::least_squares;
use super::levenberg::LmOptions;
use super::limits::ShakerLimits;
use super::multistart::{search, MultistartOptions};
use super::objective::{realised, Objective, Realised};
use super::params::{Coefficients, Layout, AXIS_NAMES};
use super::progress::{ProgressMode, SynthesisProgress};
use super::seed::{seed, Seed};
use super::stall::StallRule;
use super::transport::{scale_search, transport_start};
use crate::error::{positive, Error, Result};
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::motion::{Motion, Signals};
use crate::request::FieldSpec;
use crate::scene::FrictionSpec;

/// A realised shape error above this flags a synthesis as POOR: the
/// product's one threshold, [`crate::fit::POOR_ERROR`].
pub(crate) const POOR_SHAPE_ERROR: f64 = crate::fit::POOR_ERROR;

/// Peaks are within limits up to this relative round-off.
const PEAK_TOL: f64 = 1e-9;

/// The default Levenberg–Marquardt settings of the synthesis: up to six
/// steps of at most 0.5 (fraction of the axis limits) from the
/// phase-calibrated seed, ending when a step gains less than 1 % (the
/// sink stops after fewer). With the strength row asking for strength up
/// to `super::objective::STRENGTH_REACH` times the seed's, the longer
/// run is what lifts line_sink_30's judged strength by about half within
/// its budget, with the reach 4 and the always-on shape block of
/// [`super::objective`] (each budget's result: `platefield study
/// design-speed`, `results/design_speed.md`).
pub const SYNTH_LM: LmOptions = LmOptions {
    max_iterations: 6,
    lambda0: 1e-2,
    step: 0.01,
    min_improvement: 0.001,
    abs_cost: 0.0,
    max_rejections: 3,
    max_step: 0.5,
};

/// The default Levenberg–Marquardt settings of the played polish: up to
/// four steps of at most 0.05 (fraction of the axis limits).
pub const POLISH_LM: LmOptions = LmOptions {
    max_iterations: 4,
    lambda0: 1e-2,
    step: 0.01,
    min_improvement: 0.01,
    abs_cost: 0.0,
    max_rejections: 3,
    max_step: 0.05,
};

/// Settings of one synthesis.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SynthOptions {
    /// Coarse grid [nx, ny] of the objective, over the region.
    pub coarse: [usize; 2],
    /// Shape-error budget on the coarse grid (the cost's knee).
    pub shape_budget: f64,
    /// Evaluations (coarse re-simulations) allowed.
    pub max_evaluations: usize,
    /// Optional wall-clock budget (s); makes the result depend on the
    /// machine's speed.
    pub max_seconds: Option<f64>,
    /// Start from the phase-calibrated seed ([`super::calibrate`]), the seed
    /// an extra start; `false` starts from the seed alone.
    pub calibrate: bool,
    /// Multi-start settings and RNG seed (of the Nelder–Mead refinement,
    /// `lm` `None`).
    pub multistart: MultistartOptions,
    /// Refine by Levenberg–Marquardt on the coarse residuals
    /// (`super::least_squares`) with these settings; `None`: the
    /// multi-start Nelder–Mead of [`super::multistart`] (kept for the
    /// comparison of `platefield study design-speed`).
    pub lm: Option<LmOptions>,
    /// Levenberg–Marquardt settings of the played polish that `design`
    /// runs; `None`: its Nelder–Mead. Not used by [`synthesize`] itself.
    pub polish_lm: Option<LmOptions>,
    /// Progress display.
    pub progress: ProgressMode,
    /// Stop the refinement once its best coarse cost has stopped improving
    /// ([`super::stall`]); `None` spends `max_evaluations`.
    pub stall: Option<StallRule>,
    /// Stall rule of the played polish that `design` runs (not used by
    /// [`synthesize`] itself).
    pub polish_stall: Option<StallRule>,
    /// Optimise the worst case over this friction range
    /// ([`super::robust`]: its ends and middle) rather than at the
    /// settings' friction alone; `None` (or an exact friction): the
    /// settings' only.
    pub robust: Option<FrictionSpec>,
    /// `design` fills [`SynthOptions::robust`] from the target's friction
    /// range (default off: three times the simulations, and for most
    /// targets no better — on the whirlpool over μ ∈ [0.2, 0.4] its worst
    /// played shape is no better than the motion's synthesized at μ 0.3
    /// alone: one motion's
    /// field turns with the lead δ = asin(μg/A) whatever it is tuned for;
    /// the mirror-image time-shares of `design::mirror` cancel the turn).
    /// `auto` runs it as one more candidate when no other holds the target
    /// over the range (`design::method::RANGE_HELD`).
    pub robust_synthesis: bool,
    /// Plays of the polish that `design` runs after the synthesis
    /// (`platefield::design::polish`; 0, the default: none). Not used by
    /// [`synthesize`] itself. Off by default: the polish optimises the
    /// judge, which for one steady motion is its steady-state field at the
    /// judge's points — what the synthesis already optimises on its coarse
    /// grid — and on `targets/sink.json` it gains a tenth of a percentage
    /// point of shape error or less for two to three times the CPU of the
    /// whole design without it.
    pub polish_plays: usize,
}

impl Default for SynthOptions {
    fn default() -> Self {
        SynthOptions {
            coarse: [7, 7],
            shape_budget: 0.04,
            max_evaluations: 300,
            max_seconds: None,
            calibrate: true,
            multistart: MultistartOptions::default(),
            lm: Some(SYNTH_LM),
            polish_lm: Some(POLISH_LM),
            progress: ProgressMode::Auto,
            // Off until the shipped designs are regenerated with it
            // (`platefield study design-speed` measures it against `full`).
            stall: None,
            polish_stall: None,
            robust: None,
            robust_synthesis: false,
            polish_plays: 0,
        }
    }
}

impl SynthOptions {
    fn validate(&self) -> Result<()> {
        for (i, n) in self.coarse.iter().enumerate() {
            if !(2..=101).contains(n) {
                return Err(Error::invalid(
                    format!("coarse[{i}]"),
                    format!("must be in 2..=101, got {n}"),
                ));
            }
        }
        positive("shape_budget", self.shape_budget)?;
        if self.max_evaluations == 0 {
            return Err(Error::invalid("max_evaluations", "must be ≥ 1"));
        }
        if let Some(r) = &self.stall {
            if r.window == 0 {
                return Err(Error::invalid("stall.window", "must be ≥ 1"));
            }
            if !(r.tol >= 0.0 && r.tol.is_finite()) {
                return Err(Error::invalid("stall.tol", "must be finite and ≥ 0"));
            }
        }
        if let Some(s) = self.max_seconds {
            positive("max_seconds", s)?;
        }
        if self.multistart.starts == 0 {
            return Err(Error::invalid("starts", "must be ≥ 1"));
        }
        positive("step", self.multistart.step)?;
        Ok(())
    }
}

/// One axis's peak against its limit.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisPeak {
    /// Signal name (`linear.x`, …, `angular.z`).
    pub axis: &'static str,
    /// Peak |acceleration| of the summed signal over the period.
    pub peak: f64,
    /// Its limit.
    pub limit: f64,
}

/// A synthesized motion and its checks.
#[derive(Debug, Clone, PartialEq)]
pub struct Synthesis {
    /// The six-signal motion and its checks on the full grid: field,
    /// realised measure, peaks, least N, POOR, and notes (why it is poor,
    /// and what limited the seed).
    pub checked: Checked,
    /// The realised measure on the coarse grid (what the optimizer saw).
    pub coarse: Realised,
    /// The seed's realised measure on the coarse grid.
    pub seed_realised: Realised,
    /// The seed's predicted strength (averaged-friction analysis).
    pub seed_strength: f64,
    /// Coarse re-simulations used (seed included).
    pub evaluations: usize,
    /// Wall time (s); not part of any data file.
    pub seconds: f64,
    /// What limited the seed (the notes that do not depend on the motion
    /// kept).
    pub seed_notes: Vec<String>,
}

impl Synthesis {
    /// This synthesis with its motion replaced by `checked` (a later
    /// polish of the same request): the seed, coarse and evaluation
    /// records stay, `evaluations` and `seconds` grow by the polish's.
    pub(crate) fn with_checked(
        &self,
        checked: Checked,
        evaluations: usize,
        seconds: f64,
    ) -> Synthesis {
        Synthesis {
            checked,
            coarse: self.coarse,
            seed_realised: self.seed_realised,
            seed_strength: self.seed_strength,
            evaluations: self.evaluations + evaluations,
            seconds: self.seconds + seconds,
            seed_notes: self.seed_notes.clone(),
        }
    }

    /// One-line summary: seed, realised strength and shape error on the
    /// full grid, evaluations, least N, POOR and notes. Without the run time,
    /// so committed reports change only when their content does; printed
    /// summaries use [`Synthesis::timed_summary`].
    pub fn summary(&self) -> String {
        let c = &self.checked;
        let n = c.field.grid.n;
        let pct = crate::output::percent;
        format!(
            "seed {:.4} predicted, {:.4} at {} realised (coarse); synthesized {:.4} at {} ({}×{}), {} evaluations, least N {:.2} m/s²{}{}",
            self.seed_strength,
            self.seed_realised.strength,
            pct(self.seed_realised.shape_error, 1),
            c.realised.strength,
            pct(c.realised.shape_error, 2),
            n[0],
            n[1],
            self.evaluations,
            c.least_normal,
            if c.poor { ", POOR" } else { "" },
            if c.notes.is_empty() {
                String::new()
            } else {
                format!(" ({})", c.notes.join("; "))
            }
        )
    }

    /// [`Synthesis::summary`] followed by the run time, for printed
    /// summaries only.
    pub fn timed_summary(&self) -> String {
        format!("{} ({:.1} s)", self.summary(), self.seconds)
    }
}

/// Synthesizes one six-signal motion for `field` over `region` (the full
/// grid) within `limits`, with the physics of `settings`.
///
/// # Errors
/// Invalid limits (naming `shaker.*`), region or options; limits that
/// cannot move parts (no slip, or no allowed axis shapes the field).
pub fn synthesize(
    field: &FieldSpec,
    region: &Grid,
    limits: &ShakerLimits,
    settings: &FieldSettings,
    options: &SynthOptions,
) -> Result<Synthesis> {
    synthesize_judged(field, region, limits, settings, options, &[])
}

/// Synthesizes one six-signal motion for several part classes at once,
/// each class's field under its own physics (sorting by friction,
/// [`crate::design::sort`]): the objective is the worst class's
/// (`Objective::with_classes`: the weakest strength, the worst shape, the
/// contact margin at every class's friction), the solver the same.
/// The seed, the calibration and the reported check are those of the first
/// class; callers re-simulate the motion at every class's friction.
///
/// # Errors
/// No classes; those of [`synthesize`].
pub(crate) fn synthesize_classes(
    classes: &[(FieldSpec, FieldSettings)],
    region: &Grid,
    limits: &ShakerLimits,
    options: &SynthOptions,
) -> Result<Synthesis> {
    let (field, settings) = classes
        .first()
        .ok_or_else(|| Error::invalid("classes", "at least one class to synthesize for"))?;
    synthesize_judged(field, region, limits, settings, options, classes)
}

/// [`synthesize`], judged over `classes` when there are any
/// ([`synthesize_classes`]).
fn synthesize_judged(
    field: &FieldSpec,
    region: &Grid,
    limits: &ShakerLimits,
    settings: &FieldSettings,
    options: &SynthOptions,
    classes: &[(FieldSpec, FieldSettings)],
) -> Result<Synthesis> {
    let start = Instant::now();
    limits.validate("shaker")?;
    region.validate("region")?;
    options.validate()?;
    let seed: Seed = seed(field, region, limits, settings.friction, settings.gravity)?;
    let coarse = Grid {
        n: options.coarse,
        ..*region
    };
    let progress = Arc::new(SynthesisProgress::new(
        options.progress,
        options.max_evaluations,
    ));
    let deadline = options
        .max_seconds
        .map(|s| start + Duration::from_secs_f64(s));
    let layout = Layout::new(limits);
    // A target with uniform transport gets a second start carrying it by an
    // in-plane second harmonic ([`super::transport`]); the cost's strength
    // scale is the stronger start's.
    let transport = transport_start(&seed, limits, region, settings);
    let strength_ref = transport
        .as_ref()
        .map_or(seed.strength, |t| t.1.max(seed.strength));
    let objective = Objective::new(
        field,
        coarse,
        limits,
        settings,
        options.shape_budget,
        strength_ref,
        options.max_evaluations,
        deadline,
        &progress,
    )
    .with_stall(options.stall)
    .with_robust(options.robust)
    .with_classes(classes);
    let x0 = layout.to_vec(&seed.coefficients);
    let seed_eval = objective.evaluate(&x0);
    // Refinement starts from the phase-calibrated seed; the seed itself is
    // an extra start (Nelder–Mead is local, and the shape the full grid and
    // the played parts see is not always the coarse cost's best).
    let first = if options.calibrate {
        calibrate(&objective, &seed.coefficients, &seed_eval)
    } else {
        seed_eval.clone()
    };
    let mut extra: Vec<Vec<f64>> = if first.params == x0 {
        Vec::new()
    } else {
        vec![x0.clone()]
    };
    let mut first = first;
    if let Some((c, _)) = &transport {
        let e = objective.evaluate(&layout.to_vec(c));
        // Calibrated whatever `options.calibrate` says (which is about the
        // seed): its tilts' field comes out turned like the seed's.
        let t = scale_search(&objective, &calibrate(&objective, c, &e));
        // The better start runs first.
        if t.cost < first.cost {
            extra.push(std::mem::replace(&mut first, t).params);
        } else {
            extra.push(t.params);
        }
    }
    objective.restart_stall();
    // The residuals' strength scale is what the run starts from: the
    // start's realised coarse strength ([`super::objective`]).
    let s0 = first.realised.strength;
    let objective = if s0.is_finite() && s0 > 0.0 {
        objective.with_goal(s0)
    } else {
        objective
    };
    let best = match &options.lm {
        Some(lm) => least_squares(&objective, &first.params, lm)?,
        None => search(
            &objective,
            &first.params,
            &extra,
            options.max_evaluations,
            &options.multistart,
            &progress,
        )?,
    };
    progress.finish();
    let coefficients = objective.motion(&best.params).0;
    let mut seed_notes = seed.notes.clone();
    if seed.fit.residual > 0.01 {
        seed_notes.push(format!(
            "the target is not affine: its best affine fit leaves {:.1} % (the seed's mechanism reaches affine fields only)",
            100.0 * seed.fit.residual
        ));
    }
    let mut checked = Checked::of(field, region, limits, settings, &coefficients, &seed_notes);
    // Least-squares runs only: a motion below the contact margin on the full
    // grid is scaled to it, and the scaled motion kept when it holds the
    // margin and is not POOR.
    let (g, floor) = (settings.gravity, limits.contact_margin * settings.gravity);
    let scaled = options
        .lm
        .and_then(|_| margin_scaled(&coefficients, checked.least_normal, floor, g));
    if let Some(c) = scaled {
        let repaired = Checked::of(field, region, limits, settings, &c, &seed_notes);
        if repaired.least_normal >= floor && !repaired.poor {
            checked = repaired;
        }
    }
    Ok(Synthesis {
        checked,
        coarse: best.realised,
        seed_realised: seed_eval.realised,
        seed_strength: seed.strength,
        evaluations: objective.evaluations(),
        seconds: start.elapsed().as_secs_f64(),
        seed_notes,
    })
}

/// The motion `coefficients`, whose least normal force per unit mass on
/// the full grid is `least_normal`, with its normal-force signals (a_z,
/// α_x, α_y: [`super::calibrate::NORMAL_AXES`]) scaled down so the full
/// grid keeps the contact margin `floor` = m g, when only the coarse grid
/// did: N − g is linear in them (module documentation), so scaling them by
/// f = 0.995 (1 − m) g / (g − N_min) lifts the least N to the margin. The
/// least-squares refinement ends on the coarse margin's edge, where the
/// full grid's steady orbits can dip below it (a few thousandths of g).
/// `None` when the margin holds (or N_min ≥ g).
fn margin_scaled(
    coefficients: &Coefficients,
    least_normal: f64,
    floor: f64,
    g: f64,
) -> Option<Coefficients> {
    let swing = g - least_normal;
    if least_normal >= floor || swing <= 0.0 {
        return None;
    }
    let f = (0.995 * (g - floor) / swing).clamp(0.0, 1.0);
    let mut c = coefficients.clone();
    for a in super::calibrate::NORMAL_AXES {
        for cs in &mut c.c[a] {
            *cs = [cs[0] * f, cs[1] * f];
        }
    }
    Some(c)
}

/// The full-grid checks of one motion ([`Checked::of`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Checked {
    /// The motion (scene `signals` format).
    pub motion: Signals,
    /// Its steady-state velocity field on the full grid.
    pub field: Field,
    /// Realised strength and shape error on the full grid.
    pub realised: Realised,
    /// Per-axis peaks against limits.
    pub peaks: Vec<AxisPeak>,
    /// Least normal force per unit mass over the region (m/s²): the
    /// smaller of the kinematic check and the simulated steady orbits.
    pub least_normal: f64,
    /// POOR: shape error above `POOR_SHAPE_ERROR`, no positive strength,
    /// invalid samples, contact margin or a limit broken.
    pub poor: bool,
    /// `seed_notes`, then why it is poor.
    pub notes: Vec<String>,
}

impl Checked {
    /// Checks `coefficients` before they are reported: the field
    /// re-simulated on the full grid `region`, the realised measure against
    /// `field`, the least N over the region (kinematic and along the
    /// simulated steady orbits), the peaks against `limits`; POOR when a
    /// check fails. `seed_notes` lead the notes.
    pub(crate) fn of(
        field: &FieldSpec,
        region: &Grid,
        limits: &ShakerLimits,
        settings: &FieldSettings,
        coefficients: &Coefficients,
        seed_notes: &[String],
    ) -> Checked {
        let motion = coefficients.to_signals();
        let m = Motion::Signals(motion.clone());
        let full = Field::compute(&m, region, FieldKind::Velocity, settings, &|| {});
        let target: Vec<[f64; 2]> = region.points().iter().map(|p| field.eval(*p)).collect();
        let r = realised(&full, &target);
        let least_normal = kinematic_least_normal(&m, region, settings)
            .min(orbit_least_normal(&m, region, settings));
        let peaks: Vec<AxisPeak> = coefficients
            .peaks()
            .iter()
            .zip(limits.axes())
            .zip(AXIS_NAMES)
            .map(|((p, l), a)| AxisPeak {
                axis: a,
                peak: *p,
                limit: l,
            })
            .collect();
        let mut notes = seed_notes.to_vec();
        let moves = r.strength > 0.0;
        if !moves {
            notes.push(
                "no positive strength: the motion does not move parts the target's way".into(),
            );
        }
        // (Not finite where the strength is not positive: said above.)
        if r.shape_error > POOR_SHAPE_ERROR && r.shape_error.is_finite() {
            notes.push(format!(
                "shape error {:.1} % > {:.0} %",
                100.0 * r.shape_error,
                100.0 * POOR_SHAPE_ERROR
            ));
        }
        if r.invalid > 0 {
            notes.push(format!(
                "{} of {} samples invalid (contact lost or not converged)",
                r.invalid,
                full.grid.len()
            ));
        }
        if least_normal < limits.contact_margin * settings.gravity {
            notes.push(format!(
                "contact margin broken: least N = {:.3} m/s² < {} g",
                least_normal, limits.contact_margin
            ));
        }
        let over = peaks
            .iter()
            .any(|p| p.peak > p.limit * (1.0 + PEAK_TOL) + f64::MIN_POSITIVE);
        if over {
            notes.push("a peak exceeds its limit".into());
        }
        let poor = !moves
            || r.shape_error > POOR_SHAPE_ERROR
            || r.invalid > 0
            || least_normal < limits.contact_margin * settings.gravity
            || over;
        Checked {
            motion,
            field: full,
            realised: r,
            peaks,
            least_normal,
            poor,
            notes,
        }
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `synth::synthesize::synthesize_classes`.
    #[test]
    fn example_synthesize_classes() -> Result<(), crate::Error> {
        use crate::dynamics::Friction;
        use crate::field::{FieldSettings, Grid};
        use crate::request::FieldSpec;
        use crate::synth::{synthesize_classes, ShakerLimits, SynthOptions};

        let at = |mu: f64| FieldSettings {
            friction: Friction::uniform(mu),
            ..FieldSettings::default()
        };
        let sink = |x: f64| FieldSpec::Sink {
            center: [x, 0.0],
            strength: 1.0,
        };
        let region = Grid {
            x: [-0.02, 0.02],
            y: [-0.01, 0.01],
            n: [5, 3],
        };
        let options = SynthOptions {
            coarse: [3, 3],
            max_evaluations: 4,
            lm: None,
            progress: crate::progress::ProgressMode::Quiet,
            ..SynthOptions::default()
        };
        let classes = [(sink(-0.01), at(0.2)), (sink(0.01), at(0.45))];
        let s = synthesize_classes(&classes, &region, &ShakerLimits::default(), &options)?;
        assert!(s.evaluations <= 6);
        Ok(())
    }
}
