//! The design basis for a target: the primitive library, rotated about the
//! vertical (every 15° by default) and optionally shifted, resampled by
//! symmetry from one simulation per primitive ([`crate::basis::symmetry`])
//! at the target's points.
//!
//! A column that is invalid anywhere in the target's region (contact lost —
//! a LineSink rotated 45° loses contact in the corners of a ±4 cm square —,
//! not converged, frozen assumption broken, outside the simulated region) is
//! left out and reported; with `keep_invalid` it is kept, its invalid samples
//! set to zero and listed, never used silently.
//!
//! Rotated copies of an isotropic primitive are left out too, and reported:
//! a primitive is isotropic when rotating its simulated field by every
//! multiple of the rotation step changes it by at most [`ISOTROPY_TOL`]
//! ([`symmetry::rotation_asymmetry`]), i.e. only by resampling error; its
//! rotated copies then add columns and near-collinearity but no reach (for
//! an isotropic F, R F(Rᵀ(p − s)) = F(p − s): the copy at rotation 0 with
//! the same shift). The test is on the field, not on the primitive's name.

use serde::Serialize;

use crate::basis::symmetry;
use crate::basis::{FieldLibrary, Primitive};
use crate::field::{Field, FieldKind, Grid, Validity};
use crate::motion::{Motion, Signals};
use crate::schedule::Segment;

/// What a basis column plays.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ColumnSource {
    /// A library primitive with its rotation and shift.
    Primitive(Primitive),
    /// A six-signal motion (e.g. one synthesized for the target,
    /// [`crate::synth`]) with its label. In a schedule beside other moving
    /// segments it ramps in from rest and out to rest inside its cycles
    /// (`MIXED_RAMP_CYCLES`, [`crate::motion::Ramped`]); its column is the
    /// steady motion's field.
    Motion {
        /// Label, e.g. `Synthesized`.
        label: String,
        /// The motion.
        signals: Signals,
    },
}

/// Ramp-in and ramp-out cycles of a six-signal segment in a mixed
/// schedule: 4 cycles each way fit the default 10-cycle minimum segment
/// (with 2 steady cycles); the ramp raises the acceleration by up to about
/// 1.875/(πR) + 0.146/R² ≈ 16 % of the steady peak (one harmonic).
pub(crate) const MIXED_RAMP_CYCLES: u32 = 4;

impl ColumnSource {
    /// Label, e.g. `LineSink@45°` or `Synthesized`.
    pub fn label(&self) -> String {
        match self {
            ColumnSource::Primitive(p) => label(p),
            ColumnSource::Motion { label, .. } => label.clone(),
        }
    }

    /// The steady motion.
    pub(crate) fn motion(&self) -> Motion {
        match self {
            ColumnSource::Primitive(p) => p.motion(),
            ColumnSource::Motion { signals, .. } => Motion::Signals(signals.clone()),
        }
    }

    /// Period of one cycle (s).
    pub(crate) fn period(&self) -> f64 {
        match self {
            ColumnSource::Primitive(p) => p.period(),
            ColumnSource::Motion { signals, .. } => signals.period,
        }
    }

    /// A schedule segment playing this column for `cycles` cycles. A
    /// six-signal motion beside other moving segments (`mixed`) ramps in and
    /// out over R = `MIXED_RAMP_CYCLES` cycles (at most `cycles`) and is
    /// given R more cycles: the two ramps play about R cycles' worth of the
    /// steady field (the window averages ½ over each), so the segment still
    /// plays `cycles` of it, and the fit's proportions between segments
    /// hold; the schedule period grows by R cycles.
    pub(crate) fn segment(&self, weight: f64, cycles: u32, mixed: bool) -> Segment {
        let (primitive, motion, ramp_cycles) = match self {
            ColumnSource::Primitive(p) => (Some(p.clone()), None, None),
            ColumnSource::Motion { signals, .. } => (
                None,
                Some(signals.clone()),
                mixed.then_some(MIXED_RAMP_CYCLES.min(cycles.max(1))),
            ),
        };
        let cycles = cycles + ramp_cycles.unwrap_or(0);
        Segment {
            label: self.label(),
            primitive,
            motion,
            ramp_cycles,
            weight,
            cycles,
            duration_s: f64::from(cycles) * self.period(),
        }
    }
}

/// One basis column: a transformed primitive (or a six-signal motion) and
/// its field at the target points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BasisColumn {
    /// What the column plays.
    pub source: ColumnSource,
    /// Field vectors at the target points.
    #[serde(skip)]
    pub vectors: Vec<[f64; 2]>,
    /// Indices of target points where the field is invalid (only when kept
    /// with `keep_invalid`).
    pub invalid_points: Vec<usize>,
}

/// Largest relative L2 change of a primitive's field under the basis
/// rotations for which it counts as isotropic. On the default 63×63
/// source grid of the shipped targets, Circle and ScaledCircle change by
/// their resampling error only, a fraction of this, under rotations by
/// 15°, 30°, 45° and 90° (force and velocity fields); every other
/// primitive by ≥ 0.26 at 15° (a uniform field: 2 sin 7.5°) and by √2 at
/// 90°.
pub const ISOTROPY_TOL: f64 = 1e-2;

/// A column left out, and why.
pub(crate) use crate::schedule::ExcludedColumn as Excluded;
pub use crate::schedule::ExclusionReason;

/// The assembled basis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignBasis {
    /// Field kind of the columns.
    pub kind: FieldKind,
    /// Usable columns.
    pub columns: Vec<BasisColumn>,
    /// Columns left out.
    pub excluded: Vec<Excluded>,
}

/// Label of a transformed primitive, e.g. `LineSink@45°`.
pub(crate) fn label(p: &Primitive) -> String {
    let mut s = format!("{}@{}°", p.kind.name(), p.rotation_deg);
    // Amplitudes other than the paper's (the gentle copies of a sort).
    if let Some(d) = p.translation {
        s.push_str(&format!("[d0 {:.1} µm]", d * 1e6));
    }
    if let Some(a) = p.amplitude {
        s.push_str(&format!("[ψ0 {:.3} mrad]", a * 1e3));
    }
    if p.shift != [0.0, 0.0] {
        s.push_str(&format!("+({:.4},{:.4})m", p.shift[0], p.shift[1]));
    }
    s
}

/// The grid on which rotated copies are resampled: the target's own grid,
/// or for scattered points one sized by their region
/// (`crate::request::scattered_grid`).
pub fn sampling_grid(grid: Option<&Grid>, points: &[[f64; 2]]) -> Grid {
    grid.copied()
        .unwrap_or_else(|| crate::request::scattered_grid(points))
}

/// The change of `field` under each of `rotations_deg` when every one is
/// within [`ISOTROPY_TOL`] (the field is isotropic for this basis), else
/// `None`. Rotations by 0 (mod 360°) change nothing and are not tested.
fn isotropy(field: &Field, rotations_deg: &[f64]) -> Option<Vec<f64>> {
    rotations_deg
        .iter()
        .map(|&deg| {
            if deg.rem_euclid(360.0) == 0.0 {
                return Some(0.0);
            }
            symmetry::rotation_asymmetry(field, deg.to_radians()).filter(|c| *c <= ISOTROPY_TOL)
        })
        .collect()
}

/// Assembles the basis: every library entry at every rotation and shift,
/// except rotated copies of isotropic entries (kept at the first rotation
/// only; see the module docs).
#[allow(clippy::too_many_arguments)]
pub fn assemble(
    lib: &FieldLibrary,
    rotations_deg: &[f64],
    shifts: &[[f64; 2]],
    target_grid: Option<&Grid>,
    points: &[[f64; 2]],
    weights: &[f64],
    keep_invalid: bool,
) -> DesignBasis {
    let grid = sampling_grid(target_grid, points);
    let mut columns = Vec::new();
    let mut excluded = Vec::new();
    for entry in &lib.entries {
        let source = &entry.field;
        let isotropic = isotropy(source, rotations_deg);
        // Per shift: the label of the first rotation's column, if kept.
        let mut kept_first: Vec<Option<String>> = vec![None; shifts.len()];
        for (r, &deg) in rotations_deg.iter().enumerate() {
            for (s, &shift) in shifts.iter().enumerate() {
                let primitive = Primitive {
                    rotation_deg: deg,
                    shift,
                    ..entry.primitive.clone()
                };
                if let (Some(change), Some(first)) = (&isotropic, &kept_first[s]) {
                    excluded.push(Excluded {
                        label: label(&primitive),
                        invalid_samples: 0,
                        reason: ExclusionReason::IsotropicCopy {
                            copy_of: first.clone(),
                            rotation_change: change[r],
                        },
                    });
                    continue;
                }
                let resampled = symmetry::transformed(source, deg.to_radians(), shift, &grid);
                let name = label(&primitive);
                match column(
                    ColumnSource::Primitive(primitive),
                    &resampled,
                    target_grid.is_some(),
                    points,
                    weights,
                    keep_invalid,
                ) {
                    Ok(c) => {
                        if r == 0 {
                            kept_first[s] = Some(name);
                        }
                        columns.push(c);
                    }
                    Err(e) => excluded.push(e),
                }
            }
        }
    }
    DesignBasis {
        kind: lib.kind,
        columns,
        excluded,
    }
}

/// The column of `source` whose field on the sampling grid is `field`: its
/// vectors at the target points (the grid itself when `on_grid`, else
/// bilinear at `points`), or why it is left out — invalid at a point of
/// positive weight, unless `keep_invalid` (its invalid samples then zero
/// and listed).
pub(crate) fn column(
    source: ColumnSource,
    field: &Field,
    on_grid: bool,
    points: &[[f64; 2]],
    weights: &[f64],
    keep_invalid: bool,
) -> Result<BasisColumn, Excluded> {
    let (vectors, validity): (Vec<[f64; 2]>, Vec<Validity>) = if on_grid {
        (field.vectors.clone(), field.validity.clone())
    } else {
        points
            .iter()
            .map(|p| match field.bilinear(*p) {
                Ok(v) => (v, Validity::Ok),
                Err(flag) => ([0.0, 0.0], flag),
            })
            .unzip()
    };
    // Only points that matter (weight > 0) can disqualify a column.
    let bad: Vec<usize> = (0..points.len())
        .filter(|&i| validity[i] != Validity::Ok && weights[i] > 0.0)
        .collect();
    if bad.is_empty() || keep_invalid {
        let vectors = vectors
            .iter()
            .zip(&validity)
            .map(|(v, ok)| if *ok == Validity::Ok { *v } else { [0.0, 0.0] })
            .collect();
        return Ok(BasisColumn {
            source,
            vectors,
            invalid_points: bad,
        });
    }
    let mut counts: Vec<(Validity, usize)> = Vec::new();
    for &i in &bad {
        match counts.iter_mut().find(|(v, _)| *v == validity[i]) {
            Some(c) => c.1 += 1,
            None => counts.push((validity[i], 1)),
        }
    }
    counts.sort_by_key(|c| std::cmp::Reverse(c.1));
    Err(Excluded {
        label: source.label(),
        invalid_samples: bad.len(),
        reason: ExclusionReason::Invalid(counts[0].0),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::basis::PrimitiveKind;

    /// A scattered point next to a node where the part lost contact leaves
    /// its column out as "contact lost" (not "outside source", which would
    /// read as a grid too small); a point off the grid is "outside
    /// source".
    #[test]
    fn scattered_points_pass_on_the_flag_of_an_invalid_node() {
        let mut validity = vec![Validity::Ok; 9];
        validity[8] = Validity::ContactLost;
        let field = Field {
            grid: Grid {
                x: [0.0, 0.02],
                y: [0.0, 0.02],
                n: [3, 3],
            },
            kind: FieldKind::Velocity,
            vectors: vec![[1.0, 0.0]; 9],
            validity,
        };
        let source = || ColumnSource::Primitive(Primitive::new(PrimitiveKind::LineSink));
        let reason = |p: [f64; 2]| {
            column(source(), &field, false, &[p], &[1.0], false)
                .err()
                .map(|e| e.reason)
        };
        assert_eq!(reason([0.005, 0.005]), None);
        assert_eq!(
            reason([0.015, 0.015]),
            Some(ExclusionReason::Invalid(Validity::ContactLost))
        );
        assert_eq!(
            reason([0.025, 0.005]),
            Some(ExclusionReason::Invalid(Validity::OutsideSource))
        );
    }
}
