//! Realised from the file: a design's exported signals played on its
//! parts, beside the schedule's own play.
//!
//! A design is judged by what parts do when its signals are played
//! (the judge, `super::judge::realised_check`: a point part held at each
//! of the judge's points over the whole region, played through whole
//! schedule periods until periodic; realised strength ŝ = the
//! least-squares scale against the target and realised shape error
//! ‖R − ŝt‖/‖ŝt‖). Here that same measure
//! is taken twice under the same physics: of the schedule's motions
//! (**played**) and of the file a controller plays (**replayed**: its held
//! samples integrated exactly from rest at home and cut into the
//! schedule's segments, [`crate::play::replay`]). Only the plate's
//! trajectory differs, so the two agree to what holding the samples
//! changes — second order in ωΔt (`crate::motion::Held`) — and a file
//! that is not the schedule's (a channel's sign flipped, another design's
//! export) does not agree.

use super::judge::judge_check;
use super::method::recorded_target;
use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::field::FieldSettings;
use crate::motion::held_csv::{self, Recording};
use crate::motion::sample_hold::{self, CentreState, HoldSamples};
use crate::motion::{Held, Motion};
use crate::play::replay::{replay_motion, ReplayCheck};
use crate::play::sensitivity::{friction_sweep, Judged};
use crate::play::ScheduleMotion;
use crate::request::{SampledTarget, Target};
use crate::schedule::export::{export, DEFAULT_STEADY_CYCLES, RAMP_CYCLES};
use crate::schedule::Schedule;
use crate::work::Estimate;

/// The rate `platefield export` samples at by default (Hz).
pub(crate) const EXPORT_RATE: f64 = 10_000.0;

/// The judge of the replayed trajectory `sm` under `settings`.
pub fn judge_replay(
    target: &Target,
    sampled: &SampledTarget,
    sm: &ScheduleMotion,
    settings: &FieldSettings,
) -> Judged {
    let (plays, r) = super::judge::judge(target, sampled, sm, settings, None);
    Judged {
        points: plays.len(),
        valid: r.valid,
        realised_strength: r.realised_strength,
        shape_error: r.shape_error,
    }
}

/// `schedule`'s export as `platefield export` writes it (at
/// `EXPORT_RATE`, [`DEFAULT_STEADY_CYCLES`] steady cycles), read back
/// from its CSV text.
///
/// # Errors
/// The schedule cannot be exported.
pub fn exported(schedule: &Schedule) -> Result<HoldSamples> {
    let e = export(schedule, EXPORT_RATE, DEFAULT_STEADY_CYCLES)?;
    held_csv::parse(&e.to_csv(), "export")
}

/// An accelerometer recording of `schedule` played (any rate, noisy) as
/// the file its export would be, so that [`replay_check`] judges it: the
/// recording is held sample by sample (its velocity integral exact,
/// piecewise linear), averaged cycle by cycle onto the export's grid at
/// `EXPORT_RATE` (the mean acceleration over each grid interval, cycle
/// after cycle, averaged: synchronous averaging, which divides white noise
/// by the square root of the cycles recorded) and each channel's mean over
/// the cycle removed (a periodic motion changes no velocity per cycle, so
/// what is left of the noise cannot make the looped cycle drift).
///
/// * **A steady six-signal design**: the recording is taken to follow the
///   export's layout, and its cycles after the [`RAMP_CYCLES`]-cycle
///   ramp-in and before the ramp-out (all after the ramp-in when shorter)
///   are averaged into one steady cycle, started in its own zero-mean
///   steady state, and written as the export would write that cycle:
///   ramped in, [`DEFAULT_STEADY_CYCLES`] steady cycles, ramped out.
/// * **A looped schedule period**: every whole period recorded is
///   averaged into one, from rest at home.
///
/// ```no_run
/// use platefield::design::replay::{conform, replay_check};
/// use platefield::motion::held_csv::parse_recording;
/// use platefield::schedule::Schedule;
///
/// let schedule = Schedule::load("results/synthesized/sink/schedule.json".as_ref()).unwrap();
/// let text = std::fs::read_to_string("measured.csv").unwrap();
/// let recording = parse_recording(&text, "measured.csv", Some(5000.0)).unwrap();
/// let file = conform(&schedule, &recording, "measured.csv").unwrap();
/// println!("{}", replay_check(&schedule, &file, "measured.csv", None).unwrap().strength_gap());
/// ```
///
/// # Errors
/// The schedule cannot be exported; the recording holds no whole cycle
/// (after the ramp-in) or period (names `source`).
pub fn conform(schedule: &Schedule, recording: &Recording, source: &str) -> Result<HoldSamples> {
    let e = export(schedule, EXPORT_RATE, DEFAULT_STEADY_CYCLES)?;
    let (step, per_cycle) = (e.samples.dt, e.samples.samples_per_period);
    // The recording's velocity integral at `t`, its samples held.
    let dt = recording.dt;
    let mut nodes = vec![[0.0; 6]];
    for a in &recording.samples {
        let last = nodes[nodes.len() - 1];
        nodes.push(std::array::from_fn(|i| last[i] + a[i] * dt));
    }
    let span = dt * recording.samples.len() as f64;
    let velocity = |t: f64| -> [f64; 6] {
        let k = ((t / dt).floor().max(0.0) as usize).min(recording.samples.len() - 1);
        let tau = t - k as f64 * dt;
        std::array::from_fn(|i| nodes[k][i] + recording.samples[k][i] * tau)
    };
    // Mean accelerations of `len` grid intervals from `t0`, averaged over
    // `count` repeats `every` seconds apart, each channel's mean removed.
    let average = |t0: f64, len: usize, every: f64, count: usize| -> Vec<[f64; 6]> {
        let mut out = vec![[0.0; 6]; len];
        for c in 0..count {
            let start = t0 + every * c as f64;
            for (j, o) in out.iter_mut().enumerate() {
                let (a, b) = (
                    velocity(start + step * j as f64),
                    velocity(start + step * (j + 1) as f64),
                );
                for i in 0..6 {
                    o[i] += (b[i] - a[i]) / step / count as f64;
                }
            }
        }
        for i in 0..6 {
            let mean = out.iter().map(|a| a[i]).sum::<f64>() / len as f64;
            out.iter_mut().for_each(|a| a[i] -= mean);
        }
        out
    };
    let too_short = |what: String| {
        Error::invalid(
            source,
            format!("{span:.6} s recorded at {dt:.6e} s: {what}"),
        )
    };
    let Some(steady) = e.ramped else {
        let period = step * e.samples.samples.len() as f64;
        let count = (span / period + 1e-9).floor() as usize;
        if count == 0 {
            return Err(too_short(format!(
                "not one whole schedule period of {period:.6} s"
            )));
        }
        return Ok(HoldSamples {
            samples: average(0.0, e.samples.samples.len(), period, count),
            ..e.samples
        });
    };
    let cycle = step * per_cycle as f64;
    let ramp = cycle * f64::from(RAMP_CYCLES);
    let inside = ((span - 2.0 * ramp) / cycle + 1e-9).floor();
    let count = if inside >= 1.0 {
        inside
    } else {
        ((span - ramp) / cycle + 1e-9).floor()
    };
    if count < 1.0 {
        return Err(too_short(format!(
            "not one whole cycle of {cycle:.6} s after the {RAMP_CYCLES}-cycle ramp-in"
        )));
    }
    let samples = average(ramp, per_cycle, cycle, count as usize);
    // The zero-mean steady state at the cycle's start: node velocities
    // v_j = v0 + Σ_{i<j} a_i Δ and trapezoidal poses with mean zero.
    let mut v = vec![[0.0; 6]];
    for a in &samples[..per_cycle - 1] {
        let last = v[v.len() - 1];
        v.push(std::array::from_fn(|i| last[i] + a[i] * step));
    }
    let mut x = vec![[0.0; 6]];
    for w in v.windows(2) {
        let last = x[x.len() - 1];
        x.push(std::array::from_fn(|i| {
            last[i] + (w[0][i] + w[1][i]) * step / 2.0
        }));
    }
    let mean =
        |rows: &[[f64; 6]], i: usize| rows.iter().map(|r| r[i]).sum::<f64>() / rows.len() as f64;
    let v0: [f64; 6] = std::array::from_fn(|i| -mean(&v, i));
    // The pose also advances by v0 per step: x_j + v0 j Δ.
    let drift: [f64; 6] = std::array::from_fn(|i| v0[i] * step * (per_cycle - 1) as f64 / 2.0);
    let x0: [f64; 6] = std::array::from_fn(|i| -mean(&x, i) - drift[i]);
    let held = Held::new(&HoldSamples {
        dt: step,
        rate: 1.0 / step,
        samples_per_period: per_cycle,
        samples,
        start: CentreState {
            velocity: v0,
            pose: x0,
        },
    })?;
    sample_hold::ramped(&Motion::Held(held), 1.0 / step, RAMP_CYCLES, steady)
}

/// Checks, before anything is played, that [`replay_check`] can judge
/// `file` against `schedule`: the schedule records a target and the file's
/// rows fit its segments.
///
/// # Errors
/// As [`replay_check`]'s, without playing.
pub(crate) fn check_replay(schedule: &Schedule, file: &HoldSamples, source: &str) -> Result<()> {
    recorded_target(schedule, "--replay")?;
    replay_motion(schedule, file, source).map(|_| ())
}

/// Plays `schedule` and replays `file` (its export; `source` names it)
/// at `friction` (default: the schedule's), by the design's realised
/// check (see the [module documentation](self)).
///
/// ```no_run
/// use platefield::design::replay::{exported, replay_check};
/// use platefield::schedule::Schedule;
///
/// let schedule = Schedule::load("results/sequenced/sink/schedule.json".as_ref()).unwrap();
/// let check = replay_check(&schedule, &exported(&schedule).unwrap(), "export", None).unwrap();
/// assert!(check.strength_gap() < 0.01);
/// ```
///
/// # Errors
/// The schedule records no target or cannot be played; the file does not
/// fit it (names `source`).
pub fn replay_check(
    schedule: &Schedule,
    file: &HoldSamples,
    source: &str,
    friction: Option<Friction>,
) -> Result<ReplayCheck> {
    let (target, sampled) = recorded_target(schedule, "--replay")?;
    let sm = replay_motion(schedule, file, source)?;
    let friction = [friction.unwrap_or(schedule.settings.friction)];
    let base = &schedule.settings;
    let played = friction_sweep(base, &friction, &|settings| {
        judge_check(target, &sampled, schedule, settings)
    })?;
    let replayed = friction_sweep(base, &friction, &|settings| {
        Ok(judge_replay(target, &sampled, &sm, settings))
    })?;
    Ok(ReplayCheck {
        file: source.into(),
        played: played[0].clone(),
        replayed: replayed[0].clone(),
    })
}

/// The work of [`replay_check`] of a file sampled at `rate`: the judge
/// ([`super::judge::judge_term`]) of the schedule, at `steps_per_cycle`
/// steps per cycle, and of the file, at one step (at least) per held
/// sample (a 10 kHz file of a 0.03 s primitive: about 5 times as many).
pub(crate) fn replay_estimate(schedule: &Schedule, rate: f64) -> Result<Estimate> {
    let (target, sampled) = recorded_target(schedule, "--replay")?;
    let cycle = schedule
        .segments
        .iter()
        .find_map(|s| s.cycle_period())
        .unwrap_or(schedule.period_s);
    let steps = schedule.settings.numerics.steps_per_cycle;
    let held = (rate * cycle).max(steps as f64).ceil() as usize;
    Ok(Estimate::new(
        "--replay",
        "playing the schedule and replaying its export",
        "an export at a lower --rate",
    )
    .plus(
        super::judge::judge_term(
            target,
            &sampled,
            super::judge::judged_cycles(schedule),
            steps + held,
        )
        .named("played and replayed"),
    ))
}
