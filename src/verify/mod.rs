//! Closed-loop verification of schedules: the prediction of
//! [what combines under sequencing](crate#sequencing-what-combines) checked
//! by playing the schedule: realised against predicted, where a swarm of
//! parts ends up, rectangles.
//!
//! A [`crate::schedule::Schedule`] is played exactly by [`crate::play`].
//! Three numbers, each under its own name:
//! - **the model check**: moving parts' realised field against the
//!   design's prediction, by the measure of [`crate::play::measure`];
//! - **the swarm**: many point parts over the target region (where they
//!   end up, how long they take), and [`rectangles`] (planar parts);
//! - **the judge** of the schedule against the target it records
//!   ([`crate::design::judge`], as `design` judges): the realised field at
//!   frozen points over the whole region; a friction sweep and an
//!   export's replay are judged by it too.
//!
//! `run()` is the `platefield verify` command. Nothing here depends on
//! how the schedule was designed.

pub mod friction;
mod judged;
pub mod rectangles;
pub mod run;
pub mod sort_play;
pub(crate) mod swarm;

#[cfg(test)]
pub(crate) use rectangles::play_rectangle;
#[cfg(test)]
pub(crate) use rectangles::PoseSample;
pub use rectangles::RectangleFailure;
#[cfg(test)]
pub(crate) use rectangles::RectangleOptions;
#[cfg(test)]
pub(crate) use run::run;
pub use run::verify_schedule_file;
pub use run::Duration;
pub use run::VerifyRequest;
pub use swarm::run_swarm;
pub use swarm::{Swarm, SwarmOptions};
