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
//! from rest, the held part only creeps, and less the further below the
//! threshold the plate stays).
//! So besides the paper's primitives the basis holds **gentle copies** of
//! the in-plane translation (Trans) at [`GENTLE_FRACTIONS`] of the
//! stickier class's threshold: peak plate acceleration 1.5 d₀ω² (the
//! asymmetric waveform's peak) = f · μ_s,low g of the stickier class, where
//! μ_s,low is the low end of its static range. They move only the parts of
//! lower friction (the stickier class only creeps under them, an order of
//! magnitude slower or more), and the fit uses them to push those parts away from
//! where the strong primitives gather the others.
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
//! **Synthesized candidate.** The slip lead δ = asin(μg/A) of a part
//! under an in-plane plate acceleration of amplitude A turns its field by
//! δ and scales it by cos δ ([`crate::synth`]): parts of different μ see
//! one motion's field turned and scaled differently, and where A < μ N
//! they do not slip at all. Two consequences shape the candidate. (i) Under
//! a uniformly turning slip direction, every signal's (P, Q) pair turns by
//! the same lead, so the whole affine field turns about its fixed point:
//! one harmonic-1 motion gives every class the *same* attractor, turned
//! and rescaled (with A of tens of m/s² against μg of a few, both leads
//! asin(μg/A) are a few degrees). (ii) A motion whose
//! in-plane peak stays below the stickier class's μ_s N never moves it,
//! while it carries the slippery class. So the candidate offers the
//! stacked fit, besides the primitives and the gentle Trans copies, a
//! motion per class synthesized jointly for every class's field at its own
//! friction (`crate::synth::synthesize_classes`: the worst class's
//! judge, strength and contact margin; seeded on that class), a motion per
//! class synthesized for its own field alone (which every class follows:
//! the strong sink the others are pushed off) and, for
//! every class with a stickier one, a **gentle** motion synthesized for
//! its field within in-plane peaks of [`GENTLE_SYNTH_FRACTION`] of the
//! next stickier class's μ_s,low g and a contact margin of
//! [`GENTLE_SYNTH_MARGIN`] (so μ_s,low N ≥ 0.85 μ_s,low g stays above the
//! peak: that class is held), when that peak exceeds its own μ_s g (a
//! contrast above 1/0.7; below it the gentle window is closed to
//! syntheses). The fit's time fractions make the time-share.
//!
//! **Aim.** The stacked fit matches each class's whole-cycle average
//! field; the parts follow the schedule segment by segment, and where they
//! settle (the fixed point of one schedule period) is off that average's
//! attractor by several millimetres when strong segments carry them
//! centimetres per segment and cancel on average (the unaimed candidates
//! of `targets/sort_friction.json` leave a swarm's median end that far
//! from its sink). So a synthesized candidate is aimed: five
//! parts started at and around each class's attractor are played
//! [`AIM_PLAY_S`], the offset e from the attractor of their orbits' mean
//! centre over the last period (time-averaged between segment ends; for a
//! line, its normal part) measured, the class's target moved by −e (fitted
//! as f(q + e)) and refitted, up to [`AIM_STEPS`] times (a lane is
//! steered instead: **Lanes**).
//!
//! **Cycle aim** (sinks). Moving a class's target and refitting picks
//! other columns and lengths, and the settled offset jumps between steps
//! (by about a centimetre, either way, on `targets/sort_three.json`), so
//! the aim above cannot bring an orbit that swings out of 5 mm within it.
//! Once aimed,
//! a candidate whose parts' settled orbits reach farther than
//! [`CYCLE_REACH_OK`] from their attractor at a segment end
//! (`settled_reach`: five parts per class started at and around it,
//! played [`AIM_PLAY_S`]) is aimed by what the shaker plays, its
//! segments' whole cycles, its columns and their order fixed
//! (`cycle_aimed`): each step plays every segment's cycles changed by each
//! of [`CYCLE_STEPS`] and keeps the change that brings the worst class's
//! settled reach nearest, at most [`CYCLE_SWEEPS`] steps. The schedule so
//! aimed is offered beside the candidate it came from (labelled `cycles
//! aimed`, its fit's time fractions and predicted fields those of the fit),
//! and the plays keep whichever sorts soonest: a candidate already sorted
//! stays what it was. On `targets/sort_three.json` the cycle-aimed
//! candidates sort within their plays where most of the candidates they
//! came from do not (measured: `results/sort_three/report.md`, its
//! candidates' table).
//!
//! **Interleaving.** A part swings within a schedule period: each
//! segment carries it its own way for the segment's duration, so the
//! swing grows with the segments' durations (on sinks, periods over a
//! second already swing a part by about the 5 mm a class may span; on
//! lanes, periods of several seconds carry parts through the wrong edge).
//! Every synthesized candidate's schedule, once fitted,
//! is therefore cut into k interleaved sub-periods
//! (`interleaved`: the same segments, each cut into k pieces of nearly
//! equal cycles, played in turn, so every segment keeps its time
//! fraction), with k the least that brings the largest excursion of a
//! class's part (started at its attractor, or the region's centre, its
//! second period, `excursion`) over k within [`EXCURSION_MAX`] (half
//! the 5 mm a part may be from its attractor), at most
//! [`MAX_SUB_PERIODS`]. A six-signal segment keeps its ramps of R cycles
//! each way in every piece (so its accelerations stay as checked within
//! the shaker's limits) and is cut into at most ⌊c / R⌋ pieces (c: the
//! cycles' worth of field it plays); each piece more adds R cycles to
//! the period (its two ramps play about R cycles' worth of its field, so
//! the proportions hold). The aim then plays the cut schedule. Only a
//! target with lanes is cut: on the shipped sorts to sinks
//! (`targets/sort_three.json`, `targets/sort_friction.json`) the cut
//! candidates bring none of some class to its sink where the uncut ones
//! sort: more joins, more of their transients, change what each class's
//! parts do.
//!
//! **Lanes.** A class may instead ask to leave the region through one of
//! its edges (`"exit"`, [`crate::request::Edge`]), its field a uniform
//! `trans` through that edge. A uniform transport carries every class the
//! same way, faster or slower, and the slip lead turns it by a few degrees
//! only; opposite lanes come from the threshold again: a gentle motion
//! carries the slippery class while the sticky one is held, time-shared
//! with a strong transport the other way. The same stacked fit makes
//! them, with two additions. (i) **Keeping**: a lane's fitted field is
//! its transport plus a pull toward the lane's axis, −κ|v|y across it
//! ([`LANE_KEEP`]): a drift t = v_across/v_along off the lane then
//! settles parts at y* = t/κ from the axis instead of carrying them out
//! through a side edge (unkept, the share through the sides is L t / (2W)
//! over a region of length L and width W, which the μ 0.2 swarm of
//! `targets/sort_lanes.json` follows unkept). (ii)
//! **Steering**: the fit's whole-cycle fields are not what moving parts
//! do (the segments' joins and the parts' motion within a cycle; on
//! `targets/sort_lanes.json` the played drift across a lane can even have
//! the other sign than the frozen judge's), so each lane's
//! target is multiplied by a complex factor (turned and scaled), the
//! ratio of the drift asked for (L along the lane: every lane crossed in
//! the same time) to the drift five parts are played to have, and
//! refitted, up to [`AIM_STEPS`] times; the refit whose drifts predict
//! the soonest lanes is kept. The plays then measure where each part
//! first leaves the region (`crate::verify::sort_play`).
//!
//! **Mirror images** (a target with lanes). When every class's field is
//! symmetric in one line
//! (`super::mirror`: the first class's mirror axis, if the others share
//! it; two sinks or lanes on the x axis share y = 0), each synthesized
//! motion is offered with its mirror image in that line. The reflection
//! leaves gravity and Coulomb's law unchanged, so the mirror motion drives
//! at *every* friction the mirror image of the motion's field; the slip
//! lead turns a motion's field by a different angle for each class, and
//! the fit can now cancel, class by class, the part of those turns that
//! the reflection reverses (a motion that carries two classes off their
//! lanes in opposite senses has a mirror image that carries them off in
//! the senses reversed).
//!
//! **Judged by playing**: for lanes, every refit of the aim is ranked by
//! the swarms themselves, every class played [`AIM_SWARM_S`] as the design plays it
//! (its time to sort, then its least share at the own attractor less the
//! share mixed up), before the predicted lane times and the settled
//! offsets; the drift of five parts or the centre of a settled orbit
//! miss parts that leave through a side or swing out of 5 mm. Every
//! candidate's swarms are then played (`verify::sort_play`); the sort
//! that brings 95 % of every class to its own attractor soonest is kept.
//!
//! The mirror images and the played rank are for lanes only: on
//! `targets/sort_friction.json` with both, no refit sorted within its
//! aim's play and the kept sort was several times slower than without
//! them; so sinks keep their synthesized motions without mirror images
//! and the aim ranked by the settled offsets.

mod aim;
mod cycles;
mod interleave;
pub(crate) mod swarm;

use aim::{aimed, lane_kept, turn};
pub use aim::{
    AIM_PLAY_S, AIM_STEPS, AIM_SWARM_S, AIM_TOL, LANE_KEEP, LANE_PLAY_S, LANE_SHARE, LANE_TOL,
};
pub use cycles::{CYCLE_PERIOD_SCALES, CYCLE_REACH_MAX, CYCLE_REACH_OK, CYCLE_STEPS, CYCLE_SWEEPS};
#[cfg(test)]
pub(crate) use interleave::{excursion, interleaved, sub_periods};
pub use interleave::{EXCURSION_MAX, MAX_SUB_PERIODS};

use nalgebra::DVector;
use serde::Serialize;

use super::basis::{self as dbasis, DesignBasis};
use super::stages::{self, BasisStage};
use super::{strongest, DesignOptions};
use crate::basis::{symmetry, FieldLibrary, Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::field::{FieldSettings, Grid};
use crate::fit::{FitOptions, FitProblem};
use crate::motion::Signals;
use crate::request::{FieldSpec, SampledTarget, Target};
use crate::schedule::Schedule;
use crate::synth::{synthesize, synthesize_classes, ShakerLimits};
use crate::work::Term;

/// Peak plate accelerations of the gentle Trans copies, as fractions of
/// the stickier class's μ_s g (both below 1: that class never slips).
pub const GENTLE_FRACTIONS: [f64; 2] = [0.75, 0.9];

/// In-plane peak of a gentle synthesized motion, as a fraction of the next
/// stickier class's μ_s,low g. A class whose own μ_s is not below this
/// fraction of the next stickier one's (a contrast below 1/0.7 = 1.43)
/// gets no gentle motion: none could make it slip.
pub const GENTLE_SYNTH_FRACTION: f64 = 0.7;

/// Contact margin of a gentle synthesized motion: N ≥ 0.85 g keeps the
/// stickier class's μ_s,low N at or above 0.85 μ_s,low g, above the
/// in-plane peak [`GENTLE_SYNTH_FRACTION`] μ_s,low g.
pub const GENTLE_SYNTH_MARGIN: f64 = 0.85;

/// Shape budgets of the synthesized candidates fitted strongest within a
/// budget (`crate::fit::FitMode::Budget`) besides the shape-first one. A
/// sort needs each class's attractor where it is asked and speed, not the
/// field's shape everywhere: on `targets/sort_friction.json` the
/// shape-first fit is several times weaker per class than a budget of
/// 15–30 % and leaves both swarms off their sinks. Which budget, aimed,
/// puts both classes on their own attractors is found by playing them all
/// (the kept one: `results/sort_friction/report.md`).
pub const SORT_BUDGETS: [f64; 5] = [0.1, 0.15, 0.2, 0.25, 0.3];

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

/// How a sort candidate's basis was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SortMethod {
    /// The primitives and the gentle Trans copies.
    Primitives,
    /// The same with synthesized motions (module docs).
    Synthesized,
}

impl SortMethod {
    /// Name, e.g. `synthesized`.
    pub(crate) fn name(self) -> &'static str {
        match self {
            SortMethod::Primitives => "primitives",
            SortMethod::Synthesized => "synthesized",
        }
    }
}

impl SortDesign {
    /// The candidate's name: its method, and its shape budget if any, e.g.
    /// `synthesized, shape ≤ 15 %`.
    pub fn label(&self) -> String {
        let label = match self.budget {
            None => self.method.name().to_string(),
            Some(b) => format!("{}, shape ≤ {:.0} %", self.method.name(), 100.0 * b),
        };
        if self.cycles_aimed {
            format!("{label}, cycles aimed")
        } else {
            label
        }
    }
}

/// A sort design: one schedule, every class's predicted field.
#[derive(Debug, Clone)]
pub struct SortDesign {
    /// How its basis was made.
    pub method: SortMethod,
    /// The synthesized motions offered to the fit (labels).
    pub motions: Vec<String>,
    /// The stacked fit's shape budget, when it was fitted strongest within
    /// one ([`SORT_BUDGETS`]); `None`: shape first.
    pub budget: Option<f64>,
    /// Per class, the offset (m) its target was moved by so that its parts
    /// settle on the attractor asked for (module docs, **Aim**).
    pub aim: Vec<[f64; 2]>,
    /// Per class, the factor (re, im) its target's vectors were multiplied
    /// by, a complex number (turned by its argument, scaled by its
    /// modulus), so that the drift of a lane's parts runs along its lane
    /// at its share of the speed (module docs, **Aim**); (1, 0) for a
    /// class with an attractor.
    pub steer: Vec<[f64; 2]>,
    /// Whether its segments' cycles were changed by playing them (module
    /// docs, **Cycle aim**): the fit's time fractions (`weight`) and
    /// predicted fields are then those of the fit, before the change.
    pub cycles_aimed: bool,
    /// The sub-periods its schedule was cut into (module docs,
    /// **Interleaving**; 1: not cut).
    pub sub_periods: u32,
    /// The schedule (its settings hold the first class's friction).
    pub schedule: Schedule,
    /// Per class, in the target's order.
    pub classes: Vec<ClassFit>,
    /// The gentle columns offered to the fit (labels).
    pub gentle: Vec<String>,
}

/// Designs the sort candidates of `target`'s classes (see the module
/// docs): the primitives' stacked fit, then the fit with synthesized
/// motions; `crate::verify::sort_play::play_sort` plays them and keeps
/// the faster. Errors when the target has no classes.
pub fn design_sort(target: &Target, opts: &DesignOptions) -> Result<Vec<SortDesign>> {
    if target.classes.len() < 2 {
        return Err(Error::invalid(
            "target.classes",
            "a sort needs at least 2 part classes",
        ));
    }
    opts.runtime.admit(&sort_estimate(target, opts)?)?;
    let primitives = design_sort_primitives(target, opts)?;
    let motions = sort_motions(target, opts)?;
    let motions = if target.classes.iter().any(|c| c.exit.is_some()) {
        with_mirrors(target, motions)?
    } else {
        motions
    };
    let stack = stack(target, opts, &motions)?;
    let progress = crate::progress::Progress::new(
        "sort: aiming",
        "candidates",
        1 + SORT_BUDGETS.len() as u64,
        opts.runtime.progress(),
    );
    let mut out = vec![primitives];
    for budget in std::iter::once(None).chain(SORT_BUDGETS.map(Some)) {
        progress.set_message(match budget {
            None => "shape first".to_string(),
            Some(b) => format!("shape ≤ {:.0} %", 100.0 * b),
        });
        // A fit the conic solver cannot verify (its KKT residual over
        // tolerance) or a budget it cannot reach leaves that candidate
        // out; the primitives' candidate is always there.
        if let Ok(d) = aimed(target, &stack, budget) {
            let twin = cycles::cycle_aimed(target, &d)?;
            out.push(d);
            out.extend(twin);
        }
        progress.inc(1);
    }
    progress.finish();
    Ok(out)
}

/// The primitives' candidate alone (the first of [`design_sort`]), without
/// the syntheses.
///
/// ```no_run
/// use platefield::design::{sort::design_sort_primitives, DesignOptions};
/// use platefield::request::Target;
/// let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
/// let d = design_sort_primitives(&target, &DesignOptions::default())?;
/// assert!(d.motions.is_empty());
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// Those of [`design_sort`].
pub fn design_sort_primitives(target: &Target, opts: &DesignOptions) -> Result<SortDesign> {
    let n = target.classes.len();
    fit_stack(
        target,
        &stack(target, opts, &[])?,
        SortMethod::Primitives,
        None,
        &vec![[0.0; 2]; n],
        &vec![[1.0, 0.0]; n],
        None,
    )
}

/// The limits a sort's motions are synthesized within: the target's, and
/// when it states no linear limits, the default envelope with the vertical
/// limit of the paper's primitives
/// ([`ShakerLimits::paper_envelope`], 0.109 m/s²), not the plate's 7 m/s².
/// On `targets/sort_friction.json`, within 7 m/s² each class's own
/// motion, synthesized at its friction alone, is strong by driving the
/// normal force to the contact margin; played as the sort's short
/// segments, every class sees those swings, parts lose contact and no
/// synthesized candidate sorts within its play, while within the
/// primitives' vertical one does. A target that states `shaker.linear` is
/// synthesized within it as stated.
fn sort_limits(target: &Target) -> ShakerLimits {
    let mut limits = ShakerLimits::from_spec(target.shaker.as_ref());
    if target.shaker.as_ref().and_then(|s| s.linear).is_none() {
        limits.linear[2] = ShakerLimits::paper_envelope().linear[2];
    }
    limits
}

/// The synthesized motions of the sort of `target` (module docs), each
/// made playable beside the primitives (`super::method::mixable`):
/// `Own:<class>` (its field at its friction alone: every class sees it,
/// nearly unturned at full strength) and `Joint:<class>` for every class;
/// for every class with a stickier one whose gentle limits still exceed
/// its own μ_s g (`GENTLE_SYNTH_FRACTION`),
/// within the gentle limits, `Gentle:<class>` (its own field) and
/// `GentleCarry:<class>` (a uniform transport from the next stickier
/// class's attractor toward its own: an attractor off the plate's centre
/// needs a uniform part, which the tilts cannot give and the vertical
/// limit barely allows, so a gentle in-plane ratchet carries it).
///
/// # Errors
/// A synthesis failing (invalid limits or options).
pub(crate) fn sort_motions(
    target: &Target,
    opts: &DesignOptions,
) -> Result<Vec<(String, Signals)>> {
    let g = target
        .grid
        .as_ref()
        .ok_or_else(|| Error::invalid("target.grid", "a sort needs the target's grid"))?;
    let region = Grid {
        x: g.x,
        y: g.y,
        n: g.n,
    };
    let limits = sort_limits(target);
    let synth = crate::synth::SynthOptions {
        progress: opts.runtime.progress(),
        ..opts.synthesis
    };
    let classes: Vec<(FieldSpec, FieldSettings)> = (0..target.classes.len())
        .map(|i| {
            let ct = target.class_target(i);
            (ct.field.clone(), ct.physics(&opts.settings))
        })
        .collect();
    let lows: Vec<f64> = target.classes.iter().map(|c| c.friction.stat.lo).collect();
    let mut out = Vec::new();
    for (i, class) in target.classes.iter().enumerate() {
        let own = synthesize(&classes[i].0, &region, &limits, &classes[i].1, &synth)?;
        out.push((
            format!("Own:{}", class.name),
            super::method::mixable(own.checked.motion, &limits, opts)?,
        ));
        let mut order = classes.clone();
        order.swap(0, i);
        let joint = synthesize_classes(&order, &region, &limits, &synth)?;
        out.push((
            format!("Joint:{}", class.name),
            super::method::mixable(joint.checked.motion, &limits, opts)?,
        ));
        let stickier = lows
            .iter()
            .copied()
            .filter(|&mu| mu > lows[i])
            .fold(f64::INFINITY, f64::min);
        // The gentle limits must still let this class slip: a peak of
        // GENTLE_SYNTH_FRACTION of the stickier threshold above its own
        // μ_s g, i.e. a friction contrast above 1/GENTLE_SYNTH_FRACTION
        // (1.43); below it no gentle motion carries either class.
        let own_threshold = classes[i].1.friction.stat;
        if stickier.is_finite() && GENTLE_SYNTH_FRACTION * stickier > own_threshold {
            let g = classes[i].1.gravity;
            let peak = GENTLE_SYNTH_FRACTION * stickier * g;
            let gentle = ShakerLimits {
                linear: [
                    limits.linear[0].min(peak),
                    limits.linear[1].min(peak),
                    limits.linear[2],
                ],
                contact_margin: limits.contact_margin.max(GENTLE_SYNTH_MARGIN),
                ..limits.clone()
            };
            let s = synthesize(&classes[i].0, &region, &gentle, &classes[i].1, &synth)?;
            out.push((
                format!("Gentle:{}", class.name),
                super::method::mixable(s.checked.motion, &gentle, opts)?,
            ));
            let next = (0..lows.len())
                .filter(|&j| lows[j] == stickier)
                .min()
                .unwrap_or(i);
            if let Some(direction) = apart(&region, &classes[i].0, &classes[next].0) {
                let carry = FieldSpec::Trans {
                    center: [0.0; 2],
                    strength: 1e-3,
                    direction,
                };
                let s = synthesize(&carry, &region, &gentle, &classes[i].1, &synth)?;
                out.push((
                    format!("GentleCarry:{}", class.name),
                    super::method::mixable(s.checked.motion, &gentle, opts)?,
                ));
            }
        }
    }
    Ok(out)
}

/// `motions` and, when the classes' fields share a mirror line
/// ([`classes_mirror`]), each motion's mirror image in it, labelled
/// `<label> mirrored`.
fn with_mirrors(
    target: &Target,
    mut motions: Vec<(String, Signals)>,
) -> Result<Vec<(String, Signals)>> {
    if let Some(line) = classes_mirror(target)? {
        let mirrored: Vec<(String, Signals)> = motions
            .iter()
            .map(|(label, m)| (format!("{label} mirrored"), line.mirror(m)))
            .collect();
        motions.extend(mirrored);
    }
    Ok(motions)
}

/// A line every class's field is symmetric in (`super::mirror`): the first
/// mirror axis of the first class's field, when every other class's field
/// is symmetric in it; `None` otherwise.
fn classes_mirror(target: &Target) -> Result<Option<super::mirror::MirrorLine>> {
    let first = target.class_target(0);
    let Some(line) = super::mirror::mirror_axis(&first, &first.sample()?) else {
        return Ok(None);
    };
    for i in 1..target.classes.len() {
        let ct = target.class_target(i);
        if !line.is_symmetry_of(&ct, &ct.sample()?) {
            return Ok(None);
        }
    }
    Ok(Some(line))
}

/// The direction (degrees) in which `own`'s parts must move relative to
/// `other`'s: the difference of the two fields' means over `region` (for
/// two sinks, from the other's centre to the own); `None` when the means
/// are equal.
fn apart(region: &Grid, own: &FieldSpec, other: &FieldSpec) -> Option<f64> {
    let points = region.points();
    let mean = |f: &FieldSpec| {
        points.iter().fold([0.0; 2], |a, p| {
            let v = f.eval(*p);
            [a[0] + v[0], a[1] + v[1]]
        })
    };
    let (a, b) = (mean(own), mean(other));
    let d = [a[0] - b[0], a[1] - b[1]];
    (d[0].hypot(d[1]) > 1e-12 * (a[0].hypot(a[1]) + b[0].hypot(b[1])))
        .then(|| d[1].atan2(d[0]).to_degrees())
}

/// Every class's basis (the primitives, the gentle Trans copies and
/// `motions`, simulated at the class's friction), stacked, and the classes'
/// sampled targets.
struct Stack {
    basis: DesignBasis,
    sampled: Vec<SampledTarget>,
    motions: Vec<String>,
    opts: DesignOptions,
    gentle: Vec<String>,
}

/// The [`Stack`] of `target` over the primitives, the gentle Trans copies
/// and `motions`.
fn stack(target: &Target, opts: &DesignOptions, motions: &[(String, Signals)]) -> Result<Stack> {
    let mut opts = opts.clone();
    opts.basis.motions.extend(motions.iter().cloned());
    let gentle = gentle_primitives(target, &opts);
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
        return Err(Error::Unreachable(
            "no basis column is usable at every class's friction".into(),
        ));
    }
    Ok(Stack {
        basis,
        sampled,
        motions: motions.iter().map(|m| m.0.clone()).collect(),
        opts,
        gentle: gentle.iter().map(dbasis::label).collect(),
    })
}

/// One stacked fit of `stack` (the fit mode of `stack.opts`), each class's
/// target moved by its `aim` offset (m) and its vectors multiplied by its
/// `steer` factor (a complex number (re, im): turned and scaled): class
/// i's field f is fitted as steerᵢ · f(q − aimᵢ); the classes' relative
/// `scales` as given, else chosen (`choose_scales`).
fn fit_stack(
    target: &Target,
    stack: &Stack,
    method: SortMethod,
    budget: Option<f64>,
    aim: &[[f64; 2]],
    steer: &[[f64; 2]],
    scales: Option<&[f64]>,
) -> Result<SortDesign> {
    let mut opts = stack.opts.clone();
    if let Some(b) = budget {
        opts.fit.mode = crate::fit::FitMode::Budget { rel_error: b };
    }
    let sampled: Vec<SampledTarget> = stack
        .sampled
        .iter()
        .zip(&target.classes)
        .zip(aim)
        .zip(steer)
        .map(|(((s, c), d), &k)| SampledTarget {
            vectors: s
                .points
                .iter()
                .map(|p| {
                    let v = turn(c.field.eval([p[0] - d[0], p[1] - d[1]]), k);
                    match c.exit {
                        Some(edge) => lane_kept(target, edge, *p, v),
                        None => v,
                    }
                })
                .collect(),
            ..s.clone()
        })
        .collect();
    let scales = match scales {
        Some(s) => s.to_vec(),
        None => choose_scales(&stack.basis, &sampled)?,
    };
    let stacked = stack_targets(&sampled, &scales);
    let opts0 = opts.for_target(&target.class_target(0));
    let fit = stages::fit_basis(stack.basis.clone(), &stacked, &opts0)?;
    let (schedule, achieved) = stages::schedule_stage(target, &stacked, &fit, &opts0)?;
    let classes = class_fits(target, &sampled, &scales, &achieved)?;
    Ok(SortDesign {
        method,
        motions: stack.motions.clone(),
        budget,
        aim: aim.to_vec(),
        steer: steer.to_vec(),
        sub_periods: 1,
        cycles_aimed: false,
        schedule,
        classes,
        gentle: stack.gentle.clone(),
    })
}

/// The work of designing the sort of `target` ([`crate::work`]), stated
/// before it starts: each class's library when the cache does not hold it
/// (a library per class: each is simulated at its class's friction), and
/// each class's judge (counted, as a design's, at
/// `SYNTH_SEGMENT_CYCLES` cycles per period); the swarms are estimated
/// once the schedule is known (`crate::verify::sort_play::play_estimate`).
///
/// # Errors
/// A class whose target cannot be sampled.
pub(crate) fn sort_estimate(
    target: &Target,
    opts: &DesignOptions,
) -> Result<crate::work::Estimate> {
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
    // The synthesized motions (`sort_motions`): per class its own and a
    // joint synthesis judged under every class's physics, two gentle ones
    // per class but the stickiest; each at most its evaluation budget on
    // the coarse grid.
    let n = target.classes.len() as f64;
    let syn = &opts.synthesis;
    e = e.plus(
        crate::work::field_term(
            "sort syntheses",
            syn.max_evaluations as f64,
            "evaluations",
            (syn.coarse[0] * syn.coarse[1]) as f64,
            crate::field::FieldKind::Velocity,
            &opts.settings,
        )
        .times(n * n + n + 2.0 * (n - 1.0), "class physics"),
    );
    // Aiming (`aimed`): every synthesized candidate at most AIM_STEPS + 1
    // times, five parts per class for AIM_PLAY_S (a sink) or LANE_PLAY_S
    // (a lane) at the primitives' period, and one part per class for its
    // excursion (two schedule periods, at most AIM_PLAY_S).
    let period = opts
        .basis
        .kinds
        .first()
        .map_or(0.03, |k| Primitive::new(*k).period());
    let lanes = target.classes.iter().filter(|c| c.exit.is_some()).count() as f64;
    let plays = |label: &str, classes: f64, parts: f64, seconds: f64| {
        Term::new(label)
            .times((1 + SORT_BUDGETS.len()) as f64, "candidates")
            .times((AIM_STEPS + 1) as f64, "fits")
            .times(classes, "classes")
            .times(parts, "parts")
            .times((seconds / period).ceil(), "cycles")
            .times(opts.settings.numerics.steps_per_cycle as f64, "steps")
    };
    // The cycle aim (`cycles::cycle_aimed`, sinks only): per candidate,
    // from each of its CYCLE_PERIOD_SCALES starts, up to CYCLE_SWEEPS
    // steps of every segment's CYCLE_STEPS changes, each five parts per
    // class for AIM_PLAY_S, counted for a schedule of four segments.
    let cycle_plays = if lanes > 0.0 {
        0.0
    } else {
        1.0 + (CYCLE_PERIOD_SCALES.len() * CYCLE_SWEEPS * CYCLE_STEPS.len() * 4) as f64
    };
    e = e
        .plus(
            plays("cycle aim plays", n, 5.0, AIM_PLAY_S)
                .times(cycle_plays / (AIM_STEPS + 1) as f64, "plays per fit"),
        )
        .plus(plays("aim plays", n - lanes, 5.0, AIM_PLAY_S))
        .plus(plays("lane plays", lanes, 5.0, LANE_PLAY_S))
        .plus(plays("excursion plays", n, 1.0, AIM_PLAY_S))
        .plus(plays(
            "aim swarms",
            if lanes > 0.0 { n } else { 0.0 },
            (swarm::SORT_STARTS[0] * swarm::SORT_STARTS[1]) as f64,
            AIM_SWARM_S,
        ));
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
    let lib = FieldLibrary::build(
        gentle,
        &source,
        &opts.settings,
        opts.basis.kind,
        crate::progress::ProgressMode::Quiet,
    );
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
    // A trial the conic solver cannot verify (its KKT residual over
    // tolerance) ranks last.
    let worst = |scales: &[f64]| worst(scales).unwrap_or(f64::INFINITY);
    let mut scales = vec![1.0; sampled.len()];
    let mut best = worst(&scales);
    for i in 1..sampled.len() {
        for k in CLASS_SCALES {
            let mut trial = scales.clone();
            trial[i] = k;
            let e = worst(&trial);
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

#[cfg(test)]
mod tests {
    /// A worked example of `design::sort::design_sort`.
    #[allow(dead_code)]
    fn example_design_sort() -> Result<(), crate::Error> {
        use crate::design::{sort::design_sort, DesignOptions};
        use crate::request::Target;
        let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
        for d in design_sort(&target, &DesignOptions::default())? {
            for c in &d.classes {
                println!(
                    "{}: {}: shape {:.1} %",
                    d.method.name(),
                    c.name,
                    100.0 * c.shape_error
                );
            }
        }
        Ok(())
    }

    /// A worked example of `design::sort::sort_estimate`.
    #[test]
    fn example_sort_estimate() -> Result<(), crate::Error> {
        use crate::design::{sort::sort_estimate, DesignOptions};
        use crate::request::Target;
        let target = Target::load(std::path::Path::new("targets/sort_friction.json"))?;
        let e = sort_estimate(&target, &DesignOptions::default())?;
        assert!(e.terms.iter().any(|t| t.label.starts_with("class mu_0.45")));
        Ok(())
    }
}
