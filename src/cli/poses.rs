//! `platefield poses PART.json SOURCE.json`: where a part comes to rest in
//! a field, in which orientation, and from how many drops each.
//!
//! SOURCE is a target (its requested field is the point field) or a scene
//! (its point-part steady-state velocity field on its grid, computed here
//! whatever its `kind`). A schedule is refused (its predicted field needs
//! the primitive library; not done). The region is the source's grid.

use std::path::Path;

use serde_json::Value;

use crate::field::{Field, FieldKind, Grid};
use crate::output::write_all_atomic;
use crate::part::Part;
use crate::pose::{analyse, GridField, PointField, Region, MAX_DROPS};
use crate::request::Target;
use crate::scene::Scene;
use crate::{Error, Result};

/// The point field and its region from `source` (module docs).
fn point_field(source: &Path) -> Result<(Box<dyn PointField>, Grid, &'static str)> {
    let text = crate::input::read_input(source).map_err(|e| Error::Io {
        path: source.display().to_string(),
        source: e,
    })?;
    let value: Value = serde_json::from_str(&text)
        .map_err(|e| Error::invalid(source.display().to_string(), format!("not JSON: {e}")))?;
    if value.get("motion").is_some() {
        let scene = Scene::load(source)?;
        let settings = scene.settings();
        let field = Field::compute(
            &scene.motion.to_motion(),
            &scene.grid,
            FieldKind::Velocity,
            &settings,
            &|| {},
        );
        return Ok((Box::new(GridField::new(&field)), scene.grid, "scene.grid"));
    }
    if value.get("field").is_some() {
        let target = Target::load(source)
            .map_err(|e| Error::invalid(source.display().to_string(), e.to_string()))?;
        let Some(grid) = target.grid else {
            return Err(Error::invalid(
                "target.grid",
                "a pose analysis needs the target's grid as its region",
            ));
        };
        return Ok((Box::new(target.field.clone()), grid, "target.grid"));
    }
    Err(Error::invalid(
        "SOURCE",
        format!(
            "{}: must be a target (with \"field\") or a scene (with \"motion\"); schedules are not supported yet",
            source.display()
        ),
    ))
}

/// Runs the analysis and writes `poses.json` and `poses.svg` into `out`
/// (when given); returns the JSON with `json`, else a summary.
pub fn run(
    part: &Path,
    source: &Path,
    drops: usize,
    json: bool,
    out: Option<&Path>,
) -> Result<String> {
    if !(1..=MAX_DROPS).contains(&drops) {
        return Err(Error::invalid(
            "--drops",
            format!("must be in 1..={MAX_DROPS}, got {drops}"),
        ));
    }
    let part = Part::load(part)?;
    if let Some(dir) = out {
        crate::output::check_writable(dir, "--out")?;
    }
    let (field, grid, path) = point_field(source)?;
    part.check_fits(grid.x[1] - grid.x[0], grid.y[1] - grid.y[0], path)?;
    let region = Region {
        x: grid.x,
        y: grid.y,
    };
    let analysis = analyse(&part, field.as_ref(), region, drops);
    let mut text = serde_json::to_string_pretty(&crate::report::poses::to_json(&part, &analysis))
        .map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    let mut summary = crate::report::poses::summary(&part, &analysis);
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| Error::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
        let svg = crate::report::poses::picture(&part, &analysis);
        let (jp, sp) = (dir.join("poses.json"), dir.join("poses.svg"));
        write_all_atomic(&[(&jp, text.as_bytes()), (&sp, svg.as_bytes())])?;
        summary.push_str(&format!("wrote {}\nwrote {}\n", jp.display(), sp.display()));
    }
    Ok(if json { text } else { summary })
}
