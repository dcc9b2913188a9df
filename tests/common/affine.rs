//! The affine residual of a sampled point field: how far a field is from
//! v ≈ b + A p over a grid (issue 28: a unique pose needs a field nonlinear
//! at the part's scale).

use nalgebra::{Matrix3, Vector3};
use platefield::dynamics::V2;
use platefield::field::Grid;

/// The sample positions of `grid`, row-major (y outer).
pub fn points(grid: &Grid) -> Vec<V2> {
    let at = |r: [f64; 2], n: usize, k: usize| r[0] + (r[1] - r[0]) * k as f64 / (n - 1) as f64;
    (0..grid.n[1])
        .flat_map(|j| {
            (0..grid.n[0]).map(move |i| V2::new(at(grid.x, grid.n[0], i), at(grid.y, grid.n[1], j)))
        })
        .collect()
}

/// The largest residual of the least-squares affine fit v ≈ b + A p to
/// `vectors` sampled on `grid`, as a fraction of their largest speed.
pub fn affine_residual(grid: &Grid, vectors: &[[f64; 2]]) -> f64 {
    let rows: Vec<Vector3<f64>> = points(grid)
        .iter()
        .map(|p| Vector3::new(1.0, p.x, p.y))
        .collect();
    let normal: Matrix3<f64> = rows.iter().map(|r| r * r.transpose()).sum();
    let inv = normal.try_inverse().expect("a 2-D grid");
    let mut worst: f64 = 0.0;
    for c in 0..2 {
        let rhs: Vector3<f64> = rows.iter().zip(vectors).map(|(r, v)| r * v[c]).sum();
        let coef = inv * rhs;
        for (r, v) in rows.iter().zip(vectors) {
            worst = worst.max((v[c] - coef.dot(r)).abs());
        }
    }
    let speed = vectors.iter().map(|v| v[0].hypot(v[1])).fold(0.0, f64::max);
    worst / speed
}
