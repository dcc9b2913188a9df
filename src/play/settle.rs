//! The start-up transient of a played part, and a warm-up long enough for
//! it to die out.
//!
//! A part is placed on the plate at rest relative to it (u = 0), not on
//! its periodic orbit, and its motion relaxes onto the orbit geometrically:
//! near the orbit the deviation is multiplied each schedule period by the
//! period map's Jacobian, whose spectral radius ρ sets how many periods
//! the relaxation takes. Friction damps the slip in a few cycles for most
//! motions (ρ ≈ 0.1–0.5 per cycle), but a motion that keeps the part slipping
//! with a large relative velocity V relaxes slowly: the mean friction force
//! changes with the part's mean velocity only at a rate of order μ_k g / V,
//! and ρ ≈ exp(−T μ_k g / V) comes close to 1. On the jet's synthesized
//! motion (`results/jet/schedule.json`, an in-plane ratchet of 45 m/s²,
//! V ≈ 0.2 m/s) `verify` with 1 warm-up period (10 cycles) reports
//! realised against predicted tens of per cent off, and with a few
//! periods more agrees with it — the prediction is right, the short
//! measure is taken on the transient.
//!
//! **The estimate.** The schedule is played with the part's position
//! frozen at its start point ([`super::Player::frozen`]: the same
//! transient, without the drift through a varying field that would mask
//! it), and v_k, the part's mean velocity over period k, is recorded. With
//! e_k = |v_k − v_(k−1)| falling geometrically at the rate ρ̂ = e_k / e_(k−1),
//! what the transient still adds to v_w is about Σ_(k>w) e_k = e_(w+1) / (1 − ρ̂).
//! A warm-up of w periods is enough when that is at most
//! [`SETTLE_TOL`]·max(|v_w|, [`SETTLE_FLOOR`]/[`SETTLE_TOL`]), i.e. 1e-4 of
//! the part's drift, or 1e-7 m/s for a part that hardly drifts. The
//! warm-up asked for is a minimum; it is lengthened one period at a time,
//! up to [`SETTLE_MAX_CYCLES`] primitive cycles; a part that has not
//! settled by then is reported as such, and a warm-up asked for that is
//! already that long is taken as it is.
//! A part that loses contact in the frozen play keeps the warm-up asked for
//! (the play itself reports the loss).
//!
//! **Where it is used.** `verify` (realised against the steady-state
//! prediction, [`super::measure::PlayOptions::settle`]) settles. The
//! design's judge and the studies' measures against the *target*
//! keep their fixed warm-ups (`play::windowed::MeasureOptions::settle`
//! off): a strong field gathers the parts before a slow transient dies out
//! — the synthesized motion of `targets/sink_trans.json` (a 3 s⁻¹ sink
//! slipping at up to 50 m/s²) needs several periods, by which time every
//! part sits at the centre and the settled windows measure round-off.
//! Where parts travel far during the transient, `verify --model frozen`
//! compares at the start point exactly.

use super::{PartState, Player, V2};

/// What the start-up transient may still add to the measured mean
/// velocity, relative to it.
pub(crate) const SETTLE_TOL: f64 = 1e-4;

/// ... and in absolute terms (m/s), for parts that hardly drift.
pub(crate) const SETTLE_FLOOR: f64 = 1e-7;

/// Longest warm-up the estimate may ask for, in primitive cycles of the
/// schedule (at least one period).
pub(crate) const SETTLE_MAX_CYCLES: u32 = 400;

/// A held part that has not settled by the cap has no held steady state
/// when what its transient may still add exceeds this share of its mean
/// velocity (or of [`SETTLE_FLOOR`]/[`SETTLE_TOL`] = 1 mm/s, for parts
/// that hardly drift). The judge compares realised fields to 0.1 % and
/// holds designs to shape errors of a few per cent; a point whose own
/// mean is uncertain by more than 1 % cannot take part in that measure,
/// while a slow relaxation that is still contracting (the ratchet's,
/// ρ close to 1 but below) leaves far less than that at the cap.
/// A diverging held play (ρ ≥ 1: the velocity still grows at the cap)
/// leaves an unbounded remainder and is always caught.
pub(crate) const HELD_TOL: f64 = 1e-2;

/// The warm-up found for one start point.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Settle {
    /// Warm-up periods (at least those asked for).
    pub periods: u32,
    /// False when the transient had not died out within the cap.
    pub settled: bool,
}

/// The warm-up in schedule periods, at least `asked`, after which the
/// start-up transient of a part placed at rest at `start` adds less than
/// [`SETTLE_TOL`] to its mean velocity (see the module documentation).
pub(crate) fn warmup(player: &Player<'_>, start: [f64; 2], asked: u32) -> Settle {
    let sm = player.schedule();
    let cycles: u32 = sm.segments().iter().map(|s| s.cycles).sum();
    let cap = SETTLE_MAX_CYCLES.div_ceil(cycles.max(1));
    if asked >= cap {
        // Already as long as the longest warm-up this would ask for: taken
        // as it is (judging it would double the work).
        return Settle {
            periods: asked,
            settled: true,
        };
    }
    relax(&player.frozen(), start, asked).map_or(
        Settle {
            periods: asked,
            settled: true,
        },
        |r| r.settle,
    )
}

/// A frozen part's period means until its start-up transient has died out
/// ([`relax`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Relaxation {
    /// v_k, the part's mean velocity over period k = 0, 1, … (m/s); the
    /// last is at least two periods past the warm-up found.
    pub means: Vec<V2>,
    /// The warm-up found.
    pub settle: Settle,
    /// What the transient may still add to the last mean velocity
    /// (m/s): e_(w+1)/(1 − ρ̂) of the module documentation, infinite
    /// when the differences do not shrink (ρ̂ ≥ 1).
    pub remaining: f64,
    /// The part's displacement during each segment of the last period
    /// played (m).
    pub last_period: Vec<V2>,
}

impl Relaxation {
    /// The periodic mean velocity: the last period's mean, within
    /// [`SETTLE_TOL`] of the limit (or [`SETTLE_FLOOR`] in absolute terms)
    /// when settled.
    pub(crate) fn periodic_mean(&self) -> V2 {
        self.means.last().copied().unwrap_or_else(V2::zeros)
    }

    /// Whether the held part has a steady state to measure: settled, or
    /// with at most [`HELD_TOL`] of its mean velocity still to come.
    pub(crate) fn held_steady(&self) -> bool {
        let scale = self.periodic_mean().norm().max(SETTLE_FLOOR / SETTLE_TOL);
        self.settle.settled || self.remaining <= HELD_TOL * scale
    }
}

/// Plays `frozen` (a player whose part's position is frozen, see
/// [`Player::frozen`]) from rest at `start`, period by period, until the
/// start-up transient of the part's velocity state adds less than
/// [`SETTLE_TOL`] to its mean velocity after a warm-up of at least `asked`
/// periods (the module documentation's estimate), or for
/// [`SETTLE_MAX_CYCLES`] primitive cycles (then not settled).
///
/// # Errors
/// The part loses contact.
pub(crate) fn relax(
    frozen: &Player<'_>,
    start: [f64; 2],
    asked: u32,
) -> Result<Relaxation, super::PlayLoss> {
    let sm = frozen.schedule();
    let n = sm.segments().len();
    let cycles: u32 = sm.segments().iter().map(|s| s.cycles).sum();
    let cap = SETTLE_MAX_CYCLES.div_ceil(cycles.max(1)).max(asked);
    let anchor = V2::from(start);
    let mut state = PartState::new(anchor, V2::zeros());
    let span = sm.period();
    let mut v: Vec<V2> = Vec::new();
    let mut last_period = vec![V2::zeros(); n];
    let mut w = asked;
    loop {
        // Judging w needs v_(w+1), and v_(w−1) or v_(w+2) for the rate.
        let need = (w + 2).max(3) as usize;
        while v.len() < need {
            let r0 = state.r;
            let k = v.len() as u32;
            let mut prev = r0;
            frozen.play_periods(&mut state, &anchor, k, 1, |_, seg, s| {
                if let Some(i) = seg {
                    last_period[i] = s.r - prev;
                }
                prev = s.r;
            })?;
            v.push((state.r - r0) / span);
        }
        let e = |k: usize| (v[k] - v[k - 1]).norm();
        let w_ = w as usize;
        // e_(w+1) and the rate it falls at (from e_(w+2) when w = 0).
        let next = e(w_ + 1);
        let rate = if w_ >= 1 { next / e(w_) } else { e(2) / next };
        let left = if next == 0.0 {
            0.0
        } else if rate < 1.0 {
            next / (1.0 - rate)
        } else {
            f64::INFINITY
        };
        let settled = left <= (SETTLE_TOL * v[w_].norm()).max(SETTLE_FLOOR);
        if settled || w >= cap {
            return Ok(Relaxation {
                means: v,
                settle: Settle {
                    periods: w,
                    settled,
                },
                remaining: left,
                last_period,
            });
        }
        w += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::FieldSettings;
    use crate::motion::{Axes, FourierTerm, Motion, Signals};
    use crate::play::{PlayedSegment, ScheduleMotion};

    /// An in-plane ratchet (harmonics 1 and 2 of x, no rotation): the field
    /// is uniform, so frozen and moving parts are the same, and the part
    /// slips at up to ≈ 0.2 m/s relative to the plate: a slow relaxation.
    fn ratchet() -> ScheduleMotion {
        let term = |amplitude: f64, phase: f64, harmonic: u32| FourierTerm {
            amplitude,
            phase,
            harmonic,
        };
        let signals = Signals {
            period: 0.03,
            linear: Axes {
                x: vec![term(30.0, 0.0, 1), term(15.0, 0.5, 2)],
                y: Vec::new(),
                z: Vec::new(),
            },
            angular: Axes::default(),
        };
        let seg = PlayedSegment::moving("ratchet", Motion::Signals(signals), 10);
        ScheduleMotion::new(vec![seg]).expect("one segment")
    }

    /// Mean velocity over `periods` periods after `warm`, played directly.
    fn played(player: &Player<'_>, warm: u32, periods: u32) -> V2 {
        let anchor = V2::new(0.01, -0.01);
        let mut state = PartState::new(anchor, V2::zeros());
        player
            .play_periods(&mut state, &anchor, 0, warm, |_, _, _| {})
            .expect("contact");
        let r0 = state.r;
        player
            .play_periods(&mut state, &anchor, warm, periods, |_, _, _| {})
            .expect("contact");
        (state.r - r0) / (f64::from(periods) * player.schedule().period())
    }

    /// The warm-up found is long enough that the played mean velocity
    /// agrees with the steady state (Newton's fixed point of the cycle
    /// map, an independent computation) to 1e-3, where one period of
    /// warm-up (10 cycles) leaves it more than 1 % off.
    #[test]
    fn warmup_outlasts_a_slow_transient() {
        let sm = ratchet();
        let s = FieldSettings::default();
        let player = sm.player(s.physics(), s.numerics);
        let steady = V2::from(
            player
                .simulator(0)
                .expect("moving")
                .steady_state([0.01, -0.01])
                .expect("steady state")
                .velocity,
        );
        assert!(steady.norm() > 1e-3, "the ratchet drifts: {steady}");
        let short = (played(&player, 1, 1) - steady).norm() / steady.norm();
        assert!(short > 1e-2, "one period of warm-up is short: {short:.2e}");
        let settle = warmup(&player, [0.01, -0.01], 1);
        assert!(settle.settled && settle.periods > 1, "{settle:?}");
        let long = (played(&player, settle.periods, 1) - steady).norm() / steady.norm();
        assert!(long < 1e-3, "after {settle:?}: {long:.2e}");
        // An asked warm-up already long enough is kept.
        assert_eq!(warmup(&player, [0.01, -0.01], 30).periods, 30);
    }
}
