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
pub use analysis::check::TwistCheck;
pub use analysis::check::{check_twist, Measure};
pub use analysis::continua::{
    eigenvalues, Continuum, CurveEnd, Destination, Motion, Shape, ARRIVE, GAP,
};
pub use analysis::drops::{
    nearest, play_drop, play_drops, play_part, played_basins, DropEnd, DropPlay, PlayedBasins,
    DROP_REFINE_DEPTH, DROP_SAMPLES,
};
pub use analysis::equilibria::Rests;
pub use analysis::equilibria::{
    equilibria, rests, settle, settle_on, wrap, End, Equilibrium, Region,
};
pub use analysis::lifted::{GridField, LiftedField, PointField, Pose, Twist};
pub use analysis::request::{check_counts, poses, AnalysisRequest, PoseOutcome, MAX_PLAY_S, SCAN};
pub use analysis::rests::{
    played_rests, PlayedRest, RestOutcome, MAX_NEWTON, MAX_RESTS, NEWTON_STOP,
};
pub(crate) use analysis::run::Uniform;
pub use analysis::run::{analyse, drop_starts, PoseAnalysis, MAX_DROPS};
pub use analysis::source::{realised_field, schedule_field, REALISED_STRIDE};
pub use analysis::work::{drops_estimate, settle_estimate};
