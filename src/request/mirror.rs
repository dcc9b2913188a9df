//! Mirror images of targets in the plane y = 0.
//!
//! With S = diag(1, −1) the reflection y → −y, the mirror image of a field
//! f is f′(q) = S f(S q): what a part at S q sees under the mirror-image
//! motion ([`crate::motion::Signals::mirrored_y`]). In the field kinds'
//! own terms ([`FieldSpec`]): centres and sample points reflect, every
//! direction angle a becomes −a, a line's offset changes sign (its left
//! normal n = (−sin a, cos a) maps to −n′), and every sense of rotation
//! reverses (a whirlpool's ρ and a circle's strength change sign).
//! A design for f′, mirrored back, realises f with every motion's sense of
//! circulation reversed ([`crate::design::mirror::counter_share`]).

use super::field::{FieldSpec, SumTerm};
use super::grid::{Grid, MaskRegion};
use super::Target;

/// `p` reflected in y = 0.
fn flip(p: [f64; 2]) -> [f64; 2] {
    [p[0], -p[1]]
}

/// The interval `[lo, hi]` of y reflected: `[−hi, −lo]`.
fn flip_interval(y: [f64; 2]) -> [f64; 2] {
    [-y[1], -y[0]]
}

impl FieldSpec {
    /// The mirror image f′(q) = S f(S q) in the plane y = 0 (module
    /// documentation).
    pub(crate) fn mirrored_y(&self) -> FieldSpec {
        match self.clone() {
            FieldSpec::Sink { center, strength } => FieldSpec::Sink {
                center: flip(center),
                strength,
            },
            FieldSpec::Source { center, strength } => FieldSpec::Source {
                center: flip(center),
                strength,
            },
            FieldSpec::LineSink {
                center,
                strength,
                angle,
                offset,
            } => FieldSpec::LineSink {
                center: flip(center),
                strength,
                angle: -angle,
                offset: -offset,
            },
            FieldSpec::Saddle {
                center,
                strength,
                angle,
            } => FieldSpec::Saddle {
                center: flip(center),
                strength,
                angle: -angle,
            },
            FieldSpec::Whirlpool {
                center,
                strength,
                rotation,
            } => FieldSpec::Whirlpool {
                center: flip(center),
                strength,
                rotation: -rotation,
            },
            FieldSpec::Circle { center, strength } => FieldSpec::Circle {
                center: flip(center),
                strength: -strength,
            },
            FieldSpec::ScaledCircle { center, strength } => FieldSpec::ScaledCircle {
                center: flip(center),
                strength: -strength,
            },
            FieldSpec::Trans {
                center,
                strength,
                direction,
            } => FieldSpec::Trans {
                center: flip(center),
                strength,
                direction: -direction,
            },
            FieldSpec::SqueezeTrans {
                center,
                strength,
                angle,
                transport,
            } => FieldSpec::SqueezeTrans {
                center: flip(center),
                strength,
                angle: -angle,
                transport,
            },
            FieldSpec::Jet {
                center,
                strength,
                direction,
                width,
            } => FieldSpec::Jet {
                center: flip(center),
                strength,
                direction: -direction,
                width,
            },
            FieldSpec::Sum { terms } => FieldSpec::Sum {
                terms: terms
                    .iter()
                    .map(|t| SumTerm {
                        weight: t.weight,
                        field: t.field.mirrored_y(),
                    })
                    .collect(),
            },
            FieldSpec::Sampled {
                points,
                vectors,
                interpolation,
            } => FieldSpec::Sampled {
                points: points.into_iter().map(flip).collect(),
                vectors: vectors.into_iter().map(flip).collect(),
                interpolation,
            },
        }
    }
}

impl MaskRegion {
    /// The region reflected in y = 0.
    pub(crate) fn mirrored_y(&self) -> MaskRegion {
        match *self {
            MaskRegion::Circle { center, radius } => MaskRegion::Circle {
                center: flip(center),
                radius,
            },
            MaskRegion::Rect { x, y } => MaskRegion::Rect {
                x,
                y: flip_interval(y),
            },
        }
    }
}

impl Target {
    /// The mirror image of the target in y = 0: its field
    /// ([`FieldSpec::mirrored_y`]), grid (y range reflected, so the rows
    /// run in reverse), weights (rows reversed to match) and mask
    /// reflected; friction, gravity and shaker as they are. Part classes
    /// are dropped (a sorting target is designed by its own method).
    pub(crate) fn mirrored_y(&self) -> Target {
        Target {
            name: self.name.clone(),
            grid: self.grid.map(|g| Grid {
                y: flip_interval(g.y),
                ..g
            }),
            field: self.field.mirrored_y(),
            weights: self.weights.as_ref().map(|rows| {
                let mut rows = rows.clone();
                rows.reverse();
                rows
            }),
            mask: self.mask.iter().map(MaskRegion::mirrored_y).collect(),
            shaker: self.shaker.clone(),
            friction: self.friction,
            gravity: self.gravity,
            classes: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rng::SplitMix64;

    /// One field of every kind, off-centre and turned.
    fn every_kind() -> Vec<FieldSpec> {
        let c = [0.011, -0.007];
        let kinds = [
            format!(r#"{{"kind": "sink", "center": [{}, {}], "strength": 1.3}}"#, c[0], c[1]),
            r#"{"kind": "source", "center": [0.004, 0.02]}"#.into(),
            r#"{"kind": "line_sink", "center": [0.01, 0.003], "angle": 37, "offset": 0.006}"#.into(),
            r#"{"kind": "saddle", "center": [-0.01, 0.005], "angle": -21}"#.into(),
            r#"{"kind": "whirlpool", "center": [0.002, 0.009], "rotation": -0.8}"#.into(),
            r#"{"kind": "circle", "center": [0.003, -0.002], "strength": 0.02}"#.into(),
            r#"{"kind": "scaled_circle", "center": [0.0, 0.01], "strength": 0.5}"#.into(),
            r#"{"kind": "trans", "direction": 70, "strength": 0.01}"#.into(),
            r#"{"kind": "squeeze_trans", "center": [0.0, 0.004], "angle": 15, "transport": -0.6}"#.into(),
            r#"{"kind": "jet", "center": [0.0, 0.01], "direction": 120, "width": 0.008}"#.into(),
            r#"{"kind": "sum", "terms": [{"weight": 0.5, "field": {"kind": "line_sink", "angle": -25}}, {"field": {"kind": "whirlpool", "rotation": 1.2}}]}"#.into(),
            r#"{"kind": "sampled", "points": [[0.0, 0.0], [0.01, 0.02], [-0.02, 0.005], [0.015, -0.01]], "vectors": [[0.001, 0.002], [-0.003, 0.0], [0.0, -0.002], [0.002, 0.001]]}"#.into(),
        ];
        kinds
            .iter()
            .map(|k| serde_json::from_str::<FieldSpec>(k).expect("valid field"))
            .collect()
    }

    /// The mirror image of every kind is S f(S q) at random points, to
    /// round-off (the closed form of the module documentation), and
    /// mirroring twice gives the field back.
    #[test]
    fn mirrored_fields_are_the_reflection_conjugates() {
        let mut rng = SplitMix64::new(45);
        for f in every_kind() {
            let m = f.mirrored_y();
            assert_eq!(m.mirrored_y(), f, "{f:?}");
            for _ in 0..50 {
                let q = [0.08 * rng.uniform() - 0.04, 0.08 * rng.uniform() - 0.04];
                let v = f.eval(flip(q));
                let w = m.eval(q);
                let scale = v[0].hypot(v[1]).max(1e-12);
                assert!(
                    (w[0] - v[0]).abs() <= 1e-12 * scale && (w[1] + v[1]).abs() <= 1e-12 * scale,
                    "{f:?} at {q:?}: {w:?} against S f(S q) = {:?}",
                    flip(v)
                );
            }
        }
    }

    /// The mirrored target's samples are the reflected samples with the
    /// same weights, mask included.
    #[test]
    fn mirrored_targets_sample_the_reflected_points() {
        let t = Target::from_json_str(
            r#"{"name": "t", "grid": {"x": [-0.03, 0.04], "y": [-0.01, 0.03], "n": [8, 5]},
            "field": {"kind": "line_sink", "angle": 30, "offset": 0.004},
            "weights": [[1,2,3,4,5,6,7,8],[1,1,1,1,1,1,1,1],[0,1,0,1,0,1,0,1],[2,2,2,2,2,2,2,2],[3,1,3,1,3,1,3,1]],
            "mask": [{"circle": {"center": [0.01, 0.02], "radius": 0.008}}, {"rect": {"x": [-0.03, -0.02], "y": [0.0, 0.01]}}]}"#,
        )
        .expect("valid target");
        let (a, b) = (
            t.sample().expect("samples"),
            t.mirrored_y().sample().expect("samples"),
        );
        assert_eq!(a.points.len(), b.points.len());
        for (i, p) in a.points.iter().enumerate() {
            let j = b
                .points
                .iter()
                .position(|q| (q[0] - p[0]).abs() < 1e-12 && (q[1] + p[1]).abs() < 1e-12)
                .expect("the reflected point is a sample");
            assert_eq!(a.weights[i], b.weights[j], "weight at {p:?}");
            assert!((a.vectors[i][0] - b.vectors[j][0]).abs() < 1e-12);
            assert!((a.vectors[i][1] + b.vectors[j][1]).abs() < 1e-12);
        }
    }

    /// A worked example of `request::mirror::FieldSpec::mirrored_y`.
    #[test]
    fn example_fieldspec_mirrored_y() {
        use crate::request::FieldSpec;

        let f: FieldSpec = serde_json::from_str(
            r#"{"kind": "whirlpool", "center": [0.01, 0.02], "rotation": 0.7}"#,
        )
        .unwrap();
        let m = f.mirrored_y();
        let (q, v) = ([0.013, -0.004], f.eval([0.013, 0.004]));
        let w = m.eval(q);
        assert!((w[0] - v[0]).abs() < 1e-15 && (w[1] + v[1]).abs() < 1e-15);
    }

    /// A worked example of `request::mirror::Target::mirrored_y`.
    #[test]
    fn example_target_mirrored_y() {
        use crate::request::Target;

        let t = Target::from_json_str(
            r#"{"name": "s",
            "grid": {"x": [-0.04, 0.04], "y": [-0.01, 0.03], "n": [5, 5]},
            "field": {"kind": "sink", "center": [0.01, 0.02]}}"#,
        )
        .unwrap();
        let m = t.mirrored_y();
        assert_eq!(m.grid.unwrap().y, [-0.03, 0.01]);
        let (a, b) = (t.sample().unwrap(), m.sample().unwrap());
        assert_eq!(a.points.len(), b.points.len());
    }
}
