//! A six-signal motion switched on and off smoothly, so that it can be
//! played between rest-to-rest primitives (a segment of a mixed schedule).
//!
//! A six-signal motion has zero-mean velocity and pose only from its own
//! steady initial state, not from rest: started abruptly it would make the
//! plate's pose and velocity jump at the join. [`Ramped`] plays its
//! plate-centre pose (linear, and the rotation vector θ) through a window,
//!
//! ```text
//! x(t) = w(t) x_ss(t),   x' = w′ x_ss + w v_ss,   x'' = w″ x_ss + 2 w′ v_ss + w a_ss
//! ```
//!
//! over N = `cycles` periods: w rises over the first R = `ramp` cycles by
//! the quintic smoothstep w = 10s³ − 15s⁴ + 6s⁵ of s = t/(RT), is 1 in
//! between and falls by its mirror over the last R cycles. w, w′ and w″
//! vanish at both ends of a ramp, so the segment starts and ends at rest in
//! the home pose, and its acceleration joins the steady motion continuously
//! (C²). The kinematics in the plate frame then follow from (x, x', x'') and
//! (θ, θ', θ'') exactly as the steady motion's do
//! ([`Signals`], first order in the small rotation). During a ramp the
//! acceleration can exceed the steady peak by about 2·max w′/ω + max w″/ω²
//! of it (1.875/(πR) + 0.146/R² for one harmonic).
//!
//! The same window, sampled, is what `export` writes for a lone six-signal
//! motion ([`super::sample_hold::ramped`]).

use super::{Kinematics, Signals, V3};
use crate::error::{Error, Result};

/// The quintic smoothstep w(s) = 10s³ − 15s⁴ + 6s⁵ on [0, 1] (clamped
/// outside) with dw/ds and d²w/ds².
pub(crate) fn smoothstep(s: f64) -> [f64; 3] {
    let s = s.clamp(0.0, 1.0);
    [
        s * s * s * (10.0 + s * (-15.0 + 6.0 * s)),
        30.0 * s * s * (1.0 - s) * (1.0 - s),
        60.0 * s * (1.0 - s) * (1.0 - 2.0 * s),
    ]
}

/// A six-signal motion played for `cycles` periods inside a smooth window
/// that ramps in over the first `ramp` cycles and out over the last
/// `ramp` (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct Ramped {
    /// The steady motion.
    pub signals: Signals,
    /// Cycles of each ramp (≥ 1).
    pub ramp: u32,
    /// Cycles of the whole segment, ramps included (≥ 2 · `ramp`).
    pub cycles: u32,
}

impl Ramped {
    /// A ramped motion; `field` names the segment in errors.
    ///
    /// # Errors
    /// `ramp` = 0 or `cycles` < 2 · `ramp` (names `{field}.ramp_cycles`).
    pub fn new(signals: Signals, ramp: u32, cycles: u32, field: &str) -> Result<Ramped> {
        Ramped::check(ramp, cycles, field)?;
        Ok(Ramped {
            signals,
            ramp,
            cycles,
        })
    }

    /// Checks 1 ≤ `ramp` ≤ `cycles`/2 (a ramp in and a ramp out fit in the
    /// segment), naming `{field}.ramp_cycles`.
    pub(crate) fn check(ramp: u32, cycles: u32, field: &str) -> Result<()> {
        if ramp == 0 || u64::from(cycles) < 2 * u64::from(ramp) {
            return Err(Error::invalid(
                format!("{field}.ramp_cycles"),
                format!(
                    "must be in 1..={} for a segment of {cycles} cycles (a ramp in and a ramp out), got {ramp}",
                    cycles / 2
                ),
            ));
        }
        Ok(())
    }

    /// Duration of the whole segment N·T (s).
    pub(crate) fn span(&self) -> f64 {
        f64::from(self.cycles) * self.signals.period
    }

    /// The window w(t) and its first two time derivatives.
    pub(crate) fn window(&self, t: f64) -> [f64; 3] {
        let ramp_time = f64::from(self.ramp) * self.signals.period;
        let (r1, r2) = (1.0 / ramp_time, 1.0 / (ramp_time * ramp_time));
        if t < ramp_time {
            let [w, dw, ddw] = smoothstep(t * r1);
            [w, dw * r1, ddw * r2]
        } else if t > self.span() - ramp_time {
            let [w, dw, ddw] = smoothstep((self.span() - t) * r1);
            [w, -dw * r1, ddw * r2]
        } else {
            [1.0, 0.0, 0.0]
        }
    }

    /// The windowed (value, rate, acceleration) of a steady triple.
    fn windowed(w: &[f64; 3], x: &[V3; 3]) -> [V3; 3] {
        [
            x[0] * w[0],
            x[0] * w[1] + x[1] * w[0],
            x[0] * w[2] + x[1] * (2.0 * w[1]) + x[2] * w[0],
        ]
    }

    /// Plate-centre (pose, velocity) of the windowed motion at `t`:
    /// linear then angular components.
    pub(crate) fn centre_state(&self, t: f64) -> ([f64; 6], [f64; 6]) {
        let w = self.window(t);
        let (lin, ang) = self.signals.centre_triples(t);
        let (l, a) = (Self::windowed(&w, &lin), Self::windowed(&w, &ang));
        (
            [l[0].x, l[0].y, l[0].z, a[0].x, a[0].y, a[0].z],
            [l[1].x, l[1].y, l[1].z, a[1].x, a[1].y, a[1].z],
        )
    }

    /// Kinematics at `t` (segment time, 0 at the start of the ramp-in).
    #[inline]
    pub(crate) fn kinematics(&self, t: f64, g: f64, tilt: bool) -> Kinematics {
        self.kinematics_of(t, self.signals.centre_triples(t), g, tilt, f64::sin_cos)
    }

    /// [`Ramped::kinematics`] from the steady motion's centre triples at
    /// `t` (linear, angular), with `sin_cos` for the tilt angle.
    #[inline]
    pub(crate) fn kinematics_of(
        &self,
        t: f64,
        (lin, ang): ([V3; 3], [V3; 3]),
        g: f64,
        tilt: bool,
        sin_cos: impl Fn(f64) -> (f64, f64),
    ) -> Kinematics {
        let w = self.window(t);
        Signals::frame_with(
            &Self::windowed(&w, &lin),
            &Self::windowed(&w, &ang),
            g,
            tilt,
            sin_cos,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramped() -> Ramped {
        Ramped::new(Signals::example(), 3, 10, "segment").unwrap()
    }

    /// Starts and ends at rest in the home pose; steady in the middle,
    /// where it equals the steady motion bit for bit.
    #[test]
    fn rest_to_rest_and_steady_between() {
        let r = ramped();
        for t in [0.0, r.span()] {
            let (pose, vel) = r.centre_state(t);
            assert!(pose.iter().chain(&vel).all(|x| x.abs() < 1e-15), "{t}");
            let k = r.kinematics(t, 9.81, true);
            assert!(k.accel_center.norm() < 1e-12 && k.alpha.norm() < 1e-12);
        }
        let t = 5.3 * r.signals.period;
        assert_eq!(
            r.kinematics(t, 9.81, true),
            r.signals.kinematics(t, 9.81, true)
        );
    }

    /// The windowed velocity is the derivative of the windowed pose and the
    /// acceleration that of the velocity (central differences, across the
    /// ramp and at its joins).
    #[test]
    fn derivatives_are_consistent() {
        let r = ramped();
        let h = 1e-6 * r.signals.period;
        for k in 1..100 {
            let t = r.span() * f64::from(k) / 100.0;
            let (p0, _) = r.centre_state(t - h);
            let (p1, _) = r.centre_state(t + h);
            let (_, v) = r.centre_state(t);
            for i in 0..6 {
                let fd = (p1[i] - p0[i]) / (2.0 * h);
                assert!((fd - v[i]).abs() <= 1e-6 * (1.0 + v[i].abs()), "{t} {i}");
            }
            let a0 = r.kinematics(t - h, 0.0, false).vel_center;
            let a1 = r.kinematics(t + h, 0.0, false).vel_center;
            let a = r.kinematics(t, 0.0, false).accel_center;
            assert!(((a1 - a0) / (2.0 * h) - a).norm() <= 1e-5 * (1.0 + a.norm()));
        }
    }

    #[test]
    fn ramp_longer_than_half_is_refused() {
        let e = Ramped::new(Signals::example(), 6, 10, "segments[2]").unwrap_err();
        assert!(e.to_string().contains("segments[2].ramp_cycles"), "{e}");
    }
}
