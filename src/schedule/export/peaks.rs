//! Per-axis peaks of an export: acceleration, velocity and stroke (peak
//! displacement from home) of the plate centre, linear along the world x,
//! y, z axes (m/s², m/s, m) and angular about them (rad/s², rad/s, rad) —
//! what a shaker must be able to play.
//!
//! **As played** (`KinematicPeaks::of_held`): the held samples integrated
//! exactly from the state the file starts in (for every export, rest at
//! home), as the controller plays them: over a hold of Δt with constant a,
//! v(τ) = v₀ + aτ and x(τ) = x₀ + v₀τ + aτ²/2, so |v| peaks at a hold's
//! ends and |x| at its ends or at the turning point τ* = −v₀/a inside it.
//! The angular samples are composed as a rotation (`crate::motion::Held`)
//! and the angular stroke is the peak |component| of the orientation's
//! rotation vector, taken at the hold ends and where the component of ω
//! changes sign inside a hold (where that component of the rotation vector
//! turns, to first order in the rotation: exact for a rotation about one
//! fixed axis, as a screw primitive's).
//!
//! **Steady six-signal motion** ([`KinematicPeaks::of_motion`]): each term
//! A sin(nωt + φ) of a channel integrates to the zero-mean velocity
//! −A/(nω) cos(nωt + φ) and pose −A/(nω)² sin(nωt + φ)
//! (`crate::motion::sample_hold::centre_state`); a channel's peaks are
//! those of the sums, sampled at `super::PEAK_SAMPLES` points per period
//! of its highest harmonic (relative error ≤ 1 − cos(π/4096) ≈ 3e-7);
//! `KinematicPeaks::refined` finds them to round-off.

use std::fmt::Write as _;

use crate::motion::sample_hold::{centre_state, signal_state, CentreState, HoldSamples};
use crate::motion::{Held, Motion};
use crate::request::ShakerSpec;

/// Samples per period of the highest harmonic in the coarse scan of
/// [`KinematicPeaks::refined`]: a sample lies within π/64 of phase of a
/// harmonic's maximum, so it misses it by at most (π/64)²/2 ≈ 1.2e-3.
const REFINE_SAMPLES: usize = 64;

/// A local maximum of the coarse scan within this fraction of its
/// channel's largest sample is refined: the coarse scan's error bound
/// with a margin of 8, so that the true maximum's sample is among them.
const REFINE_MARGIN: f64 = 1e-2;

/// Golden-section steps of a refinement: the bracket of two coarse steps
/// shrinks by 0.618²⁴ ≈ 1e-5, to within about 1e-5 · π/64 of phase of the
/// maximum, which it then misses by about (5e-7)²/2, far below the 1e-9
/// by which an export's peaks are checked.
const GOLDEN_STEPS: usize = 24;

/// |acceleration|, |velocity| and |pose| of `motion` at `t` per axis,
/// first as [`KinematicPeaks::of_motion`] reads them, then as
/// [`KinematicPeaks::of_plate`] does.
fn channels(motion: &Motion, t: f64) -> [f64; 36] {
    let mut out = [0.0; 36];
    let reads = [
        (
            signal_state(motion, t),
            super::centre_acceleration(motion, t),
        ),
        (
            centre_state(motion, t),
            super::world_acceleration(motion, t),
        ),
    ];
    for (o, (s, (lin, ang))) in reads.iter().enumerate() {
        let a = [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z];
        for i in 0..6 {
            out[18 * o + i] = a[i].abs();
            out[18 * o + 6 + i] = s.velocity[i].abs();
            out[18 * o + 12 + i] = s.pose[i].abs();
        }
    }
    out
}

/// The largest value of `f` found by golden-section search for a maximum
/// on `(a, b)` ([`GOLDEN_STEPS`] steps), the ends included.
fn golden_max(f: impl Fn(f64) -> f64, (mut a, mut b): (f64, f64)) -> f64 {
    let r = 0.5 * (5.0_f64.sqrt() - 1.0);
    let mut best = f(a).max(f(b));
    let (mut x1, mut x2) = (b - r * (b - a), a + r * (b - a));
    let (mut f1, mut f2) = (f(x1), f(x2));
    for _ in 0..GOLDEN_STEPS {
        best = best.max(f1).max(f2);
        if f1 < f2 {
            a = x1;
            (x1, f1) = (x2, f2);
            x2 = a + r * (b - a);
            f2 = f(x2);
        } else {
            b = x2;
            (x2, f2) = (x1, f1);
            x1 = b - r * (b - a);
            f1 = f(x1);
        }
    }
    best.max(f1).max(f2)
}

/// Names of the six signals in order, as JSON paths in a `signals` motion.
pub const AXIS_NAMES: [&str; 6] = [
    "linear.x",
    "linear.y",
    "linear.z",
    "angular.x",
    "angular.y",
    "angular.z",
];

/// A peak over a shaker limit ([`KinematicPeaks::excesses`]).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Excess {
    /// The axis (`linear.x`, …), followed by ` velocity` or ` stroke` when
    /// that is the quantity over its limit.
    pub axis: String,
    /// The peak.
    pub peak: f64,
    /// The limit.
    pub limit: f64,
    /// Unit of both.
    pub unit: &'static str,
}

/// Per-axis peak |acceleration|, |velocity| and |stroke|, each
/// [x, y, z linear, x, y, z angular].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct KinematicPeaks {
    /// m/s² (linear), rad/s² (angular).
    pub acceleration: [f64; 6],
    /// m/s, rad/s.
    pub velocity: [f64; 6],
    /// Peak displacement from home: m, rad.
    pub stroke: [f64; 6],
}

impl KinematicPeaks {
    /// The peaks of `samples` played from their start state (see the
    /// module documentation).
    pub(crate) fn of_held(samples: &HoldSamples) -> KinematicPeaks {
        let dt = samples.dt;
        let mut p = KinematicPeaks::default();
        let Ok(held) = Held::new(samples) else {
            return p;
        };
        let start = held.state_at(0);
        for i in 0..6 {
            p.velocity[i] = start.velocity[i].abs();
            p.stroke[i] = start.pose[i].abs();
        }
        for (k, a) in samples.samples.iter().enumerate() {
            let (s, end) = (held.state_at(k), held.state_at(k + 1));
            let t0 = k as f64 * dt;
            for (i, &ai) in a.iter().enumerate() {
                p.acceleration[i] = p.acceleration[i].max(ai.abs());
                if ai != 0.0 {
                    let turn = -s.velocity[i] / ai;
                    if turn > 0.0 && turn < dt {
                        let xt = held.centre_state_piece(t0 + turn, t0).pose[i];
                        p.stroke[i] = p.stroke[i].max(xt.abs());
                    }
                }
                p.velocity[i] = p.velocity[i].max(end.velocity[i].abs());
                p.stroke[i] = p.stroke[i].max(end.pose[i].abs());
            }
        }
        p
    }

    /// The peaks of a motion's signals over one period (over the whole
    /// segment, ramps included, for a ramped one; see the module
    /// documentation), sampled at `super::PEAK_SAMPLES` × `highest` points
    /// per cycle with `highest` its highest harmonic: a six-signal motion's
    /// angular ones are those of its rotation vector θ and its rates θ′, θ″,
    /// which design limits (`KinematicPeaks::of_plate` gives the plate's).
    pub fn of_motion(motion: &Motion, highest: u32) -> KinematicPeaks {
        Self::sampled(motion, highest, signal_state, super::centre_acceleration)
    }

    /// [`KinematicPeaks::of_motion`] with the plate's world angular
    /// velocity and acceleration (the exported channels) in place of θ′
    /// and θ″.
    pub(crate) fn of_plate(motion: &Motion, highest: u32) -> KinematicPeaks {
        Self::sampled(motion, highest, centre_state, super::world_acceleration)
    }

    fn sampled(
        motion: &Motion,
        highest: u32,
        state: fn(&Motion, f64) -> CentreState,
        acceleration: fn(&Motion, f64) -> (crate::motion::V3, crate::motion::V3),
    ) -> KinematicPeaks {
        // A ramped segment over its whole span, its ramps included.
        let cycles = (motion.span() / motion.period()).round().max(1.0) as usize;
        let n = super::PEAK_SAMPLES * highest.max(1) as usize * cycles;
        let mut p = KinematicPeaks::default();
        for k in 0..n {
            let t = motion.span() * k as f64 / n as f64;
            let s = state(motion, t);
            let (lin, ang) = acceleration(motion, t);
            let a = [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z];
            for (i, ai) in a.iter().enumerate() {
                p.acceleration[i] = p.acceleration[i].max(ai.abs());
                p.velocity[i] = p.velocity[i].max(s.velocity[i].abs());
                p.stroke[i] = p.stroke[i].max(s.pose[i].abs());
            }
        }
        p
    }

    /// [`KinematicPeaks::of_motion`] and [`KinematicPeaks::of_plate`] of
    /// `motion` (in that order) to round-off, where those are sampled to
    /// 3e-7: each of the 36 channels (|acceleration|, |velocity|, |pose|
    /// per axis, as each of the two reads them) sampled at
    /// [`REFINE_SAMPLES`] points per period of the highest harmonic, ends
    /// included, then every local maximum within [`REFINE_MARGIN`] of its
    /// channel's largest sample refined by golden-section search between
    /// its two neighbours ([`GOLDEN_STEPS`] steps). What a segment scaled
    /// to a limit needs, so that no finer sampling of it (an export's) is
    /// over the limit.
    pub(crate) fn refined(motion: &Motion, highest: u32) -> (KinematicPeaks, KinematicPeaks) {
        let cycles = (motion.span() / motion.period()).round().max(1.0) as usize;
        let n = REFINE_SAMPLES * highest.max(1) as usize * cycles;
        let dt = motion.span() / n as f64;
        let at = |k: usize| k as f64 * dt;
        let samples: Vec<[f64; 36]> = (0..=n).map(|k| channels(motion, at(k))).collect();
        let mut peak = [0.0_f64; 36];
        for (c, p) in peak.iter_mut().enumerate() {
            let top = samples.iter().fold(0.0_f64, |m, s| m.max(s[c]));
            *p = top;
            if top == 0.0 {
                continue;
            }
            for k in 0..=n {
                let v = samples[k][c];
                let left = if k > 0 { samples[k - 1][c] } else { 0.0 };
                let right = if k < n { samples[k + 1][c] } else { 0.0 };
                if v >= left && v >= right && v >= (1.0 - REFINE_MARGIN) * top {
                    let span = (at(k.saturating_sub(1)), at((k + 1).min(n)));
                    *p = p.max(golden_max(|t| channels(motion, t)[c], span));
                }
            }
        }
        let part = |o: usize| KinematicPeaks {
            acceleration: std::array::from_fn(|i| peak[o + i]),
            velocity: std::array::from_fn(|i| peak[o + 6 + i]),
            stroke: std::array::from_fn(|i| peak[o + 12 + i]),
        };
        (part(0), part(18))
    }

    /// The largest factor k ≤ 1 whose motion keeps within `limits`, where
    /// `peaks_at(k)` gives the peaks of the motion scaled by k: every
    /// excess over a limit above 0 removed (one over a limit of 0 no factor
    /// but 0 removes, so it is left to the caller). Peaks linear in k are
    /// settled by one step; the rotation's second-order part falls as k²,
    /// so a few steps settle the rest.
    pub(crate) fn within_scale(
        mut peaks_at: impl FnMut(f64) -> KinematicPeaks,
        limits: &ShakerSpec,
    ) -> f64 {
        /// Steps tried before the factor found is taken as it is.
        const STEPS: usize = 4;
        let mut k = 1.0;
        for _ in 0..STEPS {
            let over = peaks_at(k)
                .excesses(limits)
                .iter()
                .filter(|e| e.limit > 0.0)
                .fold(1.0_f64, |m, e| m.max(e.peak / e.limit));
            if over <= 1.0 {
                break;
            }
            k /= over;
        }
        k
    }

    /// Every peak above `limits` by more than a relative 1e-9, in the order
    /// acceleration, velocity, stroke and axis; against a limit of 0, a peak
    /// above 1e-12 of the largest linear or angular peak of its quantity
    /// (below that it is round-off). A key `limits` leaves out is not
    /// checked.
    pub(crate) fn excesses(&self, limits: &ShakerSpec) -> Vec<Excess> {
        let group = |l: Option<[f64; 3]>, a: Option<[f64; 3]>| -> [Option<f64>; 6] {
            std::array::from_fn(|k| {
                if k < 3 {
                    l.map(|v| v[k])
                } else {
                    a.map(|v| v[k - 3])
                }
            })
        };
        let travel = |t: Option<crate::request::TravelSpec>| {
            group(t.and_then(|t| t.linear), t.and_then(|t| t.angular))
        };
        let checks = [
            (
                "",
                &self.acceleration,
                group(limits.linear, limits.angular),
                ["m/s²", "rad/s²"],
            ),
            (
                " velocity",
                &self.velocity,
                travel(limits.velocity),
                ["m/s", "rad/s"],
            ),
            (" stroke", &self.stroke, travel(limits.stroke), ["m", "rad"]),
        ];
        let mut out = Vec::new();
        for (what, peaks, limit, units) in checks {
            let floor = |k: usize| {
                let group = if k < 3 { &peaks[..3] } else { &peaks[3..] };
                1e-12 * group.iter().fold(0.0_f64, |m, p| m.max(*p))
            };
            for k in 0..6 {
                match limit[k] {
                    Some(l) if peaks[k] > (l * (1.0 + 1e-9)).max(floor(k)) => out.push(Excess {
                        axis: format!("{}{what}", AXIS_NAMES[k]),
                        peak: peaks[k],
                        limit: l,
                        unit: units[k / 3],
                    }),
                    _ => {}
                }
            }
        }
        out
    }

    /// Comment lines (`# `) stating the peaks with units, for an export's
    /// header; `what` says which motion they are of.
    pub(crate) fn header(&self, what: &str) -> String {
        let mut out = format!("# peaks per axis ({what}): x, y, z linear; x, y, z angular\n");
        let rows = [
            ("acceleration", &self.acceleration, "m/s²", "rad/s²"),
            ("velocity", &self.velocity, "m/s", "rad/s"),
            (
                "stroke (peak displacement from home)",
                &self.stroke,
                "m",
                "rad",
            ),
        ];
        for (name, v, lin, ang) in rows {
            let _ = writeln!(
                out,
                "#   {name}: [{:.6e}, {:.6e}, {:.6e}] {lin}, [{:.6e}, {:.6e}, {:.6e}] {ang}",
                v[0], v[1], v[2], v[3], v[4], v[5]
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::{Axes, FourierTerm, Signals};

    /// One harmonic A sin(nωt + φ) on x, with a phase that puts its
    /// maxima between the samples: refined, its peaks are the closed form
    /// A, A/(nω), A/(nω)² to 1e-12, where the sampled ones fall short by up
    /// to 1 − cos(π/4096); both reads agree on a motion without rotation.
    #[test]
    fn refined_peaks_are_the_closed_form_to_round_off() {
        let (a, n, period) = (10.0, 3_u32, 0.03);
        let s = Signals {
            period,
            linear: Axes {
                x: vec![FourierTerm {
                    amplitude: a,
                    phase: 0.123_456_789,
                    harmonic: n,
                }],
                ..Axes::default()
            },
            angular: Axes::default(),
        };
        let motion = Motion::Signals(s);
        let (own, played) = KinematicPeaks::refined(&motion, n);
        let nw = f64::from(n) * std::f64::consts::TAU / period;
        let rel = |got: f64, want: f64| (got / want - 1.0).abs();
        for p in [&own, &played] {
            assert!(rel(p.acceleration[0], a) < 1e-12, "{p:?}");
            assert!(rel(p.velocity[0], a / nw) < 1e-12, "{p:?}");
            assert!(rel(p.stroke[0], a / (nw * nw)) < 1e-12, "{p:?}");
        }
        let sampled = KinematicPeaks::of_motion(&motion, n);
        assert!(sampled.acceleration[0] <= own.acceleration[0]);
        assert!(rel(sampled.acceleration[0], a) < 3e-7);
    }

    /// A worked example of `schedule::export::peaks::KinematicPeaks::of_held`.
    #[test]
    fn example_kinematicpeaks_of_held() {
        use crate::motion::sample_hold::{CentreState, HoldSamples};
        use crate::schedule::export::peaks::KinematicPeaks;
        // 1 m/s² on x for 1 s, then −1 m/s² for 1 s: v peaks at 1 m/s, x reaches 1 m.
        let s = HoldSamples {
            dt: 1.0,
            rate: 1.0,
            samples_per_period: 2,
            samples: vec![
                [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ],
            start: CentreState::default(),
        };
        let p = KinematicPeaks::of_held(&s);
        assert_eq!(
            (p.acceleration[0], p.velocity[0], p.stroke[0]),
            (1.0, 1.0, 1.0)
        );
    }

    /// A worked example of `schedule::export::peaks::KinematicPeaks::within_scale`.
    #[test]
    fn example_kinematicpeaks_within_scale() {
        use crate::request::ShakerSpec;
        use crate::schedule::export::peaks::KinematicPeaks;
        let limits = ShakerSpec {
            linear: Some([8.0, 10.0, 10.0]),
            ..ShakerSpec::default()
        };
        let at = |k: f64| KinematicPeaks {
            acceleration: [10.0 * k; 6],
            ..KinematicPeaks::default()
        };
        assert_eq!(KinematicPeaks::within_scale(at, &limits), 0.8);
    }

    /// A worked example of `schedule::export::peaks::KinematicPeaks::excesses`.
    #[test]
    fn example_kinematicpeaks_excesses() {
        use crate::request::{ShakerSpec, TravelSpec};
        use crate::schedule::export::peaks::KinematicPeaks;
        let p = KinematicPeaks {
            acceleration: [10.0; 6],
            velocity: [0.1; 6],
            stroke: [1e-3; 6],
        };
        let limits = ShakerSpec {
            linear: Some([10.0, 9.0, 10.0]),
            stroke: Some(TravelSpec {
                linear: None,
                angular: Some([1e-3, 1e-3, 5e-4]),
            }),
            ..ShakerSpec::default()
        };
        let over: Vec<String> = p.excesses(&limits).into_iter().map(|e| e.axis).collect();
        assert_eq!(over, ["linear.y", "angular.z stroke"]);
    }
}
