//! A pose target: `"field": {"kind": "pose", "part": "parts/bracket.json",
//! "pose": [x, y, theta_deg]}` asks for that pose of the part (its centre
//! of mass at (x, y) m, the part file's x axis at θ degrees) from anywhere
//! in the target's region, up to the part's own symmetry
//! ([`Part::symmetry`]).
//!
//! One loader ([`PoseTarget::load`]): the rest of the file is read as a
//! target (grid, mask, friction, gravity, shaker) with its field replaced
//! by a sink at the pose, so every other key is checked as for any target.
//! `part` is a path relative to the target file. Refused (exit 2, naming
//! the JSON path): a `pose` that is not three finite numbers, keys other
//! than `kind`, `part` and `pose`, a part file that cannot be read or is
//! invalid (its own JSON path), a part larger than the region, a pose
//! whose placed part does not lie on the region, `classes`.

use std::path::{Path, PathBuf};

use serde_json::Value;

use crate::dynamics::V2;
use crate::error::{Error, Result};
use crate::input::num;
use crate::part::Part;
use crate::pose::{Pose, Region};
use crate::request::Target;

/// JSON path of the pose.
const POSE: &str = "target.field.pose";
/// JSON path of the part.
const PART: &str = "target.field.part";

/// A checked pose target.
#[derive(Debug, Clone)]
pub struct PoseTarget {
    /// The file's target with its field replaced by a sink at the pose
    /// (its grid, mask and physics; the part's friction when it states
    /// none).
    pub target: Target,
    /// The part.
    pub part: Part,
    /// The part file as written in the target.
    pub part_path: String,
    /// The pose asked for (θ in rad).
    pub pose: Pose,
    /// The region: the target's grid (m).
    pub region: Region,
}

/// The `field` object of `value` when its kind is `pose`.
fn pose_field(value: &Value) -> Option<&serde_json::Map<String, Value>> {
    let field = value.get("field")?.as_object()?;
    (field.get("kind")?.as_str()? == "pose").then_some(field)
}

/// Largest magnitude of a pose's numbers as read (x, y in m; θ in
/// degrees): far beyond any plate and any number of turns, so that only a
/// typo is refused here; the position is then checked against the grid.
const POSE_MAX: f64 = 1e6;

/// `pose` as three finite numbers (x m, y m, θ degrees).
fn pose_numbers(field: &serde_json::Map<String, Value>) -> Result<[f64; 3]> {
    let bad = |what: &str| {
        Error::invalid(
            POSE,
            format!("must be [x, y, theta_deg]: the part's centre of mass (m) and angle (degrees), three finite numbers; {what}"),
        )
    };
    let items = field
        .get("pose")
        .ok_or_else(|| bad("missing"))?
        .as_array()
        .ok_or_else(|| bad("got something else"))?;
    if items.len() != 3 {
        return Err(bad(&format!("got {} items", items.len())));
    }
    let mut out = [0.0; 3];
    for (i, v) in items.iter().enumerate() {
        let unit = if i == 2 { "degrees" } else { "m" };
        out[i] = v
            .as_f64()
            .filter(|x| x.is_finite() && x.abs() <= POSE_MAX)
            .ok_or_else(|| {
                Error::invalid(
                    format!("{POSE}[{i}]"),
                    format!(
                        "must be a finite number in [-{POSE_MAX:e}, {POSE_MAX:e}] {unit}, got {v}"
                    ),
                )
            })?;
    }
    Ok(out)
}

/// The part file `field.part` names, relative to `dir`.
fn load_part(field: &serde_json::Map<String, Value>, dir: &Path) -> Result<(String, Part)> {
    let written = field.get("part").and_then(Value::as_str).ok_or_else(|| {
        Error::invalid(
            PART,
            "must be the path of a part file (relative to the target file), e.g. \"parts/bracket.json\"",
        )
    })?;
    let path: PathBuf = dir.join(written);
    let part = Part::load(&path).map_err(|e| match e {
        Error::Io { path, source } => Error::invalid(PART, format!("cannot read {path}: {source}")),
        other => other,
    })?;
    Ok((written.to_string(), part))
}

/// The file's errors prefixed with its path, as [`Target::load`] does.
fn in_file(path: &Path, e: Error) -> Error {
    match e {
        Error::Invalid { field, message } if !field.contains(": ") => Error::Invalid {
            field: format!("{}: {field}", path.display()),
            message,
        },
        other => other,
    }
}

impl PoseTarget {
    /// The two ends of the target's friction range (μ low, μ high), `None`
    /// for an exact friction: where a pose design's probes play to meet
    /// the range (`pose::design::correct`, [`super::screen`]).
    pub(crate) fn friction_ends(&self) -> Option<[crate::dynamics::Friction; 2]> {
        let v = crate::design::stacked::ranged(&self.target)?.values(2);
        Some([v[0], v[v.len() - 1]])
    }

    /// Reads the target file at `path`: `None` when its field is not a
    /// pose (any other target, or a file that is not JSON: the target
    /// loader then reports it); the checked pose target otherwise (module
    /// docs).
    ///
    /// ```
    /// use platefield::pose::design::PoseTarget;
    /// let r = PoseTarget::load(std::path::Path::new("targets/pose_rectangle.json"))?.unwrap();
    /// assert_eq!(r.part.symmetry(), 2);
    /// assert!(PoseTarget::load(std::path::Path::new("targets/sink.json"))?.is_none());
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn load(path: &Path) -> Result<Option<PoseTarget>> {
        let text = crate::input::read_input(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        PoseTarget::from_json_str(&text, dir).map_err(|e| in_file(path, e))
    }

    /// [`PoseTarget::load`] from text, the part path relative to `dir`.
    pub(crate) fn from_json_str(text: &str, dir: &Path) -> Result<Option<PoseTarget>> {
        let Ok(mut value) = serde_json::from_str::<Value>(text) else {
            return Ok(None);
        };
        let Some(field) = pose_field(&value) else {
            return Ok(None);
        };
        if let Some(key) = field
            .keys()
            .find(|k| !["kind", "part", "pose"].contains(&k.as_str()))
        {
            return Err(Error::invalid(
                format!("target.field.{key}"),
                "unknown key; a pose field has `kind`, `part` and `pose`",
            ));
        }
        let [x, y, deg] = pose_numbers(field)?;
        let (part_path, part) = load_part(field, dir)?;
        value["field"] = serde_json::json!({"kind": "sink", "center": [x, y]});
        let mut target = Target::from_json_str(&value.to_string())?;
        if !target.classes.is_empty() {
            return Err(Error::invalid(
                "target.classes",
                "a pose target asks for one part's pose; it has no classes",
            ));
        }
        target.friction.get_or_insert(part.friction);
        let grid = target
            .grid
            .ok_or_else(|| Error::invalid("target.grid", "a pose target needs a grid"))?;
        let region = Region {
            x: grid.x,
            y: grid.y,
        };
        let pose = Pose::new(x, y, deg.to_radians());
        check_pose(&part, &pose, &region)?;
        Ok(Some(PoseTarget {
            target,
            part,
            part_path,
            pose,
            region,
        }))
    }
}

/// The part fits the region, and placed at `pose` lies on it.
fn check_pose(part: &Part, pose: &Pose, region: &Region) -> Result<()> {
    let (w, h) = (region.x[1] - region.x[0], region.y[1] - region.y[0]);
    part.check_fits(w, h, "target.grid")
        .map_err(|e| Error::invalid(PART, e.to_string()))?;
    let inside = |p: &V2| {
        (region.x[0]..=region.x[1]).contains(&p.x) && (region.y[0]..=region.y[1]).contains(&p.y)
    };
    if let Some(p) = part.placed(pose.r, pose.theta).iter().find(|p| !inside(p)) {
        return Err(Error::invalid(
            POSE,
            format!(
                "the part placed at this pose reaches ({}, {}) m, outside the region x in [{}, {}], y in [{}, {}] m (target.grid); the whole part must lie on it",
                num(p.x),
                num(p.y),
                num(region.x[0]),
                num(region.x[1]),
                num(region.y[0]),
                num(region.y[1])
            ),
        ));
    }
    Ok(())
}
