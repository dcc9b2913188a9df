//! Parts with planar extent (`targets/parts/*.json`): a simple polygon, a
//! support distribution and a friction, read by one loader whose errors
//! name the JSON path.
//!
//! ```text
//! {
//!   "name": "bracket",
//!   "polygon": [[0, 0], [0.03, 0], [0.03, 0.005], ...],   vertices (m), body frame, ≥ 3
//!   "support": {"uniform": {"samples": 256}},               the default: uniform over the area
//!            | {"points": {"points": [[x, y], ...], "weights": [w, ...]}}   listed points
//!            | {"unknown": {"contacts": 3}},                 k contact points, weights unknown
//!   "friction": 0.3                                         scene::friction forms; default 0.3
//! }
//! ```
//!
//! **Body frame.** The file's frame is moved so that its origin is the
//! support's weighted centroid (the centre of mass: each support point
//! carries the mass of its weight, [`crate::dynamics::PlanarBody`]); a
//! part's pose (x, y, θ) is that point's position and the angle of the
//! file's x axis. An unknown support is simulated with the uniform one
//! (its centre of mass is the area centroid whatever the contacts are).
//!
//! **Checks** (each an [`Error::Invalid`] at its path, exit 2): at least 3
//! vertices, finite, within ±1 m; no two edges meet except neighbours at
//! their shared vertex (self-intersection, a repeated vertex, an edge
//! folding back); area above 1e-6 of the squared diameter; listed support
//! points inside the polygon (within 1e-9 of its size), weights finite,
//! ≥ 0 and not all zero, one per point; 16..=4096 uniform samples;
//! 1..=64 unknown contacts. `Part::check_fits` refuses a part larger than
//! a target's region.

pub mod family;
mod polygon;
mod symmetry;

pub use polygon::contains;
pub(crate) use polygon::covers;
pub(crate) use polygon::diameter;
pub(crate) use polygon::signed_area;

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::dynamics::{PlanarBody, V2};
use crate::error::{Error, Result};
use crate::input::num;
use crate::scene::FrictionSpec;

/// Default uniform support samples.
pub(crate) const DEFAULT_SAMPLES: usize = 256;
/// Allowed uniform support samples.
pub const SAMPLES: [usize; 2] = [16, 4096];
/// Most listed support points.
pub(crate) const MAX_POINTS: usize = 4096;
/// Most polygon vertices. The simple-polygon check compares every pair of
/// edges (n²/2 pairs: a fraction of a second at the cap, minutes at a
/// hundred thousand vertices), and a part's outline is drawn with tens of
/// vertices (a circle to 0.03 % of its radius with 128).
pub const MAX_VERTICES: usize = 4096;
/// Most unknown contact points.
pub(crate) const MAX_CONTACTS: usize = 64;
/// Largest |vertex coordinate| (m).
pub const EXTENT: f64 = 1.0;
/// An area below this fraction of the squared diameter is zero (a sliver
/// 1 µm thick on 1 m long).
pub(crate) const ZERO_AREA: f64 = 1e-6;

/// The support distribution as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Support {
    /// Uniform over the area, sampled by about `samples` grid cells.
    Uniform {
        /// Support points (approximately; grid cells inside the polygon).
        #[serde(default = "default_samples")]
        samples: usize,
    },
    /// Listed points (m, file frame) with weights (equal when omitted).
    Points {
        /// Support points.
        points: Vec<[f64; 2]>,
        /// One non-negative weight per point, not all zero.
        #[serde(default)]
        weights: Option<Vec<f64>>,
    },
    /// Unknown: the part rests on `contacts` points anywhere in it, with
    /// unknown weights.
    Unknown {
        /// Number of contact points k.
        contacts: usize,
    },
}

fn default_samples() -> usize {
    DEFAULT_SAMPLES
}

impl Default for Support {
    fn default() -> Self {
        Support::Uniform {
            samples: DEFAULT_SAMPLES,
        }
    }
}

fn default_friction() -> FrictionSpec {
    FrictionSpec::uniform(0.3)
}

/// A part file as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct PartFile {
    /// Name (used for output folders).
    pub name: String,
    /// Vertices (m), either orientation.
    pub polygon: Vec<[f64; 2]>,
    /// Support distribution.
    #[serde(default)]
    pub support: Support,
    /// Friction between part and plate.
    #[serde(default = "default_friction")]
    pub friction: FrictionSpec,
}

/// A validated part in its body frame (origin at the centre of mass).
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Name.
    pub name: String,
    /// Vertices, counter-clockwise, body frame (m).
    pub polygon: Vec<V2>,
    /// The support as written.
    pub support: Support,
    /// The rigid body the planar simulator plays (support points and weights).
    pub body: PlanarBody,
    /// Friction.
    pub friction: FrictionSpec,
    /// Where the body origin lies in the file's frame (m).
    pub origin: V2,
}

impl Part {
    /// Reads and validates a part from JSON text; errors name the JSON
    /// path (`part.polygon: ...`).
    ///
    /// ```
    /// use platefield::part::Part;
    /// let p = Part::from_json_str(
    ///     r#"{"name": "r", "polygon": [[-0.01, -0.0025], [0.01, -0.0025], [0.01, 0.0025], [-0.01, 0.0025]]}"#,
    /// )?;
    /// assert_eq!(p.body.points().len(), 256); // a 32 × 8 grid
    /// let bad = Part::from_json_str(r#"{"name": "t", "polygon": [[0, 0], [1, 0]]}"#);
    /// assert!(bad.unwrap_err().to_string().starts_with("part.polygon:"));
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn from_json_str(text: &str) -> Result<Part> {
        let file: PartFile =
            crate::input::from_str(text, "part").map_err(|e| Error::invalid(e.path, e.message))?;
        Part::new(file)
    }

    /// Reads a part file; errors are prefixed with the file path.
    pub fn load(path: &Path) -> Result<Part> {
        let text = crate::input::read_input(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        Part::from_json_str(&text).map_err(|e| match e {
            Error::Invalid { field, message } => Error::Invalid {
                field: format!("{}: {field}", path.display()),
                message,
            },
            other => other,
        })
    }

    /// Validates `file` and builds its body (module docs).
    pub(crate) fn new(file: PartFile) -> Result<Part> {
        file.friction.validate("part.friction")?;
        let raw = check_polygon(&file.polygon)?;
        let (points, weights) = support_points(&file.support, &raw)?;
        let (body, origin) = PlanarBody::centred(&points, &weights);
        let mut polygon: Vec<V2> = raw.iter().map(|p| p - origin).collect();
        if signed_area(&polygon) < 0.0 {
            polygon.reverse();
        }
        Ok(Part {
            name: file.name,
            polygon,
            support: file.support,
            body,
            friction: file.friction,
            origin,
        })
    }

    /// The part's diameter (its largest extent, m).
    ///
    /// ```
    /// use platefield::part::Part;
    /// let p = Part::from_json_str(r#"{"name": "r", "polygon": [[0, 0], [0.03, 0], [0.03, 0.04], [0, 0.04]]}"#)?;
    /// assert!((p.size() - 0.05).abs() < 1e-15); // the diagonal
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn size(&self) -> f64 {
        diameter(&self.polygon)
    }

    /// Radius of the part about its origin (m): how far a vertex reaches.
    pub fn radius(&self) -> f64 {
        self.polygon.iter().map(|p| p.norm()).fold(0.0, f64::max)
    }

    /// Refuses a part larger than a target region of sides `width` ×
    /// `height` (m): its diameter must fit in the smaller side. `path`
    /// names the region.
    pub(crate) fn check_fits(&self, width: f64, height: f64, path: &str) -> Result<()> {
        let side = width.min(height);
        if self.size() > side {
            return Err(Error::invalid(
                "part.polygon",
                format!(
                    "the part ({} m across) is larger than the target region {path} ({} × {} m); it must fit in the smaller side",
                    num(self.size()),
                    num(width),
                    num(height)
                ),
            ));
        }
        Ok(())
    }

    /// The body resampled by about `samples` uniform support points, with
    /// its centre of mass in the part's body frame (a cheaper body for
    /// played drops, `crate::pose::DropPlay`); `None` unless the support is
    /// uniform (or unknown, simulated as uniform) with more points than that.
    ///
    /// ```
    /// use platefield::part::Part;
    /// let p = Part::load(std::path::Path::new("targets/parts/rectangle.json"))?;
    /// let (body, offset) = p.coarse_body(36).unwrap();
    /// assert_eq!(body.points().len(), 36); // a 12 × 3 grid
    /// assert!(offset.norm() < 1e-15); // symmetric: the same centre of mass
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn coarse_body(&self, samples: usize) -> Option<(PlanarBody, V2)> {
        let uniform = matches!(
            self.support,
            Support::Uniform { .. } | Support::Unknown { .. }
        );
        if !uniform || self.body.points().len() <= samples {
            return None;
        }
        let (points, weights): (Vec<V2>, Vec<f64>) = polygon::uniform_grid(&self.polygon, samples)
            .into_iter()
            .unzip();
        (!points.is_empty()).then(|| PlanarBody::centred(&points, &weights))
    }

    /// Vertices in the plate frame at pose (r, θ).
    pub fn placed(&self, r: V2, theta: f64) -> Vec<V2> {
        let (s, c) = theta.sin_cos();
        self.polygon
            .iter()
            .map(|p| r + V2::new(c * p.x - s * p.y, s * p.x + c * p.y))
            .collect()
    }
}

/// The polygon checked (module docs), as vectors.
fn check_polygon(raw: &[[f64; 2]]) -> Result<Vec<V2>> {
    if raw.len() < 3 {
        return Err(Error::invalid(
            "part.polygon",
            format!("needs at least 3 vertices, got {}", raw.len()),
        ));
    }
    if raw.len() > MAX_VERTICES {
        return Err(Error::invalid(
            "part.polygon",
            format!(
                "has {} vertices, more than the {MAX_VERTICES} a part's outline may have (its simplicity check takes n²/2 edge pairs)",
                raw.len()
            ),
        ));
    }
    for (i, p) in raw.iter().enumerate() {
        for (k, v) in p.iter().enumerate() {
            if !(v.is_finite() && v.abs() <= EXTENT) {
                return Err(Error::invalid(
                    format!("part.polygon[{i}][{k}]"),
                    format!(
                        "must be a finite coordinate in [-{EXTENT}, {EXTENT}] m, got {}",
                        num(*v)
                    ),
                ));
            }
        }
    }
    let v: Vec<V2> = raw.iter().map(|p| V2::new(p[0], p[1])).collect();
    if let Some((i, j)) = polygon::crossing(&v) {
        return Err(Error::invalid(
            "part.polygon",
            format!("is not a simple polygon: edge {i} (vertex {i} to the next) meets edge {j}; vertices must trace the outline once without crossing or repeating"),
        ));
    }
    let area = signed_area(&v).abs();
    if area <= ZERO_AREA * diameter(&v).powi(2) {
        return Err(Error::invalid(
            "part.polygon",
            format!(
                "has zero area ({} m²); a part needs an outline enclosing an area",
                num(area)
            ),
        ));
    }
    Ok(v)
}

/// Support points and weights (file frame) of `support` on polygon `v`.
fn support_points(support: &Support, v: &[V2]) -> Result<(Vec<V2>, Vec<f64>)> {
    match support {
        Support::Uniform { samples } => uniform(v, *samples, "part.support.uniform.samples"),
        Support::Unknown { contacts } => {
            if !(1..=MAX_CONTACTS).contains(contacts) {
                return Err(Error::invalid(
                    "part.support.unknown.contacts",
                    format!("must be in 1..={MAX_CONTACTS} contact points, got {contacts}"),
                ));
            }
            uniform(v, DEFAULT_SAMPLES, "part.support")
        }
        Support::Points { points, weights } => listed(v, points, weights.as_deref()),
    }
}

fn uniform(v: &[V2], samples: usize, path: &str) -> Result<(Vec<V2>, Vec<f64>)> {
    if !(SAMPLES[0]..=SAMPLES[1]).contains(&samples) {
        return Err(Error::invalid(
            path,
            format!(
                "must be in {}..={} support points, got {samples}",
                SAMPLES[0], SAMPLES[1]
            ),
        ));
    }
    let (points, weights): (Vec<V2>, Vec<f64>) =
        polygon::uniform_grid(v, samples).into_iter().unzip();
    if points.is_empty() {
        return Err(Error::invalid(
            "part.polygon",
            "is too thin for its support grid: no grid cell centre falls inside",
        ));
    }
    Ok((points, weights))
}

fn listed(v: &[V2], points: &[[f64; 2]], weights: Option<&[f64]>) -> Result<(Vec<V2>, Vec<f64>)> {
    let base = "part.support.points";
    if points.is_empty() || points.len() > MAX_POINTS {
        return Err(Error::invalid(
            format!("{base}.points"),
            format!("must list 1..={MAX_POINTS} points, got {}", points.len()),
        ));
    }
    let tol = 1e-9 * diameter(v);
    let pts: Vec<V2> = points.iter().map(|p| V2::new(p[0], p[1])).collect();
    for (i, p) in pts.iter().enumerate() {
        if !(p.x.is_finite() && p.y.is_finite() && covers(v, p, tol)) {
            return Err(Error::invalid(
                format!("{base}.points[{i}]"),
                format!(
                    "[{}, {}] lies outside the part's polygon; support points must be on the part",
                    num(p.x),
                    num(p.y)
                ),
            ));
        }
    }
    let w = match weights {
        None => vec![1.0; pts.len()],
        Some(w) => w.to_vec(),
    };
    if w.len() != pts.len() {
        return Err(Error::invalid(
            format!("{base}.weights"),
            format!(
                "must give one weight per point ({}), got {}",
                pts.len(),
                w.len()
            ),
        ));
    }
    for (i, x) in w.iter().enumerate() {
        if !(x.is_finite() && *x >= 0.0) {
            return Err(Error::invalid(
                format!("{base}.weights[{i}]"),
                format!("must be a finite weight ≥ 0, got {}", num(*x)),
            ));
        }
    }
    if w.iter().all(|x| *x == 0.0) {
        return Err(Error::invalid(
            format!("{base}.weights"),
            "are all zero; at least one support point must carry the part",
        ));
    }
    // Only the weights' ratios matter (they are fractions of the part's
    // mass): scaled by the largest, so that their sum neither overflows
    // (three weights of 1e308) nor the centre of mass underflows (three
    // of 5e-324).
    let largest = w.iter().copied().fold(0.0, f64::max);
    Ok((pts, w.iter().map(|x| x / largest).collect()))
}

#[cfg(test)]
mod tests;
