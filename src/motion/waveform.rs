//! Periodic scalar waveforms: a coordinate q(t) (angle in rad or displacement
//! in m) with its rate q'(t) and acceleration q''(t), period T, ω = 2π/T.
//!
//! Every waveform is periodic in pose *and* velocity: the velocity is the
//! zero-mean antiderivative of the acceleration, so the plate returns to the
//! same pose with the same velocity after each cycle.

use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

use crate::error::{finite, Error, Result};

/// One Fourier term of an acceleration signal: `amplitude · sin(harmonic·ω t + phase)`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FourierTerm {
    /// Acceleration amplitude (rad/s² or m/s²).
    pub amplitude: f64,
    /// Phase φ (rad).
    #[serde(default)]
    pub phase: f64,
    /// Harmonic number n ≥ 1.
    #[serde(default = "one")]
    pub harmonic: u32,
}

fn one() -> u32 {
    1
}

/// A periodic waveform, given by its acceleration. JSON:
/// `{"type": "sine", "accel": A}` (read by [`Waveform::deserialize`], which
/// keeps the JSON path of an error inside it).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Waveform {
    /// No motion.
    #[default]
    Zero,
    /// q'' = accel · sin(ω t); zero-mean velocity and pose (symmetric oscillation).
    Sine {
        /// Acceleration amplitude.
        accel: f64,
    },
    /// The paper's eq. 1: q'' = +α on [0, T/2), −α on [T/2, T); zero-mean
    /// velocity and pose. Piecewise constant, so integrated exactly.
    Square {
        /// α, the acceleration magnitude.
        accel: f64,
    },
    /// Rest-to-rest: q = q0 (1 − cos ω t), so q(0) = q'(0) = 0 at the start of
    /// every cycle, q'' = q0 ω² cos ω t (pure sinusoidal acceleration). Used
    /// for primitives that are sequenced: joins are at rest in the home pose.
    /// The price is a mean offset q0.
    RestToRest {
        /// Displacement amplitude q0 (rad or m).
        amplitude: f64,
    },
    /// A finite Fourier series of the acceleration plus a constant pose offset.
    Fourier {
        /// Acceleration terms.
        terms: Vec<FourierTerm>,
        /// Constant offset added to the pose (velocity stays zero-mean;
        /// default 0).
        offset: f64,
    },
}

/// The values of a waveform's `"type"`.
pub(crate) const WAVE_TYPES: &[&str] = &["zero", "sine", "square", "rest_to_rest", "fourier"];

impl<'de> Deserialize<'de> for Waveform {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        crate::input::tagged(d, "type", WAVE_TYPES, |kind, b| {
            Some(match kind {
                "sine" => Waveform::Sine {
                    accel: b.get("accel"),
                },
                "square" => Waveform::Square {
                    accel: b.get("accel"),
                },
                "rest_to_rest" => Waveform::RestToRest {
                    amplitude: b.get("amplitude"),
                },
                "fourier" => Waveform::Fourier {
                    terms: b.get("terms"),
                    offset: b.or("offset", 0.0),
                },
                _ => Waveform::Zero,
            })
        })
    }
}

/// Value, rate and acceleration of a waveform at one instant.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Sample {
    /// q
    pub q: f64,
    /// q'
    pub dq: f64,
    /// q''
    pub ddq: f64,
}

impl Waveform {
    /// Evaluates the waveform at time `t` for period `period`.
    #[inline]
    pub(crate) fn eval(&self, t: f64, period: f64) -> Sample {
        self.eval_piece(t, period, t)
    }

    /// Evaluates at `t` using the smooth piece that contains `piece_t`.
    /// Piecewise waveforms (the square wave) are right-continuous under
    /// [`Waveform::eval`]; an integrator stepping over [a, b] between two
    /// breakpoints passes a `piece_t` inside (a, b) so that the value at `b`
    /// is the left limit, and constant accelerations stay exactly constant
    /// over the whole interval.
    #[inline]
    pub(crate) fn eval_piece(&self, t: f64, period: f64, piece_t: f64) -> Sample {
        let w = 2.0 * PI / period;
        match self {
            Waveform::Zero => Sample::default(),
            Waveform::Sine { accel } => {
                let (s, c) = (w * t).sin_cos();
                Sample {
                    q: -accel / (w * w) * s,
                    dq: -accel / w * c,
                    ddq: accel * s,
                }
            }
            Waveform::Square { accel } => {
                let cycle_start = (piece_t / period).floor() * period;
                let tau = t - cycle_start;
                if piece_t - cycle_start < 0.5 * period {
                    let x = tau - 0.25 * period;
                    Sample {
                        q: accel * (0.5 * x * x - period * period / 32.0),
                        dq: accel * x,
                        ddq: *accel,
                    }
                } else {
                    let x = tau - 0.75 * period;
                    Sample {
                        q: accel * (-0.5 * x * x + period * period / 32.0),
                        dq: -accel * x,
                        ddq: -accel,
                    }
                }
            }
            Waveform::RestToRest { amplitude } => {
                let (s, c) = (w * t).sin_cos();
                Sample {
                    q: amplitude * (1.0 - c),
                    dq: amplitude * w * s,
                    ddq: amplitude * w * w * c,
                }
            }
            Waveform::Fourier { terms, offset } => {
                let mut out = Sample {
                    q: *offset,
                    ..Sample::default()
                };
                for term in terms {
                    let wn = w * f64::from(term.harmonic);
                    let (s, c) = (wn * t + term.phase).sin_cos();
                    out.q -= term.amplitude / (wn * wn) * s;
                    out.dq -= term.amplitude / wn * c;
                    out.ddq += term.amplitude * s;
                }
                out
            }
        }
    }

    /// Times in [0, period) where the acceleration jumps. The integrator
    /// places step boundaries there so piecewise-smooth signals are
    /// integrated at full order (and piecewise-constant ones exactly).
    pub(crate) fn breakpoints(&self, period: f64) -> Vec<f64> {
        match self {
            Waveform::Square { .. } => vec![0.0, 0.5 * period],
            _ => Vec::new(),
        }
    }

    /// True when the waveform is identically zero.
    pub(crate) fn is_zero(&self) -> bool {
        match self {
            Waveform::Zero => true,
            Waveform::Sine { accel } | Waveform::Square { accel } => *accel == 0.0,
            Waveform::RestToRest { amplitude } => *amplitude == 0.0,
            Waveform::Fourier { terms, offset } => {
                *offset == 0.0 && terms.iter().all(|t| t.amplitude == 0.0)
            }
        }
    }

    /// Peak |q''| bound (sum of amplitudes), used for scales and checks.
    pub(crate) fn accel_bound(&self, period: f64) -> f64 {
        let w = 2.0 * PI / period;
        match self {
            Waveform::Zero => 0.0,
            Waveform::Sine { accel } | Waveform::Square { accel } => accel.abs(),
            Waveform::RestToRest { amplitude } => amplitude.abs() * w * w,
            Waveform::Fourier { terms, .. } => terms.iter().map(|t| t.amplitude.abs()).sum(),
        }
    }

    /// The same waveform scaled in amplitude by `k`.
    pub(crate) fn scaled(&self, k: f64) -> Waveform {
        match self {
            Waveform::Zero => Waveform::Zero,
            Waveform::Sine { accel } => Waveform::Sine { accel: accel * k },
            Waveform::Square { accel } => Waveform::Square { accel: accel * k },
            Waveform::RestToRest { amplitude } => Waveform::RestToRest {
                amplitude: amplitude * k,
            },
            Waveform::Fourier { terms, offset } => Waveform::Fourier {
                terms: terms
                    .iter()
                    .map(|t| FourierTerm {
                        amplitude: t.amplitude * k,
                        ..*t
                    })
                    .collect(),
                offset: offset * k,
            },
        }
    }

    /// Validates the parameters, naming `field` in errors.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        match self {
            Waveform::Zero => Ok(()),
            Waveform::Sine { accel } | Waveform::Square { accel } => {
                finite(&format!("{field}.accel"), *accel).map(|_| ())
            }
            Waveform::RestToRest { amplitude } => {
                finite(&format!("{field}.amplitude"), *amplitude).map(|_| ())
            }
            Waveform::Fourier { terms, offset } => {
                finite(&format!("{field}.offset"), *offset)?;
                for (i, t) in terms.iter().enumerate() {
                    finite(&format!("{field}.terms[{i}].amplitude"), t.amplitude)?;
                    finite(&format!("{field}.terms[{i}].phase"), t.phase)?;
                    if t.harmonic == 0 {
                        return Err(Error::invalid(
                            format!("{field}.terms[{i}].harmonic"),
                            "must be ≥ 1 (a constant acceleration is not periodic)",
                        ));
                    }
                }
                Ok(())
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Checks q' and q'' against central differences and periodicity of q, q'.
    fn check_consistent(w: &Waveform, period: f64) {
        let h = 1e-6 * period;
        for i in 0..50 {
            let t = (i as f64 + 0.37) / 50.0 * period;
            let s = w.eval(t, period);
            let (a, b) = (w.eval(t - h, period), w.eval(t + h, period));
            let scale = w.accel_bound(period);
            assert!(((b.q - a.q) / (2.0 * h) - s.dq).abs() < 1e-6 * scale * period);
            assert!(((b.dq - a.dq) / (2.0 * h) - s.ddq).abs() < 1e-5 * scale);
            let p = w.eval(t + period, period);
            assert!((p.q - s.q).abs() < 1e-12 * scale * period * period);
            assert!((p.dq - s.dq).abs() < 1e-12 * scale * period);
        }
    }

    /// Mean of q' over a cycle by the midpoint rule.
    fn mean_rate(w: &Waveform, period: f64) -> f64 {
        let n = 4000;
        (0..n)
            .map(|i| w.eval((i as f64 + 0.5) / n as f64 * period, period).dq)
            .sum::<f64>()
            / n as f64
    }

    #[test]
    fn derivatives_consistent_and_periodic() {
        let period = 0.03;
        let waves = [
            Waveform::Sine { accel: 220.0 },
            Waveform::Square { accel: 180.0 },
            Waveform::RestToRest { amplitude: 0.005 },
            Waveform::Fourier {
                terms: vec![
                    FourierTerm {
                        amplitude: 3.0,
                        phase: 0.3,
                        harmonic: 1,
                    },
                    FourierTerm {
                        amplitude: 1.5,
                        phase: -1.0,
                        harmonic: 2,
                    },
                ],
                offset: 0.001,
            },
        ];
        for w in &waves {
            check_consistent(w, period);
            let scale = w.accel_bound(period) * period;
            assert!(mean_rate(w, period).abs() < 1e-9 * scale, "{w:?}");
        }
    }

    #[test]
    fn square_wave_matches_paper_eq1() {
        let (t, a) = (0.03, 180.0);
        assert_eq!(Waveform::Square { accel: a }.eval(0.01, t).ddq, a);
        assert_eq!(Waveform::Square { accel: a }.eval(0.02, t).ddq, -a);
        // Maximum plate angular speed is αT/4 (used in eq. 14).
        let s = Waveform::Square { accel: a }.eval(0.5 * t, t);
        assert!((s.dq - a * t / 4.0).abs() < 1e-12);
    }

    #[test]
    fn square_piece_gives_left_limit() {
        let w = Waveform::Square { accel: 2.0 };
        let t = 1.0;
        // At t = T/2 the right-continuous value is −α; the left piece gives +α.
        assert_eq!(w.eval(0.5, t).ddq, -2.0);
        let left = w.eval_piece(0.5, t, 0.25);
        assert_eq!(left.ddq, 2.0);
        assert!((left.dq - w.eval(0.5, t).dq).abs() < 1e-15);
        assert!((left.q - w.eval(0.5, t).q).abs() < 1e-15);
        // Across a cycle end (t = T, piece in the second half).
        let end = w.eval_piece(1.0, t, 0.75);
        assert_eq!(end.ddq, -2.0);
        assert!((end.dq - w.eval(0.0, t).dq).abs() < 1e-15);
    }

    #[test]
    fn rest_to_rest_starts_at_rest() {
        let s = Waveform::RestToRest { amplitude: 0.005 }.eval(0.0, 0.03);
        assert_eq!((s.q, s.dq), (0.0, 0.0));
    }
}
