//! Part classes: a target that sorts parts by their friction.
//!
//! Instead of one `field`, a target may hold `"classes"`: at least two part
//! classes, each with a `name`, its own `friction` ([`FrictionSpec`], every
//! form of the top-level key) and its own `field`. One schedule is designed
//! for all of them, each class's field matched at its own friction
//! ([`crate::design::sort`]). With classes the top-level `field` and
//! `friction` are refused (each class states its own); `grid`, `weights`,
//! `mask`, `shaker` and `gravity` are shared.
//!
//! At least two classes: one class is a plain target with a `friction`,
//! and the error says so.

use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::{FieldSpec, FrictionSpec, Target, TargetError};

/// One class of parts: its name, its friction and where it should go.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartClass {
    /// Label, unique among the target's classes.
    pub name: String,
    /// The class's friction (exact or a range; designed for its nominal value).
    pub friction: FrictionSpec,
    /// The field this class's parts should follow.
    pub field: FieldSpec,
    /// A lane: the edge of the target's region (its grid's box) the
    /// class's parts should leave through; its field is then a uniform
    /// `trans` pointing through that edge.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exit: Option<Edge>,
}

/// An edge of the target's region, the box of its grid: x low (`left`),
/// x high (`right`), y low (`bottom`), y high (`top`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Edge {
    /// x = x_min.
    Left,
    /// x = x_max.
    Right,
    /// y = y_min.
    Bottom,
    /// y = y_max.
    Top,
}

impl Edge {
    /// Every edge, in the order above.
    pub const ALL: [Edge; 4] = [Edge::Left, Edge::Right, Edge::Bottom, Edge::Top];

    /// Its name in a target file, e.g. `left`.
    pub fn name(self) -> &'static str {
        match self {
            Edge::Left => "left",
            Edge::Right => "right",
            Edge::Bottom => "bottom",
            Edge::Top => "top",
        }
    }

    /// Its outward unit normal.
    pub(crate) fn outward(self) -> [f64; 2] {
        match self {
            Edge::Left => [-1.0, 0.0],
            Edge::Right => [1.0, 0.0],
            Edge::Bottom => [0.0, -1.0],
            Edge::Top => [0.0, 1.0],
        }
    }

    /// Where the straight move from `from` (inside the box `x` × `y`) to
    /// `to` first leaves it: the edge crossed and the fraction of the
    /// move at the crossing; `None` when `to` is inside.
    pub(crate) fn crossing(
        from: [f64; 2],
        to: [f64; 2],
        x: [f64; 2],
        y: [f64; 2],
    ) -> Option<(Edge, f64)> {
        let fraction = |a: f64, b: f64, bound: f64| {
            let d = b - a;
            (d != 0.0).then(|| ((bound - a) / d).clamp(0.0, 1.0))
        };
        let mut out: Option<(Edge, f64)> = None;
        for (edge, outside, s) in [
            (Edge::Left, to[0] < x[0], fraction(from[0], to[0], x[0])),
            (Edge::Right, to[0] > x[1], fraction(from[0], to[0], x[1])),
            (Edge::Bottom, to[1] < y[0], fraction(from[1], to[1], y[0])),
            (Edge::Top, to[1] > y[1], fraction(from[1], to[1], y[1])),
        ] {
            if let (true, Some(s)) = (outside, s) {
                if out.is_none_or(|(_, best)| s < best) {
                    out = Some((edge, s));
                }
            }
        }
        out
    }
}

/// `classes` read alone, so its errors carry their paths.
#[derive(Deserialize)]
struct Classes {
    classes: Vec<PartClass>,
}

/// Top-level keys a classes target may not hold, and why.
const EXCLUSIVE: [(&str, &str); 2] = [
    ("field", "each class gives its own field"),
    ("friction", "each class gives its own friction"),
];

/// Checks the raw JSON of a classes target before it is read as a
/// [`Target`]: `classes` parsed alone (errors at `target.classes[i]…`),
/// at least two, no top-level `field` or `friction`. Returns the JSON with
/// the first class's field as the top-level `field` (what code that reads
/// one field sees), or `None` when the target has no classes.
pub(super) fn prepare(text: &str) -> Result<Option<String>, TargetError> {
    let Ok(Value::Object(mut map)) = serde_json::from_str::<Value>(text) else {
        return Ok(None);
    };
    let Some(raw) = map.get("classes") else {
        return Ok(None);
    };
    let only = serde_json::json!({ "classes": raw });
    let classes = crate::input::from_str::<Classes>(&only.to_string(), "target")
        .map_err(|e| TargetError::invalid(e.path, e.message))?
        .classes;
    for (key, why) in EXCLUSIVE {
        if map.contains_key(key) {
            return Err(TargetError::invalid(
                format!("target.{key}"),
                format!("not allowed together with target.classes ({why})"),
            ));
        }
    }
    if classes.len() < 2 {
        return Err(TargetError::invalid(
            "target.classes",
            format!(
                "needs at least 2 classes to sort, got {} (for one kind of part give \"field\" and \"friction\" instead)",
                classes.len()
            ),
        ));
    }
    let first = serde_json::to_value(&classes[0].field)
        .map_err(|e| TargetError::invalid("target.classes[0].field", e.to_string()))?;
    map.insert("field".into(), first);
    Ok(Some(Value::Object(map).to_string()))
}

/// Most part classes one target sorts. Each class needs its own attractor
/// at least a few tolerances (5 mm) apart within the plate's region, and
/// its own friction band separated from its neighbours': every class's
/// field is judged at every class's friction, so the design's work grows
/// with the square of the count, and ratios between neighbouring
/// frictions shrink (μ 0.1–1.0 in 8 classes is a ratio of 1.39 between
/// neighbours, where `results/sort_friction` already needs the lead
/// δ = asin(μg/A) of each to differ).
pub const MAX_CLASSES: usize = 8;

/// Checks every class: a unique name, its friction and its field; at most
/// [`MAX_CLASSES`] classes, and no two whose static friction ranges
/// overlap (a part in both ranges could be sent to either attractor).
pub(super) fn validate(classes: &[PartClass]) -> Result<(), TargetError> {
    if classes.len() > MAX_CLASSES {
        return Err(TargetError::invalid(
            "target.classes",
            format!(
                "at most {MAX_CLASSES} classes, got {} (each class is judged at every class's friction; see platefield::request::MAX_CLASSES)",
                classes.len()
            ),
        ));
    }
    for (i, c) in classes.iter().enumerate() {
        let path = format!("target.classes[{i}]");
        if let Some(j) = classes[..i].iter().position(|d| d.name == c.name) {
            return Err(TargetError::invalid(
                format!("{path}.name"),
                format!(
                    "\"{}\" is already the name of target.classes[{j}]; class names must be unique",
                    c.name
                ),
            ));
        }
        c.friction
            .validate(&format!("{path}.friction"))
            .map_err(|e| match e {
                crate::error::Error::Invalid { field, message } => {
                    TargetError::invalid(field, message)
                }
                other => TargetError::invalid(path.clone(), other.to_string()),
            })?;
        c.field.validate(&format!("{path}.field"))?;
        if let Some(edge) = c.exit {
            validate_lane(&path, edge, &c.field)?;
        }
        let (lo, hi) = (c.friction.stat.lo, c.friction.stat.hi);
        if let Some(j) = classes[..i]
            .iter()
            .position(|d| lo <= d.friction.stat.hi && d.friction.stat.lo <= hi)
        {
            let d = &classes[j].friction.stat;
            return Err(TargetError::invalid(
                format!("{path}.friction"),
                format!(
                    "static friction [{lo}, {hi}] overlaps target.classes[{j}]'s [{}, {}]; a part in both ranges could go to either attractor, so class frictions must not overlap",
                    d.lo, d.hi
                ),
            ));
        }
    }
    Ok(())
}

/// A lane's field (class at `path`, leaving through `edge`): a uniform
/// `trans` whose direction points out through that edge.
fn validate_lane(path: &str, edge: Edge, field: &FieldSpec) -> Result<(), TargetError> {
    let FieldSpec::Trans { direction, .. } = field else {
        return Err(TargetError::invalid(
            format!("{path}.field"),
            format!(
                "a lane (\"exit\": \"{}\") takes a uniform field, {{\"kind\": \"trans\", \"direction\": DEGREES}}, pointing through its edge",
                edge.name()
            ),
        ));
    };
    let a = direction.to_radians();
    let n = edge.outward();
    if a.cos() * n[0] + a.sin() * n[1] <= 1e-9 {
        return Err(TargetError::invalid(
            format!("{path}.field.direction"),
            format!(
                "{direction}° does not point through the {} edge of the region (its outward normal is [{}, {}]); a lane's transport must leave through its exit",
                edge.name(),
                n[0],
                n[1]
            ),
        ));
    }
    Ok(())
}

impl Target {
    /// Class `i` as a plain target: the shared grid, weights, mask, shaker
    /// and gravity with the class's field and friction.
    ///
    /// # Panics
    /// When `i` is not a class index.
    pub(crate) fn class_target(&self, i: usize) -> Target {
        let c = &self.classes[i];
        Target {
            name: format!("{}/{}", self.name, c.name),
            field: c.field.clone(),
            friction: Some(c.friction),
            classes: Vec::new(),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `request::classes`.
    #[test]
    fn example_classes() -> Result<(), crate::request::TargetError> {
        use crate::request::Target;
        let t = Target::from_json_str(
            r#"{
          "grid": {"x": [-0.04, 0.04], "y": [-0.02, 0.02], "n": [9, 5]},
          "classes": [
            {"name": "slippery", "friction": 0.2, "field": {"kind": "sink", "center": [-0.02, 0]}},
            {"name": "sticky", "friction": 0.45, "field": {"kind": "sink", "center": [0.02, 0]}}]}"#,
        )?;
        assert_eq!(t.classes.len(), 2);
        assert_eq!(t.class_target(1).friction.unwrap().nominal().stat, 0.45);
        Ok(())
    }

    /// A worked example of `request::classes::Edge::outward`.
    #[test]
    fn example_edge_outward() {
        use crate::request::Edge;
        assert_eq!(Edge::Left.outward(), [-1.0, 0.0]);
    }

    /// A worked example of `request::classes::Edge::crossing`.
    #[test]
    fn example_edge_crossing() {
        use crate::request::Edge;
        let x = [-0.5, 0.5];
        let y = [-0.25, 0.25];
        assert_eq!(
            Edge::crossing([0.25, 0.0], [0.75, 0.0], x, y),
            Some((Edge::Right, 0.5))
        );
        // Both bounds passed: the one crossed first.
        assert_eq!(
            Edge::crossing([0.25, 0.0], [0.75, 0.75], x, y),
            Some((Edge::Top, 1.0 / 3.0))
        );
        assert_eq!(Edge::crossing([0.0, 0.0], [0.25, 0.0], x, y), None);
    }
}
