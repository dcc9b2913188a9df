//! A plate motion played from held acceleration samples: what a shaker
//! controller does with an exported file (`platefield export`, read back by
//! [`super::held_csv`]).
//!
//! Sample k holds the plate-centre acceleration a_k (linear along, and
//! angular about, the world axes) constant over [t_k, t_k + Δt), t_k = kΔt.
//! From a start state (v₀, x₀) — rest in the home pose for a file as
//! exported — velocity and pose are integrated exactly, piecewise linear and
//! quadratic in τ = t − t_k ∈ [0, Δt), per channel:
//!
//! ```text
//! a(t) = a_k,   v(t) = v_k + a_k τ,   x(t) = x_k + v_k τ + a_k τ²/2
//! v_{k+1} = v_k + a_k Δt,   x_{k+1} = x_k + v_k Δt + a_k Δt²/2
//! ```
//!
//! for the linear channels. The angular channels are the plate's angular
//! acceleration α about the world axes, composed as a rotation
//! ([`super::rotation::advance`]: ω(τ) = ω_k + α_k τ, R(τ) =
//! exp(\[Φ(τ)\]×) R_k with Φ its Magnus series), so the orientation is the
//! one a rigid plate driven by those accelerations takes. The plate-frame
//! kinematics are Ω = Rᵀω, Ω' = Rᵀα, v_c = Rᵀv, a_c = Rᵀa and
//! g_S = Rᵀ(0, 0, −g) with the tilt switch on; with it off (the
//! small-angle model) R = I. The acceleration
//! jumps at every t_k: those are the motion's breakpoints, so no integration
//! step of a part straddles one. The period used for step sizes and
//! tolerances is one cycle of the exported motion ([`Held::period`], N
//! samples); the motion is defined over all its samples ([`Held::span`]).
//!
//! **Against the analytic motion.** An export's sample is the mean
//! acceleration over its interval ([`super::sample_hold`]), so the held
//! velocity equals the analytic one at every t_k; inside an interval,
//! with a(t) ≈ a_k + a′·(τ − Δt/2),
//! v − v_exact = a′ τ(Δt − τ)/2, at most a′Δt²/8: relative to a harmonic
//! of angular frequency ω, (ωΔt)²/8 (5.5e-5 for ω = 209 rad/s at 10 kHz).
//! The acceleration differs by up to a′Δt/2 (ωΔt/2 = 1 % relative), but
//! with zero mean over each interval, so what parts do changes at second
//! order in ωΔt (`tests/replay.rs` measures it).

use std::ops::Range;

use nalgebra::UnitQuaternion;

use super::rotation;
use super::sample_hold::{CentreState, HoldSamples};
use super::{Kinematics, V3};
use crate::error::{Error, Result};

/// A motion from held acceleration samples (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Held {
    dt: f64,
    per_period: usize,
    samples: Vec<[f64; 6]>,
    /// The state at the start of each sample, and after the last: linear
    /// velocity and pose, world angular velocity ω and the orientation.
    states: Vec<(CentreState, UnitQuaternion<f64>)>,
}

/// One step of the exact integration: the state `tau` after `s` under the
/// held acceleration `a` (the linear channels per axis, the angular ones
/// composed as a rotation), with the rotation vector of the orientation as
/// the angular pose.
fn advance(
    (s, q): &(CentreState, UnitQuaternion<f64>),
    a: &[f64; 6],
    tau: f64,
) -> (CentreState, UnitQuaternion<f64>) {
    let v3 = |x: &[f64; 6]| V3::new(x[3], x[4], x[5]);
    let (turned, w) = rotation::advance(q, &v3(&s.velocity), &v3(a), tau);
    let theta = rotation::rotation_vector(&turned);
    let lin = |i: usize| {
        (
            s.velocity[i] + a[i] * tau,
            s.pose[i] + s.velocity[i] * tau + 0.5 * a[i] * tau * tau,
        )
    };
    let state = CentreState {
        velocity: [lin(0).0, lin(1).0, lin(2).0, w.x, w.y, w.z],
        pose: [lin(0).1, lin(1).1, lin(2).1, theta.x, theta.y, theta.z],
    };
    (state, turned)
}

impl Held {
    /// The motion of `held`: its samples from its start state, one cycle
    /// [`HoldSamples::samples_per_period`] samples.
    ///
    /// # Errors
    /// No samples, Δt not positive and finite, a sample not finite, or a
    /// sample after which the integrated velocity or pose is not finite.
    pub(crate) fn new(held: &HoldSamples) -> Result<Held> {
        if held.samples.is_empty() || !(held.dt.is_finite() && held.dt > 0.0) {
            return Err(Error::invalid(
                "held samples",
                format!(
                    "need at least one sample and a positive hold time, got {} samples of {} s",
                    held.samples.len(),
                    held.dt
                ),
            ));
        }
        if let Some(k) = held
            .samples
            .iter()
            .position(|a| a.iter().any(|x| !x.is_finite()))
        {
            return Err(Error::invalid(
                format!("held samples[{k}]"),
                "every acceleration must be finite",
            ));
        }
        let mut states = Vec::with_capacity(held.samples.len() + 1);
        let start = &held.start.pose;
        states.push((
            held.start,
            rotation::orientation(&V3::new(start[3], start[4], start[5])),
        ));
        for (k, a) in held.samples.iter().enumerate() {
            let next = advance(&states[states.len() - 1], a, held.dt);
            if !(next.0.velocity.iter().chain(&next.0.pose)).all(|x| x.is_finite()) {
                return Err(Error::invalid(
                    format!("held samples[{k}]"),
                    format!(
                        "the plate's velocity or pose, integrated over the samples of {} s, is not finite after this one: the accelerations are not physical",
                        held.dt
                    ),
                ));
            }
            states.push(next);
        }
        Ok(Held {
            dt: held.dt,
            per_period: held.samples_per_period.clamp(1, held.samples.len()),
            samples: held.samples.clone(),
            states,
        })
    }

    /// Samples `range` of this motion, started from the state this motion
    /// has when sample `range.start` begins (a cut of the file that plays
    /// as it does in the whole).
    ///
    /// # Panics
    /// When `range` is empty or past the samples.
    pub(crate) fn slice(&self, range: Range<usize>) -> Held {
        assert!(range.start < range.end && range.end <= self.samples.len());
        Held {
            dt: self.dt,
            per_period: self.per_period.min(range.len()),
            samples: self.samples[range.clone()].to_vec(),
            states: self.states[range.start..=range.end].to_vec(),
        }
    }

    /// Hold time Δt (s).
    pub(crate) fn dt(&self) -> f64 {
        self.dt
    }

    /// Number of samples.
    pub(crate) fn len(&self) -> usize {
        self.samples.len()
    }

    /// One cycle of the exported motion: N samples (s).
    pub(crate) fn period(&self) -> f64 {
        self.per_period as f64 * self.dt
    }

    /// Time over which the motion is defined: all its samples (s).
    pub(crate) fn span(&self) -> f64 {
        self.samples.len() as f64 * self.dt
    }

    /// The state when sample `k` begins (`k` = [`Held::len`]: after the
    /// last).
    pub(crate) fn state_at(&self, k: usize) -> CentreState {
        self.states[k].0
    }

    /// The orientation when sample `k` begins (`k` = [`Held::len`]: after
    /// the last).
    #[cfg(test)]
    pub(crate) fn orientation_at(&self, k: usize) -> UnitQuaternion<f64> {
        self.states[k].1
    }

    /// The sample holding at `piece_t` (clamped to the samples).
    fn index(&self, piece_t: f64) -> usize {
        let k = (piece_t / self.dt).floor();
        if k <= 0.0 {
            0
        } else {
            (k as usize).min(self.samples.len() - 1)
        }
    }

    /// Centre velocity and pose at `t` on the sample holding at `piece_t`.
    pub(crate) fn centre_state_piece(&self, t: f64, piece_t: f64) -> CentreState {
        let k = self.index(piece_t);
        advance(&self.states[k], &self.samples[k], t - k as f64 * self.dt).0
    }

    /// Plate-frame kinematics at `t` on the sample holding at `piece_t`
    /// (see the module documentation).
    pub(crate) fn kinematics(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        let k = self.index(piece_t);
        let (s, q) = advance(&self.states[k], &self.samples[k], t - k as f64 * self.dt);
        let a = &self.samples[k];
        let v3 = |x: &[f64; 6], o: usize| V3::new(x[o], x[o + 1], x[o + 2]);
        let back = |x: V3| {
            if tilt {
                q.inverse_transform_vector(&x)
            } else {
                x
            }
        };
        Kinematics {
            omega: back(v3(&s.velocity, 3)),
            alpha: back(v3(a, 3)),
            center: V3::zeros(),
            vel_center: back(v3(&s.velocity, 0)),
            accel_center: back(v3(a, 0)),
            gravity: back(V3::new(0.0, 0.0, -g)),
        }
    }

    /// The sample starts within one period: kΔt, k < N.
    pub(crate) fn breakpoints(&self) -> Vec<f64> {
        (0..self.per_period).map(|k| k as f64 * self.dt).collect()
    }

    /// True when only x, y translation and z rotation are driven, from a
    /// start with no other velocity or pose.
    pub(crate) fn is_in_plane(&self) -> bool {
        let off = |v: &[f64; 6]| v[2] != 0.0 || v[3] != 0.0 || v[4] != 0.0;
        !self.samples.iter().any(off)
            && !off(&self.states[0].0.velocity)
            && !off(&self.states[0].0.pose)
    }

    /// Rotated about the vertical by `angle` (rad), then shifted
    /// horizontally by `shift` (m), as [`super::Signals::transformed`]: linear
    /// vectors and angular vectors turned, and the new centre (the old
    /// plate point −s) given Ω' × (−s) more (and, in velocity and pose, the
    /// same map of Ω and θ); first order in the small rotation, like a
    /// six-signal motion's shift.
    pub(crate) fn transformed(&self, angle: f64, shift: [f64; 2]) -> Held {
        let (s, c) = angle.sin_cos();
        let map = |v: &[f64; 6]| -> [f64; 6] {
            let turn = |x: f64, y: f64| (c * x - s * y, s * x + c * y);
            let (lx, ly) = turn(v[0], v[1]);
            let (ax, ay) = turn(v[3], v[4]);
            let az = v[5];
            let (sx, sy) = (shift[0], shift[1]);
            [
                lx + az * sy,
                ly - az * sx,
                v[2] - ax * sy + ay * sx,
                ax,
                ay,
                az,
            ]
        };
        // The orientation turned with the plate: R → R_z R R_zᵀ.
        let turn = UnitQuaternion::from_scaled_axis(V3::new(0.0, 0.0, angle));
        let state = |(st, q): &(CentreState, UnitQuaternion<f64>)| {
            (
                CentreState {
                    velocity: map(&st.velocity),
                    pose: map(&st.pose),
                },
                turn * q * turn.inverse(),
            )
        };
        Held {
            dt: self.dt,
            per_period: self.per_period,
            samples: self.samples.iter().map(map).collect(),
            states: self.states.iter().map(state).collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::sample_hold;
    use crate::motion::{Motion, Signals};

    /// Finite samples whose integral overflows are refused, naming the
    /// first sample after which the state is not finite: 1e307 m/s² held
    /// 1 s from rest gives x = 1e307 (k + 1)²/2 after sample k, past f64's
    /// 1.797e308 first at k + 1 = 6 ((k + 1)² > 35.95).
    #[test]
    fn an_overflowing_integral_is_refused_naming_the_sample() {
        let file = HoldSamples {
            dt: 1.0,
            rate: 1.0,
            samples_per_period: 10,
            samples: vec![[1e307, 0.0, 0.0, 0.0, 0.0, 0.0]; 10],
            start: CentreState::default(),
        };
        let e = Held::new(&file).unwrap_err().to_string();
        assert!(
            e.starts_with("held samples[5]: ")
                && e.contains("is not finite after this one: the accelerations are not physical"),
            "{e}"
        );
        let mut ok = file.clone();
        ok.samples.truncate(5);
        assert!(Held::new(&ok).is_ok());
    }

    /// The held motion of an exported six-signal motion matches it at
    /// every sample time in velocity (exact, by the mean-acceleration
    /// samples) and in pose to the trapezoidal rule's error from the start,
    /// Δt²/12 |a(t_k) − a(0)| ≤ Δt²/6 max|a| (exact again after a whole
    /// period), and within an interval the velocity is off by at most
    /// a′Δt²/8 (the module's bound).
    #[test]
    fn held_export_follows_the_motion() {
        let sig = Signals::example();
        let motion = Motion::Signals(sig.clone());
        let file = sample_hold::periodic(&motion, 10_000.0).unwrap();
        let held = Held::new(&file).unwrap();
        let dt = held.dt();
        // |a′| ≤ Σ A nω over the x channel's terms.
        let w = 2.0 * std::f64::consts::PI / sig.period;
        let jerk = 10.0 * w + 2.0 * 2.0 * w;
        // max|a| per channel ≤ the sum of its amplitudes.
        let peak = [12.0, 10.0, 0.0, 65.0, 65.0, 0.0];
        for k in [0, 7, 123, held.len() - 1, held.len()] {
            let exact = sample_hold::centre_state(&motion, k as f64 * dt);
            let s = held.state_at(k);
            let whole = k == held.len();
            for (i, peak) in peak.iter().enumerate() {
                assert!((s.velocity[i] - exact.velocity[i]).abs() < 1e-12, "{k} {i}");
                // The angular pose is composed: off exp([θ]×) also by the
                // held samples' coning, O((ωΔt)²) of the cone's own turn
                // (`motion::sample_hold`), within (ωΔt)²ε² = 2.7e-9 rad for the
                // example's tilt ε = 4.1e-3 rad at ω = 126 rad/s.
                let bound = match (whole, i < 3) {
                    (true, true) => 0.0,
                    (false, true) => dt * dt / 6.0 * peak,
                    (_, false) => (dt * dt / 6.0 * peak).max(3e-9),
                };
                let e = (s.pose[i] - exact.pose[i]).abs();
                assert!(e <= bound + 1e-14, "{k} {i}: {e:e} > {bound:e}");
            }
            if whole {
                continue;
            }
            let t = (k as f64 + 0.5) * dt;
            let mid = held.centre_state_piece(t, t);
            let e = sample_hold::centre_state(&motion, t);
            let err = (mid.velocity[0] - e.velocity[0]).abs();
            assert!(err <= jerk * dt * dt / 8.0 * 1.01, "{k}: {err:e}");
        }
        // Kinematics: the centre's acceleration is the held sample.
        let t = 41.3 * dt;
        let kin = held.kinematics(t, t, 9.81, false);
        assert!((kin.accel_center.x - file.samples[41][0]).abs() < 1e-12);
    }

    /// A slice plays as the whole does from its first sample.
    #[test]
    fn a_slice_starts_where_the_whole_is() {
        let motion = Motion::Signals(Signals::example());
        let held = Held::new(&sample_hold::periodic(&motion, 4_000.0).unwrap()).unwrap();
        let part = held.slice(50..120);
        let dt = held.dt();
        let t = 13.25 * dt;
        let (a, b) = (
            part.centre_state_piece(t, t),
            held.centre_state_piece(t + 50.0 * dt, t + 50.0 * dt),
        );
        for i in 0..6 {
            // Equal but for the rounding of τ = t − kΔt.
            assert!((a.velocity[i] - b.velocity[i]).abs() <= 1e-15, "{i}");
            assert!((a.pose[i] - b.pose[i]).abs() <= 1e-15, "{i}");
        }
        assert_eq!(part.len(), 70);
    }

    /// Turning by 90° maps x acceleration to y; a shift adds Ω' × (−s).
    #[test]
    fn transformed_turns_and_shifts() {
        let file = HoldSamples {
            dt: 0.01,
            rate: 100.0,
            samples_per_period: 1,
            samples: vec![[1.0, 0.0, 0.0, 0.0, 0.0, 2.0]],
            start: CentreState::default(),
        };
        let held = Held::new(&file).unwrap();
        let turned = held.transformed(std::f64::consts::FRAC_PI_2, [0.0, 0.0]);
        let a = turned.samples[0];
        assert!(a[0].abs() < 1e-15 && (a[1] - 1.0).abs() < 1e-15);
        let shifted = held.transformed(0.0, [0.1, 0.0]);
        // Ω' = (0, 0, 2), −s = (−0.1, 0, 0): Ω' × (−s) = (0, −0.2, 0).
        assert!((shifted.samples[0][1] + 0.2).abs() < 1e-15);
    }

    /// A worked example of `motion::held::Held::new`.
    #[test]
    fn example_held_new() {
        use crate::motion::sample_hold::{CentreState, HoldSamples};
        use crate::motion::Held;

        // 1 m/s² along x for 0.1 s, then −1 m/s² for 0.1 s: rest to rest.
        let file = HoldSamples {
            dt: 0.1,
            rate: 10.0,
            samples_per_period: 2,
            samples: vec![
                [1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
                [-1.0, 0.0, 0.0, 0.0, 0.0, 0.0],
            ],
            start: CentreState::default(),
        };
        let held = Held::new(&file).unwrap();
        let end = held.state_at(2);
        assert!(end.velocity[0].abs() < 1e-15);
        assert!((end.pose[0] - 0.01).abs() < 1e-15); // x = a Δt² = 0.01 m
    }
}
