//! Paper reproductions and benchmarks-as-commands, kept apart from the
//! product: each module is one study behind one subcommand and writes its
//! files under `results/`. Studies import product modules; no product module
//! imports a study.
//!
//! | module | command | writes |
//! |---|---|---|
//! | [`linesink`] | `platefield study linesink` | — (the section II one-axis shaker against eq. 17) |
//! | [`reproduce`] | `platefield study reproduce` | `linesink_fig3.{csv,svg}`, `linesink_terms.md`, `linesink_travel.csv`, `linesink_convergence.md` |
//! | [`primitives`], `table1` | `platefield study primitives` | `primitives/` fields, plots, `table1.md` |
//! | [`rung`] | `platefield study rungs` | `primitives/rungs.md` |
//! | [`rungs_auto`] | `platefield study rungs-auto` | `rungs_auto.md` (the automatic rung of every shipped design's segments) |
//! | [`speed`] | `platefield study speed` | `library_speed.md` |
//! | [`engine_speed`] | `platefield study engine-speed` | `engine_speed.{md,csv}`, `engine_speed_{force,velocity}.svg` |
//! | [`fit_quality`] | `platefield study fit-quality` | `fit_quality.md` |
//! | [`interaction`] | `platefield study interaction` | `verify/sink_interaction.md` |
//! | [`squeeze_order`] | `platefield study squeeze-order` | `verify/squeeze_trans_order.{md,csv}` |
//! | [`synthesis`] | `platefield study synthesis` | `synthesis.{md,csv}` |
//! | [`design_speed`] | `platefield study design-speed` | `design_speed.md` |
//! | [`poses`] | `platefield study poses` | `poses.md` |
//! | [`poses_friction`] | `platefield study poses-friction` | `poses_friction.md` (the pose designs at μ ± 20 %) |
//! | [`pose_family`] | `platefield study pose-family` | `pose_family.md`, `pose_family/` (pose design over a seeded family of random parts) |
//! | [`robust_family`] | `platefield study robust-family` | `robust_family.md` (robust design over a seeded family of random targets) |
//! | [`robust_knobs`] | `platefield study robust-knobs` | `robust_knobs.md` (the robust share's segment length and the frictions judged, over the family) |
//! | [`sort`] | `platefield study sort` | `sort.md` (where sorting by friction stops: time to sort against the friction contrast and the sinks' distance) |
//! | [`probes`] | `platefield study probes` | `probes.md` (the measurements behind numbers the docs state) |

pub mod design_speed;
pub mod engine_speed;
pub mod feeder;
pub mod fit_quality;
pub mod flight_strength;
pub mod interaction;
pub mod linesink;
pub mod pose_family;
pub mod poses;
pub mod poses_friction;
pub mod primitives;
pub mod probes;
pub mod reproduce;
pub mod robust;
pub mod robust_family;
pub mod robust_knobs;
pub mod robust_shipped;
pub mod rung;
pub mod rungs_auto;
pub mod sort;
pub mod speed;
pub mod squeeze_order;
pub mod synthesis;
pub(crate) mod table1;
pub mod work;

pub use work::{watched, watched_defaults};
