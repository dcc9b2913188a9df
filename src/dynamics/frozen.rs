//! The exact flow of a 2-D Coulomb slip under a frozen free acceleration
//! and normal force: the closed form that finishes a slip slowing to a
//! stop (`swing.rs`).
//!
//! With a = a_free and N constant, k = μ_k N/|a| and ψ the angle of the
//! slip velocity u from a, the slip u' = a − μ_k N û has, with s = |u|,
//!
//! ```text
//! ds/dt = |a| (cos ψ − k),   dψ/dt = −|a| sin ψ / s,
//! ```
//!
//! so ds/dψ = s (k − cos ψ)/sin ψ and, with w = tan(ψ/2),
//! s = C w^(k−1) (1 + w²)/2: ψ turns monotonically onto a (w → 0) and, for
//! k > 1, the speed reaches zero with it, in finite time (a stop). Writing
//! ρ = w/w₀ ∈ [0, 1] for the progress from the start (s₀, ψ₀), q = (1 + cos
//! ψ₀)/2, p = (1 − cos ψ₀)/2 and E_m(ρ) = (1 − ρ^m)/m, the flow is
//!
//! ```text
//! s(ρ)  = s₀ ρ^(k−1) (q + p ρ²)
//! u(ρ)  = s₀ ρ^(k−1) ((q − p ρ²) â + ρ sin ψ₀ ê)
//! t(ρ)  = (s₀/|a|) (q E_(k−1) + p E_(k+1))
//! x(ρ)  = (s₀²/|a|) (q² E_(2k−2) − p² E_(2k+2))          (along â)
//! y(ρ)  = (s₀²/|a|) sin ψ₀ (q E_(2k−1) + p E_(2k+1))      (along ê)
//! ```
//!
//! (ê ⊥ â on the side of u₀; from dt = −(s/(|a| w)) dw, dx = s cos ψ dt,
//! dy = s sin ψ dt). The stop is ρ = 0: after t(0) = (s₀/|a|)(q/(k−1) +
//! p/(k+1)), at the displacement (x(0), y(0)). Every term is bounded for
//! any ψ₀ ∈ [0, π] (ψ₀ = 0 is a straight slow-down with deceleration
//! μ_k N − |a|, ψ₀ = π one with μ_k N + |a|). Checked against a fine RK4
//! integration of the frozen equation in the tests below.

use super::integrator::V2;

/// The frozen flow from one slip state (k > 1: it ends in a stop).
#[derive(Debug, Clone, Copy)]
pub(super) struct Frozen {
    /// Unit vector along a.
    ex: V2,
    /// Unit vector across a, on the side of the initial slip velocity.
    ey: V2,
    /// |a|.
    a: f64,
    /// k = μ_k N/|a| (> 1).
    k: f64,
    /// Initial speed s₀.
    s0: f64,
    /// (1 + cos ψ₀)/2.
    q: f64,
    /// (1 − cos ψ₀)/2.
    p: f64,
    /// sin ψ₀ ≥ 0.
    sin0: f64,
}

/// (1 − ρ^m)/m for m > 0, accurate for small m.
fn e(m: f64, ln_rho: f64) -> f64 {
    -(m * ln_rho).exp_m1() / m
}

impl Frozen {
    /// The flow of u' = `a` − `mu_n` û from slip velocity `u` ≠ 0, or None
    /// where it does not end in a stop (μ_k N ≤ |a|) or a is too small to
    /// define the a-frame (|a| ≤ 1e-12 μ_k N; the caller then takes its
    /// other steps).
    pub(super) fn new(a: &V2, mu_n: f64, u: &V2) -> Option<Frozen> {
        let am = a.norm();
        let s0 = u.norm();
        if !(s0 > 0.0 && s0.is_finite() && am > 1e-12 * mu_n && mu_n > am) {
            return None;
        }
        let ex = a / am;
        let uhat = u / s0;
        let cos = uhat.dot(&ex).clamp(-1.0, 1.0);
        let cross = ex.x * uhat.y - ex.y * uhat.x;
        let sin0 = cross.abs();
        let side = if cross < 0.0 { -1.0 } else { 1.0 };
        let ey = V2::new(-ex.y, ex.x) * side;
        // q, p without cancellation: sin²ψ₀ = 4 p q.
        let (q, p) = if cos >= 0.0 {
            let q = 0.5 * (1.0 + cos);
            (q, 0.25 * sin0 * sin0 / q)
        } else {
            let p = 0.5 * (1.0 - cos);
            (0.25 * sin0 * sin0 / p, p)
        };
        Some(Frozen {
            ex,
            ey,
            a: am,
            k: mu_n / am,
            s0,
            q,
            p,
            sin0,
        })
    }

    /// Time t(ρ) from the start to progress ρ.
    fn time(&self, ln_rho: f64) -> f64 {
        let k = self.k;
        self.s0 / self.a * (self.q * e(k - 1.0, ln_rho) + self.p * e(k + 1.0, ln_rho))
    }

    /// Time to the stop, t(0).
    pub(super) fn stop_time(&self) -> f64 {
        self.time(f64::NEG_INFINITY)
    }

    /// Displacement from the start to progress ρ (ln ρ given).
    fn displacement(&self, ln_rho: f64) -> V2 {
        let (k, q, p) = (self.k, self.q, self.p);
        let c = self.s0 * self.s0 / self.a;
        let x = c * (q * q * e(2.0 * k - 2.0, ln_rho) - p * p * e(2.0 * k + 2.0, ln_rho));
        let y = c * self.sin0 * (q * e(2.0 * k - 1.0, ln_rho) + p * e(2.0 * k + 1.0, ln_rho));
        self.ex * x + self.ey * y
    }

    /// Slip velocity at progress ρ.
    fn velocity(&self, ln_rho: f64) -> V2 {
        let rho = ln_rho.exp();
        let f = self.s0 * ((self.k - 1.0) * ln_rho).exp();
        (self.ex * (self.q - self.p * rho * rho) + self.ey * (rho * self.sin0)) * f
    }

    /// Displacement from the start to the stop.
    pub(super) fn stop_displacement(&self) -> V2 {
        self.displacement(f64::NEG_INFINITY)
    }

    /// Displacement and slip velocity after time `dt` ≥ 0 (at the stop,
    /// zero velocity, from its time on).
    pub(super) fn at(&self, dt: f64) -> (V2, V2) {
        let total = self.stop_time();
        if dt >= total {
            return (self.stop_displacement(), V2::zeros());
        }
        if dt <= 0.0 {
            return (V2::zeros(), self.velocity(0.0));
        }
        // Root of t(ρ) = dt in λ = ln ρ ∈ (−∞, 0]: t is increasing in −λ,
        // dt/dλ = −(s₀/|a|) (q ρ^(k−1) + p ρ^(k+1)). Newton, safeguarded
        // by a bracket grown downwards from 0.
        let (mut hi, mut lo) = (0.0f64, -1.0f64);
        while self.time(lo) < dt && lo > -700.0 {
            hi = lo;
            lo *= 2.0;
        }
        let mut x = 0.5 * (lo + hi);
        for _ in 0..200 {
            let g = self.time(x) - dt;
            if g < 0.0 {
                hi = x;
            } else {
                lo = x;
            }
            let rho = x.exp();
            let slope = -self.s0 / self.a
                * (self.q * ((self.k - 1.0) * x).exp() + self.p * ((self.k + 1.0) * x).exp());
            let mut next = x - g / slope;
            if !(next > lo && next < hi) {
                next = 0.5 * (lo + hi);
            }
            let done = (next - x).abs() <= 1e-15 * (1.0 + x.abs()) || hi - lo <= 1e-15;
            x = next;
            if done || rho == 0.0 {
                break;
            }
        }
        (self.displacement(x), self.velocity(x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fine classical RK4 of u' = a − μN û, r' = u over `dt` in `n` steps.
    fn rk4(a: V2, mu_n: f64, u: V2, dt: f64, n: usize) -> (V2, V2) {
        let f = |u: V2| a - u / u.norm() * mu_n;
        let h = dt / n as f64;
        let (mut r, mut u) = (V2::zeros(), u);
        for _ in 0..n {
            let k1 = f(u);
            let u2 = u + k1 * (0.5 * h);
            let k2 = f(u2);
            let u3 = u + k2 * (0.5 * h);
            let k3 = f(u3);
            let u4 = u + k3 * h;
            let k4 = f(u4);
            r += (u + (u2 + u3) * 2.0 + u4) * (h / 6.0);
            u += (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
        }
        (r, u)
    }

    fn cases() -> Vec<(V2, f64, V2)> {
        let mut out = Vec::new();
        for &k in &[1.05, 1.5, 3.0] {
            for &psi in &[0.0f64, 0.3, 1.5, 2.5, 3.1] {
                for &side in &[1.0, -1.0] {
                    let a = V2::new(0.6, -0.8) * 2.0;
                    let ex = a / a.norm();
                    let ey = V2::new(-ex.y, ex.x) * side;
                    let u = (ex * psi.cos() + ey * psi.sin()) * 0.01;
                    out.push((a, k * a.norm(), u));
                }
            }
        }
        out
    }

    /// Midway to the stop, the closed form's position and velocity agree
    /// with 200000 RK4 steps of the frozen equation within 1e-11 of the
    /// start's speed (and of speed × stop time); the speed there is the
    /// closed form's s(ρ).
    #[test]
    fn flow_matches_fine_integration() {
        for (a, mu_n, u) in cases() {
            let f = Frozen::new(&a, mu_n, &u).expect("k > 1");
            let total = f.stop_time();
            for frac in [0.1, 0.5, 0.9] {
                let dt = frac * total;
                let (dr, du) = f.at(dt);
                let (r, v) = rk4(a, mu_n, u, dt, 200_000);
                let (s0, scale) = (u.norm(), u.norm() * total);
                assert!(
                    (du - v).norm() <= 1e-11 * s0,
                    "k {} u {u:?} frac {frac}: velocity {du:?} vs {v:?}",
                    mu_n / a.norm()
                );
                assert!(
                    (dr - r).norm() <= 1e-11 * scale,
                    "k {} u {u:?} frac {frac}: position {dr:?} vs {r:?}",
                    mu_n / a.norm()
                );
            }
        }
    }

    /// The stop: fine RK4 steps (t(0)/10⁵) of the frozen equation until
    /// the speed would no longer fall, the last bit s/(μN − a·û) (an error
    /// of order h² relative, but taken from where h μN/s nears RK4's
    /// stability limit, ψ still turning for k near 1): its time agrees with
    /// t(0) within 1e-5 relative (measured ≤ 3e-6), and its position at 0.9999 t(0) is within 1e-6 s₀ t(0) of
    /// the stop's. A straight slow-down (ψ₀ = 0) and a reversal (ψ₀ = π)
    /// reduce to s₀/(μN ∓ |a|).
    #[test]
    fn stop_matches_fine_integration() {
        for (a, mu_n, u) in cases() {
            let f = Frozen::new(&a, mu_n, &u).expect("k > 1");
            let total = f.stop_time();
            let scale = u.norm() * total;
            let h = total / 1e5;
            let (mut t, mut v) = (0.0, u);
            loop {
                let (_, next) = rk4(a, mu_n, v, h, 1);
                if next.dot(&v) <= 0.0 || next.norm() >= v.norm() {
                    break;
                }
                (t, v) = (t + h, next);
            }
            let decel = mu_n - a.dot(&v) / v.norm();
            let stop_time = t + v.norm() / decel;
            assert!(
                (stop_time / total - 1.0).abs() <= 1e-5,
                "{u:?}: stop at {stop_time:.9e}, closed form {total:.9e}"
            );
            let (r, _) = rk4(a, mu_n, u, 0.9999 * total, 100_000);
            let stop = f.stop_displacement();
            assert!(
                (r - stop).norm() <= 1e-6 * scale,
                "{u:?}: {:.2e}",
                (r - stop).norm() / scale
            );
        }
        let a = V2::new(1.0, 0.0);
        let straight = Frozen::new(&a, 2.0, &V2::new(0.5, 0.0)).expect("k > 1");
        assert!((straight.stop_time() - 0.5 / (2.0 - 1.0)).abs() <= 1e-15);
        let back = Frozen::new(&a, 2.0, &V2::new(-0.5, 0.0)).expect("k > 1");
        assert!((back.stop_time() - 0.5 / (2.0 + 1.0)).abs() <= 1e-15);
        assert!((back.stop_displacement() - V2::new(-0.25 / 6.0, 0.0)).norm() <= 1e-15);
    }

    /// No stop when μN ≤ |a| (the slip swings on): no frozen flow.
    #[test]
    fn no_stop_without_k_above_one() {
        let a = V2::new(1.0, 1.0);
        assert!(Frozen::new(&a, 1.0, &V2::new(0.1, 0.0)).is_none());
        assert!(Frozen::new(&a, 2.0, &V2::zeros()).is_none());
    }
}
