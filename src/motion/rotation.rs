//! The plate's orientation and its rates, exactly.
//!
//! **The convention.** The plate's orientation is R = exp(\[θ\]×), θ the
//! rotation vector (rad, world axes: R turns by |θ| about θ/|θ|). Its
//! angular velocity ω and angular acceleration α = ω′ are the physical
//! ones, in world axes: R′ = \[ω\]× R. They follow from θ, θ′, θ″ through
//! the left Jacobian of the exponential map,
//!
//! ```text
//! ω = J(θ) θ′,    J(θ) = I + a [θ]× + b [θ]×²,
//! a = (1 − cos t)/t²,   b = (t − sin t)/t³,   t = |θ|,
//! α = ω′ = J(θ) θ″ + a′ θ × θ′ + b′ θ × (θ × θ′) + b θ′ × (θ × θ′),
//! a′ = a₁ (θ·θ′),  a₁ = (t sin t − 2(1 − cos t))/t⁴,
//! b′ = b₁ (θ·θ′),  b₁ = ((1 − cos t) t − 3(t − sin t))/t⁵
//! ```
//!
//! (d/dt (θ × θ′) = θ × θ″). In the plate's own (body) axes the rates are
//! Rᵀω and Rᵀα (d/dt (Rᵀω) = Rᵀα, for Rᵀ′ω = −\[Rᵀω\]× Rᵀω = 0). With one
//! fixed rotation axis (θ ∥ θ′ ∥ θ″) every correction vanishes and
//! ω = θ′, α = θ″.
//!
//! Near t = 0 the closed forms cancel (b₁'s numerator is t⁵/60 of terms
//! of t³/2), so below [`SERIES_BELOW`] their Taylor series are used:
//! a = Σ (−1)ⁿ t²ⁿ/(2n+2)!, b = Σ (−1)ⁿ t²ⁿ/(2n+3)!, a₁ = (da/dt)/t and
//! b₁ = (db/dt)/t term by term, which also leaves them independent of the
//! sine and cosine passed in.
//!
//! **Playing world-frame rates** (`advance`): a controller that holds α
//! constant over an interval τ, ω(s) = ω₀ + α s, turns the plate by
//! R(τ) = exp(\[Φ\]×) R₀ with the Magnus series
//! Φ = ω₀τ + ατ²/2 + (τ³/12) α × ω₀ + O(|ω|²|α|τ⁵), the first two terms
//! ∫ω, the third half the double integral of ω(s₁) × ω(s₂) over s₂ < s₁.

use nalgebra::{Rotation3, UnitQuaternion};

use super::V3;

/// Below this rotation angle (rad) the Jacobian's quotients are taken from
/// their Taylor series (see the module documentation).
pub const SERIES_BELOW: f64 = 0.5;

/// Terms of each series: the first left out is below 1e-22 at
/// [`SERIES_BELOW`].
const SERIES_TERMS: u32 = 9;

/// The quotients a, b, a₁, b₁ of the module documentation at angle `t`
/// with (sin t, cos t) = `sc`.
fn quotients(t: f64, (s, c): (f64, f64)) -> [f64; 4] {
    if t < SERIES_BELOW {
        // a = Σ (−1)ⁿ t²ⁿ/(2n+2)!, b = Σ (−1)ⁿ t²ⁿ/(2n+3)!, and a₁, b₁ their
        // derivatives over t: Σ_{n≥1} (−1)ⁿ 2n t²ⁿ⁻²/(2n+2)! and /(2n+3)!.
        let t2 = t * t;
        let (mut a, mut b, mut a1, mut b1) = (0.0, 0.0, 0.0, 0.0);
        // (−1)ⁿ t²ⁿ and the one before, and 1/(2n+2)!, 1/(2n+3)!.
        let (mut power, mut before, mut fa, mut fb) = (1.0, 0.0, 0.5, 1.0 / 6.0);
        for n in 0..SERIES_TERMS {
            a += power * fa;
            b += power * fb;
            // (−1)ⁿ 2n t²ⁿ⁻² = −2n (−1)ⁿ⁻¹ t²⁽ⁿ⁻¹⁾.
            let k = -2.0 * f64::from(n) * before;
            a1 += k * fa;
            b1 += k * fb;
            let m = f64::from(2 * n + 3);
            fa /= m * (m + 1.0);
            fb /= (m + 1.0) * (m + 2.0);
            before = power;
            power *= -t2;
        }
        return [a, b, a1, b1];
    }
    let (t2, t3) = (t * t, t * t * t);
    [
        (1.0 - c) / t2,
        (t - s) / t3,
        (t * s - 2.0 * (1.0 - c)) / (t2 * t2),
        ((1.0 - c) * t - 3.0 * (t - s)) / (t2 * t3),
    ]
}

/// World-frame angular velocity ω and acceleration α of the orientation
/// exp(\[θ\]×) from θ, θ′, θ″ (see the module documentation), with
/// `sin_cos` giving (sin, cos) of |θ|.
#[inline]
pub(crate) fn world_rates(
    theta: &V3,
    dtheta: &V3,
    ddtheta: &V3,
    sin_cos: impl Fn(f64) -> (f64, f64),
) -> (V3, V3) {
    let t = theta.norm();
    if t == 0.0 {
        return (*dtheta, *ddtheta);
    }
    let [a, b, a1, b1] = quotients(t, sin_cos(t));
    let c1 = theta.cross(dtheta);
    let c2 = theta.cross(&c1);
    let omega = dtheta + c1 * a + c2 * b;
    let d = theta.dot(dtheta);
    let alpha = ddtheta
        + theta.cross(ddtheta) * a
        + theta.cross(&theta.cross(ddtheta)) * b
        + c1 * (a1 * d)
        + c2 * (b1 * d)
        + dtheta.cross(&c1) * b;
    (omega, alpha)
}

/// The orientation exp(\[θ\]×) as a unit quaternion.
pub(crate) fn orientation(theta: &V3) -> UnitQuaternion<f64> {
    UnitQuaternion::from_scaled_axis(*theta)
}

/// The rotation vector θ of `q` (|θ| ≤ π).
pub(crate) fn rotation_vector(q: &UnitQuaternion<f64>) -> V3 {
    q.scaled_axis()
}

/// The orientation and world angular velocity `tau` after (`q`, `omega`)
/// with the world angular acceleration `alpha` held (see the module
/// documentation).
#[inline]
pub(crate) fn advance(
    q: &UnitQuaternion<f64>,
    omega: &V3,
    alpha: &V3,
    tau: f64,
) -> (UnitQuaternion<f64>, V3) {
    let phi =
        omega * tau + alpha * (0.5 * tau * tau) + alpha.cross(omega) * (tau * tau * tau / 12.0);
    (
        UnitQuaternion::from_scaled_axis(phi) * q,
        omega + alpha * tau,
    )
}

/// The fixed-axis x-y-z angles (roll about x, then pitch about y, then yaw
/// about z, all about the world axes: R = R_z(yaw) R_y(pitch) R_x(roll)) of
/// `q`, the angle set hexapod controllers take (rad).
pub(crate) fn xyz_angles(q: &UnitQuaternion<f64>) -> [f64; 3] {
    let (roll, pitch, yaw) = Rotation3::from(*q).euler_angles();
    [roll, pitch, yaw]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A tilt and spin path θ(t) with its derivatives.
    fn path(t: f64) -> [V3; 3] {
        let f = |t: f64| {
            V3::new(
                0.004 * (3.0 * t).sin(),
                0.003 * (3.0 * t + 1.0).cos(),
                0.6 * (2.0 * t).sin() + 0.1,
            )
        };
        let h = 1e-4;
        let d = (f(t + h) - f(t - h)) / (2.0 * h);
        let dd = (f(t + h) - 2.0 * f(t) + f(t - h)) / (h * h);
        [f(t), d, dd]
    }

    /// ω and α against central differences of the orientation exp([θ]×):
    /// [ω]× = R′Rᵀ, and α the difference of ω; on both sides of the series
    /// switch.
    #[test]
    fn rates_are_the_derivatives_of_the_orientation() {
        for scale in [1.0, 1e-2, 1e-3] {
            let at = |t: f64| {
                let [th, d, dd] = path(t);
                [th * scale, d * scale, dd * scale]
            };
            for k in 0..20 {
                let t = 0.37 * f64::from(k);
                let [th, d, dd] = at(t);
                let (w, a) = world_rates(&th, &d, &dd, f64::sin_cos);
                let h = 1e-5;
                let (q0, q1) = (orientation(&at(t - h)[0]), orientation(&at(t + h)[0]));
                let fd = (q1 * q0.inverse()).scaled_axis() / (2.0 * h);
                assert!(
                    (fd - w).norm() < 1e-8 * (1.0 + w.norm()),
                    "{scale} {t}: {fd} {w}"
                );
                let (w0, _) = {
                    let p = at(t - h);
                    world_rates(&p[0], &p[1], &p[2], f64::sin_cos)
                };
                let (w1, _) = {
                    let p = at(t + h);
                    world_rates(&p[0], &p[1], &p[2], f64::sin_cos)
                };
                let fa = (w1 - w0) / (2.0 * h);
                assert!(
                    (fa - a).norm() < 1e-5 * (1.0 + a.norm()),
                    "{scale} {t}: {fa} {a}"
                );
            }
        }
    }

    /// The series and the closed forms agree at the switch.
    #[test]
    fn series_meets_closed_form() {
        let t = SERIES_BELOW;
        let s = quotients(t * (1.0 - 1e-12), t.sin_cos());
        let c = quotients(t, t.sin_cos());
        for (x, y) in s.iter().zip(&c) {
            assert!((x - y).abs() < 1e-13 * y.abs(), "{x} {y}");
        }
        // The first terms: 1/2, 1/6, −1/12, −1/60 at t = 0.
        let zero = quotients(0.0, (0.0, 1.0));
        assert_eq!(zero, [0.5, 1.0 / 6.0, -1.0 / 12.0, -1.0 / 60.0]);
    }

    /// Held acceleration over many short holds reproduces a smooth
    /// rotation's orientation (the Magnus step's error is O(τ⁵) per hold).
    #[test]
    fn advance_follows_a_smooth_rotation() {
        let (mut q, mut w) = (
            orientation(&path(0.0)[0]),
            world_rates(&path(0.0)[0], &path(0.0)[1], &path(0.0)[2], f64::sin_cos).0,
        );
        let n = 4000;
        let dt = 2.0 / f64::from(n);
        for k in 0..n {
            let p0 = path(f64::from(k) * dt);
            let p1 = path(f64::from(k + 1) * dt);
            let w1 = world_rates(&p1[0], &p1[1], &p1[2], f64::sin_cos).0;
            let _ = p0;
            (q, w) = advance(&q, &w, &((w1 - w) / dt), dt);
        }
        let end = orientation(&path(2.0)[0]);
        assert!(
            (q.inverse() * end).angle() < 1e-6,
            "{}",
            (q.inverse() * end).angle()
        );
    }

    /// A worked example of `motion::rotation::world_rates`.
    #[test]
    fn example_world_rates() {
        use crate::motion::rotation::world_rates;
        use crate::motion::V3;

        // One fixed axis: ω = θ′, α = θ″.
        let (w, a) = world_rates(
            &V3::new(0.0, 0.0, 0.3),
            &V3::new(0.0, 0.0, 2.0),
            &V3::new(0.0, 0.0, -5.0),
            f64::sin_cos,
        );
        assert!(
            (w - V3::new(0.0, 0.0, 2.0)).norm() < 1e-15
                && (a - V3::new(0.0, 0.0, -5.0)).norm() < 1e-15
        );
        // Coning: θ = ε(cos t, sin t, 0) turns about z on average, ω_z = a ε² ≈ ε²/2.
        let e = 1e-3;
        let (w, _) = world_rates(
            &V3::new(e, 0.0, 0.0),
            &V3::new(0.0, e, 0.0),
            &V3::new(-e, 0.0, 0.0),
            f64::sin_cos,
        );
        assert!((w.z - e * e / 2.0).abs() < 1e-13);
    }

    /// A worked example of `motion::rotation::advance`.
    #[test]
    fn example_advance() {
        use crate::motion::rotation::{advance, orientation, rotation_vector};
        use crate::motion::V3;

        // Spun up about z from rest: θ_z = α τ²/2.
        let (q, w) = advance(
            &orientation(&V3::zeros()),
            &V3::zeros(),
            &V3::new(0.0, 0.0, 2.0),
            0.1,
        );
        assert!((rotation_vector(&q).z - 0.01).abs() < 1e-15 && (w.z - 0.2).abs() < 1e-15);
    }

    /// A worked example of `motion::rotation::xyz_angles`.
    #[test]
    fn example_xyz_angles() {
        use crate::motion::rotation::{orientation, xyz_angles};
        use crate::motion::V3;

        let [roll, pitch, yaw] = xyz_angles(&orientation(&V3::new(0.0, 0.0, 0.25)));
        assert!(roll.abs() < 1e-15 && pitch.abs() < 1e-15 && (yaw - 0.25).abs() < 1e-15);
    }
}
