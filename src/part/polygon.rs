//! Simple polygons in the body frame: area, centroid, simplicity, inside
//! tests and the uniform grid of support points over the area.

use crate::dynamics::V2;

/// Signed area (shoelace; > 0 for counter-clockwise vertices).
pub(crate) fn signed_area(v: &[V2]) -> f64 {
    let n = v.len();
    0.5 * (0..n).map(|i| v[i].perp(&v[(i + 1) % n])).sum::<f64>()
}

/// Area centroid of a simple polygon of non-zero area.
pub(crate) fn centroid(v: &[V2]) -> V2 {
    let n = v.len();
    let a = signed_area(v);
    let mut c = V2::zeros();
    for i in 0..n {
        let (p, q) = (v[i], v[(i + 1) % n]);
        c += (p + q) * p.perp(&q);
    }
    c / (6.0 * a)
}

/// Largest extent of the polygon: the longest distance between two
/// vertices (its diameter).
pub(crate) fn diameter(v: &[V2]) -> f64 {
    v.iter()
        .flat_map(|a| v.iter().map(move |b| (a - b).norm()))
        .fold(0.0, f64::max)
}

/// Orientation of the triangle (a, b, c): > 0 counter-clockwise.
fn orient(a: &V2, b: &V2, c: &V2) -> f64 {
    (b - a).perp(&(c - a))
}

/// True when the closed segments [a, b] and [c, d] share a point
/// (touching or collinear overlap included).
fn segments_meet(a: &V2, b: &V2, c: &V2, d: &V2) -> bool {
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
        return true;
    }
    let on = |p: &V2, q: &V2, r: &V2, o: f64| {
        o == 0.0
            && r.x >= p.x.min(q.x)
            && r.x <= p.x.max(q.x)
            && r.y >= p.y.min(q.y)
            && r.y <= p.y.max(q.y)
    };
    on(c, d, a, d1) || on(c, d, b, d2) || on(a, b, c, d3) || on(a, b, d, d4)
}

/// The first pair of edges (i, j), i < j, that meet although they are not
/// neighbours (edge i joins vertex i to vertex i + 1); `None` for a simple
/// polygon. A repeated vertex makes a zero-length edge that meets both
/// its neighbours' neighbours, so it is found too.
pub(crate) fn crossing(v: &[V2]) -> Option<(usize, usize)> {
    let n = v.len();
    let edge = |i: usize| (v[i], v[(i + 1) % n]);
    for i in 0..n {
        for j in i + 1..n {
            let adjacent = j == i + 1 || (i == 0 && j == n - 1);
            let (a, b) = edge(i);
            let (c, d) = edge(j);
            if adjacent {
                // Neighbours share one vertex; they must not fold back.
                let shared_at_b = j == i + 1;
                let (p, q, r) = if shared_at_b { (a, b, d) } else { (c, a, b) };
                if orient(&p, &q, &r) == 0.0 && (r - q).dot(&(p - q)) > 0.0 {
                    return Some((i, j));
                }
                if a == b || c == d {
                    return Some((i, j));
                }
            } else if segments_meet(&a, &b, &c, &d) {
                return Some((i, j));
            }
        }
    }
    None
}

/// Distance from `p` to the polygon's boundary.
pub(crate) fn boundary_distance(v: &[V2], p: &V2) -> f64 {
    let n = v.len();
    (0..n)
        .map(|i| {
            let (a, b) = (v[i], v[(i + 1) % n]);
            let ab = b - a;
            let t = ((p - a).dot(&ab) / ab.norm_squared()).clamp(0.0, 1.0);
            (p - (a + ab * t)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// True when `p` is inside the polygon (even-odd rule; a point on the
/// boundary may fall either way).
pub fn contains(v: &[V2], p: &V2) -> bool {
    let n = v.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (v[i], v[(i + 1) % n]);
        if (a.y > p.y) != (b.y > p.y) {
            let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
            if p.x < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Inside or within `tol` of the boundary.
pub(crate) fn covers(v: &[V2], p: &V2, tol: f64) -> bool {
    contains(v, p) || boundary_distance(v, p) <= tol
}

/// Uniform support over the area: an nx × ny grid of near-square cells
/// over the bounding box (about `samples` of them inside, nx, ny ≥ 1, at
/// most 64 cells per sample), each cell clipped to the polygon; a support
/// point at each non-empty piece's centroid, weighted by its area. The
/// points' weighted centroid and total weight are then the polygon's
/// exactly (to round-off); an axis-aligned rectangle gets its nx × ny
/// cell centres with equal weights.
pub(crate) fn uniform_grid(v: &[V2], samples: usize) -> Vec<(V2, f64)> {
    let (lo, hi) = bounds(v);
    let size = hi - lo;
    // Coarser cells for a thin, slanted part (at most 64 per sample).
    let cell = (signed_area(v).abs() / samples as f64)
        .sqrt()
        .max((size.x * size.y / (64.0 * samples as f64)).sqrt());
    let nx = ((size.x / cell).round() as usize).max(1);
    let ny = ((size.y / cell).round() as usize).max(1);
    let min_area = 1e-9 * size.x * size.y / (nx * ny) as f64;
    let mut out = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let a = V2::new(
                lo.x + size.x * i as f64 / nx as f64,
                lo.y + size.y * j as f64 / ny as f64,
            );
            let b = V2::new(
                lo.x + size.x * (i + 1) as f64 / nx as f64,
                lo.y + size.y * (j + 1) as f64 / ny as f64,
            );
            let piece = clip_to_box(v, a, b);
            if piece.len() >= 3 {
                let area = signed_area(&piece).abs();
                if area > min_area {
                    out.push((centroid(&piece), area));
                }
            }
        }
    }
    out
}

/// The polygon clipped to the box [a, b] (Sutherland–Hodgman: the clip
/// window is convex, so the piece's area and centroid are exact even where
/// a concave polygon leaves degenerate edges on the box's sides).
fn clip_to_box(v: &[V2], a: V2, b: V2) -> Vec<V2> {
    let mut poly = v.to_vec();
    // Each side as (axis, bound, keep the side above the bound).
    for (axis, bound, above) in [
        (0, a.x, true),
        (0, b.x, false),
        (1, a.y, true),
        (1, b.y, false),
    ] {
        let inside = |p: &V2| {
            if above {
                p[axis] >= bound
            } else {
                p[axis] <= bound
            }
        };
        let mut next = Vec::with_capacity(poly.len() + 4);
        for k in 0..poly.len() {
            let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
            let (pin, qin) = (inside(&p), inside(&q));
            if pin {
                next.push(p);
            }
            if pin != qin {
                let t = (bound - p[axis]) / (q[axis] - p[axis]);
                let mut x = p + (q - p) * t;
                x[axis] = bound;
                next.push(x);
            }
        }
        poly = next;
        if poly.is_empty() {
            break;
        }
    }
    poly
}

/// Lower-left and upper-right corners of the bounding box.
pub(crate) fn bounds(v: &[V2]) -> (V2, V2) {
    v.iter().fold(
        (V2::repeat(f64::INFINITY), V2::repeat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.inf(p), hi.sup(p)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn poly(xy: &[(f64, f64)]) -> Vec<V2> {
        xy.iter().map(|&(x, y)| V2::new(x, y)).collect()
    }

    /// Closed forms: an L of legs 0.5 on a 3 × 2 box has area 3·0.5 +
    /// 1.5·0.5 = 2.25 and its centroid by composite areas.
    #[test]
    fn area_and_centroid_of_an_l() {
        let l = poly(&[
            (0., 0.),
            (3., 0.),
            (3., 0.5),
            (0.5, 0.5),
            (0.5, 2.),
            (0., 2.),
        ]);
        assert!((signed_area(&l) - 2.25).abs() < 1e-12);
        // Bar 3 × 0.5 at (1.5, 0.25), leg 0.5 × 1.5 at (0.25, 1.25).
        let cx = (1.5 * 1.5 + 0.75 * 0.25) / 2.25;
        let cy = (1.5 * 0.25 + 0.75 * 1.25) / 2.25;
        assert!((centroid(&l) - V2::new(cx, cy)).norm() < 1e-12);
        assert_eq!(crossing(&l), None);
        assert!(contains(&l, &V2::new(0.2, 1.8)) && !contains(&l, &V2::new(1.0, 1.0)));
        // Uniform grid: 6 × 4 cells of 0.5 → 24 cells, 9 inside the L;
        // 8 × 5 cells of 0.375 × 0.4 cut the legs: 22 pieces whose weighted
        // centroid and area are the L's.
        let g = uniform_grid(&l, 9);
        assert_eq!(g.len(), 9);
        let g = uniform_grid(&l, 16);
        assert_eq!(g.len(), 22);
        let total: f64 = g.iter().map(|p| p.1).sum();
        let c = g.iter().fold(V2::zeros(), |acc, p| acc + p.0 * p.1) / total;
        assert!((total - 2.25).abs() < 1e-12 && (c - centroid(&l)).norm() < 1e-12);
    }

    /// A bow-tie crosses itself; a fold back along an edge and a repeated
    /// vertex are caught too.
    #[test]
    fn self_intersections_are_found() {
        let bow = poly(&[(0., 0.), (1., 1.), (1., 0.), (0., 1.)]);
        assert!(crossing(&bow).is_some());
        let fold = poly(&[(0., 0.), (2., 0.), (1., 0.), (1., 1.)]);
        assert!(crossing(&fold).is_some());
        let repeat = poly(&[(0., 0.), (1., 0.), (1., 0.), (0., 1.)]);
        assert!(crossing(&repeat).is_some());
        let square = poly(&[(0., 0.), (1., 0.), (1., 1.), (0., 1.)]);
        assert_eq!(crossing(&square), None);
    }
}
