//! The attractor of a target field: where parts that follow it end up.
//!
//! A sink-like target pulls parts to a point or a line at a known
//! exponential rate, which makes closed-loop verification checkable: a part
//! at distance d₀ from the attractor, following the field scaled by the
//! design's achieved strength σ, is at distance d(t) = d₀ e^{−σ s t}, so it
//! reaches a tolerance δ after
//!
//! ```text
//! t(d₀) = ln(d₀/δ) / (σ s)      (0 when d₀ ≤ δ)
//! ```
//!
//! with s the target's own strength (1/s).
//!
//! * `sink` (s > 0): the point `center`; the field is −s d exactly.
//! * `whirlpool` (s > 0): the point `center`; the radial part is −s d and the
//!   rotation does not change the distance.
//! * `line_sink` (s > 0): the line through `center + offset n` along
//!   `angle`; the normal part is −s (n·d − offset).
//! * `squeeze_trans` (s > 0): the line through `center` along `angle`; the
//!   transport runs along the line.
//!
//! Every other kind (sources, saddles, rotations, transports, jets, sums,
//! samples) has no attractor: [`Attractor::of`] returns `None`.

use serde::Serialize;

use super::FieldSpec;

/// Where parts following a target field converge.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Attractor {
    /// A point (m).
    Point {
        /// The point.
        center: [f64; 2],
        /// Convergence rate s (1/s) of the target field.
        rate: f64,
    },
    /// A line through `point` with unit direction `direction`.
    Line {
        /// A point on the line (m).
        point: [f64; 2],
        /// Unit direction of the line.
        direction: [f64; 2],
        /// Convergence rate s (1/s) of the target field.
        rate: f64,
    },
}

impl Attractor {
    /// The attractor of `field`, if it has one (see the module docs).
    pub fn of(field: &FieldSpec) -> Option<Attractor> {
        let dir = |deg: f64| {
            let (s, c) = deg.to_radians().sin_cos();
            [c, s]
        };
        match *field {
            FieldSpec::Sink { center, strength }
            | FieldSpec::Whirlpool {
                center, strength, ..
            } if strength > 0.0 => Some(Attractor::Point {
                center,
                rate: strength,
            }),
            FieldSpec::LineSink {
                center,
                strength,
                angle,
                offset,
            } if strength > 0.0 => {
                let t = dir(angle);
                Some(Attractor::Line {
                    point: [center[0] - offset * t[1], center[1] + offset * t[0]],
                    direction: t,
                    rate: strength,
                })
            }
            FieldSpec::SqueezeTrans {
                center,
                strength,
                angle,
                ..
            } if strength > 0.0 => Some(Attractor::Line {
                point: center,
                direction: dir(angle),
                rate: strength,
            }),
            _ => None,
        }
    }

    /// Distance (m) from `p` to the attractor.
    pub(crate) fn distance(&self, p: [f64; 2]) -> f64 {
        match *self {
            Attractor::Point { center, .. } => (p[0] - center[0]).hypot(p[1] - center[1]),
            Attractor::Line {
                point, direction, ..
            } => ((p[0] - point[0]) * -direction[1] + (p[1] - point[1]) * direction[0]).abs(),
        }
    }

    /// The target's convergence rate s (1/s).
    pub(crate) fn rate(&self) -> f64 {
        match *self {
            Attractor::Point { rate, .. } | Attractor::Line { rate, .. } => rate,
        }
    }

    /// Predicted time (s) for a part starting at `p` to come within `tol`
    /// of the attractor under the target field scaled by `strength` (the
    /// design's achieved strength): ln(d₀/tol)/(strength · s), 0 when it
    /// starts within `tol`, infinite when `strength` ≤ 0.
    pub(crate) fn predicted_time(&self, p: [f64; 2], strength: f64, tol: f64) -> f64 {
        let d0 = self.distance(p);
        if d0 <= tol {
            0.0
        } else if strength > 0.0 {
            (d0 / tol).ln() / (strength * self.rate())
        } else {
            f64::INFINITY
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sink_time_matches_the_exponential_decay_of_the_field() {
        let f = FieldSpec::Sink {
            center: [0.01, -0.02],
            strength: 2.0,
        };
        let a = Attractor::of(&f).expect("a sink has an attractor");
        let p = [0.04, 0.02];
        assert!((a.distance(p) - 0.05).abs() < 1e-15);
        // Integrate d' = −σ s d with explicit small steps: independent of the log.
        let (sigma, tol) = (0.3, 0.003);
        let (mut d, mut t, dt) = (0.05_f64, 0.0, 1e-5);
        while d > tol {
            d -= sigma * 2.0 * d * dt;
            t += dt;
        }
        assert!((a.predicted_time(p, sigma, tol) - t).abs() < 1e-3);
        assert_eq!(a.predicted_time([0.011, -0.02], sigma, tol), 0.0);
    }

    #[test]
    fn line_sink_line_is_offset_along_its_normal() {
        let f = FieldSpec::LineSink {
            center: [0.0, 0.0],
            strength: 1.0,
            angle: 90.0,
            offset: 0.01,
        };
        let a = Attractor::of(&f).expect("a line sink has an attractor");
        // Line along +y, normal n = (−1, 0): the line is x = −0.01, where the field vanishes.
        assert!(a.distance([-0.01, 0.3]) < 1e-15);
        let v = f.eval([-0.01, 0.3]);
        assert!(v[0].abs() < 1e-15 && v[1].abs() < 1e-15);
        assert!((a.distance([0.02, 0.0]) - 0.03).abs() < 1e-15);
    }

    #[test]
    fn sources_saddles_and_weak_fields_have_none() {
        assert!(Attractor::of(&FieldSpec::Source {
            center: [0.0; 2],
            strength: 1.0
        })
        .is_none());
        assert!(Attractor::of(&FieldSpec::Sink {
            center: [0.0; 2],
            strength: -1.0
        })
        .is_none());
        assert!(Attractor::of(&FieldSpec::Saddle {
            center: [0.0; 2],
            strength: 1.0,
            angle: 0.0
        })
        .is_none());
    }
}
