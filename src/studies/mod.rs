//! Paper reproductions and benchmarks-as-commands, kept apart from the
//! product: each module is one study behind one subcommand and writes its
//! files under `results/`. Studies import product modules; no product module
//! imports a study.
//!
//! | module | command | writes |
//! |---|---|---|
//! | [`linesink`] | `platefield linesink` | — (the section II one-axis shaker against eq. 17) |
//! | [`reproduce`] | `platefield reproduce` | `linesink_fig3.{csv,svg}`, `linesink_terms.md`, `linesink_travel.csv`, `linesink_convergence.md` |
//! | [`primitives`], `table1` | `platefield primitives` | `primitives/` fields, plots, `table1.md` |
//! | [`rung`] | `platefield rungs` | `primitives/rungs.md` |
//! | [`speed`] | `platefield speed` | `library_speed.md` |
//! | [`engine_speed`] | `platefield engine-speed` | `engine_speed.{md,csv}`, `engine_speed_{force,velocity}.svg` |
//! | [`fit_quality`] | `platefield fit-quality` | `fit_quality.md` |
//! | [`interaction`] | `platefield interaction` | `verify/sink_interaction.md` |
//! | [`squeeze_order`] | `platefield squeeze-order` | `verify/squeeze_trans_order.{md,csv}` |
//! | [`synthesis`] | `platefield synthesis` | `synthesis.{md,csv}` |
//! | [`design_speed`] | `platefield design-speed` | `design_speed.md` |
//! | [`poses`] | `platefield poses-study` | `poses.md` |
//! | [`poses_friction`] | `platefield poses-friction-study` | `poses_friction.md` (the pose designs at μ ± 20 %) |
//! | [`probes`] | `platefield probes` | `probes.md` (the measurements behind numbers the docs state) |

pub mod design_speed;
pub mod engine_speed;
pub mod fit_quality;
pub mod interaction;
pub mod linesink;
pub mod poses;
pub mod poses_friction;
pub mod primitives;
pub mod probes;
pub mod reproduce;
pub mod robust;
pub mod rung;
pub mod speed;
pub mod squeeze_order;
pub mod synthesis;
pub(crate) mod table1;
pub mod work;

pub use work::{watched, watched_defaults};
