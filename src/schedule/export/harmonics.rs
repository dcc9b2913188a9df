//! `platefield export --format harmonics`: a schedule's six-signal motion
//! as the terms a 6-DOF shaker controller takes, per channel the amplitude
//! A and phase φ of each harmonic n in c(t) = A·sin(nωt + φ), ω = 2π/T.
//!
//! Only a schedule of one steady six-signal motion (a synthesized design)
//! is a finite sum of harmonics; a sequence of primitives is not (its
//! rest-to-rest screws are played one after the other, and their exact
//! rotation is not a sum of a few sines), so it is refused, naming
//! `--format`, and exported as CSV samples instead. A channel's terms of
//! one harmonic are written as one term, their phasors A·e^{iφ} summed; a
//! single term is written as it is in the schedule (a negative amplitude
//! as |A| with φ + π), so the motion's own terms come back exactly.

use std::fmt::Write as _;

use super::peaks::KinematicPeaks;
use super::{Schedule, CHANNELS, FRAME};
use crate::error::{Error, Result};
use crate::motion::{FourierTerm, Motion, Signals};

/// One term c(t) = amplitude · sin(harmonic · ω t + phase) of a channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    /// Channel index into `CHANNELS` (x, y, z linear, then angular).
    pub channel: usize,
    /// Harmonic number n ≥ 1.
    pub harmonic: u32,
    /// Amplitude A ≥ 0 (m/s² or rad/s²).
    pub amplitude: f64,
    /// Phase φ (rad).
    pub phase: f64,
}

/// A six-signal motion as per-channel harmonics, with its steady peaks.
#[derive(Debug, Clone, PartialEq)]
pub struct Harmonics {
    /// Period T (s) of the fundamental.
    pub period: f64,
    /// Every channel's terms, by channel then harmonic.
    pub terms: Vec<Term>,
    /// Peak acceleration, velocity and stroke of the steady motion.
    pub peaks: KinematicPeaks,
}

/// The harmonics of `schedule`'s one steady six-signal motion.
///
/// # Errors
/// An invalid schedule, or one that is not a single steady six-signal
/// motion (names `--format`).
pub fn harmonics(schedule: &Schedule) -> Result<Harmonics> {
    schedule.validate()?;
    let moving: Vec<_> = schedule.segments.iter().filter(|s| s.is_moving()).collect();
    let signals = match moving.as_slice() {
        [s] if s.ramp_cycles.is_none() => s.motion.as_ref(),
        _ => None,
    };
    let Some(signals) = signals else {
        return Err(Error::invalid(
            "--format",
            format!(
                "harmonics needs a schedule of one steady six-signal motion (a synthesized design); this one has {} moving segment(s) of primitives or ramped motions, which are not a sum of harmonics: export it with --format csv",
                moving.len()
            ),
        ));
    };
    Ok(of_signals(signals))
}

/// The harmonics of a six-signal motion (see the module documentation).
pub fn of_signals(signals: &Signals) -> Harmonics {
    let channels = [
        &signals.linear.x,
        &signals.linear.y,
        &signals.linear.z,
        &signals.angular.x,
        &signals.angular.y,
        &signals.angular.z,
    ];
    let mut terms = Vec::new();
    for (channel, list) in channels.into_iter().enumerate() {
        let mut ns: Vec<u32> = list.iter().map(|t| t.harmonic).collect();
        ns.sort_unstable();
        ns.dedup();
        for n in ns {
            let same: Vec<&FourierTerm> = list.iter().filter(|t| t.harmonic == n).collect();
            let (amplitude, phase) = combined(&same);
            terms.push(Term {
                channel,
                harmonic: n,
                amplitude,
                phase,
            });
        }
    }
    let highest = terms.iter().map(|t| t.harmonic).max().unwrap_or(1);
    Harmonics {
        period: signals.period,
        terms,
        peaks: KinematicPeaks::of_motion(&Motion::Signals(signals.clone()), highest),
    }
}

/// One term equal to the sum of `terms` (all of one harmonic).
fn combined(terms: &[&FourierTerm]) -> (f64, f64) {
    if let [t] = terms {
        return if t.amplitude < 0.0 {
            (-t.amplitude, wrap(t.phase + std::f64::consts::PI))
        } else {
            (t.amplitude, t.phase)
        };
    }
    let (re, im) = terms.iter().fold((0.0, 0.0), |(re, im), t| {
        let (s, c) = t.phase.sin_cos();
        (re + t.amplitude * c, im + t.amplitude * s)
    });
    (re.hypot(im), im.atan2(re))
}

/// `phase` in (−π, π].
fn wrap(phase: f64) -> f64 {
    let tau = std::f64::consts::TAU;
    let p = phase - tau * (phase / tau).round();
    if p <= -std::f64::consts::PI {
        p + tau
    } else {
        p
    }
}

impl Harmonics {
    /// Channel `channel`'s value c(t) = Σ A sin(nωt + φ) at time `t`.
    pub fn value(&self, channel: usize, t: f64) -> f64 {
        let w = std::f64::consts::TAU / self.period;
        self.terms
            .iter()
            .filter(|h| h.channel == channel)
            .map(|h| h.amplitude * (f64::from(h.harmonic) * w * t + h.phase).sin())
            .sum()
    }

    /// The CSV `export --format harmonics` writes: comment lines (`# `)
    /// stating the form, ω, the frame, the reference point and the peaks,
    /// then `channel,harmonic,amplitude,phase_rad` rows (numbers in their
    /// shortest exact form).
    ///
    /// ```
    /// use platefield::motion::{Axes, FourierTerm, Signals};
    /// use platefield::schedule::export::harmonics::of_signals;
    /// let term = FourierTerm { amplitude: 2.0, phase: 0.5, harmonic: 1 };
    /// let s = Signals { period: 0.05, linear: Axes { x: vec![term], ..Axes::default() }, angular: Axes::default() };
    /// let csv = of_signals(&s).to_csv();
    /// assert!(csv.contains("ax_m_s2,1,2,0.5\n"));
    /// ```
    pub fn to_csv(&self) -> String {
        let mut out = format!(
            "# platefield export --format harmonics: per channel c(t) = amplitude · sin(harmonic · ω t + phase), ω = 2π/T, T = {} s (ω = {:.6} rad/s); the steady motion: ramp it in from rest (the CSV export's ramp does)\n",
            self.period,
            std::f64::consts::TAU / self.period
        );
        let _ = writeln!(out, "# {FRAME}");
        out.push_str(&self.peaks.header("the steady motion"));
        out.push_str("channel,harmonic,amplitude,phase_rad\n");
        for t in &self.terms {
            let _ = writeln!(
                out,
                "{},{},{},{}",
                CHANNELS[t.channel], t.harmonic, t.amplitude, t.phase
            );
        }
        out
    }
}
