//! Parts with planar extent on the plate: where a part comes to rest in a
//! field (`analysis`: the lifted field on (x, y, θ), its equilibria and
//! their basins, drops played by the planar simulator; its items are
//! re-exported here), and a motion that makes one asked pose the part's
//! stable one ([`design`]: a pose target designed and played). The design
//! reads the analysis, never the reverse.

mod analysis;
pub mod design;

pub use analysis::averaged::AveragedTwist;
pub use analysis::averaged::LiftRow;
pub use analysis::averaged::{
    AveragedField, LiftCheck, Slip, AVERAGING_STEPS, AVERAGING_TOLERANCE, CHECKED_POSES,
    JACOBIAN_STEP, JACOBIAN_STEP_RAD, LOCAL, MAX_AVERAGING_PERIODS,
};
pub use analysis::bounds::Bounds;
pub use analysis::check::check_twist;
pub use analysis::check::Measure;
pub use analysis::check::TwistCheck;
#[cfg(test)]
pub(crate) use analysis::continua::eigenvalues;
pub use analysis::continua::{Continuum, CurveEnd, Destination, Motion, Shape, ARRIVE, GAP};
pub(crate) use analysis::drops::nearest;
pub use analysis::drops::play_drop;
pub use analysis::drops::play_drops;
pub use analysis::drops::play_part;
pub use analysis::drops::played_basins;
pub use analysis::drops::{DropEnd, DropPlay, PlayedBasins, DROP_REFINE_DEPTH, DROP_SAMPLES};
pub use analysis::equilibria::equilibria;
pub use analysis::equilibria::rests;
pub use analysis::equilibria::settle;
pub use analysis::equilibria::wrap;
pub use analysis::equilibria::Rests;
pub use analysis::equilibria::{End, Equilibrium, Region};
pub use analysis::lifted::{GridField, LiftedField, PointField, Pose, Twist};
pub use analysis::request::check_counts;
pub use analysis::request::poses;
pub use analysis::request::{AnalysisRequest, PoseOutcome, MAX_PLAY_S, SCAN};
pub use analysis::rests::played_rests;
pub use analysis::rests::{PlayedRest, RestOutcome, MAX_NEWTON, MAX_RESTS, NEWTON_STOP};
pub use analysis::run::analyse;
pub use analysis::run::drop_starts;
pub(crate) use analysis::run::Uniform;
pub use analysis::run::{PoseAnalysis, MAX_DROPS};
pub use analysis::source::realised_field;
pub use analysis::source::schedule_field;
pub use analysis::source::REALISED_STRIDE;
pub use analysis::work::{drops_estimate, settle_estimate};
