//! `platefield poses PART.json SOURCE.json`: where a part comes to rest in
//! a field, in which orientation, and from how many drops each.
//!
//! SOURCE is a target (its requested field is the point field), a scene
//! (its point-part steady-state velocity field on its grid, computed here
//! whatever its `kind`) or a designed schedule (the time-weighted field of
//! its segments on its target's grid, [`platefield::pose::schedule_field`]).
//! The region is the source's grid. With `--play SECONDS` (schedules only)
//! every drop is also played by the planar simulator through the schedule
//! ([`platefield::pose::played_basins`]). For a part with an unknown support the
//! equilibrium bounds ([`platefield::pose::Bounds`]) are scanned over the region.

use std::path::Path;

use serde_json::Value;

use platefield::field::{Field, FieldKind, Grid};
use platefield::output::write_all_atomic;
use platefield::part::Part;
use platefield::pose::{analyse, schedule_field, GridField, PointField, Region, MAX_DROPS};
use platefield::progress::{Progress, ProgressMode};
use platefield::request::Target;
use platefield::scene::Scene;
use platefield::schedule::Schedule;
use platefield::work::{with_counted_progress, PLANAR_POINT_STEP_COST};
use platefield::{Error, Result};

/// A point field, its grid, the grid's JSON path and the schedule it came
/// from (if any).
type Source = (Box<dyn PointField>, Grid, &'static str, Option<Schedule>);

/// Longest `--play` (s).
const MAX_PLAY_S: f64 = 3600.0;

/// The point field and its region from `source` (module docs).
fn point_field(source: &Path) -> Result<Source> {
    let text = platefield::input::read_input(source).map_err(|e| Error::Io {
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
        return Ok((
            Box::new(GridField::new(&field)),
            scene.grid,
            "scene.grid",
            None,
        ));
    }
    if value.get("segments").is_some() {
        let schedule = Schedule::load(source)?;
        let Some(grid) = schedule.target_spec.as_ref().and_then(|t| t.grid) else {
            return Err(Error::invalid(
                "schedule.target_spec.grid",
                "a pose analysis needs the schedule's target grid as its region",
            ));
        };
        let field = schedule_field(&schedule, &grid)?;
        return Ok((
            Box::new(field),
            grid,
            "schedule.target_spec.grid",
            Some(schedule),
        ));
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
        return Ok((Box::new(target.field.clone()), grid, "target.grid", None));
    }
    Err(Error::invalid(
        "SOURCE",
        format!(
            "{}: must be a target (with \"field\"), a scene (with \"motion\") or a schedule (with \"segments\")",
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
    play: Option<f64>,
    json: bool,
    out: Option<&Path>,
    allow_long: bool,
) -> Result<String> {
    if !(1..=MAX_DROPS).contains(&drops) {
        return Err(Error::invalid(
            "--drops",
            format!("must be in 1..={MAX_DROPS}, got {drops}"),
        ));
    }
    if let Some(t) = play {
        if !(t > 0.0 && t <= MAX_PLAY_S) {
            return Err(Error::invalid(
                "--play",
                format!("must be in (0, {MAX_PLAY_S}] s, got {t}"),
            ));
        }
    }
    let part = Part::load(part)?;
    if let Some(dir) = out {
        platefield::output::check_writable(dir, "--out")?;
    }
    let (field, grid, path, schedule) = point_field(source)?;
    part.check_fits(grid.x[1] - grid.x[0], grid.y[1] - grid.y[0], path)?;
    let region = Region {
        x: grid.x,
        y: grid.y,
    };
    // The drops' play is refused (a non-schedule source, or work over the
    // limit) and estimated before anything is computed.
    let play = match (play, &schedule) {
        (None, _) => None,
        (Some(_), None) => {
            return Err(Error::invalid(
                "--play",
                "needs a schedule as SOURCE (the drops are played through it)",
            ))
        }
        (Some(t), Some(s)) => {
            let sm = platefield::play::ScheduleMotion::from_schedule(s)?;
            let p = platefield::pose::DropPlay::new(&s.settings, t);
            let work = platefield::pose::drops_estimate(&part, &sm, drops, &p);
            work.admit(allow_long, false)?;
            Some((sm, p, work))
        }
    };
    let analysis = analyse(&part, field.as_ref(), region, drops);
    let played = play.map(|(sm, p, work)| {
        let progress = Progress::new(
            "poses",
            "k planar steps",
            (work.steps() / PLANAR_POINT_STEP_COST / 1e3).ceil() as u64,
            ProgressMode::Auto,
        );
        with_counted_progress(&progress, || {
            platefield::pose::played_basins(&analysis, &part, &sm, &p)
        })
    });
    let bounds = matches!(part.support, platefield::part::Support::Unknown { .. }).then(|| {
        platefield::pose::Bounds::new(&part, field.as_ref())
            .scan(&region, platefield::report::poses::SCAN)
    });
    let extras = platefield::report::poses::Extras {
        played: played.as_ref(),
        bounds: bounds.as_deref(),
    };
    let mut text = serde_json::to_string_pretty(&platefield::report::poses::to_json(
        &part, &analysis, &extras,
    ))
    .map_err(|e| Error::Physical(e.to_string()))?;
    text.push('\n');
    let mut summary = platefield::report::poses::summary(&part, &analysis, &extras);
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).map_err(|e| Error::Io {
            path: dir.display().to_string(),
            source: e,
        })?;
        let svg = platefield::report::poses::picture(&part, &analysis);
        let (jp, sp) = (dir.join("poses.json"), dir.join("poses.svg"));
        write_all_atomic(&[(&jp, text.as_bytes()), (&sp, svg.as_bytes())])?;
        summary.push_str(&format!("wrote {}\nwrote {}\n", jp.display(), sp.display()));
    }
    Ok(if json { text } else { summary })
}
