//! A pose design played over the part's friction range: the part's
//! friction is the user's, rarely known within ±20 %, so a design judged at
//! one μ only may be lucky. When the target (or the part file, whose
//! friction a pose target takes when it states none: [`super::PoseTarget`])
//! gives a range, the design's drops are played again at its ends (its
//! middle is the design's own play, `over_range_after`; [`over_range`]
//! plays all three: [`FrictionSpec::values`], [`PER_RANGE`] per range, as
//! [`crate::design::stacked`] fits fields) and recorded in
//! `schedule.json`'s `played.pose.over_friction`
//! ([`crate::schedule::PoseOverFriction`]); its `worst_pose_fraction` is
//! the least over them. The design itself is synthesized at the middle,
//! its spin screened and its placement centred over the range
//! ([`super::screen`], `pose::design::correct`); `pose_fraction` stays the
//! middle's.
//!
//! **Which μ the drops take.** `play::play_ends` builds its
//! [`crate::pose::DropPlay`] from the settings it is given, and a design
//! passes the schedule's, whose friction is the target's nominal (the
//! middle of a range). Here each value is played with the schedule's
//! settings at that friction, so every support point's Coulomb law in the
//! planar simulator takes it, and each drop's end is classified against
//! the lifted field computed at it ([`crate::pose::schedule_field`] with
//! that friction). Every friction plays the same starts for the same time
//! (the middle's: `play::play_rate`).
//!
//! **Why the pose moves with μ.** The placement puts the middle's stable
//! pose on the asked one; at another μ the field is another field, not
//! the same shape at another speed. One synthesized motion's slip
//! direction leads the plate velocity by δ = asin(μg/A) (`synth` docs),
//! so a friction error turns the field about every point: the elliptic
//! sink's principal axes turn with μ and the part's long axis follows.
//! On the shipped designs the elliptic sinks' poses turn by a few degrees
//! over μ ± 20 % and barely shift, while the slowest lifted rate barely
//! changes (the synthesized field's strength is not ∝ μ); the bracket's
//! spin route, whose angle is a balance of the spin's torque against the
//! sink's, turns by more, enough to put its drops outside the tolerance at
//! one end (measured: `platefield study poses-friction`,
//! `results/poses_friction.md`). On a schedule whose field is
//! mirror-symmetric in x and y at every μ (line sinks at 0°, 90°, 180°,
//! 270°) the pose cannot move and only the speed changes, all lifted
//! rates by one factor (less than μ's own ratio);
//! `tests/unit/pose_friction.rs` checks both.

use super::correct::median;
use super::play::{play_ends, play_rate};
use super::search::{nearest_stable, pose_error};
use super::{PoseTarget, LIFTED_DROPS};
use crate::dynamics::Friction;
use crate::error::Result;
use crate::play::ScheduleMotion;
use crate::pose::{analyse, schedule_field, Pose, PoseAnalysis};
use crate::request::FrictionSpec;
use crate::schedule::{PoseAtFriction, PoseOverFriction, PosePlayed, Schedule};

/// Frictions played per range: its ends and middle.
pub const PER_RANGE: usize = 3;

/// `nominal` (the design's drops at the schedule's friction) with the
/// same drops played over `range`'s values (module docs), the middle
/// again so that every row carries its played rest pose, timed by the
/// slowest decay `rate` (1/s); unchanged when `range` is `None` (an exact
/// friction: `over_friction` stays absent).
///
/// # Errors
/// A schedule whose field cannot be computed at one of the values.
///
/// ```no_run
/// use platefield::pose::design::{design_pose, friction, PoseTarget, DROPS};
/// use platefield::request::FrictionSpec;
/// let req = PoseTarget::load(std::path::Path::new("targets/pose_rectangle.json"))?.unwrap();
/// let d = design_pose(&req, &Default::default(), DROPS)?;
/// let schedule = &d.method.kept().schedule;
/// let nominal = schedule.played.as_ref().unwrap().pose.clone().unwrap();
/// let rate = friction::rate(&d);
/// let range = FrictionSpec::range(0.24, 0.36);
/// let p = friction::over_range(&req, schedule, nominal, rate, Some(range))?;
/// println!("worst {:.0} %", 100.0 * p.over_friction.unwrap().worst_pose_fraction);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn over_range(
    req: &PoseTarget,
    schedule: &Schedule,
    nominal: PosePlayed,
    rate: f64,
    range: Option<FrictionSpec>,
) -> Result<PosePlayed> {
    over_range_after(req, schedule, (nominal, None), rate, range)
}

/// A design's own drops at the schedule's friction: each drop's end
/// (`None`: lost) and the lifted analysis they were judged by.
pub(crate) type OwnPlay<'a> = (&'a [Option<Pose>], &'a PoseAnalysis);

/// [`over_range`] after the design's own play `nominal` at the schedule's
/// friction, with its drops' ends and the lifted analysis it was judged
/// by when known: the range's value equal to that friction (its middle)
/// takes that play instead of playing the same drops again (the same
/// starts, time and friction: the same row).
///
/// # Errors
/// A schedule whose field cannot be computed at one of the values.
pub(crate) fn over_range_after(
    req: &PoseTarget,
    schedule: &Schedule,
    (nominal, own): (PosePlayed, Option<OwnPlay>),
    rate: f64,
    range: Option<FrictionSpec>,
) -> Result<PosePlayed> {
    let Some(range) = range else {
        return Ok(nominal);
    };
    let at = range
        .values(PER_RANGE)
        .into_iter()
        .map(|f| match own {
            Some((ends, analysis)) if f == schedule.settings.friction => {
                Ok(entry(req, f, &nominal, analysis, ends))
            }
            _ => play_at(req, schedule, f, rate, nominal.drops),
        })
        .collect::<Result<Vec<_>>>()?;
    let worst_pose_fraction = at.iter().map(|a| a.pose_fraction).fold(1.0, f64::min);
    Ok(PosePlayed {
        over_friction: Some(PoseOverFriction {
            range,
            worst_pose_fraction,
            at,
        }),
        ..nominal
    })
}

/// The slowest decay rate `design` timed `d`'s drops by
/// (`play::play_rate`).
pub fn rate(d: &super::PoseDesign) -> f64 {
    play_rate(&d.request, &d.analysis, d.spin.is_some())
}

/// `drops` drops of the pose target's part played through `schedule` with
/// the parts' friction `friction`, judged against the lifted field at it.
///
/// # Errors
/// A schedule whose field cannot be computed.
pub(crate) fn play_at(
    req: &PoseTarget,
    schedule: &Schedule,
    friction: Friction,
    rate: f64,
    drops: usize,
) -> Result<PoseAtFriction> {
    let mut at = schedule.clone();
    at.settings.friction = friction;
    let grid = req.target.grid.unwrap_or(crate::field::Grid::DEFAULT);
    let analysis = analyse(
        &req.part,
        &schedule_field(&at, &grid)?,
        req.region,
        LIFTED_DROPS,
    );
    let sm = ScheduleMotion::from_schedule(&at)?;
    let (p, ends) = play_ends(
        req,
        &sm,
        &at.settings,
        (&analysis, String::new(), rate),
        drops,
    );
    Ok(entry(req, friction, &p, &analysis, &ends))
}

/// Drops ending within this angle (degrees, modulo symmetry) of the asked
/// pose count for the played offset.
pub const NEAR_DEG: f64 = 30.0;

/// The median distance (mm) and the median signed angle (degrees, modulo
/// symmetry) from the asked pose of the ends within [`NEAR_DEG`] of it:
/// where the played drops come to rest near it; `None` when none does.
fn played_offset(req: &PoseTarget, ends: &[Option<Pose>]) -> Option<[f64; 2]> {
    let n = req.part.symmetry();
    let (d, t): (Vec<f64>, Vec<f64>) = ends
        .iter()
        .flatten()
        .map(|e| pose_error(e, &req.pose, n))
        .map(|(d, t)| (1e3 * d, t.to_degrees()))
        .filter(|(_, t)| t.abs() <= NEAR_DEG)
        .unzip();
    Some([median(d)?, median(t)?])
}

/// One friction's row from its played drops `p` and lifted `analysis`.
fn entry(
    req: &PoseTarget,
    friction: Friction,
    p: &PosePlayed,
    analysis: &PoseAnalysis,
    ends: &[Option<Pose>],
) -> PoseAtFriction {
    let n = req.part.symmetry();
    let near = nearest_stable(&analysis.equilibria, &req.pose, n, req.part.radius());
    PoseAtFriction {
        friction,
        pose_fraction: p.pose_fraction,
        median_settle_s: p.median_settle_s,
        lost: p.lost,
        stable: p.stable.clone(),
        distinct_stable: p.distinct_stable,
        lifted_offset: near.map(|e| {
            let (d, t) = pose_error(&e.pose, &req.pose, n);
            [1e3 * d, t.to_degrees()]
        }),
        lifted_rates: near.map(|e| e.rates.map(|r| -r)),
        played_offset: played_offset(req, ends),
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/pose_friction.rs"]
mod friction_range_tests;
