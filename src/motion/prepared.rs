//! A motion's kinematics with its constants worked out once.
//!
//! The integrator evaluates the plate kinematics at thousands of instants
//! off the kinematics table's grid per field (the stages of τ-steps and
//! implicit steps, event location: issue 12). For a screw, each evaluation
//! normalised the axis and divided the waveform amplitudes by ω and ω²
//! again. [`PreparedMotion`] holds those quotients and performs the rest of
//! [`Screw::kinematics`] and [`Waveform::eval_piece`] with the same
//! operations in the same order, so its values are bitwise those of
//! [`Motion::kinematics_piece`] (tested); other motions are passed through.

use std::f64::consts::PI;

use super::{rotate, Kinematics, Motion, Screw, Waveform, V3};

/// A waveform's constants: each coefficient is the quotient or product
/// [`Waveform::eval_piece`] forms before multiplying by sin or cos.
#[derive(Debug, Clone)]
enum Wave {
    Zero,
    /// −a/ω², −a/ω, a, ω.
    Sine([f64; 4]),
    /// q0, q0 ω, q0 ω², ω.
    RestToRest([f64; 4]),
    /// Per term nω, φ, a/(nω)², a/(nω) and a; the offset.
    Fourier(Vec<[f64; 5]>, f64),
    /// Evaluated by the waveform itself (the square wave).
    Other(Waveform),
}

impl Wave {
    fn new(w: &Waveform, period: f64) -> Wave {
        let om = 2.0 * PI / period;
        match w {
            Waveform::Zero => Wave::Zero,
            Waveform::Sine { accel } => Wave::Sine([-accel / (om * om), -accel / om, *accel, om]),
            Waveform::RestToRest { amplitude } => {
                Wave::RestToRest([*amplitude, amplitude * om, amplitude * om * om, om])
            }
            Waveform::Fourier { terms, offset } => Wave::Fourier(
                terms
                    .iter()
                    .map(|term| {
                        let wn = om * f64::from(term.harmonic);
                        [
                            wn,
                            term.phase,
                            term.amplitude / (wn * wn),
                            term.amplitude / wn,
                            term.amplitude,
                        ]
                    })
                    .collect(),
                *offset,
            ),
            Waveform::Square { .. } => Wave::Other(w.clone()),
        }
    }

    /// (q, q', q'') at `t`, as [`Waveform::eval_piece`].
    #[inline]
    fn eval(&self, t: f64, period: f64, piece_t: f64) -> (f64, f64, f64) {
        match self {
            Wave::Zero => (0.0, 0.0, 0.0),
            Wave::Sine([q, dq, ddq, om]) => {
                let (s, c) = (om * t).sin_cos();
                (q * s, dq * c, ddq * s)
            }
            Wave::RestToRest([a, aw, aww, om]) => {
                let (s, c) = (om * t).sin_cos();
                (a * (1.0 - c), aw * s, aww * c)
            }
            Wave::Fourier(terms, offset) => {
                let (mut q, mut dq, mut ddq) = (*offset, 0.0, 0.0);
                for [wn, phase, qa, dqa, a] in terms {
                    let (s, c) = (wn * t + phase).sin_cos();
                    q -= qa * s;
                    dq -= dqa * c;
                    ddq += a * s;
                }
                (q, dq, ddq)
            }
            Wave::Other(w) => {
                let x = w.eval_piece(t, period, piece_t);
                (x.q, x.dq, x.ddq)
            }
        }
    }
}

/// A screw's unit axis, point and waveforms' constants.
#[derive(Debug, Clone)]
struct PreparedScrew {
    k: V3,
    center: V3,
    period: f64,
    rotation: Wave,
    translation: Wave,
}

impl PreparedScrew {
    fn new(s: &Screw) -> PreparedScrew {
        PreparedScrew {
            k: V3::from(s.axis).normalize(),
            center: V3::from(s.point),
            period: s.period,
            rotation: Wave::new(&s.rotation, s.period),
            translation: Wave::new(&s.translation, s.period),
        }
    }

    /// As [`Screw::kinematics`].
    #[inline]
    fn kinematics(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        let k = self.k;
        let (q, dq, ddq) = self.rotation.eval(t, self.period, piece_t);
        let (_, ddot, dddot) = self.translation.eval(t, self.period, piece_t);
        let down = V3::new(0.0, 0.0, -g);
        Kinematics {
            omega: k * dq,
            alpha: k * ddq,
            center: self.center,
            vel_center: k * ddot,
            accel_center: k * dddot,
            gravity: if tilt { rotate(&down, &k, -q) } else { down },
        }
    }
}

/// A motion ready for repeated kinematics evaluation.
#[derive(Debug, Clone)]
pub struct PreparedMotion<'a> {
    motion: &'a Motion,
    screw: Option<PreparedScrew>,
}

impl<'a> PreparedMotion<'a> {
    /// The constants of `motion` (a screw's; other motions are evaluated
    /// as they are).
    pub fn new(motion: &'a Motion) -> PreparedMotion<'a> {
        let screw = match motion {
            Motion::Screw(s) => Some(PreparedScrew::new(s)),
            Motion::Signals(_) | Motion::Ramped(_) => None,
        };
        PreparedMotion { motion, screw }
    }

    /// [`Motion::kinematics_piece`], bitwise.
    #[inline]
    pub fn kinematics_piece(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        match &self.screw {
            Some(s) => s.kinematics(t, piece_t, g, tilt),
            None => self.motion.kinematics_piece(t, piece_t, g, tilt),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::FourierTerm;

    /// Every waveform kind, on rotation and translation, along a tilted
    /// axis: the prepared kinematics equal the direct ones bit for bit at
    /// instants over two periods (negative, inside, past), tilt on and off.
    #[test]
    fn prepared_kinematics_are_bitwise_direct() {
        let fourier = Waveform::Fourier {
            terms: vec![
                FourierTerm {
                    amplitude: -3.7,
                    phase: 0.3,
                    harmonic: 1,
                },
                FourierTerm {
                    amplitude: 1.9,
                    phase: -1.1,
                    harmonic: 3,
                },
            ],
            offset: 0.012,
        };
        let waves = [
            Waveform::Zero,
            Waveform::Sine { accel: 2.5 },
            Waveform::Square { accel: -4.0 },
            Waveform::RestToRest { amplitude: 0.004 },
            fourier,
        ];
        let mut compared = 0;
        for rotation in &waves {
            for translation in &waves {
                let motion = Motion::Screw(Screw {
                    axis: [0.3, -0.5, 0.8],
                    point: [0.01, -0.02, -0.05],
                    period: 0.031,
                    rotation: rotation.clone(),
                    translation: translation.clone(),
                });
                let prepared = PreparedMotion::new(&motion);
                for i in -20..=80 {
                    let t = 0.031 * i as f64 / 37.0 + 1e-5;
                    let piece = t + 1e-4;
                    for tilt in [false, true] {
                        let a = prepared.kinematics_piece(t, piece, 9.81, tilt);
                        let b = motion.kinematics_piece(t, piece, 9.81, tilt);
                        let bits = |k: &Kinematics| {
                            [
                                k.omega,
                                k.alpha,
                                k.center,
                                k.vel_center,
                                k.accel_center,
                                k.gravity,
                            ]
                            .map(|v| v.map(f64::to_bits))
                        };
                        assert_eq!(bits(&a), bits(&b), "{motion:?} t {t} tilt {tilt}");
                        compared += 1;
                    }
                }
            }
        }
        assert_eq!(compared, 25 * 101 * 2);
    }
}
