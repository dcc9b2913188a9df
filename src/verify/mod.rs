//! Closed-loop verification of schedules: the prediction of
//! [what combines under sequencing](crate#sequencing-what-combines) checked
//! by playing the schedule: realised against predicted, where a swarm of
//! parts ends up, rectangles.
//!
//! A [`crate::schedule::Schedule`] is played exactly by [`crate::play`];
//! the realised field is compared with the prediction by the one measure of
//! [`crate::play::measure`]; `swarm` plays many point parts over the
//! target region (where they end up, how long they take); [`rectangles`]
//! plays uniform rectangles (planar parts); [`strength`] measures the
//! realised strength against the target; [`run()`] is the
//! `platefield verify` command. Nothing here depends on how the schedule
//! was designed; a friction sweep and an export's replay are judged by the
//! design's own check (`crate::design::method::realised_check`).

pub mod friction;
mod judged;
pub mod rectangles;
pub mod run;
pub mod sort_play;
pub mod strength;
pub(crate) mod swarm;

pub use rectangles::{
    play_rectangle, PoseSample, RectangleFailure, RectangleOptions, RectangleRun, RectangleSummary,
};
pub use run::{run, verify_schedule_file, Duration, VerifyReport, VerifyRequest};
pub use swarm::{run_swarm, Swarm, SwarmOptions, SwarmPart};
