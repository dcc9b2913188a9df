//! Target velocity fields ("targets") and their JSON file format.
//!
//! A *target* is a requested 2-D velocity field `f(p)` (m/s) on a
//! rectangular region of the plate (`p` in metres). The inverse design tries
//! to find a plate-motion schedule whose time-averaged friction field matches
//! the target at a set of sample points, optionally weighted.
//!
//! Typical use:
//!
//! ```ignore
//! use platefield::request::Target;
//! let target = Target::load(std::path::Path::new("targets/sink.json"))?;
//! let samples = target.sample()?; // points, requested vectors, weights
//! ```
//!
//! # JSON schema reference
//!
//! This section is the reference for target files. All units are SI:
//! positions and lengths in **metres**, velocities in **m/s**, angles in
//! **degrees** counter-clockwise from +x. Unknown keys are rejected
//! everywhere, so typos are errors rather than silently ignored.
//!
//! ```json
//! {
//!   "name": "sink",
//!   "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]},
//!   "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0},
//!   "weights": null,
//!   "mask": [{"circle": {"center": [0.0, 0.0], "radius": 0.005}}]
//! }
//! ```
//!
//! ## Top level
//!
//! | key | type | required | meaning |
//! |-----|------|----------|---------|
//! | `name` | string | no (default `""`) | label for reports and plots |
//! | `grid` | object | yes, unless `field.kind` is `"sampled"` | sample grid, see below |
//! | `field` | object | yes | the requested field, see *Field kinds* |
//! | `weights` | `null` or array of arrays of numbers ≥ 0 | no | per-point weights, see below |
//! | `mask` | array of regions | no (default `[]`) | regions that do not matter (weight 0) |
//! | `shaker` | object | no | limits of a synthesized motion (`design --method synthesize\|auto`), see below |
//! | `friction` | number, `[low, high]` or `{"static": .., "kinetic": ..}` | no (default 0.3) | the parts' friction, exact or known within a range ([`FrictionSpec`]; each coefficient in [0, 2], static ≥ kinetic); a design is made for the range's middle |
//! | `gravity` | number | no (default 9.81) | gravity (m/s², in [0.1, 100]) |
//!
//! ## `shaker`
//!
//! `{"period": T, "linear": [ax, ay, az], "angular": [bx, by, bz],
//! "harmonics": H, "contact_margin": m, "velocity": {"linear": [3], "angular": [3]},
//! "stroke": {"linear": [3], "angular": [3]}}`, every key optional ([`ShakerSpec`];
//! `velocity` and `stroke` limit the plate centre's peak velocity and
//! displacement per axis, `TravelSpec`):
//! the fundamental period (s, in [1e-4, 10]), the peak plate-centre
//! accelerations allowed per world axis (of the summed signal: linear in
//! [0, 1e4] m/s², angular in [0, 1e5] rad/s²), the harmonics 1..=H of
//! 2π/T the controller may play (1..=16) and the least normal force to keep
//! everywhere in the region as a fraction of g ([0, 1)). Keys left out take the default
//! envelope ([`crate::synth::ShakerLimits::envelope`], the paper's primitives and a
//! 6-DOF plate's saved signals: T = 2π/209 s,
//! linear [45.28, 45.28, 7] m/s², angular [218.4, 218.4, 9055] rad/s²,
//! H = 2, m = 0.1). Sequenced designs report the per-axis peaks they use
//! and keep to the limits given here. `"tolerance": {"amplitude": a,
//! "phase_deg": p}` ([`Tolerance`]; a in [0, 0.5], p in [0, 45]) states how
//! closely the controller delivers each channel's harmonics; `verify
//! --tolerance` judges the design under seeded errors within it
//! ([`crate::design::tolerance`]).
//!
//! ## `grid`
//!
//! `{"x": [xmin, xmax], "y": [ymin, ymax], "n": [nx, ny]}` with finite
//! `xmin < xmax`, `ymin < ymax` and `2 ≤ nx, ny ≤ 2048`
//! ([`MAX_GRID_N`]). Both end points are included:
//! `x_i = xmin + i (xmax - xmin) / (nx - 1)`. Sample points are ordered
//! row-major, **y outer, x inner**: point `k = iy * nx + ix` is
//! `(x_ix, y_iy)` (see [`Grid::points`]).
//!
//! ## `weights`
//!
//! Optional non-negative, finite per-point weights with the same layout as
//! the grid: an array of `ny` rows, each an array of `nx` numbers, so
//! `weights[iy][ix]` belongs to point `(x_ix, y_iy)`. For a `sampled` field
//! without a grid, give a single row with one weight per sample point:
//! `[[w_0, w_1, ..., w_{N-1}]]`. Missing or `null` means all weights 1.
//!
//! ## `mask`
//!
//! Array of regions; a sample point inside any region (boundary included)
//! gets weight 0 whatever `weights` says:
//!
//! * `{"circle": {"center": [x, y], "radius": r}}` — `r > 0`, `center`
//!   defaults to `[0, 0]`;
//! * `{"rect": {"x": [xmin, xmax], "y": [ymin, ymax]}}` — `"rectangle"` is
//!   accepted as an alias of `"rect"`.
//!
//! ## Field kinds
//!
//! Every field object has a `"kind"`. In the formulas `d = p - center`,
//! `s = strength`, `t̂ = (cos a, sin a)` is the unit vector of the angle
//! parameter `a` and `n = (-sin a, cos a)` its left normal. All analytic
//! kinds accept `center` (default `[0, 0]`) and `strength` (default `1`).
//!
//! **Units of `strength`.** For fields that grow linearly with distance
//! (`sink`, `source`, `line_sink`, `saddle`, `whirlpool`, `scaled_circle`,
//! `squeeze_trans`) `s` is a rate in **1/s**: the speed at 1 cm from the
//! centre (or line) is `0.01·s` m/s. For bounded fields (`circle`, `trans`,
//! `jet`) `s` is a **speed in m/s**.
//!
//! | kind | extra keys (default) | field `f(p)` |
//! |------|----------------------|--------------|
//! | `sink` | — | `-s d` |
//! | `source` | — | `+s d` |
//! | `line_sink` | `angle` (0): direction of the line; `offset` (0): signed distance of the line from `center` along `n` | `-s (n·d - offset) n` |
//! | `saddle` | `angle` (0): direction of the contracting axis | `s (-(t̂·d) t̂ + (n·d) n)`; for `angle = 0`: `s (-dx, +dy)` |
//! | `whirlpool` | `rotation` ρ (1) | `s (-d + ρ (-dy, dx))` (counter-clockwise for ρ > 0) |
//! | `circle` | — | `s (-dy, dx) / \|d\|`, `0` at the centre (\|d\| ≤ 1e-12 m) |
//! | `scaled_circle` | — | `s (-dy, dx)` |
//! | `trans` | `direction` (0) | `s t̂` (uniform; `center` is accepted but has no effect) |
//! | `squeeze_trans` | `angle` (0): direction of the line; `transport` ρₜ (1) | `s (-(n·d) n + ρₜ L t̂)` with `L = 0.01 m` ([`TRANSPORT_LENGTH`]) |
//! | `jet` | `direction` (0); `width` w (0.01 m, in [1e-6, 1] m) | `s exp(-(n·d)² / (2 w²)) t̂` |
//! | `sum` | `terms`: `[{"weight": w (1), "field": {...}}, ...]`, at least one | `Σ wᵢ fᵢ(p)` |
//! | `sampled` | `points`, `vectors`, `interpolation` (`"idw"`) | interpolated samples |
//!
//! **`squeeze_trans` scaling.** The line (through `center`, direction
//! `angle`) attracts like a `line_sink` with rate `s`, and material moves
//! along it at speed `ρₜ · s · 0.01 m`. So with `transport = 1` the transport
//! speed equals the squeeze speed found 1 cm from the line; with the default
//! `strength = 1` that is 0.01 m/s. A negative `transport` reverses the
//! direction of transport.
//!
//! **`jet` scaling.** `strength` is the speed on the jet's axis (the line
//! through `center` with direction `direction`); `width` is the Gaussian
//! standard deviation across it, so the speed has dropped to
//! `e^{-1/2} ≈ 0.61 s` at distance `width` from the axis. The jet does not
//! decay along its axis.
//!
//! ## `sampled` fields
//!
//! ```json
//! {"kind": "sampled",
//!  "points":  [[x0, y0], [x1, y1], ...],
//!  "vectors": [[fx0, fy0], [fx1, fy1], ...],
//!  "interpolation": "idw"}
//! ```
//!
//! `points` and `vectors` must be non-empty, finite and of equal length.
//! Without a `grid`, the samples themselves are the sample set (and
//! `weights`/`mask` apply to them). With a `grid`, the field is interpolated
//! onto the grid points:
//!
//! * `"idw"` (default): inverse-distance-squared (Shepard) weighting of the 8
//!   nearest samples ([`IDW_NEIGHBORS`]); exact at a sample point (within
//!   1e-12 m), always within the range of the neighbouring samples;
//! * `"nearest"`: the value of the nearest sample (ties: first listed).
//!
//! There is no extrapolation guard: grid points far outside the sampled
//! cloud get the values of the nearest samples, so mask them if they do not
//! matter. A `sampled` field nested inside a `sum` needs a grid.
//!
//! Where a part goes between and beyond the samples of a grid-less target
//! (the played measure of a design, [`crate::design::judge`]),
//! the field is `SampledInterpolant`: local linear fits on a node grid,
//! computed once per point set, exact for an affine field.
//!
//! ## Errors
//!
//! [`Target::from_json_str`] and [`Target::load`] parse *and* validate.
//! Every error names the JSON path of the offending value and what is
//! allowed, e.g.
//!
//! * `target.grid.n[0]: must be ≥ 2, got 0`
//! * `target.grid.x: xmin must be < xmax, got [0.04, -0.04]`
//! * `target.field.kind: unknown kind "sinc" (expected one of sink, source, ...)`
//! * ``target.field: unknown field `strenght`, expected one of `center`, `strength` ``
//!   (serde's message, prefixed with the path)
//! * `target.field.points: 12 points but 11 vectors`
//! * `target.field.strength: must be finite, got NaN`
//! * `target.weights[3][4]: must be ≥ 0, got -1`
//! * `target.grid: missing; required for field kind "sink" ...`
//!
//! Errors from [`Target::load`] are additionally prefixed with the file
//! path. JSON itself cannot hold NaN or infinity (and overflowing literals
//! such as `1e999` are syntax errors), but [`Target::validate`] also checks
//! finiteness for targets built in code.

mod attractor;
mod classes;
mod error;
mod examples;
pub mod family;
mod field;
mod folder;
mod grid;
mod interpolant;
mod mirror;
mod shaker;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::field::FieldSettings;
/// Fewest sample points with a positive weight a target may leave: one or
/// two points sample a field at one or two places (a 2-D affine field has
/// six coefficients; three points in general position fix them), so a fit
/// or a realised measure over fewer would be reported as a result it is
/// not.
pub const MIN_WEIGHTED_POINTS: usize = 3;

pub use crate::scene::FrictionSpec;
pub use attractor::Attractor;
pub(crate) use classes::PartClass;
pub use classes::{Edge, MAX_CLASSES};
pub use error::TargetError;
pub use examples::examples;
pub use field::SumTerm;
pub use field::{
    FieldSpec, Interpolation, ANGLE, COINCIDENT, DEFAULT_JET_WIDTH, EXTENT, FIELD_KINDS,
    IDW_NEIGHBORS, MAX_SAMPLED_POINTS, MAX_TERMS, MIN_JET_WIDTH, RATIO, SPEED, STRENGTH,
    TRANSPORT_LENGTH, WEIGHT,
};
pub(crate) use folder::plain_folder_name;
pub(crate) use grid::scattered_grid;
pub(crate) use grid::Grid;
pub use grid::{MaskRegion, MAX_GRID_N, SCATTERED_N, SCATTERED_SPACING};
pub(crate) use interpolant::SampledInterpolant;
pub use interpolant::{LINEAR_NEIGHBORS, MAX_NODES, MIN_NODES};
pub use shaker::ShakerSpec;
pub use shaker::Tolerance;
pub(crate) use shaker::TravelSpec;
pub use shaker::{MAX_HARMONICS, MAX_PERIOD_S, MIN_PERIOD_S};

use error::show;

/// A target whose largest |f| (m/s) over its weighted points is at most
/// this is refused as zero: no schedule can be designed for it.
pub(crate) const ZERO_FIELD: f64 = 1e-12;

/// A requested velocity field on a region of the plate; the in-memory form
/// of a target JSON file (see the [module documentation](self)).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Target {
    /// Label for reports and plots.
    #[serde(default)]
    pub name: String,
    /// Sample grid; required unless `field` is [`FieldSpec::Sampled`].
    #[serde(default)]
    pub grid: Option<Grid>,
    /// The requested field.
    pub field: FieldSpec,
    /// Optional per-point weights, `weights[iy][ix]` (see the module docs
    /// for the grid-less `sampled` case).
    #[serde(default, deserialize_with = "weights")]
    pub weights: Option<Vec<Vec<f64>>>,
    /// Regions whose points get weight 0.
    #[serde(default)]
    pub mask: Vec<MaskRegion>,
    /// Limits of a synthesized motion (absent: the paper's envelope).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shaker: Option<ShakerSpec>,
    /// The parts' friction, exact or a range ([`FrictionSpec`]; absent:
    /// the design options' friction, μ = 0.3 by default). A design is made
    /// for its nominal value (a range's middle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionSpec>,
    /// Gravity (m/s², in the scenes' range; absent: the design options',
    /// 9.81 by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<f64>,
    /// Part classes sorted by friction (`PartClass`, at least two),
    /// instead of one `field` and `friction`; empty for a plain target.
    /// With classes, `field` holds the first class's field.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub classes: Vec<PartClass>,
}

/// `null` or rows of weights; a flat list of numbers is an error that says
/// which shape is expected.
fn weights<'de, D: serde::Deserializer<'de>>(d: D) -> Result<Option<Vec<Vec<f64>>>, D::Error> {
    let value = serde_json::Value::deserialize(d)?;
    if let Some(items) = value.as_array() {
        if items.first().is_some_and(|v| v.is_number()) {
            return Err(serde::de::Error::custom(format!(
                "must be an array of rows, weights[iy][ix]: ny rows of nx numbers for a grid, \
                 or one row [[w0, w1, ...]] for a sampled field without a grid; got a flat \
                 list of {} numbers (wrap it in [ ])",
                items.len()
            )));
        }
    }
    crate::input::nested::<D, _>(value)
}

/// A target evaluated at its sample points: what the inverse design fits.
#[derive(Debug, Clone, PartialEq)]
pub struct SampledTarget {
    /// Sample positions (metres); grid order is row-major, y outer.
    pub points: Vec<[f64; 2]>,
    /// Requested field (m/s) at each point.
    pub vectors: Vec<[f64; 2]>,
    /// Weight of each point (≥ 0; 0 where masked).
    pub weights: Vec<f64>,
}

impl SampledTarget {
    /// Number of sample points.
    pub fn len(&self) -> usize {
        self.points.len()
    }

    /// Largest `|f|` (m/s) over points with a positive weight.
    pub(crate) fn max_norm(&self) -> f64 {
        self.vectors
            .iter()
            .zip(&self.weights)
            .filter(|&(_, &w)| w > 0.0)
            .map(|(v, _)| v[0].hypot(v[1]))
            .fold(0.0, f64::max)
    }
}

impl Target {
    /// Parses and validates a target from JSON text.
    ///
    /// Errors name the JSON path of the problem (see the module docs).
    pub fn from_json_str(s: &str) -> Result<Target, TargetError> {
        let prepared = classes::prepare(s)?;
        let target: Target = crate::input::from_str(prepared.as_deref().unwrap_or(s), "target")
            .map_err(|e| TargetError::invalid(e.path, e.message))?;
        target.validate()?;
        Ok(target)
    }

    /// Reads, parses and validates a target file; errors are prefixed with
    /// the file path.
    pub fn load(path: &Path) -> Result<Target, TargetError> {
        let text = crate::input::read_input(path).map_err(|error| TargetError::Io {
            file: path.to_path_buf(),
            error,
        })?;
        Target::from_json_str(&text).map_err(|error| TargetError::InFile {
            file: path.to_path_buf(),
            error: Box::new(error),
        })
    }

    /// Serializes the target as pretty-printed JSON (all defaults written
    /// out explicitly).
    pub fn to_json_pretty(&self) -> String {
        let mut value = serde_json::to_value(self).expect("a Target always serializes");
        if !self.classes.is_empty() {
            // The classes give the fields; `field` only mirrors the first.
            if let Some(map) = value.as_object_mut() {
                map.remove("field");
            }
        }
        serde_json::to_string_pretty(&value).expect("a Target always serializes")
    }

    /// Number of sample points: grid points if there is a grid, otherwise
    /// the samples of a `sampled` field (0 if neither).
    pub(crate) fn sample_count(&self) -> usize {
        match (&self.grid, &self.field) {
            (Some(g), _) => g.len(),
            (None, FieldSpec::Sampled { points, .. }) => points.len(),
            (None, _) => 0,
        }
    }

    /// Checks every value against its allowed range (see the module docs);
    /// the first problem found is returned.
    pub fn validate(&self) -> Result<(), TargetError> {
        if !self.classes.is_empty() && self.grid.is_none() {
            return Err(TargetError::invalid(
                "target.grid",
                "missing; required with target.classes",
            ));
        }
        classes::validate(&self.classes)?;
        match &self.grid {
            Some(g) => grid::validate_grid(g, "target.grid")?,
            None => {
                if !matches!(self.field, FieldSpec::Sampled { .. }) {
                    return Err(TargetError::invalid(
                        "target.grid",
                        format!(
                            "missing; required for field kind \"{}\" (only a \"sampled\" field may omit the grid)",
                            self.field.kind()
                        ),
                    ));
                }
            }
        }
        self.field.validate("target.field")?;
        if let Some(w) = &self.weights {
            self.validate_weights(w)?;
        }
        for (i, m) in self.mask.iter().enumerate() {
            m.validate(&format!("target.mask[{i}]"))?;
        }
        if let Some(s) = &self.shaker {
            s.validate("target.shaker")?;
        }
        self.validate_physics()
    }

    /// The parts' friction and gravity, with the scenes' one validation.
    fn validate_physics(&self) -> Result<(), TargetError> {
        let invalid = |e: crate::error::Error| match e {
            crate::error::Error::Invalid { field, message } => TargetError::invalid(field, message),
            other => TargetError::invalid("target", other.to_string()),
        };
        if let Some(f) = &self.friction {
            f.validate_driven("target.friction").map_err(invalid)?;
        }
        if let Some(g) = self.gravity {
            let (lo, hi) = (crate::scene::GRAVITY_MIN, crate::scene::GRAVITY);
            if !(g.is_finite() && (lo..=hi).contains(&g)) {
                return Err(TargetError::invalid(
                    "target.gravity",
                    format!(
                        "must be in [{}, {}] m/s², got {}",
                        show(lo),
                        show(hi),
                        show(g)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `base` with the friction (its nominal value) and gravity this
    /// target states; the rest of `base` as it is.
    pub(crate) fn physics(&self, base: &FieldSettings) -> FieldSettings {
        FieldSettings {
            friction: self.friction.map_or(base.friction, |f| f.nominal()),
            gravity: self.gravity.unwrap_or(base.gravity),
            ..*base
        }
    }

    fn validate_weights(&self, w: &[Vec<f64>]) -> Result<(), TargetError> {
        let (rows, cols, what_rows, what_cols) = match &self.grid {
            Some(g) => (g.n[1], g.n[0], "grid.n[1]", "grid.n[0]"),
            None => (
                1,
                self.sample_count(),
                "a single row",
                "one per sample point",
            ),
        };
        if w.len() != rows {
            return Err(TargetError::invalid(
                "target.weights",
                format!("expected {rows} rows ({what_rows}), got {}", w.len()),
            ));
        }
        for (iy, row) in w.iter().enumerate() {
            if row.len() != cols {
                return Err(TargetError::invalid(
                    format!("target.weights[{iy}]"),
                    format!("expected {cols} entries ({what_cols}), got {}", row.len()),
                ));
            }
            for (ix, &v) in row.iter().enumerate() {
                let p = format!("target.weights[{iy}][{ix}]");
                error::check_finite(&p, v)?;
                if v < 0.0 {
                    return Err(TargetError::invalid(
                        p,
                        format!("must be ≥ 0, got {}", show(v)),
                    ));
                }
            }
        }
        Ok(())
    }

    /// Validates the target and evaluates it at its sample points.
    ///
    /// With a grid, the points are [`Grid::points`] and the vectors
    /// [`FieldSpec::eval`] there. Without a grid (only for a `sampled`
    /// field) the samples are used as given. Each weight is the `weights`
    /// entry (default 1), or 0 if the point lies in a mask region.
    ///
    /// Fails if the target is invalid, if the field evaluates to a
    /// non-finite value somewhere, or if every weight ends up 0.
    pub fn sample(&self) -> Result<SampledTarget, TargetError> {
        self.validate()?;
        let (points, vectors) = match (&self.grid, &self.field) {
            (Some(g), field) => {
                let points = g.points();
                let vectors: Vec<[f64; 2]> = points.iter().map(|&p| field.eval(p)).collect();
                (points, vectors)
            }
            (
                None,
                FieldSpec::Sampled {
                    points, vectors, ..
                },
            ) => (points.clone(), vectors.clone()),
            (None, _) => unreachable!("validate() requires a grid for analytic fields"),
        };
        if let Some((p, v)) = points
            .iter()
            .zip(&vectors)
            .find(|(_, v)| !(v[0].is_finite() && v[1].is_finite()))
        {
            return Err(TargetError::invalid(
                "target.field",
                format!(
                    "evaluates to a non-finite vector {} at {}",
                    error::show2(*v),
                    error::show2(*p)
                ),
            ));
        }
        let mut weights: Vec<f64> = match &self.weights {
            Some(w) => w.iter().flatten().copied().collect(),
            None => vec![1.0; points.len()],
        };
        for (w, p) in weights.iter_mut().zip(&points) {
            if self.mask.iter().any(|m| m.contains(*p)) {
                *w = 0.0;
            }
        }
        if !weights.iter().any(|&w| w > 0.0) {
            return Err(TargetError::invalid(
                "target",
                format!(
                    "all {} sample points have weight 0 (check target.weights and target.mask)",
                    points.len()
                ),
            ));
        }
        self.enough_weighted(&weights)?;
        let largest = vectors
            .iter()
            .zip(&weights)
            .filter(|&(_, &w)| w > 0.0)
            .map(|(v, _)| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        if largest <= ZERO_FIELD {
            return Err(TargetError::invalid(
                "target.field",
                format!(
                    "is zero (|f| ≤ {} m/s) at every sample point with a positive weight: \
                     there is nothing to design (check the strengths and sum weights)",
                    error::show(ZERO_FIELD)
                ),
            ));
        }
        Ok(SampledTarget {
            points,
            vectors,
            weights,
        })
    }
}

impl Target {
    /// Refuses `weights` (one per sample point, masks applied) that leave
    /// fewer than [`MIN_WEIGHTED_POINTS`] points weighted, naming what left
    /// them: `target.field.points` (a sampled field with too few points),
    /// `target.weights` or `target.mask`.
    fn enough_weighted(&self, weights: &[f64]) -> Result<(), TargetError> {
        let weighted = weights.iter().filter(|&&w| w > 0.0).count();
        if weighted >= MIN_WEIGHTED_POINTS {
            return Ok(());
        }
        let at = match (&self.field, &self.weights, self.mask.is_empty()) {
            (FieldSpec::Sampled { .. }, None, true) => "target.field.points",
            (_, None, false) => "target.mask",
            _ => "target.weights",
        };
        Err(TargetError::invalid(
            at,
            format!(
                "leaves {weighted} of {} sample points with a positive weight; a field is fitted and measured over at least {MIN_WEIGHTED_POINTS} (a 2-D affine field has six coefficients: three points in general position fix them)",
                weights.len()
            ),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: &str = r#""grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]}"#;

    fn with_field(field: &str) -> String {
        format!(r#"{{"name": "t", {GRID}, "field": {field}}}"#)
    }

    /// Asserts that parsing `json` fails with a message containing every
    /// string in `needles`.
    fn assert_err(json: &str, needles: &[&str]) -> TargetError {
        let err = match Target::from_json_str(json) {
            Ok(t) => panic!("expected an error for {json}, got {t:?}"),
            Err(e) => e,
        };
        let msg = err.to_string();
        for n in needles {
            assert!(msg.contains(n), "message {msg:?} lacks {n:?}");
        }
        err
    }

    #[test]
    fn every_example_parses_validates_and_samples() {
        let ex = examples();
        let names: Vec<&str> = ex.iter().map(|(n, _)| *n).collect();
        for want in [
            "sink.json",
            "saddle.json",
            "whirlpool.json",
            "squeeze_trans.json",
            "jet.json",
            "line_sink.json",
            "circle.json",
            "sampled.json",
        ] {
            assert!(names.contains(&want), "missing example {want}");
        }
        for (name, json) in ex {
            let t = Target::from_json_str(&json).unwrap_or_else(|e| panic!("{name}: {e}"));
            t.validate().unwrap();
            let s = t.sample().unwrap_or_else(|e| panic!("{name}: {e}"));
            assert_eq!(s.points.len(), s.vectors.len());
            assert_eq!(s.points.len(), s.weights.len());
            assert!(s.weights.iter().any(|&w| w > 0.0));
            assert!(s.max_norm() > 0.0, "{name}");
            if name == "sampled.json" {
                assert!(t.grid.is_none());
                assert!((20..=30).contains(&s.len()));
            } else {
                assert_eq!(s.len(), 21 * 21, "{name}");
                let g = t.grid.unwrap();
                assert_eq!((g.x, g.y), ([-0.04, 0.04], [-0.04, 0.04]));
            }
            // Round trip through the serde derive form.
            let again = Target::from_json_str(&t.to_json_pretty()).unwrap();
            assert_eq!(again, t, "{name}");
        }
    }

    #[test]
    fn whirlpool_example_has_rotation_one() {
        let (_, json) = examples()
            .into_iter()
            .find(|(n, _)| *n == "whirlpool.json")
            .unwrap();
        let t = Target::from_json_str(&json).unwrap();
        assert!(matches!(t.field, FieldSpec::Whirlpool { rotation, .. } if rotation == 1.0));
    }

    #[test]
    fn defaults_are_applied() {
        let t = Target::from_json_str(&with_field(r#"{"kind": "sink"}"#)).unwrap();
        assert_eq!(
            t.field,
            FieldSpec::Sink {
                center: [0.0, 0.0],
                strength: 1.0
            }
        );
        assert_eq!(t.weights, None);
        assert!(t.mask.is_empty());
        let t = Target::from_json_str(&with_field(r#"{"kind": "jet"}"#)).unwrap();
        assert!(matches!(t.field, FieldSpec::Jet { width, .. } if width == DEFAULT_JET_WIDTH));
    }

    #[test]
    fn sampling_follows_grid_order_weights_and_mask() {
        let json = r#"{
            "grid": {"x": [0, 0.2], "y": [0, 0.1], "n": [3, 2]},
            "field": {"kind": "source"},
            "weights": [[1, 2, 3], [4, 5, 6]],
            "mask": [{"rect": {"x": [0.15, 0.3], "y": [0.05, 0.2]}}]
        }"#;
        let s = Target::from_json_str(json).unwrap().sample().unwrap();
        assert_eq!(s.points[4], [0.1, 0.1]);
        assert_eq!(s.vectors[4], [0.1, 0.1]);
        assert_eq!(s.weights, vec![1.0, 2.0, 3.0, 4.0, 5.0, 0.0]);
    }

    #[test]
    fn sampled_field_on_grid_and_gridless_weights() {
        let json = r#"{
            "grid": {"x": [0, 1], "y": [0, 1], "n": [2, 2]},
            "field": {"kind": "sampled", "points": [[0, 0], [1, 1]], "vectors": [[1, 0], [0, 1]],
                      "interpolation": "nearest"}
        }"#;
        let s = Target::from_json_str(json).unwrap().sample().unwrap();
        assert_eq!(
            s.vectors,
            vec![[1.0, 0.0], [1.0, 0.0], [1.0, 0.0], [0.0, 1.0]]
        );

        let json = r#"{
            "field": {"kind": "sampled", "points": [[0, 0], [1, 1], [1, 0]],
                      "vectors": [[1, 0], [0, 1], [1, 1]]},
            "weights": [[0.5, 2, 1]]
        }"#;
        let s = Target::from_json_str(json).unwrap().sample().unwrap();
        assert_eq!(s.points, vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0]]);
        assert_eq!(s.weights, vec![0.5, 2.0, 1.0]);

        let json = r#"{
            "field": {"kind": "sampled", "points": [[0, 0], [1, 1], [1, 0]],
                      "vectors": [[1, 0], [0, 1], [1, 1]]},
            "weights": [[0.5], [2], [1]]
        }"#;
        assert_err(json, &["target.weights", "expected 1 rows"]);

        // Two weighted points are no field to fit.
        let json = r#"{
            "field": {"kind": "sampled", "points": [[0, 0], [1, 1], [1, 0]],
                      "vectors": [[1, 0], [0, 1], [1, 1]]},
            "weights": [[0.5, 2, 0]]
        }"#;
        let e = Target::from_json_str(json).unwrap().sample().unwrap_err();
        assert!(
            e.to_string()
                .starts_with("target.weights: leaves 2 of 3 sample points"),
            "{e}"
        );
    }

    #[test]
    fn sum_json_samples_to_weighted_sum_of_terms() {
        let sum = Target::from_json_str(&with_field(
            r#"{"kind": "sum", "terms": [
                {"weight": 0.5, "field": {"kind": "sink", "center": [0.01, 0.0]}},
                {"weight": -2, "field": {"kind": "trans", "strength": 0.01, "direction": 30}},
                {"field": {"kind": "sum", "terms": [{"weight": 3, "field": {"kind": "saddle", "angle": 45}}]}}
            ]}"#,
        ))
        .unwrap()
        .sample()
        .unwrap();
        let part = |f: &str| {
            Target::from_json_str(&with_field(f))
                .unwrap()
                .sample()
                .unwrap()
        };
        let a = part(r#"{"kind": "sink", "center": [0.01, 0.0]}"#);
        let b = part(r#"{"kind": "trans", "strength": 0.01, "direction": 30}"#);
        let c = part(r#"{"kind": "saddle", "angle": 45}"#);
        for i in 0..sum.len() {
            for k in 0..2 {
                let want = 0.5 * a.vectors[i][k] - 2.0 * b.vectors[i][k] + 3.0 * c.vectors[i][k];
                assert!((sum.vectors[i][k] - want).abs() < 1e-15);
            }
        }
    }

    #[test]
    fn sampled_example_interpolated_onto_grid() {
        let (_, json) = examples().pop().unwrap();
        let mut t = Target::from_json_str(&json).unwrap();
        t.grid = Some(Grid {
            x: [-0.04, 0.04],
            y: [-0.04, 0.04],
            n: [21, 21],
        });
        let s = t.sample().unwrap();
        assert_eq!(s.len(), 441);
        for (p, v) in s.points.iter().zip(&s.vectors) {
            // Exact (up to grid rounding) on the 2 cm sample lattice, and a
            // bounded blend of neighbours elsewhere.
            let on_lattice = p
                .iter()
                .all(|c| ((c / 0.02).round() * 0.02 - c).abs() < 1e-12);
            if on_lattice {
                assert!(
                    (v[0] + p[0]).abs() < 1e-12 && (v[1] + p[1]).abs() < 1e-12,
                    "{p:?}"
                );
            }
            assert!(v[0].abs() <= 0.04 + 1e-12 && v[1].abs() <= 0.04 + 1e-12);
        }
    }

    #[test]
    fn bad_grid_n() {
        let json = r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [0, 21]},
                       "field": {"kind": "sink"}}"#;
        let e = assert_err(json, &["target.grid.n[0]: must be in 2..=1001, got 0"]);
        assert_eq!(e.field_path(), Some("target.grid.n[0]"));
        let json = r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 100000]},
                       "field": {"kind": "sink"}}"#;
        assert_err(json, &["target.grid.n[1]: must be in 2..=1001, got 100000"]);
        let json = r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [-3, 21]},
                       "field": {"kind": "sink"}}"#;
        assert_err(json, &["target.grid"]);
    }

    #[test]
    fn empty_ranges() {
        let json = r#"{"grid": {"x": [0.04, -0.04], "y": [-0.04, 0.04], "n": [21, 21]},
                       "field": {"kind": "sink"}}"#;
        assert_err(json, &["target.grid.x: xmin must be < xmax"]);
        let json = r#"{"grid": {"x": [-0.04, 0.04], "y": [0.01, 0.01], "n": [21, 21]},
                       "field": {"kind": "sink"}}"#;
        assert_err(json, &["target.grid.y: ymin must be < ymax"]);
    }

    #[test]
    fn unknown_kind_lists_allowed_kinds() {
        assert_err(
            &with_field(r#"{"kind": "sinc"}"#),
            &[
                "target.field.kind: unknown kind \"sinc\"",
                "expected one of sink, source,",
                "sampled",
            ],
        );
        assert_err(
            &with_field(
                r#"{"kind": "sum", "terms": [{"weight": 1, "field": {"kind": "sink"}},
                                             {"weight": 1, "field": {"kind": "whirl"}}]}"#,
            ),
            &["target.field.terms[1].field.kind: unknown kind \"whirl\""],
        );
        assert_err(
            &with_field(r#"{"strength": 1}"#),
            &["target.field.kind: missing"],
        );
    }

    #[test]
    fn typos_are_rejected_with_path() {
        assert_err(
            &with_field(r#"{"kind": "sink", "strenght": 2}"#),
            &["target.field", "strenght"],
        );
        assert_err(
            &format!(r#"{{{GRID}, "field": {{"kind": "sink"}}, "maks": []}}"#),
            &["target.maks: unknown field"],
        );
        assert_err(
            r#"{"grid": {"x": [0, 1], "y": [0, 1], "n": [2, 2], "nx": 3}, "field": {"kind": "sink"}}"#,
            &["target.grid.nx: unknown field"],
        );
        assert_err(
            &format!(
                r#"{{{GRID}, "field": {{"kind": "sink"}}, "mask": [{{"circle": {{"radius": 0.01, "centre": [0, 0]}}}}]}}"#
            ),
            &["target.mask[0]", "centre"],
        );
        assert_err(
            &with_field(r#"{"kind": "sum", "terms": [{"wieght": 1, "field": {"kind": "sink"}}]}"#),
            &["target.field.terms[0].wieght: unknown field"],
        );
        assert_err(
            &with_field(r#"{"kind": "sum", "terms": [{"field": {"kind": "sink", "angle": 3}}]}"#),
            &["target.field.terms[0].field", "angle"],
        );
        assert_err(
            &with_field(r#"{"kind": "sink", "strength": "big"}"#),
            &["target.field.strength: must be a number, got string \"big\""],
        );
    }

    #[test]
    fn point_vector_count_mismatch() {
        let pts: Vec<String> = (0..12).map(|i| format!("[{i}, 0]")).collect();
        let vecs: Vec<String> = (0..11).map(|_| "[0, 0]".to_string()).collect();
        let json = format!(
            r#"{{"field": {{"kind": "sampled", "points": [{}], "vectors": [{}]}}}}"#,
            pts.join(","),
            vecs.join(",")
        );
        assert_err(&json, &["target.field.points: 12 points but 11 vectors"]);
        assert_err(
            r#"{"field": {"kind": "sampled", "points": [], "vectors": []}}"#,
            &["target.field.points: must contain 1..=100000 points, got 0"],
        );
    }

    #[test]
    fn non_finite_values_are_rejected() {
        let mut t = Target::from_json_str(&with_field(r#"{"kind": "sink"}"#)).unwrap();
        t.field = FieldSpec::Sink {
            center: [0.0, 0.0],
            strength: f64::NAN,
        };
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("target.field.strength: must be finite"), "{e}");

        t.field = FieldSpec::Whirlpool {
            center: [f64::INFINITY, 0.0],
            strength: 1.0,
            rotation: 1.0,
        };
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("target.field.center: must be finite"), "{e}");

        t.field = FieldSpec::Sum {
            terms: vec![SumTerm {
                weight: 1.0,
                field: FieldSpec::Jet {
                    center: [0.0, 0.0],
                    strength: 1.0,
                    direction: f64::NAN,
                    width: 0.01,
                },
            }],
        };
        let e = t.validate().unwrap_err().to_string();
        assert!(
            e.contains("target.field.terms[0].field.direction: must be finite"),
            "{e}"
        );

        t.field = FieldSpec::Sink {
            center: [0.0, 0.0],
            strength: 1.0,
        };
        t.grid.as_mut().unwrap().x[1] = f64::NAN;
        let e = t.validate().unwrap_err().to_string();
        assert!(e.contains("target.grid.x: must be finite"), "{e}");

        // Overflowing literals cannot even be parsed.
        assert_err(
            &with_field(r#"{"kind": "sink", "strength": 1e999}"#),
            &["target.field.strength: must be a finite number, got 1e999 (out of range"],
        );
    }

    #[test]
    fn bad_weights() {
        let rows = |n: usize, v: &str| {
            let row = format!("[{}]", vec!["1"; 21].join(","));
            let mut r = vec![row; n];
            if !v.is_empty() {
                r[3] = format!("[{}]", {
                    let mut c = vec!["1"; 21];
                    c[4] = v;
                    c.join(",")
                });
            }
            format!("[{}]", r.join(","))
        };
        let make =
            |w: String| format!(r#"{{{GRID}, "field": {{"kind": "sink"}}, "weights": {w}}}"#);
        assert!(Target::from_json_str(&make(rows(21, ""))).is_ok());
        assert_err(
            &make(rows(21, "-1")),
            &["target.weights[3][4]: must be ≥ 0, got -1"],
        );
        assert_err(
            &make(rows(20, "")),
            &["target.weights: expected 21 rows (grid.n[1]), got 20"],
        );
        let short = make(rows(21, "").replacen("[1,", "[", 1));
        assert_err(
            &short,
            &["target.weights[0]: expected 21 entries (grid.n[0]), got 20"],
        );
        assert_err(&make("[1, 2]".into()), &["target.weights"]);
    }

    #[test]
    fn bad_mask_and_sum() {
        assert_err(
            &format!(
                r#"{{{GRID}, "field": {{"kind": "sink"}}, "mask": [{{"circle": {{"radius": -1}}}}]}}"#
            ),
            &["target.mask[0].circle.radius: must be > 0, got -1"],
        );
        assert_err(
            &format!(
                r#"{{{GRID}, "field": {{"kind": "sink"}}, "mask": [{{"rect": {{"x": [1, 0], "y": [0, 1]}}}}]}}"#
            ),
            &["target.mask[0].rect.x: xmin must be < xmax"],
        );
        assert_err(
            &format!(r#"{{{GRID}, "field": {{"kind": "sink"}}, "mask": [{{"polygon": {{}}}}]}}"#),
            &["target.mask[0]", "polygon"],
        );
        assert_err(
            &with_field(r#"{"kind": "sum", "terms": []}"#),
            &["target.field.terms: must contain 1..=1000 terms, got 0"],
        );
        assert_err(
            &with_field(r#"{"kind": "jet", "width": 0}"#),
            &["target.field.width: must be in [0.000001, 1] m, got 0"],
        );
    }

    #[test]
    fn everything_masked_is_an_error() {
        let json = format!(
            r#"{{{GRID}, "field": {{"kind": "sink"}}, "mask": [{{"rect": {{"x": [-1, 1], "y": [-1, 1]}}}}]}}"#
        );
        let t = Target::from_json_str(&json).unwrap();
        let e = t.sample().unwrap_err().to_string();
        assert!(e.contains("weight 0"), "{e}");
    }

    #[test]
    fn missing_grid_for_analytic_field() {
        assert_err(
            r#"{"field": {"kind": "saddle"}}"#,
            &["target.grid: missing; required for field kind \"saddle\""],
        );
        assert_err(
            r#"{"field": {"kind": "sum", "terms": [{"field": {"kind": "sampled", "points": [[0,0]], "vectors": [[0,0]]}}]}}"#,
            &["target.grid: missing"],
        );
        assert_err(r#"{"name": "x"}"#, &["target.field: missing"]);
        assert_err(r#"[1, 2]"#, &["target: must be a JSON object"]);
    }

    /// Vanishing strengths and weights, a zero field, a grid
    /// finer than the region allows and flat weights are refused by the
    /// loader, naming the path and the range, with short numbers.
    #[test]
    fn degenerate_targets_are_refused_with_their_range() {
        let range = "must be non-zero, with |value| in [0.000001, 1000000] 1/s, got";
        assert_err(
            &with_field(r#"{"kind": "sink", "strength": 0}"#),
            &["target.field.strength: ", range, "got 0"],
        );
        assert_err(
            &with_field(r#"{"kind": "sink", "strength": 1e-300}"#),
            &["target.field.strength: ", range, "got 1e-300"],
        );
        assert_err(
            &with_field(r#"{"kind": "sum", "terms": [{"field": {"kind": "sink"}}, {"weight": 0, "field": {"kind": "trans"}}]}"#),
            &["target.field.terms[1].weight: must be non-zero, with |value| in [0.000001, 1000000], got 0"],
        );
        assert_err(
            &with_field(r#"{"kind": "trans", "strength": -1e308}"#),
            &["target.field.strength: must be non-zero, with |value| in [0.000001, 1000000] m/s, got -1e308"],
        );
        // A sum that cancels everywhere: refused when sampled, before any
        // library is built (design samples the target first).
        let t = Target::from_json_str(&with_field(
            r#"{"kind": "sum", "terms": [{"field": {"kind": "sink"}}, {"field": {"kind": "source"}}]}"#,
        ))
        .unwrap();
        let e = t.sample().unwrap_err().to_string();
        assert!(
            e.starts_with("target.field: is zero (|f| ≤ 1e-12 m/s) at every sample point"),
            "{e}"
        );
        let zero = r#"{"field": {"kind": "sampled", "points": [[0, 0], [0.01, 0], [0, 0.01]], "vectors": [[0, 0], [0, 0], [0, 0]]}}"#;
        let e = Target::from_json_str(zero)
            .unwrap()
            .sample()
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("target.field: is zero"), "{e}");
        // The target's own limit, not the library grid's: at ±4 cm the
        // rotations need 2·0.0566 m / h ≤ ~1000 nodes, so n ≤ 703.
        let big = r#"{"grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [1001, 1001]}, "field": {"kind": "sink"}}"#;
        assert_err(
            big,
            &[
                "target.grid.n: must be at most [703, 703] over this region",
                "got [1001, 1001]",
            ],
        );
        let ok = big.replace("1001, 1001", "703, 703");
        assert!(Target::from_json_str(&ok).is_ok());
        assert_err(
            &format!(r#"{{{GRID}, "field": {{"kind": "sink"}}, "weights": [1, 2, 3]}}"#),
            &[
                "target.weights: must be an array of rows, weights[iy][ix]: ny rows of nx numbers",
                "flat list of 3 numbers",
            ],
        );
        assert_err(
            &with_field(r#"{"kind": "sink", "center": [1e300, 0]}"#),
            &["target.field.center[0]: must be in [-1, 1] m, got 1e300"],
        );
    }

    /// The limit [`grid::max_points`] states holds for the library grid
    /// the design really builds (every 15°, no shift), with its margin.
    #[test]
    fn max_points_keeps_the_library_grid_within_its_limit() {
        use crate::basis::symmetry::{source_grid, MARGIN_NODES};
        assert_eq!(MARGIN_NODES, 2, "update LIBRARY_MARGIN in target/grid.rs");
        let angles: Vec<f64> = (0..24).map(|i| (15.0 * i as f64).to_radians()).collect();
        for (x, y) in [
            ([-0.04, 0.04], [-0.04, 0.04]),
            ([0.01, 0.05], [-0.02, 0.0]),
            ([-1.0, 1.0], [0.5, 1.0]),
            ([0.3, 0.31], [0.2, 0.3]),
        ] {
            let n = grid::max_points(x, y);
            let g = Grid { x, y, n };
            assert!(grid::validate_grid(&g, "g").is_ok(), "{g:?}");
            let cover = source_grid(&g, &angles, &[[0.0, 0.0]]);
            assert!(
                cover.n[0] <= crate::field::Grid::MAX_N,
                "{g:?} -> {cover:?}"
            );
            let finer = Grid {
                n: [n[0] + 1, n[1]],
                ..g
            };
            assert!(grid::validate_grid(&finer, "g").is_err() || n[0] == MAX_GRID_N);
        }
    }

    /// Scattered points spanning a small area (one point, four
    /// within 1 cm) give a library grid of a few hundred samples, not the
    /// 63,504 their spacing asked for; the shipped example keeps its grid.
    #[test]
    fn scattered_targets_are_sized_by_their_region() {
        use crate::basis::symmetry::source_grid;
        let angles: Vec<f64> = (0..24).map(|i| (15.0 * i as f64).to_radians()).collect();
        let cover = |pts: &[[f64; 2]]| {
            let g = scattered_grid(pts);
            (g, source_grid(&g, &angles, &[[0.0, 0.0]]).len())
        };
        let (g, n) = cover(&[[0.01, 0.0]]);
        assert_eq!(g.n, [2, 2]);
        assert!(n <= 500, "{n}");
        let four = [[0.0, 0.0], [0.009, 0.0], [0.0, 0.009], [0.009, 0.009]];
        let (g, n) = cover(&four);
        assert!(g.spacing() >= SCATTERED_SPACING - 1e-15, "{g:?}");
        assert!(n <= 500, "{n}");
        let (_, json) = examples().pop().unwrap();
        let t = Target::from_json_str(&json).unwrap();
        let s = t.sample().unwrap();
        let g = scattered_grid(&s.points);
        assert_eq!(g.n, [41, 41]);
        assert!(
            (g.x[0] + 0.04).abs() < 1e-12 && (g.x[1] - 0.04).abs() < 1e-12,
            "{g:?}"
        );
        let far = [[0.99, 0.99], [0.995, 0.99]];
        let (_, n) = cover(&far);
        assert!(n <= crate::field::Grid::MAX_N.pow(2), "{n}");
    }

    #[test]
    fn load_prefixes_file_path() {
        let dir = std::env::temp_dir().join(format!("pf-target-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bad.json");
        std::fs::write(&path, with_field(r#"{"kind": "sinc"}"#)).unwrap();
        let e = Target::load(&path).unwrap_err();
        let msg = e.to_string();
        assert!(msg.starts_with(&path.display().to_string()), "{msg}");
        assert!(msg.contains("target.field.kind"), "{msg}");
        assert_eq!(e.field_path(), Some("target.field.kind"));

        let good = dir.join("sink.json");
        std::fs::write(&good, &examples()[0].1).unwrap();
        assert!(Target::load(&good).is_ok());

        let missing = dir.join("nope.json");
        let msg = Target::load(&missing).unwrap_err().to_string();
        assert!(
            msg.contains("nope.json") && msg.contains("cannot read"),
            "{msg}"
        );

        std::fs::write(&path, "{\"field\": ").unwrap();
        let msg = Target::load(&path).unwrap_err().to_string();
        assert!(
            msg.contains("invalid JSON") && msg.contains("line 1"),
            "{msg}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
