//! `platefield export --format harmonics`: a schedule's six-signal motion
//! as the terms a 6-DOF shaker controller takes, per channel the amplitude
//! A and phase φ of each harmonic n in c(t) = A·sin(nωt + φ), ω = 2π/T.
//!
//! Only a schedule of one steady six-signal motion (a synthesized design)
//! is a sum of harmonics; a sequence of primitives is not (its
//! rest-to-rest screws are played one after the other, and their exact
//! rotation is not a sum of a few sines), so it is refused, naming
//! `--format`, and exported as CSV samples instead.
//!
//! The channels are the export's (`super::FRAME`): the linear ones are the
//! schedule's own terms; a channel's terms of one harmonic are written as
//! one term, their phasors A·e^{iφ} summed; a single term is written as it
//! is in the schedule (a negative amplitude as |A| with φ + π), so the
//! motion's own terms come back exactly. The angular ones are the plate's
//! world-frame angular acceleration α = ω′ of the orientation exp(\[θ\]×)
//! (`crate::motion::rotation`): the schedule's own terms (θ″) when the
//! motion turns about one axis only (then α = θ″ exactly); otherwise α
//! holds, besides θ″, terms second order in the tilt angles at other
//! harmonics (and on the third axis), taken from a discrete Fourier
//! transform of α over [`DFT_POINTS`] × the highest harmonic points per
//! cycle, terms below [`DFT_FLOOR`] of the largest angular peak left out.

use std::fmt::Write as _;

use super::peaks::KinematicPeaks;
use super::{steady_signals, world_acceleration, Schedule, CHANNELS, FRAME};
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
    let Some(signals) = steady_signals(schedule) else {
        let moving = schedule.segments.iter().filter(|s| s.is_moving()).count();
        return Err(Error::invalid(
            "--format",
            format!(
                "harmonics needs a schedule of one steady six-signal motion (a synthesized design); this one has {moving} moving segment(s) of primitives or ramped motions, which are not a sum of harmonics: export it with --format csv"
            ),
        ));
    };
    Ok(of_signals(signals))
}

/// Points per cycle and per harmonic of the motion on which the angular
/// channels' transform is taken.
pub const DFT_POINTS: usize = 128;
/// Angular terms below this fraction of the largest angular acceleration
/// peak are left out.
pub const DFT_FLOOR: f64 = 1e-12;

/// The world angular acceleration's terms per angular channel (3, 4, 5),
/// from a discrete Fourier transform over one period (module docs).
fn angular_terms(signals: &Signals) -> Vec<Term> {
    let motion = Motion::Signals(signals.clone());
    let n = DFT_POINTS * signals.highest_harmonic() as usize;
    let tau = std::f64::consts::TAU;
    let alpha: Vec<[f64; 3]> = (0..n)
        .map(|k| {
            let a = world_acceleration(&motion, signals.period * k as f64 / n as f64).1;
            [a.x, a.y, a.z]
        })
        .collect();
    let peak = alpha.iter().flatten().fold(0.0_f64, |m, a| m.max(a.abs()));
    let mut terms = Vec::new();
    for axis in 0..3 {
        for h in 1..=n / 4 {
            let (a, b) = alpha.iter().enumerate().fold((0.0, 0.0), |(a, b), (k, v)| {
                let (sn, cs) = (tau * (h * k) as f64 / n as f64).sin_cos();
                (a + v[axis] * cs, b + v[axis] * sn)
            });
            let (a, b) = (2.0 * a / n as f64, 2.0 * b / n as f64);
            if a.hypot(b) > DFT_FLOOR * peak {
                terms.push(Term {
                    channel: 3 + axis,
                    harmonic: h as u32,
                    amplitude: a.hypot(b),
                    phase: a.atan2(b),
                });
            }
        }
    }
    terms
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
    // One axis turning (or none): α = θ″ exactly, the schedule's terms.
    let turning = channels[3..]
        .iter()
        .filter(|l| l.iter().any(|t| t.amplitude != 0.0))
        .count();
    let own = if turning <= 1 { 6 } else { 3 };
    let mut terms = Vec::new();
    for (channel, list) in channels.into_iter().enumerate().take(own) {
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
    if own == 3 {
        terms.extend(angular_terms(signals));
    }
    Harmonics {
        period: signals.period,
        terms,
        peaks: KinematicPeaks::of_plate(
            &Motion::Signals(signals.clone()),
            signals.highest_harmonic(),
        ),
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
    #[cfg(test)]
    pub(crate) fn value(&self, channel: usize, t: f64) -> f64 {
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
