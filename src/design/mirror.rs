//! Mirror-image time-share: a synthesized motion played alternately with
//! its mirror image, a design that holds its shape over the parts'
//! friction.
//!
//! **Why a synthesized field turns with friction.** A part slips against
//! the plate in the direction that leads the plate velocity by about
//! δ = asin(μg/A) (A the in-plane acceleration amplitude), so a motion
//! synthesized for one μ makes, at another, its field turned by the change
//! in δ: the synthesized sink gains swirl (its shape error at μ 0.2 or 0.4
//! is several times its error at the μ 0.3 it was synthesized for).
//!
//! **Why the mirror image cancels it.** Let M = diag(1, −1, 1) reflect the
//! world in the vertical plane y = 0. The mirror motion
//! (`crate::motion::Signals::mirrored_y`) moves a part at (x, −y) as the
//! mirror image of a part at (x, y) under the original, *at every friction*
//! (gravity and Coulomb's law are unchanged by the reflection), so its
//! field is F′(x, y) = (Fx(x, −y), −Fy(x, −y)). Playing the two for equal
//! time makes the time-weighted field ½(F + F′), which is symmetric under
//! the reflection whatever μ is. Every field splits into a symmetric and an
//! antisymmetric part; a swirl J q is antisymmetric (the reflection
//! reverses rotation). So for a target that is itself symmetric
//! ([`mirror_axis`]: a sink, a saddle, a squeeze line, not a whirlpool)
//! the time-share keeps the part of F that the target can use
//! and removes, at every friction, the swirl a friction error adds — to the
//! extent that sequencing combines fields (the joins' interaction, see the
//! crate docs).
//!
//! The same holds for the reflection in any vertical plane, at any angle
//! φ and through any point c of the plate ([`MirrorLine`],
//! `crate::motion::Signals::mirrored_in`): the reflection S(p) =
//! M(p − c) + c conjugates the whole plate motion, its reference point
//! included, so the mirror motion moves a part at S p as the mirror image
//! of a part at p and its field is F′(q) = M F(S q). A LineSink along 30°
//! is symmetric in every line across it (the one through the centre at
//! 120°), a sink in every line through its centre, a saddle off the
//! centre only in its own two axes, which miss the centre.
//! [`mirror_axis`] finds a line through the centre if there is one (its
//! mirror image is exact and needs no shift), else one anywhere.
//!
//! **Rotations do not cancel the turn.** A target may also be symmetric
//! under a rotation about a point (a sink or saddle by 180°, a whirlpool
//! by every angle). Time-sharing a motion with its rotated copy makes the
//! field rotation-symmetric, but a friction error turns every field
//! vector by the same Δ, and R(Δ) commutes with every rotation: the turned
//! field is as rotation-symmetric as the target, so no rotation share
//! removes it. Only a reflection, which reverses the sense of turning,
//! does; so reflections are the symmetries used.
//!
//! **Without a symmetry** (a whirlpool, any sampled field) the partner is
//! made instead of mirrored: a second motion synthesized for the target's
//! mirror image and reflected back realises the target itself with the
//! opposite sense of circulation, so its friction turn is the opposite one
//! (`counter_share`).
//!
//! **Its schedule.** Two six-signal segments of `MIRROR_SEGMENT_CYCLES`
//! cycles each, the motion and its mirror, each ramped in from rest and out
//! to rest over `MIXED_RAMP_CYCLES` cycles (the
//! plate velocities of the two motions differ at a cycle's start, so they
//! cannot be joined directly). The length trades two errors: longer
//! segments spend less of the period in the ramps, so they are stronger,
//! but let a part drift longer under one half's turned field before the
//! other half turns it back. `results/robust_knobs.md` (`platefield study
//! robust-knobs`) measures it over the 28 mirror-symmetric members of the
//! seeded family, each over its own range: the rule is the length with
//! the least 90th-percentile worst shape, the stronger of a tie, which is
//! `MIRROR_SEGMENT_CYCLES`. The ramps raise the acceleration above the steady peak
//! (up to about 16 %); where that passes a shaker limit, the motion is
//! scaled down to keep every axis within its limit.

use super::basis::MIXED_RAMP_CYCLES;
use crate::error::{Error, Result};
use crate::motion::Signals;
use crate::request::{SampledTarget, Target};
use crate::schedule::export::schedule_peaks;
use crate::schedule::{Schedule, Segment};
use crate::synth::ShakerLimits;

/// Cycles of each of the two segments, ramps included: what the design
/// passes to [`mirror_share`] and `counter_share`. Chosen over the
/// family's mirror shares (module documentation, "Its schedule"): of the
/// lengths `platefield study robust-knobs` compares, the one with the
/// least 90th-percentile worst shape over the members' ranges, the
/// stronger of a tie (`results/robust_knobs.md`). The counter-rotating
/// share takes the same length, not measured over the family.
pub const MIRROR_SEGMENT_CYCLES: u32 = 28;

/// Relative tolerance of the symmetry test of a target.
const SYMMETRY_TOL: f64 = 1e-9;

/// Step of the coarse scan of [`mirror_axis`] (degrees).
const AXIS_SCAN_DEG: f64 = 0.5;

/// Most points the coarse scan evaluates (every k-th weighted point
/// beyond; the final test uses all of them).
const AXIS_SCAN_POINTS: usize = 400;

/// Most points the scan over angle and offset evaluates (each angle
/// costs about 130 lines).
const OFF_CENTRE_SCAN_POINTS: usize = 64;

/// Offset steps on either side of the centre in the scan over angle and
/// offset, out to the points' largest distance from the centre.
const OFFSET_SCAN_STEPS: usize = 40;

/// Local minima of the scan over angle and offset refined and tested.
const OFF_CENTRE_CANDIDATES: usize = 8;

/// A line in the plate plane, the trace of a vertical mirror plane: at
/// `angle_deg` degrees from x, through `point` (m), the line's point
/// nearest the plate centre (the centre itself for an axis through it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MirrorLine {
    /// Direction of the line, degrees from x in [0°, 180°).
    pub angle_deg: f64,
    /// The line's point nearest the plate centre (m).
    pub point: [f64; 2],
}

impl MirrorLine {
    /// The line through the plate centre at `angle_deg`.
    pub(crate) fn through_centre(angle_deg: f64) -> MirrorLine {
        MirrorLine {
            angle_deg,
            point: [0.0, 0.0],
        }
    }

    /// The line at `angle_deg` at signed distance `offset` (m) from the
    /// centre along its normal (−sin, cos).
    fn at(angle_deg: f64, offset: f64) -> MirrorLine {
        if offset == 0.0 {
            return MirrorLine::through_centre(angle_deg);
        }
        let (s, c) = angle_deg.to_radians().sin_cos();
        MirrorLine {
            angle_deg,
            point: [-s * offset, c * offset],
        }
    }

    /// True when the line passes through the plate centre.
    pub(crate) fn is_through_centre(&self) -> bool {
        self.point == [0.0, 0.0]
    }

    /// Signed distance of the line from the plate centre (m), along the
    /// normal (−sin, cos).
    pub fn offset(&self) -> f64 {
        let (s, c) = self.angle_deg.to_radians().sin_cos();
        -s * self.point[0] + c * self.point[1]
    }

    /// Whether `target`'s field is symmetric in this line at its sampled
    /// `(point, vector)` pairs: the field at each reflected point is the
    /// reflected vector, within [`SYMMETRY_TOL`] of `scale`.
    fn is_symmetry(&self, target: &Target, samples: &[([f64; 2], [f64; 2])], scale: f64) -> bool {
        samples.iter().all(|(p, t)| {
            let m = target.field.eval(self.reflect_point(*p));
            let r = self.reflect_vector(*t);
            (m[0] - r[0]).hypot(m[1] - r[1]) <= SYMMETRY_TOL * scale
        })
    }

    /// Whether `target`'s field is symmetric in this line over its
    /// `sampled` points of positive weight ([`mirror_axis`]'s test).
    pub(crate) fn is_symmetry_of(&self, target: &Target, sampled: &SampledTarget) -> bool {
        self.is_symmetry(
            target,
            &weighted(sampled),
            sampled.max_norm().max(f64::MIN_POSITIVE),
        )
    }

    /// The vector `v` reflected (the reflection's linear part M).
    fn reflect_vector(&self, v: [f64; 2]) -> [f64; 2] {
        let (s, c) = (2.0 * self.angle_deg.to_radians()).sin_cos();
        [c * v[0] + s * v[1], s * v[0] - c * v[1]]
    }

    /// The point `p` reflected in the line: M (p − c) + c.
    fn reflect_point(&self, p: [f64; 2]) -> [f64; 2] {
        let c = self.point;
        let m = self.reflect_vector([p[0] - c[0], p[1] - c[1]]);
        [m[0] + c[0], m[1] + c[1]]
    }

    /// The motion's mirror image in this line ([`Signals::mirrored_in`]).
    pub(crate) fn mirror(&self, motion: &Signals) -> Signals {
        motion.mirrored_in(self.angle_deg.to_radians(), self.point)
    }

    /// The line's words: "the 65° axis" through the centre, else with the
    /// point in mm.
    pub(crate) fn describe(&self) -> String {
        if self.is_through_centre() {
            format!("the {}° axis", self.angle_deg)
        } else {
            format!(
                "the line at {}° through ({:.3}, {:.3}) mm",
                self.angle_deg,
                1e3 * self.point[0],
                1e3 * self.point[1]
            )
        }
    }
}

/// The target's field `t(p)`, evaluated.
type Eval<'a> = &'a dyn Fn([f64; 2]) -> [f64; 2];

/// Σ |t(Sp) − M t(p)|² over `points` (p, t(p)), S the reflection in `line`.
fn asymmetry(t: Eval, points: &[([f64; 2], [f64; 2])], line: &MirrorLine) -> f64 {
    points
        .iter()
        .map(|(p, v)| {
            let m = t(line.reflect_point(*p));
            let r = line.reflect_vector(*v);
            (m[0] - r[0]).powi(2) + (m[1] - r[1]).powi(2)
        })
        .sum()
}

/// The `(point, vector)` pairs of `sampled` whose weight is positive.
fn weighted(sampled: &SampledTarget) -> Vec<([f64; 2], [f64; 2])> {
    sampled
        .points
        .iter()
        .zip(&sampled.vectors)
        .zip(&sampled.weights)
        .filter(|&(_, &w)| w > 0.0)
        .map(|((p, t), _)| (*p, *t))
        .collect()
}

/// A line in whose vertical plane the target is symmetric at every sample
/// point of positive weight: t(Sp) = M t(p) within 1e-9 of its largest
/// vector, S the reflection, M its linear part; `None` when there is none
/// (a whirlpool, a generic sampled field). Lines through the plate centre
/// come first (the smallest angle in [0°, 180°)): their mirror image needs
/// no shift of the reference point. Only then lines off the centre (an
/// off-centre saddle's axes), at any angle and offset.
///
/// Through the centre, the squared asymmetry Σ|t(Sp) − M t(p)|² is scanned
/// every 0.5° (on at most 400 of the points); each local minimum of the
/// scan is refined by golden-section search over the two steps around it
/// (the asymmetry is a sum of squares that vanishes on an axis, so its
/// round-off shrinks with it and the refinement reaches ≈ 1e-10 rad),
/// snapped to the nearest millionth of a degree when that passes too, and
/// the first that passes the test on every point is the axis. Off the
/// centre, the scan runs over angle and offset (0.5° by 1/40 of the
/// points' largest distance from the centre, on at most 100 points); its
/// local minima, lowest first, are refined by nested golden-section
/// searches (offset within angle) and tested the same way.
///
/// ```
/// use platefield::design::mirror::mirror_axis;
/// use platefield::request::Target;
///
/// // Line sinks along −25° and 65° (weights 1 and 0.5): symmetric in
/// // both lines, the first from 0° is 65°.
/// let t = Target::from_json_str(r#"{"name": "e",
///     "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
///     "field": {"kind": "sum", "terms": [
///     {"field": {"kind": "line_sink", "angle": -25, "strength": 1}},
///     {"field": {"kind": "line_sink", "angle": 65, "strength": 0.5}}]}}"#).unwrap();
/// let axis = mirror_axis(&t, &t.sample().unwrap()).unwrap();
/// assert!((axis.angle_deg - 65.0).abs() < 1e-9 && axis.point == [0.0, 0.0], "{axis:?}");
/// // A saddle at (1, −0.5) cm along 30°: its axes miss the centre.
/// let t = Target::from_json_str(r#"{"name": "s",
///     "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
///     "field": {"kind": "saddle", "center": [0.01, -0.005], "angle": 30}}"#).unwrap();
/// let axis = mirror_axis(&t, &t.sample().unwrap()).unwrap();
/// let d = (axis.angle_deg - 30.0).rem_euclid(90.0);
/// assert!(d.min(90.0 - d) < 1e-6, "{axis:?}");
/// // The line passes through the saddle's centre.
/// let (s, c) = axis.angle_deg.to_radians().sin_cos();
/// assert!((-s * 0.01 + c * -0.005 - axis.offset()).abs() < 1e-9, "{axis:?}");
/// ```
pub fn mirror_axis(target: &Target, sampled: &SampledTarget) -> Option<MirrorLine> {
    let scale = sampled.max_norm().max(f64::MIN_POSITIVE);
    let all = weighted(sampled);
    let symmetric = |line: &MirrorLine| line.is_symmetry(target, &all, scale);
    let passing = |line: MirrorLine| {
        let snapped = MirrorLine::at(
            (line.angle_deg * 1e6).round() / 1e6,
            (line.offset() * 1e9).round() / 1e9,
        );
        let found = [snapped, line].into_iter().find(|l| symmetric(l))?;
        Some(MirrorLine {
            angle_deg: found.angle_deg.rem_euclid(180.0),
            point: found.point,
        })
    };
    // The scans evaluate a sampled field by its grid interpolant (O(1)
    // per point); the test above by the field itself.
    let interpolant = target.field.interpolant();
    let fast = |p: [f64; 2]| {
        interpolant
            .as_ref()
            .map_or_else(|| target.field.eval(p), |i| i.eval(p))
    };
    centre_axes(&fast, &thinned(&all, AXIS_SCAN_POINTS))
        .into_iter()
        .find_map(passing)
        .or_else(|| {
            off_centre_axes(&fast, &thinned(&all, OFF_CENTRE_SCAN_POINTS))
                .into_iter()
                .find_map(passing)
        })
}

/// Every k-th of `points`, at most `most` of them.
fn thinned(points: &[([f64; 2], [f64; 2])], most: usize) -> Vec<([f64; 2], [f64; 2])> {
    let stride = points.len().div_ceil(most).max(1);
    points.iter().step_by(stride).copied().collect()
}

/// The refined local minima of the asymmetry over lines through the
/// centre, in order of angle.
fn centre_axes(t: Eval, scan: &[([f64; 2], [f64; 2])]) -> Vec<MirrorLine> {
    let f = |deg: f64| asymmetry(t, scan, &MirrorLine::through_centre(deg));
    let n = (180.0 / AXIS_SCAN_DEG).round() as usize;
    let values: Vec<f64> = (0..n).map(|k| f(k as f64 * AXIS_SCAN_DEG)).collect();
    (0..n)
        .filter(|&k| values[k] <= values[(k + n - 1) % n] && values[k] <= values[(k + 1) % n])
        .map(|k| {
            let centre = k as f64 * AXIS_SCAN_DEG;
            let best = if values[k] == 0.0 {
                centre
            } else {
                golden_min(f, centre - AXIS_SCAN_DEG, centre + AXIS_SCAN_DEG)
            };
            MirrorLine::through_centre(best)
        })
        .collect()
}

/// The refined local minima of the asymmetry over lines at any angle and
/// offset, lowest first (at most [`OFF_CENTRE_CANDIDATES`]). At each
/// angle of the scan the asymmetry is minimised over the offset (a scan
/// of [`OFFSET_SCAN_STEPS`] each side, refined by golden section): a
/// scan of both at once aliases the narrow valley along the best offset
/// into false minima. The local minima of that valley over the angle are
/// refined by golden section in turn.
fn off_centre_axes(t: Eval, scan: &[([f64; 2], [f64; 2])]) -> Vec<MirrorLine> {
    let reach = scan
        .iter()
        .map(|(p, _)| p[0].hypot(p[1]))
        .fold(0.0, f64::max);
    if reach == 0.0 {
        return Vec::new();
    }
    let step = reach / OFFSET_SCAN_STEPS as f64;
    let f = |deg: f64, d: f64| asymmetry(t, scan, &MirrorLine::at(deg, d));
    let best_offset = |deg: f64| {
        let steps = OFFSET_SCAN_STEPS as i64;
        let j = (-steps..=steps)
            .map(|j| (f(deg, j as f64 * step), j))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map_or(0, |(_, j)| j);
        let d = j as f64 * step;
        golden_min(|x| f(deg, x), d - step, d + step)
    };
    let valley = |deg: f64| f(deg, best_offset(deg));
    let n = (180.0 / AXIS_SCAN_DEG).round() as usize;
    let values: Vec<f64> = (0..n).map(|k| valley(k as f64 * AXIS_SCAN_DEG)).collect();
    let mut minima: Vec<(f64, usize)> = (0..n)
        .filter(|&k| values[k] <= values[(k + n - 1) % n] && values[k] <= values[(k + 1) % n])
        .map(|k| (values[k], k))
        .collect();
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    minima
        .into_iter()
        .take(OFF_CENTRE_CANDIDATES)
        .map(|(_, k)| {
            let deg = k as f64 * AXIS_SCAN_DEG;
            let a = golden_min(valley, deg - AXIS_SCAN_DEG, deg + AXIS_SCAN_DEG);
            MirrorLine::at(a, best_offset(a))
        })
        .collect()
}

/// The minimiser of `f` on [a, b] by golden-section search, to the
/// bracket's round-off.
fn golden_min(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let r = (5.0_f64.sqrt() - 1.0) / 2.0;
    let (mut c, mut d) = (b - r * (b - a), a + r * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..200 {
        if (b - a).abs() <= 1e-13 * (1.0 + a.abs()) {
            break;
        }
        if fc < fd {
            b = d;
            (d, fd) = (c, fc);
            c = b - r * (b - a);
            fc = f(c);
        } else {
            a = c;
            (c, fc) = (d, fd);
            d = a + r * (b - a);
            fd = f(d);
        }
    }
    0.5 * (a + b)
}

/// The mirror-image time-share of a one-motion schedule (a synthesized
/// design) in the vertical plane of `line` ([`mirror_axis`]): the motion and
/// its mirror image, `cycles` cycles each (the design's:
/// [`MIRROR_SEGMENT_CYCLES`]), ramped, scaled down where the ramps would
/// pass `limits`. The rest of the schedule (target, settings, fit metrics)
/// is kept.
///
/// # Errors
/// The schedule does not hold exactly one six-signal motion, or `cycles`
/// does not leave a steady cycle between the two ramps.
pub fn mirror_share(
    synthesized: &Schedule,
    limits: &ShakerLimits,
    line: &MirrorLine,
    cycles: u32,
) -> Result<Schedule> {
    let motion = only_motion(synthesized)?;
    let mirrored = line.mirror(motion);
    let label = format!("Synthesized, mirrored in {}", line.describe());
    time_share(
        synthesized,
        motion,
        (&label, &mirrored),
        ("mirror", cycles),
        limits,
    )
}

/// The counter-rotating time-share, for any target: the synthesized
/// motion of `synthesized`, and `partner` — a motion synthesized for the
/// target's mirror image in y = 0 ([`crate::request::Target::mirrored_y`])
/// — mirrored back ([`Signals::mirrored_y`]).
///
/// **Why it holds over friction without symmetry.** A friction error
/// turns a synthesized field pointwise by the change Δ of the slip lead
/// (module documentation; [`crate::synth`]: in the averaged model
/// v = (W/g)(Q_N, P_N), a change Δ of ε rotates every (P, Q) pair, so
/// every field vector turns by the same Δ). The sense of that turn is the
/// sense in which the plate's velocity circulates. The partner, made for
/// f′(q) = S f(S q) and reflected by S = diag(1, −1), realises
/// S f′(S q) = f at the nominal friction, and its circulation is
/// reversed, so at another friction it realises R(−Δ) f where the first
/// realises R(Δ) f. The equal time-share realises ½(R(Δ) + R(−Δ)) f =
/// cos Δ · f: the turn costs strength to second order and shape not at
/// all (to the extent that sequencing combines fields, and the two motions'
/// strengths change alike with μ). For a target symmetric under a
/// reflection the partner is that reflection of the motion itself
/// ([`mirror_share`]), so this costs one synthesis more than it.
///
/// Each of the two segments lasts `cycles` cycles (the design's:
/// [`MIRROR_SEGMENT_CYCLES`]).
///
/// # Errors
/// Either schedule does not hold exactly one six-signal motion, or `cycles`
/// does not leave a steady cycle between the two ramps.
pub(crate) fn counter_share(
    synthesized: &Schedule,
    partner: &Schedule,
    limits: &ShakerLimits,
    cycles: u32,
) -> Result<Schedule> {
    let motion = only_motion(synthesized)?;
    let back = only_motion(partner)?.mirrored_y();
    time_share(
        synthesized,
        motion,
        ("Synthesized for the mirror image, mirrored back", &back),
        ("counter-rotating", cycles),
        limits,
    )
}

/// The one six-signal motion of a synthesized schedule.
fn only_motion(synthesized: &Schedule) -> Result<&Signals> {
    let [one] = synthesized.segments.as_slice() else {
        return Err(Error::invalid(
            "segments",
            "a mirror-image time-share is made from a one-motion (synthesized) schedule",
        ));
    };
    one.motion.as_ref().ok_or_else(|| {
        Error::invalid(
            "segments[0].motion",
            "a mirror-image time-share is made from a six-signal motion",
        )
    })
}

/// `synthesized` with its segments replaced by `first` and `second`,
/// `cycles` cycles each, ramped, both scaled down alike where the ramps
/// would pass `limits`; solver mode `mode`. The rest of the schedule
/// (target, settings, fit metrics) is kept.
fn time_share(
    synthesized: &Schedule,
    first: &Signals,
    second: (&str, &Signals),
    (mode, cycles): (&str, u32),
    limits: &ShakerLimits,
) -> Result<Schedule> {
    if cycles <= 2 * MIXED_RAMP_CYCLES {
        return Err(Error::invalid(
            "cycles",
            format!(
                "{cycles}: a share's segment needs more than its two ramps' {} cycles",
                2 * MIXED_RAMP_CYCLES
            ),
        ));
    }
    let build = |k: f64| {
        let segment = |label: &str, signals: Signals| Segment {
            label: label.into(),
            primitive: None,
            motion: Some(signals),
            ramp_cycles: Some(MIXED_RAMP_CYCLES),
            weight: 0.5,
            cycles,
            duration_s: 0.0,
        };
        let scaled = |m: &Signals| if k < 1.0 { m.scaled(k) } else { m.clone() };
        let mut s = synthesized.clone();
        s.segments = vec![
            segment("Synthesized", scaled(first)),
            segment(second.0, scaled(second.1)),
        ];
        s.played = None;
        s.solver.mode = mode.into();
        s.derive();
        s
    };
    let schedule = build(1.0);
    let peaks = schedule_peaks(&schedule);
    let allowed = [limits.linear, limits.angular].concat();
    let scale = peaks
        .iter()
        .zip(&allowed)
        .filter(|(p, _)| **p > 0.0)
        .map(|(p, a)| a / p)
        .fold(1.0_f64, f64::min);
    Ok(if scale < 1.0 { build(scale) } else { schedule })
}

#[cfg(test)]
#[path = "../../tests/unit/robust.rs"]
mod robust_tests;
