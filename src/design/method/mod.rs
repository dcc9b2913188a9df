//! `platefield design --method sequence|synthesize|auto|mix`: which kind of
//! plate motion realises a target, decided by playing it.
//!
//! * `sequence`: the time-shared schedule of primitives ([`super::design`]).
//!   When the target gives `shaker` limits, basis columns whose per-axis
//!   peak exceeds a limit are left out (listed with the reason
//!   `over the shaker limit`), so the schedule keeps them.
//! * `synthesize`: one simultaneous six-signal motion within the target's
//!   limits ([`crate::synth::synthesize`]; `shaker` keys left out take the
//!   paper's envelope), written as a one-segment schedule holding the
//!   signals, `SYNTH_SEGMENT_CYCLES` cycles per schedule period (one
//!   motion repeated: the count only sets the measuring windows).
//! * `mix` (`mix_design`): the sequenced design's basis plus one column,
//!   a synthesized motion, so the conic fit can mix it with primitives where
//!   neither reaches the target alone; its segment ramps in and out of rest
//!   inside its cycles (`crate::design::basis::ColumnSource::segment`).
//!   When the fit leaves the column out, the mix is the sequenced design
//!   again and is reported as such, not played twice.
//! * `auto` (the CLI's default): both, and the better **realised** one is
//!   kept; when both are POOR, the mix too, and the best of the three. Both play on the same shaker: when the target gives no `shaker`,
//!   the synthesis keeps the per-axis peaks and the period of the sequenced
//!   schedule ([`sequenced_limits`]; harmonics and contact margin from the
//!   envelope), not the envelope itself — the envelope is the per-axis
//!   maximum over all eight primitives, far more than any one of them uses
//!   at once, and a motion that uses all of it at once is too strong for its
//!   steady-state field to describe what moving parts do (the sink
//!   synthesized within the envelope realises a field far from its
//!   prediction, in strength and in shape). When the synthesis within
//!   those peaks plays POOR (or fails), the peaks are shown to be no shaker
//!   for the target — a sequenced fit of near-cancelling columns may drive
//!   one tilt axis only and leave the other at zero — and `auto`
//!   synthesizes again within the envelope ([`Variant::Envelope`]), judged
//!   beside the others by the same rule. **Over a friction range** the
//!   synthesis takes the envelope instead: a part slips with the lead
//!   δ = asin(μg/A) behind the plate's in-plane acceleration amplitude A, so
//!   a change of μ turns the field by dδ = g dμ / (A cos δ), less the
//!   stronger the drive; the envelope's A (45.3 m/s²) against a sequenced
//!   schedule's peaks (often 11–23 m/s²) halves or quarters the turn the
//!   range causes, which is what a robust design has to cancel (on the
//!   family's sink_4, listed in `results/robust_family.md`, that is the
//!   difference between missing the range and holding it). It is not
//!   better for every target: a motion that strong is further from what
//!   its steady-state field describes (on the family's off-centre line
//!   sink line_sink_0 the sequenced peaks hold the range and the envelope
//!   does not). So when no candidate within the
//!   envelope holds the range within `RANGE_HELD`, `auto` synthesizes
//!   again within the sequenced peaks, with the mirror-image shares
//!   ([`Variant::SequencedPeaks`]), and the rule chooses between the two
//!   shakers' candidates. If none holds it still, or those that hold it
//!   are weaker than half the first synthesized motion (what the wider
//!   margin below is expected to keep; the rule keeps the stronger of two
//!   that hold), `auto` trades strength for shape: the synthesis and its
//!   shares again within the envelope
//!   with the contact margin raised halfway to g
//!   ([`Variant::Gentle`], `gentle_limits`: 0.1 → 0.55). The averaged
//!   model the synthesis is seeded from ([`crate::synth`]: v =
//!   (W/g)(Q_N, P_N)) is first order in the normal force's swing N − g,
//!   and a target with a gradient (a sink, saddle, line sink, whirlpool)
//!   takes that gradient from the tilts, whose swing the margin caps at
//!   (1 − m) g at the region's corners; the synthesis drives them to the
//!   cap. Where N swings from 0.1 g to 1.9 g the parts' slip is far from
//!   the uniform one the model assumes, and the field bends away from the
//!   affine target by more than any friction turn (on the family's
//!   whirlpool_2 the worst shape over the range falls as the margin rises
//!   toward halfway, while it barely changes with friction at any one
//!   margin: the swing, not the friction, bounds it). Halfway halves the
//!   strength (the margin's cap is proportional to 1 − m) and about halves
//!   the part of the error the swing makes; beyond it the rest remains and
//!   only strength is lost. It is made only when the first
//!   synthesis swings N past the raised margin (else the same limits bind
//!   the same motion). If none holds it still, one more motion is
//!   synthesized for the worst case ([`Variant::WorstCase`]). When the
//!   target states the shaker's tolerance, the candidate the rule keeps is
//!   judged over the delivery errors as well, at its worst friction; a
//!   synthesized one whose worst there misses 6 % is weighed against the
//!   wider-margin candidates judged the same way, by the rule applied to
//!   the worst over the draws ([`Choice::Delivered`]):
//!   a delivery error scales the tilts' swing of the normal force by up to
//!   1 + a, past the margin the synthesis drove it to. The kept
//!   candidate's limits are recorded in `schedule.json`. The rule: the
//!   lower realised shape error wins; when the two are within
//!   [`TIE_SHAPE_ERROR`] (one percentage point) of each other, the higher
//!   realised strength wins. Over a friction range, a candidate that holds
//!   the target within `RANGE_HELD` (6 %) at its worst beats one that
//!   does not first, and of two that both hold it the stronger at its
//!   worst wins (`better_within`, which states why). A POOR candidate
//!   (see below) loses to one that is not POOR. If one method fails (e.g.
//!   limits too small to move parts), the other is kept and the failure
//!   is stated.
//!
//! **Every design is judged before it is reported** (`play_check`): the
//! schedule is played by [`super::judge`] — the realised field at frozen
//! points over the whole region the target asks for, whole periods, joins
//! and ramps included — and compared with the target: realised strength ŝ
//! (the least-squares scale of the realised field on the target),
//! realised shape error ‖R − ŝt‖/‖ŝt‖ and the error against the predicted
//! strength. Over a friction range the target states, every candidate is
//! judged across it and its played numbers are the worst case, with the
//! friction where it falls ([`crate::schedule::Played::worst_friction`]).
//! It is POOR when the realised shape error (at its worst) exceeds
//! [`crate::fit::POOR_ERROR`], when a part loses contact at a point of the
//! region, or when too few points count.

pub use super::judge::judge_check;
use super::judge::{judge_points, realised_check, PointPlay, RealisedError, JUDGE_MIN_PERIODS};
use super::polish::{polish, PolishOptions};
pub(crate) use super::rule::better_within;
pub use super::rule::{Rule, MIN_MEASURED_POINTS, TIE_SHAPE_ERROR};
use super::{design, Design, DesignOptions};
use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::field::FieldKind;
use crate::field::Grid;
use crate::fit::{self, FitMetrics};
use crate::motion::Signals;
use crate::play::sensitivity::{self, FrictionRow, Sensitivity, Span};
use crate::request::{SampledTarget, Target};
use crate::schedule::export::schedule_peaks;
pub use crate::schedule::Method;
use crate::schedule::{AxisPeaks, BasisInfo, Played, Schedule, Segment, SolverInfo};
use crate::synth::levenberg::LmOptions;
use crate::synth::{synthesize, ShakerLimits, SynthOptions, Synthesis};
use crate::work::{Estimate, Term};
use std::time::Instant;

mod choice;
mod estimate;
mod mix;
mod played;
mod synthesized;

pub use choice::number;
pub use choice::percent;
pub use choice::worst_at;
pub(crate) use choice::Failure;
pub(crate) use choice::RANGE_HELD;
use choice::{choose, held, key};
pub use choice::{Choice, FailureReason};
use estimate::region;
pub use estimate::{design_estimate, synthesis_estimate};
pub(crate) use estimate::{sequenced_cycles, sweep_estimate};
pub(crate) use mix::{mix_design, mixable};
use played::polish_played;
pub(crate) use played::{play_check, played_of};
use synthesized::resolving;
pub use synthesized::sequenced_limits;
pub(crate) use synthesized::synthesize_schedule;

/// Cycles of the synthesized motion per schedule period.
pub(crate) const SYNTH_SEGMENT_CYCLES: u32 = 10;

/// One designed and played candidate.
#[derive(Debug, Clone)]
pub struct Candidate {
    /// `sequence` or `synthesize`.
    pub method: Method,
    /// The schedule (its [`Schedule::played`] filled in).
    pub schedule: Schedule,
    /// Seconds to design it (not in any data file).
    pub design_s: f64,
    /// Seconds to play it.
    pub play_s: f64,
    /// Its judge over the friction range the target states
    /// (`None` for an exact friction): what `auto` judges it by.
    pub sensitivity: Option<Sensitivity>,
    /// Which synthesis it comes from, when `auto` adds one over a
    /// friction range.
    pub variant: Variant,
}

/// Which synthesis a candidate comes from: `auto` adds up to three over a
/// friction range when no candidate before holds the target within
/// `RANGE_HELD` at its worst, and at one friction one within the envelope
/// when the synthesis within the sequenced peaks plays POOR (module
/// documentation).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Variant {
    /// Its method's own design.
    First,
    /// Synthesized (and mirror-shared) within the sequenced schedule's
    /// per-axis peaks instead of the envelope: a weaker drive, nearer what
    /// its steady-state field describes.
    SequencedPeaks,
    /// Synthesized (and mirror-shared) within the kept limits with the
    /// contact margin raised halfway to g (`gentle_limits`): tilts
    /// that swing the normal force half as far, half the strength, nearer
    /// what the averaged model describes.
    Gentle,
    /// One motion synthesized and polished for the worst case over the
    /// range (as `--robust-synthesis` does).
    WorstCase,
    /// At one friction, synthesized within the envelope after the
    /// synthesis within the sequenced schedule's peaks played POOR or
    /// failed.
    Envelope,
}

impl Candidate {
    /// `schedule` (designed in `design_s` seconds) played by
    /// [`play_check`]: `predicted` is its predicted strength, `asked` the
    /// method asked for with the limits to record.
    fn play(
        (target, sampled): (&Target, &SampledTarget),
        mut schedule: Schedule,
        predicted: f64,
        (asked, limits): (Method, Option<crate::request::ShakerSpec>),
        design_s: f64,
    ) -> Result<Candidate> {
        let t = Instant::now();
        let p = play_check(target, sampled, &schedule, predicted, asked, limits)?;
        let method = p.method;
        schedule.played = Some(p);
        Ok(Candidate {
            method,
            schedule,
            design_s,
            play_s: t.elapsed().as_secs_f64(),
            sensitivity: None,
            variant: Variant::First,
        })
    }

    /// Judged across the friction range the target states
    /// ([`candidate_sensitivity`]): its played measure becomes the worst
    /// case ([`Played::worst_friction`]), POOR when that is.
    fn judge_range(&mut self, target: &Target, sampled: &SampledTarget) -> Result<()> {
        self.sensitivity = candidate_sensitivity(target, sampled, &self.schedule)?;
        let (Some(s), Some(p)) = (&self.sensitivity, self.schedule.played.as_mut()) else {
            return Ok(());
        };
        if let Some(row) = s.worst_row() {
            p.realised_strength = row.realised_strength;
            p.realised_shape_error = row.realised_shape_error;
            p.worst_friction = Some(row.friction);
            let shape = row.realised_shape_error.unwrap_or(f64::INFINITY);
            if shape > fit::POOR_ERROR {
                p.poor = true;
                p.notes.push(format!(
                    "worst over the friction range: realised shape error {} > {:.0} % at μ_s {}, μ_k {}",
                    percent(row.realised_shape_error),
                    100.0 * fit::POOR_ERROR,
                    row.friction.stat,
                    row.friction.kinetic
                ));
            }
        }
        Ok(())
    }

    /// Its name in reports: the method's, marked by its
    /// [`Candidate::variant`].
    pub fn name(&self) -> String {
        let tag = match self.variant {
            Variant::First => "",
            Variant::SequencedPeaks => " (within the sequenced peaks)",
            Variant::Gentle => " (within the wider contact margin)",
            Variant::WorstCase => " (for the worst case)",
            Variant::Envelope => " (within the envelope)",
        };
        format!("{}{tag}", self.method.name())
    }

    /// The judge.
    pub fn played(&self) -> &Played {
        self.schedule
            .played
            .as_ref()
            .expect("a candidate is always played")
    }
}

/// Fraction of the normal force's allowed swing (1 − m) g that the
/// [`Variant::Gentle`] synthesis keeps: half (module documentation).
pub const GENTLE_SWING: f64 = 0.5;

/// `limits` with the contact margin m raised so that the normal force may
/// swing [`GENTLE_SWING`] of what m allows: m′ = 1 − (1 − m) / 2, halfway
/// to g (0.1 → 0.55). A synthesis whose strength the margin binds keeps
/// half of it (the seed's cap is (1 − m) g over the tilts' swing per unit
/// strength, [`crate::synth::seed`]) and swings N half as far, which is
/// what the averaged model's error grows with (module documentation).
pub(crate) fn gentle_limits(limits: &ShakerLimits) -> ShakerLimits {
    ShakerLimits {
        contact_margin: 1.0 - GENTLE_SWING * (1.0 - limits.contact_margin),
        ..limits.clone()
    }
}

/// The design by method: what [`crate::inverse::run`] returns for a target
/// designed by [`DesignOptions::method`].
#[derive(Debug, Clone)]
pub struct MethodDesign {
    /// The method asked for.
    pub asked: Method,
    /// The sequenced design (when run and successful).
    pub sequence: Option<Design>,
    /// The synthesis (when run and successful).
    pub synthesis: Option<Synthesis>,
    /// The synthesis' schedule within [`MethodDesign::limits`] (when run
    /// and successful): a candidate under `synthesize` and `auto`; under
    /// `mirror`, the motion its shares are built from, itself not played.
    pub synthesized: Option<Schedule>,
    /// The mixed design (when run and successful): primitives and a
    /// synthesized motion in one fit.
    pub mixed: Option<Design>,
    /// The candidates played (sequence first).
    pub candidates: Vec<Candidate>,
    /// Index of the kept candidate.
    pub chosen: usize,
    /// Why it was kept ([`MethodDesign::why`] words it).
    pub choice: Choice,
    /// Methods that failed, with the reason.
    pub failures: Vec<Failure>,
    /// The limits a synthesis keeps.
    pub limits: ShakerLimits,
    /// The kept design played across the friction the target states
    /// (`sensitivity::of_target`; `None` when it states none).
    pub sensitivity: Option<Sensitivity>,
    /// The work stated before the synthesis ([`design_estimate`] with the
    /// limits the synthesis keeps; `auto` states it once the sequenced
    /// schedule is fitted and has given them, before that schedule is
    /// judged, its judge counted at the fitted period), and that of each
    /// synthesis `auto` adds ([`Variant`]), stated when it starts.
    pub estimate: Estimate,
    /// The kept design judged over the shaker's delivery errors at its
    /// worst friction, when the target states `shaker.tolerance`
    /// ([`super::tolerance`]).
    pub tolerance: Option<super::tolerance::Spread>,
    /// The candidates judged over the shaker's delivery errors to choose
    /// between them (by index; `MethodRun::delivery_synthesis`).
    pub delivered: Vec<(usize, super::tolerance::Spread)>,
    /// The worst-case shape error a candidate had to hold over the
    /// friction range to beat those that do not (`RANGE_HELD` when the
    /// target states a range, `better_within`).
    pub bound: Option<f64>,
}

impl MethodDesign {
    /// The kept candidate.
    pub fn kept(&self) -> &Candidate {
        &self.candidates[self.chosen]
    }
}

/// Designs `target` by [`DesignOptions::method`] with
/// [`DesignOptions::synthesis`] (see the [module documentation](self)),
/// plays every candidate and keeps one; [`crate::inverse::run`] is its public door.
/// The stages, in order: the work refused up front
/// (`MethodRun::start`), the sequenced candidate, the synthesized one
/// (and its mirror-image shares), the mix, the judgement across the
/// target's friction range, the syntheses added when no candidate holds
/// it ([`Variant`]), and the choice (`MethodRun::finish`).
///
/// # Errors
/// Invalid options; every method asked for failing (the first error).
pub fn design_by_method(target: &Target, opts: &DesignOptions) -> Result<MethodDesign> {
    let opts = &opts.for_target(target);
    opts.validate()?;
    let sampled = target.sample()?;
    let mut run = MethodRun::start(target, &sampled, opts)?;
    run.sequence()?;
    run.synthesis()?;
    run.envelope_synthesis()?;
    run.mix()?;
    run.judge_range()?;
    run.sequenced_peaks_synthesis()?;
    run.gentle_synthesis()?;
    run.worst_case_synthesis()?;
    run.delivery_synthesis()?;
    let mut out = run.finish()?;
    if out.tolerance.is_none() {
        out.tolerance = tolerance_spread(target, &sampled, &out.kept().schedule, opts)?;
    }
    Ok(out)
}

/// The kept design judged over the shaker's delivery errors when the
/// target states `shaker.tolerance` ([`super::tolerance`]):
/// [`DEFAULT_DRAWS`](super::tolerance::DEFAULT_DRAWS) draws at the
/// friction of its worst case over the target's range (its own without
/// one), the work stated first.
fn tolerance_spread(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
    opts: &DesignOptions,
) -> Result<Option<super::tolerance::Spread>> {
    use super::tolerance::{judged_at, spread, spread_estimate, DEFAULT_DRAWS};
    let Some(tol) = target.shaker.as_ref().and_then(|s| s.tolerance) else {
        return Ok(None);
    };
    opts.runtime
        .admit(&spread_estimate(target, sampled, schedule, DEFAULT_DRAWS))?;
    let physics = judged_at(schedule, &schedule.settings, None);
    spread(target, sampled, schedule, &physics, (&tol, DEFAULT_DRAWS)).map(Some)
}

/// One [`design_by_method`] under way: the target, its options, the
/// design so far and what the later stages need to know of the earlier.
struct MethodRun<'a> {
    target: &'a Target,
    sampled: &'a SampledTarget,
    opts: &'a DesignOptions,
    /// The cold basis library's work, when it is to be built.
    library: Option<Estimate>,
    /// The design so far; its `limits` are those the synthesis keeps.
    out: MethodDesign,
    /// The sequenced design's error under `auto`, returned when nothing
    /// else designs.
    first_error: Option<Error>,
    /// The synthesis keeps the sequenced schedule's peaks (`auto` without
    /// the target's own limits).
    from_sequence: bool,
    /// The envelope the sequenced schedule's peaks replaced, for the
    /// synthesis within it when the one within those peaks plays POOR
    /// ([`MethodRun::envelope_synthesis`]).
    envelope: Option<ShakerLimits>,
    /// The target's symmetry line, searched once when the mirror-image
    /// shares are offered (`None` when they are not; `Some(None)` when no
    /// reflection maps the target to itself).
    axis: Option<Option<super::mirror::MirrorLine>>,
    /// The sequenced schedule's per-axis peaks as limits, under `auto`
    /// over a friction range without the target's own limits
    /// ([`MethodRun::sequenced_peaks_synthesis`]).
    sequenced: Option<ShakerLimits>,
    /// The syntheses `auto` adds over a friction range, with their limits:
    /// the design's synthesis and limits if one of their candidates is kept.
    added: Vec<(Variant, Synthesis, ShakerLimits)>,
    /// The candidate kept for its worst case over the shaker's delivery
    /// errors, and the one the rule over friction alone keeps
    /// ([`MethodRun::delivery_synthesis`]).
    delivered_pick: Option<(usize, usize)>,
    /// The fitted sequenced schedule's cycles per period, once known
    /// ([`MethodRun::restate`]).
    fitted_cycles: Option<u32>,
    /// Whether the work was stated once the sequenced schedule was fitted.
    announced: bool,
}

/// How many times the count stated before the sequenced fit its work must
/// exceed for `sequence` to state it again ([`MethodRun::restate`]): the
/// accuracy `tests/estimates.rs` holds the estimates to, so a restated
/// estimate is one the first would have failed.
const RESTATE_FACTOR: f64 = 3.0;

impl<'a> MethodRun<'a> {
    /// The run's start: the target's limits checked and the work refused
    /// up front on them (those of `auto`'s synthesis come from the
    /// sequenced schedule, within them), the library's own refusal first
    /// (as the basis stage words it).
    fn start(
        target: &'a Target,
        sampled: &'a SampledTarget,
        opts: &'a DesignOptions,
    ) -> Result<MethodRun<'a>> {
        let method = opts.method;
        let limits = ShakerLimits::from_spec(target.shaker.as_ref());
        limits.validate("target.shaker")?;
        let library = super::stages::cold_library_estimate(target, sampled, opts);
        if let Some(library) = &library {
            opts.runtime.check(library)?;
        }
        let estimate = design_estimate(
            target,
            sampled,
            &asked_synthesis(target, opts),
            opts,
            method,
            &limits,
            library.clone(),
            None,
        );
        opts.runtime.check(&estimate)?;
        if method != Method::Auto {
            estimate.announce(opts.runtime.progress());
        }
        Ok(MethodRun {
            target,
            sampled,
            opts,
            library,
            out: MethodDesign {
                asked: method,
                sequence: None,
                synthesis: None,
                synthesized: None,
                mixed: None,
                candidates: Vec::new(),
                chosen: 0,
                choice: Choice::Asked(method),
                failures: Vec::new(),
                limits,
                sensitivity: None,
                estimate,
                tolerance: None,
                delivered: Vec::new(),
                bound: None,
            },
            first_error: None,
            from_sequence: false,
            envelope: None,
            axis: None,
            sequenced: None,
            added: Vec::new(),
            delivered_pick: None,
            fitted_cycles: None,
            announced: false,
        })
    }

    /// The work of the design with the limits the synthesis keeps now
    /// ([`design_estimate`]; `auto` states it once the sequenced schedule
    /// has given them).
    fn estimate(&self) -> Estimate {
        design_estimate(
            self.target,
            self.sampled,
            &asked_synthesis(self.target, self.opts),
            self.opts,
            self.opts.method,
            &self.out.limits,
            self.library.clone(),
            self.fitted_cycles,
        )
    }

    /// States the design's work again (and refuses it past the limit
    /// without `--allow-long`) once the sequenced schedule is fitted and
    /// its judges' cycles are known: first under `auto` (whose synthesis
    /// limits come from that schedule), and under `sequence` when the fit's
    /// period makes the work more than [`RESTATE_FACTOR`] times the count
    /// stated before it.
    fn restate(&mut self, fitted: &Schedule) -> Result<()> {
        let before = self.out.estimate.steps();
        self.fitted_cycles = Some(crate::design::judge::judged_cycles(fitted));
        let now = self.estimate();
        let method = self.opts.method;
        if method == Method::Auto || now.steps() > RESTATE_FACTOR * before {
            self.opts.runtime.check(&now)?;
            now.announce(self.opts.runtime.progress());
            self.announced = true;
        }
        self.out.estimate = now;
        Ok(())
    }

    /// A candidate of `schedule` (predicted strength `predicted`, the
    /// limits to record `limits`), set to the model the options play
    /// ([`DesignOptions::model`]: under `auto` its rung chosen here, the
    /// choice's time counted in the design's) and played; designed in
    /// `design_s` seconds.
    fn play(
        &self,
        schedule: Schedule,
        predicted: f64,
        limits: Option<crate::request::ShakerSpec>,
        design_s: f64,
    ) -> Result<Candidate> {
        let t = Instant::now();
        let schedule = self.opts.model.apply(schedule);
        let design_s = design_s + t.elapsed().as_secs_f64();
        Candidate::play(
            (self.target, self.sampled),
            schedule,
            predicted,
            (self.opts.method, limits),
            design_s,
        )
    }

    /// The limits a primitive design records: the limits kept, when the
    /// target gives its own.
    fn recorded_limits(&self) -> Option<crate::request::ShakerSpec> {
        self.target
            .shaker
            .as_ref()
            .map(|_| self.out.limits.to_spec())
    }

    /// The sequenced candidate (`sequence`, `auto`). Bad input or a
    /// refused long run (exit 2) ends `auto` too: only a design that is
    /// physically impossible or did not converge hands over to the
    /// synthesis.
    fn sequence(&mut self) -> Result<()> {
        let method = self.opts.method;
        if !matches!(method, Method::Sequence | Method::Auto) {
            return Ok(());
        }
        let t = Instant::now();
        match design(self.target, self.opts) {
            Ok(d) => {
                let design_s = t.elapsed().as_secs_f64();
                // Without the target's own limits, the synthesis gets the
                // shaker that plays the sequenced schedule (the envelope if
                // that schedule has no moving primitive to take peaks from),
                // except over a friction range (module docs).
                if method == Method::Auto && self.target.shaker.is_none() {
                    if let Ok(l) = sequenced_limits(&d.schedule, &self.out.limits) {
                        if self.ranged() {
                            self.sequenced = Some(l);
                        } else {
                            self.envelope = Some(std::mem::replace(&mut self.out.limits, l));
                            self.from_sequence = true;
                        }
                    }
                }
                self.restate(&d.schedule)?;
                let record = self.recorded_limits();
                let c = self.play(
                    d.schedule.clone(),
                    d.schedule.fit.strength,
                    record,
                    design_s,
                )?;
                self.out.candidates.push(c);
                self.out.sequence = Some(d);
            }
            Err(e) if method == Method::Auto && !matches!(e, Error::Invalid { .. }) => {
                self.out.failures.push(Failure::new(
                    Method::Sequence,
                    FailureReason::Error(e.to_string()),
                ));
                self.first_error = Some(e);
            }
            Err(e) => return Err(e),
        }
        Ok(())
    }

    /// The synthesized candidate (`synthesize`, `auto`, `mirror`) and the
    /// mirror-image time-share: asked for, or under `auto` when the target
    /// states a friction range. About the target's symmetry axis where it
    /// has one; for a target no reflection maps to itself, the
    /// counter-rotating share (`super::mirror::counter_share`: one more
    /// synthesis, for the target's mirror image).
    fn synthesis(&mut self) -> Result<()> {
        let method = self.opts.method;
        if method == Method::Auto && !self.announced {
            self.out.estimate = self.estimate();
            self.out.estimate.announce(self.opts.runtime.progress());
        }
        if !matches!(method, Method::Synthesize | Method::Auto | Method::Mirror) {
            return Ok(());
        }
        self.axis = (method == Method::Mirror || (method == Method::Auto && self.ranged()))
            .then(|| super::mirror::mirror_axis(self.target, self.sampled));
        let limits = self.out.limits.clone();
        match self.synthesized_with_shares(&limits) {
            Ok((syn, schedule, cands)) => {
                self.out.candidates.extend(cands);
                self.out.synthesis = Some(syn);
                self.out.synthesized = Some(schedule);
            }
            Err(e) if method == Method::Auto && !self.out.candidates.is_empty() => {
                let reason = if self.from_sequence {
                    FailureReason::WithinSequencedPeaks(e.to_string())
                } else {
                    FailureReason::Error(e.to_string())
                };
                self.out
                    .failures
                    .push(Failure::new(Method::Synthesize, reason));
            }
            Err(e) => return Err(self.first_error.take().unwrap_or(e)),
        }
        Ok(())
    }

    /// The synthesized candidate within `limits` and, when the mirror-image
    /// shares are offered ([`MethodRun::axis`]), its shares (first); the
    /// synthesized motion alone is not a candidate of `mirror`, which
    /// therefore does not play it.
    fn synthesized_with_shares(
        &self,
        limits: &ShakerLimits,
    ) -> Result<(Synthesis, Schedule, Vec<Candidate>)> {
        let t = Instant::now();
        let (syn, schedule) = synthesize_schedule(
            self.target,
            self.sampled,
            limits,
            self.opts,
            &asked_synthesis(self.target, self.opts),
        )?;
        let design_s = t.elapsed().as_secs_f64();
        let mut cands = Vec::new();
        if let Some(axis) = &self.axis {
            let t = Instant::now();
            for share in self.mirror_shares(&schedule, axis.as_ref(), limits)? {
                cands.push(self.play(
                    share,
                    syn.checked.realised.strength,
                    Some(limits.to_spec()),
                    design_s + t.elapsed().as_secs_f64(),
                )?);
            }
        }
        if self.opts.method != Method::Mirror {
            cands.push(self.synthesized(&syn, schedule.clone(), limits, design_s)?);
        }
        Ok((syn, schedule, cands))
    }

    /// The candidate of the synthesized `schedule` (`syn`'s within
    /// `limits`, designed in `design_s` seconds), played; POOR with the synthesis' notes when
    /// the synthesis says so.
    fn synthesized(
        &self,
        syn: &Synthesis,
        schedule: Schedule,
        limits: &ShakerLimits,
        design_s: f64,
    ) -> Result<Candidate> {
        let spec = Some(limits.to_spec());
        let mut c = self.play(schedule, syn.checked.realised.strength, spec, design_s)?;
        if let (true, Some(p)) = (syn.checked.poor, c.schedule.played.as_mut()) {
            p.poor = true;
            p.notes
                .extend(syn.checked.notes.iter().map(|n| format!("synthesis: {n}")));
        }
        Ok(c)
    }

    /// Over a friction range, every candidate so far played across it
    /// ([`candidate_sensitivity`]): what `auto` judges it by. A candidate
    /// already POOR at the nominal friction is not, while another is not
    /// POOR: the range's values include the nominal one, so its worst case
    /// is POOR too and it cannot be kept (the sweep of a schedule that
    /// loses contact is the longest judge there is: parts that do not
    /// settle play to the cap).
    fn judge_range(&mut self) -> Result<()> {
        if !self.ranged() {
            return Ok(());
        }
        let any_sound = self.out.candidates.iter().any(|c| !c.played().poor);
        for c in &mut self.out.candidates {
            if any_sound && c.played().poor {
                if let Some(p) = c.schedule.played.as_mut() {
                    p.notes.push(
                        "POOR at the nominal friction: not judged across the range (its worst case is POOR too)".into(),
                    );
                }
                continue;
            }
            c.judge_range(self.target, self.sampled)?;
        }
        Ok(())
    }

    /// `auto` over a friction range without the target's own limits, when
    /// no candidate holds the target within [`RANGE_HELD`] at its worst:
    /// the synthesis and its mirror-image shares again, within the
    /// sequenced schedule's per-axis peaks instead of the envelope (module
    /// documentation: a weaker drive turns more with μ but is nearer what
    /// its steady-state field describes), judged across the range beside
    /// the others. Its work is stated first; its failure is stated, not
    /// fatal.
    fn sequenced_peaks_synthesis(&mut self) -> Result<()> {
        let Some(limits) = self.sequenced.clone() else {
            return Ok(());
        };
        if held(&self.out.candidates) {
            return Ok(());
        }
        self.added_with_shares(
            limits,
            Variant::SequencedPeaks,
            FailureReason::WithinSequencedPeaks,
        )
    }

    /// `auto` at one friction, when the synthesis within the sequenced
    /// schedule's peaks plays POOR or fails: those peaks are then shown to
    /// be no shaker for the target (a sequenced fit of near-cancelling
    /// columns may drive one tilt axis only), and the synthesis is made
    /// again within the envelope they replaced ([`Variant::Envelope`]),
    /// judged beside the others by the same rule.
    fn envelope_synthesis(&mut self) -> Result<()> {
        let Some(limits) = self.envelope.clone() else {
            return Ok(());
        };
        let sound = self
            .out
            .candidates
            .iter()
            .any(|c| c.method == Method::Synthesize && !c.played().poor);
        if sound {
            return Ok(());
        }
        self.added_with_shares(limits, Variant::Envelope, FailureReason::Envelope)
    }

    /// The synthesis and its mirror-image shares again within `limits`,
    /// its work stated first, added as `variant`'s candidates; a failure
    /// is recorded as `reason`, not fatal.
    fn added_with_shares(
        &mut self,
        limits: ShakerLimits,
        variant: Variant,
        reason: fn(String) -> FailureReason,
    ) -> Result<()> {
        let synth = asked_synthesis(self.target, self.opts);
        let estimate = synthesis_estimate(self.target, self.sampled, &synth, self.opts, &limits);
        self.opts.runtime.admit(&estimate)?;
        self.out.estimate.terms.extend(estimate.terms);
        match self.synthesized_with_shares(&limits) {
            Ok((syn, _, cands)) => self.add(variant, (syn, limits), cands)?,
            Err(e) => self
                .out
                .failures
                .push(Failure::new(Method::Synthesize, reason(e.to_string()))),
        }
        Ok(())
    }

    /// `auto` over a friction range when no candidate holds the target
    /// within [`RANGE_HELD`] at its worst, or every one that holds it is
    /// weaker than [`GENTLE_SWING`] of the first synthesis' strength (what
    /// the wider margin is expected to keep, [`gentle_limits`]; the rule
    /// keeps the stronger of two that hold, so a weaker one could not
    /// win): the synthesis and its mirror-image shares again within the
    /// kept limits, the contact margin raised halfway to g (module
    /// documentation), judged across the range beside the others. Not
    /// made when the first synthesis keeps that margin already (its
    /// least normal force is at least the raised margin's): the same
    /// limits would bind the same motion. Its work is stated first; its
    /// failure is stated, not fatal.
    fn gentle_synthesis(&mut self) -> Result<()> {
        if self.opts.method != Method::Auto || !self.ranged() {
            return Ok(());
        }
        let limits = gentle_limits(&self.out.limits);
        let strongest_held = self
            .out
            .candidates
            .iter()
            .map(key)
            .filter(|&(poor, shape, _)| !poor && shape <= RANGE_HELD)
            .map(|k| k.2)
            .fold(f64::NEG_INFINITY, f64::max);
        let worth = match &self.out.synthesis {
            Some(s) => {
                self.swings_past(&limits)
                    && strongest_held < GENTLE_SWING * s.checked.realised.strength
            }
            None => !held(&self.out.candidates),
        };
        if !worth {
            return Ok(());
        }
        self.added_with_shares(limits, Variant::Gentle, FailureReason::Gentle)
    }

    /// The first synthesis drives the normal force below `limits`'
    /// contact margin (else those limits bind the same motion); `false`
    /// without a synthesis.
    fn swings_past(&self, limits: &ShakerLimits) -> bool {
        let floor = limits.contact_margin * self.opts.settings.gravity;
        self.out
            .synthesis
            .as_ref()
            .is_some_and(|s| s.checked.least_normal < floor)
    }

    /// `auto` over a friction range when the target states the shaker's
    /// tolerance (`shaker.tolerance`): the candidate the rule keeps is
    /// judged over the delivery errors at its worst friction
    /// ([`tolerance_spread`]). When it is a synthesized motion whose worst
    /// over the draws misses [`RANGE_HELD`], the synthesis and its shares
    /// within the wider contact margin ([`Variant::Gentle`]) are made (if
    /// not made already, and only when the first synthesis swings the
    /// normal force past that margin) and judged over the same draws, and
    /// the rule chooses among these and the kept one by their worst case
    /// over the draws ([`better_within`] on the worst shape error and the
    /// weakest strength over them). Why the wider margin: a delivery error
    /// scales each channel's harmonics by up to 1 ± a, so the tilts swing
    /// the normal force up to (1 + a) times as far as designed, past the
    /// margin the synthesis drove them to, where the averaged model it
    /// trusts is least right (module documentation); within half the
    /// swing they stay inside it. Measured on `targets/sink.json` over
    /// μ 0.2–0.4 with ±5 % and ±5°: `docs/shaker.md`. Each judgement's
    /// work is stated first.
    fn delivery_synthesis(&mut self) -> Result<()> {
        let Some(tol) = self.target.shaker.as_ref().and_then(|s| s.tolerance) else {
            return Ok(());
        };
        if self.opts.method != Method::Auto || !self.ranged() || self.out.candidates.is_empty() {
            return Ok(());
        }
        let bound = Some(RANGE_HELD);
        let (pick, _) = choose(&self.out.candidates, self.out.asked, bound);
        let kept = self.delivered(pick, &tol)?;
        let (worst, _, perturbed) = kept;
        if perturbed == 0
            || self.out.candidates[pick].variant == Variant::Gentle
            || worst <= RANGE_HELD
        {
            return Ok(());
        }
        if !self.added.iter().any(|(v, ..)| *v == Variant::Gentle) {
            let limits = gentle_limits(&self.out.limits);
            if !self.swings_past(&limits) {
                return Ok(());
            }
            self.added_with_shares(limits, Variant::Gentle, FailureReason::Gentle)?;
        }
        let mut best = (pick, kept);
        for i in 0..self.out.candidates.len() {
            if self.out.candidates[i].variant != Variant::Gentle
                || self.out.candidates[i].played().poor
            {
                continue;
            }
            let d = self.delivered(i, &tol)?;
            let key = |(w, s, _): (f64, f64, usize)| (false, w, s);
            if better_within(key(best.1), key(d), bound).0 {
                best = (i, d);
            }
        }
        if best.0 != pick {
            self.delivered_pick = Some((best.0, pick));
        }
        Ok(())
    }

    /// Candidate `i` over the shaker's delivery errors within `tol` at its
    /// worst friction, judged once and recorded in
    /// [`MethodDesign::delivered`]: its worst shape error, weakest strength
    /// and the segments a draw perturbs.
    fn delivered(
        &mut self,
        i: usize,
        tol: &crate::request::Tolerance,
    ) -> Result<(f64, f64, usize)> {
        use super::tolerance::{judged_at, spread, spread_estimate, DEFAULT_DRAWS};
        let summary =
            |s: &super::tolerance::Spread| (s.shape()[2], s.strength()[2], s.perturbed_segments);
        if let Some((_, s)) = self.out.delivered.iter().find(|(k, _)| *k == i) {
            return Ok(summary(s));
        }
        let schedule = &self.out.candidates[i].schedule;
        self.opts.runtime.admit(&spread_estimate(
            self.target,
            self.sampled,
            schedule,
            DEFAULT_DRAWS,
        ))?;
        let physics = judged_at(schedule, &schedule.settings, None);
        let s = spread(
            self.target,
            self.sampled,
            schedule,
            &physics,
            (tol, DEFAULT_DRAWS),
        )?;
        let out = summary(&s);
        self.out.delivered.push((i, s));
        Ok(out)
    }

    /// `auto` over a friction range when no candidate holds the target
    /// within [`RANGE_HELD`] at its worst over the range: one more motion,
    /// synthesized and polished for the worst case (as
    /// `--robust-synthesis`: every evaluation and play under the range's
    /// ends and middle, about three times the synthesis' work, stated
    /// first), within the envelope, played across the range and judged
    /// beside the others. Its failure is stated, not fatal: the other
    /// candidates stand.
    fn worst_case_synthesis(&mut self) -> Result<()> {
        let synth = SynthOptions {
            robust_synthesis: true,
            ..self.opts.synthesis
        };
        let asked = self.opts.method == Method::Auto && !self.opts.synthesis.robust_synthesis;
        if !asked || !self.ranged() || held(&self.out.candidates) {
            return Ok(());
        }
        let limits = self.out.limits.clone();
        let estimate = synthesis_estimate(self.target, self.sampled, &synth, self.opts, &limits);
        self.opts.runtime.admit(&estimate)?;
        self.out.estimate.terms.extend(estimate.terms);
        let t = Instant::now();
        match synthesize_schedule(self.target, self.sampled, &limits, self.opts, &synth) {
            Ok((syn, schedule)) => {
                let c = self.synthesized(&syn, schedule, &limits, t.elapsed().as_secs_f64())?;
                self.add(Variant::WorstCase, (syn, limits), vec![c])?;
            }
            Err(e) => self.out.failures.push(Failure::new(
                Method::Synthesize,
                FailureReason::WorstCase(e.to_string()),
            )),
        }
        Ok(())
    }

    /// The candidates of a synthesis `auto` adds (`variant`, with the
    /// synthesis and its limits), each judged across the target's friction
    /// range beside the others when it states one.
    fn add(
        &mut self,
        variant: Variant,
        (syn, limits): (Synthesis, ShakerLimits),
        cands: Vec<Candidate>,
    ) -> Result<()> {
        for mut c in cands {
            c.variant = variant;
            if self.ranged() {
                c.judge_range(self.target, self.sampled)?;
            }
            self.out.candidates.push(c);
        }
        self.added.push((variant, syn, limits));
        Ok(())
    }

    /// The target states a friction range: every candidate is judged by
    /// its worst case over it.
    fn ranged(&self) -> bool {
        self.target.friction.is_some_and(|f| !f.is_exact())
    }

    /// The mirror-image time-shares of the synthesized `schedule`: about
    /// `axis` when a reflection maps the target to itself, and shared with
    /// a partner synthesized for the target's mirror image and mirrored back
    /// (`super::mirror::counter_share`) when there is none or the line
    /// misses the centre: that mirror image moves the reference point, so
    /// the tilts' lever about it adds vertical acceleration at the centre,
    /// which the limits may not allow (then the share is scaled down and
    /// the partner, exact about the centre, may be the stronger one; the
    /// judge chooses).
    fn mirror_shares(
        &self,
        schedule: &Schedule,
        axis: Option<&super::mirror::MirrorLine>,
        limits: &ShakerLimits,
    ) -> Result<Vec<Schedule>> {
        let mut shares = Vec::new();
        if let Some(line) = axis {
            shares.push(super::mirror::mirror_share(
                schedule,
                limits,
                line,
                super::mirror::MIRROR_SEGMENT_CYCLES,
            )?);
        }
        if !axis.is_some_and(super::mirror::MirrorLine::is_through_centre) {
            let mirrored = self.target.mirrored_y();
            let sampled = mirrored.sample()?;
            let (_, partner) = synthesize_schedule(
                &mirrored,
                &sampled,
                limits,
                self.opts,
                &asked_synthesis(self.target, self.opts),
            )?;
            shares.push(super::mirror::counter_share(
                schedule,
                &partner,
                limits,
                super::mirror::MIRROR_SEGMENT_CYCLES,
            )?);
        }
        Ok(shares)
    }

    /// The mix: asked for, or under `auto` when no candidate realises the
    /// target (every one POOR): one motion alone cannot reach it.
    fn mix(&mut self) -> Result<()> {
        let method = self.opts.method;
        let all_poor = self.out.candidates.iter().all(|c| c.played().poor);
        if !(method == Method::Mix || (method == Method::Auto && all_poor)) {
            return Ok(());
        }
        let t = Instant::now();
        match mix_design(
            self.target,
            self.sampled,
            &self.out,
            self.opts,
            &self.opts.synthesis,
        ) {
            Ok((d, syn)) if d.schedule.segments.iter().all(|s| s.motion.is_none()) => {
                // Nothing mixed: the schedule is the sequenced one again.
                self.out
                    .failures
                    .push(Failure::new(Method::Mix, FailureReason::ColumnLeftOut));
                if self.out.synthesis.is_none() {
                    self.out.synthesis = syn;
                }
            }
            Ok((d, syn)) => {
                // The whole-cycle strength: the ramps' extra cycles dilute it.
                let record = self.recorded_limits();
                let c = self.play(
                    d.schedule.clone(),
                    d.schedule.fit_quantized.strength,
                    record,
                    t.elapsed().as_secs_f64(),
                )?;
                self.out.candidates.push(c);
                self.out.mixed = Some(d);
                if self.out.synthesis.is_none() {
                    self.out.synthesis = syn;
                }
            }
            Err(e) if method == Method::Auto && !self.out.candidates.is_empty() => {
                self.out.failures.push(Failure::new(
                    Method::Mix,
                    FailureReason::Error(e.to_string()),
                ));
            }
            Err(e) => return Err(self.first_error.take().unwrap_or(e)),
        }
        Ok(())
    }

    /// One candidate kept ([`choose`]; over a friction range by its worst
    /// case, [`MethodRun::judge_range`]) and the kept one's judge
    /// across the target's friction recorded.
    fn finish(self) -> Result<MethodDesign> {
        let (target, sampled) = (self.target, self.sampled);
        let bound = self.ranged().then_some(RANGE_HELD);
        let mut out = self.out;
        let (chosen, choice) = match self.delivered_pick {
            Some((kept, rule)) => (kept, Choice::Delivered(rule)),
            None => choose(&out.candidates, out.asked, bound),
        };
        out.tolerance = out
            .delivered
            .iter()
            .find(|(i, _)| *i == chosen)
            .map(|(_, s)| s.clone());
        out.bound = bound;
        out.chosen = chosen;
        out.choice = choice;
        let variant = out.candidates[chosen].variant;
        if let Some((_, syn, limits)) = self.added.into_iter().find(|(v, ..)| *v == variant) {
            out.synthesis = Some(syn);
            out.limits = limits;
        }
        let why = out.why();
        for c in &mut out.candidates {
            if let Some(p) = c.schedule.played.as_mut() {
                p.choice = why.clone();
            }
        }
        out.sensitivity = match &out.candidates[chosen].sensitivity {
            Some(s) => Some(s.clone()),
            None => candidate_sensitivity(target, sampled, &out.candidates[chosen].schedule)?,
        };
        Ok(out)
    }
}

/// `schedule`'s judge across the friction the target states
/// ([`sensitivity::of_target`]).
fn candidate_sensitivity(
    target: &Target,
    sampled: &SampledTarget,
    schedule: &Schedule,
) -> Result<Option<Sensitivity>> {
    sensitivity::of_target(target, &schedule.settings, &|settings| {
        judge_check(target, sampled, schedule, settings)
    })
}

/// The judge of `schedule` at each of `values`, against the
/// target it records (`verify --friction LO:HI:N`).
///
/// # Errors
/// The schedule records no target (nothing to judge against), or cannot be
/// played.
pub(crate) fn sweep_schedule(schedule: &Schedule, values: &[Friction]) -> Result<Sensitivity> {
    let (target, sampled) = recorded_target(schedule, "--friction")?;
    let rows: Vec<FrictionRow> =
        sensitivity::friction_sweep(&schedule.settings, values, &|settings| {
            judge_check(target, &sampled, schedule, settings)
        })?;
    Ok(Sensitivity {
        span: Span::Asked,
        nominal: schedule.settings.friction,
        rows,
    })
}

/// The target `schedule` records, sampled: what the judge compares with
/// when a schedule is judged again (`arg` names the option that asks).
///
/// # Errors
/// The schedule records none.
pub(crate) fn recorded_target<'a>(
    schedule: &'a Schedule,
    arg: &str,
) -> Result<(&'a Target, SampledTarget)> {
    let target = schedule.target_spec.as_ref().ok_or_else(|| {
        Error::invalid(
            arg,
            "the judge compares the schedule with its target, and this schedule records none (\"target_spec\")",
        )
    })?;
    Ok((target, target.sample()?))
}

/// The synthesis options of the method asked for: over a friction range
/// `--method synthesize`, whose one candidate is the synthesized motion,
/// optimises the worst case (as `--robust-synthesis`); `auto` and `mirror`
/// synthesize for the range's middle and hold the range by the
/// mirror-image share ([`super::mirror`]), `auto` adding the worst-case
/// synthesis when no candidate holds it ([`RANGE_HELD`]).
fn asked_synthesis(target: &Target, opts: &DesignOptions) -> SynthOptions {
    let ranged = target.friction.is_some_and(|f| !f.is_exact());
    SynthOptions {
        robust_synthesis: opts.synthesis.robust_synthesis
            || (ranged && opts.method == Method::Synthesize),
        ..opts.synthesis
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Over a friction range `--method synthesize` optimises the worst
    /// case; `auto` and `mirror` synthesize for the middle; an exact
    /// friction never asks for the worst case.
    #[test]
    fn synthesize_over_a_range_optimises_the_worst_case() {
        let mut target = Target::load(std::path::Path::new("targets/sink.json")).unwrap();
        let asked = |target: &Target, method| {
            let opts = DesignOptions {
                method,
                ..DesignOptions::default()
            };
            asked_synthesis(target, &opts).robust_synthesis
        };
        assert!(!asked(&target, Method::Synthesize));
        target.friction = Some(crate::scene::FrictionSpec::range(0.2, 0.4));
        assert!(asked(&target, Method::Synthesize));
        assert!(!asked(&target, Method::Auto));
        assert!(!asked(&target, Method::Mirror));
    }

    /// The polish term counts the points the polish plays, the judge's:
    /// every sample of a grid-less target, 40 or 2000.
    #[test]
    fn polish_estimate_counts_the_played_parts() {
        let parts_of = |n: usize| {
            let points: Vec<[f64; 2]> = (0..n)
                .map(|k| {
                    let t = k as f64;
                    [0.04 * (1.7 * t).sin(), 0.04 * (2.3 * t).cos()]
                })
                .collect();
            let target = Target {
                name: "scattered".into(),
                grid: None,
                field: crate::request::FieldSpec::Sampled {
                    vectors: points.iter().map(|p| [-p[1], p[0]]).collect(),
                    points,
                    interpolation: crate::request::Interpolation::Idw,
                },
                weights: None,
                mask: Vec::new(),
                shaker: None,
                friction: None,
                gravity: None,
                classes: Vec::new(),
            };
            let sampled = target.sample().unwrap();
            let e = synthesis_estimate(
                &target,
                &sampled,
                &SynthOptions::default(),
                &DesignOptions::default(),
                &ShakerLimits::from_spec(None),
            );
            let polish = e.terms.iter().find(|t| t.label == "played polish").unwrap();
            polish.factors.iter().find(|f| f.0 == "points").unwrap().1
        };
        assert_eq!(parts_of(40), 40.0);
        assert_eq!(parts_of(2000), 2000.0);
    }

    /// A worked example of `design::method::gentle_limits`.
    #[test]
    fn example_gentle_limits() {
        use crate::design::method::gentle_limits;
        use crate::synth::ShakerLimits;

        let envelope = ShakerLimits::envelope();
        let gentle = gentle_limits(&envelope);
        assert!((gentle.contact_margin - 0.55).abs() < 1e-12);
        assert_eq!(gentle.linear, envelope.linear);
        assert_eq!(gentle.angular, envelope.angular);
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/method.rs"]
mod method_tests;
