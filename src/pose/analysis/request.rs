//! [`poses`]: the one door of `platefield poses` — where a part comes to
//! rest in a field, in which orientation, and from how many drops each.
//!
//! The source is a target (its requested field is the point field), a
//! scene (its point-part steady-state velocity field on its grid, computed
//! here whatever its `kind`) or a designed schedule (the time-weighted
//! field of its segments on its target's grid, [`crate::pose::schedule_field`]).
//! The region is the source's grid. With [`AnalysisRequest::play`] (schedules
//! only) every drop is also played by the planar simulator through the
//! schedule ([`crate::pose::played_basins`]). For a part with an unknown support
//! the equilibrium bounds ([`crate::pose::Bounds`]) are scanned over the region
//! ([`SCAN`]).

use std::path::{Path, PathBuf};

use serde_json::Value;

use super::averaged::{checked_poses, AveragedField, LiftCheck};
use super::bounds::Bounds;
use super::drops::{played_basins, DropPlay, PlayedBasins};
use super::equilibria::Region;
use super::lifted::{GridField, LiftedField, PointField, Pose};
use super::rests::{played_rests, PlayedRest, MAX_NEWTON, MAX_RESTS};
use super::run::{analyse_with, PoseAnalysis, MAX_DROPS};
use super::source::schedule_field;
use super::work::{averaged_estimate, bounds_term, drops_estimate, settle_estimate};
use crate::dynamics::{Friction, PartPhysics};
use crate::error::{Error, Result};
use crate::field::{Field, FieldKind, Grid};
use crate::part::{Part, Support};
use crate::play::{PlayedSegment, ScheduleMotion};
use crate::progress::Progress;
use crate::request::Target;
use crate::scene::FrictionSpec;
use crate::scene::Scene;
use crate::schedule::Schedule;
use crate::work::{with_counted_progress, Term, PLANAR_POINT_STEP_COST};

/// Longest [`AnalysisRequest::play`] (s).
pub const MAX_PLAY_S: f64 = 3600.0;

/// The grid of poses (x, y, θ) scanned for an unknown support's bounds.
pub const SCAN: [usize; 3] = [24, 24, 36];

/// What `platefield poses` is asked to do.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisRequest {
    /// The part's JSON file.
    pub part: PathBuf,
    /// The source's JSON file: a target, a scene or a schedule.
    pub source: PathBuf,
    /// Random drops (1..=[`MAX_DROPS`]).
    pub drops: usize,
    /// Seconds of planar simulation per drop through a schedule source
    /// (`None`: no play; at most [`MAX_PLAY_S`]).
    pub play: Option<f64>,
    /// The parts' friction: one value, or a range answered at its ends and
    /// middle (`PER_RANGE`); `None`: the source's own (a scene's or a
    /// schedule's settings). A target's requested field has none.
    pub friction: Option<FrictionSpec>,
    /// The work's progress and long-run guard (`settle_estimate`,
    /// [`crate::pose::drops_estimate`]).
    pub runtime: crate::work::Runtime,
}

/// Frictions a range is answered at: its low end, middle and high end.
pub const PER_RANGE: usize = 3;

/// What [`poses`] found (written by `crate::report::poses`).
#[derive(Debug, Clone)]
pub struct PoseOutcome {
    /// The part, as read.
    pub part: Part,
    /// Equilibria, their stability and basins along the lifted field.
    pub analysis: PoseAnalysis,
    /// The drops played through the schedule (with [`AnalysisRequest::play`]).
    pub played: Option<PlayedBasins>,
    /// The poses of the [`SCAN`] that may rest for some admissible
    /// support (a part with an unknown support).
    pub bounds: Option<Vec<Pose>>,
    /// The lifted field against the averaged field at the equilibria and
    /// drop starts (`checked_poses`); `None` for a target (no plate
    /// motion to play).
    pub lift_check: Option<LiftCheck>,
    /// The played rests Newton found on the averaged field from the lifted equilibria
    /// ([`played_rests`]); `None` for a target.
    pub played_rests: Option<Vec<PlayedRest>>,
    /// Why the averaged field's check and refinement did not run (their
    /// work estimate is over the limit without `--allow-long`).
    pub averaged_skipped: Option<String>,
    /// Over a friction range ([`AnalysisRequest::friction`]): the lifted
    /// analysis at each of its `PER_RANGE` values, low to high (the
    /// middle is `analysis`); empty for one friction.
    pub over_friction: Vec<(Friction, PoseAnalysis)>,
}

/// What a SOURCE file gives the analysis.
struct Source {
    /// The point field.
    field: Box<dyn PointField>,
    /// Its grid: the region.
    grid: Grid,
    /// The grid's JSON path, for errors.
    path: &'static str,
    /// The schedule, when the source is one (its drops can be played).
    schedule: Option<Schedule>,
    /// The plate trajectory behind the field and the part physics, for the
    /// averaged field; `None` for a target (a requested field has no plate
    /// motion).
    plate: Option<(ScheduleMotion, PartPhysics)>,
    /// What the field is computed from, to compute it again at another
    /// friction; `None` for a target.
    plays: Option<Plays>,
}

/// A field computed from a plate motion, at the parts' friction.
enum Plays {
    /// A scene's motion with its settings.
    Scene(Box<(crate::motion::Motion, crate::field::FieldSettings)>),
    /// A schedule's segments.
    Schedule(Box<Schedule>),
}

impl Plays {
    /// The point field on `grid` with the parts' friction `f`.
    fn field(&self, grid: &Grid, f: Friction) -> Result<Box<dyn PointField>> {
        Ok(match self {
            Plays::Scene(scene) => {
                let (motion, settings) = scene.as_ref();
                let settings = crate::field::FieldSettings {
                    friction: f,
                    ..*settings
                };
                let field = Field::compute(motion, grid, FieldKind::Velocity, &settings, &|| {});
                Box::new(GridField::new(&field))
            }
            Plays::Schedule(schedule) => {
                let mut at = schedule.clone();
                at.settings.friction = f;
                Box::new(schedule_field(&at, grid)?)
            }
        })
    }
}

/// The point field and its region from `source` (module docs), at the
/// parts' friction `friction` when given (a scene or a schedule; a target
/// refuses it, naming `--friction`).
fn point_field(source: &Path, friction: Option<Friction>) -> Result<Source> {
    let text = crate::input::read_input(source).map_err(|e| Error::Io {
        path: source.display().to_string(),
        source: e,
    })?;
    let value: Value = serde_json::from_str(&text)
        .map_err(|e| Error::invalid(source.display().to_string(), format!("not JSON: {e}")))?;
    if value.get("motion").is_some() {
        let scene = Scene::load(source)?;
        let mut settings = scene.settings();
        if let Some(f) = friction {
            settings.friction = f;
        }
        let motion = scene.motion.to_motion();
        let plays = Plays::Scene(Box::new((motion.clone(), settings)));
        return Ok(Source {
            field: plays.field(&scene.grid, settings.friction)?,
            grid: scene.grid,
            path: "scene.grid",
            schedule: None,
            plate: Some((
                ScheduleMotion::new(vec![PlayedSegment::moving("scene", motion, 1)])?,
                settings.physics(),
            )),
            plays: Some(plays),
        });
    }
    if value.get("segments").is_some() {
        let mut schedule = Schedule::load(source)?;
        if let Some(f) = friction {
            schedule.settings.friction = f;
        }
        let Some(grid) = schedule.target_spec.as_ref().and_then(|t| t.grid) else {
            return Err(Error::invalid(
                "schedule.target_spec.grid",
                "a pose analysis needs the schedule's target grid as its region",
            ));
        };
        let field = schedule_field(&schedule, &grid)?;
        let sm = ScheduleMotion::from_schedule(&schedule)?;
        return Ok(Source {
            field: Box::new(field),
            grid,
            path: "schedule.target_spec.grid",
            plate: Some((sm, schedule.settings.physics())),
            plays: Some(Plays::Schedule(Box::new(schedule.clone()))),
            schedule: Some(schedule),
        });
    }
    let designed_first = |what: &str, key: &str| {
        Error::invalid(
            format!("{}: {key}", source.display()),
            format!("is {what}: `poses` analyses a point field (a target's field, a scene's or a schedule's); design this target first (`platefield design`) and give its schedule.json as SOURCE"),
        )
    };
    if value.get("classes").is_some() {
        return Err(designed_first(
            "a sorting target (one field per friction class)",
            "target.classes",
        ));
    }
    if value.pointer("/field/kind").and_then(Value::as_str) == Some("pose") {
        return Err(designed_first(
            "a pose target (a part's pose to reach)",
            "target.field.kind",
        ));
    }
    if value.get("field").is_some() {
        // Its errors name the file and the JSON path already.
        let target = Target::load(source)?;
        let Some(grid) = target.grid else {
            return Err(Error::invalid(
                "target.grid",
                "a pose analysis needs the target's grid as its region",
            ));
        };
        if friction.is_some() {
            return Err(Error::invalid(
                "--friction",
                "a target's requested field does not depend on the parts' friction: give a scene or a designed schedule as SOURCE",
            ));
        }
        return Ok(Source {
            field: Box::new(target.field.clone()),
            grid,
            path: "target.grid",
            schedule: None,
            plate: None,
            plays: None,
        });
    }
    Err(Error::invalid(
        "SOURCE",
        format!(
            "{}: must be a target (with \"field\"), a scene (with \"motion\") or a schedule (with \"segments\")",
            source.display()
        ),
    ))
}

/// The pose analysis `req` asks for (module docs).
///
/// ```no_run
/// use platefield::pose::{poses, AnalysisRequest};
/// let req = AnalysisRequest {
///     part: "targets/parts/triangle.json".into(),
///     source: "targets/sink.json".into(),
///     drops: 200,
///     play: None,
///     friction: None,
///     runtime: platefield::work::Runtime::default(),
/// };
/// let outcome = poses(&req)?;
/// println!("{} equilibria", outcome.analysis.equilibria.len());
/// # Ok::<(), platefield::Error>(())
/// ```
///
/// # Errors
/// [`Error::Invalid`] naming `--drops`, `--play`, `SOURCE` or a JSON path;
/// a part that does not fit the region; the source's own errors.
pub fn poses(req: &AnalysisRequest) -> Result<PoseOutcome> {
    check_counts(req.drops, req.play)?;
    let part = Part::load(&req.part)?;
    let range = req.friction.filter(|f| f.values(PER_RANGE).len() > 1);
    let Source {
        field,
        grid,
        path,
        schedule,
        plate,
        plays,
    } = point_field(&req.source, req.friction.map(|f| f.nominal()))?;
    part.check_fits(grid.x[1] - grid.x[0], grid.y[1] - grid.y[0], path)?;
    let region = Region {
        x: grid.x,
        y: grid.y,
    };
    // Every estimate is stated, and work over the limit refused, before
    // anything is computed.
    let play = match (req.play, &schedule) {
        (None, _) => None,
        (Some(_), None) => {
            return Err(Error::invalid(
                "--play",
                "needs a schedule as SOURCE (the drops are played through it)",
            ))
        }
        (Some(t), Some(s)) => {
            let sm = crate::play::ScheduleMotion::from_schedule(s)?;
            let p = DropPlay::new(&s.settings, t);
            let work = drops_estimate(&part, &sm, req.drops, &p);
            let mode = req.runtime.admit_stated(&work)?;
            Some((sm, p, work, mode))
        }
    };
    let frictions = range.map_or(Vec::new(), |f| f.values(PER_RANGE));
    let mut work = settle_estimate(&part, &region, req.drops);
    if frictions.len() > 1 {
        // The middle is the main analysis; the others again each.
        let again = (frictions.len() - 1) as f64;
        let terms: Vec<Term> = work.terms.clone();
        for t in terms {
            work = work.plus(
                t.times(again, "more frictions")
                    .named("over the friction range"),
            );
        }
    }
    let unknown = matches!(part.support, Support::Unknown { .. });
    if unknown {
        work = work.plus(bounds_term(&part));
    }
    let mode = req.runtime.admit_stated(&work)?;
    let analysis = settled(&part, field.as_ref(), region, req.drops, mode, "");
    let over_friction = match &plays {
        Some(plays) if frictions.len() > 1 => frictions
            .iter()
            .map(|f| {
                if Some(*f) == req.friction.map(|r| r.nominal()) {
                    return Ok((*f, analysis.clone()));
                }
                let at = plays.field(&grid, *f)?;
                let label = format!(" at μ {}", f.kinetic);
                Ok((
                    *f,
                    settled(&part, at.as_ref(), region, req.drops, mode, &label),
                ))
            })
            .collect::<Result<Vec<_>>>()?,
        _ => Vec::new(),
    };
    let played = play.map(|(sm, p, work, mode)| {
        let progress = Progress::new(
            "poses",
            "k planar steps",
            (work.steps() / PLANAR_POINT_STEP_COST / 1e3).ceil() as u64,
            mode,
        );
        with_counted_progress(&progress, || played_basins(&analysis, &part, &sm, &p))
    });
    let bounds = unknown.then(|| Bounds::new(&part, field.as_ref()).scan(&region, SCAN));
    let mut averaged_skipped = None;
    let averaged = plate.and_then(|(sm, physics)| {
        let work = averaged_estimate(&part, &sm, analysis.equilibria.len());
        let mode = match req.runtime.admit_stated(&work) {
            Ok(mode) => mode,
            Err(e) => {
                let why = format!("the averaged field's check and refinement are skipped: {e}");
                crate::progress::say(&format!("poses: {why}"));
                averaged_skipped = Some(why);
                return None;
            }
        };
        let averaged = AveragedField::for_part(&part, sm, physics);
        let lifted = LiftedField::new(field.as_ref(), &part.body);
        let check = LiftCheck::run(&lifted, &averaged, &checked_poses(&analysis));
        let rests = rests_announced(&averaged, &analysis, mode);
        Some((check, rests))
    });
    let (lift_check, played_rests) = averaged.unzip();
    Ok(PoseOutcome {
        part,
        analysis,
        played,
        bounds,
        lift_check,
        played_rests,
        averaged_skipped,
        over_friction,
    })
}

/// The lifted analysis of `drops` drops of `part` in `field` with its
/// progress (`mode`) on stderr, one count per drop settled.
fn settled(
    part: &Part,
    field: &dyn PointField,
    region: Region,
    drops: usize,
    mode: crate::progress::ProgressMode,
    label: &str,
) -> PoseAnalysis {
    let progress = Progress::new(
        &format!("poses: drops settled along the lifted field{label}"),
        "drops",
        drops as u64,
        mode,
    );
    let analysis = analyse_with(part, field, region, drops, &|| progress.inc(1));
    progress.finish();
    analysis
}

/// The played rests on `averaged` from the lifted equilibria, with a progress line per
/// equilibrium on stderr.
fn rests_announced(
    averaged: &AveragedField,
    analysis: &PoseAnalysis,
    mode: crate::progress::ProgressMode,
) -> Vec<PlayedRest> {
    let n = analysis.equilibria.len().min(MAX_RESTS);
    let progress = Progress::new(
        "poses: played rests from the lifted equilibria",
        &format!("equilibria (each at most {MAX_NEWTON} Newton steps of 7 averaged twists)"),
        n as u64,
        mode,
    );
    let rests = played_rests(averaged, &analysis.equilibria, &analysis.region, &|| {
        progress.inc(1)
    });
    progress.finish();
    rests
}

/// `drops` in 1..=[`MAX_DROPS`] and `play` in (0, [`MAX_PLAY_S`]] s.
pub fn check_counts(drops: usize, play: Option<f64>) -> Result<()> {
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
    Ok(())
}
