//! Parts with planar extent on the plate: where a part comes to rest in a
//! field (`analysis`: the lifted field on (x, y, θ), its equilibria and
//! their basins, drops played by the planar simulator; its items are
//! re-exported here), and a motion that makes one asked pose the part's
//! stable one ([`design`]: a pose target designed and played). The design
//! reads the analysis, never the reverse.

mod analysis;
pub mod design;

pub use analysis::averaged::AveragedField;
pub use analysis::averaged::LiftCheck;
pub use analysis::averaged::{
    AVERAGING_STEPS, AVERAGING_TOLERANCE, CHECKED_POSES, JACOBIAN_STEP, JACOBIAN_STEP_RAD, LOCAL,
    MAX_AVERAGING_PERIODS,
};
pub use analysis::bounds::Bounds;
pub use analysis::check::check_twist;
pub use analysis::check::Measure;
#[cfg(test)]
pub(crate) use analysis::continua::eigenvalues;
pub use analysis::continua::Continuum;
pub use analysis::continua::{CurveEnd, Destination, Motion, Shape, ARRIVE, GAP};
pub(crate) use analysis::drops::nearest;
pub use analysis::drops::play_drop;
pub use analysis::drops::play_drops;
pub use analysis::drops::play_part;
pub use analysis::drops::played_basins;
pub use analysis::drops::DropEnd;
pub use analysis::drops::DropPlay;
pub use analysis::drops::PlayedBasins;
pub use analysis::drops::{DROP_REFINE_DEPTH, DROP_SAMPLES};
pub use analysis::equilibria::equilibria;
pub use analysis::equilibria::rests;
pub use analysis::equilibria::settle;
pub use analysis::equilibria::wrap;
pub use analysis::equilibria::End;
pub use analysis::equilibria::Equilibrium;
pub use analysis::equilibria::Region;
pub use analysis::lifted::GridField;
pub use analysis::lifted::LiftedField;
pub use analysis::lifted::PointField;
pub use analysis::lifted::Pose;
pub use analysis::lifted::Twist;
pub use analysis::request::check_counts;
pub use analysis::request::poses;
pub use analysis::request::AnalysisRequest;
pub use analysis::request::PoseOutcome;
pub use analysis::request::{MAX_PLAY_S, SCAN};
pub use analysis::rests::played_rests;
pub use analysis::rests::PlayedRest;
pub use analysis::rests::{RestOutcome, MAX_NEWTON, MAX_RESTS, NEWTON_STOP};
pub use analysis::run::analyse;
pub use analysis::run::drop_starts;
pub use analysis::run::PoseAnalysis;
pub(crate) use analysis::run::Uniform;
pub use analysis::run::MAX_DROPS;
pub use analysis::source::realised_field;
pub use analysis::source::schedule_field;
pub use analysis::source::REALISED_STRIDE;
pub use analysis::work::drops_estimate;

#[cfg(test)]
#[path = "../../tests/unit/pose_convention.rs"]
mod pose_convention_tests;
