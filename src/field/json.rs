//! The field JSON format written by `platefield field` and `primitives`:
//!
//! ```text
//! {"x": [nx], "y": [ny], "fx": [[nx] × ny], "fy": [[nx] × ny],
//!  "valid": [[nx] × ny], "status": [[nx] × ny], "kind": "force" | "velocity",
//!  "units": "m/s^2" | "m/s", "model": {...}, "stats": {...}}
//! ```
//!
//! Rows are y (outer), columns x (inner). `valid` is true where the sample is
//! usable; `status` says why not (`contact_lost`, `not_converged`,
//! `frozen_invalid`, `outside_source`, `non_finite`). Nothing time-dependent is written,
//! so the same input gives the same bytes.

use serde::Serialize;

use super::{Field, FieldKind, FieldSettings, Validity};

/// Counts of samples by validity, and the largest magnitude.
#[derive(Debug, Clone, Serialize, PartialEq)]
pub(crate) struct FieldStats {
    /// Samples.
    pub samples: usize,
    /// Valid samples.
    pub valid: usize,
    /// Samples where the part leaves the plate.
    pub contact_lost: usize,
    /// Samples whose steady state did not converge.
    pub not_converged: usize,
    /// Frozen samples whose excursion is too large.
    pub frozen_invalid: usize,
    /// Resampled samples outside the simulated source region.
    pub outside_source: usize,
    /// Samples that came out NaN or infinite (written only when some did).
    #[serde(skip_serializing_if = "is_zero")]
    pub non_finite: usize,
    /// Largest valid magnitude.
    pub max_magnitude: f64,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Field {
    /// Sample counts by validity.
    pub(crate) fn stats(&self) -> FieldStats {
        let count = |v: Validity| self.validity.iter().filter(|x| **x == v).count();
        FieldStats {
            samples: self.vectors.len(),
            valid: count(Validity::Ok),
            contact_lost: count(Validity::ContactLost),
            not_converged: count(Validity::NotConverged),
            frozen_invalid: count(Validity::FrozenInvalid),
            outside_source: count(Validity::OutsideSource),
            non_finite: count(Validity::NonFinite),
            max_magnitude: self.max_magnitude(),
        }
    }

    /// The field in the documented JSON format.
    pub fn to_json(&self, settings: &FieldSettings) -> serde_json::Value {
        let nx = self.grid.n[0];
        let rows = |f: &dyn Fn(usize) -> serde_json::Value| -> Vec<Vec<serde_json::Value>> {
            (0..self.grid.n[1])
                .map(|j| (0..nx).map(|i| f(j * nx + i)).collect())
                .collect()
        };
        serde_json::json!({
            "x": self.grid.xs(),
            "y": self.grid.ys(),
            "fx": rows(&|k| self.vectors[k][0].into()),
            "fy": rows(&|k| self.vectors[k][1].into()),
            "valid": rows(&|k| (self.validity[k] == Validity::Ok).into()),
            "status": rows(&|k| serde_json::to_value(self.validity[k]).unwrap_or_default()),
            "kind": self.kind,
            "units": match self.kind { FieldKind::Force => "m/s^2", FieldKind::Velocity => "m/s" },
            "model": settings.model,
            "settings": settings,
            "stats": self.stats(),
        })
    }
}
