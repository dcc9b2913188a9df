//! Deterministic test helpers: a splitmix64 PRNG and synthetic basis fields.

use nalgebra::{DMatrix, DVector};

pub(crate) use crate::rng::SplitMix64;

pub(crate) fn random_matrix(rng: &mut SplitMix64, rows: usize, cols: usize) -> DMatrix<f64> {
    DMatrix::from_fn(rows, cols, |_, _| rng.symmetric())
}

pub(crate) fn random_vector(rng: &mut SplitMix64, n: usize) -> DVector<f64> {
    DVector::from_fn(n, |_, _| rng.symmetric())
}

/// Points of a `g×g` grid on `[-1, 1]²`.
pub(crate) fn grid_points(g: usize) -> Vec<[f64; 2]> {
    let mut pts = Vec::with_capacity(g * g);
    for iy in 0..g {
        for ix in 0..g {
            let x = -1.0 + 2.0 * ix as f64 / (g - 1) as f64;
            let y = -1.0 + 2.0 * iy as f64 / (g - 1) as f64;
            pts.push([x, y]);
        }
    }
    pts
}

/// Line sink through the origin at angle `theta` (radians):
/// `f(p) = −(n·p) n`, `n = (cos θ, sin θ)`, stacked as `[fx…; fy…]`.
pub(crate) fn line_sink(points: &[[f64; 2]], theta: f64) -> DVector<f64> {
    let (s, c) = theta.sin_cos();
    let n = points.len();
    let mut v = DVector::zeros(2 * n);
    for (i, p) in points.iter().enumerate() {
        let dot = c * p[0] + s * p[1];
        v[i] = -dot * c;
        v[n + i] = -dot * s;
    }
    v
}

/// Point sink at `q`: `f(p) = −(p − q)`, stacked.
pub(crate) fn point_sink(points: &[[f64; 2]], q: [f64; 2]) -> DVector<f64> {
    let n = points.len();
    let mut v = DVector::zeros(2 * n);
    for (i, p) in points.iter().enumerate() {
        v[i] = -(p[0] - q[0]);
        v[n + i] = -(p[1] - q[1]);
    }
    v
}

/// Uniform translation field `f(p) = u`, stacked.
pub(crate) fn uniform_field(points: &[[f64; 2]], u: [f64; 2]) -> DVector<f64> {
    let n = points.len();
    let mut v = DVector::zeros(2 * n);
    for i in 0..n {
        v[i] = u[0];
        v[n + i] = u[1];
    }
    v
}

/// Rotation (vortex) field `f(p) = ω (−y, x)`, stacked.
pub(crate) fn rotation_field(points: &[[f64; 2]], omega: f64) -> DVector<f64> {
    let n = points.len();
    let mut v = DVector::zeros(2 * n);
    for (i, p) in points.iter().enumerate() {
        v[i] = -omega * p[1];
        v[n + i] = omega * p[0];
    }
    v
}

/// Matrix from columns.
pub(crate) fn from_columns(cols: &[DVector<f64>]) -> DMatrix<f64> {
    let rows = cols[0].len();
    let mut a = DMatrix::zeros(rows, cols.len());
    for (j, c) in cols.iter().enumerate() {
        a.set_column(j, c);
    }
    a
}

/// A "plate-like" basis of `m` columns on the `g×g` grid: line sinks at
/// spread angles, point sinks at random centres, uniform fields, rotations,
/// all deterministic from `seed`.
pub(crate) fn plate_like_basis(rng: &mut SplitMix64, g: usize, m: usize) -> DMatrix<f64> {
    let pts = grid_points(g);
    let mut cols = Vec::with_capacity(m);
    for j in 0..m {
        let col = match j % 4 {
            0 => line_sink(&pts, std::f64::consts::PI * rng.uniform()),
            1 => point_sink(&pts, [rng.symmetric(), rng.symmetric()]),
            2 => {
                let ang = 2.0 * std::f64::consts::PI * rng.uniform();
                uniform_field(&pts, [ang.cos(), ang.sin()])
            }
            _ => rotation_field(&pts, if rng.uniform() < 0.5 { -1.0 } else { 1.0 }),
        };
        // Random per-column amplitude and a little random perturbation so
        // that no two columns coincide.
        let amp = 0.5 + rng.uniform();
        let noise = DVector::from_fn(2 * pts.len(), |_, _| 0.05 * rng.symmetric());
        cols.push(col * amp + noise);
    }
    from_columns(&cols)
}

/// Solves the L1 (`l1`) or L∞ LP on all rows and columns of `a`, `t`
/// directly and asserts that `x` (at least `a.ncols()` entries: the
/// weights first) reaches its objective to 1e-9·‖t‖_p and its weights to
/// 1e-6, and that the direct LP ends `Solved`.  Returns `x`'s objective.
pub(crate) fn assert_matches_full_lp(
    a: &DMatrix<f64>,
    t: &DVector<f64>,
    x: &[f64],
    l1: bool,
) -> f64 {
    let m = a.ncols();
    let full = if l1 {
        crate::fit::conic::solve_l1_linear(a, t, &[]).unwrap()
    } else {
        crate::fit::conic::solve_linf(a, t).unwrap()
    };
    assert_eq!(full.status, clarabel::solver::SolverStatus::Solved);
    let norm = |r: &DVector<f64>| if l1 { r.lp_norm(1) } else { r.amax() };
    let obj0 = norm(t);
    let obj = |w: &[f64]| norm(&(a * DVector::from_column_slice(&w[..m]) - t));
    let (o, o_full) = (obj(x), obj(&full.x));
    assert!(
        (o - o_full).abs() <= 1e-9 * obj0,
        "l1={l1}: {o} vs {o_full}"
    );
    let dw = (0..m).map(|j| (x[j] - full.x[j]).abs()).fold(0.0, f64::max);
    assert!(dw < 1e-6, "l1={l1}: weights differ by {dw:.2e}");
    o
}
