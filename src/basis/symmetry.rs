//! Reuse by symmetry: rotated and shifted copies of a simulated field.
//!
//! For an isotropic plate (friction the same in every direction, gravity
//! vertical) rotating a plate motion about the vertical by θ rotates its
//! field by θ, and shifting it horizontally by s shifts its field:
//!
//! ```text
//! F'(p) = R(θ) F(R(θ)ᵀ (p − s))
//! ```
//!
//! (the same convention as `crate::motion::Motion::transformed` and
//! [`crate::basis::Primitive`]'s `rotation_deg` and `shift`: rotate about
//! the world vertical first, then shift). A primitive is simulated once, on
//! a grid that covers every preimage of the target region
//! ([`source_grid`]), and each copy is resampled from it by
//! [`transformed`] instead of being simulated again.
//!
//! # Interpolation
//!
//! The preimage point q = Rᵀ(p − s) is interpolated on the source grid by
//! Keys' cubic convolution with a = −1/2 (Catmull–Rom), a tensor product of
//! the 1-D kernel over a 4 × 4 stencil. Per axis, with t ∈ [0, 1) the
//! fractional position between nodes i and i + 1, the weights of nodes
//! i − 1 … i + 2 are
//!
//! ```text
//! w₋₁ = (−t³ + 2t² − t)/2,  w₀ = (3t³ − 5t² + 2)/2,
//! w₁  = (−3t³ + 4t² + t)/2, w₂ = (t³ − t²)/2.
//! ```
//!
//! They reproduce polynomials up to degree 2 exactly, so by Taylor's theorem
//! with remainder the 1-D error is at most
//! (h³/6) · max_t Σ|w_k| |k − t|³ · max|f'''| = (3/32) h³ max|f'''| (the
//! maximum, 9/16, is at t = 1/2), and the weights' absolute sum (Lebesgue
//! constant) is at most 5/4. For the tensor product, per field component,
//!
//! ```text
//! |F − I F| ≤ (3/32) h³ (max|∂³F/∂x³| + 5/4 · max|∂³F/∂y³|) + (25/16) ε
//! ```
//!
//! over the stencil, where ε bounds the simulation error of the source
//! samples. This is the bound relied on, and it needs the field to be
//! C³ over the stencil: where the field has a kink (the edge of a stick
//! deadband, a contact-loss boundary) the error is only O(h · jump of the
//! slope) within two nodes of it. `tests/basis.rs` measures the error
//! against direct simulation and states its tolerance.
//!
//! Where q coincides with a source node along an axis (within 1e-9 of the
//! spacing, `NODE_TOL`) that axis uses the node alone, with weight 1, so
//! that 90° rotations of a grid symmetric about the rotation centre, and
//! shifts by whole grid steps, are exact copies. (The kernel is exactly 1 at
//! 0 and 0 at the other integers, so this is the same interpolant without
//! the round-off of the other three weights.) Rotations by multiples of 90°
//! use exact cosines and sines (0, ±1).
//!
//! # Validity
//!
//! A target sample is valid only if its whole stencil (the 4 × 4 nodes, or
//! fewer along an axis where q sits on a node) lies inside the source grid
//! and every stencil node is valid. A stencil reaching outside the source
//! grid gives [`Validity::OutsideSource`]; otherwise an invalid stencil node
//! passes its flag on (contact lost, not converged, frozen assumption
//! broken; that of the heaviest-weighted invalid node). Invalid samples are
//! set to (0, 0).

use std::f64::consts::FRAC_PI_2;

use crate::field::{Field, Grid, Validity};

/// A preimage within this fraction of the source spacing of a node is taken
/// to be on the node.
pub(crate) const NODE_TOL: f64 = 1e-9;

/// Nodes added on each side of the preimages' bounding box by
/// [`source_grid`], for the cubic stencil.
pub(crate) const MARGIN_NODES: usize = 2;

/// Keys' cubic convolution weights (a = −1/2) of nodes i − 1 … i + 2 at
/// fractional position `t` ∈ [0, 1) past node i.
fn keys(t: f64) -> [f64; 4] {
    let t2 = t * t;
    let t3 = t2 * t;
    [
        0.5 * (-t3 + 2.0 * t2 - t),
        0.5 * (3.0 * t3 - 5.0 * t2 + 2.0),
        0.5 * (-3.0 * t3 + 4.0 * t2 + t),
        0.5 * (t3 - t2),
    ]
}

/// One axis of the source grid.
struct Axis {
    start: f64,
    step: f64,
    n: usize,
    /// Length scale of the node tolerance (m).
    scale: f64,
}

/// The stencil along one axis: first node, weights, number of nodes.
type Stencil = (usize, [f64; 4], usize);

impl Axis {
    fn new(range: [f64; 2], n: usize, scale: f64) -> Axis {
        if n <= 1 {
            Axis {
                start: 0.5 * (range[0] + range[1]),
                step: f64::INFINITY,
                n: 1,
                scale,
            }
        } else {
            Axis {
                start: range[0],
                step: (range[1] - range[0]) / (n - 1) as f64,
                n,
                scale,
            }
        }
    }

    /// The stencil at coordinate `c`, or `None` if it leaves the grid.
    fn stencil(&self, c: f64) -> Option<Stencil> {
        if !c.is_finite() {
            return None;
        }
        if self.n == 1 {
            return ((c - self.start).abs() <= NODE_TOL * self.scale).then_some((
                0,
                [1.0, 0.0, 0.0, 0.0],
                1,
            ));
        }
        let f = (c - self.start) / self.step;
        let k = f.round();
        let last = (self.n - 1) as f64;
        if (f - k).abs() <= NODE_TOL && (0.0..=last).contains(&k) {
            return Some((k as usize, [1.0, 0.0, 0.0, 0.0], 1));
        }
        let i = f.floor();
        if i - 1.0 < 0.0 || i + 2.0 > last {
            return None;
        }
        Some((i as usize - 1, keys(f - i), 4))
    }
}

/// Cosine and sine of `angle`, exact (0, ±1) at multiples of 90°.
fn cos_sin(angle: f64) -> (f64, f64) {
    let quarter = angle / FRAC_PI_2;
    let k = quarter.round();
    if (quarter - k).abs() <= 1e-12 {
        match (k as i64).rem_euclid(4) {
            0 => (1.0, 0.0),
            1 => (0.0, 1.0),
            2 => (-1.0, 0.0),
            _ => (0.0, -1.0),
        }
    } else {
        (angle.cos(), angle.sin())
    }
}

/// The field of the motion rotated by `angle` (rad, about the vertical)
/// and then shifted by `shift` (m), resampled from `field` (on its own grid)
/// at the points of `grid`: F'(p) = R F(Rᵀ(p − s)). See the module docs for
/// the interpolation, its error bound and the validity of each sample.
pub fn transformed(field: &Field, angle: f64, shift: [f64; 2], grid: &Grid) -> Field {
    let src = &field.grid;
    let scale = if src.spacing().is_finite() {
        src.spacing()
    } else {
        1.0
    };
    let ax = Axis::new(src.x, src.n[0], scale);
    let ay = Axis::new(src.y, src.n[1], scale);
    let nx = src.n[0];
    let (c, s) = cos_sin(angle);
    let points = grid.points();
    let mut vectors = Vec::with_capacity(points.len());
    let mut validity = Vec::with_capacity(points.len());
    for p in &points {
        let (dx, dy) = (p[0] - shift[0], p[1] - shift[1]);
        let q = [c * dx + s * dy, -s * dx + c * dy];
        let (sx, sy) = match (ax.stencil(q[0]), ay.stencil(q[1])) {
            (Some(sx), Some(sy)) => (sx, sy),
            _ => {
                vectors.push([0.0, 0.0]);
                validity.push(Validity::OutsideSource);
                continue;
            }
        };
        let mut f = [0.0, 0.0];
        let mut bad: Option<(f64, Validity)> = None;
        for b in 0..sy.2 {
            let row = (sy.0 + b) * nx;
            for a in 0..sx.2 {
                let k = row + sx.0 + a;
                let w = sy.1[b] * sx.1[a];
                let v = field.validity[k];
                if v != Validity::Ok {
                    if bad.is_none_or(|(wb, _)| w.abs() > wb) {
                        bad = Some((w.abs(), v));
                    }
                    continue;
                }
                f[0] += w * field.vectors[k][0];
                f[1] += w * field.vectors[k][1];
            }
        }
        match bad {
            Some((_, v)) => {
                vectors.push([0.0, 0.0]);
                validity.push(v);
            }
            None => {
                vectors.push([c * f[0] - s * f[1], s * f[0] + c * f[1]]);
                validity.push(Validity::Ok);
            }
        }
    }
    Field {
        grid: *grid,
        kind: field.kind,
        vectors,
        validity,
    }
}

/// How much a field changes when it is rotated by `angle` (rad) about the
/// vertical through the origin: with F' = [`transformed`]`(F, angle, 0)` on
/// F's own grid and K the nodes where both F and F' are valid,
///
/// ```text
/// asymmetry = ‖F' − F‖₂,K / ‖F‖₂,K      (L2 norms over the nodes K).
/// ```
///
/// A field symmetric under the rotation (isotropic, e.g. that of a circular
/// translation, whose rotated motion differs only by a phase shift) gives
/// the resampling error alone (see the module docs); any other gives a
/// change of order one. `None` when fewer than half of F's valid nodes can
/// be compared (the rotated grid leaves too little overlap) or F vanishes
/// there.
pub fn rotation_asymmetry(field: &Field, angle: f64) -> Option<f64> {
    let rotated = transformed(field, angle, [0.0, 0.0], &field.grid);
    let (mut diff, mut norm, mut compared) = (0.0, 0.0, 0usize);
    for (k, (f, r)) in field.vectors.iter().zip(&rotated.vectors).enumerate() {
        if field.validity[k] == Validity::Ok && rotated.validity[k] == Validity::Ok {
            diff += (r[0] - f[0]).powi(2) + (r[1] - f[1]).powi(2);
            norm += f[0] * f[0] + f[1] * f[1];
            compared += 1;
        }
    }
    let valid = field
        .validity
        .iter()
        .filter(|v| **v == Validity::Ok)
        .count();
    (2 * compared >= valid && compared > 0 && norm > 0.0).then(|| (diff / norm).sqrt())
}

/// A square grid with the target grid's spacing (its smaller one; 1 mm for
/// a single-point target) whose nodes lie on the target's lattice, covering
/// the preimage Rᵀ(p − s) of the target rectangle under every combination
/// of `angles` (rad) and `shifts` (m), plus `MARGIN_NODES` nodes on every
/// side for the cubic stencil: simulate a primitive once on it, then
/// [`transformed`] gives every copy on `target` without `OutsideSource`
/// samples. An empty `angles` or `shifts` means no rotation or no shift.
///
/// Because the nodes are on the target's lattice, a target grid symmetric
/// about the origin is resampled exactly under 90° rotations and shifts by
/// whole steps.
pub fn source_grid(target: &Grid, angles: &[f64], shifts: &[[f64; 2]]) -> Grid {
    let h = if target.spacing().is_finite() {
        target.spacing()
    } else {
        1e-3
    };
    let angles = if angles.is_empty() {
        &[0.0][..]
    } else {
        angles
    };
    let shifts = if shifts.is_empty() {
        &[[0.0, 0.0]][..]
    } else {
        shifts
    };
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &angle in angles {
        let (c, s) = cos_sin(angle);
        for shift in shifts {
            for x in target.x {
                for y in target.y {
                    let (dx, dy) = (x - shift[0], y - shift[1]);
                    let q = [c * dx + s * dy, -s * dx + c * dy];
                    for k in 0..2 {
                        lo[k] = lo[k].min(q[k]);
                        hi[k] = hi[k].max(q[k]);
                    }
                }
            }
        }
    }
    let origin = [target.x[0], target.y[0]];
    let mut centre = [0.0; 2];
    let mut half: f64 = 0.0;
    for k in 0..2 {
        let mid = 0.5 * (lo[k] + hi[k]);
        centre[k] = origin[k] + ((mid - origin[k]) / h).round() * h;
        half = half.max(hi[k] - centre[k]).max(centre[k] - lo[k]);
    }
    let m = (half / h - NODE_TOL).ceil().max(0.0) as usize + MARGIN_NODES;
    let r = m as f64 * h;
    Grid {
        x: [centre[0] - r, centre[0] + r],
        y: [centre[1] - r, centre[1] + r],
        n: [2 * m + 1, 2 * m + 1],
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::FieldKind;

    fn field_of(grid: &Grid, f: impl Fn(f64, f64) -> [f64; 2]) -> Field {
        let vectors = grid.points().iter().map(|p| f(p[0], p[1])).collect();
        Field {
            grid: *grid,
            kind: FieldKind::Force,
            vectors,
            validity: vec![Validity::Ok; grid.len()],
        }
    }

    #[test]
    fn kernel_reproduces_quadratics() {
        for i in 0..=20 {
            let t = i as f64 / 20.0;
            let w = keys(t);
            let d = [-1.0 - t, -t, 1.0 - t, 2.0 - t];
            let m = |p: i32| w.iter().zip(&d).map(|(w, d)| w * d.powi(p)).sum::<f64>();
            assert!((m(0) - 1.0).abs() < 1e-15);
            assert!(m(1).abs() < 1e-15 && m(2).abs() < 1e-15, "t = {t}");
        }
    }

    /// A quadratic vector field is reproduced to round-off under any
    /// rotation and shift (the kernel reproduces quadratics, and a rotated
    /// quadratic is a quadratic).
    #[test]
    fn quadratic_field_is_exact() {
        let f = |x: f64, y: f64| [3.0 * x * x - 2.0 * x * y + y, 0.5 - x + 4.0 * y * y];
        let target = Grid {
            n: [7, 7],
            ..Grid::DEFAULT
        };
        let (angle, shift) = (0.4_f64, [0.003, -0.007]);
        let src_grid = source_grid(&target, &[angle], &[shift]);
        let out = transformed(&field_of(&src_grid, f), angle, shift, &target);
        let (c, s) = (angle.cos(), angle.sin());
        for (k, p) in target.points().iter().enumerate() {
            assert_eq!(out.validity[k], Validity::Ok);
            let (dx, dy) = (p[0] - shift[0], p[1] - shift[1]);
            let v = f(c * dx + s * dy, -s * dx + c * dy);
            let want = [c * v[0] - s * v[1], s * v[0] + c * v[1]];
            for (got, want) in out.vectors[k].iter().zip(want) {
                assert!((got - want).abs() < 1e-13, "{k}");
            }
        }
    }

    #[test]
    fn outside_and_invalid_are_flagged() {
        let g = Grid {
            n: [9, 9],
            ..Grid::DEFAULT
        };
        let mut field = field_of(&g, |x, y| [x, y]);
        // A shift of 1.5 steps puts the edge columns' stencils outside.
        let out = transformed(&field, 0.0, [0.015, 0.0], &g);
        assert_eq!(out.validity[0], Validity::OutsideSource);
        assert_eq!(out.validity[9 * 4 + 4], Validity::Ok);
        field.validity[9 * 4 + 4] = Validity::ContactLost;
        let out = transformed(&field, 0.0, [0.005, 0.0], &g);
        assert_eq!(out.validity[9 * 4 + 4], Validity::ContactLost);
        assert_eq!(out.validity[9 * 4 + 5], Validity::ContactLost);
        assert_eq!(out.validity[9 * 6 + 4], Validity::Ok);
    }

    #[test]
    fn source_grid_is_on_the_lattice_and_covers() {
        let target = Grid {
            n: [9, 9],
            ..Grid::DEFAULT
        };
        let g = source_grid(&target, &[FRAC_PI_2], &[]);
        assert_eq!(g.n, [13, 13]);
        assert!((g.x[0] + 0.06).abs() < 1e-15 && (g.y[1] - 0.06).abs() < 1e-15);
        let g = source_grid(&target, &[30f64.to_radians()], &[[0.004, -0.002]]);
        let field = field_of(&g, |x, y| [x, y]);
        let out = transformed(&field, 30f64.to_radians(), [0.004, -0.002], &target);
        assert_eq!(out.valid_count(), target.len());
    }
}
