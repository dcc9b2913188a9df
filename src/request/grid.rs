//! Rectangular sample grids and mask regions.

use serde::{Deserialize, Serialize};

use crate::request::error::{
    check_finite, check_finite2, check_interval, check_range, show, TargetError,
};
use crate::request::field::EXTENT;

/// Largest allowed number of grid points along one axis (`grid.n[i]`);
/// a region may allow fewer (`max_points`).
pub const MAX_GRID_N: usize = 1001;

/// Nodes per side of the largest library grid ([`crate::field::Grid::MAX_N`]).
const LIBRARY_N: usize = crate::field::Grid::MAX_N;
/// Nodes the library grid adds on every side of the region it covers
/// (`basis::symmetry::MARGIN_NODES`; a test holds the two together).
const LIBRARY_MARGIN: usize = 2;

/// Largest radius of the library grid in node spacings: its centre is
/// rounded to a node, so half a spacing is lost to that as well.
fn cover_nodes() -> f64 {
    ((LIBRARY_N - 1) / 2 - LIBRARY_MARGIN - 1) as f64
}

/// The sample grid: the same type as the simulator's grid
/// ([`crate::field::Grid`]), validated here with the target's own limits.
pub(crate) use crate::field::Grid;

/// The most points per side a target grid over `x × y` may have. The
/// design simulates each primitive once on a library grid that covers the
/// region under every rotation about the plate centre, at the target's
/// spacing: a disc of radius R (the farthest corner) at spacing h needs
/// about 2R/h nodes per side, and the library grid has at most
/// [`crate::field::Grid::MAX_N`]. So h ≥ R/497 and n ≤ L/h + 1 per axis.
pub(crate) fn max_points(x: [f64; 2], y: [f64; 2]) -> [usize; 2] {
    let reach = x
        .iter()
        .flat_map(|&a| y.iter().map(move |&b| a.hypot(b)))
        .fold(0.0, f64::max);
    let h = reach / cover_nodes();
    [x, y].map(|r| {
        let n = ((r[1] - r[0]) / h + 1e-9).floor() + 1.0;
        if n.is_finite() && n < MAX_GRID_N as f64 {
            n as usize
        } else {
            MAX_GRID_N
        }
    })
}

/// Validates a target grid: finite `xmin < xmax`, `ymin < ymax` within
/// ±[`EXTENT`] m, and `2 ≤ nx, ny ≤ `[`MAX_GRID_N`], and no more points
/// than the region allows (`max_points`); errors name `path`.
pub(crate) fn validate_grid(grid: &Grid, path: &str) -> Result<(), TargetError> {
    for (axis, r) in [("x", grid.x), ("y", grid.y)] {
        let p = format!("{path}.{axis}");
        check_interval(&p, axis, r)?;
        for (i, v) in r.iter().enumerate() {
            check_range(&format!("{p}[{i}]"), *v, -EXTENT, EXTENT, " m")?;
        }
    }
    for (i, &n) in grid.n.iter().enumerate() {
        let p = format!("{path}.n[{i}]");
        if !(2..=MAX_GRID_N).contains(&n) {
            return Err(TargetError::invalid(
                p,
                format!("must be in 2..={MAX_GRID_N}, got {n}"),
            ));
        }
    }
    let most = max_points(grid.x, grid.y);
    if grid.n[0] > most[0] || grid.n[1] > most[1] {
        return Err(TargetError::invalid(
            format!("{path}.n"),
            format!(
                "must be at most [{}, {}] over this region (its copies rotated about the \
                 plate centre are simulated on a library grid of at most {LIBRARY_N} nodes \
                 per side), got [{}, {}]",
                most[0], most[1], grid.n[0], grid.n[1]
            ),
        ));
    }
    Ok(())
}

/// Finest spacing (m) of the grid on which the basis of a grid-less
/// `sampled` target is resampled (`scattered_grid`).
pub const SCATTERED_SPACING: f64 = 2e-3;
/// Most points per side of that grid.
pub const SCATTERED_N: usize = 41;

/// The grid on which a grid-less `sampled` target's basis is resampled:
/// the points' bounding box rounded outward to a lattice of spacing h
/// through the plate centre, with at most [`SCATTERED_N`] points per side
/// and h at least [`SCATTERED_SPACING`] (coarser when the points lie far
/// from the plate centre, so that the library grid covering its rotations
/// stays within `crate::field::Grid::MAX_N` nodes per side). Sized by the
/// region, never by the points' spacing: one point, or four within 1 cm,
/// give a grid of a few nodes.
///
/// **Why a lattice through the centre and no margin.** The library grid
/// ([`crate::basis::symmetry::source_grid`]) lies on this grid's lattice,
/// so copies turned by multiples of 90° are resampled exactly (node onto
/// node), as on a target grid symmetric about the centre. A margin, or a
/// lattice off the centre, puts interpolation nodes beyond the farthest
/// sample, where a LineSink's plate lifts the part: a dense scattered
/// target then loses every LineSink to "contact lost" at nodes no part
/// visits (1000 points over ±4 cm would design to DivCircles only).
pub(crate) fn scattered_grid(points: &[[f64; 2]]) -> Grid {
    if points.is_empty() {
        return Grid::DEFAULT;
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let reach =
        lo.iter().chain(&hi).fold(0.0_f64, |m, &c| m.max(c.abs())) * std::f64::consts::SQRT_2;
    let mut h = SCATTERED_SPACING.max(reach / cover_nodes());
    loop {
        let (x, y) = (lattice_side(lo[0], hi[0], h), lattice_side(lo[1], hi[1], h));
        let n = [side_nodes(x, h), side_nodes(y, h)];
        if n[0] <= SCATTERED_N && n[1] <= SCATTERED_N {
            return Grid { x, y, n };
        }
        h *= n[0].max(n[1]) as f64 / SCATTERED_N as f64 * (1.0 + 1e-9);
    }
}

/// `[a, b]` rounded outward to multiples of `h` (a side of at least one
/// spacing), tolerant of points already on the lattice.
fn lattice_side(a: f64, b: f64, h: f64) -> [f64; 2] {
    const ON_LATTICE: f64 = 1e-9;
    let lo = (a / h + ON_LATTICE).floor();
    let hi = (b / h - ON_LATTICE).ceil().max(lo + 1.0);
    [lo * h, hi * h]
}

/// Nodes on a lattice side from [`lattice_side`].
fn side_nodes(r: [f64; 2], h: f64) -> usize {
    ((r[1] - r[0]) / h).round() as usize + 1
}

/// A region of the plate whose sample points do not matter (weight 0).
///
/// JSON (externally tagged, one key per region):
/// `{"circle": {"center": [x, y], "radius": r}}` or
/// `{"rect": {"x": [xmin, xmax], "y": [ymin, ymax]}}` (`"rectangle"` is
/// accepted as an alias of `"rect"`). Regions are closed: points on the
/// boundary are masked too.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum MaskRegion {
    /// Disc `|p - center| ≤ radius`.
    Circle {
        /// Centre in metres (default `[0, 0]`).
        #[serde(default)]
        center: [f64; 2],
        /// Radius in metres, `> 0`.
        radius: f64,
    },
    /// Axis-aligned rectangle `xmin ≤ x ≤ xmax`, `ymin ≤ y ≤ ymax`.
    #[serde(alias = "rectangle")]
    Rect {
        /// `[xmin, xmax]` in metres, `xmin < xmax`.
        x: [f64; 2],
        /// `[ymin, ymax]` in metres, `ymin < ymax`.
        y: [f64; 2],
    },
}

impl MaskRegion {
    /// `true` if `p` lies in the (closed) region.
    pub(crate) fn contains(&self, p: [f64; 2]) -> bool {
        match *self {
            MaskRegion::Circle { center, radius } => {
                let dx = p[0] - center[0];
                let dy = p[1] - center[1];
                dx * dx + dy * dy <= radius * radius
            }
            MaskRegion::Rect { x, y } => {
                x[0] <= p[0] && p[0] <= x[1] && y[0] <= p[1] && p[1] <= y[1]
            }
        }
    }

    /// Checks the region's parameters; `path` is the JSON path of the
    /// region (e.g. `target.mask[0]`).
    pub(crate) fn validate(&self, path: &str) -> Result<(), TargetError> {
        match *self {
            MaskRegion::Circle { center, radius } => {
                check_finite2(&format!("{path}.circle.center"), center)?;
                let p = format!("{path}.circle.radius");
                check_finite(&p, radius)?;
                if radius <= 0.0 {
                    return Err(TargetError::invalid(
                        p,
                        format!("must be > 0, got {}", show(radius)),
                    ));
                }
                Ok(())
            }
            MaskRegion::Rect { x, y } => {
                check_interval(&format!("{path}.rect.x"), "x", x)?;
                check_interval(&format!("{path}.rect.y"), "y", y)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_are_row_major_y_outer() {
        let g = Grid {
            x: [0.0, 2.0],
            y: [10.0, 11.0],
            n: [3, 2],
        };
        assert_eq!(g.xs(), vec![0.0, 1.0, 2.0]);
        assert_eq!(g.ys(), vec![10.0, 11.0]);
        let p = g.points();
        assert_eq!(p.len(), 6);
        assert_eq!(p[1], [1.0, 10.0]);
        assert_eq!(p[2 + 3], [2.0, 11.0]);
        assert_eq!(g.spacing(), 1.0);
    }

    #[test]
    fn linspace_hits_end_points_exactly() {
        let g = Grid {
            x: [-0.04, 0.04],
            y: [-0.04, 0.04],
            n: [21, 21],
        };
        let xs = g.xs();
        assert_eq!(xs[0], -0.04);
        assert_eq!(xs[20], 0.04);
        assert!(xs[10].abs() < 1e-15);
    }

    #[test]
    fn mask_regions_are_closed() {
        let c = MaskRegion::Circle {
            center: [0.0, 0.0],
            radius: 1.0,
        };
        assert!(c.contains([1.0, 0.0]));
        assert!(!c.contains([1.0, 0.1]));
        let r = MaskRegion::Rect {
            x: [0.0, 1.0],
            y: [0.0, 1.0],
        };
        assert!(r.contains([1.0, 1.0]));
        assert!(!r.contains([1.01, 0.5]));
    }

    #[test]
    fn rect_alias_parses() {
        let m: MaskRegion =
            serde_json::from_str(r#"{"rectangle": {"x": [0, 1], "y": [0, 1]}}"#).unwrap();
        assert!(matches!(m, MaskRegion::Rect { .. }));
    }
}
