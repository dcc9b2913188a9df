//! Mirror-image time-share: a synthesized motion played alternately with
//! its mirror image, a design that holds its shape over the parts'
//! friction.
//!
//! **Why a synthesized field turns with friction.** A part slips against
//! the plate in the direction that leads the plate velocity by about
//! δ = asin(μg/A) (A the in-plane acceleration amplitude), so a motion
//! synthesized for one μ makes, at another, its field turned by the change
//! in δ: the synthesized sink gains swirl (measured: 4.7 % shape error at
//! μ 0.3, 16.7 % at 0.2 and 14.6 % at 0.4).
//!
//! **Why the mirror image cancels it.** Let M = diag(1, −1, 1) reflect the
//! world in the vertical plane y = 0. The mirror motion
//! ([`crate::motion::Signals::mirrored_y`]) moves a part at (x, −y) as the
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
//! The same holds for the reflection in any vertical plane through the
//! plate centre at an angle φ ([`crate::motion::Signals::mirrored_about`]):
//! a LineSink along 30° is symmetric under φ = 120° (any line across it),
//! a sink under every φ; the smallest φ in [0°, 180°) that maps the target
//! to itself is used, at any angle ([`mirror_axis`]).
//!
//! **Without a symmetry** (a whirlpool, a line sink off the centre beside
//! a swirl, any sampled field) the partner is made instead of mirrored:
//! a second motion synthesized for the target's mirror image and
//! reflected back realises the target itself with the opposite sense of
//! circulation, so its friction turn is the opposite one
//! ([`counter_share`]).
//!
//! **Its schedule.** Two six-signal segments of `MIRROR_SEGMENT_CYCLES`
//! cycles each, the motion and its mirror, each ramped in from rest and out
//! to rest over `MIXED_RAMP_CYCLES` cycles (the
//! plate velocities of the two motions differ at a cycle's start, so they
//! cannot be joined directly). Measured for the synthesized sink, worst
//! over μ ∈ [0.2, 0.4] (the design's judge, moving parts): 8
//! steady-plus-ramp cycles per segment 7.1 % at 0.22 s⁻¹, 12: 4.3 % at
//! 0.39, 20: 3.1 % at 0.55, 28: 3.5 % at 0.62, 36: 4.6 % at 0.66 —
//! longer segments lose less to the ramps and gain back some interaction;
//! 28 is the knee. The ramps raise the acceleration above the steady peak
//! (up to about 16 %); where that passes a shaker limit, the motion is
//! scaled down to keep every axis within its limit.

use super::basis::MIXED_RAMP_CYCLES;
use crate::error::{Error, Result};
use crate::motion::Signals;
use crate::request::{SampledTarget, Target};
use crate::schedule::export::schedule_peaks;
use crate::schedule::{Schedule, Segment};
use crate::synth::ShakerLimits;

/// Cycles of each of the two segments, ramps included.
pub(crate) const MIRROR_SEGMENT_CYCLES: u32 = 28;

/// Relative tolerance of the symmetry test of a target.
const SYMMETRY_TOL: f64 = 1e-9;

/// Step of the coarse scan of [`mirror_axis`] (degrees).
const AXIS_SCAN_DEG: f64 = 0.5;

/// Most points the coarse scan evaluates (every k-th weighted point
/// beyond; the final test uses all of them).
const AXIS_SCAN_POINTS: usize = 400;

/// `v` reflected in the vertical plane at `deg` degrees from x.
fn reflect(deg: f64, v: [f64; 2]) -> [f64; 2] {
    let (s, c) = (2.0 * deg.to_radians()).sin_cos();
    [c * v[0] + s * v[1], s * v[0] - c * v[1]]
}

/// Σ |t(Mp) − M t(p)|² over `points` (p, t(p)), M the reflection at `deg`.
fn asymmetry(target: &Target, points: &[([f64; 2], [f64; 2])], deg: f64) -> f64 {
    points
        .iter()
        .map(|(p, t)| {
            let m = target.field.eval(reflect(deg, *p));
            let r = reflect(deg, *t);
            (m[0] - r[0]).powi(2) + (m[1] - r[1]).powi(2)
        })
        .sum()
}

/// The smallest axis angle in [0°, 180°) (degrees from x, through the
/// plate centre) in whose vertical plane the target is symmetric at every
/// sample point of positive weight: t(Mp) = M t(p) within 1e-9 of its
/// largest vector, M the reflection; `None` when there is none (a
/// whirlpool).
///
/// Any angle: the squared asymmetry Σ|t(Mp) − M t(p)|² is scanned every
/// 0.5° (on at most 400 of the points), each local minimum of the scan is
/// refined by golden-section search over the two steps around it (the
/// asymmetry is quadratic in the angle near an axis, so the refinement
/// reaches ≈ 1e-10 rad), snapped to the nearest millionth of a degree
/// when that passes too, and the first that passes the test on every
/// point is the axis.
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
/// assert!((axis - 65.0).abs() < 1e-9, "{axis}");
/// ```
pub fn mirror_axis(target: &Target, sampled: &SampledTarget) -> Option<f64> {
    let scale = sampled.max_norm().max(f64::MIN_POSITIVE);
    let all: Vec<([f64; 2], [f64; 2])> = sampled
        .points
        .iter()
        .zip(&sampled.vectors)
        .zip(&sampled.weights)
        .filter(|(_, &w)| w > 0.0)
        .map(|((p, t), _)| (*p, *t))
        .collect();
    let stride = all.len().div_ceil(AXIS_SCAN_POINTS).max(1);
    let scan: Vec<([f64; 2], [f64; 2])> = all.iter().step_by(stride).copied().collect();
    let symmetric = |deg: f64| {
        all.iter().all(|(p, t)| {
            let m = target.field.eval(reflect(deg, *p));
            let r = reflect(deg, *t);
            (m[0] - r[0]).hypot(m[1] - r[1]) <= SYMMETRY_TOL * scale
        })
    };
    let n = (180.0 / AXIS_SCAN_DEG).round() as usize;
    let f: Vec<f64> = (0..n)
        .map(|k| asymmetry(target, &scan, k as f64 * AXIS_SCAN_DEG))
        .collect();
    (0..n)
        .filter(|&k| f[k] <= f[(k + n - 1) % n] && f[k] <= f[(k + 1) % n])
        .find_map(|k| {
            let centre = k as f64 * AXIS_SCAN_DEG;
            let best = if f[k] == 0.0 {
                centre
            } else {
                golden_min(
                    |d| asymmetry(target, &scan, d),
                    centre - AXIS_SCAN_DEG,
                    centre + AXIS_SCAN_DEG,
                )
            };
            let snapped = (best * 1e6).round() / 1e6;
            let axis = [snapped, best].into_iter().find(|&d| symmetric(d))?;
            Some(axis.rem_euclid(180.0))
        })
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
/// design) in the plane at `axis_deg` ([`mirror_axis`]): the motion and
/// its mirror image, `MIRROR_SEGMENT_CYCLES`
/// cycles each, ramped, scaled down where the ramps would pass `limits`.
/// The rest of the schedule (target, settings, fit metrics) is kept.
///
/// # Errors
/// The schedule does not hold exactly one six-signal motion.
pub fn mirror_share(
    synthesized: &Schedule,
    limits: &ShakerLimits,
    axis_deg: f64,
) -> Result<Schedule> {
    let motion = only_motion(synthesized)?;
    let mirrored = motion.mirrored_about(axis_deg.to_radians());
    let label = format!("Synthesized, mirrored in the {axis_deg}° axis");
    Ok(time_share(
        synthesized,
        motion,
        (&label, &mirrored),
        "mirror",
        limits,
    ))
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
/// # Errors
/// Either schedule does not hold exactly one six-signal motion.
pub fn counter_share(
    synthesized: &Schedule,
    partner: &Schedule,
    limits: &ShakerLimits,
) -> Result<Schedule> {
    let motion = only_motion(synthesized)?;
    let back = only_motion(partner)?.mirrored_y();
    Ok(time_share(
        synthesized,
        motion,
        ("Synthesized for the mirror image, mirrored back", &back),
        "counter-rotating",
        limits,
    ))
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
/// [`MIRROR_SEGMENT_CYCLES`] cycles each, ramped, both scaled down alike
/// where the ramps would pass `limits`; solver mode `mode`. The rest of
/// the schedule (target, settings, fit metrics) is kept.
fn time_share(
    synthesized: &Schedule,
    first: &Signals,
    second: (&str, &Signals),
    mode: &str,
    limits: &ShakerLimits,
) -> Schedule {
    let build = |k: f64| {
        let segment = |label: &str, signals: Signals| Segment {
            label: label.into(),
            primitive: None,
            motion: Some(signals),
            ramp_cycles: Some(MIXED_RAMP_CYCLES),
            weight: 0.5,
            cycles: MIRROR_SEGMENT_CYCLES,
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
    if scale < 1.0 {
        build(scale)
    } else {
        schedule
    }
}
