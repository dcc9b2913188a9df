//! # platefield
//!
//! Which plate motion makes parts on the plate go where they are wanted?
//! platefield answers this for vibratory part feeders and 6-DOF shaker
//! tables. Forward, it simulates what a rigid plate vibrating with up to six
//! degrees of freedom does to parts resting on it: the friction fields of
//! Vose, Umbanhowar and Lynch, *Vibration-Induced Frictional Force Fields on
//! a Rigid Plate* (squeeze lines, sinks, whirlpools). Inverse, it turns a
//! requested field into a schedule of primitive plate motions and verifies
//! the schedule by simulating it. Units are SI throughout (m, s, rad).
//!
//! ## Designing a sink from Rust
//!
//! A target field, read like a target file (`targets/*.json`, see
//! [`request`]), is designed into a schedule of primitive plate motions by
//! [`inverse::run`], the one door of the inverse design: it designs by the
//! method asked for ([`design::Method`]; here the sequence of primitives),
//! plays every candidate on simulated point parts and keeps one with a
//! typed reason ([`design::Choice`]). Here on a small grid with few steps
//! per cycle, so that it runs in seconds:
//!
//! ```
//! use platefield::design::{self, BasisSection, DesignOptions, Method};
//! use platefield::inverse::{self, DesignOutcome};
//! use platefield::request::Target;
//! use platefield::work::Runtime;
//!
//! // Parts drawn to the plate's centre, sampled on a 7 × 7 grid (m).
//! let target = Target::from_json_str(
//!     r#"{"name": "sink", "field": {"kind": "sink"},
//!         "grid": {"x": [-0.03, 0.03], "y": [-0.03, 0.03], "n": [7, 7]}}"#,
//! )?;
//! let mut options = DesignOptions {
//!     method: Method::Sequence,
//!     basis: BasisSection {
//!         rotation_step_deg: 45.0, // primitives turned in steps of 45°
//!         cache_dir: None,         // build the primitive library, do not cache it
//!         ..BasisSection::default()
//!     },
//!     runtime: Runtime::QUIET, // no progress on stderr
//!     ..DesignOptions::default()
//! };
//! options.settings.numerics.steps_per_cycle = 16;
//! options.settings.phases = 4;
//! let DesignOutcome::Method(outcome) = inverse::run(&target, &options)? else {
//!     unreachable!("a target without classes or closed loop is designed by its method")
//! };
//! assert_eq!(outcome.choice, design::Choice::Asked(Method::Sequence));
//! let kept = outcome.kept();
//! assert_eq!(kept.method, Method::Sequence);
//!
//! // The schedule's predicted field has the target's shape within 5 %
//! // (relative L2 error of the fitted time fractions, and after rounding
//! // them to whole cycles), and a sink needs squeezing along two lines at
//! // least: primitives at two angles.
//! let schedule = &kept.schedule;
//! assert!(!schedule.poor_fit);
//! assert!(schedule.fit.relative_l2_error < 0.05, "{}", schedule.fit.relative_l2_error);
//! assert!(schedule.fit_quantized.relative_l2_error < 0.05);
//! let angles: std::collections::BTreeSet<i64> = schedule
//!     .segments
//!     .iter()
//!     .filter_map(|segment| segment.primitive.as_ref())
//!     .map(|p| p.rotation_deg.rem_euclid(180.0).round() as i64)
//!     .collect();
//! assert!(angles.len() >= 2, "{angles:?}");
//!
//! // Realised, not only predicted: point parts played from about 5 × 5
//! // start points kept contact and were measured.
//! let played = kept.played();
//! assert!(played.points >= 9 && played.valid >= 3, "{played:?}");
//! # Ok::<(), platefield::Error>(())
//! ```
//!
//! ## Data path
//!
//! ```text
//! scene ─► motion ─► dynamics ─► field ─► basis ─► fit ─► schedule ─► play ─► verify
//!  target ────────────────────────────────────────┘
//! ```
//!
//! Each physical statement is made once, in the module that implements it:
//!
//! | stage | module | what it states |
//! |---|---|---|
//! | inputs | [`scene`], [`request`] (target files) | a plate motion with its physics and grid; a requested field (kinds, grid, mask, attractor) |
//! | kinematics | [`motion`] | world and plate frames; the plate's velocity and acceleration at a plate point; gravity in the plate frame. The screw primitive in `motion::screw`, general six-signal motion in `motion::signals` (ramped in and out of a mixed schedule's segment in [`motion::Ramped`]), waveforms in `motion::waveform`; repeated evaluation with constants worked out once in `motion::PreparedMotion`, sin and cos by angle addition from tabulated nodes in `motion::trig` |
//! | dynamics | [`dynamics`] | a point part's equations: the effective gravity N, Coulomb stick and slip, contact loss, the terms the paper drops as [`dynamics::Model`] switches. The simulator's settings, kinematics, forces and RK4 step in [`dynamics::Simulator`], exact stick-slip events in its `advance` ([`dynamics::Simulator::advance`]), one type per slip scheme behind one trait (`dynamics::scheme`): implicit steps where a 2-D slip's direction is stiff ([`dynamics::SlipScheme::Stiff`], opt-in), 2-D swings past u = 0 in regularised time ([`dynamics::SlipScheme::Regularised`], the default), the closed-form frozen flow that finishes a 2-D stop in `dynamics::frozen`, the periodic orbit (and its stall test) in `dynamics::steady`, time-only kinematics tabulated once per field in `dynamics::KinematicsTable`, rectangles in `dynamics::planar` |
//! | fields | [`field`] | the zero-velocity force field, the steady-state velocity field (frozen or free), per-sample validity (including non-finite samples); one point simulated per family of points the motion moves alike ([`motion::Invariance`], [`field::Orbits`]) |
//! | basis | [`basis`] | the paper's eight primitives and their defaults ([`basis::primitives`]), rotated and shifted copies by symmetry ([`basis::symmetry`]), the on-disk cache |
//! | fit | [`fit`] | the inverse problem: time fractions w ≥ 0, Σw ≤ 1, the fit modes, how each is solved and verified |
//! | schedule | [`schedule`] | time fractions as whole cycles (`schedule::quantize`); the six controller signals ([`schedule::export`]) |
//! | design | [`inverse`], [`design`] | [`inverse::run`], the one door (a target file read by [`inverse::TargetFile`]: a field designed by [`design`], a part's pose by [`pose::design`]); the open-loop pipeline, the closed loop ([`design::closed_loop`]), refinement of a design's primitives by re-simulation ([`design::refine`]), the played polish of a synthesized motion ([`design::polish`]), and `--method` ([`design::method`]): sequence, synthesize or mix (a synthesized motion as one more basis column, [`design::basis::ColumnSource`]), every candidate played against the target, the POOR rule ([`fit::POOR_ERROR`]) and the choice |
//! | synthesis | [`synth`] | one simultaneous six-signal motion: shaker limits, the averaged-friction seed, the in-plane ratchet start for transport ([`synth::transport`]), refinement by re-simulation |
//! | play, verify | [`play`], [`verify`] | a schedule's exact plate trajectory, the rule at the joins, rest in closed form; realised against predicted (one motion alone: its drift-lag-corrected steady state per cycle, [`play::lag`]; a warm-up that outlasts the start-up transient, `play::settle`); where parts end up |
//! | poses | [`pose`] | a planar part in a field (analysis; the design of a pose target in [`pose::design`]): the lifted field on (x, y, θ) (the point field integrated over the support, [`pose::LiftedField`]), its equilibria and their stability, basins from drops integrated along it or played ([`pose::played_basins`]); the averaged field ([`pose::AveragedField`]: the rigid part's own periodic slip, the period map of the played schedule), which checks the lifted field and refines its equilibria onto the played rests ([`pose::played_rests`]) |
//! | work | [`work`] | the work estimate (RK4 part steps at a stated rate) every long command makes first, refusing above 10 min unless `--allow-long` |
//!
//! ## The workspace around the library
//!
//! This crate is the pipeline only. Beside it: `platefield-report` (the
//! report writers and SVG plots a design, a verification or a study
//! writes), `platefield-studies` (the laboratory: the paper's results
//! reproduced — eq. 17 of section II, Table I, the interaction of
//! sequenced primitives, the order study of section V —, model rungs,
//! speed against error) and `platefield-cli` (the `platefield` command,
//! `platefield study <name>` for the studies). They depend on this crate,
//! never the reverse.
//!
//! ## Sequencing: what combines
//!
//! A schedule plays primitives one after another, never at once, so the
//! question the inverse design rests on is what a sequence produces. Parts
//! on a vibrating plate are overdamped: their mean velocity relaxes to the
//! local steady state within a few cycles. A schedule therefore produces,
//! approximately, the *time-weighted combination of its primitives'
//! steady-state velocity fields*, Σ wᵢ Vᵢ; this is the prediction every fit
//! makes and every verification checks. Force fields do not combine this
//! way: a zero-velocity force field measured over a window of several cycles
//! shrinks as the window grows (the part stops accelerating once it reaches
//! its steady velocity), so it is not the time-weighted mean of its
//! segments' one-cycle force fields. Steady-state velocity fields are hence
//! the default basis; force fields remain available.
//!
//! The combination is only approximate, and worst for short segments: each
//! segment starts off its own periodic orbit and spends a cycle or so
//! reaching it. For a Sink from two orthogonal LineSinks the realised field
//! is far off the prediction at 1 cycle per segment and approaches it as
//! the segments lengthen (`results/verify/sink_interaction.md`, written by
//! `platefield study interaction`; `schedule::quantize` states the numbers
//! its default minimum of cycles per segment rests on).
//! Hence the design's rules: primitives start and end each cycle at rest in
//! the home pose (rest-to-rest waveforms, [`basis::primitives`]), a schedule
//! has a minimum number of cycles per segment (`schedule::quantize`), the
//! order of segments and rest at the joins are chosen by simulation
//! ([`design::order`]), and the closed loop measures the real combination
//! and feeds it back into the fit ([`design::closed_loop`]). At a join the
//! plate velocity may jump; the part's inertial velocity is continuous
//! ([`play`]).
#![warn(missing_docs)]
#![deny(rustdoc::broken_intra_doc_links, rustdoc::private_intra_doc_links)]

pub mod basis;
pub mod calibrate;
pub mod design;
pub mod dynamics;
pub mod error;
pub mod field;
pub mod fit;
pub mod input;
pub mod inverse;
pub(crate) mod linalg;
pub mod motion;
pub mod output;
pub mod part;
pub mod play;
pub mod pose;
pub mod progress;
pub mod request;
pub(crate) mod rng;
pub mod scene;
pub mod schedule;
pub mod synth;
pub mod verify;
pub mod work;

pub use error::{Error, Result};
