//! Parts with planar extent in a vibration field: the lifted field on the
//! part's configuration space (x, y, θ) ([`LiftedField`]; checked by the
//! [`AveragedField`] of the rigid part's own periodic slip), its equilibrium
//! poses and their stability ([`equilibria`]), the basins of the stable
//! ones predicted ([`settle`]) and played by the planar simulator
//! ([`played_basins`]), a designed schedule's point field
//! ([`schedule_field`]), and the poses that may rest for some support when
//! the support is unknown ([`Bounds`]).

mod averaged;
mod bounds;
mod check;
mod continua;
mod drops;
mod equilibria;
mod lifted;
mod refine;
mod request;
mod run;
mod source;
mod work;

pub use averaged::{
    checked_poses, Averaged, AveragedField, LiftCheck, LiftRow, Slip, AVERAGING_STEPS,
    AVERAGING_TOLERANCE, CHECKED_POSES, JACOBIAN_STEP, JACOBIAN_STEP_RAD, LOCAL,
    MAX_AVERAGING_PERIODS,
};
pub use bounds::Bounds;
pub use check::{check_twist, Measure, TwistCheck};
pub use continua::{eigenvalues, Continuum, CurveEnd, Destination, Motion, Shape, ARRIVE, GAP};
pub use drops::{
    nearest, play_drop, play_drop_tracked, play_drops, play_part, played_basins, DropEnd, DropPlay,
    PlanarPlayer, PlayedBasins, DROP_REFINE_DEPTH, DROP_SAMPLES,
};
pub use equilibria::{equilibria, rests, settle, settle_on, wrap, End, Equilibrium, Region, Rests};
pub use lifted::{GridField, LiftedField, PointField, Pose, Twist};
pub use refine::{refine, Refined, Refinement, MAX_NEWTON, MAX_REFINED, STOP};
pub use request::{check_counts, poses, PoseOutcome, PoseRequest, MAX_PLAY_S, SCAN};
pub(crate) use run::Uniform;
pub use run::{analyse, analyse_with, drop_starts, PoseAnalysis, MAX_DROPS};
pub use source::{realised_field, schedule_field, REALISED_STRIDE};
pub use work::{bounds_term, drops_estimate, played_points, settle_estimate, steps_per_period};
