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
//!
//! ```
//! use platefield::request::Target;
//! let t = Target::from_json_str(r#"{
//!   "grid": {"x": [-0.04, 0.04], "y": [-0.02, 0.02], "n": [9, 5]},
//!   "classes": [
//!     {"name": "slippery", "friction": 0.2, "field": {"kind": "sink", "center": [-0.02, 0]}},
//!     {"name": "sticky", "friction": 0.45, "field": {"kind": "sink", "center": [0.02, 0]}}]}"#)?;
//! assert_eq!(t.classes.len(), 2);
//! assert_eq!(t.class_target(1).friction.unwrap().nominal().stat, 0.45);
//! # Ok::<(), platefield::request::TargetError>(())
//! ```

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

impl Target {
    /// Class `i` as a plain target: the shared grid, weights, mask, shaker
    /// and gravity with the class's field and friction.
    ///
    /// # Panics
    /// When `i` is not a class index.
    pub fn class_target(&self, i: usize) -> Target {
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
