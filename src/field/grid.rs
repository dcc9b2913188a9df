//! Rectangular sampling grids over a region of the plate.

use serde::{Deserialize, Serialize};

use crate::error::{finite, Error, Result};

/// A rectangular grid: `n[0]` points over `x`, `n[1]` over `y` (metres),
/// points ordered row-major (y outer, x inner).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Grid {
    /// [xmin, xmax] (m).
    pub x: [f64; 2],
    /// [ymin, ymax] (m).
    pub y: [f64; 2],
    /// [nx, ny].
    pub n: [usize; 2],
}

impl Grid {
    /// The paper's default region: ±4 cm, 21 × 21 points.
    pub const DEFAULT: Grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [21, 21],
    };

    /// Largest number of points per side ([`Grid::validate`]).
    pub(crate) const MAX_N: usize = 1001;

    /// The four grid nodes around `p` (row-major indices, x fastest) and
    /// their bilinear weights, which sum to 1; `None` outside the grid or
    /// on a grid of fewer than 2 points per side.
    pub(crate) fn bilinear_weights(&self, p: [f64; 2]) -> Option<[(usize, f64); 4]> {
        if self.n[0] < 2 || self.n[1] < 2 {
            return None;
        }
        let fx = |v: f64, r: [f64; 2], n: usize| (v - r[0]) / (r[1] - r[0]) * (n - 1) as f64;
        let (u, v) = (fx(p[0], self.x, self.n[0]), fx(p[1], self.y, self.n[1]));
        let (nu, nv) = ((self.n[0] - 1) as f64, (self.n[1] - 1) as f64);
        if !(u >= 0.0 && v >= 0.0 && u <= nu && v <= nv) {
            return None;
        }
        // u, v ≥ 0 here, where truncation is the floor (without a libm call).
        let (i, j) = (
            (u as usize).min(self.n[0] - 2),
            (v as usize).min(self.n[1] - 2),
        );
        let (a, b) = (u - i as f64, v - j as f64);
        let k = |di: usize, dj: usize| (j + dj) * self.n[0] + i + di;
        Some([
            (k(0, 0), (1.0 - a) * (1.0 - b)),
            (k(1, 0), a * (1.0 - b)),
            (k(0, 1), (1.0 - a) * b),
            (k(1, 1), a * b),
        ])
    }

    /// `p` moved onto the grid's rectangle (each coordinate clamped).
    pub(crate) fn clamp(&self, p: [f64; 2]) -> [f64; 2] {
        [
            p[0].clamp(self.x[0].min(self.x[1]), self.x[0].max(self.x[1])),
            p[1].clamp(self.y[0].min(self.y[1]), self.y[0].max(self.y[1])),
        ]
    }

    /// Validates ranges (nx, ny in 1..=`Grid::MAX_N`, finite, min < max
    /// when n > 1).
    pub fn validate(&self, field: &str) -> Result<()> {
        for (axis, range, n) in [("x", self.x, self.n[0]), ("y", self.y, self.n[1])] {
            finite(&format!("{field}.{axis}[0]"), range[0])?;
            finite(&format!("{field}.{axis}[1]"), range[1])?;
            if n > 1 && range[0] >= range[1] {
                return Err(Error::invalid(
                    format!("{field}.{axis}"),
                    format!(
                        "min must be < max, got [{}, {}]",
                        crate::input::num(range[0]),
                        crate::input::num(range[1])
                    ),
                ));
            }
        }
        for (i, n) in self.n.iter().enumerate() {
            if !(1..=Self::MAX_N).contains(n) {
                return Err(Error::invalid(
                    format!("{field}.n[{i}]"),
                    format!("must be in 1..={}, got {n}", Self::MAX_N),
                ));
            }
        }
        Ok(())
    }

    /// The grid as reports print it: `nx×ny over x ∈ [xmin, xmax] m,
    /// y ∈ [ymin, ymax] m` (numbers as `{}` prints them).
    ///
    /// ```
    /// use platefield::field::Grid;
    /// assert_eq!(Grid::DEFAULT.describe(), "21×21 over x ∈ [-0.04, 0.04] m, y ∈ [-0.04, 0.04] m");
    /// ```
    pub fn describe(&self) -> String {
        let (x, y, n) = (self.x, self.y, self.n);
        format!(
            "{}×{} over x ∈ [{}, {}] m, y ∈ [{}, {}] m",
            n[0], n[1], x[0], x[1], y[0], y[1]
        )
    }

    fn axis(range: [f64; 2], n: usize) -> Vec<f64> {
        if n == 1 {
            return vec![0.5 * (range[0] + range[1])];
        }
        // Both end points exact.
        (0..n)
            .map(|i| {
                if i == n - 1 {
                    range[1]
                } else {
                    range[0] + (range[1] - range[0]) * i as f64 / (n - 1) as f64
                }
            })
            .collect()
    }

    /// x coordinates.
    pub fn xs(&self) -> Vec<f64> {
        Self::axis(self.x, self.n[0])
    }

    /// y coordinates.
    pub fn ys(&self) -> Vec<f64> {
        Self::axis(self.y, self.n[1])
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.n[0] * self.n[1]
    }

    /// All points, row-major (y outer, x inner).
    pub fn points(&self) -> Vec<[f64; 2]> {
        let xs = self.xs();
        self.ys()
            .into_iter()
            .flat_map(|y| xs.iter().map(move |&x| [x, y]))
            .collect()
    }

    /// Smallest spacing between neighbouring points (m); infinite for a
    /// single point.
    pub fn spacing(&self) -> f64 {
        let d = |r: [f64; 2], n: usize| {
            if n > 1 {
                (r[1] - r[0]) / (n - 1) as f64
            } else {
                f64::INFINITY
            }
        };
        d(self.x, self.n[0]).min(d(self.y, self.n[1]))
    }
}
