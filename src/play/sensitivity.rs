//! How a design degrades when the parts' friction is not the one it was
//! made for.
//!
//! The slip direction of a part leads the plate velocity by δ = asin(μg/A)
//! (A the in-plane acceleration amplitude), and a part sticks through the
//! part of the cycle where |a| < μN: so a friction error both turns a
//! field (a synthesized sink gains swirl) and scales it (a LineSink's
//! strength follows eq. 19's b ∝ μ(μ²g² − 3h²α²)). Real friction is rarely
//! known to better than ±20–30 %, so every design with a stated friction
//! is played again across it: each row is a `Judge` at one friction —
//! for a design, the judge (`design::judge`: the realised field at frozen
//! points over the whole region) against the target: realised strength ŝ
//! (s⁻¹ for a sink) and realised shape error ‖R − ŝt‖/‖ŝt‖. Over a range
//! the target states, the worst row is the design's headline
//! ([`Sensitivity::worst_row`]). The types and the sweep live here, below
//! `design` and `verify`, which both report them.

use std::fmt::Write as _;

use serde::Serialize;

use crate::dynamics::Friction;
use crate::error::Result;
use crate::field::FieldSettings;
use crate::request::{FrictionSpec, Target};

/// Frictions a sensitivity table holds per range: the ends, the middle
/// and the quarter points.
pub(crate) const SWEEP_VALUES: usize = 5;

/// A single stated friction is swept over ± this fraction of itself.
pub(crate) const AROUND_FRACTION: f64 = 0.2;

/// The design's realised measure at one friction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrictionRow {
    /// The parts' friction played.
    pub friction: Friction,
    /// Realised strength ŝ (`None`: no valid point).
    pub realised_strength: Option<f64>,
    /// Realised shape error ‖R − ŝt‖/‖ŝt‖ (`None`: not finite).
    pub realised_shape_error: Option<f64>,
    /// Start points whose part stayed on the plate and was counted.
    pub valid: usize,
    /// Start points played.
    pub points: usize,
}

/// Over what a sweep spans.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Span {
    /// The range the target states.
    TargetRange,
    /// ± `AROUND_FRACTION` of the single value the target states.
    AroundValue,
    /// Values the user asked for (`verify --friction`).
    Asked,
}

impl Span {
    /// In words, for a table's heading.
    pub fn describe(self) -> String {
        match self {
            Span::TargetRange => "over the target's friction range".into(),
            Span::AroundValue => format!(
                "over ±{:.0} % of the target's single friction value (labelled: the target states no range)",
                100.0 * AROUND_FRACTION
            ),
            Span::Asked => "at the frictions asked for".into(),
        }
    }
}

/// A friction sweep of one design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    /// What the frictions span.
    pub span: Span,
    /// The friction the design was made for (its schedule's).
    pub nominal: Friction,
    /// One row per friction, in the sweep's order.
    pub rows: Vec<FrictionRow>,
}

impl Sensitivity {
    /// The worst case: the row of the largest realised shape error (a row
    /// without one counts as largest; the first of equals). `None` without
    /// rows.
    pub fn worst_row(&self) -> Option<&FrictionRow> {
        let key = |r: &FrictionRow| r.realised_shape_error.unwrap_or(f64::INFINITY);
        self.rows
            .iter()
            .reduce(|a, b| if key(b) > key(a) { b } else { a })
    }

    /// The worst realised shape error over the rows (`None` if a row has
    /// none).
    pub(crate) fn worst_shape_error(&self) -> Option<f64> {
        self.rows
            .iter()
            .map(|r| r.realised_shape_error)
            .try_fold(0.0_f64, |m, e| e.map(|e| m.max(e)))
    }

    /// The weakest realised strength over the rows (`None` if a row has
    /// none).
    pub(crate) fn weakest_strength(&self) -> Option<f64> {
        self.rows
            .iter()
            .map(|r| r.realised_strength)
            .try_fold(f64::INFINITY, |m, s| s.map(|s| m.min(s)))
    }

    /// The table as markdown: one row per friction.
    pub fn table_md(&self) -> String {
        let mut md = format!(
            "The judge {} (the realised field at the design's judge points, parts held at their points), made for μ_s = {}, μ_k = {}:\n\n",
            self.span.describe(),
            self.nominal.stat,
            self.nominal.kinetic
        );
        md.push_str("| μ_s | μ_k | realised strength | realised shape error | parts counted |\n|---|---|---|---|---|\n");
        for r in &self.rows {
            let _ = writeln!(
                md,
                "| {:.3} | {:.3} | {} | {} | {} of {} |",
                r.friction.stat,
                r.friction.kinetic,
                r.realised_strength
                    .map_or_else(|| "n/a".into(), |s| format!("{s:.4}")),
                crate::output::percent(r.realised_shape_error.unwrap_or(f64::NAN), 1),
                r.valid,
                r.points
            );
        }
        let _ = writeln!(
            md,
            "\nWorst over these frictions: shape error {}, strength {}.",
            crate::output::percent(self.worst_shape_error().unwrap_or(f64::NAN), 1),
            self.weakest_strength()
                .map_or_else(|| "n/a".into(), |s| format!("{s:.4}"))
        );
        md
    }
}

/// What a judge measured under one physics.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Judged {
    /// Parts played.
    pub points: usize,
    /// Parts counted (stayed on the plate, weight > 0).
    pub valid: usize,
    /// Realised strength ŝ.
    pub realised_strength: f64,
    /// Realised shape error ‖R − ŝt‖/‖ŝt‖.
    #[serde(rename = "realised_shape_error")]
    pub shape_error: f64,
}

/// How a design is judged under given physics.
pub(crate) type Judge<'a> = dyn Fn(&FieldSettings) -> Result<Judged> + 'a;

/// `judge` at each of `frictions`, in order, with the rest of the physics
/// `base`'s.
///
/// # Errors
/// The judge's (the schedule cannot be played).
pub fn friction_sweep(
    base: &FieldSettings,
    frictions: &[Friction],
    judge: &Judge,
) -> Result<Vec<FrictionRow>> {
    frictions
        .iter()
        .map(|&friction| {
            let r = judge(&FieldSettings { friction, ..*base })?;
            let finite = |x: f64| x.is_finite().then_some(x);
            Ok(FrictionRow {
                friction,
                realised_strength: (r.valid > 0)
                    .then_some(r.realised_strength)
                    .and_then(finite),
                realised_shape_error: finite(r.shape_error),
                valid: r.valid,
                points: r.points,
            })
        })
        .collect()
}

/// The sensitivity table a design reports when its target states a
/// friction: [`SWEEP_VALUES`] values over the stated range, or over
/// ±[`AROUND_FRACTION`] of a single value; `None` when the target states
/// none (such designs report no sensitivity table). `base` is the design's physics.
///
/// # Errors
/// The judge's.
pub(crate) fn of_target(
    target: &Target,
    base: &FieldSettings,
    judge: &Judge,
) -> Result<Option<Sensitivity>> {
    let Some(spec) = target.friction else {
        return Ok(None);
    };
    let (span, swept) = if spec.is_exact() {
        (
            Span::AroundValue,
            FrictionSpec::around(spec.nominal(), AROUND_FRACTION),
        )
    } else {
        (Span::TargetRange, spec)
    };
    let rows = friction_sweep(base, &swept.values(SWEEP_VALUES), judge)?;
    Ok(Some(Sensitivity {
        span,
        nominal: base.friction,
        rows,
    }))
}
