//! What `design` records in `schedule.json` about how the design was chosen
//! and what it realises when played ([`Played`]); absent from schedules
//! written before it was recorded, and from schedules built in code.

use serde::{Deserialize, Serialize};

use crate::request::ShakerSpec;

/// Per-axis peak |plate-centre acceleration| a schedule commands (world
/// axes; see [`super::export::motion_peaks`]).
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
    pub fn from_six(p: [f64; 6]) -> AxisPeaks {
        AxisPeaks {
            linear: [p[0], p[1], p[2]],
            angular: [p[3], p[4], p[5]],
        }
    }
}

/// The realised check of a design: the schedule played on point parts with
/// the one realised measure ([`crate::play::measure`], via
/// `design::closed_loop::measure`), against the target.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Played {
    /// How the schedule was designed: `sequence` or `synthesize`.
    pub method: String,
    /// The method asked for: `sequence`, `synthesize` or `auto`.
    pub asked: String,
    /// Why this design was kept (the rule and both candidates' numbers
    /// under `auto`).
    pub choice: String,
    /// Start points played (a coarse grid over the target region).
    pub points: usize,
    /// Points whose part kept contact and counted (weight > 0).
    pub valid: usize,
    /// Points whose part ended farther from the target's attractor than it
    /// started, or left the region and lost contact beyond it (0 for
    /// targets without an attractor).
    pub escaped: usize,
    /// The strength the design predicts (fit or synthesis).
    pub predicted_strength: f64,
    /// Realised strength ŝ (least-squares scale of the realised field on
    /// the target); `None` when not finite.
    pub realised_strength: Option<f64>,
    /// Realised shape error ‖R − ŝ t‖/‖ŝ t‖; `None` when not finite.
    pub realised_shape_error: Option<f64>,
    /// Realised error against the prediction ‖R − s t‖/‖s t‖; `None`
    /// when not finite.
    pub realised_error: Option<f64>,
    /// Realised shape error above [`crate::fit::POOR_ERROR`], no valid
    /// point, a part that lost contact in the region, or a part escaping
    /// the attractor.
    pub poor: bool,
    /// Why it is POOR; also parts that left the region of a target without
    /// an attractor (stated, not POOR).
    pub notes: Vec<String>,
    /// Per-axis peaks the schedule commands.
    pub peaks: AxisPeaks,
    /// The shaker limits the design kept (the target's `shaker`, defaults
    /// filled in); `None` when the target gives none and the design is
    /// sequenced.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limits: Option<ShakerSpec>,
}
