//! The model rung of each segment of a schedule, and the one rung a play of
//! the whole schedule can use ([`Schedule::rungs`]).
//!
//! Each moving segment's steady motion (between its ramps) is measured at
//! every rung on the sample grid by [`crate::field::rung::choose_rung`]
//! (the rule is stated there). A schedule is played under one model, so
//! the rung played is the cheapest rung acceptable for *every* moving
//! segment (within the tolerance with identical validity flags) among the
//! rungs that move the part: a play carries parts across the plate (the
//! swarm, the model check), and `paper`, which holds the kinematics at the
//! part's start point, is exact for a field at held points but not for a
//! part that travels centimetres, so it is reported per segment and never
//! played. `full` is always acceptable, so there is one. Rest segments
//! have no field and no rung.

use serde::{Deserialize, Serialize};

use super::Schedule;
use crate::dynamics::Model;
use crate::error::{Error, Result};
use crate::field::rung::{choose_rung, RungReport, RUNGS};
use crate::field::{FieldSettings, Grid};

/// One moving segment's rung.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SegmentRung {
    /// The segment's index in the schedule.
    pub segment: usize,
    /// Its label.
    pub label: String,
    /// Its choice and the evidence (every rung's error against `full`).
    pub report: RungReport,
    /// Its error against `full` at the rung played.
    pub played_error: f64,
}

/// The rungs of a schedule's segments and the rung played.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScheduleRungs {
    /// The rung played: the cheapest that moves the part and is
    /// acceptable for every moving segment.
    pub rung: &'static str,
    /// Its model.
    pub model: Model,
    /// The tolerance (relative L2 error against `full`).
    pub tolerance: f64,
    /// The sample grid the fields were compared on.
    pub grid: Grid,
    /// Every moving segment, in playing order.
    pub segments: Vec<SegmentRung>,
}

/// The rung choice as `schedule.json` records it (`"rungs"`, written by
/// `design --model auto`, absent otherwise): the rung the schedule is
/// played at (its `settings.model`), and per moving segment the cheapest
/// rung and the errors against `full`. An error is `null` where no sample
/// was valid in both fields.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordedRungs {
    /// The rung played, a name of [`RUNGS`]; the schedule's
    /// `settings.model` is its model.
    pub played: String,
    /// The tolerance (relative L2 error against `full`).
    pub tolerance: f64,
    /// The sample grid the fields were compared on.
    pub grid: Grid,
    /// Every moving segment, in playing order.
    pub segments: Vec<RecordedSegmentRung>,
}

/// One moving segment's rung in [`RecordedRungs`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RecordedSegmentRung {
    /// The segment's index in the schedule.
    pub segment: usize,
    /// Its label.
    pub label: String,
    /// Its cheapest rung within the tolerance, a name of [`RUNGS`].
    pub rung: String,
    /// That rung's error against `full`.
    pub error: Option<f64>,
    /// Its error against `full` at the rung played.
    pub played_error: Option<f64>,
}

/// `e` when it is a number (JSON has no NaN).
fn finite(e: f64) -> Option<f64> {
    e.is_finite().then_some(e)
}

/// The model of the rung named `name`, or an error at `at` naming the rungs.
fn rung_model(name: &str, at: &str) -> Result<Model> {
    RUNGS
        .iter()
        .find(|(n, _)| *n == name)
        .map(|(_, m)| *m)
        .ok_or_else(|| {
            let names: Vec<&str> = RUNGS.iter().map(|(n, _)| *n).collect();
            Error::invalid(
                at,
                format!("must be one of {}, got {name:?}", names.join(", ")),
            )
        })
}

impl ScheduleRungs {
    /// The choice as `schedule.json` records it.
    pub fn record(&self) -> RecordedRungs {
        RecordedRungs {
            played: self.rung.to_string(),
            tolerance: self.tolerance,
            grid: self.grid,
            segments: self
                .segments
                .iter()
                .map(|s| RecordedSegmentRung {
                    segment: s.segment,
                    label: s.label.clone(),
                    rung: s.report.rung.to_string(),
                    error: finite(s.report.error),
                    played_error: finite(s.played_error),
                })
                .collect(),
        }
    }
}

impl RecordedRungs {
    /// Checks the record against `schedule` (errors name `rungs.…`): rung
    /// names of [`RUNGS`], the played rung's model equal to
    /// `settings.model` (the model the schedule is played at), a tolerance
    /// ≥ 0, and each segment index a moving segment of the schedule.
    pub(crate) fn validate(&self, schedule: &Schedule) -> Result<()> {
        let model = rung_model(&self.played, "rungs.played")?;
        if model != schedule.settings.model {
            return Err(Error::invalid(
                "rungs.played",
                format!(
                    "the schedule is played at settings.model ({}), not at {}: the two must agree",
                    schedule.settings.model.name(),
                    self.played
                ),
            ));
        }
        crate::error::non_negative("rungs.tolerance", self.tolerance)?;
        for (i, s) in self.segments.iter().enumerate() {
            let at = format!("rungs.segments[{i}]");
            rung_model(&s.rung, &format!("{at}.rung"))?;
            if !schedule
                .segments
                .get(s.segment)
                .is_some_and(super::Segment::is_moving)
            {
                return Err(Error::invalid(
                    format!("{at}.segment"),
                    format!(
                        "must be the index of a moving segment (0..{}), got {}",
                        schedule.segments.len(),
                        s.segment
                    ),
                ));
            }
        }
        Ok(())
    }
}

impl Schedule {
    /// The cheapest model rung of each moving segment within `tolerance` of
    /// `full` on `grid`, for the schedule's field kind under `settings`
    /// (its model ignored), and the rung a play of the whole schedule uses
    /// (the module docs).
    ///
    /// ```
    /// use platefield::basis::{Primitive, PrimitiveKind};
    /// use platefield::field::{FieldKind, FieldSettings, Grid};
    /// use platefield::field::rung::DEFAULT_RUNG_TOLERANCE;
    /// use platefield::schedule::Schedule;
    /// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"),
    ///     "/results/sink/schedule.json")).unwrap();
    /// let s = Schedule::from_json_str(&text, "sink").unwrap();
    /// let grid = Grid { x: [-0.02, 0.02], y: [-0.02, 0.02], n: [3, 3] };
    /// let r = s.rungs(&grid, &s.settings, DEFAULT_RUNG_TOLERANCE);
    /// assert_eq!(r.segments.len(), s.segments.iter().filter(|g| g.is_moving()).count());
    /// assert!(r.segments.iter().all(|g| g.played_error <= DEFAULT_RUNG_TOLERANCE));
    /// // As schedule.json records it (`design --model auto`).
    /// let recorded = r.record();
    /// assert_eq!((recorded.played.as_str(), recorded.segments.len()), (r.rung, r.segments.len()));
    /// ```
    pub fn rungs(&self, grid: &Grid, settings: &FieldSettings, tolerance: f64) -> ScheduleRungs {
        let reports: Vec<(usize, &str, RungReport)> = self
            .segments
            .iter()
            .enumerate()
            .filter_map(|(i, s)| s.steady_motion().map(|m| (i, s.label.as_str(), m)))
            .map(|(i, label, motion)| {
                let r = choose_rung(&motion, grid, self.basis.kind, settings, tolerance);
                (i, label, r)
            })
            .collect();
        let played = (0..RUNGS.len())
            .filter(|&k| RUNGS[k].1.moving)
            .find(|&k| reports.iter().all(|(_, _, r)| r.rungs[k].acceptable))
            .unwrap_or(RUNGS.len() - 1);
        let segments = reports
            .into_iter()
            .map(|(segment, label, report)| SegmentRung {
                segment,
                label: label.to_string(),
                played_error: report.rungs[played].error,
                report,
            })
            .collect();
        ScheduleRungs {
            rung: RUNGS[played].0,
            model: RUNGS[played].1,
            tolerance,
            grid: *grid,
            segments,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shipped sequenced sink with a rung choice recorded by hand (no
    /// field computed): played at `paper+moving+centripetal+tilt`, one
    /// segment's errors, one of them not measured.
    fn recorded() -> Schedule {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/results/sequenced/sink/schedule.json"
        );
        let mut s = Schedule::load(path.as_ref()).unwrap();
        assert!(s.rungs.is_none() && !s.to_json().unwrap().contains("\"rungs\""));
        let (name, model) = RUNGS[2];
        s.settings.model = model;
        s.rungs = Some(RecordedRungs {
            played: name.into(),
            tolerance: 0.02,
            grid: Grid {
                x: [-0.04, 0.04],
                y: [-0.04, 0.04],
                n: [5, 5],
            },
            segments: vec![RecordedSegmentRung {
                segment: 1,
                label: s.segments[1].label.clone(),
                rung: name.into(),
                error: Some(0.00645),
                played_error: None,
            }],
        });
        s
    }

    /// A recorded choice is written under `"rungs"` (an error not measured
    /// as `null`) and loads back equal; a record that names no rung, whose
    /// played rung is not the model the schedule plays, with a negative
    /// tolerance or a segment that is not a moving one is refused naming
    /// its JSON path, and an unknown key too.
    #[test]
    fn a_recorded_choice_loads_back_and_a_bad_one_is_named() {
        let s = recorded();
        let text = s.to_json().unwrap();
        assert!(text.contains("\"played_error\": null"), "{text}");
        let back = Schedule::from_json_str(&text, "s.json").unwrap();
        assert_eq!(back.rungs, s.rungs);
        assert_eq!(back.settings.model, RUNGS[2].1);
        let value: serde_json::Value = serde_json::from_str(&text).unwrap();
        type Edit = fn(&mut serde_json::Value);
        let cases: [(Edit, &[&str]); 5] = [
            (
                |v| v["rungs"]["played"] = "cheap".into(),
                &["s.json: rungs.played", "paper+moving", "\"cheap\""],
            ),
            (
                |v| v["settings"]["model"]["coriolis"] = true.into(),
                &["s.json: rungs.played", "settings.model (full)"],
            ),
            (
                |v| v["rungs"]["tolerance"] = (-0.01).into(),
                &["s.json: rungs.tolerance", "≥ 0"],
            ),
            (
                |v| v["rungs"]["segments"][0]["segment"] = 99.into(),
                &["s.json: rungs.segments[0].segment", "moving segment"],
            ),
            (
                |v| v["rungs"]["segments"][0]["rung"] = "full+flight".into(),
                &["s.json: rungs.segments[0].rung", "paper+moving"],
            ),
        ];
        for (edit, needles) in cases {
            let mut v = value.clone();
            edit(&mut v);
            let e = Schedule::from_json_str(&v.to_string(), "s.json")
                .unwrap_err()
                .to_string();
            for n in needles {
                assert!(e.contains(n), "{e:?} should name {n:?}");
            }
        }
        let mut v = value.clone();
        v["rungs"]["rung"] = "full".into();
        let e = Schedule::from_json_str(&v.to_string(), "s.json")
            .unwrap_err()
            .to_string();
        assert!(e.contains("rungs") && e.contains("unknown field"), "{e}");
    }
}
