//! sin and cos without a libm call: angle addition from a table of nodes.
//!
//! The integrator evaluates the plate kinematics at instants off the
//! kinematics table's grid (the stages of τ-steps and implicit steps, event
//! location), each with a `sin_cos` per waveform term and one for
//! the gravity tilt — a third of a 2-D field's time in libm. [`sin_cos`]
//! gives the same values to round-off at a fraction of the cost.
//!
//! # Method
//! With M = 1024 nodes θ_k = 2πk/M on the circle and x = θ_N + r, N the
//! integer nearest x M/(2π) and k = N mod M,
//!
//! ```text
//! sin x = s_k + (s_k (cos r − 1) + c_k sin r)
//! cos x = c_k + (c_k (cos r − 1) − s_k sin r),   |r| ≤ π/M
//! ```
//!
//! (|r| may pass π/M by the rounding of x M/(2π), a relative 10⁻¹⁵.)
//!
//! with (s_k, c_k) = (sin θ_k, cos θ_k) tabulated once (to ≤ ½ ulp plus
//! libm's error). The reduction r = (x − N C₁) − N C₂, C₁ + C₂ = 2π/M with
//! C₁ carrying 31 significant bits, is exact in its first subtraction (N C₁
//! is exact for |N| < 2²² and x − N C₁ by Sterbenz's lemma) and off by less
//! than |N| 2⁻⁸⁴ 2π/M < 2⁻⁶⁰ in the second, so r is x's reduced argument
//! to round-off in r: the result is that of libm's exact reduction of the
//! same x. Larger |x| (and non-finite x) go to libm; |x| ≤ π/M (N = 0, the
//! small tilt angles of the gravity rotation) skips the reduction and the
//! table.
//!
//! sin r and cos r − 1 are Taylor polynomials, `r − r³/3! + r⁵/5!` and
//! `−r²/2! + r⁴/4!`, whose truncation errors are below the first omitted
//! terms (alternating series with decreasing terms for |r| < 1): |r|⁷/7! <
//! 10⁻²¹ and |r|⁶/6! < 2·10⁻¹⁸ at |r| = π/1024 (below 10⁻¹⁷, tested). The
//! corrections in brackets are at most |r| ≤ 0.0031 in size, so their
//! rounding costs a hundredth of an ulp of a unit result; what remains is
//! the node value's rounding and the final addition's: |fast − exact| ≤ 1
//! ulp of 1 (2.2e-16) and |fast − libm| ≤ 2.3e-16 absolute (tested over
//! 3.7·10⁵ arguments; the largest difference seen is 1.1e-16).

use std::f64::consts::{PI, TAU};
use std::sync::OnceLock;

/// log₂ M.
const BITS: u32 = 10;
/// M, the nodes on the circle.
const NODES: usize = 1 << BITS;
/// The reduced argument's bound π/M.
pub(crate) const REDUCED_MAX: f64 = PI / NODES as f64;
/// 2π − fl(2π).
const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;
/// 1.5 · 2⁵²: adding and subtracting it rounds to the nearest integer
/// (|y| < 2⁵¹), leaving the integer in the low bits of the sum.
const ROUND: f64 = 6_755_399_441_055_744.0;
/// Arguments with |x| below this (25 700) have |N| < 2²² (the
/// reduction's range).
const LIMIT: f64 = (1u64 << 22) as f64 * (TAU / NODES as f64);

/// The node table and the reduction constants ([`table`]).
#[derive(Debug)]
pub(crate) struct Nodes {
    /// M/(2π).
    inv: f64,
    /// 2π/M to 31 significant bits.
    c1: f64,
    /// 2π/M − C₁.
    c2: f64,
    /// (sin θ_k, cos θ_k), k = 0 … M − 1.
    sc: [(f64, f64); NODES],
}

/// The table, built on first use (hold the reference where it is used
/// often).
pub(crate) fn table() -> &'static Nodes {
    static NODES_TABLE: OnceLock<Nodes> = OnceLock::new();
    NODES_TABLE.get_or_init(|| {
        let m = NODES as f64;
        let step = TAU / m;
        let c1 = f64::from_bits(step.to_bits() & !((1u64 << 22) - 1));
        // TAU − M C₁ is exact (M a power of two, Sterbenz).
        let c2 = ((TAU - m * c1) + TAU_LO) / m;
        let mut sc = [(0.0, 1.0); NODES];
        for (k, node) in sc.iter_mut().enumerate() {
            // θ_k = k C₁ (exact) + d, d = k C₂: sin(a + d) = sin a + d cos a
            // − d²/2 sin a + O(d³), d ≤ 2π 2⁻³¹ so d³ < 10⁻²⁶.
            let a = k as f64 * c1;
            let d = k as f64 * c2;
            let (s, c) = a.sin_cos();
            *node = (s + (d * c - 0.5 * d * d * s), c - (d * s + 0.5 * d * d * c));
        }
        Nodes {
            inv: m / TAU,
            c1,
            c2,
            sc,
        }
    })
}

/// (sin r, cos r − 1) for |r| ≤ [`REDUCED_MAX`] by the Taylor polynomials
/// of the module docs.
#[inline(always)]
pub(crate) fn small_sin_cosm1(r: f64) -> (f64, f64) {
    let r2 = r * r;
    let s = r + r * r2 * (-1.0 / 6.0 + r2 * (1.0 / 120.0));
    let cm1 = r2 * (-0.5 + r2 * (1.0 / 24.0));
    (s, cm1)
}

impl Nodes {
    /// (sin x, cos x) to within 2.3e-16 of libm's (module docs).
    #[inline(always)]
    pub(crate) fn sin_cos(&self, x: f64) -> (f64, f64) {
        if x.abs() <= REDUCED_MAX {
            // N = 0: the node (0, 1) and r = x, without the reduction (the
            // same values as through it; small tilt angles).
            let (sr, cm1) = small_sin_cosm1(x);
            return (sr, 1.0 + cm1);
        }
        if x.abs() >= LIMIT || x.is_nan() {
            return x.sin_cos();
        }
        self.reduced(x)
    }

    /// The angle addition from the nearest node, |x| < `LIMIT`.
    #[inline(always)]
    fn reduced(&self, x: f64) -> (f64, f64) {
        let t = self;
        let y = x * t.inv + ROUND;
        let n = y - ROUND;
        let k = (y.to_bits() as usize) & (NODES - 1);
        let r = (x - n * t.c1) - n * t.c2;
        let (sr, cm1) = small_sin_cosm1(r);
        let (s, c) = t.sc[k];
        (s + (s * cm1 + c * sr), c + (c * cm1 - s * sr))
    }
}

#[cfg(test)]
mod tests {
    /// (sin x, cos x) from the shared table.
    fn sin_cos(x: f64) -> (f64, f64) {
        table().sin_cos(x)
    }

    use super::*;

    /// The Taylor remainders stated in the docs, at the largest reduced
    /// argument, are below 1e-17; and the polynomials agree with libm's
    /// sin and with cos − 1 = −2 sin²(r/2) over the whole reduced range
    /// within that bound plus the rounding of each (an ulp of sin r, three
    /// of −2 sin²(r/2), rounded three times).
    #[test]
    fn polynomial_error_is_below_bound() {
        let r = REDUCED_MAX * (1.0 + 1e-9);
        let fact = |n: u32| (1..=n).map(f64::from).product::<f64>();
        assert!(r.powi(7) / fact(7) < 1e-21);
        assert!(r.powi(6) / fact(6) < 2e-18);
        let mut worst = (0.0f64, 0.0f64);
        for i in -20_000..=20_000 {
            let r = REDUCED_MAX * i as f64 / 20_000.0;
            let (s, cm1) = small_sin_cosm1(r);
            let h = (0.5 * r).sin();
            let cm1_ref = -2.0 * h * h;
            let ulp = |v: f64| f64::EPSILON * v.abs();
            worst.0 = worst.0.max((s - r.sin()).abs() - ulp(r.sin()));
            worst.1 = worst.1.max((cm1 - cm1_ref).abs() - 3.0 * ulp(cm1_ref));
        }
        println!(
            "worst |poly − libm| beyond rounding: sin {:e}, cos − 1 {:e}",
            worst.0, worst.1
        );
        assert!(worst.0 <= 1e-17 && worst.1 <= 1e-17, "{worst:?}");
    }

    /// The nodes are sin and cos of 2πk/M: against libm at k C₁ + k C₂
    /// to within an ulp, and the symmetries sin θ_{M/4 − k} = cos θ_k hold
    /// to an ulp.
    #[test]
    fn nodes_are_sin_cos_of_2pi_k_over_m() {
        let t = table();
        assert!((t.c1 + t.c2 - TAU / NODES as f64).abs() < 1e-17);
        for k in 0..NODES {
            let (s, c) = t.sc[k];
            let (ls, lc) = (TAU * k as f64 / NODES as f64).sin_cos();
            // libm's argument fl(2πk/M) is itself off by up to ½ ulp of θ_k.
            let tol = 1.2e-16 + 0.5 * f64::EPSILON * (TAU * k as f64 / NODES as f64);
            assert!((s - ls).abs() <= tol && (c - lc).abs() <= tol, "{k}");
            if k <= NODES / 4 {
                let (s2, c2) = t.sc[NODES / 4 - k];
                assert!(
                    (s2 - c).abs() <= 1.2e-16 && (c2 - s).abs() <= 1.2e-16,
                    "{k}"
                );
            }
        }
        assert_eq!(t.sc[0], (0.0, 1.0));
        assert_eq!(t.sc[NODES / 4].0, 1.0);
    }

    /// Fast against libm at 3.7·10⁵ arguments, small to large, both signs,
    /// exact node angles and their neighbours: within 2.3e-16 absolute;
    /// non-finite and huge arguments go to libm.
    #[test]
    fn sin_cos_matches_libm() {
        let mut worst = 0.0f64;
        let mut check = |x: f64| {
            let (s, c) = sin_cos(x);
            let (ls, lc) = x.sin_cos();
            let e = (s - ls).abs().max((c - lc).abs());
            assert!(e <= 2.3e-16, "x {x}: {e:e}");
            worst = worst.max(e);
        };
        let mut seed = 0x9E37_79B9_7F4A_7C15u64;
        let mut uniform = || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        for scale in [1e-6, 0.003, 1.0, 7.0, 100.0, 1e4, 2.5e4] {
            for _ in 0..50_000 {
                check(scale * (2.0 * uniform() - 1.0));
            }
        }
        for k in -2000..2000 {
            let x = TAU * k as f64 / NODES as f64;
            for y in [x, x.next_up(), x.next_down(), x + 0.5 * REDUCED_MAX * 2.0] {
                check(y);
            }
        }
        println!("worst |fast − libm| {worst:e}");
        for x in [f64::NAN, f64::INFINITY, 1e6, -3e4] {
            let (s, c) = sin_cos(x);
            let (ls, lc) = x.sin_cos();
            assert_eq!((s.to_bits(), c.to_bits()), (ls.to_bits(), lc.to_bits()));
        }
        assert_eq!(sin_cos(0.0), (0.0, 1.0));
        // The small-argument path is the reduction's N = 0 case.
        let t = table();
        for i in -1000..=1000 {
            let x = REDUCED_MAX * i as f64 / 1000.0;
            assert_eq!(t.sin_cos(x), t.reduced(x), "{x}");
        }
    }
}
