//! Field specifications (`target.field`) and their evaluation.
//!
//! See the [module documentation](crate::request) for the JSON form and the
//! formula of every kind.

use serde::{Deserialize, Serialize};

use crate::request::error::{
    check_finite, check_finite2, check_range, check_scale, show, TargetError,
};
use crate::request::interpolant::SampledInterpolant;

/// Reference length `L` (metres) of the `squeeze_trans` transport term:
/// `transport = 1` means the transport speed equals the squeeze speed found
/// at distance `L` = 1 cm from the line.
pub const TRANSPORT_LENGTH: f64 = 0.01;

/// Default `width` (metres) of a `jet`.
pub const DEFAULT_JET_WIDTH: f64 = 0.01;
/// Narrowest jet (m): below about 1e-162 m the Gaussian's `2 w²`
/// underflows to 0 and the field on the axis is 0/0 (NaN).
pub const MIN_JET_WIDTH: f64 = 1e-6;

/// Number of nearest samples used by inverse-distance interpolation.
pub const IDW_NEIGHBORS: usize = 8;

/// Distance (metres) below which a query point counts as *at* a sample
/// point (`sampled` interpolation) or *at* the centre (`circle`).
pub const COINCIDENT: f64 = 1e-12;

/// Allowed |strength| of a field: non-zero, within `[STRENGTH[0],
/// STRENGTH[1]]` (1/s for the linear fields, m/s for the bounded ones). A
/// zero or vanishing strength asks for no field at all.
pub const STRENGTH: [f64; 2] = [1e-6, 1e6];
/// Allowed |weight| of a `sum` term: non-zero (a zero term is dropped from
/// the file instead), within `[WEIGHT[0], WEIGHT[1]]`.
pub const WEIGHT: [f64; 2] = [1e-6, 1e6];
/// Largest |coordinate| (m) of centres, offsets, widths, sample points,
/// grid corners and mask regions: the plate's own scale.
pub const EXTENT: f64 = 1.0;
/// Largest |angle| or |direction| (degrees).
pub const ANGLE: f64 = 3600.0;
/// Largest |ratio| (`whirlpool` rotation, `squeeze_trans` transport).
pub const RATIO: f64 = 1e6;
/// Largest |component| of a `sampled` vector (m/s).
pub const SPEED: f64 = 1e6;
/// Most terms in one `sum`.
pub const MAX_TERMS: usize = 1000;
/// Most points of a `sampled` field.
pub const MAX_SAMPLED_POINTS: usize = 100_000;

/// All accepted values of `"kind"`, in documentation order.
pub const FIELD_KINDS: &[&str] = &[
    "sink",
    "source",
    "line_sink",
    "saddle",
    "whirlpool",
    "circle",
    "scaled_circle",
    "trans",
    "squeeze_trans",
    "jet",
    "sum",
    "sampled",
];

fn one() -> f64 {
    1.0
}

impl<'de> Deserialize<'de> for FieldSpec {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        crate::input::tagged(d, "kind", FIELD_KINDS, |kind, b| {
            Some(match kind {
                "sum" => FieldSpec::Sum {
                    terms: b.get("terms"),
                },
                "sampled" => FieldSpec::Sampled {
                    points: b.get("points"),
                    vectors: b.get("vectors"),
                    interpolation: b.or("interpolation", Interpolation::Idw),
                },
                _ => {
                    let center = b.or("center", [0.0; 2]);
                    let strength = b.or("strength", 1.0);
                    analytic(kind, center, strength, b)
                }
            })
        })
    }
}

/// An analytic field of `kind` with its own keys read from `b` (defaults
/// as documented on each variant).
fn analytic(kind: &str, center: [f64; 2], strength: f64, b: &mut crate::input::Body) -> FieldSpec {
    match kind {
        "source" => FieldSpec::Source { center, strength },
        "line_sink" => FieldSpec::LineSink {
            center,
            strength,
            angle: b.or("angle", 0.0),
            offset: b.or("offset", 0.0),
        },
        "saddle" => FieldSpec::Saddle {
            center,
            strength,
            angle: b.or("angle", 0.0),
        },
        "whirlpool" => FieldSpec::Whirlpool {
            center,
            strength,
            rotation: b.or("rotation", 1.0),
        },
        "circle" => FieldSpec::Circle { center, strength },
        "scaled_circle" => FieldSpec::ScaledCircle { center, strength },
        "trans" => FieldSpec::Trans {
            center,
            strength,
            direction: b.or("direction", 0.0),
        },
        "squeeze_trans" => FieldSpec::SqueezeTrans {
            center,
            strength,
            angle: b.or("angle", 0.0),
            transport: b.or("transport", 1.0),
        },
        "jet" => FieldSpec::Jet {
            center,
            strength,
            direction: b.or("direction", 0.0),
            width: b.or("width", DEFAULT_JET_WIDTH),
        },
        _ => FieldSpec::Sink { center, strength },
    }
}

/// A requested velocity field `f(p)` (m/s) on the plate, `p` in metres.
///
/// Serialized internally tagged by `"kind"`; read by
/// [`FieldSpec::deserialize`], which applies the defaults, rejects unknown
/// keys and names the JSON path of every error.
/// Throughout, `d = p - center`, `s = strength`, angles are in degrees
/// counter-clockwise from +x, `t̂ = (cos a, sin a)` is the direction given by
/// the angle and `n = (-sin a, cos a)` its left normal.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum FieldSpec {
    /// `f = -s d` (s in 1/s).
    Sink {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
    },
    /// `f = +s d` (s in 1/s).
    Source {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
    },
    /// Sink onto a line: `f = -s (n·d - offset) n` (s in 1/s).
    LineSink {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
        /// Direction of the line in degrees (default 0: line along x).
        angle: f64,
        /// Signed distance (metres) of the line from `center` along `n`
        /// (default 0).
        offset: f64,
    },
    /// `f = s (-(t̂·d) t̂ + (n·d) n)`: contracts along `angle`, expands along
    /// the normal; `angle = 0` gives `s (-dx, +dy)` (s in 1/s).
    Saddle {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
        /// Direction of the contracting axis in degrees (default 0).
        angle: f64,
    },
    /// Sink plus rotation: `f = s (-d + ρ (-dy, dx))` (s in 1/s;
    /// counter-clockwise for ρ > 0).
    Whirlpool {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
        /// Ratio ρ of rotation to sink (default 1).
        rotation: f64,
    },
    /// Unit-speed rotation: `f = s (-dy, dx) / |d|`, zero at the centre
    /// (s in m/s).
    Circle {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Speed `s` in m/s (default 1).
        strength: f64,
    },
    /// Rigid rotation: `f = s (-dy, dx)` (s in 1/s = angular rate in rad/s).
    ScaledCircle {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
    },
    /// Uniform transport: `f = s (cos a, sin a)` (s in m/s).
    Trans {
        /// Accepted for uniformity; has no effect on a uniform field.
        center: [f64; 2],
        /// Speed `s` in m/s (default 1).
        strength: f64,
        /// Direction `a` in degrees (default 0).
        direction: f64,
    },
    /// Line sink along the line through `center` with direction `angle`,
    /// plus transport along it:
    /// `f = s (-(n·d) n + transport · L t̂)` with `L` =
    /// [`TRANSPORT_LENGTH`] = 0.01 m (s in 1/s).
    SqueezeTrans {
        /// Centre `c` in metres (default `[0, 0]`).
        center: [f64; 2],
        /// Scale `s` in 1/s (default 1).
        strength: f64,
        /// Direction of the line (and of the transport) in degrees
        /// (default 0).
        angle: f64,
        /// Ratio `ρ_t` of transport speed to the squeeze speed at 1 cm from
        /// the line (default 1; negative reverses the transport).
        transport: f64,
    },
    /// Localised transport along the line through `center` with direction
    /// `direction`: `f = s exp(-(n·d)² / (2 width²)) t̂` (s in m/s, the
    /// speed on the line).
    Jet {
        /// Centre `c` (a point on the jet's axis) in metres (default
        /// `[0, 0]`).
        center: [f64; 2],
        /// Peak speed `s` in m/s (default 1).
        strength: f64,
        /// Direction of the jet in degrees (default 0).
        direction: f64,
        /// Gaussian standard deviation across the jet in metres, `> 0`
        /// (default [`DEFAULT_JET_WIDTH`] = 0.01 m).
        width: f64,
    },
    /// Weighted sum `f = Σ wᵢ fᵢ` of other fields (at least one term).
    Sum {
        /// The terms.
        terms: Vec<SumTerm>,
    },
    /// A field given by samples (e.g. exported from MATLAB/numpy),
    /// evaluated elsewhere by [`Interpolation`].
    Sampled {
        /// Sample positions in metres.
        points: Vec<[f64; 2]>,
        /// Field values (m/s) at `points` (same length).
        vectors: Vec<[f64; 2]>,
        /// How to evaluate between samples (default `"idw"`).
        interpolation: Interpolation,
    },
}

/// One term `{"weight": w, "field": {...}}` of a `sum` field.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SumTerm {
    /// Weight `w` (any finite number; default 1).
    #[serde(default = "one")]
    pub weight: f64,
    /// The term's field.
    pub field: FieldSpec,
}

/// Interpolation of a `sampled` field at points that are not samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Inverse-distance-squared (Shepard) weighting of the
    /// [`IDW_NEIGHBORS`] nearest samples; exact at the samples.
    #[default]
    Idw,
    /// Value of the nearest sample (ties: first in the list).
    Nearest,
}

/// Unit direction vector of an angle in degrees.
fn dir(deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [c, s]
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

impl FieldSpec {
    /// The `"kind"` string of this field.
    pub(crate) fn kind(&self) -> &'static str {
        match self {
            FieldSpec::Sink { .. } => "sink",
            FieldSpec::Source { .. } => "source",
            FieldSpec::LineSink { .. } => "line_sink",
            FieldSpec::Saddle { .. } => "saddle",
            FieldSpec::Whirlpool { .. } => "whirlpool",
            FieldSpec::Circle { .. } => "circle",
            FieldSpec::ScaledCircle { .. } => "scaled_circle",
            FieldSpec::Trans { .. } => "trans",
            FieldSpec::SqueezeTrans { .. } => "squeeze_trans",
            FieldSpec::Jet { .. } => "jet",
            FieldSpec::Sum { .. } => "sum",
            FieldSpec::Sampled { .. } => "sampled",
        }
    }

    /// The centre (m) and strength of an analytic field; `None` for a sum
    /// or a sampled field.
    pub(crate) fn center_strength(&self) -> Option<([f64; 2], f64)> {
        match *self {
            FieldSpec::Sink { center, strength }
            | FieldSpec::Source { center, strength }
            | FieldSpec::Circle { center, strength }
            | FieldSpec::ScaledCircle { center, strength }
            | FieldSpec::LineSink {
                center, strength, ..
            }
            | FieldSpec::Saddle {
                center, strength, ..
            }
            | FieldSpec::Whirlpool {
                center, strength, ..
            }
            | FieldSpec::Trans {
                center, strength, ..
            }
            | FieldSpec::SqueezeTrans {
                center, strength, ..
            }
            | FieldSpec::Jet {
                center, strength, ..
            } => Some((center, strength)),
            FieldSpec::Sum { .. } | FieldSpec::Sampled { .. } => None,
        }
    }

    /// Evaluates the field (m/s) at `p` (metres).
    ///
    /// Assumes the spec is valid (see `FieldSpec::validate`); an empty
    /// `sampled` field evaluates to zero.
    pub fn eval(&self, p: [f64; 2]) -> [f64; 2] {
        let rel = |c: [f64; 2]| [p[0] - c[0], p[1] - c[1]];
        match self {
            FieldSpec::Sink { center, strength } => {
                let d = rel(*center);
                [-strength * d[0], -strength * d[1]]
            }
            FieldSpec::Source { center, strength } => {
                let d = rel(*center);
                [strength * d[0], strength * d[1]]
            }
            FieldSpec::LineSink {
                center,
                strength,
                angle,
                offset,
            } => {
                let d = rel(*center);
                let t = dir(*angle);
                let n = [-t[1], t[0]];
                let k = -strength * (dot(n, d) - offset);
                [k * n[0], k * n[1]]
            }
            FieldSpec::Saddle {
                center,
                strength,
                angle,
            } => {
                let d = rel(*center);
                let t = dir(*angle);
                let n = [-t[1], t[0]];
                let u = dot(t, d);
                let v = dot(n, d);
                [
                    strength * (-u * t[0] + v * n[0]),
                    strength * (-u * t[1] + v * n[1]),
                ]
            }
            FieldSpec::Whirlpool {
                center,
                strength,
                rotation,
            } => {
                let d = rel(*center);
                [
                    strength * (-d[0] - rotation * d[1]),
                    strength * (-d[1] + rotation * d[0]),
                ]
            }
            FieldSpec::Circle { center, strength } => {
                let d = rel(*center);
                let r = d[0].hypot(d[1]);
                if r <= COINCIDENT {
                    [0.0, 0.0]
                } else {
                    [-strength * d[1] / r, strength * d[0] / r]
                }
            }
            FieldSpec::ScaledCircle { center, strength } => {
                let d = rel(*center);
                [-strength * d[1], strength * d[0]]
            }
            FieldSpec::Trans {
                strength,
                direction,
                ..
            } => {
                let t = dir(*direction);
                [strength * t[0], strength * t[1]]
            }
            FieldSpec::SqueezeTrans {
                center,
                strength,
                angle,
                transport,
            } => {
                let d = rel(*center);
                let t = dir(*angle);
                let n = [-t[1], t[0]];
                let v = dot(n, d);
                let tr = transport * TRANSPORT_LENGTH;
                [
                    strength * (-v * n[0] + tr * t[0]),
                    strength * (-v * n[1] + tr * t[1]),
                ]
            }
            FieldSpec::Jet {
                center,
                strength,
                direction,
                width,
            } => {
                let d = rel(*center);
                let t = dir(*direction);
                let n = [-t[1], t[0]];
                let v = dot(n, d);
                let k = strength * (-(v * v) / (2.0 * width * width)).exp();
                [k * t[0], k * t[1]]
            }
            FieldSpec::Sum { terms } => {
                let mut f = [0.0, 0.0];
                for term in terms {
                    let g = term.field.eval(p);
                    f[0] += term.weight * g[0];
                    f[1] += term.weight * g[1];
                }
                f
            }
            FieldSpec::Sampled {
                points,
                vectors,
                interpolation,
            } => interpolate(points, vectors, *interpolation, p),
        }
    }

    /// The [`SampledInterpolant`] of a `sampled` field's samples (weights
    /// computed once, O(1) per evaluation); `None` for every other kind.
    pub(crate) fn interpolant(&self) -> Option<SampledInterpolant> {
        match self {
            FieldSpec::Sampled {
                points, vectors, ..
            } => Some(SampledInterpolant::new(points, vectors)),
            _ => None,
        }
    }

    /// Checks every parameter against its range (the constants of this
    /// module); `path` is the JSON path of this field object (e.g.
    /// `target.field`), used as the prefix of error messages.
    pub(crate) fn validate(&self, path: &str) -> Result<(), TargetError> {
        let at = |key: &str| format!("{path}.{key}");
        let unit = match self {
            FieldSpec::Circle { .. } | FieldSpec::Trans { .. } | FieldSpec::Jet { .. } => " m/s",
            _ => " 1/s",
        };
        let center_strength = |center: &[f64; 2], strength: &f64| {
            check_finite2(&at("center"), *center)?;
            for (i, c) in center.iter().enumerate() {
                check_range(&format!("{path}.center[{i}]"), *c, -EXTENT, EXTENT, " m")?;
            }
            check_finite(&at("strength"), *strength)?;
            check_scale(&at("strength"), *strength, STRENGTH, unit)
        };
        let param = |name: &str, v: f64, max: f64, unit: &str| {
            check_finite(&at(name), v)?;
            check_range(&at(name), v, -max, max, unit)
        };
        if let Some((center, strength)) = self.center_strength() {
            center_strength(&center, &strength)?;
        }
        match self {
            FieldSpec::Sink { .. }
            | FieldSpec::Source { .. }
            | FieldSpec::Circle { .. }
            | FieldSpec::ScaledCircle { .. } => Ok(()),
            FieldSpec::LineSink { angle, offset, .. } => {
                param("angle", *angle, ANGLE, "°")?;
                param("offset", *offset, EXTENT, " m")
            }
            FieldSpec::Saddle { angle, .. } => param("angle", *angle, ANGLE, "°"),
            FieldSpec::Whirlpool { rotation, .. } => param("rotation", *rotation, RATIO, ""),
            FieldSpec::Trans { direction, .. } => param("direction", *direction, ANGLE, "°"),
            FieldSpec::SqueezeTrans {
                angle, transport, ..
            } => {
                param("angle", *angle, ANGLE, "°")?;
                param("transport", *transport, RATIO, "")
            }
            FieldSpec::Jet {
                direction, width, ..
            } => {
                param("direction", *direction, ANGLE, "°")?;
                check_finite(&at("width"), *width)?;
                if !(MIN_JET_WIDTH..=EXTENT).contains(width) {
                    return Err(TargetError::invalid(
                        at("width"),
                        format!(
                            "must be in [{}, {EXTENT}] m, got {}",
                            show(MIN_JET_WIDTH),
                            show(*width)
                        ),
                    ));
                }
                Ok(())
            }
            FieldSpec::Sum { terms } => {
                if terms.is_empty() || terms.len() > MAX_TERMS {
                    return Err(TargetError::invalid(
                        at("terms"),
                        format!("must contain 1..={MAX_TERMS} terms, got {}", terms.len()),
                    ));
                }
                for (i, term) in terms.iter().enumerate() {
                    let w = format!("{path}.terms[{i}].weight");
                    check_finite(&w, term.weight)?;
                    check_scale(&w, term.weight, WEIGHT, "")?;
                    term.field.validate(&format!("{path}.terms[{i}].field"))?;
                }
                Ok(())
            }
            FieldSpec::Sampled {
                points, vectors, ..
            } => {
                if points.is_empty() || points.len() > MAX_SAMPLED_POINTS {
                    return Err(TargetError::invalid(
                        at("points"),
                        format!(
                            "must contain 1..={MAX_SAMPLED_POINTS} points, got {}",
                            points.len()
                        ),
                    ));
                }
                if points.len() != vectors.len() {
                    return Err(TargetError::invalid(
                        at("points"),
                        format!("{} points but {} vectors", points.len(), vectors.len()),
                    ));
                }
                for (i, p) in points.iter().enumerate() {
                    let pp = format!("{path}.points[{i}]");
                    check_finite2(&pp, *p)?;
                    for (k, c) in p.iter().enumerate() {
                        check_range(&format!("{pp}[{k}]"), *c, -EXTENT, EXTENT, " m")?;
                    }
                }
                for (i, v) in vectors.iter().enumerate() {
                    let vp = format!("{path}.vectors[{i}]");
                    check_finite2(&vp, *v)?;
                    for (k, c) in v.iter().enumerate() {
                        check_range(&format!("{vp}[{k}]"), *c, -SPEED, SPEED, " m/s")?;
                    }
                }
                check_distinct_points(path, points, vectors)
            }
        }
    }
}

/// Every sample point of a sampled field appears once. A repeat with a
/// different vector is two answers for one place; a repeat with the same
/// vector is refused as well, since it would count twice among the
/// neighbours that [`Interpolation::Idw`] averages and so bend the field
/// around it. The error names the repeat (`{path}.points[j]`) and the
/// sample it repeats.
fn check_distinct_points(
    path: &str,
    points: &[[f64; 2]],
    vectors: &[[f64; 2]],
) -> Result<(), TargetError> {
    // Keyed by the coordinates' bits, with −0 read as +0.
    let key = |p: &[f64; 2]| p.map(|c| (c + 0.0).to_bits());
    let mut seen = std::collections::HashMap::with_capacity(points.len());
    for (j, p) in points.iter().enumerate() {
        let Some(&i) = seen.get(&key(p)) else {
            seen.insert(key(p), j);
            continue;
        };
        let num = crate::input::num;
        let [(a, b), (c, d)] = [vectors[i], vectors[j]].map(|v| (num(v[0]), num(v[1])));
        let why = if vectors[i] == vectors[j] {
            "with the same vector (remove the repeat)".to_string()
        } else {
            format!("with a different vector: [{a}, {b}] there, [{c}, {d}] here")
        };
        return Err(TargetError::invalid(
            format!("{path}.points[{j}]"),
            format!(
                "repeats points[{i}] [{}, {}] {why}; each sample point must appear once",
                num(p[0]),
                num(p[1])
            ),
        ));
    }
    Ok(())
}

/// Interpolates a sampled field at `p` (see [`Interpolation`]).
fn interpolate(
    points: &[[f64; 2]],
    vectors: &[[f64; 2]],
    method: Interpolation,
    p: [f64; 2],
) -> [f64; 2] {
    let k = match method {
        Interpolation::Idw => IDW_NEIGHBORS,
        Interpolation::Nearest => 1,
    };
    // The k nearest samples as (squared distance, index), sorted ascending;
    // strict comparisons keep the earliest sample on ties.
    let mut best: Vec<(f64, usize)> = Vec::with_capacity(k + 1);
    let n = points.len().min(vectors.len());
    for (i, q) in points[..n].iter().enumerate() {
        let dx = p[0] - q[0];
        let dy = p[1] - q[1];
        let d2 = dx * dx + dy * dy;
        if d2 <= COINCIDENT * COINCIDENT {
            return vectors[i];
        }
        if best.len() < k || d2 < best[best.len() - 1].0 {
            let pos = best.partition_point(|&(e, _)| e <= d2);
            best.insert(pos, (d2, i));
            best.truncate(k);
        }
    }
    let (mut sw, mut fx, mut fy) = (0.0, 0.0, 0.0);
    for &(d2, i) in &best {
        let w = 1.0 / d2;
        sw += w;
        fx += w * vectors[i][0];
        fy += w * vectors[i][1];
    }
    if sw > 0.0 {
        [fx / sw, fy / sw]
    } else {
        [0.0, 0.0]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 2], b: [f64; 2]) -> bool {
        (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12
    }

    fn rot(v: [f64; 2], deg: f64) -> [f64; 2] {
        let (s, c) = deg.to_radians().sin_cos();
        [c * v[0] - s * v[1], s * v[0] + c * v[1]]
    }

    const PROBES: [[f64; 2]; 5] = [
        [0.01, 0.02],
        [-0.03, 0.005],
        [0.0, 0.0],
        [0.04, -0.04],
        [-0.002, -0.017],
    ];

    #[test]
    fn sink_source_whirlpool_formulas() {
        let c = [0.01, -0.01];
        let sink = FieldSpec::Sink {
            center: c,
            strength: 2.0,
        };
        assert!(close(sink.eval([0.02, 0.0]), [-0.02, -0.02]));
        let source = FieldSpec::Source {
            center: c,
            strength: 2.0,
        };
        assert!(close(source.eval([0.02, 0.0]), [0.02, 0.02]));
        let w = FieldSpec::Whirlpool {
            center: [0.0, 0.0],
            strength: 1.0,
            rotation: 1.0,
        };
        // d = (1, 0): -d + (−0, 1) = (−1, 1)
        assert!(close(w.eval([1.0, 0.0]), [-1.0, 1.0]));
    }

    #[test]
    fn saddle_default_axes() {
        let s = FieldSpec::Saddle {
            center: [0.0, 0.0],
            strength: 1.0,
            angle: 0.0,
        };
        assert!(close(s.eval([0.01, 0.02]), [-0.01, 0.02]));
    }

    #[test]
    fn line_sink_90_is_rotation_of_0() {
        let make = |angle| FieldSpec::LineSink {
            center: [0.003, -0.002],
            strength: 1.5,
            angle,
            offset: 0.004,
        };
        let f0 = make(0.0);
        let f90 = make(90.0);
        let c = [0.003, -0.002];
        for p in PROBES {
            // Rotate p about the centre by 90°, compare with the rotated value.
            let d = [p[0] - c[0], p[1] - c[1]];
            let rd = rot(d, 90.0);
            let q = [c[0] + rd[0], c[1] + rd[1]];
            assert!(close(f90.eval(q), rot(f0.eval(p), 90.0)), "{p:?}");
        }
        // Angle 0: line along x at y = c_y + offset, flow is purely along y.
        let v = f0.eval([0.02, 0.0]);
        assert!(v[0].abs() < 1e-15);
        assert!((v[1] - (-1.5 * (0.002 - 0.004))).abs() < 1e-15);
    }

    #[test]
    fn circle_has_unit_magnitude_off_centre() {
        let f = FieldSpec::Circle {
            center: [0.01, 0.0],
            strength: 1.0,
        };
        for p in PROBES {
            let v = f.eval(p);
            assert!((v[0].hypot(v[1]) - 1.0).abs() < 1e-12, "{p:?}");
            // Perpendicular to the radius, counter-clockwise.
            let d = [p[0] - 0.01, p[1]];
            assert!(dot(v, d).abs() < 1e-12);
            assert!(d[0] * v[1] - d[1] * v[0] > 0.0);
        }
        assert_eq!(f.eval([0.01, 0.0]), [0.0, 0.0]);
        let sc = FieldSpec::ScaledCircle {
            center: [0.0, 0.0],
            strength: 2.0,
        };
        assert!(close(sc.eval([0.01, 0.0]), [0.0, 0.02]));
    }

    #[test]
    fn trans_squeeze_trans_and_jet() {
        let t = FieldSpec::Trans {
            center: [0.0, 0.0],
            strength: 0.02,
            direction: 90.0,
        };
        assert!(close(t.eval([0.03, 0.01]), [0.0, 0.02]));
        let st = FieldSpec::SqueezeTrans {
            center: [0.0, 0.0],
            strength: 1.0,
            angle: 0.0,
            transport: 1.0,
        };
        // 1 cm from the line: squeeze speed 0.01 = transport speed 0.01.
        assert!(close(st.eval([0.0, 0.01]), [0.01, -0.01]));
        assert!(close(st.eval([0.03, 0.0]), [0.01, 0.0]));
        let jet = FieldSpec::Jet {
            center: [0.0, 0.0],
            strength: 0.02,
            direction: 0.0,
            width: 0.01,
        };
        assert!(close(jet.eval([0.03, 0.0]), [0.02, 0.0]));
        let v = jet.eval([0.0, 0.01]);
        assert!((v[0] - 0.02 * (-0.5f64).exp()).abs() < 1e-15 && v[1] == 0.0);
    }

    #[test]
    fn sum_is_weighted_sum_of_terms() {
        let a = FieldSpec::Sink {
            center: [0.01, 0.0],
            strength: 1.0,
        };
        let b = FieldSpec::Jet {
            center: [0.0, 0.01],
            strength: 0.02,
            direction: 30.0,
            width: 0.005,
        };
        let c = FieldSpec::Circle {
            center: [0.0, 0.0],
            strength: 0.01,
        };
        let sum = FieldSpec::Sum {
            terms: vec![
                SumTerm {
                    weight: 0.5,
                    field: a.clone(),
                },
                SumTerm {
                    weight: -2.0,
                    field: b.clone(),
                },
                SumTerm {
                    weight: 1.25,
                    field: c.clone(),
                },
            ],
        };
        for p in PROBES {
            let (fa, fb, fc) = (a.eval(p), b.eval(p), c.eval(p));
            let want = [
                0.5 * fa[0] - 2.0 * fb[0] + 1.25 * fc[0],
                0.5 * fa[1] - 2.0 * fb[1] + 1.25 * fc[1],
            ];
            assert!(close(sum.eval(p), want), "{p:?}");
        }
    }

    #[test]
    fn sampled_interpolation_is_exact_at_samples_and_bounded() {
        let points = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
        let vectors = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]];
        for method in [Interpolation::Idw, Interpolation::Nearest] {
            let f = FieldSpec::Sampled {
                points: points.clone(),
                vectors: vectors.clone(),
                interpolation: method,
            };
            for (p, v) in points.iter().zip(&vectors) {
                assert_eq!(f.eval(*p), *v);
            }
            let m = f.eval([0.5, 0.5]);
            assert!((m[0] - 0.5).abs() < 1e-12 || method == Interpolation::Nearest);
            assert!((0.0..=1.0).contains(&m[0]) && (0.0..=1.0).contains(&m[1]));
        }
        let nearest = FieldSpec::Sampled {
            points,
            vectors,
            interpolation: Interpolation::Nearest,
        };
        assert_eq!(nearest.eval([0.9, 0.2]), [1.0, 0.0]);
    }

    #[test]
    fn kinds_list_matches_kind_names() {
        let f = FieldSpec::Sink {
            center: [0.0, 0.0],
            strength: 1.0,
        };
        assert!(FIELD_KINDS.contains(&f.kind()));
        assert_eq!(FIELD_KINDS.len(), 12);
    }
}
