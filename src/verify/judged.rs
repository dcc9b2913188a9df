//! What a verification judges by the design's own check
//! ([`crate::design::judge::realised_check`]): the friction sweep of
//! `--friction LO:HI:N` ([`crate::design::method::sweep_schedule`]) and the
//! export's replay of `--replay FILE`
//! ([`crate::design::replay::replay_check`]). Both are admitted — the
//! replay file read and refused where it is not the schedule's, the work
//! estimated against the long-run guard — before anything is played, and
//! run after the verification's own plays.

use std::path::Path;

use super::friction::FrictionArg;
use crate::design::method::{sweep_estimate, sweep_schedule};
use crate::design::replay::{check_replay, conform, replay_check, replay_estimate};
use crate::dynamics::Friction;
use crate::error::Result;
use crate::motion::held_csv;
use crate::motion::sample_hold::HoldSamples;
use crate::play::replay::ReplayCheck;
use crate::play::sensitivity::Sensitivity;
use crate::schedule::Schedule;
use crate::work::Runtime;

/// The judged checks a request asks for, admitted.
pub(crate) struct JudgedChecks {
    /// The frictions of the sweep (none without one).
    sweep: Vec<Friction>,
    /// The replay file and its name.
    replay: Option<(HoldSamples, String)>,
    /// The friction the schedule is played at (`--friction MU`).
    played: Option<Friction>,
}

/// The replay file at `path`: an export (with its header), or a
/// header-less accelerometer recording (t and six channels, or six at
/// `rate`) conformed to the export's grid ([`conform`]).
fn read_replay(schedule: &Schedule, path: &Path, rate: Option<f64>) -> Result<HoldSamples> {
    let (text, source) = (held_csv::read_text(path)?, path.display().to_string());
    if held_csv::is_recording(&text) {
        let recording = held_csv::parse_recording(&text, &source, rate)?;
        return conform(schedule, &recording, &source);
    }
    check_fingerprint(schedule, held_csv::fingerprint(&text), &source)?;
    held_csv::parse(&text, &source)
}

impl JudgedChecks {
    /// Reads and checks the replay file and admits both checks' estimates
    /// under `runtime`, before anything is played.
    pub(crate) fn admit(
        schedule: &Schedule,
        friction: Option<FrictionArg>,
        replay: Option<(&Path, Option<f64>)>,
        runtime: &Runtime,
    ) -> Result<JudgedChecks> {
        let sweep = friction.map(|f| f.sweep_values()).unwrap_or_default();
        if !sweep.is_empty() {
            runtime.admit(&sweep_estimate(schedule, sweep.len())?)?;
        }
        let replay = match replay {
            Some((p, rate)) => {
                let (file, source) = (read_replay(schedule, p, rate)?, p.display().to_string());
                check_replay(schedule, &file, &source)?;
                runtime.admit(&replay_estimate(schedule, file.rate)?)?;
                Some((file, source))
            }
            None => None,
        };
        let played = friction.and_then(|f| f.played());
        Ok(JudgedChecks {
            sweep,
            replay,
            played,
        })
    }

    /// The replay file read and its name, when one was asked for.
    pub(crate) fn replay_file(&self) -> Option<(&HoldSamples, &str)> {
        self.replay.as_ref().map(|(f, s)| (f, s.as_str()))
    }

    /// Runs the admitted checks on `schedule`: the sweep, then the replay.
    pub(crate) fn run(
        &self,
        schedule: &Schedule,
    ) -> Result<(Option<Sensitivity>, Option<ReplayCheck>)> {
        let sweep = if self.sweep.is_empty() {
            None
        } else {
            Some(sweep_schedule(schedule, &self.sweep)?)
        };
        let replay = match &self.replay {
            Some((file, source)) => Some(replay_check(schedule, file, source, self.played)?),
            None => None,
        };
        Ok((sweep, replay))
    }
}

/// Refuses a replay file whose header states another schedule's
/// fingerprint (`source` names it): its realised field would be compared
/// with this schedule's as if it were its export. A file without one
/// (written by hand or by an older `export`) is checked by its layout
/// alone ([`check_replay`]), and a note says so.
fn check_fingerprint(schedule: &Schedule, stated: Option<&str>, source: &str) -> Result<()> {
    let own = schedule.fingerprint();
    match stated {
        Some(f) if f != own => Err(crate::error::Error::invalid(
            source,
            format!(
                "is the export of another schedule: its header states the schedule fingerprint {f}, this schedule's is {own}; replay the file `platefield export` writes from this schedule.json"
            ),
        )),
        Some(_) => Ok(()),
        None => {
            crate::progress::say(&format!(
                "note: {source} states no schedule fingerprint (its header lacks \"# {}\"): only its layout (rows, sample time) is checked against this schedule",
                held_csv::FINGERPRINT.trim_end()
            ));
            Ok(())
        }
    }
}
