//! Export of a schedule as the six plate-centre acceleration signals a
//! shaker controller is driven with: translational acceleration of the plate
//! centre along the world x, y, z axes (m/s²) and angular acceleration about
//! them (rad/s²), sampled at a given rate over one schedule period.
//!
//! For a screw primitive {k, h, ψ, d} with R = exp(ψ\[k\]×) and
//! p = (I − R)h + d k (exact, not small-angle):
//! p'' = −(α × Rh + ω × (ω × Rh)) + d'' k with ω = ψ'k, α = ψ''k, and the
//! angular acceleration is ψ''k. Rest segments are zero. Primitives are
//! rest-to-rest, so the signals are continuous in pose and velocity at joins.
//!
//! The schedule is validated and its period derived from the segments
//! ([`Schedule::derive`]) before anything is sampled, so `export` plays
//! exactly what `verify` plays.
//!
//! **Six-signal segments are ramped.** A six-signal motion (e.g. a
//! synthesized one) has zero-mean velocity and pose only from its own
//! steady initial state, not from rest, so a schedule holding one is
//! exported as `crate::motion::sample_hold::ramped` plays it: a ramp-in
//! from rest at home over [`RAMP_CYCLES`] cycles (the quintic smoothstep
//! window w = 10s³ − 15s⁴ + 6s⁵ on the pose, C² at both ends), `steady`
//! cycles of the motion (`--steady-cycles`, default
//! [`DEFAULT_STEADY_CYCLES`]), and the mirrored ramp-out back to rest at
//! home. The file ends at rest in the home pose, so looping it repeats the
//! whole sequence. Such a schedule must hold that one moving segment (rest
//! segments are allowed and ignored: the ramps begin and end at rest).
//! Schedules of primitives only are exported as one schedule period, to be
//! looped. So are mixed schedules, whose six-signal
//! segments ramp in and out inside their own cycles (`ramp_cycles`,
//! [`crate::motion::Ramped`]): every segment then starts and ends at rest
//! at home, like a primitive.

pub mod harmonics;
pub mod peaks;
pub mod pose;
pub mod response;

use super::Schedule;
use crate::error::{positive, Error, Result};
use crate::input::num;
use crate::motion::{rotate, rotation, sample_hold, Motion, Signals, V3};
use crate::request::ShakerSpec;

pub use sample_hold::DEFAULT_STEADY_CYCLES;

/// The exported channels, as the CSV columns name them (after `t_s`):
/// plate-centre acceleration along and about the world axes.
pub(crate) const CHANNELS: [&str; 6] = [
    "ax_m_s2",
    "ay_m_s2",
    "az_m_s2",
    "alpha_x_rad_s2",
    "alpha_y_rad_s2",
    "alpha_z_rad_s2",
];

/// The frame and reference point of every exported signal, as the export
/// headers state them.
pub(crate) const FRAME: &str = "frame: world axes, x and y horizontal in the plate's rest plane, z up (right-handed); reference point: the plate centre (the plate frame's origin, where the target grid's (0, 0) is); linear channels: the centre's acceleration in m/s²; angular channels: the plate's angular acceleration α = dω/dt about the world axes in rad/s², ω the angular velocity in dR/dt = [ω]× R: integrate α to ω and compose the rotation (not each angle on its own), and the plate takes the design's orientation R = exp([θ]×), θ its rotation vector (body axes: Rᵀω, Rᵀα; docs/shaker.md gives the other readings)";

/// Ramp length (cycles of the motion) of a six-signal export, in and out.
pub const RAMP_CYCLES: u32 = sample_hold::DEFAULT_RAMP_CYCLES;

/// Most rows (samples) an export may hold. A CSV row takes somewhat over a
/// hundred bytes, and the file is built in memory with the samples, so
/// 1e7 rows is about a gigabyte of CSV and more of memory: 100 kHz (well
/// above a shaker controller's usual 5–20 kHz) for 100 s, or the default
/// 10 kHz for 1000 s, far more than the ≈ 1 s period of a designed
/// schedule (measured sizes: `docs/shaker.md`, beside the limit). The
/// sampler's own bound ([`sample_hold::MAX_SAMPLES`], 5e7) would let a
/// 5.7 GB file through without a word.
pub(crate) const MAX_EXPORT_ROWS: f64 = 1e7;

/// Bytes per CSV row used to state an export's size (measured:
/// `docs/shaker.md`, beside the export's row limit).
pub(crate) const BYTES_PER_ROW: f64 = 118.0;

/// A schedule's exported samples and how they were laid out.
#[derive(Debug, Clone, PartialEq)]
pub struct Export {
    /// The samples to hold.
    pub samples: sample_hold::HoldSamples,
    /// `Some(steady cycles)` when a six-signal motion was ramped in and out
    /// ([`RAMP_CYCLES`] each way); `None` for a looped schedule period.
    pub ramped: Option<u32>,
    /// The factor (≤ 1) the design's signals are played at so that the
    /// ramps keep within the shaker limits (`ramped_within`); 1 for a
    /// looped schedule period and for a ramped design within them.
    pub scale: f64,
    /// The shaker limits the file is held to: those the schedule was
    /// designed for (`played.limits`), or those [`Export::held_to`] gives
    /// a schedule that records none.
    pub limits: Option<ShakerSpec>,
    /// The schedule's `Schedule::fingerprint`, stated in the header.
    pub fingerprint: String,
}

impl Export {
    /// The CSV `platefield export` writes: comment lines (`# `) stating the
    /// layout, the frame and reference point (`FRAME`) and each axis's
    /// peak acceleration, velocity and stroke as played
    /// (`peaks::KinematicPeaks::of_held`), then the samples
    /// (`sample_hold::HoldSamples::to_csv`).
    pub fn to_csv(&self) -> String {
        let lines: String = self
            .scaled()
            .into_iter()
            .chain(self.over_limits())
            .chain(self.undriven_turns())
            .map(|l| format!("# {l}\n"))
            .collect();
        format!(
            "# platefield export: the six plate-centre acceleration signals, each sample held for its interval: {}\n# {}{} (of the schedule's segments; verify --replay checks it)\n# {FRAME}\n{}{lines}{}",
            self.describe(),
            crate::motion::held_csv::FINGERPRINT,
            self.fingerprint,
            self.peaks().header("the file as played, from rest at home"),
            self.samples.to_csv()
        )
    }

    /// The line saying the design is played scaled so that its ramps keep
    /// within the shaker limits (`ramped_within`), when it is.
    pub fn scaled(&self) -> Option<String> {
        (self.scale < 1.0).then(|| {
            format!(
                "scaled: the design's signals are played × {:.6} (−{:.4} %) so that the ramps keep within the shaker limits (the ramp's pose envelope w(t) adds 2ẇẋ + ẅx to the steady acceleration, which no ramp of finite length avoids); the steady cycles play the design so scaled",
                self.scale,
                100.0 * (1.0 - self.scale)
            )
        })
    }

    /// This export held to `limits` when its schedule records none
    /// (`crate::synth::ShakerLimits::stated` gives its target's).
    pub fn held_to(mut self, limits: Option<ShakerSpec>) -> Export {
        if self.limits.is_none() {
            self.limits = limits;
        }
        self
    }

    /// One line per peak of the file as played above a shaker limit of the
    /// schedule's (`peaks::KinematicPeaks::excesses`), saying by how much;
    /// an angular axis the limits forbid (limit 0) is
    /// [`undriven_turns`](Self::undriven_turns)'. Empty when within every
    /// limit or when the schedule records none.
    pub fn over_limits(&self) -> Vec<String> {
        self.excesses(false)
            .iter()
            .map(|e| {
                format!(
                    "over the shaker limit: {} peaks at {:.6e} {} against {:.6e} (+{:.3} %)",
                    e.axis,
                    e.peak,
                    e.unit,
                    e.limit,
                    100.0 * (e.peak / e.limit - 1.0)
                )
            })
            .collect()
    }

    /// One line per angular axis the limits forbid (limit 0) on which the
    /// plate still turns: tilts about the two other axes, composed exactly,
    /// turn the plate about the third at second order in their angles.
    /// The design's signals leave the axis at 0; no periodic motion with
    /// tilts in quadrature can (the tilts' path encloses an area, and the
    /// orientation's holonomy is that turn; docs/shaker.md).
    pub fn undriven_turns(&self) -> Vec<String> {
        self.excesses(true)
            .iter()
            .map(|e| {
                format!(
                    "undriven axis turned: {} peaks at {:.6e} {} where the limits forbid the axis (the exact rotation: tilts about two axes turn the plate about the third at second order in their angles, which the design's signals leave at 0; docs/shaker.md)",
                    e.axis, e.peak, e.unit
                )
            })
            .collect()
    }

    /// The excesses of the file as played over the schedule's limits:
    /// those on a forbidden angular axis (`undriven`) or the others.
    fn excesses(&self, undriven: bool) -> Vec<peaks::Excess> {
        let Some(limits) = &self.limits else {
            return Vec::new();
        };
        self.peaks()
            .excesses(limits)
            .into_iter()
            .filter(|e| (e.limit == 0.0 && e.axis.starts_with("angular")) == undriven)
            .collect()
    }

    /// Per-axis peak acceleration, velocity and stroke of the file as played.
    pub fn peaks(&self) -> peaks::KinematicPeaks {
        peaks::KinematicPeaks::of_held(&self.samples)
    }

    /// One line stating the layout: the looped period, or the ramp.
    pub fn describe(&self) -> String {
        match self.ramped {
            None => format!(
                "one schedule period to loop, {:.4} s at {:.3} Hz effective",
                self.samples.samples.len() as f64 * self.samples.dt,
                self.samples.rate
            ),
            Some(steady) => {
                let p = self.samples.peaks();
                format!(
                    "ramp-in from rest at home over {RAMP_CYCLES} cycles (quintic smoothstep on the pose), {steady} steady cycles, ramp-out to rest at home over {RAMP_CYCLES} cycles; {:.4} s at {:.3} Hz effective; exported peaks linear [{:.3}, {:.3}, {:.3}] m/s², angular [{:.3}, {:.3}, {:.3}] rad/s²",
                    self.samples.samples.len() as f64 * self.samples.dt,
                    self.samples.rate,
                    p[0], p[1], p[2], p[3], p[4], p[5]
                )
            }
        }
    }
}

/// The samples of `schedule` at (about) `rate` samples/s: one schedule
/// period of primitives and ramped six-signal segments ([`signals_csv`]),
/// or, for a schedule holding a steady six-signal segment, that motion
/// ramped in, played `steady` cycles and ramped out (see the module
/// documentation).
///
/// # Errors
/// An invalid schedule or rate (a steady six-signal segment beside other
/// moving segments names `segments[i].ramp_cycles`); `steady` over the
/// sample budget (names `--steady-cycles`).
pub fn export(schedule: &Schedule, rate: f64, steady: u32) -> Result<Export> {
    positive("--rate", rate)?;
    schedule.validate()?;
    let fingerprint = schedule.fingerprint();
    let schedule = &schedule.with_segments(schedule.segments.clone());
    // A steady six-signal segment is, by `validate`, the one moving segment.
    let steady_motion = schedule
        .segments
        .iter()
        .find(|s| s.motion.is_some() && s.ramp_cycles.is_none())
        .and_then(|s| s.plate_motion());
    check_size(schedule, steady_motion.as_ref(), rate, steady)?;
    let limits = schedule.played.as_ref().and_then(|p| p.limits.clone());
    if let Some(Motion::Signals(signals)) = steady_motion {
        let (samples, scale) = ramped_within(&signals, limits.as_ref(), rate, steady)?;
        return Ok(Export {
            samples,
            ramped: Some(steady),
            scale,
            limits,
            fingerprint,
        });
    }
    Ok(Export {
        samples: sequence_samples(schedule, rate)?,
        ramped: None,
        scale: 1.0,
        limits,
        fingerprint,
    })
}

/// `signals` ramped in, played `steady` cycles and ramped out, scaled by
/// the largest factor ≤ 1 whose file as played keeps within `limits`
/// (acceleration, velocity and stroke; the axes a limit of 0 forbids
/// aside, see [`Export::over_limits`]), and that factor
/// ([`peaks::KinematicPeaks::within_scale`]).
///
/// Why a factor: the ramp multiplies the steady pose by a smoothstep w(t),
/// so its acceleration w ẍ + 2ẇẋ + ẅx exceeds the steady peak wherever
/// ẅ < 0 while w < 1, the last cycles of the ramp-in (by about 2e-4 at
/// [`RAMP_CYCLES`] cycles for one harmonic, `tests/unit/export.rs`). No ramp of
/// finite length avoids it: near its end 1 − w = e must satisfy
/// ë ≤ ω² e, and e(t_end) = ė(t_end) = 0 then gives e ≡ 0 (Grönwall).
/// A design whose steady peak sits on a limit, as a synthesis's does, is
/// therefore played scaled by 1/(1 + that excess).
fn ramped_within(
    signals: &Signals,
    limits: Option<&ShakerSpec>,
    rate: f64,
    steady: u32,
) -> Result<(sample_hold::HoldSamples, f64)> {
    let sample = |k: f64| {
        sample_hold::ramped(
            &Motion::Signals(signals.scaled(k)),
            rate,
            RAMP_CYCLES,
            steady,
        )
    };
    let scale = match limits {
        None => 1.0,
        Some(l) => {
            // The sampler's errors are the rate's, the same at every scale:
            // the first call states them below.
            let mut failed = false;
            let k = peaks::KinematicPeaks::within_scale(
                |k| match sample(k) {
                    Ok(s) => peaks::KinematicPeaks::of_held(&s),
                    Err(_) => {
                        failed = true;
                        peaks::KinematicPeaks::default()
                    }
                },
                l,
            );
            if failed {
                1.0
            } else {
                k
            }
        }
    };
    Ok((sample(scale)?, scale))
}

/// Rows an export of `schedule` at `rate` would hold (before anything is
/// sampled), as the samplers lay them out: Δt = T/round(rate·T) with T the
/// period of the (first) motion; `ramped` is the steady six-signal motion
/// played 2·[`RAMP_CYCLES`] + `steady` cycles, else every segment is a whole
/// number of samples (a rest at least one, a rest of 0 s none). `None`
/// when the rate gives fewer than 2 samples per period (the sampler says so).
fn estimated_rows(
    schedule: &Schedule,
    ramped: Option<&Motion>,
    rate: f64,
    steady: u32,
) -> Option<f64> {
    let first = ramped.map(Motion::period).or_else(|| {
        schedule
            .segments
            .iter()
            .find_map(|s| s.plate_motion())
            .map(|m| m.period())
    });
    let dt = match first {
        Some(t) => {
            let n = (rate * t).round();
            if n < 2.0 {
                return None;
            }
            if ramped.is_some() {
                return Some(n * (2.0 * f64::from(RAMP_CYCLES) + f64::from(steady)));
            }
            t / n
        }
        None => 1.0 / rate,
    };
    Some(
        schedule
            .segments
            .iter()
            .filter(|s| s.plate_motion().is_some() || s.duration_s != 0.0)
            .map(|s| (s.duration_s / dt).round().max(1.0))
            .sum(),
    )
}

/// Refuses an export of more than [`MAX_EXPORT_ROWS`] rows before it is
/// sampled, stating the estimated rows and size and the largest `--rate`
/// (and, for a ramped export, the most `--steady-cycles`) that fit.
fn check_size(schedule: &Schedule, ramped: Option<&Motion>, rate: f64, steady: u32) -> Result<()> {
    let rows = |rate: f64, steady: u32| estimated_rows(schedule, ramped, rate, steady);
    let Some(n) = rows(rate, steady) else {
        return Ok(());
    };
    if n <= MAX_EXPORT_ROWS {
        return Ok(());
    }
    // The largest rate that fits, to 3 significant digits, rounded down
    // and checked (rounding to whole samples per period can add a few).
    let mut fit = rate * MAX_EXPORT_ROWS / n;
    let scale = 10f64.powf(fit.log10().floor() - 2.0);
    fit = (fit / scale).floor() * scale;
    while fit > 0.0 && rows(fit, steady).is_some_and(|m| m > MAX_EXPORT_ROWS) {
        fit -= scale;
    }
    // Rates and row counts in words a reader can compare: 4e7, 8.31e6.
    let hz = |r: f64| {
        if r >= 1e5 {
            format!("{r:e} Hz")
        } else {
            format!("{} Hz", num(r))
        }
    };
    let rate_hint = if fit > 0.0 && rows(fit, steady).is_some() {
        format!("the largest --rate that fits is {}", hz(fit))
    } else {
        "no --rate fits".to_string()
    };
    let gb = |rows: f64| {
        let gb = rows * BYTES_PER_ROW / 1e9;
        if gb < 1e4 {
            format!("{gb:.1} GB")
        } else {
            format!("{gb:.1e} GB")
        }
    };
    let mut field = "--rate";
    let (layout, steady_hint) = match ramped {
        None => (
            format!("one {:.4} s schedule period", schedule.period_s),
            String::new(),
        ),
        Some(m) => {
            // Rows per cycle at this rate, and the steady cycles that fit.
            let per_cycle = (rate * m.period()).round();
            let most = (MAX_EXPORT_ROWS / per_cycle).floor() - 2.0 * f64::from(RAMP_CYCLES);
            let hint = if most >= 0.0 {
                // The ramps fit at this rate: the steady cycles are too many.
                if steady > DEFAULT_STEADY_CYCLES {
                    field = "--steady-cycles";
                }
                format!(", or at most {most} --steady-cycles at this rate")
            } else {
                String::new()
            };
            (
                format!(
                    "{RAMP_CYCLES} + {steady} (--steady-cycles) + {RAMP_CYCLES} cycles of {:.6} s",
                    m.period()
                ),
                hint,
            )
        }
    };
    Err(Error::invalid(
        field,
        format!(
            "{} over {layout} is about {:.3e} rows, {} of CSV, over the limit of {:e} rows (≈ {}); {rate_hint}{steady_hint}",
            hz(rate),
            n,
            gb(n),
            MAX_EXPORT_ROWS,
            gb(MAX_EXPORT_ROWS),
        ),
    ))
}

/// Plate-centre (linear, angular) acceleration of `motion`'s signals at
/// time `t`, world axes: for a six-signal motion the angular one is θ″, the
/// rotation vector's, which design limits (`world_acceleration` is the
/// plate's, which exports write).
pub fn centre_acceleration(motion: &Motion, t: f64) -> (V3, V3) {
    match motion {
        Motion::Screw(s) => {
            let k = V3::from(s.axis).normalize();
            let psi = s.rotation.eval(t, s.period);
            let d = s.translation.eval(t, s.period);
            let rh = rotate(&V3::from(s.point), &k, psi.q);
            let (w, a) = (k * psi.dq, k * psi.ddq);
            let lin = -(a.cross(&rh) + w.cross(&w.cross(&rh))) + k * d.ddq;
            (lin, a)
        }
        Motion::Signals(_) | Motion::Ramped(_) | Motion::Held(_) => {
            let kin = motion.kinematics(t, 0.0, false);
            (kin.accel_center, kin.alpha)
        }
    }
}

/// Plate-centre (linear, angular) acceleration of `motion` at time `t`,
/// world axes, the angular one the plate's α = ω′ (`crate::motion::rotation`):
/// what the export's channels hold.
pub(crate) fn world_acceleration(motion: &Motion, t: f64) -> (V3, V3) {
    match motion {
        Motion::Screw(_) => centre_acceleration(motion, t),
        Motion::Signals(_) | Motion::Ramped(_) | Motion::Held(_) => {
            // The plate-frame kinematics turned back to the world axes by
            // the orientation exp([θ]×).
            let kin = motion.kinematics(t, 0.0, true);
            let pose = sample_hold::centre_state(motion, t).pose;
            let turn = rotation::orientation(&V3::new(pose[3], pose[4], pose[5]));
            (turn * kin.accel_center, turn * kin.alpha)
        }
    }
}

/// Samples per period used to find a motion's peaks.
pub(crate) const PEAK_SAMPLES: usize = 4096;

/// Per-axis peak |plate-centre acceleration| of `motion` over
/// [`PEAK_SAMPLES`] samples per period (over the whole segment of a ramped motion) (linear x, y, z in m/s², angular
/// x, y, z in rad/s², world axes): what a controller must be able to play.
pub(crate) fn motion_peaks(motion: &Motion) -> [f64; 6] {
    // A ramped motion over its whole segment, at the same density.
    let n = PEAK_SAMPLES * (motion.span() / motion.period()).round().max(1.0) as usize;
    let mut p = [0.0_f64; 6];
    for i in 0..n {
        let (lin, ang) = centre_acceleration(motion, motion.span() * i as f64 / n as f64);
        for (k, v) in [lin.x, lin.y, lin.z, ang.x, ang.y, ang.z]
            .iter()
            .enumerate()
        {
            p[k] = p[k].max(v.abs());
        }
    }
    p
}

/// Per-axis peaks over every moving segment of `schedule` (see
/// `motion_peaks`; rest contributes 0).
pub fn schedule_peaks(schedule: &Schedule) -> [f64; 6] {
    let mut p = [0.0_f64; 6];
    for m in schedule.segments.iter().filter_map(|s| s.plate_motion()) {
        for (k, v) in motion_peaks(&m).iter().enumerate() {
            p[k] = p[k].max(*v);
        }
    }
    p
}

/// CSV of the six signals over one schedule period at (about) `rate`
/// samples/s, as a sample-and-hold controller plays them
/// (`crate::motion::sample_hold::sequence`): each sample is the mean
/// acceleration over its interval, Δt = T₀/round(rate·T₀) with T₀ the
/// primitives' period, and every join and the period end fall on sample
/// boundaries, so the plate integrated from the file returns to rest in the
/// home pose every period (to round-off), where point samples drift.
/// A schedule holding a six-signal segment is ramped ([`export`] with
/// [`DEFAULT_STEADY_CYCLES`]).
pub fn signals_csv(schedule: &Schedule, rate: f64) -> Result<String> {
    Ok(export(schedule, rate, DEFAULT_STEADY_CYCLES)?
        .samples
        .to_csv())
}

/// One period of a primitives-only (validated, derived) schedule.
fn sequence_samples(schedule: &Schedule, rate: f64) -> Result<sample_hold::HoldSamples> {
    if schedule.period_s * rate > 5e7 {
        return Err(Error::invalid(
            "--rate",
            format!(
                "{} Hz over a {:.3} s schedule is more than 5e7 samples",
                crate::input::num(rate),
                schedule.period_s
            ),
        ));
    }
    let motions = segment_motions(schedule);
    sample_hold::sequence(&spans(schedule, &motions), rate)
}

/// The plate motion of every segment of `schedule` (`None`: rest).
pub(crate) fn segment_motions(schedule: &Schedule) -> Vec<Option<Motion>> {
    schedule.segments.iter().map(|s| s.plate_motion()).collect()
}

/// The segments of `schedule` as spans of their `motions`
/// ([`segment_motions`]).
pub(crate) fn spans<'a>(
    schedule: &Schedule,
    motions: &'a [Option<Motion>],
) -> Vec<sample_hold::MotionSpan<'a>> {
    schedule
        .segments
        .iter()
        .zip(motions)
        .map(|(s, m)| sample_hold::MotionSpan {
            motion: m.as_ref(),
            duration: s.duration_s,
        })
        .collect()
}

/// The one steady six-signal motion of a validated `schedule` (a
/// synthesized design), if that is what it holds: a single moving segment
/// without `ramp_cycles`.
pub(crate) fn steady_signals(schedule: &Schedule) -> Option<&Signals> {
    let mut moving = schedule.segments.iter().filter(|s| s.is_moving());
    match (moving.next(), moving.next()) {
        (Some(s), None) if s.ramp_cycles.is_none() => s.motion.as_ref(),
        _ => None,
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/export.rs"]
mod export_tests;

#[cfg(test)]
mod tests {
    /// A worked example of `schedule::export::world_acceleration`.
    #[test]
    fn example_world_acceleration() {
        use crate::motion::{Motion, Signals};
        use crate::schedule::export::{centre_acceleration, world_acceleration};

        let m = Motion::Signals(Signals::example());
        let ((l, a), (wl, wa)) = (centre_acceleration(&m, 0.01), world_acceleration(&m, 0.01));
        assert!((l - wl).norm() < 1e-12);
        // Two tilts: α differs from θ″ at second order in the tilt angles.
        assert!((a - wa).norm() > 0.0 && (a - wa).norm() < 1e-3 * a.norm());
    }
}
