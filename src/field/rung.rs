//! Model rungs: the cheapest model whose field is within a tolerance of
//! the full model's ("model only what the scene needs").
//!
//! Rungs, cheapest first (switches of [`Model`], see [`crate::dynamics`]);
//! each rung's switches include the previous rung's:
//!
//! | rung | switches on | what it neglects |
//! |---|---|---|
//! | `paper` | none ([`Model::PAPER`]) | the part's motion within the cycle (kinematics frozen at the start point), centripetal, gravity tilt, Coriolis |
//! | `paper+moving` | moving | centripetal, tilt, Coriolis |
//! | `paper+moving+centripetal+tilt` | moving, centripetal, tilt | Coriolis |
//! | `full` | all ([`Model::FULL`]) | nothing |
//!
//! **The rule.** [`choose_rung`] computes the field at every rung at the
//! sample points of a grid, measures each one's relative L2 error against
//! `full` over the samples valid in both, ‖F_rung − F_full‖₂ / ‖F_full‖₂,
//! and picks the cheapest rung whose error is within the tolerance *and*
//! whose validity flags (contact lost, not converged, frozen assumption
//! broken) agree with `full`'s at every sample: a cheaper model that misses
//! a contact loss is not acceptable at any error. `full` is always
//! acceptable.
//!
//! The errors are measured, not predicted; the reason string adds the
//! physics that explains them, for example: an in-plane motion has N = g
//! exactly, so the terms that enter only the normal force vanish; a pure
//! translation has Ω = 0, so every plate point has the same acceleration and
//! all four rungs agree to the last bit.
//!
//! **What a cheaper rung saves.** Each switch off removes terms from
//! every step (the centripetal and Coriolis products, the tilted gravity),
//! and `paper` also evaluates the plate kinematics at one point for the
//! whole cycle, which is most of its saving; a steady-state velocity field
//! at a cheaper rung may need more cycles to converge, so a cheaper rung is
//! not always a faster one. The primitives that tilt the plate need at
//! least `paper+moving+centripetal+tilt` (`results/primitives/rungs.md`);
//! `platefield study rungs-auto` prints, per shipped design, the time of
//! the rung played against `full`'s (times are never written to files).
//!
//! Compute times are reported in [`RungResult::seconds`] (never
//! serialized): fields are bitwise independent of the thread count, times
//! are not.

use std::fmt::Write as _;
use std::time::Instant;

use serde::Serialize;

use super::{Field, FieldKind, FieldSettings, Grid, Validity};
use crate::dynamics::Model;
use crate::motion::Motion;
use crate::output::significant_percent;

/// Default tolerance: 2 % relative L2 error against the full model. Two
/// per cent is below what separates a primitive's field from its Table I
/// form (the fits in `results/primitives/table1.md` leave relative residuals
/// √(1 − R²) of 3–17 %) and above the integrator's own error at the default
/// 64 steps per cycle (worst 3e-3 over the library,
/// `results/library_speed.md`), so a rung is accepted only when the terms
/// it drops change the field by less than the basis can resolve, and never
/// rejected because of numerical noise.
pub const DEFAULT_RUNG_TOLERANCE: f64 = 0.02;

/// The rungs, cheapest first: name and model.
pub const RUNGS: [(&str, Model); 4] = [
    ("paper", Model::PAPER),
    (
        "paper+moving",
        Model {
            centripetal: false,
            tilt: false,
            coriolis: false,
            moving: true,
        },
    ),
    (
        "paper+moving+centripetal+tilt",
        Model {
            centripetal: true,
            tilt: true,
            coriolis: false,
            moving: true,
        },
    ),
    ("full", Model::FULL),
];

/// One rung's measurement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RungResult {
    /// Rung name.
    pub name: &'static str,
    /// Its model switches.
    pub model: Model,
    /// Relative L2 error against `full` over samples valid in both
    /// (NaN when there are none).
    pub error: f64,
    /// Samples valid in both.
    pub compared: usize,
    /// Samples whose validity flag differs from `full`'s.
    pub flags_differ: usize,
    /// Within the tolerance with identical validity flags.
    pub acceptable: bool,
    /// Wall time of the field computation (s); not deterministic, so
    /// never serialized.
    #[serde(skip)]
    pub seconds: f64,
}

impl RungResult {
    /// The error as a percentage, with the validity flags that differ
    /// from `full`'s when any do: "7.97 %", "0 (80 validity flags differ)".
    pub fn error_text(&self) -> String {
        let mut c = significant_percent(self.error);
        if self.flags_differ > 0 {
            let _ = write!(c, " ({})", flags(self.flags_differ));
        }
        c
    }
}

/// The choice and its evidence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RungReport {
    /// The chosen rung's name.
    pub rung: &'static str,
    /// Its model.
    pub model: Model,
    /// Its measured error against `full`.
    pub error: f64,
    /// The tolerance used.
    pub tolerance: f64,
    /// The field compared.
    pub kind: FieldKind,
    /// Every rung, cheapest first.
    pub rungs: Vec<RungResult>,
    /// Why this rung.
    pub reason: String,
}

/// Relative L2 difference of `a` against `reference` over the samples
/// valid in both, with the number of such samples; 0 when both vanish
/// there, NaN when no sample is valid in both.
///
/// ```
/// use platefield::basis::{Primitive, PrimitiveKind};
/// use platefield::field::rung::relative_l2;
/// use platefield::field::{Field, FieldKind, FieldSettings, Grid};
/// let grid = Grid { x: [-0.02, 0.02], y: [-0.02, 0.02], n: [3, 3] };
/// let motion = Primitive::new(PrimitiveKind::Trans).motion();
/// let f = Field::compute(&motion, &grid, FieldKind::Force, &FieldSettings::default(), &|| {});
/// assert_eq!(relative_l2(&f, &f), (0.0, 9));
/// ```
pub fn relative_l2(a: &Field, reference: &Field) -> (f64, usize) {
    let (mut num, mut den, mut n) = (0.0, 0.0, 0);
    for k in 0..reference.vectors.len().min(a.vectors.len()) {
        if a.validity[k] != Validity::Ok || reference.validity[k] != Validity::Ok {
            continue;
        }
        let (f, r) = (a.vectors[k], reference.vectors[k]);
        num += (f[0] - r[0]).powi(2) + (f[1] - r[1]).powi(2);
        den += r[0] * r[0] + r[1] * r[1];
        n += 1;
    }
    let e = if n == 0 {
        f64::NAN
    } else if den == 0.0 {
        if num == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        (num / den).sqrt()
    };
    (e, n)
}

/// True when the motion has no rotation at all (Ω = 0).
fn is_translation(motion: &Motion) -> bool {
    match motion {
        Motion::Screw(s) => s.rotation.is_zero(),
        Motion::Signals(s) | Motion::Ramped(crate::motion::Ramped { signals: s, .. }) => {
            [&s.angular.x, &s.angular.y, &s.angular.z]
                .iter()
                .all(|terms| terms.iter().all(|t| t.amplitude == 0.0))
        }
        Motion::Held(h) => (0..=h.len()).all(|k| {
            let s = h.state_at(k);
            s.velocity[3..]
                .iter()
                .chain(&s.pose[3..])
                .all(|x| *x == 0.0)
        }),
    }
}

/// "1 validity flag differs", "n validity flags differ".
fn flags(n: usize) -> String {
    if n == 1 {
        "1 validity flag differs".into()
    } else {
        format!("{n} validity flags differ")
    }
}

/// Computes `kind` for `motion` on `grid` at every rung (with `settings`
/// otherwise), measures each against `full` and picks the cheapest rung
/// within `tolerance` (the rule in the module docs).
///
/// ```
/// use platefield::basis::{Primitive, PrimitiveKind};
/// use platefield::field::rung::{choose_rung, DEFAULT_RUNG_TOLERANCE};
/// use platefield::field::{FieldKind, FieldSettings, Grid};
/// let grid = Grid { x: [-0.02, 0.02], y: [-0.02, 0.02], n: [3, 3] };
/// let motion = Primitive::new(PrimitiveKind::Trans).motion();
/// let r = choose_rung(&motion, &grid, FieldKind::Force, &FieldSettings::default(),
///                     DEFAULT_RUNG_TOLERANCE);
/// // A translation: every rung agrees with full to the last bit.
/// assert_eq!((r.rung, r.error), ("paper", 0.0));
/// ```
pub fn choose_rung(
    motion: &Motion,
    grid: &Grid,
    kind: FieldKind,
    settings: &FieldSettings,
    tolerance: f64,
) -> RungReport {
    let fields: Vec<(Field, f64)> = RUNGS
        .iter()
        .map(|(_, model)| {
            let s = FieldSettings {
                model: *model,
                ..*settings
            };
            let start = Instant::now();
            let f = Field::compute(motion, grid, kind, &s, &|| {});
            (f, start.elapsed().as_secs_f64())
        })
        .collect();
    let full = &fields[RUNGS.len() - 1].0;
    let rungs: Vec<RungResult> = RUNGS
        .iter()
        .zip(&fields)
        .map(|((name, model), (field, seconds))| {
            let (error, compared) = relative_l2(field, full);
            let flags_differ = field
                .validity
                .iter()
                .zip(&full.validity)
                .filter(|(a, b)| a != b)
                .count();
            let acceptable =
                *model == Model::FULL || (error <= tolerance && flags_differ == 0 && compared > 0);
            RungResult {
                name,
                model: *model,
                error,
                compared,
                flags_differ,
                acceptable,
                seconds: *seconds,
            }
        })
        .collect();
    let chosen = rungs
        .iter()
        .position(|r| r.acceptable)
        .unwrap_or(RUNGS.len() - 1);
    let c = &rungs[chosen];
    let mut reason = rung_reason(&rungs, chosen, tolerance);
    reason.push_str(physics_reason(motion));
    RungReport {
        rung: c.name,
        model: c.model,
        error: c.error,
        tolerance,
        kind,
        rungs,
        reason,
    }
}

/// Why the rung at `chosen` is kept: the cheapest within `tolerance` of
/// full, and what the cheaper ones missed by.
fn rung_reason(rungs: &[RungResult], chosen: usize, tolerance: f64) -> String {
    let c = &rungs[chosen];
    let mut reason = format!(
        "{} is the cheapest rung within {} of full (its error {}{})",
        c.name,
        significant_percent(tolerance),
        significant_percent(c.error),
        if c.name == "full" {
            ", by definition"
        } else {
            ", validity flags identical"
        }
    );
    let missed: Vec<String> = rungs[..chosen]
        .iter()
        .map(|r| format!("{} {}", r.name, r.error_text()))
        .collect();
    if !missed.is_empty() {
        let _ = write!(reason, "; cheaper rungs miss it: {}", missed.join(", "));
    }
    reason
}

/// Which of the model's terms the motion's kind makes vanish.
fn physics_reason(motion: &Motion) -> &'static str {
    if motion.is_in_plane() {
        if is_translation(motion) {
            "; in-plane motion: N = g exactly, so the normal-force terms (tilt, centripetal z) vanish, and with no rotation (Ω = 0) the centripetal and Coriolis terms vanish too and every \
             plate point has the same acceleration, so the frozen position is exact"
        } else {
            "; in-plane motion: N = g exactly, so the normal-force terms (tilt, centripetal z) vanish; the rotation about the vertical keeps in-plane centripetal and Coriolis terms"
        }
    } else {
        "; out-of-plane motion: the normal force varies over the cycle and the tilt, centripetal and \
         Coriolis terms enter it"
    }
}
