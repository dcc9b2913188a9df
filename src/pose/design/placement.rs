//! One synthesized motion, placed by rigid transforms.
//!
//! **The motion.** One simultaneous six-signal motion ([`crate::synth`],
//! `design --method synthesize`) is synthesized for the elliptic sink
//! f = −(αx, βy) centred at the plate centre, its weaker contraction
//! along x ([`Family::Ellipse`], α/β = [`RATIO`]). A linear field turns a
//! part by its second moments only: its major axis settles along the
//! weaker contraction, so the part has one stable pose modulo 180° (two
//! 180° apart for a part without that symmetry).
//!
//! **Placement without redesign.** The plate is homogeneous, so turning
//! the motion about the vertical by Δ and moving its reference point by
//! c ([`crate::motion::Signals::transformed`]: the linear signals mixed by
//! the turn, and v(p) = v₀ + ω × p → v₀ − ω × c + ω × p) turns the whole
//! physics by Δ and shifts it by c: a part's trajectory from Q(Δ)q + c is
//! the turned and shifted trajectory from q. So a stable pose (r₀, θ₀) of
//! the centred motion becomes (Q(Δ) r₀ + c, θ₀ + Δ) of the placed one,
//! played or lifted alike, and the asked pose (r*, θ*) is reached with
//! Δ = θ* − θ₀ (modulo the part's symmetry) and c = r* − Q(Δ) r₀
//! ([`Placement::onto`]). The shift moves a spin about the vertical
//! exactly, centripetal acceleration included (the moved reference
//! point's path as Fourier terms); the tilts' lever is moved to first
//! order in the tilt (milliradians): `tests/pose_design.rs` measures the
//! field of a shifted motion against the shifted field.
//!
//! **Region.** The motion's strength is capped by the contact margin at
//! the corners of the region it is synthesized on; the placed motion must
//! keep contact over the whole target region, whose corners lie up to
//! |corner − c| from the moved reference point in any direction. So the
//! motion is synthesized on a square of half-width the farthest corner's
//! distance from the asked pose plus [`SLACK`] (rounded up to 5 mm).

use super::search::{wrap_symmetric, Family};
use super::PoseTarget;
use crate::design::method::design_by_method;
use crate::design::{DesignOptions, MethodDesign};
use crate::dynamics::V2;
use crate::error::{Error, Result};
use crate::field::Grid;
use crate::pose::{Equilibrium, Pose};
use crate::request::FrictionSpec;
use crate::schedule::export::peaks::KinematicPeaks;
use crate::schedule::{Method, Schedule};
use crate::synth::SynthOptions;

/// α/β of the synthesized elliptic sink.
pub const RATIO: f64 = 0.3;
/// Room (m) beyond the farthest corner for the placement's corrections.
pub const SLACK: f64 = 0.005;
/// Samples per axis of the synthesis grid.
const SYNTH_N: usize = 21;

/// A rigid placement of the centred motion: turned by `angle` (rad) about
/// the vertical, its reference point moved to `shift` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Turn about the vertical (rad).
    pub angle: f64,
    /// The moved reference point (m).
    pub shift: V2,
}

impl Placement {
    /// No turn, no shift.
    pub const IDENTITY: Placement = Placement {
        angle: 0.0,
        shift: V2::new(0.0, 0.0),
    };

    /// Where this placement takes `pose` of the centred motion.
    pub(crate) fn apply(&self, pose: &Pose) -> Pose {
        let (s, c) = self.angle.sin_cos();
        let r = pose.r;
        Pose {
            r: V2::new(c * r.x - s * r.y, s * r.x + c * r.y) + self.shift,
            theta: pose.theta + self.angle,
        }
    }

    /// The pose of the centred motion this placement takes to `pose`.
    pub(crate) fn unapply(&self, pose: &Pose) -> Pose {
        let (s, c) = (-self.angle).sin_cos();
        let r = pose.r - self.shift;
        Pose {
            r: V2::new(c * r.x - s * r.y, s * r.x + c * r.y),
            theta: pose.theta - self.angle,
        }
    }

    /// The placement that takes `centred` (a pose of the centred motion)
    /// onto `asked`, turning by the least angle modulo the symmetry `n`.
    pub fn onto(centred: &Pose, asked: &Pose, n: usize) -> Placement {
        let angle = -wrap_symmetric(centred.theta - asked.theta, n);
        let turned = Placement {
            angle,
            shift: V2::zeros(),
        }
        .apply(centred);
        Placement {
            angle,
            shift: asked.r - turned.r,
        }
    }

    /// A damped correction: where the placed motion's part came to rest
    /// (`end`) is taken back to the centred motion and this placement moved
    /// by `gain` (0 … 1) of the way to the one that takes it onto `asked`.
    pub(crate) fn corrected(&self, end: &Pose, asked: &Pose, n: usize, gain: f64) -> Placement {
        let full = Placement::onto(&self.unapply(end), asked, n);
        Placement {
            angle: self.angle + gain * wrap_symmetric(full.angle - self.angle, n),
            shift: self.shift + gain * (full.shift - self.shift),
        }
    }

    /// `origin`'s six-signal segments placed (module docs; each stage of
    /// a [`super::cycle`] alike) and each scaled into the shaker limits
    /// `origin` records (`within_limits`); its target, when it has one,
    /// placed with it.
    ///
    /// # Errors
    /// `origin` has no six-signal motion, or a segment with a primitive;
    /// a placed segment over a limit of 0 (`within_limits`).
    pub(crate) fn schedule(
        &self,
        origin: &Schedule,
        placed_target: Option<crate::request::Target>,
    ) -> Result<Schedule> {
        let mut out = self.placed(origin, placed_target)?;
        within_limits(&mut out)?;
        Ok(out)
    }

    /// [`schedule`](Self::schedule) and one line per segment it scaled.
    ///
    /// # Errors
    /// As [`schedule`](Self::schedule).
    pub(crate) fn schedule_scaled(
        &self,
        origin: &Schedule,
        placed_target: Option<crate::request::Target>,
    ) -> Result<(Schedule, Vec<String>)> {
        let mut out = self.placed(origin, placed_target)?;
        let lines = within_limits(&mut out)?;
        Ok((out, lines))
    }

    /// `origin`'s six-signal segments placed as they are, whatever their
    /// peaks.
    fn placed(
        &self,
        origin: &Schedule,
        placed_target: Option<crate::request::Target>,
    ) -> Result<Schedule> {
        let mut out = origin.clone();
        let mut motions = 0;
        for seg in &mut out.segments {
            match (&seg.primitive, seg.motion.as_mut()) {
                (Some(_), _) => {
                    return Err(Error::Internal(
                        "a pose placement needs six-signal motions, not primitives".into(),
                    ))
                }
                (None, Some(m)) => {
                    *m = m.transformed(self.angle, [self.shift.x, self.shift.y]);
                    motions += 1;
                }
                (None, None) => {}
            }
        }
        if motions == 0 {
            return Err(Error::Internal(
                "a pose placement needs a six-signal motion".into(),
            ));
        }
        if placed_target.is_some() {
            out.target_spec = placed_target;
        }
        Ok(out)
    }
}

/// `origin` with its one six-signal motion changed by `edit`.
///
/// # Errors
/// `origin` is not one six-signal motion (`what` names the user).
pub(crate) fn with_motion(
    origin: &Schedule,
    what: &str,
    edit: impl FnOnce(&mut crate::motion::Signals),
) -> Result<Schedule> {
    let mut out = origin.clone();
    let [seg] = out.segments.as_mut_slice() else {
        return Err(Error::Internal(format!(
            "{what} needs a schedule of one motion"
        )));
    };
    let motion = seg
        .motion
        .as_mut()
        .ok_or_else(|| Error::Internal(format!("{what} needs a six-signal motion")))?;
    edit(motion);
    Ok(out)
}

/// Each six-signal segment of `schedule` scaled by the largest factor ≤ 1
/// that keeps its peaks (acceleration, velocity, stroke: [`placed_peaks`]) within the shaker
/// limits it records (`played.limits`, those the motion was synthesized
/// within), one line per segment scaled. A placement moves the reference
/// point by c, which adds α × c (and a spin's centripetal terms) to the
/// plate-centre linear signals and, with the tilts, a vertical
/// acceleration, none of which the synthesis budgeted; scaling the signals
/// by k scales every one of these peaks by k (the signals are linear in
/// their terms), so [`within_scale`](crate::schedule::export::peaks::KinematicPeaks::within_scale)'s first step is the
/// factor (the steps after it settle a rotation's second-order peaks). Nothing changes when
/// the schedule records no limits.
///
/// # Errors
/// A segment over a limit of 0 (no factor but 0 keeps it), naming the
/// axis and `target.shaker`.
pub(crate) fn within_limits(schedule: &mut Schedule) -> Result<Vec<String>> {
    let Some(limits) = schedule.played.as_ref().and_then(|p| p.limits.clone()) else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, seg) in schedule.segments.iter_mut().enumerate() {
        let ramp = seg.ramp_cycles.map(|r| (r, seg.cycles));
        let Some(signals) = seg.motion.as_mut() else {
            continue;
        };
        let excesses = placed_peaks(signals, ramp).excesses(&limits);
        if let Some(e) = excesses.iter().find(|e| e.limit == 0.0) {
            return Err(Error::invalid(
                "target.shaker",
                format!(
                    "segment {k} ({}) placed peaks on {} at {:.4} {}, which the limits forbid (0): no scale keeps it; allow the axis",
                    seg.label, e.axis, e.peak, e.unit
                ),
            ));
        }
        let Some(worst) = excesses
            .iter()
            .max_by(|a, b| (a.peak / a.limit).total_cmp(&(b.peak / b.limit)))
        else {
            continue;
        };
        let factor =
            KinematicPeaks::within_scale(|k| placed_peaks(&signals.scaled(k), ramp), &limits);
        *signals = signals.scaled(factor);
        out.push(format!(
            "segment {k} ({}): scaled × {factor:.4}, placed it peaked on {} at {:.4} {} against {:.4}",
            seg.label, worst.axis, worst.peak, worst.unit, worst.limit
        ));
    }
    Ok(out)
}

/// A six-signal segment's peaks as a placement holds them to the shaker
/// limits, its ramps included (`ramp` = (cycles of each ramp, cycles of
/// the segment), as the export plays
/// it: a ramp multiplies the pose by a smoothstep w(t), adding 2ẇẋ + ẅx to
/// the steady acceleration, [`crate::motion::Ramped`]; the steady cycles
/// between the ramps repeat one cycle, so at most one is played between
/// them),
/// found to round-off ([`KinematicPeaks::refined`]) so that the segment
/// scaled to a limit exports within it. The design's own peaks
/// ([`KinematicPeaks::of_motion`]: the rotation vector and its rates on
/// the angular axes), the linear axes also as the export plays them
/// ([`KinematicPeaks::of_plate`]: world axes, which the plate's turn
/// mixes at second order in the tilts).
fn placed_peaks(signals: &crate::motion::Signals, ramp: Option<(u32, u32)>) -> KinematicPeaks {
    use crate::motion::{Motion, Ramped};
    let motion = match ramp {
        Some((ramp, cycles)) => Motion::Ramped(Ramped {
            signals: signals.clone(),
            ramp,
            cycles: cycles.min(2 * ramp + 1),
        }),
        None => Motion::Signals(signals.clone()),
    };
    let (mut p, played) = KinematicPeaks::refined(&motion, signals.highest_harmonic());
    for i in 0..3 {
        p.acceleration[i] = p.acceleration[i].max(played.acceleration[i]);
        p.velocity[i] = p.velocity[i].max(played.velocity[i]);
        p.stroke[i] = p.stroke[i].max(played.stroke[i]);
    }
    p
}

/// Every peak of `schedule`'s six-signal segments above the shaker limits
/// it records, one line each (empty after `within_limits`).
#[cfg(test)]
pub(crate) fn over_limits(schedule: &Schedule) -> Vec<String> {
    let Some(limits) = schedule.played.as_ref().and_then(|p| p.limits.as_ref()) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (k, seg) in schedule.segments.iter().enumerate() {
        let Some(signals) = &seg.motion else {
            continue;
        };
        let ramp = seg.ramp_cycles.map(|r| (r, seg.cycles));
        for e in placed_peaks(signals, ramp).excesses(limits) {
            out.push(format!(
                "segment {k} ({}): {} peaks at {:.4} {} against {:.4} (+{:.1} %)",
                seg.label,
                e.axis,
                e.peak,
                e.unit,
                e.limit,
                100.0 * (e.peak / e.limit - 1.0)
            ));
        }
    }
    out
}

/// Half-width (m) of the synthesis square for `req` (module docs).
pub(crate) fn synthesis_half_width(req: &PoseTarget) -> f64 {
    let g = &req.region;
    let far = [g.x[0], g.x[1]]
        .iter()
        .flat_map(|&x| [g.y[0], g.y[1]].map(|y| (V2::new(x, y) - req.pose.r).norm()))
        .fold(0.0, f64::max);
    ((far + SLACK) / 0.005).ceil() * 0.005
}

/// The point field synthesized: the elliptic sink of [`RATIO`], or with
/// `spin` the isotropic sink (ratio 1) that [`super::spin`] makes
/// nonlinear.
pub fn family(spin: bool) -> Family {
    Family::Ellipse {
        ratio: if spin { 1.0 } else { RATIO },
    }
}

/// The pose target's target with `family` turned by `angle` (degrees) about
/// `c` on `grid`, no mask, at the middle of its friction range: a pose
/// design meets a range by centring its placement over it
/// (`pose::design::correct`), not by a worst-case synthesis, which turns the
/// bracket's played rest by 8.4° over μ 0.24–0.36 against 5.7° for the
/// nominal synthesis (`docs/parts.md`).
pub(crate) fn ellipse_target(
    req: &PoseTarget,
    family: Family,
    (c, angle): (V2, f64),
    grid: Grid,
) -> crate::request::Target {
    let mut target = req.target.clone();
    target.friction = target.friction.map(|f| FrictionSpec::exact(f.nominal()));
    target.grid = Some(grid);
    target.mask = Vec::new();
    target.field = family.field(c, angle);
    target
}

/// The centred `family` synthesized once (module docs), on the square of
/// `synthesis_half_width`.
///
/// # Errors
/// The synthesis's.
pub fn synthesize_centred(
    req: &PoseTarget,
    family: Family,
    opts: &DesignOptions,
    synth: &SynthOptions,
) -> Result<MethodDesign> {
    let h = synthesis_half_width(req);
    let grid = Grid {
        x: [-h, h],
        y: [-h, h],
        n: [SYNTH_N, SYNTH_N],
    };
    let target = ellipse_target(req, family, (V2::zeros(), 0.0), grid);
    design_by_method(&target, &opts.by_method(Method::Synthesize, synth))
}

/// The lifted stable pose of the centred motion that the placement moves
/// onto the asked one: the stable equilibrium whose turn onto the asked
/// angle is least (modulo the symmetry), then the nearest to the centre.
pub fn centred_pose(eqs: &[Equilibrium], asked: &Pose, n: usize) -> Option<Equilibrium> {
    let key = |e: &Equilibrium| {
        (
            (1e3 * wrap_symmetric(e.pose.theta - asked.theta, n).abs()).round(),
            e.pose.r.norm(),
        )
    };
    eqs.iter()
        .filter(|e| e.stable)
        .min_by(|a, b| {
            let (ka, kb) = (key(a), key(b));
            ka.0.total_cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
        })
        .copied()
}

#[cfg(test)]
mod tests {
    /// A worked example of `pose::design::placement::Placement::onto`.
    #[test]
    fn example_placement_onto() {
        use crate::pose::design::placement::Placement;
        use crate::pose::Pose;
        let centred = Pose::new(0.001, -0.002, 0.1);
        let asked = Pose::new(0.012, -0.008, 0.5);
        let p = Placement::onto(&centred, &asked, 2);
        let got = p.apply(&centred);
        assert!((got.r - asked.r).norm() < 1e-15 && (got.theta - asked.theta).abs() < 1e-15);
    }
}
