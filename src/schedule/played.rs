//! What `design` records in `schedule.json` about how the design was chosen
//! and what it realises when played ([`Played`]); absent from schedules
//! written before it was recorded, and from schedules built in code.

use serde::{Deserialize, Serialize};

use crate::dynamics::Friction;
use crate::request::{FrictionSpec, ShakerSpec};

/// How `design` designs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum Method {
    /// A time-shared schedule of primitives.
    Sequence,
    /// One simultaneous six-signal motion.
    Synthesize,
    /// Both; the better realised one is kept.
    #[default]
    Auto,
    /// A schedule whose fit mixes a synthesized six-signal motion (one
    /// basis column, ramped in and out inside its segment) with the
    /// primitives: for targets no single motion reaches (see
    /// `design::method::mix_design`).
    Mix,
    /// A synthesized motion time-shared with its mirror image
    /// (`design::mirror`): a field that keeps its shape over the parts'
    /// friction, for targets symmetric under y → −y. `auto` designs it too
    /// when the target states a friction range and is symmetric.
    Mirror,
}

impl Method {
    /// The name used on the command line and in `schedule.json`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Sequence => "sequence",
            Method::Synthesize => "synthesize",
            Method::Auto => "auto",
            Method::Mix => "mix",
            Method::Mirror => "mirror",
        }
    }
}

impl std::fmt::Display for Method {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

/// Per-axis peak |plate-centre acceleration| a schedule commands (world
/// axes; see `super::export::motion_peaks`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxisPeaks {
    /// Linear x, y, z (m/s²).
    pub linear: [f64; 3],
    /// Angular x, y, z (rad/s²).
    pub angular: [f64; 3],
}

impl AxisPeaks {
    /// From the six peaks in signal order (linear x, y, z, angular x, y, z).
    pub(crate) fn from_six(p: [f64; 6]) -> AxisPeaks {
        AxisPeaks {
            linear: [p[0], p[1], p[2]],
            angular: [p[3], p[4], p[5]],
        }
    }
}

/// The judge of a design (`design::judge`): the realised field at frozen
/// points over the whole target region, against the target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Played {
    /// How the schedule was designed (never [`Method::Auto`]).
    pub method: Method,
    /// The method asked for.
    pub asked: Method,
    /// Why this design was kept (the rule and both candidates' numbers
    /// under `auto`).
    pub choice: String,
    /// Judge points played (a regular sub-grid of the target region, at
    /// least 9 × 9, or every sample).
    pub points: usize,
    /// Points whose part kept contact and counted (weight > 0).
    pub valid: usize,
    /// The strength the design predicts (fit or synthesis).
    pub predicted_strength: f64,
    /// Realised strength ŝ (least-squares scale of the realised field on
    /// the target); `None` when not finite. Over a friction range, the
    /// worst case's ([`Played::worst_friction`]).
    pub realised_strength: Option<f64>,
    /// Realised shape error ‖R − ŝ t‖/‖ŝ t‖; `None` when not finite. Over
    /// a friction range, the worst case's ([`Played::worst_friction`]).
    pub realised_shape_error: Option<f64>,
    /// Over the friction range the target states: the friction of the
    /// worst case, the row of the friction table with the largest realised
    /// shape error, whose numbers `realised_strength` and
    /// `realised_shape_error` are. `None` when the design is judged at its
    /// one friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_friction: Option<Friction>,
    /// Realised error against the prediction ‖R − s t‖/‖s t‖ at the
    /// design's own friction; `None` when not finite.
    pub realised_error: Option<f64>,
    /// Realised shape error above [`crate::fit::POOR_ERROR`] (over a
    /// friction range, at its worst), no valid point, or a part that lost
    /// contact in the region.
    pub poor: bool,
    /// Why it is POOR.
    pub notes: Vec<String>,
    /// Per-axis peaks the schedule commands.
    pub peaks: AxisPeaks,
    /// The shaker limits the design kept (the target's `shaker`, defaults
    /// filled in); `None` when the target gives none and the design is
    /// sequenced.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<ShakerSpec>,
    /// A pose target's part played from random drops (`pose::design`);
    /// `None` for every other target.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pose: Option<PosePlayed>,
    /// `escaped` of a schedule judged by moving parts (how many escaped
    /// the attractor): read so that such a schedule still loads, never
    /// written.
    #[serde(default, skip_serializing, rename = "escaped")]
    pub(crate) moving_escaped: Option<serde::de::IgnoredAny>,
}

/// A pose target's design played: the part dropped at random poses and
/// simulated by the planar simulator, each end compared with the asked
/// pose (modulo the part's symmetry) and with the stable poses the lifted
/// field predicts.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PosePlayed {
    /// The part file as the target names it.
    pub part: String,
    /// The pose asked for: x, y (m), θ (degrees).
    pub pose: [f64; 3],
    /// Order of the part's rotational symmetry (poses count modulo
    /// 360°/symmetry).
    pub symmetry: usize,
    /// The requested point field the kept schedule was designed for.
    pub field: String,
    /// Drops played.
    pub drops: usize,
    /// Simulated time per drop (s).
    pub duration_s: f64,
    /// The tolerance of "at the pose": mm and degrees.
    pub tolerance: [f64; 2],
    /// Fraction of the drops ending within the tolerance of the pose.
    pub pose_fraction: f64,
    /// Median over the drops of the time after which the part stays
    /// within the tolerance (s, at whole schedule periods); `None` when
    /// half of the drops or more never do.
    pub median_settle_s: Option<f64>,
    /// Drops that lost contact.
    pub lost: usize,
    /// The lifted field's stable poses (all of them, symmetric copies
    /// included) with their basins.
    pub stable: Vec<PoseBasin>,
    /// Stable poses modulo the part's symmetry: 1 when the pose is unique.
    pub distinct_stable: usize,
    /// The same drops played at the ends and middle of the part's friction
    /// range (`pose::design::friction`); `None` for an exact friction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub over_friction: Option<PoseOverFriction>,
}

/// A pose design's drops played over the part's friction range: the same
/// starts and play time at each friction, each judged against the lifted
/// field at that friction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseOverFriction {
    /// The range played (the target's, or the part's when the target
    /// states none).
    pub range: FrictionSpec,
    /// The least `pose_fraction` over the frictions played.
    pub worst_pose_fraction: f64,
    /// Each friction played, low to high (the range's ends and middle).
    pub at: Vec<PoseAtFriction>,
}

/// The drops of a pose design played at one friction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseAtFriction {
    /// The friction the drops and the lifted field were computed at.
    pub friction: Friction,
    /// Fraction of the drops ending within the tolerance of the pose.
    pub pose_fraction: f64,
    /// Median settle time (s), as [`PosePlayed::median_settle_s`].
    pub median_settle_s: Option<f64>,
    /// Drops that lost contact.
    pub lost: usize,
    /// The lifted field's stable poses at this friction, with their
    /// basins (lifted and played).
    pub stable: Vec<PoseBasin>,
    /// Stable poses modulo the part's symmetry.
    pub distinct_stable: usize,
    /// The lifted field's stable pose nearest the asked one at this
    /// friction: its distance (mm) and angle (degrees, modulo symmetry)
    /// from the asked pose; `None` when it has no stable pose.
    pub lifted_offset: Option<[f64; 2]>,
    /// That pose's decay rates, the negated real parts of its Jacobian's
    /// eigenvalues, slowest first (1/s).
    pub lifted_rates: Option<[f64; 3]>,
    /// Where the played drops rest near the asked pose: the median
    /// distance (mm) and signed angle (degrees, modulo symmetry) from it
    /// of the ends within 30° of it; `None` when none ends there.
    pub played_offset: Option<[f64; 2]>,
}

/// One stable pose of the lifted field and its basin.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseBasin {
    /// x, y (m), θ (degrees).
    pub pose: [f64; 3],
    /// Fraction of drops integrated along the lifted field that settle here.
    pub lifted: f64,
    /// Fraction of the played drops ending nearest to it.
    pub played: f64,
}
