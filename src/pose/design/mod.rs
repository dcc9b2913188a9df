//! Pose targets: a motion whose lifted field makes one pose of a
//! part the stable equilibrium, played on the part from random drops.
//!
//! 1. **Target** ([`PoseTarget`]): the target file with
//!    `"field": {"kind": "pose", "part": …, "pose": [x, y, θ°]}`.
//! 2. **One motion** ([`placement::synthesize_centred`]): one simultaneous
//!    six-signal motion synthesized once for the elliptic sink −(αx, βy)
//!    centred at the plate centre (weaker contraction along x,
//!    α/β = [`placement::RATIO`]), on a square large enough for any
//!    placement of it to keep contact over the region. For a part
//!    without a 180° symmetry, whose two poses 180° apart the ellipse
//!    cannot tell, a second motion, the isotropic sink with a spin
//!    ([`spin`], chosen by play: [`screen`]), is played in turn with it
//!    ([`cycle`]: the spin selects one of the two poses, the ellipse sets
//!    it), and the cycle is the motion placed below.
//! 3. **Lifted placement** ([`placement::Placement::onto`]): the centred
//!    motion's lifted field's stable pose ([`placement::centred_pose`])
//!    moved onto the asked one by turning the motion about the vertical and
//!    moving its reference point: a rigid transform of the plate physics
//!    (the turn exact, the shift to first order in the tilt), so of every
//!    pose, lifted or played.
//! 4. **Played correction** (`correct`): probes played on the placed
//!    motion; their mean rest pose corrects the placement (damped steps,
//!    the motion never redesigned).
//! 5. **Played** (`play`): the part dropped at `drops` random poses
//!    (centres uniform over the region inset by the part's radius, angles
//!    uniform: [`crate::pose::drop_starts`]) and simulated by the planar
//!    simulator; `"pose_fraction"` is the fraction ending within
//!    [`TOL_MM`] and [`TOL_DEG`] of the pose modulo its symmetry, recorded
//!    in `schedule.json`'s `played.pose` ([`crate::schedule::PosePlayed`])
//!    with the median settle time and each stable pose's basin, predicted
//!    (along the lifted field) and played. When the part's friction is a
//!    range, the same drops are also played at its ends and middle
//!    ([`friction`]: `played.pose.over_friction`).
//!
//! The kept schedule is the placed motion (or cycle), its `target_spec`
//! the elliptic sink placed with it. A cycle's lifted analysis (equilibria
//! and predicted basins) is its time average's, which is not what a part
//! played through the stages sees: its played drops judge it. Its point-part check (`played`, and `fit`) is the
//! centred motion's against the centred target: the placement turns and
//! shifts motion and target together, which leaves those measures
//! unchanged up to where the grid samples them.

pub mod correct;
pub mod cycle;
pub mod friction;
pub mod handover;
pub mod placement;
pub(crate) mod play;
pub mod screen;
pub mod search;
pub mod spin;
pub mod support;
pub(crate) mod target;

pub use placement::Placement;
pub use play::at_pose;
pub use search::Family;
pub use target::PoseTarget;

use crate::design::{DesignOptions, MethodDesign};
use crate::error::{Error, Result};
use crate::play::ScheduleMotion;
use crate::pose::{
    analyse, drops_estimate, equilibria, schedule_field, DropPlay, Equilibrium, LiftedField,
    PoseAnalysis,
};
use crate::progress::{Progress, ProgressMode};
use crate::work::{with_counted_progress, PLANAR_POINT_STEP_COST};

/// "At the pose": within this distance (mm) …
pub const TOL_MM: f64 = 1.0;
/// … and this angle (degrees), modulo the part's symmetry.
pub const TOL_DEG: f64 = 3.0;
/// Drops `design` plays by default.
pub const DROPS: usize = 100;
/// Drops integrated along the lifted field for the predicted basins.
pub const LIFTED_DROPS: usize = 200;

/// A designed pose target.
#[derive(Debug, Clone)]
pub struct PoseDesign {
    /// The pose target.
    pub request: PoseTarget,
    /// The stable pose of the centred motion's lifted field that was
    /// placed, with the lifted field's turning rate there, −∂θ'/∂θ (1/s);
    /// `None` for a cycle ([`cycle`]), placed on its played pose.
    pub centred: Option<(Equilibrium, f64)>,
    /// The placement the correction starts from: on the lifted field, or
    /// on the spin route on the probes' played pose ([`screen`]).
    pub lifted: Placement,
    /// The placement kept after the played correction.
    pub placement: Placement,
    /// The rounds of the played correction.
    pub rounds: Vec<correct::Round>,
    /// The centred motion's synthesis, its kept schedule replaced by the
    /// placed one, whose `played.pose` holds the part's played drops.
    pub method: MethodDesign,
    /// The spin added to the synthesized sink ([`spin`]), `None` for a
    /// part with a 180° symmetry (the elliptic sink alone).
    pub spin: Option<spin::Spin>,
    /// The kept cycle's stage lengths ([`cycle::Stages`]), `None` without
    /// a spin.
    pub stages: Option<cycle::Stages>,
    /// The spin candidates judged by play ([`screen`]), empty for a part
    /// with a 180° symmetry.
    pub screened: Vec<screen::Screened>,
    /// The lifted field of the placed schedule: equilibria and predicted basins.
    pub analysis: PoseAnalysis,
    /// The placed segments scaled into the shaker limits their motion was
    /// synthesized within (`placement::within_limits`), one line each.
    pub scaled: Vec<String>,
}

/// Designs the pose target `req` (module docs), playing `drops` drops.
///
/// # Errors
/// The synthesis's; a centred motion that gives the part no stable pose in
/// the region; a placed motion that loses contact somewhere in the region.
///
/// ```no_run
/// use platefield::pose::design::{design_pose, PoseTarget, DROPS};
/// let req = PoseTarget::load(std::path::Path::new("targets/pose_rectangle.json"))?.unwrap();
/// let d = design_pose(&req, &Default::default(), DROPS)?;
/// let played = d.method.kept().schedule.played.as_ref().unwrap().pose.as_ref().unwrap();
/// println!("{:.0} % at the pose", 100.0 * played.pose_fraction);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn design_pose(req: &PoseTarget, opts: &DesignOptions, drops: usize) -> Result<PoseDesign> {
    // A pose design takes minutes (a synthesis alone is a large share of
    // it): its work is stated first, under --quiet too.
    crate::progress::say(&announce(req, drops));
    let grid = req.target.grid.unwrap_or(crate::field::Grid::DEFAULT);
    let Centred {
        mut method,
        origin,
        spin: spun,
        screened,
    } = centred_motion(req, opts, &grid)?;
    let spin = spun.map(|s| s.0);
    let stages = spun.map(|s| s.2);
    let family = placement::family(spin.is_some());
    let (centred, lifted) = lifted_start(req, &origin, &grid, spun.map(|s| s.1))?;
    let rests = correct::rest_symmetry(req.part.symmetry(), spin.is_some());
    let (kept, rounds) = correct::correct(req, (&origin, rests), lifted)?;
    let mut target = req.target.clone();
    target.field = family.field(kept.shift, kept.angle.to_degrees());
    let (mut schedule, scaled) = kept.schedule_scaled(&origin, Some(target))?;
    // What is written must load again (`platefield export`, `verify`).
    schedule.validate()?;
    if !opts.runtime.quiet {
        for line in &scaled {
            crate::progress::say(&format!(
                "note: the placed motion is scaled into the shaker limits: {line}"
            ));
        }
    }
    let field = schedule_field(&schedule, &grid)?;
    let analysis = analyse(&req.part, &field, req.region, LIFTED_DROPS);
    let rate = play::play_rate(req, &analysis, spin.is_some());
    let label = field_label(spin.zip(stages), spin::needs_spin(req.part.symmetry()));
    let played = play_drops(req, &schedule, (&analysis, label, rate), drops, opts)?;
    if let Some(p) = schedule.played.as_mut() {
        p.pose = Some(played);
    }
    let chosen = method.chosen;
    method.candidates[chosen].schedule = schedule;
    Ok(PoseDesign {
        request: req.clone(),
        centred,
        lifted,
        placement: kept,
        rounds,
        method,
        spin,
        stages,
        screened,
        analysis,
        scaled,
    })
}

/// What the kept schedule plays, as the design's summary names it: the
/// cycle of `kept` (its spin and stages), else the elliptic sink alone,
/// said to rest a part that `needs_spin` at the asked pose or half a turn
/// from it when no spin candidate was kept.
fn field_label(kept: Option<(spin::Spin, cycle::Stages)>, needs_spin: bool) -> String {
    let family = placement::family(kept.is_some());
    match kept {
        Some((s, st)) => format!(
            "a cycle of {:.1} s of the {}, translation × {}, plus a spin of {} rad/s² at phase {} rad, then {:.1} s of the {} placed on its rest (the spin stage as long as it takes to hand parts over to the ellipse, measured by play; the ellipse stage ln(d)/λ from its slowest lifted rate and the hand-over's worst turn; its lifted field: the stages' time average)",
            st.spin_s,
            family.label(),
            s.translation,
            s.alpha,
            s.phase,
            st.ellipse_s,
            placement::family(false).label()
        ),
        None if needs_spin => format!(
            "one synthesized motion: {} alone, since no spin candidate hands the part over to it (the screen table): it rests the part at the asked pose or half a turn from it, about half the drops each",
            family.label()
        ),
        None => format!("one synthesized motion: {}", family.label()),
    }
}

/// Where the correction starts: a cycle's placement onto the asked pose
/// from its `played` pose on the centred motion; else the lifted field's
/// stable pose of `origin` nearest the asked one (with its turning rate)
/// placed onto it.
///
/// # Errors
/// `origin`'s field loses contact on `grid`; its lifted field has no
/// stable pose in the region.
fn lifted_start(
    req: &PoseTarget,
    origin: &crate::schedule::Schedule,
    grid: &crate::field::Grid,
    played: Option<crate::pose::Pose>,
) -> Result<(Option<(Equilibrium, f64)>, Placement)> {
    let n = req.part.symmetry();
    if let Some(p) = played {
        return Ok((None, Placement::onto(&p, &req.pose, n)));
    }
    let field = schedule_field(origin, grid)?;
    let lifted_field = LiftedField::new(&field, &req.part.body);
    let eqs = equilibria(&lifted_field, &req.region);
    let centred = placement::centred_pose(&eqs, &req.pose, n).ok_or_else(|| {
        Error::Unreachable(format!(
            "the synthesized sink gives the part no stable pose in the region ({} equilibria, none stable)",
            eqs.len()
        ))
    })?;
    let rate = -lifted_field.jacobian(centred.pose)[(2, 2)];
    Ok((
        Some((centred, rate)),
        Placement::onto(&centred.pose, &req.pose, n),
    ))
}

/// The work `design_pose` will do, said before it starts.
fn announce(req: &PoseTarget, drops: usize) -> String {
    let at_ends = if req.friction_ends().is_some() {
        " at the middle and each end of the friction range"
    } else {
        ""
    };
    let periods = cycle::SETTLE_PERIODS;
    let longest = (cycle::settle_seconds(screen::CYCLE_S, 2.0 * cycle::MAX_STAGE_S)).ceil();
    let (syntheses, screen) = if spin::needs_spin(req.part.symmetry()) {
        let n = spin::CANDIDATES.len();
        let screen = format!(
            ", up to {n} spin candidates ({n} more with r* halved when none is kept) × {} probes × {} s on the spun sink, × {} × {} frictions × {} s for the spin stage's hand-over and × {} s or {periods} periods of its placed cycle with the ellipse (at most {longest} s){at_ends}",
            screen::PROBES,
            screen::PROBE_S,
            handover::RESTS,
            handover::FRICTIONS,
            cycle::MAX_STAGE_S,
            screen::CYCLE_S,
        );
        ("two syntheses (about a minute", screen)
    } else {
        ("one synthesis (about half a minute", String::new())
    };
    let (ends, range) = match crate::design::stacked::ranged(&req.target) {
        Some(_) => (
            " at each end of the friction range",
            format!(
                ", then the same drops again at {} more frictions over the range (its middle is that play)",
                friction::PER_RANGE - 1
            ),
        ),
        None => ("", String::new()),
    };
    format!(
        "pose: {syntheses} of CPU){screen}, then at most {} rounds of {} probes × {} s{ends} and {drops} drops of ≥ {} s on the planar simulator{range} (about 0.2 s of CPU per 20 s drop){}",
        correct::ROUNDS,
        correct::PROBES,
        correct::PROBE_S,
        play::MIN_PLAY_S,
        if spin::needs_spin(req.part.symmetry()) {
            format!("; on a cycle each probe and drop plays at least {periods} periods")
        } else {
            String::new()
        }
    )
}

/// The placed `schedule`'s `drops` drops, played with progress on stderr
/// (`play::play_ends`), and again over the pose target's friction range when it
/// states one (`friction::over_range`); `label` names the field (the
/// motion or cycle).
///
/// # Errors
/// A schedule that is not one motion, or whose field cannot be computed
/// at a friction of the range.
fn play_drops(
    req: &PoseTarget,
    schedule: &crate::schedule::Schedule,
    (analysis, label, rate): (&PoseAnalysis, String, f64),
    drops: usize,
    opts: &DesignOptions,
) -> Result<crate::schedule::PosePlayed> {
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let progress = opts.runtime.progress();
    let duration = play::drop_seconds(rate, sm.period());
    let settings = &schedule.settings;
    let (played, ends) = watched(
        "pose drops",
        (req, &sm, settings, drops, duration),
        progress,
        || play::play_ends(req, &sm, settings, (analysis, label, rate), drops),
    );
    let Some(range) = crate::design::stacked::ranged(&req.target) else {
        return Ok(played);
    };
    // The range's middle is the play above: its ends only are replayed.
    let replays = (
        req,
        &sm,
        settings,
        drops * (friction::PER_RANGE - 1),
        duration,
    );
    watched("pose drops over friction", replays, progress, || {
        let own = Some((ends.as_slice(), analysis));
        friction::over_range_after(req, schedule, (played, own), rate, Some(range))
    })
}

/// Runs `f`, which plays `drops` drops of `duration_s` seconds each of
/// the pose target's part through `sm` (the `plays`), with its progress on
/// stderr in thousands of counted planar steps (the total from
/// [`drops_estimate`]) unless `progress` is quiet and the estimate is
/// under 10 s (longer work shows its progress when quiet too).
fn watched<T>(
    label: &str,
    plays: (
        &PoseTarget,
        &ScheduleMotion,
        &crate::field::FieldSettings,
        usize,
        f64,
    ),
    progress: ProgressMode,
    f: impl FnOnce() -> T,
) -> T {
    let (req, sm, settings, drops, duration_s) = plays;
    let play = DropPlay::new(settings, duration_s);
    watched_play(label, (req, sm, &play, drops), progress, f)
}

/// [`watched`] for drops played with `play`.
pub(crate) fn watched_play<T>(
    label: &str,
    plays: (&PoseTarget, &ScheduleMotion, &DropPlay, usize),
    progress: ProgressMode,
    f: impl FnOnce() -> T,
) -> T {
    let (req, sm, play, drops) = plays;
    let estimate = drops_estimate(&req.part, sm, drops, play);
    let steps = estimate.steps() / PLANAR_POINT_STEP_COST;
    let total = (steps / 1e3).ceil() as u64;
    let long = estimate.announcement(crate::work::threads()).is_some();
    let mode = if long { ProgressMode::Auto } else { progress };
    let progress = Progress::new(label, "k steps", total, mode);
    with_counted_progress(&progress, f)
}

/// The centred motion the placement moves, its synthesis, the spin
/// candidates judged by play and the kept one with its cycle's played
/// pose: for a part without a 180° symmetry the cycle ([`cycle`]) of the
/// isotropic sink with the spin [`screen::choose`] keeps from
/// [`spin::CANDIDATES`], or else from the same with r* halved
/// ([`spin::Spin::finer`]), and the elliptic sink; else (or when neither
/// keeps one) the elliptic sink alone.
///
/// # Errors
/// The synthesis's; a spun motion losing contact on `grid`.
fn centred_motion(
    req: &PoseTarget,
    opts: &DesignOptions,
    grid: &crate::field::Grid,
) -> Result<Centred> {
    let ellipse =
        placement::synthesize_centred(req, placement::family(false), opts, &opts.synthesis)?;
    if !spin::needs_spin(req.part.symmetry()) {
        return Ok(Centred::ellipse(ellipse, Vec::new()));
    }
    let method =
        placement::synthesize_centred(req, placement::family(true), opts, &opts.synthesis)?;
    let sink = method.kept().schedule.clone();
    let stage = cycle::EllipseStage::new(req, ellipse.kept().schedule.clone(), grid)?;
    let lattice = |spins: &[spin::Spin], label| {
        screen_lattice(req, (&sink, &stage), grid, spins, (label, opts))
    };
    let (mut all, mut kept) = lattice(&spin::CANDIDATES, "pose spin screen")?;
    if kept.is_none() {
        let finer = spin::CANDIDATES.map(|s| s.finer());
        let (more, k) = lattice(&finer, "pose spin screen, r* halved")?;
        all.extend(more);
        kept = k;
    }
    let Some((k, rest, pose, stages)) =
        kept.and_then(|k| Some((k.spin, k.spin_rest?, k.pose?, k.stages?)))
    else {
        return Ok(Centred::ellipse(ellipse, all));
    };
    let origin = cycle::cycle(&spin::spun(&sink, k)?, &stage, &rest, stages)?;
    Ok(Centred {
        method,
        origin,
        spin: Some((k, pose, stages)),
        screened: all,
    })
}

/// The spins of `lattice` added to the centred `sink` and judged by play
/// in their cycles with `stage` ([`screen::choose`]), the work stated
/// first under `label`.
///
/// # Errors
/// A spun motion losing contact on `grid`; a play's.
fn screen_lattice(
    req: &PoseTarget,
    (sink, stage): (&crate::schedule::Schedule, &cycle::EllipseStage),
    grid: &crate::field::Grid,
    lattice: &[spin::Spin],
    (label, opts): (&str, &DesignOptions),
) -> Result<(Vec<screen::Screened>, Option<screen::Screened>)> {
    let tried = spin::try_all(req, sink, grid, lattice)?;
    let plays = if req.friction_ends().is_some() { 3 } else { 1 };
    // Per candidate played: the spun sink's probes for PROBE_S, its spin
    // stage's hand-over (both rests at three frictions for MAX_STAGE_S),
    // then its placed cycle's probes at each friction, each CYCLE_S or
    // SETTLE_PERIODS cycle periods (counted in probes of PROBE_S on the
    // sink).
    let handover =
        (handover::RESTS * handover::FRICTIONS) as f64 * cycle::MAX_STAGE_S / screen::PROBE_S;
    let probes: usize = tried
        .iter()
        .filter(|t| !t.stable.is_empty())
        .filter_map(|t| screen::stages_of(req, stage, t))
        .map(|st| {
            let per_cycle = cycle::settle_seconds(screen::CYCLE_S, st.period()) / screen::PROBE_S;
            screen::PROBES * (1 + (per_cycle * plays as f64).ceil() as usize)
                + handover.ceil() as usize
        })
        .sum();
    let sm = ScheduleMotion::from_schedule(sink)?;
    watched(
        label,
        (req, &sm, &sink.settings, probes, screen::PROBE_S),
        opts.runtime.progress(),
        || screen::choose(req, (sink, stage), &tried),
    )
}

/// [`centred_motion`]'s outcome.
struct Centred {
    method: MethodDesign,
    origin: crate::schedule::Schedule,
    /// The kept spin, its cycle's played pose on the centred motion and
    /// its stage lengths.
    spin: Option<(spin::Spin, crate::pose::Pose, cycle::Stages)>,
    screened: Vec<screen::Screened>,
}

impl Centred {
    /// The elliptic sink alone, after the `screened` spins (if any).
    fn ellipse(method: MethodDesign, screened: Vec<screen::Screened>) -> Centred {
        let origin = method.kept().schedule.clone();
        Centred {
            method,
            origin,
            spin: None,
            screened,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The summary names the ellipse alone as resting the part at the pose
    /// or half a turn from it only for a part that needed a spin and got
    /// none; a part with a 180° symmetry gets the plain name.
    #[test]
    fn the_ellipse_alone_is_named_for_what_it_does() {
        let lone = field_label(None, true);
        assert!(
            lone.contains("no spin candidate hands the part over"),
            "{lone}"
        );
        assert!(lone.contains("half a turn from it"), "{lone}");
        let plain = field_label(None, false);
        assert!(!plain.contains("no spin"), "{plain}");
        assert!(plain.starts_with("one synthesized motion: "), "{plain}");
    }

    /// The estimate stated before a pose design names the drops played
    /// again over a friction range exactly when the pose target has one.
    #[test]
    fn announce_names_the_range_plays() {
        let path = std::path::Path::new("targets/pose_bracket.json");
        let mut req = PoseTarget::load(path).unwrap().unwrap();
        let extra = "the same drops again at 2 more frictions over the range";
        let probes = "probes × 60 s at each end of the friction range";
        assert!(!announce(&req, DROPS).contains(extra));
        assert!(!announce(&req, DROPS).contains(probes));
        req.target.friction = Some(crate::request::FrictionSpec::range(0.24, 0.36));
        assert!(announce(&req, DROPS).contains(extra));
        assert!(announce(&req, DROPS).contains(probes));
    }

    /// The screen's cost stated first names what it plays: every probe
    /// start and its twin on the spun sink for PROBE_S, the two rests at
    /// three frictions for the spin stage's hand-over, then the probes on
    /// the placed cycle for as long as the drops play a cycle; and the
    /// second screen, of the lattice with r* halved, when none is kept.
    #[test]
    fn announce_states_the_screen_played() {
        let path = std::path::Path::new("targets/pose_bracket.json");
        let req = PoseTarget::load(path).unwrap().unwrap();
        let said = format!(
            "{} probes × {} s on the spun sink, × 2 × 3 frictions × {} s for the spin stage's hand-over and × {} s or",
            screen::PROBES,
            screen::PROBE_S,
            cycle::MAX_STAGE_S,
            play::MIN_PLAY_S
        );
        assert_eq!(handover::RESTS, 2);
        let mu =
            handover::frictions(&req, crate::dynamics::Friction::uniform(0.3)).map(|f| f.kinetic);
        assert!(
            (mu[0] - 0.3).abs() + (mu[1] - 0.24).abs() + (mu[2] - 0.36).abs() < 1e-12,
            "{mu:?}"
        );
        assert_eq!(screen::PROBES, 32);
        let refined = "up to 7 spin candidates (7 more with r* halved when none is kept)";
        assert_eq!(spin::CANDIDATES.len(), 7);
        assert!(announce(&req, DROPS).contains(refined));
        assert!(
            announce(&req, DROPS).contains(&said),
            "{}",
            announce(&req, DROPS)
        );
    }
}
