//! Rectangular sample grids and mask regions.

use serde::{Deserialize, Serialize};

use crate::target::error::{check_finite, check_finite2, check_interval, show, TargetError};

/// Largest allowed number of grid points along one axis (`grid.n[i]`).
pub const MAX_GRID_N: usize = 2048;

/// The sample grid: the same type as the simulator's grid
/// ([`crate::field::Grid`]), validated here with the target's own limits.
pub use crate::field::Grid;

/// Validates a target grid: finite `xmin < xmax`, `ymin < ymax`, and
/// `2 ≤ nx, ny ≤ `[`MAX_GRID_N`]; errors name `path`.
pub fn validate_grid(grid: &Grid, path: &str) -> Result<(), TargetError> {
    check_interval(&format!("{path}.x"), "x", grid.x)?;
    check_interval(&format!("{path}.y"), "y", grid.y)?;
    for (i, &n) in grid.n.iter().enumerate() {
        let p = format!("{path}.n[{i}]");
        if n < 2 {
            return Err(TargetError::invalid(p, format!("must be ≥ 2, got {n}")));
        }
        if n > MAX_GRID_N {
            return Err(TargetError::invalid(
                p,
                format!("must be ≤ {MAX_GRID_N}, got {n}"),
            ));
        }
    }
    Ok(())
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
    pub fn contains(&self, p: [f64; 2]) -> bool {
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
    pub fn validate(&self, path: &str) -> Result<(), TargetError> {
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
