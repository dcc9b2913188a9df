//! The two-stage cycle: the spin selects, the ellipse sets.
//!
//! **Why.** A spun sink ([`super::spin`]) puts most drops of a part
//! without a 180° symmetry at one pose, but not all, and its pose moves
//! with friction: the triangle's strongest spin (4800 rad/s² × 0.15) put
//! 97 % of 64 drops at one pose and 3 % at a second 139° away, and its
//! rest turned 17.6° over μ 0.24–0.36 (0 % within 3° at either end;
//! `docs/parts.md`). The elliptic sink ([`super::search::Family::Ellipse`])
//! gives every such part two stable poses 180° apart, fixed by its second
//! moments and hardly moving with μ (the triangle's ±1.25° over the same
//! range), each holding about half the drops.
//!
//! **How.** The two are played in turn, repeated: [`Stages::spin_s`] of
//! the spun sink, then [`Stages::ellipse_s`] of the elliptic sink placed
//! (turned about the vertical and shifted, [`super::placement`]) so that
//! its lifted stable pose nearest the spun sink's played rest lies on it;
//! each stage ramps in and out over about [`RAMP_S`]
//! ([`crate::motion::Ramped`]). The spin stage takes a part into the half
//! of the ellipse's turn that holds the kept pose; the ellipse stage takes
//! it onto that pose, wherever in the half the spin left it. A part ending
//! at the spin's second rest is turned back by the ellipse to the pose
//! 180° from the kept one, which the next spin stage takes away. The
//! cycle is one schedule: the placement and the correction move both
//! stages together, and its probes and drops play at least
//! [`SETTLE_PERIODS`] of its periods.
//!
//! **Stage lengths, derived** (`Stages::derive`). Near its stable pose a
//! stage's lifted field decays as e^{−λt}, λ its slowest rate (the least
//! |real part| of the Jacobian's eigenvalues there). A part a distance d
//! away, in tolerances, comes within the tolerance after
//!
//! ```text
//! t = ln(d) / λ,   d = max(h / 1 mm, Δθ / 3°)
//! ```
//!
//! with h the half-diagonal of the region the drops start in (the region
//! inset by the part's radius: [`crate::pose::drop_starts`]) and Δθ the
//! largest turn the stage must make: 180° for the spin (a part may land
//! anywhere), 90° for the ellipse (the spin left it in the kept half).
//! The spin's λ is the least over its lifted stable poses; the ellipse's
//! over its two. These place the cycle until the hand-over is measured
//! (below). The spin stage's estimate only screens out the spins too slow
//! to play (a stage over
//! [`MAX_STAGE_S`]): the decay holds near the spin's rest, while the spin
//! stage works far from it, turning a part from the ellipse's rival rest
//! 180° away, and some spins turn a part on and on rather than bring it
//! to rest. The spin stage is therefore measured by play on the placed
//! cycle: as long as the spin takes to hand a part from either of the
//! ellipse's rests over to the ellipse, within 45° of the asked pose, over
//! the friction range ([`super::handover`]). The cycle's played probes
//! judge the result, and a part the spin left in the wrong half gets
//! another period. The period is therefore a property of the two motions
//! and the region, not a constant: the settle time of a drop is counted
//! in whole periods (`super::play`), so a shorter period settles sooner.
//!
//! **The ellipse stage after the hand-over** (`Stages::handed_over`).
//! The ellipse turns a part by its second moments only, with a torque
//! ∝ sin 2Δθ about its kept rest ([`super::placement`]). With λ its
//! linear rate there, dΔθ/dt = −(λ/2) sin 2Δθ, solved by
//! tan Δθ(t) = tan Δθ₀ e^{−λt}. A part handed over at Δθ₀, the hand-over's
//! worst turn, is within 3° after
//!
//! ```text
//! t = ln(d) / λ,   d = max(h / 1 mm, tan Δθ₀ / tan 3°)
//! ```
//!
//! 2.95/λ from 45° and 5.38/λ from 85°. The linear estimate above,
//! ln(90°/3°) = 3.40/λ, is too short for a part handed over near the
//! ellipse's unstable 90°, where the torque vanishes. λ is the slowest
//! lifted rate, at most the turning one, so the stage errs long.
//!
//! Measured numbers (stage rates, lengths, shares and settle times):
//! `results/poses.md`, `docs/parts.md`.

use super::placement::{centred_pose, Placement};
use super::{PoseTarget, TOL_DEG, TOL_MM};
use crate::error::{Error, Result};
use crate::field::Grid;
use crate::pose::{equilibria, schedule_field, Equilibrium, LiftedField, Pose, Region};
use crate::schedule::{Schedule, Segment};

/// Seconds of each stage's ramp in and out (whole cycles, at least one).
pub const RAMP_S: f64 = 0.5;
/// Periods of a cycle a probe or drop plays at least: one spin stage
/// does not always take a part out of the ellipse's wrong half (the part
/// may land near the spin's unstable pose, where the linear decay of
/// `Stages::derive` does not hold), so the later periods give it the
/// chances it needs and show that a settled part stays.
pub const SETTLE_PERIODS: f64 = 3.0;
/// Longest stage (s): a spin whose derived stage is longer is not
/// screened, and a spin stage's hand-over is played for at most this
/// long (module docs).
pub const MAX_STAGE_S: f64 = 40.0;
/// Turn the spin stage must make at most: any angle (degrees).
pub const SPIN_TURN_DEG: f64 = 180.0;
/// Turn the ellipse stage must make at most: within the kept half
/// (degrees).
pub const ELLIPSE_TURN_DEG: f64 = 90.0;

/// The stage lengths of a cycle (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stages {
    /// Seconds of the spin stage.
    pub spin_s: f64,
    /// Seconds of the ellipse stage.
    pub ellipse_s: f64,
}

impl Stages {
    /// The stage lengths for slowest lifted rates `spin_rate` and
    /// `ellipse_rate` (1/s) and drops starting in `starts` (the region
    /// inset by the part's radius): t = ln(d)/λ per stage (module docs).
    /// `None` when a rate is not positive or the spin stage would exceed
    /// [`MAX_STAGE_S`].
    pub(crate) fn derive(spin_rate: f64, ellipse_rate: f64, starts: &Region) -> Option<Stages> {
        if !(spin_rate > 0.0 && ellipse_rate > 0.0) {
            return None;
        }
        let d = |turn: f64| reach(starts).max(turn / TOL_DEG);
        let spin_s = d(SPIN_TURN_DEG).ln() / spin_rate;
        let ellipse_s = d(ELLIPSE_TURN_DEG).ln() / ellipse_rate;
        (spin_s <= MAX_STAGE_S).then_some(Stages { spin_s, ellipse_s })
    }

    /// The stages once the spin stage's hand-over is measured
    /// (`super::handover`): `(spin_s, worst_deg)` its seconds and its
    /// worst turn (degrees). The spin stage lasts `spin_s`; the ellipse
    /// stage as long as the ellipse's sin 2Δθ torque takes to bring a part
    /// from `worst_deg` within the tolerance, t = ln(d)/λ with
    /// d = max(h / 1 mm, tan Δθ / tan 3°) (module docs), `ellipse_rate` its
    /// λ and `starts` the drops' region.
    pub(crate) fn handed_over(
        (spin_s, worst_deg): (f64, f64),
        ellipse_rate: f64,
        starts: &Region,
    ) -> Stages {
        let turn = worst_deg.to_radians().tan() / TOL_DEG.to_radians().tan();
        Stages {
            spin_s,
            ellipse_s: reach(starts).max(turn).ln() / ellipse_rate,
        }
    }

    /// The nominal period: both stages (s).
    pub fn period(&self) -> f64 {
        self.spin_s + self.ellipse_s
    }
}

/// The farthest a drop starts from a rest in `starts`, in tolerances: the
/// region's half-diagonal over [`TOL_MM`].
fn reach(starts: &Region) -> f64 {
    let h = 0.5 * (starts.x[1] - starts.x[0]).hypot(starts.y[1] - starts.y[0]);
    1e3 * h / TOL_MM
}

/// The slowest decay rate (1/s) over the stable poses of `stable`: the
/// least −Re λ (none: 0).
pub(crate) fn slowest_rate(stable: &[Equilibrium]) -> f64 {
    stable
        .iter()
        .map(|e| -e.rates[0])
        .reduce(f64::min)
        .unwrap_or(0.0)
}

/// `seconds`, or [`SETTLE_PERIODS`] periods of `period` (s) when longer.
pub(crate) fn settle_seconds(seconds: f64, period: f64) -> f64 {
    seconds.max(SETTLE_PERIODS * period)
}

/// The ellipse stage before placement: the centred elliptic sink and its
/// part's lifted stable poses.
#[derive(Debug, Clone)]
pub struct EllipseStage {
    /// The centred elliptic sink (one six-signal motion).
    pub schedule: Schedule,
    /// The pose target's part's lifted stable poses in its field.
    pub stable: Vec<Equilibrium>,
}

impl EllipseStage {
    /// The elliptic sink `schedule` and the pose target's part's lifted stable
    /// poses in its field on `grid`.
    ///
    /// # Errors
    /// A field that loses contact on `grid`; no stable pose in the region.
    pub fn new(req: &PoseTarget, schedule: Schedule, grid: &Grid) -> Result<EllipseStage> {
        let field = schedule_field(&schedule, grid)?;
        let lifted = LiftedField::new(&field, &req.part.body);
        let stable: Vec<Equilibrium> = equilibria(&lifted, &req.region)
            .into_iter()
            .filter(|e| e.stable)
            .collect();
        if stable.is_empty() {
            return Err(Error::Unreachable(
                "the elliptic sink gives the part no stable pose in the region".into(),
            ));
        }
        Ok(EllipseStage { schedule, stable })
    }

    /// The slowest decay rate over its lifted stable poses (1/s).
    pub(crate) fn rate(&self) -> f64 {
        slowest_rate(&self.stable)
    }

    /// The elliptic sink placed so that its stable pose of least turn
    /// onto `rest` lies on it.
    ///
    /// # Errors
    /// The schedule is not one six-signal motion.
    pub(crate) fn placed_on(&self, rest: &Pose) -> Result<Schedule> {
        let own = centred_pose(&self.stable, rest, 1)
            .ok_or_else(|| Error::Unreachable("the elliptic sink has no stable pose".into()))?;
        Placement::onto(&own.pose, rest, 1).schedule(&self.schedule, None)
    }
}

/// The cycle of the centred spun sink `spun` whose played rest is `rest`
/// and `ellipse` placed on that rest, played for `stages` (module docs).
///
/// # Errors
/// Either schedule is not one six-signal motion.
pub fn cycle(
    spun: &Schedule,
    ellipse: &EllipseStage,
    rest: &Pose,
    stages: Stages,
) -> Result<Schedule> {
    let placed = ellipse.placed_on(rest)?;
    let mut out = spun.clone();
    out.segments = vec![
        stage(&spun.segments, stages.spin_s, "spin stage")?,
        stage(&placed.segments, stages.ellipse_s, "ellipse stage")?,
    ];
    let total: f64 = out.segments.iter().map(|s| s.duration_s).sum();
    for seg in &mut out.segments {
        seg.weight = seg.duration_s / total;
    }
    out.derive();
    Ok(out)
}

/// The one six-signal segment of `segments` played for about `seconds`
/// (whole cycles) with a ramp in and out of about [`RAMP_S`].
fn stage(segments: &[Segment], seconds: f64, what: &str) -> Result<Segment> {
    let [seg] = segments else {
        return Err(Error::Internal(format!("a {what} needs one motion")));
    };
    let period = seg
        .motion
        .as_ref()
        .map(|m| m.period)
        .ok_or_else(|| Error::Internal(format!("a {what} needs a six-signal motion")))?;
    let mut out = seg.clone();
    let ramp = ((RAMP_S / period).ceil() as u32).max(1);
    out.cycles = ((seconds / period).round() as u32).max(2 * ramp);
    out.ramp_cycles = Some(ramp);
    out.duration_s = f64::from(out.cycles) * period;
    out.label = format!("{} ({what})", seg.label);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::design::DesignOptions;
    use crate::pose::design::placement::{family, synthesize_centred};
    use crate::pose::design::spin::{spun, CANDIDATES};

    /// The cycle plays the spun sink for its [`Stages::spin_s`] then the
    /// ellipse for its [`Stages::ellipse_s`] (whole cycles, ramped), and the placed ellipse's
    /// lifted stable pose lies on the given rest (within 0.5 mm and 1°:
    /// the lifted equilibria are found on a grid field, so up to its
    /// interpolation), while the centred one does not. The committed pose
    /// designs' cycles are held to their limits by `tests/envelope.rs` in
    /// the default run.
    #[test]
    #[ignore = "about 12 s of CPU: cargo test --release --lib -- --ignored the_ellipse_stage_rests"]
    fn the_ellipse_stage_rests_where_the_spin_did() {
        let path = std::path::Path::new("targets/pose_triangle.json");
        let req = PoseTarget::load(path).unwrap().unwrap();
        let opts = DesignOptions {
            runtime: crate::work::Runtime::QUIET,
            ..Default::default()
        };
        let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
        let synth = |spin| synthesize_centred(&req, family(spin), &opts, &opts.synthesis);
        let sink = synth(true).unwrap().kept().schedule.clone();
        let ellipse = synth(false).unwrap().kept().schedule.clone();
        let stage = EllipseStage::new(&req, ellipse, &grid).unwrap();
        let rest = Pose::new(-0.0016, 0.0065, 89.2f64.to_radians());
        let stages = Stages {
            spin_s: 9.7,
            ellipse_s: 5.1,
        };
        let c = cycle(&spun(&sink, CANDIDATES[4]).unwrap(), &stage, &rest, stages).unwrap();
        let secs: Vec<f64> = c.segments.iter().map(|s| s.duration_s).collect();
        assert!(
            (secs[0] - stages.spin_s).abs() < 0.1 && (secs[1] - stages.ellipse_s).abs() < 0.1,
            "{secs:?}"
        );
        assert!((c.period_s - secs[0] - secs[1]).abs() < 1e-9);
        assert!(c.segments.iter().all(|s| s.ramp_cycles.is_some()));
        // Placed again as a whole (the ellipse stage turned twice), it is
        // still a schedule the loader accepts (no round-off harmonics
        // beyond what its steps per cycle resolve).
        let twice = Placement::onto(&rest, &req.pose, 1)
            .schedule(&c, None)
            .unwrap();
        twice.validate().unwrap();
        // The centred spun sink is within the limits it was synthesized
        // for; placed, the cycle's shift c ≈ 1 cm adds α × c to the
        // plate-centre linear signals (4800 rad/s² × 1 cm = 48 m/s², more
        // than the 45.3 m/s² limit), so the spin stage is scaled into them,
        // and the placed schedule is within every limit.
        let spun_sink = spun(&sink, CANDIDATES[4]).unwrap();
        assert!(crate::pose::design::placement::over_limits(&spun_sink).is_empty());
        assert!(crate::pose::design::placement::over_limits(&twice).is_empty());
        let (_, scaled) = Placement::onto(&rest, &req.pose, 1)
            .schedule_scaled(&c, None)
            .unwrap();
        assert!(
            scaled
                .iter()
                .any(|l| l.contains("(spin stage)): scaled × 0.")),
            "{scaled:?}"
        );
        let placed = EllipseStage::new(&req, stage.placed_on(&rest).unwrap(), &grid).unwrap();
        let near = |st: &EllipseStage| {
            st.stable
                .iter()
                .map(|e| {
                    let (d, t) = crate::pose::design::search::pose_error(&e.pose, &rest, 1);
                    (1e3 * d, t.abs().to_degrees())
                })
                .fold((f64::INFINITY, f64::INFINITY), |a, b| {
                    (a.0.min(b.0), a.1.min(b.1))
                })
        };
        let (d, t) = near(&placed);
        assert!(d < 0.5 && t < 1.0, "placed: {d} mm, {t}°");
        let (d0, t0) = near(&stage);
        assert!(d0 > 2.0 || t0 > 10.0, "centred: {d0} mm, {t0}°");
    }

    /// The derived stage lengths follow t = ln(d)/λ (module docs), checked
    /// against the closed form by hand: on ±2 cm of starts the half-diagonal
    /// 28.28 mm is under the turns' 60 and 30 tolerances, so the spin
    /// takes ln 60/λ and the ellipse ln 30/λ; on ±5 cm (70.71 mm) the
    /// distance wins for both. Halving a rate doubles its stage; a spin
    /// slower than [`MAX_STAGE_S`] allows, or a rate ≤ 0, gives none.
    #[test]
    fn stage_lengths_follow_from_the_rates() {
        let square = |a: f64| Region {
            x: [-a, a],
            y: [-a, a],
        };
        let s = Stages::derive(0.5, 0.7, &square(0.02)).unwrap();
        assert!((s.spin_s - 4.094_344_562_222_1 / 0.5).abs() < 1e-9, "{s:?}");
        assert!((s.ellipse_s - 3.401_197_381_662_155 / 0.7).abs() < 1e-9);
        assert!((s.period() - s.spin_s - s.ellipse_s).abs() < 1e-15);
        let wide = Stages::derive(0.5, 0.7, &square(0.05)).unwrap();
        let ln_h = (50.0 * 2f64.sqrt()).ln();
        assert!((wide.spin_s - ln_h / 0.5).abs() < 1e-9, "{wide:?}");
        assert!((wide.ellipse_s - ln_h / 0.7).abs() < 1e-9);
        let half = Stages::derive(0.25, 0.35, &square(0.02)).unwrap();
        assert!((half.spin_s - 2.0 * s.spin_s).abs() < 1e-9);
        assert!((half.ellipse_s - 2.0 * s.ellipse_s).abs() < 1e-9);
        // ln 60 / 40 s = 0.1024 1/s: the slowest spin that is screened.
        assert!(Stages::derive(0.103, 0.7, &square(0.02)).is_some());
        assert!(Stages::derive(0.102, 0.7, &square(0.02)).is_none());
        assert!(Stages::derive(0.0, 0.7, &square(0.02)).is_none());
        assert!(Stages::derive(0.5, -0.1, &square(0.02)).is_none());
        let eq = |r: f64| Equilibrium {
            pose: Pose::new(0.0, 0.0, 0.0),
            stable: true,
            rates: [-r, -2.0 * r, -3.0 * r],
        };
        assert_eq!(slowest_rate(&[eq(0.4), eq(0.3), eq(0.5)]), 0.3);
        assert_eq!(slowest_rate(&[]), 0.0);
    }

    /// The ellipse stage after a hand-over is the time the ellipse's
    /// torque, dΔθ/dt = −(λ/2) sin 2Δθ (linear rate λ at its rest), takes
    /// from the hand-over's worst turn to the 3° tolerance: checked by
    /// integrating that equation with RK4 (1e-4 s steps) to the stage's end,
    /// which lands on 3° within 1e-6°, from 45°, 76° and 85°. On a wide
    /// region the drops' reach in tolerances wins instead; the spin stage is
    /// the hand-over's seconds.
    #[test]
    fn the_ellipse_stage_follows_the_hand_over_turn() {
        let small = Region {
            x: [-0.005, 0.005],
            y: [-0.005, 0.005],
        };
        let rate = 0.68;
        for deg in [45.0, 76.0, 85.0] {
            let s = Stages::handed_over((12.5, deg), rate, &small);
            assert_eq!(s.spin_s, 12.5);
            let f = |t: f64| -0.5 * rate * (2.0 * t).sin();
            let (mut theta, dt) = (f64::to_radians(deg), 1e-4);
            let n = (s.ellipse_s / dt).round() as usize;
            let dt = s.ellipse_s / n as f64;
            for _ in 0..n {
                let k1 = f(theta);
                let k2 = f(theta + 0.5 * dt * k1);
                let k3 = f(theta + 0.5 * dt * k2);
                let k4 = f(theta + dt * k3);
                theta += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            }
            assert!(
                (theta.to_degrees() - TOL_DEG).abs() < 1e-6,
                "{deg}: {}",
                theta.to_degrees()
            );
        }
        let wide = Region {
            x: [-0.05, 0.05],
            y: [-0.05, 0.05],
        };
        let s = Stages::handed_over((3.0, 45.0), rate, &wide);
        assert!((s.ellipse_s - (50.0 * 2f64.sqrt()).ln() / rate).abs() < 1e-12);
    }

    /// A worked example of `pose::design::cycle::Stages::derive`.
    #[test]
    fn example_stages_derive() {
        use crate::pose::design::cycle::Stages;
        use crate::pose::Region;
        // Half-diagonal 28.3 mm: the spin's d = max(28.3, 180/3) = 60,
        // the ellipse's d = max(28.3, 90/3) = 30.
        let starts = Region {
            x: [-0.02, 0.02],
            y: [-0.02, 0.02],
        };
        let s = Stages::derive(0.4, 0.68, &starts).unwrap();
        assert!((s.spin_s - 60f64.ln() / 0.4).abs() < 1e-12);
        assert!((s.ellipse_s - 30f64.ln() / 0.68).abs() < 1e-12);
        assert!(Stages::derive(0.05, 0.68, &starts).is_none());
    }

    /// A worked example of `pose::design::cycle::settle_seconds`.
    #[test]
    fn example_settle_seconds() {
        use crate::pose::design::cycle::settle_seconds;
        assert_eq!(settle_seconds(60.0, 0.05), 60.0);
        assert_eq!(settle_seconds(60.0, 60.0), 180.0);
    }
}
