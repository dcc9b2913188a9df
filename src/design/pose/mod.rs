//! Pose targets (issue 28): a motion whose lifted field makes one pose of a
//! part the unique stable equilibrium, played on the part from random
//! drops.
//!
//! 1. **Request** ([`PoseRequest`]): the target file with
//!    `"field": {"kind": "pose", "part": …, "pose": [x, y, θ°]}`.
//! 2. **Search** ([`search`]): candidate requested point fields, each
//!    designed by the sequenced fit and placed so that its lifted field's
//!    stable equilibrium nearest the pose sits on it; the best kept
//!    ([`search::best`]: a unique stable pose modulo the part's symmetry
//!    first, then the pose error, then the slowest decay rate).
//! 3. **Design**: the kept candidate's target designed by
//!    [`design_by_method`] with [`Method::Sequence`] (its point parts
//!    played as for every design).
//! 4. **Played** ([`play`]): the part dropped at `drops` random poses
//!    (centres uniform over the region inset by the part's radius, angles
//!    uniform: [`crate::pose::drop_starts`]) and simulated by the planar
//!    simulator; `"pose_fraction"` is the fraction ending within
//!    [`TOL_MM`] and [`TOL_DEG`] of the pose modulo its symmetry, recorded
//!    in `schedule.json`'s `played.pose` ([`crate::schedule::PosePlayed`])
//!    with the median settle time and each stable pose's basin, predicted
//!    (along the lifted field) and played.

pub mod correct;
pub mod play;
pub mod request;
pub mod search;

pub use request::PoseRequest;
pub use search::{Family, Trial};

use crate::design::{design_by_method, DesignOptions, Method, MethodDesign};
use crate::error::{Error, Result};
use crate::play::ScheduleMotion;
use crate::pose::{analyse, schedule_field, PoseAnalysis};

/// "At the pose": within this distance (mm) …
pub const TOL_MM: f64 = 1.0;
/// … and this angle (degrees), modulo the part's symmetry.
pub const TOL_DEG: f64 = 3.0;
/// Drops `design` plays by default.
pub const DROPS: usize = 100;
/// Drops integrated along the lifted field for the predicted basins.
pub const LIFTED_DROPS: usize = 200;

/// A designed pose target.
#[derive(Debug, Clone)]
pub struct PoseDesign {
    /// The request.
    pub request: PoseRequest,
    /// Every candidate placed (or why it could not be designed).
    pub trials: Vec<(Family, std::result::Result<Trial, String>)>,
    /// Index of the kept trial.
    pub kept: usize,
    /// The kept candidate as placed again on played probes.
    pub corrected: Trial,
    /// The rounds of that placement.
    pub rounds: Vec<correct::Round>,
    /// The kept candidate designed and played on point parts; its kept
    /// schedule's `played.pose` holds the part's played drops.
    pub method: MethodDesign,
    /// The lifted field of the kept schedule: equilibria and predicted basins.
    pub analysis: PoseAnalysis,
}

impl PoseDesign {
    /// The kept trial.
    pub fn kept_trial(&self) -> &Trial {
        match &self.trials[self.kept].1 {
            Ok(t) => t,
            Err(_) => unreachable!("the kept trial was designed"),
        }
    }
}

/// Designs the pose target `req` (module docs), playing `drops` drops.
///
/// # Errors
/// No candidate could be designed (the first reason); the errors of the
/// kept design and of its schedule's field.
///
/// ```no_run
/// use platefield::design::pose::{design_pose, PoseRequest, DROPS};
/// let req = PoseRequest::load(std::path::Path::new("targets/pose_rectangle.json"))?.unwrap();
/// let d = design_pose(&req, &Default::default(), DROPS)?;
/// let played = d.method.kept().schedule.played.as_ref().unwrap().pose.as_ref().unwrap();
/// println!("{:.0} % at the pose", 100.0 * played.pose_fraction);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn design_pose(req: &PoseRequest, opts: &DesignOptions, drops: usize) -> Result<PoseDesign> {
    let quiet = DesignOptions {
        quiet: true,
        ..opts.clone()
    };
    let trials: Vec<(Family, std::result::Result<Trial, String>)> = search::search(req, &quiet)
        .into_iter()
        .map(|(f, t)| (f, t.map_err(|e| e.to_string())))
        .collect();
    let designed: Vec<Trial> = trials.iter().filter_map(|(_, t)| t.clone().ok()).collect();
    let n = req.part.symmetry();
    let Some(best) = search::best(&designed, &req.pose, n) else {
        let why = trials.iter().find_map(|(_, t)| t.clone().err());
        return Err(Error::Physical(format!(
            "no candidate field for the pose could be designed: {}",
            why.unwrap_or_default()
        )));
    };
    let kept = trials
        .iter()
        .position(|(f, t)| *f == best.family && t.is_ok())
        .unwrap_or(0);
    let (best, rounds) = correct::correct(req, &quiet, best.clone())?;
    let best = &best;
    let mut method = design_by_method(&best.target, &quiet, &opts.synthesis, Method::Sequence)?;
    let schedule = &method.kept().schedule;
    let grid = req.target.grid.unwrap_or(crate::field::Grid::DEFAULT);
    let field = schedule_field(schedule, &grid)?;
    let analysis = analyse(&req.part, &field, req.region, LIFTED_DROPS);
    let sm = ScheduleMotion::from_schedule(schedule)?;
    let played = play::play(req, &sm, &schedule.settings, (&analysis, best), drops);
    let chosen = method.chosen;
    if let Some(p) = method.candidates[chosen].schedule.played.as_mut() {
        p.pose = Some(played);
    }
    Ok(PoseDesign {
        request: req.clone(),
        trials,
        kept,
        corrected: best.clone(),
        rounds,
        method,
        analysis,
    })
}
