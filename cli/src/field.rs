//! `platefield field`: load a scene, compute its field, then write (nothing is
//! written on bad input).

use std::path::Path;

use super::values::ModelChoice;
use platefield::output::write_all_atomic;
use platefield::scene::{FieldRequest, Scene};
use platefield::work::Runtime;
use platefield::{Error, Result};

/// Computes the field of the scene at `scene_path`, writes it as JSON to `out`
/// and as a quiver plot to `svg` (when given), and returns the text to print:
/// the field JSON with `json`, else the scene's summary and the files written.
/// `model` overrides the scene's model; `auto` chooses the rung
/// ([`platefield::scene::Scene::rung`]) and records it under `"rung"`.
pub fn run(
    scene_path: &Path,
    json: bool,
    out: Option<&Path>,
    svg: Option<&Path>,
    quiet: bool,
    allow_long: bool,
    model: Option<ModelChoice>,
) -> Result<String> {
    let mut scene = Scene::load(scene_path)?;
    // Both destinations are checked before the work, and written all or
    // none after it.
    for (path, arg) in [(out, "--out"), (svg, "--svg")] {
        if let Some(folder) = path.and_then(Path::parent) {
            platefield::output::check_writable(folder, arg)?;
        }
    }
    let start = std::time::Instant::now();
    // `--model` overrides the scene's; `auto` measures every rung on a
    // few sample points and plays the cheapest within the tolerance
    // (its time counted in the field's).
    let rung = match model {
        None => None,
        Some(ModelChoice::Model(m)) => {
            scene.model = m;
            None
        }
        Some(ModelChoice::Auto) => {
            let r = scene.rung(platefield::field::rung::DEFAULT_RUNG_TOLERANCE);
            scene.model = r.model;
            Some(r)
        }
    };
    let req = FieldRequest {
        scene,
        source: scene_path.to_path_buf(),
        runtime: Runtime { quiet, allow_long },
    };
    let field = platefield::scene::field(&req)?;
    let scene = req.scene;
    let seconds = start.elapsed().as_secs_f64();
    let mut value = field.to_json(&scene.settings());
    if let (Some(r), Some(object)) = (&rung, value.as_object_mut()) {
        let r = serde_json::to_value(r).map_err(|e| Error::Internal(e.to_string()))?;
        object.insert("rung".into(), r);
    }
    let mut text =
        serde_json::to_string_pretty(&value).map_err(|e| Error::Internal(e.to_string()))?;
    text.push('\n');
    let stem = scene_path
        .file_stem()
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    let plot =
        svg.map(|_| platefield_report::plot::field_quiver(&field, &scene.title(&stem)).to_svg());
    let files: Vec<(&Path, &[u8])> = out
        .map(|p| (p, text.as_bytes()))
        .into_iter()
        .chain(svg.zip(plot.as_deref()).map(|(p, t)| (p, t.as_bytes())))
        .collect();
    write_all_atomic(&files)?;
    if json {
        return Ok(text);
    }
    let mut summary = scene.summary(&field, seconds);
    if let Some(r) = &rung {
        summary.push_str(&format!("model auto: {}\n", r.reason));
    }
    for path in out.iter().chain(svg.iter()) {
        summary.push_str(&format!("wrote {}\n", path.display()));
    }
    Ok(summary)
}
