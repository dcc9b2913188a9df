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
//!
//! # The composition that follows a changing a_free and N ([`Cf4`])
//!
//! u' = a(t) − μ_k N(t) û is a combination, with coefficients depending on
//! t only, of fixed vector fields (the constant fields along x and y, and
//! −û), and a combination of frozen fields is a frozen field: the
//! commutator-free composition of Blanes and Moan, the frozen flow of
//! W₁ F₁ + W₂ F₂ over the first half of a span h and that of W₂ F₁ + W₁ F₂
//! over the second (F₁, F₂ the frozen (a, μ_k N) at the Gauss nodes
//! h (½ ∓ √3/6), W = ½ ± √3/3), is made of two closed forms. For smooth
//! fields it is of fourth order; here it is not: near a stop −û is stiff
//! (its Lipschitz constant μ_k N/s grows as s ∝ the span shrinks), and the
//! stop time's relative error falls only in proportion to the span, for
//! the composition as for the frozen flow at the start, but with a
//! constant several times smaller than the flow frozen at the start's or
//! the flow of the plain average of F₁ and F₂ (the test
//! `composition_follows_turning_field` asserts at most a quarter; measured:
//! `docs/dev/forward-model.md`, **Measurements behind the integrator's constants**).
//! For a stop the span is the stop time itself, found by iterating the
//! composition from the frozen flow at the start.

use super::state::V2;

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

/// The powers of ρ the flow is made of, at one progress ln ρ = λ ≤ 0, each
/// as ρ^m − 1 (no cancellation where ρ^m is close to 1): from two `expm1`
/// calls, A = ρ^(k−1) − 1 and D = ρ − 1, by (1 + a)(1 + b) − 1 = a + b (1 + a),
/// whose terms share a sign (both are ≤ 0), so each is as accurate as A and D.
#[derive(Debug, Clone, Copy)]
struct Powers {
    /// ρ^(k−1) − 1.
    a: f64,
    /// ρ − 1.
    d: f64,
}

/// (1 + x)(1 + y) − 1.
fn times(x: f64, y: f64) -> f64 {
    x + y * (1.0 + x)
}

impl Powers {
    /// At the stop, ρ = 0.
    const STOP: Powers = Powers { a: -1.0, d: -1.0 };

    fn new(k: f64, ln_rho: f64) -> Powers {
        Powers {
            a: ((k - 1.0) * ln_rho).exp_m1(),
            d: ln_rho.exp_m1(),
        }
    }

    /// ρ² − 1.
    fn rho2(&self) -> f64 {
        times(self.d, self.d)
    }

    /// ρ^(k+1) − 1.
    fn k_plus(&self) -> f64 {
        times(self.a, self.rho2())
    }
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

    /// Time t(ρ) from the start to progress ρ, with E_m = (1 − ρ^m)/m.
    fn time(&self, w: &Powers) -> f64 {
        let k = self.k;
        -self.s0 / self.a * (self.q * w.a / (k - 1.0) + self.p * w.k_plus() / (k + 1.0))
    }

    /// dt/d(ln ρ) = −(s₀/|a|) (q ρ^(k−1) + p ρ^(k+1)).
    fn time_slope(&self, w: &Powers) -> f64 {
        -self.s0 / self.a * (self.q * (1.0 + w.a) + self.p * (1.0 + w.k_plus()))
    }

    /// Time to the stop, t(0).
    pub(super) fn stop_time(&self) -> f64 {
        self.time(&Powers::STOP)
    }

    /// Displacement from the start to progress ρ.
    fn displacement(&self, w: &Powers) -> V2 {
        let (k, q, p) = (self.k, self.q, self.p);
        let c = self.s0 * self.s0 / self.a;
        // ρ^m − 1 for m = 2k − 2, 2k − 1, 2k + 1, 2k + 2.
        let m2 = times(w.a, w.a);
        let m1 = times(m2, w.d);
        let p1 = times(m1, w.rho2());
        let p2 = times(w.k_plus(), w.k_plus());
        let x = -c * (q * q * m2 / (2.0 * k - 2.0) - p * p * p2 / (2.0 * k + 2.0));
        let y = -c * self.sin0 * (q * m1 / (2.0 * k - 1.0) + p * p1 / (2.0 * k + 1.0));
        self.ex * x + self.ey * y
    }

    /// Slip velocity at progress ρ.
    fn velocity(&self, w: &Powers) -> V2 {
        let rho = 1.0 + w.d;
        let f = self.s0 * (1.0 + w.a);
        (self.ex * (self.q - self.p * rho * rho) + self.ey * (rho * self.sin0)) * f
    }

    /// Displacement from the start to the stop.
    pub(super) fn stop_displacement(&self) -> V2 {
        self.displacement(&Powers::STOP)
    }

    /// Displacement and slip velocity after time `dt` ≥ 0 (at the stop,
    /// zero velocity, from its time on). The velocity is accurate to a few
    /// ε s₀ absolute, not relative: within about ε of the stop time the
    /// time left, total − dt, is itself known only to ε total, and the
    /// speed there (≲ ε s₀ (1 + k)) may round to zero just before the stop.
    /// The caller that ends a step there (`swing.rs`, a stop within the
    /// event tolerance past the step's end) leaves u = 0 with the stuck
    /// status undecided, which the integrator decides on its next step, as
    /// after any stop.
    pub(super) fn at(&self, dt: f64) -> (V2, V2) {
        let total = self.stop_time();
        if dt >= total {
            return (self.stop_displacement(), V2::zeros());
        }
        if dt <= 0.0 {
            return (V2::zeros(), self.velocity(&Powers::new(self.k, 0.0)));
        }
        // The progress λ = ln ρ ∈ (−∞, 0] at which t(λ) = dt, by Newton's
        // method on a function whose curvature makes every iterate stay on
        // one side of the root (no bracket needed):
        // * in the first half of the time to the stop, on t itself: in
        //   −λ it is increasing and concave (each E_m is), so from the
        //   first-order guess λ = −dt |a|/s₀ (the tangent at λ = 0, short of
        //   the root) the iterates rise to the root;
        // * in the second half, on the log of the time left to the stop,
        //   H(λ) = ln((s₀/|a|)(q ρ^(k−1)/(k−1) + p ρ^(k+1)/(k+1))) −
        //   ln(total − dt): a log-sum of exponentials in λ, increasing and
        //   convex with a slope between k − 1 and k + 1, so from a λ above
        //   the root the iterates fall to it — where t itself is flat
        //   (ρ^(k±1) ≪ 1) and Newton on it overshoots.
        // Newton iterations per call on DivCircle's force field: 3.75,
        // against 8.4 for a bracketed Newton on t alone.
        let late = dt > 0.5 * total;
        let (c0, c1) = (self.q / (self.k - 1.0), self.p / (self.k + 1.0));
        let target = ((total - dt) * self.a / self.s0).ln();
        let mut x = if late {
            // Each term alone reaches the time left at a λ at or above the
            // root: the lower of the two.
            ((target - c0.ln()) / (self.k - 1.0))
                .min((target - c1.ln()) / (self.k + 1.0))
                .min(0.0)
        } else {
            -dt * self.a / self.s0
        };
        let mut last_step = 0.0f64;
        for _ in 0..100 {
            let step = if late {
                let b = c1 * (2.0 * x).exp();
                ((self.k - 1.0) * x + (c0 + b).ln() - target)
                    / ((self.k - 1.0) + 2.0 * b / (c0 + b))
            } else {
                let w = Powers::new(self.k, x);
                (self.time(&w) - dt) / self.time_slope(&w)
            };
            let next = x - step;
            // (A NaN step ends the iteration too.) The iterates move one
            // way (above), so a step that turns back is round-off: where
            // the root is ill-conditioned (k near 1, ψ₀ near π) it would
            // otherwise dither at that level until the cap.
            let moving = step.abs() > 1e-15 * (1.0 + x.abs());
            let turned = step * last_step < 0.0 && step.abs() <= 1e-9 * (1.0 + x.abs());
            let done = !moving || next == x || turned || !next.is_finite();
            if next.is_finite() {
                x = next;
            }
            if done {
                break;
            }
            last_step = step;
        }
        let w = Powers::new(self.k, x);
        (self.displacement(&w), self.velocity(&w))
    }
}

/// Gauss–Legendre nodes on [0, 1] (two points).
const GAUSS: [f64; 2] = [0.211_324_865_405_187_1, 0.788_675_134_594_812_9];

/// Weights W = ½ ± √3/3 of the commutator-free composition (module docs).
const CF4_W: [f64; 2] = [1.077_350_269_189_625_7, -0.077_350_269_189_625_7];

/// Iterations of the span of a stop (the stop time of the last
/// composition, with the fields at its Gauss nodes).
const CF4_ITERATIONS: usize = 3;

/// The frozen flows of the commutator-free composition over a span: the
/// first for half of it (or to its stop), the second from there.
#[derive(Debug, Clone, Copy)]
pub(super) struct Cf4 {
    first: Frozen,
    /// The second flow and the first's displacement at `half`.
    second: Option<(Frozen, V2)>,
    half: f64,
}

impl Cf4 {
    /// The composition over `span` from slip velocity `u` with the frozen
    /// (a, μ_k N) `f` at the two Gauss nodes; None where a half does not
    /// end in a stop.
    fn new(f: &[(V2, f64); 2], span: f64, u: &V2) -> Option<Cf4> {
        let [w1, w2] = CF4_W;
        let mix = |p: f64, q: f64| (f[0].0 * p + f[1].0 * q, f[0].1 * p + f[1].1 * q);
        let (a, mu_n) = mix(w1, w2);
        let first = Frozen::new(&a, mu_n, u)?;
        let half = 0.5 * span;
        if first.stop_time() <= half {
            return Some(Cf4 {
                first,
                second: None,
                half,
            });
        }
        let (dr, uh) = first.at(half);
        let (a, mu_n) = mix(w2, w1);
        let second = Frozen::new(&a, mu_n, &uh)?;
        Some(Cf4 {
            first,
            second: Some((second, dr)),
            half,
        })
    }

    /// The path from slip velocity `u` to its stop or to `rest`, whichever
    /// comes first, starting from the frozen flow `start` at u: the span
    /// (stop time, at most `rest`) and the composition over it are iterated
    /// [`CF4_ITERATIONS`] times, `field(dt, dr, u)` giving (a, μ_k N) at time
    /// dt, displacement dr and slip velocity u along the last path. None
    /// where μ_k N ≤ |a| at a node (the slip may swing past u = 0 rather
    /// than stop) or a half does not stop.
    pub(super) fn to_stop<E>(
        start: Frozen,
        u: &V2,
        rest: f64,
        mut field: impl FnMut(f64, &V2, &V2) -> Result<(V2, f64), E>,
    ) -> Result<Option<Cf4>, E> {
        let mut path = Cf4 {
            first: start,
            second: None,
            half: f64::INFINITY,
        };
        for _ in 0..CF4_ITERATIONS {
            let span = path.stop_time().min(rest);
            let mut f = [(V2::zeros(), 0.0); 2];
            for (fi, c) in f.iter_mut().zip(GAUSS) {
                let dt = c * span;
                let (dr, ui) = path.at(dt);
                *fi = field(dt, &dr, &ui)?;
            }
            if f.iter().any(|(a, mu_n)| *mu_n <= a.norm()) {
                return Ok(None);
            }
            match Cf4::new(&f, span, u) {
                Some(p) => path = p,
                None => return Ok(None),
            }
        }
        Ok(Some(path))
    }

    /// Time to the stop.
    pub(super) fn stop_time(&self) -> f64 {
        match &self.second {
            Some((b, _)) => self.half + b.stop_time(),
            None => self.first.stop_time(),
        }
    }

    /// Displacement and slip velocity after `dt`.
    pub(super) fn at(&self, dt: f64) -> (V2, V2) {
        match &self.second {
            Some((b, dr)) if dt > self.half => {
                let (d2, u) = b.at(dt - self.half);
                (dr + d2, u)
            }
            _ => self.first.at(dt),
        }
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

    /// The exact flow is a semigroup: the flow from the state reached
    /// after dt₁, run for dt₂, ends where the flow from the start run for
    /// dt₁ + dt₂ does, within 1e-12 of the start's speed (and of speed ×
    /// stop time) — across the switch between the two root-finding
    /// branches of `at` (half the stop time) and close to the stop.
    #[test]
    fn flow_is_a_semigroup_across_the_root_finders() {
        let mut extreme = cases();
        for &k in &[1.0 + 1e-9, 40.0] {
            for &psi in &[0.0f64, 1.0, std::f64::consts::PI] {
                let a = V2::new(1.0, 0.0);
                let u = V2::new(psi.cos(), psi.sin()) * 0.3;
                extreme.push((a, k, u));
            }
        }
        for (a, mu_n, u) in extreme {
            let f = Frozen::new(&a, mu_n, &u).expect("k > 1");
            let total = f.stop_time();
            let scale = u.norm() * total;
            for (x1, x2) in [
                (0.3, 0.4),
                (0.45, 0.1),
                (0.2, 0.299_999),
                (0.9, 0.099_9),
                (0.6, 0.399_999),
            ] {
                let (r1, u1) = f.at(x1 * total);
                let (r12, u12) = f.at((x1 + x2) * total);
                let g = Frozen::new(&a, mu_n, &u1).expect("still slipping");
                let (r2, u2) = g.at(x2 * total);
                assert!(
                    (u2 - u12).norm() <= 1e-12 * u.norm(),
                    "k {mu_n} u {u:?} {x1}+{x2}: velocity {u2:?} vs {u12:?}"
                );
                assert!(
                    (r1 + r2 - r12).norm() <= 1e-12 * scale,
                    "k {mu_n} u {u:?} {x1}+{x2}: position {:?} vs {r12:?}",
                    r1 + r2
                );
            }
        }
    }

    /// A slip along a (ψ₀ = 0) or against it (ψ₀ = π) slows down at the
    /// constant rate μ_k N ∓ |a|: s = s₀ − (μ_k N ∓ |a|) t, x = s₀ t −
    /// (μ_k N ∓ |a|) t²/2 along u₀. The root finders of `at` and the closed
    /// form agree with it within 1e-13 s₀ (velocity) and 1e-13 s₀ t_stop
    /// (position), from k = 1 + 1e-9 to k = 40, in both branches and to
    /// within 1e-15 of the stop time.
    #[test]
    fn straight_slow_downs_are_elementary() {
        for &k in &[1.0 + 1e-9, 1.05, 3.0, 40.0] {
            for (psi, sign) in [(0.0f64, -1.0), (std::f64::consts::PI, 1.0)] {
                let a = V2::new(0.6, -0.8) * 2.0;
                let ex = a / a.norm();
                let u = V2::new(psi.cos() * ex.x, psi.cos() * ex.y) * 0.3;
                let f = Frozen::new(&a, k * a.norm(), &u).expect("k > 1");
                let decel = k * a.norm() + sign * a.norm();
                let s0 = u.norm();
                let total = s0 / decel;
                assert!(
                    (f.stop_time() - total).abs() <= 1e-13 * total,
                    "k {k} psi {psi}: stop {} vs {total}",
                    f.stop_time()
                );
                let along = u / s0;
                for frac in [0.1, 0.4999, 0.5001, 0.9, 1.0 - 1e-9, 1.0 - 1e-15] {
                    let t = frac * total;
                    let (r, v) = f.at(t);
                    let v_exact = along * (s0 - decel * t);
                    let r_exact = along * (s0 * t - 0.5 * decel * t * t);
                    assert!(
                        (v - v_exact).norm() <= 1e-13 * s0,
                        "k {k} psi {psi} at {frac}: velocity {v:?} vs {v_exact:?}"
                    );
                    assert!(
                        (r - r_exact).norm() <= 1e-13 * s0 * total,
                        "k {k} psi {psi} at {frac}: position {r:?} vs {r_exact:?}"
                    );
                }
            }
        }
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
    /// t(0) within 1e-5 relative, and its position at 0.9999 t(0) is within 1e-6 s₀ t(0) of
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

    /// A stop under a turning a(t) = |a| (cos ωt, sin ωt) and a growing
    /// μN(t) = μN₀ (1 + βt), against 10⁵ fine RK4 steps of the
    /// time-dependent equation (stop where the speed would no longer fall,
    /// the last bit s/(μN − a·û)), for stops of shrinking length (ω t_stop
    /// from 0.4 to 0.025): the composition's stop time and stop position
    /// are within 1e-2 relative, its stop-time error at
    /// most a quarter of the flow frozen at the start,
    /// and from ω t_stop = 0.2 on it falls at least 1.7-fold per halving of
    /// the span (first order relative, see the module docs).
    #[test]
    fn composition_follows_turning_field() {
        let (am, k0, beta) = (2.0, 1.3, 3.0);
        let fine = |omega: f64, u0: V2, total: f64| {
            let f = |t: f64, u: V2| {
                let a = V2::new((omega * t).cos(), (omega * t).sin()) * am;
                a - u / u.norm() * (k0 * am * (1.0 + beta * t))
            };
            let h = total / 1e5;
            let (mut t, mut r, mut u) = (0.0, V2::zeros(), u0);
            loop {
                let k1 = f(t, u);
                let u2 = u + k1 * (0.5 * h);
                let k2 = f(t + 0.5 * h, u2);
                let u3 = u + k2 * (0.5 * h);
                let k3 = f(t + 0.5 * h, u3);
                let u4 = u + k3 * h;
                let k4 = f(t + h, u4);
                let next = u + (k1 + (k2 + k3) * 2.0 + k4) * (h / 6.0);
                if next.dot(&u) <= 0.0 || next.norm() >= u.norm() {
                    let a = V2::new((omega * t).cos(), (omega * t).sin()) * am;
                    let decel = k0 * am * (1.0 + beta * t) - a.dot(&u) / u.norm();
                    let left = u.norm() / decel;
                    return (t + left, r + u * (0.5 * left));
                }
                r += (u + (u2 + u3) * 2.0 + u4) * (h / 6.0);
                (t, u) = (t + h, next);
            }
        };
        let mut last = f64::NAN;
        let mut last_frozen = f64::NAN;
        let omega = 40.0;
        for omega_t in [0.4, 0.2, 0.1, 0.05, 0.025] {
            let start =
                Frozen::new(&V2::new(am, 0.0), k0 * am, &V2::new(-0.3, 1.0)).expect("k > 1");
            // s₀ such that ω t_stop = omega_t.
            let u0 = V2::new(-0.3, 1.0) * (omega_t / omega / start.stop_time());
            let start = Frozen::new(&V2::new(am, 0.0), k0 * am, &u0).expect("k > 1");
            let field = |dt: f64, _: &V2, _: &V2| -> Result<(V2, f64), ()> {
                let a = V2::new((omega * dt).cos(), (omega * dt).sin()) * am;
                Ok((a, k0 * am * (1.0 + beta * dt)))
            };
            let path = Cf4::to_stop(start, &u0, f64::INFINITY, field)
                .expect("no error")
                .expect("a stop");
            let (t_ref, r_ref) = fine(omega, u0, start.stop_time() * 1.5);
            let t_err = (path.stop_time() / t_ref - 1.0).abs();
            let r_err = (path.at(path.stop_time()).0 - r_ref).norm() / r_ref.norm();
            let frozen_err = (start.stop_time() / t_ref - 1.0).abs();
            println!(
                "ω t_stop {omega_t}: stop time {t_err:.2e}, position {r_err:.2e} (frozen at the start {frozen_err:.2e})"
            );
            assert!(
                t_err <= 1e-2 && r_err <= 1e-2,
                "ω t {omega_t}: {t_err:.2e} {r_err:.2e}"
            );
            assert!(
                4.0 * t_err <= frozen_err,
                "ω t {omega_t}: {t_err:.2e} vs {frozen_err:.2e}"
            );
            if omega_t <= 0.1 {
                assert!(
                    last / t_err >= 1.7,
                    "ω t {omega_t}: {last:.2e} → {t_err:.2e}"
                );
            }
            assert!(frozen_err < last_frozen || last_frozen.is_nan());
            (last, last_frozen) = (t_err, frozen_err);
        }
    }
}
