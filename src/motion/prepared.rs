//! A motion's kinematics with its constants worked out once, and sin and
//! cos by angle addition from a table instead of libm.
//!
//! The integrator evaluates the plate kinematics at thousands of instants
//! off the kinematics table's grid per field (the stages of τ-steps and
//! implicit steps, event location). For a screw, each evaluation off the
//! table would normalise the axis and divide the waveform amplitudes by ω
//! and ω² again, and call libm's `sin_cos` three times (rotation, translation,
//! the gravity tilt). [`PreparedMotion`] holds those quotients and performs
//! the rest of [`Screw::kinematics`] and [`Waveform::eval_piece`] (for a
//! six-signal motion, of [`Signals::kinematics`]) with the same operations
//! in the same order, except that every sine and cosine comes from
//! [`trig::Nodes::sin_cos`], which is libm's to 2.3e-16 absolute. So each waveform
//! value differs from the direct [`Motion::kinematics_piece`] by at most
//! 2.3e-16 times its amplitude (a Fourier series: the sum of its terms'
//! amplitudes), the tilted gravity by as much times g (1 + |q|), q the tilt
//! angle (whose own difference turns it), and the products and sums the
//! kinematics form from them add an ulp or two of their own: the test bounds
//! every component by 4e-16 of its scale. A ramped six-signal motion
//! ([`super::Ramped`]) takes its steady triples so and applies its window
//! as it does; a held export is evaluated as it is.

use std::f64::consts::PI;

use super::{
    rotate_sc, trig, FourierTerm, Kinematics, Motion, Ramped, Screw, Signals, Waveform, V3,
};

/// Fourier terms' constants: per term nω, φ, a/(nω)², a/(nω) and a.
type Terms = Vec<[f64; 5]>;

/// The constants of the acceleration terms `terms` at base frequency `om`.
fn prepare(terms: &[FourierTerm], om: f64) -> Terms {
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
        .collect()
}

/// (q, q', q'') of a Fourier series at `t`, q starting from `q0`, summed
/// term by term as [`Waveform::eval_piece`] does.
#[inline(always)]
fn series(trig: &trig::Nodes, terms: &Terms, q0: f64, t: f64) -> (f64, f64, f64) {
    let (mut q, mut dq, mut ddq) = (q0, 0.0, 0.0);
    for [wn, phase, qa, dqa, a] in terms {
        let (s, c) = trig.sin_cos(wn * t + phase);
        q -= qa * s;
        dq -= dqa * c;
        ddq += a * s;
    }
    (q, dq, ddq)
}

/// A waveform's constants: each coefficient is the quotient or product
/// [`Waveform::eval_piece`] forms before multiplying by sin or cos.
#[derive(Debug, Clone)]
enum Wave {
    Zero,
    /// −a/ω², −a/ω, a, ω.
    Sine([f64; 4]),
    /// q0, q0 ω, q0 ω², ω.
    RestToRest([f64; 4]),
    /// The terms; the offset.
    Fourier(Terms, f64),
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
            Waveform::Fourier { terms, offset } => Wave::Fourier(prepare(terms, om), *offset),
            Waveform::Square { .. } => Wave::Other(w.clone()),
        }
    }

    /// (q, q', q'') at `t`, as [`Waveform::eval_piece`] (to round-off).
    #[inline(always)]
    fn eval(&self, trig: &trig::Nodes, t: f64, period: f64, piece_t: f64) -> (f64, f64, f64) {
        match self {
            Wave::Zero => (0.0, 0.0, 0.0),
            Wave::Sine([q, dq, ddq, om]) => {
                let (s, c) = trig.sin_cos(om * t);
                (q * s, dq * c, ddq * s)
            }
            Wave::RestToRest([a, aw, aww, om]) => {
                let (s, c) = trig.sin_cos(om * t);
                (a * (1.0 - c), aw * s, aww * c)
            }
            Wave::Fourier(terms, offset) => series(trig, terms, *offset, t),
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
    trig: &'static trig::Nodes,
    k: V3,
    center: V3,
    period: f64,
    rotation: Wave,
    translation: Wave,
}

impl PreparedScrew {
    fn new(s: &Screw) -> PreparedScrew {
        PreparedScrew {
            trig: trig::table(),
            k: V3::from(s.axis).normalize(),
            center: V3::from(s.point),
            period: s.period,
            rotation: Wave::new(&s.rotation, s.period),
            translation: Wave::new(&s.translation, s.period),
        }
    }

    /// As [`Screw::kinematics`] (to round-off).
    #[inline]
    fn kinematics(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        let k = self.k;
        let (q, dq, ddq) = self.rotation.eval(self.trig, t, self.period, piece_t);
        let (_, ddot, dddot) = self.translation.eval(self.trig, t, self.period, piece_t);
        let down = V3::new(0.0, 0.0, -g);
        Kinematics {
            omega: k * dq,
            alpha: k * ddq,
            center: self.center,
            vel_center: k * ddot,
            accel_center: k * dddot,
            gravity: if tilt && q != 0.0 {
                rotate_sc(&down, &k, self.trig.sin_cos(-q))
            } else {
                down
            },
        }
    }
}

/// A six-signal motion's constants: the terms of the x, y, z signals,
/// linear and angular.
#[derive(Debug, Clone)]
struct PreparedSignals {
    trig: &'static trig::Nodes,
    linear: [Terms; 3],
    angular: [Terms; 3],
}

impl PreparedSignals {
    fn new(s: &Signals) -> PreparedSignals {
        let om = 2.0 * PI / s.period;
        let axes = |a: &super::Axes| [&a.x, &a.y, &a.z].map(|terms| prepare(terms, om));
        PreparedSignals {
            trig: trig::table(),
            linear: axes(&s.linear),
            angular: axes(&s.angular),
        }
    }

    /// (value, rate, acceleration) vectors of one group at `t`.
    #[inline(always)]
    fn eval(&self, group: &[Terms; 3], t: f64) -> [V3; 3] {
        let mut out = [V3::zeros(); 3];
        for (i, terms) in group.iter().enumerate() {
            (out[0][i], out[1][i], out[2][i]) = series(self.trig, terms, 0.0, t);
        }
        out
    }

    /// The centre triples (linear, angular) at `t`, as
    /// [`Signals::centre_triples`] (to round-off).
    #[inline]
    fn triples(&self, t: f64) -> ([V3; 3], [V3; 3]) {
        (self.eval(&self.linear, t), self.eval(&self.angular, t))
    }

    /// As [`Signals::kinematics`] (to round-off).
    #[inline]
    fn kinematics(&self, t: f64, g: f64, tilt: bool) -> Kinematics {
        let (lin, ang) = self.triples(t);
        Signals::frame_with(&lin, &ang, g, tilt, |x| self.trig.sin_cos(x))
    }
}

/// A motion's prepared form.
#[derive(Debug, Clone)]
enum Prepared<'a> {
    Screw(PreparedScrew),
    Signals(PreparedSignals),
    /// A ramped motion's steady signals (its window applied as it is).
    Ramped(PreparedSignals, &'a Ramped),
    /// Evaluated as it is.
    Direct,
}

/// A motion ready for repeated kinematics evaluation.
#[derive(Debug, Clone)]
pub(crate) struct PreparedMotion<'a> {
    motion: &'a Motion,
    prepared: Prepared<'a>,
}

impl<'a> PreparedMotion<'a> {
    /// The constants of `motion` (a screw's, a six-signal motion's, ramped
    /// or not; a held export is evaluated as it is).
    pub(crate) fn new(motion: &'a Motion) -> PreparedMotion<'a> {
        let prepared = match motion {
            Motion::Screw(s) => Prepared::Screw(PreparedScrew::new(s)),
            Motion::Signals(s) => Prepared::Signals(PreparedSignals::new(s)),
            Motion::Ramped(r) => Prepared::Ramped(PreparedSignals::new(&r.signals), r),
            Motion::Held(_) => Prepared::Direct,
        };
        PreparedMotion { motion, prepared }
    }

    /// `motion` evaluated as it is ([`Motion::kinematics_piece`], libm's
    /// sin and cos): bitwise the direct values, where an evaluation is
    /// rare and those bits matter more than its cost.
    pub(crate) fn direct(motion: &'a Motion) -> PreparedMotion<'a> {
        PreparedMotion {
            motion,
            prepared: Prepared::Direct,
        }
    }

    /// [`Motion::kinematics_piece`] to round-off (module docs).
    #[inline]
    pub(crate) fn kinematics_piece(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        match &self.prepared {
            Prepared::Screw(s) => s.kinematics(t, piece_t, g, tilt),
            Prepared::Signals(s) => s.kinematics(t, g, tilt),
            Prepared::Ramped(s, r) => {
                r.kinematics_of(t, s.triples(t), g, tilt, |x| s.trig.sin_cos(x))
            }
            Prepared::Direct => self.motion.kinematics_piece(t, piece_t, g, tilt),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::Axes;

    /// Scales of (q, q', q'') of a waveform: the sum of its terms'
    /// amplitudes in each (for the square wave, its bounds).
    fn scales(w: &Waveform, period: f64) -> [f64; 3] {
        let om = 2.0 * PI / period;
        match w {
            Waveform::Zero => [0.0; 3],
            Waveform::Sine { accel } => [accel / (om * om), accel / om, *accel].map(f64::abs),
            Waveform::Square { accel } => {
                [accel * period * period / 32.0, accel * period / 4.0, *accel].map(f64::abs)
            }
            Waveform::RestToRest { amplitude } => {
                [2.0 * amplitude, amplitude * om, amplitude * om * om].map(f64::abs)
            }
            Waveform::Fourier { terms, offset } => {
                let mut out = [offset.abs(), 0.0, 0.0];
                for t in terms {
                    let wn = om * f64::from(t.harmonic);
                    out[0] += (t.amplitude / (wn * wn)).abs();
                    out[1] += (t.amplitude / wn).abs();
                    out[2] += t.amplitude.abs();
                }
                out
            }
        }
    }

    /// Worst |prepared − direct| over (ω, Ω', v_c, a_c, g_S), each over
    /// its scale (a zero scale must give a zero difference), at 3000
    /// instants off any grid over −0.4 T … 12 T, tilt on and off.
    fn worst(motion: &Motion, scale: [f64; 5]) -> f64 {
        let prepared = PreparedMotion::new(motion);
        let period = motion.period();
        let mut worst = 0.0f64;
        for i in 0..3000 {
            let t = period * (-0.4 + 12.4 * (i as f64 + 0.271) / 3000.0);
            let piece = t + 1e-9 * period;
            for tilt in [false, true] {
                let a = prepared.kinematics_piece(t, piece, 9.81, tilt);
                let b = motion.kinematics_piece(t, piece, 9.81, tilt);
                let pairs = [
                    (a.omega, b.omega),
                    (a.alpha, b.alpha),
                    (a.vel_center, b.vel_center),
                    (a.accel_center, b.accel_center),
                    (a.gravity, b.gravity),
                ];
                assert_eq!(a.center, b.center);
                for ((x, y), s) in pairs.iter().zip(scale) {
                    let d = (x - y).amax();
                    if s == 0.0 {
                        assert_eq!(d, 0.0, "{motion:?} t {t}");
                    } else {
                        worst = worst.max(d / s);
                    }
                }
            }
        }
        worst
    }

    fn fourier() -> Waveform {
        Waveform::Fourier {
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
                FourierTerm {
                    amplitude: 0.7,
                    phase: 2.9,
                    harmonic: 7,
                },
            ],
            offset: 0.012,
        }
    }

    /// Every waveform kind, on rotation and translation, along a tilted
    /// axis, with rotation amplitudes small (the paper's primitives, tilts
    /// of 1e-2 rad) and large (tilts past the polynomial's range, up to
    /// 3 rad): the prepared kinematics equal the direct ones within 4e-16
    /// of each quantity's scale (module docs; gravity's g (1 + max |q|)),
    /// exactly where libm is used for both (the square wave's values).
    #[test]
    fn prepared_kinematics_are_direct_to_round_off() {
        let period = 0.031;
        let mut overall = 0.0f64;
        for big in [1.0, 300.0] {
            let waves = [
                Waveform::Zero,
                Waveform::Sine { accel: 2.5 * big },
                Waveform::Square { accel: -4.0 * big },
                Waveform::RestToRest {
                    amplitude: 0.004 * big,
                },
                fourier().scaled(big),
            ];
            for rotation in &waves {
                for translation in &waves {
                    let motion = Motion::Screw(Screw {
                        axis: [0.3, -0.5, 0.8],
                        point: [0.01, -0.02, -0.05],
                        period,
                        rotation: rotation.clone(),
                        translation: translation.clone(),
                    });
                    let [q, dq, ddq] = scales(rotation, period);
                    let [_, dd, ddd] = scales(translation, period);
                    // The tilt angle's own difference turns gravity too.
                    let w = worst(&motion, [dq, ddq, dd, ddd, 9.81 * (1.0 + q)]);
                    assert!(w <= 4e-16, "{motion:?}: {w:e}");
                    overall = overall.max(w);
                }
            }
        }
        println!("screws: worst difference {overall:e} of scale");
    }

    /// A six-signal motion (the timing example, and one with all six
    /// signals and harmonics up to 5), tilt up to 0.1 rad: within 4e-16 of
    /// each quantity's scale.
    #[test]
    fn prepared_signals_are_direct_to_round_off() {
        // (amplitude, phase, harmonic) of each signal's terms.
        let series = |terms: &[(f64, f64, u32)]| -> Vec<FourierTerm> {
            let term = |&(amplitude, phase, harmonic)| FourierTerm {
                amplitude,
                phase,
                harmonic,
            };
            terms.iter().map(term).collect()
        };
        let full = Signals {
            period: 0.04,
            linear: Axes {
                x: series(&[(10.0, 1.37, 1), (2.0, 0.3, 2)]),
                y: series(&[(-8.0, -0.17, 1), (1.0, 2.0, 5)]),
                z: series(&[(6.0, 0.9, 2)]),
            },
            angular: Axes {
                x: series(&[(65.0, 1.83, 1)]),
                y: series(&[(-40.0, 0.28, 1), (30.0, -2.5, 3)]),
                z: series(&[(800.0, 0.5, 1)]),
            },
        };
        let mut overall = 0.0f64;
        for s in [Signals::example(), full] {
            let om = 2.0 * PI / s.period;
            let sum = |a: &Axes, p: i32| {
                [&a.x, &a.y, &a.z]
                    .iter()
                    .flat_map(|ts| ts.iter())
                    .map(|t| t.amplitude.abs() / (om * f64::from(t.harmonic)).powi(p))
                    .sum::<f64>()
            };
            let scale = [
                sum(&s.angular, 1),
                sum(&s.angular, 0),
                sum(&s.linear, 1),
                sum(&s.linear, 0),
                9.81,
            ];
            let w = worst(&Motion::Signals(s.clone()), scale);
            assert!(w <= 4e-16, "{s:?}: {w:e}");
            overall = overall.max(w);
            // Ramped over 3 of 12 cycles each way: the window's w ≤ 1,
            // w′ ≤ 1.875/(RT), w″ ≤ 5.77/(RT)² raise each windowed triple
            // to at most 1 + 2·1.875/(2πR) + 5.77/(2πR)² ≈ 1.22 times the
            // steady scale (R = 3, ωT = 2π); the bound allows 2.
            let r = Motion::Ramped(Ramped::new(s.clone(), 3, 12, "segment").unwrap());
            let w = worst(&r, scale.map(|x| 2.0 * x));
            assert!(w <= 4e-16, "ramped {s:?}: {w:e}");
            overall = overall.max(w);
        }
        println!("six-signal: worst difference {overall:e} of scale");
    }
}
