//! The implicit Coulomb step of the planar integrator: the exact minimiser of
//!
//! ```text
//! f(z) = ½ |z − z_f|² + μ Σ_j w_j |B_j z|,    B_j z = (z₀ + z₂ c_j,x, z₁ + z₂ c_j,y)
//! ```
//!
//! over z ∈ R³ (the generalised slip velocity scaled so that the mass matrix
//! is the identity: z = (u_x, u_y, ω √(I/m)); c_j = k × a_j / √(I/m) with a_j
//! the support point's lever arm; μ w_j ≥ 0 its largest friction impulse per
//! unit mass). f is strictly convex and non-smooth where some B_j z = 0.
//! By Moreau's decomposition its minimiser is z_f − Π_C(z_f), with C = Σ_j μ w_j
//! B_jᵀ D (D the unit disc) the set of friction impulses: exactly 0 iff z_f ∈ C.
//!
//! Method:
//! 0. **Slipping fast path**: when the body slipped at the last step, damped
//!    Newton on the exact objective from that slip velocity, every iterate
//!    with every support point slipping (f smooth there). If it converges,
//!    ∇f(z) = 0 at a smooth point of a strictly convex f: z is the exact
//!    minimiser and steps 1–4 are skipped. Otherwise (a support point at or
//!    near rest, the body coming to rest) they decide.
//! 1. **Smoothing with continuation**: |v| → √(|v|² + ε²) − ε, minimised by
//!    damped Newton (Cholesky on the 3×3 Hessian, Armijo backtracking; where
//!    the objective's round-off cannot resolve the step, the gradient norm
//!    must fall instead), with ε lowered from 1e-2 to 1e-12 of the problem's
//!    velocity scale, each level warm-started from the last.
//! 2. **Stuck certificate** (before the first level and after each): the
//!    smoothed minimiser's friction directions s_j = B_j z/√(|B_j z|² + ε²)
//!    plus the least-squares correction that makes Σ μ w_j B_jᵀ s_j = z_f
//!    exactly; if every |s_j| ≤ 1, z_f ∈ C is proven and the answer is exactly
//!    0. (Before the first level s_j = 0: the "viscous" distribution, exact for
//!    a uniform translational load.)
//! 3. **Polish**: Newton on the exact objective, which is smooth where every
//!    support point slips, removes the smoothing error of a slipping answer.
//! 4. **Exact decision**: the answer is z̃ if f(z̃) < f(0) (the difference
//!    computed without cancellation), else exactly 0. Whenever 0 is the true
//!    minimiser f(z̃) ≥ f(0) for every z̃, so a stuck body is never given a
//!    creeping velocity; otherwise the error is bounded by the smoothing
//!    (about (μ w ε²)^(1/3), 1e-8 of the velocity scale, right at the
//!    stick-slip boundary; far less inside the slip region).

use nalgebra::{Matrix3, Vector2};

pub(crate) use crate::motion::V3;

/// One support point of the implicit step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Contact {
    /// c_j = k × a_j / √(I/m) (dimensionless).
    pub lever: Vector2<f64>,
    /// w_j = h N_j / K (m/s): the largest friction impulse per unit mass is μ w_j.
    pub weight: f64,
}

/// Smoothing levels of the continuation, relative to the velocity scale.
const EPSILONS: [f64; 6] = [1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12];

/// Newton iterations per smoothing level, at most.
const MAX_NEWTON: usize = 40;

/// Newton stops when the step is below this, relative to the velocity scale.
const STEP_TOL: f64 = 1e-15;

/// Below this predicted decrease, relative to f, the objective cannot
/// resolve the step (round-off): the gradient norm judges it instead.
const FLAT: f64 = 1e-13;

/// What one solve produced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Solution {
    /// The minimiser (exactly zero when stuck).
    pub z: V3,
    /// Newton iterations used, over all smoothing levels.
    pub iterations: usize,
    /// False when some level hit its iteration limit.
    pub converged: bool,
}

#[inline]
fn slip(c: &Contact, z: &V3) -> Vector2<f64> {
    Vector2::new(z.x + z.z * c.lever.x, z.y + z.z * c.lever.y)
}

/// The exact objective f(z) with weights μ w_j.
pub(crate) fn objective(z: &V3, zf: &V3, contacts: &[Contact], mu: f64) -> f64 {
    0.5 * (z - zf).norm_squared()
        + mu * contacts
            .iter()
            .map(|c| c.weight * slip(c, z).norm())
            .sum::<f64>()
}

/// Bᵀ s for one support point.
#[inline]
fn lift(c: &Contact, s: &Vector2<f64>) -> V3 {
    V3::new(s.x, s.y, s.dot(&c.lever))
}

/// Adds w Bᵀ Hv B to `h`, with Hv = [[h00, h01], [h01, h11]] (B = [I | lever]).
#[inline]
fn add_block(h: &mut Matrix3<f64>, c: &Contact, h00: f64, h01: f64, h11: f64) {
    let (lx, ly) = (c.lever.x, c.lever.y);
    let hl0 = h00 * lx + h01 * ly;
    let hl1 = h01 * lx + h11 * ly;
    h[(0, 0)] += h00;
    h[(0, 1)] += h01;
    h[(1, 0)] += h01;
    h[(1, 1)] += h11;
    h[(0, 2)] += hl0;
    h[(2, 0)] += hl0;
    h[(1, 2)] += hl1;
    h[(2, 1)] += hl1;
    h[(2, 2)] += lx * hl0 + ly * hl1;
}

/// The smoothed objective (weights μ w_j), its gradient and Hessian at `z`.
fn smoothed(z: &V3, zf: &V3, contacts: &[Contact], mu: f64, eps: f64) -> (f64, V3, Matrix3<f64>) {
    let d = z - zf;
    let mut f = 0.5 * d.norm_squared();
    let mut g = d;
    let mut h = Matrix3::identity();
    for c in contacts {
        let w = mu * c.weight;
        if w == 0.0 {
            continue;
        }
        let v = slip(c, z);
        let s = (v.norm_squared() + eps * eps).sqrt();
        f += w * (s - eps);
        // ∂|v|_ε/∂v = v/s; ∂²/∂v² = I/s − v vᵀ/s³; v = B z.
        g += lift(c, &(v * (w / s)));
        let a = w / s;
        let b = w / (s * s * s);
        add_block(
            &mut h,
            c,
            a - b * v.x * v.x,
            -b * v.x * v.y,
            a - b * v.y * v.y,
        );
    }
    (f, g, h)
}

/// Damped Newton on the smoothed objective from `z`; returns the iterate,
/// the iterations used and whether it converged.
fn newton(
    mut z: V3,
    zf: &V3,
    contacts: &[Contact],
    mu: f64,
    eps: f64,
    tol: f64,
) -> (V3, usize, bool) {
    let (mut f, mut g, mut h) = smoothed(&z, zf, contacts, mu, eps);
    for it in 0..MAX_NEWTON {
        let Some(chol) = h.cholesky() else {
            return (z, it, false);
        };
        let step = -chol.solve(&g);
        if step.norm() <= tol {
            return (z + step, it + 1, true);
        }
        let eval = |c: &V3| smoothed(c, zf, contacts, mu, eps);
        match backtrack(&z, &step, (f, &g), eval, |_| true, 1e-12) {
            Some(next) => (z, f, g, h) = next,
            // No progress representable: converged to round-off.
            None => return (z, it + 1, true),
        }
    }
    (z, MAX_NEWTON, false)
}

/// Objective, gradient and Hessian at a point.
type Local = (f64, V3, Matrix3<f64>);

/// The backtracking of a damped Newton step from `z` along `step` (`at`:
/// the objective and gradient at `z`): Armijo on the objective `eval`, or,
/// where its round-off cannot resolve the step ([`FLAT`]), a falling
/// gradient norm; candidates `admit` refuses are halved past. The accepted
/// point with its [`Local`], or `None` once the step fraction falls below
/// `t_min`.
fn backtrack(
    z: &V3,
    step: &V3,
    at: (f64, &V3),
    eval: impl Fn(&V3) -> Local,
    admit: impl Fn(&V3) -> bool,
    t_min: f64,
) -> Option<(V3, f64, V3, Matrix3<f64>)> {
    let (f, g) = at;
    let slope = g.dot(step);
    let flat = -slope <= FLAT * f.abs();
    let mut t = 1.0;
    while t >= t_min {
        let cand = z + step * t;
        if admit(&cand) {
            let (fc, gc, hc) = eval(&cand);
            let better = if flat {
                gc.norm() < g.norm()
            } else {
                fc <= f + 1e-4 * t * slope
            };
            if better {
                return Some((cand, fc, gc, hc));
            }
        }
        t *= 0.5;
    }
    None
}

/// True when z_f is proven to lie in the friction set C = Σ_j μ w_j B_jᵀ D
/// (D the unit disc), i.e. 0 is the exact minimiser. `s` holds candidate
/// dual directions s_j (|s_j| ≤ 1); the residual z_f − Σ μ w_j B_jᵀ s_j is
/// removed by the correction δs_j = B_j y, (Σ μ w_j B_jᵀ B_j) y = residual,
/// and the certificate holds when every |s_j + δs_j| ≤ 1.
fn stuck_certificate(zf: &V3, contacts: &[Contact], mu: f64, s: &[Vector2<f64>]) -> bool {
    let mut a = Matrix3::zeros();
    let mut residual = *zf;
    for (c, sj) in contacts.iter().zip(s) {
        let w = mu * c.weight;
        add_block(&mut a, c, w, 0.0, w);
        residual -= lift(c, sj) * w;
    }
    let Some(chol) = a.cholesky() else {
        return false;
    };
    let y = chol.solve(&residual);
    if !y.iter().all(|x| x.is_finite()) {
        return false;
    }
    contacts
        .iter()
        .zip(s)
        .all(|(c, sj)| (sj + slip(c, &y)).norm_squared() <= 1.0)
}

/// The exact minimiser of f with weights μ w_j (see the module docs),
/// Newton started at `start`.
pub(crate) fn minimise(zf: &V3, start: &V3, contacts: &[Contact], mu: f64) -> Solution {
    let total: f64 = mu * contacts.iter().map(|c| c.weight).sum::<f64>();
    let scale = zf.norm().max(start.norm()).max(total);
    let zero = |iterations, converged| Solution {
        z: V3::zeros(),
        iterations,
        converged,
    };
    if scale == 0.0 || !scale.is_finite() {
        return zero(0, scale == 0.0);
    }
    // The viscous certificate (the limit ε → ∞ of the smoothing): s_j = 0
    // plus the correction.
    let mut s = vec![Vector2::zeros(); contacts.len()];
    if stuck_certificate(zf, contacts, mu, &s) {
        return zero(0, true);
    }
    // A slipping body usually keeps every support point slipping: Newton on
    // the exact objective from the last slip velocity, accepted only when it
    // converges with every point slipping (then f is smooth at z, ∇f(z) = 0
    // and, f being strictly convex, z is the unique minimiser).
    if *start != V3::zeros() {
        if let Some((z, iterations)) = slipping_newton(*start, zf, contacts, mu, scale) {
            if gain(&z, zf, contacts, mu) < 0.0 {
                return Solution {
                    z,
                    iterations,
                    converged: true,
                };
            }
        }
    }
    // Start from whichever of `start` and z_f is better for the exact objective.
    let mut z = if objective(start, zf, contacts, mu) <= objective(zf, zf, contacts, mu) {
        *start
    } else {
        *zf
    };
    let mut iterations = 0;
    let mut converged = true;
    for e in EPSILONS {
        let eps = e * scale;
        let (next, it, ok) = newton(z, zf, contacts, mu, eps, STEP_TOL * scale);
        z = next;
        iterations += it;
        converged &= ok;
        // The smoothed minimiser's friction directions, certified or not.
        for (sj, c) in s.iter_mut().zip(contacts) {
            let v = slip(c, &z);
            *sj = v / (v.norm_squared() + eps * eps).sqrt();
        }
        if stuck_certificate(zf, contacts, mu, &s) {
            return zero(iterations, converged);
        }
    }
    let z = polish(z, zf, contacts, mu, STEP_TOL * scale);
    if gain(&z, zf, contacts, mu) < 0.0 {
        Solution {
            z,
            iterations,
            converged,
        }
    } else {
        zero(iterations, converged)
    }
}

/// Newton iterations of the slipping fast path, at most.
const FAST_NEWTON: usize = 12;

/// True when every support point slips at `z` (f is smooth there).
fn all_slip(z: &V3, contacts: &[Contact]) -> bool {
    contacts.iter().all(|c| slip(c, z) != Vector2::zeros())
}

/// Where round-off stops the fast path's line search, a Newton step below
/// this (relative to the velocity scale) is accepted as converged.
const FAST_STALL: f64 = 1e-10;

/// Damped Newton on the exact objective from `z`, every iterate keeping
/// every support point slipping; `Some((minimiser, iterations))` when the
/// step falls below [`STEP_TOL`] (or [`FAST_STALL`] where round-off stops
/// the line search) of `scale` within [`FAST_NEWTON`] iterations, else
/// `None` (a support point at or near rest: the continuation decides).
fn slipping_newton(
    mut z: V3,
    zf: &V3,
    contacts: &[Contact],
    mu: f64,
    scale: f64,
) -> Option<(V3, usize)> {
    let tol = STEP_TOL * scale;
    if !all_slip(&z, contacts) {
        return None;
    }
    let (mut f, mut g, mut h) = smoothed(&z, zf, contacts, mu, 0.0);
    for it in 0..FAST_NEWTON {
        let step = -h.cholesky()?.solve(&g);
        if !step.iter().all(|x| x.is_finite()) {
            return None;
        }
        if step.norm() <= tol {
            let z = z + step;
            return all_slip(&z, contacts).then_some((z, it + 1));
        }
        let eval = |c: &V3| smoothed(c, zf, contacts, mu, 0.0);
        let admit = |c: &V3| all_slip(c, contacts);
        match backtrack(&z, &step, (f, &g), eval, admit, 1e-6) {
            Some(next) => (z, f, g, h) = next,
            None => {
                let done = step.norm() <= FAST_STALL * scale;
                return done.then_some((z, it + 1));
            }
        }
    }
    None
}

/// f(z) − f(0) = Σ μ w_j |B_j z| − z·(z_f − z/2), computed without the
/// cancelling ½|z_f|² terms so that its sign is resolved down to |z|
/// of round-off size.
fn gain(z: &V3, zf: &V3, contacts: &[Contact], mu: f64) -> f64 {
    mu * contacts
        .iter()
        .map(|c| c.weight * slip(c, z).norm())
        .sum::<f64>()
        - z.dot(&(zf - z * 0.5))
}

/// Newton on the exact objective, which is smooth where every support
/// point slips: removes the smoothing error of a slipping solution. A step
/// is kept only while no support point comes to rest and the exact gradient
/// shrinks.
fn polish(mut z: V3, zf: &V3, contacts: &[Contact], mu: f64, tol: f64) -> V3 {
    let moving = |z: &V3| contacts.iter().all(|c| slip(c, z) != Vector2::zeros());
    if !moving(&z) {
        return z;
    }
    let (_, mut g, mut h) = smoothed(&z, zf, contacts, mu, 0.0);
    for _ in 0..3 {
        let Some(chol) = h.cholesky() else {
            break;
        };
        let step = -chol.solve(&g);
        let cand = z + step;
        if !moving(&cand) {
            break;
        }
        let (_, gc, hc) = smoothed(&cand, zf, contacts, mu, 0.0);
        if gc.norm().partial_cmp(&g.norm()) != Some(std::cmp::Ordering::Less) {
            break;
        }
        (z, g, h) = (cand, gc, hc);
        if step.norm() <= tol {
            break;
        }
    }
    z
}

/// True when every support point's slip at `b` makes an acute angle with
/// its slip at `a` (none comes to rest or turns by 90° or more between them).
pub(crate) fn keeps_direction(contacts: &[Contact], a: &V3, b: &V3) -> bool {
    contacts.iter().all(|c| slip(c, a).dot(&slip(c, b)) > 0.0)
}

/// Closed-form minimiser of ½|x − x_f|² + w|x| (one support point, or any
/// set of support points at the same place): x_f shrunk toward 0 by w, or
/// exactly 0 when |x_f| ≤ w.
pub(crate) fn shrink(xf: &Vector2<f64>, w: f64) -> Vector2<f64> {
    let n = xf.norm();
    if n <= w {
        Vector2::zeros()
    } else {
        xf * ((n - w) / n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn contacts(levers: &[(f64, f64)], w: f64) -> Vec<Contact> {
        levers
            .iter()
            .map(|&(x, y)| Contact {
                lever: Vector2::new(x, y),
                weight: w,
            })
            .collect()
    }

    /// Support points without lever arms: the translational part is the
    /// closed-form shrink and the spin is untouched by friction.
    #[test]
    fn matches_shrink_without_levers() {
        let cs = contacts(&[(0.0, 0.0); 4], 0.025);
        for (zf, stuck) in [
            (V3::new(0.3, -0.4, 0.2), false),
            (V3::new(0.05, 0.06, -1.0), true),
            (V3::new(0.1, 0.0, 0.0), true),
            (V3::new(0.1 + 1e-9, 0.0, 0.0), false),
        ] {
            let s = minimise(&zf, &V3::zeros(), &cs, 1.0);
            let want = shrink(&Vector2::new(zf.x, zf.y), 0.1);
            assert!(s.converged);
            if stuck {
                // Exactly zero when the spin is zero too; with a free spin
                // the translation is zero to the smoothing (1e-11 of the scale).
                assert_eq!(want, Vector2::zeros());
                let tol = if zf.z == 0.0 { 0.0 } else { 1e-10 * zf.norm() };
                assert!(s.z.x.hypot(s.z.y) <= tol, "{zf:?}: {:?}", s.z);
                assert!((s.z.z - zf.z).abs() <= 1e-10 * zf.norm());
            } else {
                let err = (Vector2::new(s.z.x, s.z.y) - want).norm();
                assert!(err < 1e-14 * zf.norm(), "{zf:?}: {err:e}");
            }
            assert!(gain(&s.z, &zf, &cs, 1.0) <= 0.0);
        }
    }

    /// Optimality of a slipping solution: the exact gradient vanishes (all
    /// support points slip), and no random perturbation lowers f.
    #[test]
    fn slipping_solution_is_optimal() {
        let cs: Vec<Contact> = (0..8)
            .map(|j| {
                let a = j as f64 * 0.8;
                Contact {
                    lever: Vector2::new(a.cos(), 0.6 * a.sin()),
                    weight: 0.004 * (1.0 + 0.1 * j as f64),
                }
            })
            .collect();
        let zf = V3::new(0.05, -0.03, 0.08);
        let s = minimise(&zf, &V3::zeros(), &cs, 1.0);
        assert!(s.converged && s.z != V3::zeros());
        let mut g = s.z - zf;
        for c in &cs {
            let v = slip(c, &s.z);
            assert!(v.norm() > 1e-6);
            g += lift(c, &(v * (c.weight / v.norm())));
        }
        assert!(g.norm() < 1e-12 * zf.norm(), "gradient {:e}", g.norm());
        let f = objective(&s.z, &zf, &cs, 1.0);
        let mut seed = 12345u64;
        for _ in 0..200 {
            let mut r = || {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            };
            let p = s.z + V3::new(r(), r(), r()) * 1e-4;
            assert!(objective(&p, &zf, &cs, 1.0) >= f);
        }
    }

    /// The slipping fast path (a nonzero start) and the continuation (a
    /// zero start) find the same minimiser, the fast path with fewer
    /// Newton iterations; where the minimiser has a support point at rest
    /// the fast path gives way (`inside_friction_set_is_exactly_zero`).
    #[test]
    fn fast_path_matches_continuation() {
        let cs: Vec<Contact> = (0..16)
            .map(|j| {
                let a = j as f64 * 0.4;
                Contact {
                    lever: Vector2::new(1.2 * a.cos(), 0.3 * a.sin()),
                    weight: 0.002 * (1.0 + 0.05 * j as f64),
                }
            })
            .collect();
        for zf in [
            V3::new(0.05, -0.03, 0.08),
            V3::new(-0.2, 0.01, -0.01),
            V3::new(0.001, 0.07, 0.3),
        ] {
            let slow = minimise(&zf, &V3::zeros(), &cs, 1.0);
            let fast = minimise(&zf, &(zf * 0.9), &cs, 1.0);
            assert!(slow.z != V3::zeros() && fast.converged);
            assert!(
                (slow.z - fast.z).norm() <= 1e-12 * zf.norm(),
                "{zf:?}: {:?} {:?}",
                slow.z,
                fast.z
            );
            assert!(
                fast.iterations < slow.iterations,
                "{} {}",
                fast.iterations,
                slow.iterations
            );
        }
    }

    /// A free impulse inside the friction set gives exactly zero.
    #[test]
    fn inside_friction_set_is_exactly_zero() {
        let cs = contacts(&[(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)], 0.01);
        // Pure torque within the set: 4 points at unit lever, each at most
        // 0.01, so |z₂| ≤ 0.04 holds.
        for zf in [V3::new(0.0, 0.0, 0.039), V3::new(0.02, -0.01, 0.0)] {
            let s = minimise(&zf, &zf, &cs, 1.0);
            assert_eq!(s.z, V3::zeros(), "{zf:?}");
        }
        let s = minimise(&V3::new(0.0, 0.0, 0.041), &V3::zeros(), &cs, 1.0);
        assert!(s.z.z > 0.0 && (s.z.z - 0.001).abs() < 1e-12, "{:?}", s.z);
    }
}
