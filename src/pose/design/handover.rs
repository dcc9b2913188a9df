//! The spin stage's length, measured by play: how long the spin takes to
//! hand a part over to the ellipse.
//!
//! **Why.** The spin stage's job in the cycle ([`super::cycle`]) is done
//! far from the spin's own rest: every period it must turn a part that
//! the ellipse stage left at its rival rest, 180° from the asked pose,
//! back into the half of the turn that the ellipse takes to the asked
//! pose. `cycle::Stages::derive` sizes the stage from the spin's
//! slowest lifted rate at its rest, ln(d)/λ, a decay that holds near that
//! rest only. Played from the rival rest the turn takes longer or
//! shorter than that estimate, and some spins turn a part on and on
//! rather than bring it to rest, so that where the stage ends decides
//! where the part is handed over. On the bracket the estimate was too
//! short for its kept spin to carry the rival rest into the kept half,
//! and a fifth of its drops stayed there; on the triangle it was past
//! the best hand-over (`docs/parts.md`, "The spin stage measured: the
//! hand-over").
//!
//! **Rule.** The placed cycle's spin stage is played steadily from the
//! ellipse stage's two rests: the asked pose (where the placement puts
//! the kept rest) and the same turned by 180°, at the pose target's
//! friction and at the two ends of its friction range, or of μ ± 20 %
//! ([`crate::play::sensitivity`]'s default band) when it states none,
//! for up to [`super::cycle::MAX_STAGE_S`], each part's pose read at the
//! end of every motion cycle. The stage lasts until the first cycle end
//! at which all six parts lie within [`HANDOVER_DEG`] of the asked angle
//! (modulo the part's symmetry). Where no cycle end reaches that, it
//! lasts until the one whose worst part is nearest.
//!
//! **Why 45°.** The ellipse turns a part by its second moments only, with
//! a torque ∝ sin 2Δθ about its kept rest ([`super::placement`]): within
//! 45° of the rest the torque grows with Δθ; past 45° it falls, to nothing
//! at the unstable pose 90° away. The ellipse stage then lasts as long as
//! that torque takes from the hand-over's worst turn
//! (`cycle::Stages::handed_over`): at most ln(tan 45°/tan 3°)/λ
//! = 2.95/λ from within 45°, with half the kept half left as margin, and
//! longer from nearer 90° (5.38/λ from 85°), where a spin that hands over
//! no better leaves a part.

use super::cycle::MAX_STAGE_S;
use super::search::pose_error;
use super::PoseTarget;
use crate::dynamics::Friction;
use crate::error::Result;
use crate::play::ScheduleMotion;
use crate::pose::{play_part, DropPlay, Pose};
use crate::scene::FrictionSpec;
use crate::schedule::Schedule;

/// Where the spin hands a part over to the ellipse: within this turn of
/// the asked pose (degrees; module docs).
pub const HANDOVER_DEG: f64 = 45.0;

/// Parts played per friction: the ellipse stage's kept and rival rests.
pub const RESTS: usize = 2;

/// Frictions played: the target's and the two ends of its range (or of
/// μ ± 20 %).
pub const FRICTIONS: usize = 3;

/// The spin stage's measured hand-over (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Handover {
    /// Seconds of the spin stage: whole motion cycles.
    pub seconds: f64,
    /// The worst part's turn from the asked pose at that time (degrees):
    /// at most [`HANDOVER_DEG`] when the spin hands every part over.
    pub worst_deg: f64,
}

/// The three frictions the hand-over is played at: the target's, then the
/// ends of its range, or of μ ± 20 % when it states none (module docs).
pub(crate) fn frictions(req: &PoseTarget, nominal: Friction) -> [Friction; FRICTIONS] {
    let [lo, hi] = req.friction_ends().unwrap_or_else(|| {
        let band = crate::play::sensitivity::AROUND_FRACTION;
        let v = FrictionSpec::around(nominal, band).values(2);
        [v[0], v[v.len() - 1]]
    });
    [nominal, lo, hi]
}

/// The spin stage of the placed cycle `placed` (its first segment) played
/// steadily, one motion cycle per schedule period.
fn steady_spin(placed: &Schedule) -> Option<Schedule> {
    let mut seg = placed.segments.first()?.clone();
    seg.motion.as_ref()?;
    seg.ramp_cycles = None;
    seg.cycles = 1;
    seg.weight = 1.0;
    let mut out = placed.clone();
    out.segments = vec![seg];
    out.derive();
    Some(out)
}

/// The hand-over of the placed cycle `placed` for `req` (module docs);
/// `None` when `placed` has no six-signal spin stage or a part loses
/// contact.
///
/// # Errors
/// The spin stage cannot be played.
pub(crate) fn handover(req: &PoseTarget, placed: &Schedule) -> Result<Option<Handover>> {
    Ok(worst_turns(req, placed)?.and_then(|(worst, period)| first_within(&worst, period)))
}

/// At every motion-cycle end of the steadily played spin stage of
/// `placed`, the largest turn from the asked pose (degrees) over both
/// rests and the three frictions, with the motion's period (s); `None`
/// as [`handover`].
///
/// # Errors
/// The spin stage cannot be played.
pub(crate) fn worst_turns(req: &PoseTarget, placed: &Schedule) -> Result<Option<(Vec<f64>, f64)>> {
    let Some(spin) = steady_spin(placed) else {
        return Ok(None);
    };
    let asked = req.pose;
    let rival = Pose {
        r: asked.r,
        theta: asked.theta + std::f64::consts::PI,
    };
    let n = req.part.symmetry();
    let mut worst: Vec<f64> = Vec::new();
    let mut period = 0.0;
    for friction in frictions(req, spin.settings.friction) {
        let mut at = spin.clone();
        at.settings.friction = friction;
        let sm = ScheduleMotion::from_schedule(&at)?;
        period = sm.period();
        let play = DropPlay::new(&at.settings, MAX_STAGE_S);
        for run in play_part(&req.part, &sm, &[asked, rival], &play) {
            let Ok((_, track)) = run else {
                return Ok(None);
            };
            let turns = track
                .iter()
                .map(|p| pose_error(p, &asked, n).1.abs().to_degrees());
            if worst.is_empty() {
                worst = turns.collect();
            } else {
                worst.iter_mut().zip(turns).for_each(|(w, t)| *w = w.max(t));
            }
        }
    }
    Ok(Some((worst, period)))
}

/// The first cycle end (1-based, `period` s each) whose worst turn
/// `worst[i]` is within [`HANDOVER_DEG`], else the one with the least.
pub(crate) fn first_within(worst: &[f64], period: f64) -> Option<Handover> {
    let i = worst
        .iter()
        .position(|&w| w <= HANDOVER_DEG)
        .or_else(|| (0..worst.len()).min_by(|&a, &b| worst[a].total_cmp(&worst[b])))?;
    Some(Handover {
        seconds: (i + 1) as f64 * period,
        worst_deg: worst[i],
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first cycle end within 45° is kept, not the best one; with
    /// none within, the least worst turn; nothing played, none.
    #[test]
    fn first_within_takes_the_first_hand_over() {
        let h = first_within(&[170.0, 90.0, 44.0, 10.0, 60.0], 0.5).unwrap();
        assert_eq!(h.seconds, 1.5);
        assert_eq!(h.worst_deg, 44.0);
        let none = first_within(&[170.0, 90.0, 50.0, 80.0], 0.25).unwrap();
        assert_eq!(none.seconds, 0.75);
        assert_eq!(none.worst_deg, 50.0);
        assert!(first_within(&[], 0.5).is_none());
    }

    /// Exploration: the worst turn of a schedule's spin stage (its first
    /// segment) each second, `PF_SCHEDULE` a cycle's `schedule.json`
    /// (default the shipped bracket's) for `PF_TARGET` (default
    /// targets/pose_bracket.json). The design before the hand-over:
    /// `git show accb742:results/poses/bracket/schedule.json > /tmp/b.json`,
    /// then `PF_SCHEDULE=/tmp/b.json cargo test --release --lib
    /// explore_worst_turns -- --ignored --nocapture`.
    #[test]
    #[ignore = "exploration: PF_SCHEDULE=…/schedule.json"]
    fn explore_worst_turns() {
        let env = |k: &str, d: &str| std::env::var(k).unwrap_or(d.into());
        let target = env("PF_TARGET", "targets/pose_bracket.json");
        let req = PoseTarget::load(std::path::Path::new(&target))
            .unwrap()
            .unwrap();
        let path = env("PF_SCHEDULE", "results/poses/bracket/schedule.json");
        let placed = Schedule::load(std::path::Path::new(&path)).unwrap();
        let (worst, period) = worst_turns(&req, &placed).unwrap().unwrap();
        let every = (1.0 / period).round().max(1.0) as usize;
        for (i, w) in worst.iter().enumerate().skip(every - 1).step_by(every) {
            println!("{:5.1} s: worst turn {w:5.1}°", (i + 1) as f64 * period);
        }
        println!("hand-over: {:?}", first_within(&worst, period));
    }
}
