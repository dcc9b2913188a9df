//! General periodic 6-DOF motion: six plate-centre signals, each a sum of
//! sinusoids `A sin(n·2πt/T + φ)`: translational acceleration p''(t) along
//! the world x, y, z axes (m/s²), and the second derivative θ''(t) of the
//! plate's rotation vector θ (rad/s²), R = exp(\[θ\]×).
//!
//! Velocities and poses are the zero-mean antiderivatives: p, p' and θ, θ'
//! are periodic. The plate's physical angular velocity and acceleration
//! follow from θ exactly ([`super::rotation`]): ω = J(θ)θ' and α = ω' in
//! world axes, equal to θ' and θ'' to first order in the (small) rotation
//! and exactly when the plate turns about one fixed axis. An export writes
//! those world-frame ω' (`crate::schedule::export`), so a controller that
//! composes them as rotations plays the orientation exp(\[θ\]×). In the
//! plate frame: Ω = Rᵀω, Ω' = Rᵀα, c = 0, v_c = Rᵀp', a_c = Rᵀp'',
//! g_S = Rᵀ(0,0,−g). With the tilt switch off (the small-angle model)
//! R = I and Ω = θ', Ω' = θ''.

use serde::{Deserialize, Serialize};

use super::{rotate_sc, rotation, FourierTerm, Invariance, Kinematics, Waveform, V3};
use crate::error::{positive, Result};

/// Three Fourier-series signals about/along the world x, y and z axes.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Axes {
    /// Terms of the x signal.
    #[serde(default)]
    pub x: Vec<FourierTerm>,
    /// Terms of the y signal.
    #[serde(default)]
    pub y: Vec<FourierTerm>,
    /// Terms of the z signal.
    #[serde(default)]
    pub z: Vec<FourierTerm>,
}

impl Axes {
    fn waves(&self) -> [Waveform; 3] {
        [&self.x, &self.y, &self.z].map(|terms| Waveform::Fourier {
            terms: terms.clone(),
            offset: 0.0,
        })
    }

    /// (value, rate, acceleration) vectors at time t.
    fn eval(&self, t: f64, period: f64) -> [V3; 3] {
        let mut out = [V3::zeros(); 3];
        for (i, terms) in [&self.x, &self.y, &self.z].into_iter().enumerate() {
            let w = 2.0 * std::f64::consts::PI / period;
            for term in terms {
                let wn = w * f64::from(term.harmonic);
                let (s, c) = (wn * t + term.phase).sin_cos();
                out[0][i] -= term.amplitude / (wn * wn) * s;
                out[1][i] -= term.amplitude / wn * c;
                out[2][i] += term.amplitude * s;
            }
        }
        out
    }

    fn is_zero(&self) -> bool {
        [&self.x, &self.y, &self.z]
            .iter()
            .all(|ts| ts.iter().all(|t| t.amplitude == 0.0))
    }
}

/// Six-signal periodic motion of the plate centre.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Signals {
    /// Period T (s).
    pub period: f64,
    /// Translational acceleration of the plate centre (m/s²), world axes.
    #[serde(default)]
    pub linear: Axes,
    /// Second time derivative θ'' of the plate's rotation vector θ
    /// (rad/s², world axes, right-handed; R = exp(\[θ\]×)): to first order
    /// in the rotation, the angular acceleration about the world axes (see
    /// the module documentation for the exact one).
    #[serde(default)]
    pub angular: Axes,
}

impl Signals {
    /// A six-signal motion for timings (benches, `platefield study probes`):
    /// T = 0.05 s, x and y translation (the x one with a second harmonic)
    /// and tilts about x and y — the kind synthesis evaluates hundreds of
    /// (the motion of `tests/unit/synth.rs`).
    pub fn example() -> Signals {
        let term = |amplitude: f64, phase: f64, harmonic: u32| FourierTerm {
            amplitude,
            phase,
            harmonic,
        };
        Signals {
            period: 0.05,
            linear: Axes {
                x: vec![term(10.0, 1.37, 1), term(2.0, 0.3, 2)],
                y: vec![term(10.0, -0.17, 1)],
                z: Vec::new(),
            },
            angular: Axes {
                x: vec![term(65.0, 1.83, 1)],
                y: vec![term(65.0, 0.28, 1)],
                z: Vec::new(),
            },
        }
    }

    /// The highest harmonic of any signal (1 when there is none).
    pub(crate) fn highest_harmonic(&self) -> u32 {
        [&self.linear, &self.angular]
            .iter()
            .flat_map(|a| [&a.x, &a.y, &a.z])
            .flat_map(|terms| terms.iter().map(|t| t.harmonic))
            .max()
            .unwrap_or(1)
            .max(1)
    }

    /// Kinematics at time `t`.
    #[inline]
    pub(crate) fn kinematics(&self, t: f64, g: f64, tilt: bool) -> Kinematics {
        let (lin, ang) = self.centre_triples(t);
        Signals::frame(&lin, &ang, g, tilt)
    }

    /// World-frame (value, rate, acceleration) of the plate centre at `t`:
    /// linear (pose p, p', p'') and angular (rotation vector θ, ω, ω').
    #[inline]
    pub(crate) fn centre_triples(&self, t: f64) -> ([V3; 3], [V3; 3]) {
        (
            self.linear.eval(t, self.period),
            self.angular.eval(t, self.period),
        )
    }

    /// Plate-frame kinematics from the world-frame centre triples (p, p',
    /// p'') and (θ, θ', θ'') (module docs: R = exp(\[θ\]×), ω and α from
    /// θ exactly and every vector rotated back by Rᵀ when `tilt`; Ω = θ',
    /// Ω' = θ'' and R = I when not).
    #[inline]
    pub(crate) fn frame(lin: &[V3; 3], ang: &[V3; 3], g: f64, tilt: bool) -> Kinematics {
        Signals::frame_with(lin, ang, g, tilt, f64::sin_cos)
    }

    /// [`Signals::frame`] with `sin_cos` for the tilt angle's sine and
    /// cosine (worked out once for the five rotated vectors).
    #[inline]
    pub(crate) fn frame_with(
        lin: &[V3; 3],
        ang: &[V3; 3],
        g: f64,
        tilt: bool,
        sin_cos: impl Fn(f64) -> (f64, f64),
    ) -> Kinematics {
        let [_, v, a] = lin;
        let [theta, dtheta, ddtheta] = ang;
        let down = V3::new(0.0, 0.0, -g);
        let angle = theta.norm();
        if !tilt || angle == 0.0 {
            // The small-angle model (or no rotation): Ω = θ′, Ω′ = θ″.
            return Kinematics {
                omega: *dtheta,
                alpha: *ddtheta,
                center: V3::zeros(),
                vel_center: *v,
                accel_center: *a,
                gravity: down,
            };
        }
        let (s, c) = sin_cos(angle);
        let (w, dw) = rotation::world_rates(theta, dtheta, ddtheta, |_| (s, c));
        let axis = theta / angle;
        let back = |x: V3| rotate_sc(&x, &axis, (-s, c));
        Kinematics {
            omega: back(w),
            alpha: back(dw),
            center: V3::zeros(),
            vel_center: back(*v),
            accel_center: back(*a),
            gravity: back(down),
        }
    }

    /// The points this motion moves alike ([`Invariance`]): every point
    /// without angular signals; the lines along x (or y) when only the
    /// angular signal about x (or y) is driven, for then Ω, Ω' and the
    /// rotation R stay about that axis whatever the linear signals; the
    /// circles about the centre when only the angular signal about z and
    /// the linear one along z are driven.
    pub(crate) fn invariance(&self) -> Invariance {
        let zero = |terms: &[FourierTerm]| terms.iter().all(|t| t.amplitude == 0.0);
        let (a, l) = (&self.angular, &self.linear);
        match (zero(&a.x), zero(&a.y), zero(&a.z)) {
            (true, true, true) => Invariance::Uniform,
            (false, true, true) => Invariance::Along([1.0, 0.0]),
            (true, false, true) => Invariance::Along([0.0, 1.0]),
            (true, true, false) if zero(&l.x) && zero(&l.y) => Invariance::About([0.0, 0.0]),
            _ => Invariance::None,
        }
    }

    /// True when only x, y translation and z rotation are driven.
    pub(crate) fn is_in_plane(&self) -> bool {
        let only = |axes: &Axes, keep_z: bool| {
            let mut a = axes.clone();
            if keep_z {
                a.z.clear();
            } else {
                a.x.clear();
                a.y.clear();
            }
            a.is_zero()
        };
        only(&self.linear, false) && only(&self.angular, true)
    }

    /// Validates parameters.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        positive(&format!("{field}.period"), self.period)?;
        for (group, axes) in [("linear", &self.linear), ("angular", &self.angular)] {
            for (name, w) in ["x", "y", "z"].iter().zip(axes.waves()) {
                w.validate(&format!("{field}.{group}.{name}"))?;
            }
        }
        Ok(())
    }

    /// Rotated about the vertical by `angle` (rad), then shifted
    /// horizontally by `shift` (m). The new plate centre is the old plate
    /// point −s: it moves as the old centre plus (I − R_z(θ_z(t))) s, the
    /// offset of a point turned with the plate about the vertical through
    /// the old centre. That offset's acceleration −(R_z(θ_z) s)'' is added
    /// to the linear x and y signals as Fourier terms
    /// (`turned_offset_terms` below): to first order in θ_z it is Ω'_z ẑ × (−s);
    /// its second-order part, (θ_z²/2)'' s at twice the spin's harmonics,
    /// is what a spin of angular amplitude θ_z needs for the plate frame's
    /// centripetal acceleration about the moved centre. The vertical
    /// signal gets the tilts' lever Ω' × (−s) to first order in the tilt
    /// (milliradians: its second-order part is below 10⁻⁵ of it).
    /// Screw motions shift exactly.
    pub fn transformed(&self, angle: f64, shift: [f64; 2]) -> Signals {
        let (s, c) = angle.sin_cos();
        let rot = |axes: &Axes| -> Axes {
            // Rotate the vector signal: mix x and y terms.
            let mut x: Vec<FourierTerm> = axes.x.iter().map(|t| scale(t, c)).collect();
            x.extend(axes.y.iter().map(|t| scale(t, -s)));
            let mut y: Vec<FourierTerm> = axes.x.iter().map(|t| scale(t, s)).collect();
            y.extend(axes.y.iter().map(|t| scale(t, c)));
            Axes {
                x,
                y,
                z: axes.z.clone(),
            }
        };
        let angular = rot(&self.angular);
        let mut linear = rot(&self.linear);
        let (sx, sy) = (shift[0], shift[1]);
        let [ox, oy] = turned_offset_terms(&angular.z, self.period, shift);
        linear.x.extend(ox);
        linear.y.extend(oy);
        // Ω' × (−s) with s = (sx, sy, 0), vertical part: −Ω'_x sy + Ω'_y sx
        linear.z.extend(angular.x.iter().map(|t| scale(t, -sy)));
        linear.z.extend(angular.y.iter().map(|t| scale(t, sx)));
        Signals {
            period: self.period,
            linear,
            angular,
        }
    }

    /// The mirror image of this motion in the vertical plane y = 0 (the
    /// reflection M = diag(1, −1, 1)): the centre's translation p → Mp, so
    /// the linear y signal changes sign; the rotation R → MRM, whose
    /// rotation vector θ → (−θx, θy, −θz) (M·\[θ\]×·M = \[det(M)·Mθ\]×), so the
    /// angular x and z signals change sign. Gravity is unchanged, so a part
    /// at (x, −y) moves as the mirror image of a part at (x, y) under the
    /// original motion, at every friction: the field becomes
    /// F'(x, y) = (Fx(x, −y), −Fy(x, −y)). Exact (no small-amplitude step).
    pub(crate) fn mirrored_y(&self) -> Signals {
        let neg = |terms: &[FourierTerm]| -> Vec<FourierTerm> {
            terms.iter().map(|t| scale(t, -1.0)).collect()
        };
        Signals {
            period: self.period,
            linear: Axes {
                y: neg(&self.linear.y),
                ..self.linear.clone()
            },
            angular: Axes {
                x: neg(&self.angular.x),
                y: self.angular.y.clone(),
                z: neg(&self.angular.z),
            },
        }
    }

    /// The mirror image in the vertical plane through the centre at `angle`
    /// (rad) from x: turned by −angle, mirrored in y = 0
    /// ([`Signals::mirrored_y`]), turned back. Exact: a turn about the
    /// vertical through the centre has no shift.
    pub(crate) fn mirrored_about(&self, angle: f64) -> Signals {
        self.transformed(-angle, [0.0, 0.0])
            .mirrored_y()
            .transformed(angle, [0.0, 0.0])
    }

    /// The mirror image in the vertical plane at `angle` (rad) from x
    /// through the plate point `point` (m): a reflection S about a line
    /// off the centre conjugates the whole plate motion by S, its
    /// reference point included. Shifted so that `point` is the centre
    /// ([`Signals::transformed`] by −point), mirrored through the centre
    /// ([`Signals::mirrored_about`]), shifted back: the field becomes
    /// F′(q) = M F(M (q − c) + c), M the reflection's linear part, c the
    /// point. The shifts are exact for turns and translations and first
    /// order in the tilts (see [`Signals::transformed`]); through the
    /// centre this is [`Signals::mirrored_about`] itself.
    pub(crate) fn mirrored_in(&self, angle: f64, point: [f64; 2]) -> Signals {
        if point == [0.0, 0.0] {
            return self.mirrored_about(angle);
        }
        self.transformed(0.0, [-point[0], -point[1]])
            .mirrored_about(angle)
            .transformed(0.0, point)
    }

    /// The motion a controller delivers with per-channel errors: every term
    /// of channel `c` (linear x, y, z, angular x, y, z = 0…5) at harmonic
    /// h has its amplitude multiplied by `gain(c, h)` and `shift(c, h)`
    /// (rad) added to its phase — a transfer function's error at that
    /// channel and frequency.
    pub(crate) fn delivered(&self, error: &dyn Fn(usize, u32) -> (f64, f64)) -> Signals {
        let channel = |c: usize, terms: &[FourierTerm]| -> Vec<FourierTerm> {
            terms
                .iter()
                .map(|t| {
                    let (gain, shift) = error(c, t.harmonic);
                    FourierTerm {
                        amplitude: t.amplitude * gain,
                        phase: t.phase + shift,
                        harmonic: t.harmonic,
                    }
                })
                .collect()
        };
        let axes = |a: &Axes, first: usize| Axes {
            x: channel(first, &a.x),
            y: channel(first + 1, &a.y),
            z: channel(first + 2, &a.z),
        };
        Signals {
            period: self.period,
            linear: axes(&self.linear, 0),
            angular: axes(&self.angular, 3),
        }
    }

    /// Every amplitude multiplied by `k` (the same waveforms, scaled).
    pub(crate) fn scaled(&self, k: f64) -> Signals {
        let axes = |a: &Axes| Axes {
            x: a.x.iter().map(|t| scale(t, k)).collect(),
            y: a.y.iter().map(|t| scale(t, k)).collect(),
            z: a.z.iter().map(|t| scale(t, k)).collect(),
        };
        Signals {
            period: self.period,
            linear: axes(&self.linear),
            angular: axes(&self.angular),
        }
    }
}

/// Samples per period and per harmonic of the angular z signal on which
/// [`turned_offset_terms`] takes the offset's Fourier series.
const OFFSET_SAMPLES: usize = 128;
/// Offset terms below this acceleration amplitude (m/s²) are left out …
const OFFSET_FLOOR: f64 = 1e-9;
/// … and those whose displacement amplitude is below this fraction of
/// |s|: the transform's round-off (about 1e-16 |s|), which (hω)² lifts
/// above [`OFFSET_FLOOR`] at high harmonics (1–5e-9 m/s² at harmonics
/// 44–64 of a 33 Hz motion turned twice, more than its integration step
/// resolves).
const OFFSET_REL_FLOOR: f64 = 1e-13;

/// The acceleration −(R_z(θ_z(t)) s)'' of the plate point s turned with
/// the plate about the vertical through the centre, θ_z(t) the zero-mean
/// angle of the angular z signal `z`: its x and y Fourier terms.
///
/// The offset is periodic, so its terms come from a discrete Fourier
/// transform of R_z(θ_z) s on N = [`OFFSET_SAMPLES`] × the highest
/// harmonic of `z` samples per period: with p(t) ≈ a_h cos hωt + b_h sin
/// hωt per harmonic h ≤ N/4, −p'' has the term (hω)² √(a_h² + b_h²) ·
/// sin(hωt + atan2(a_h, b_h)). For one spin term of angular amplitude Φ
/// the harmonic-h amplitude is 2 J_h(Φ) (hω)² |s| (Bessel J_h): Φω²|s| at
/// h = 1, the first-order Ω'_z ẑ × (−s), then Φ²ω²|s| at h = 2 and
/// falling as Φ^h; terms below [`OFFSET_FLOOR`] or
/// [`OFFSET_REL_FLOOR`] |s| are left out. No spin or no shift: no terms.
pub(crate) fn turned_offset_terms(
    z: &[FourierTerm],
    period: f64,
    s: [f64; 2],
) -> [Vec<FourierTerm>; 2] {
    let highest = z.iter().map(|t| t.harmonic).max().unwrap_or(0) as usize;
    if highest == 0 || s == [0.0, 0.0] {
        return [Vec::new(), Vec::new()];
    }
    let angle = Axes {
        z: z.to_vec(),
        ..Axes::default()
    };
    let n = OFFSET_SAMPLES * highest;
    let turn = |k: usize| 2.0 * std::f64::consts::PI * k as f64 / n as f64;
    let path: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            let theta = angle.eval(period * k as f64 / n as f64, period)[0].z;
            let (sn, cs) = theta.sin_cos();
            [cs * s[0] - sn * s[1], sn * s[0] + cs * s[1]]
        })
        .collect();
    let w = 2.0 * std::f64::consts::PI / period;
    let mut out = [Vec::new(), Vec::new()];
    for h in 1..=n / 4 {
        for (axis, terms) in out.iter_mut().enumerate() {
            let (a, b) = path.iter().enumerate().fold((0.0, 0.0), |(a, b), (k, p)| {
                let (sn, cs) = (h as f64 * turn(k)).sin_cos();
                (a + p[axis] * cs, b + p[axis] * sn)
            });
            let (a, b) = (2.0 * a / n as f64, 2.0 * b / n as f64);
            let amplitude = (h as f64 * w).powi(2) * a.hypot(b);
            if amplitude > OFFSET_FLOOR && a.hypot(b) > OFFSET_REL_FLOOR * s[0].hypot(s[1]) {
                terms.push(FourierTerm {
                    amplitude,
                    phase: a.atan2(b),
                    harmonic: h as u32,
                });
            }
        }
    }
    out
}

fn scale(t: &FourierTerm, k: f64) -> FourierTerm {
    FourierTerm {
        amplitude: t.amplitude * k,
        ..*t
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A translation with a spin of angular amplitude 0.11 rad (the
    /// triangle's strongest spin).
    fn spun() -> Signals {
        let term = |amplitude: f64, phase: f64| FourierTerm {
            amplitude,
            phase,
            harmonic: 1,
        };
        Signals {
            period: 0.03,
            linear: Axes {
                x: vec![term(6.8, 0.0)],
                y: vec![term(6.8, 1.57)],
                z: Vec::new(),
            },
            angular: Axes {
                x: Vec::new(),
                y: Vec::new(),
                z: vec![term(4800.0, -1.6)],
            },
        }
    }

    /// Moved by s, the plate's velocity and acceleration (centripetal
    /// included, in the plate frame) at plate point r are the unmoved
    /// motion's at r − s, at every time: the rigid motion moved, exactly
    /// up to the offset's truncation (10⁻⁹ of the spin's lever α|s|).
    /// The first-order shift alone misses it by the centripetal term's
    /// order, Φ²ω²|s|.
    #[test]
    fn shift_moves_the_plate_physics_at_a_large_spin() {
        let (m, s) = (spun(), [0.012, -0.007]);
        let moved = m.transformed(0.0, s);
        let lever = 4800.0 * s[0].hypot(s[1]);
        let r = V3::new(0.004, 0.009, 0.0);
        let d = r - V3::new(s[0], s[1], 0.0);
        let worst = |moved: &Signals| {
            (0..37).fold(0.0_f64, |worst, k| {
                let t = 0.03 * k as f64 / 37.0;
                let (a, b) = (m.kinematics(t, 9.81, true), moved.kinematics(t, 9.81, true));
                let gap = (a.acceleration_at(&d, true) - b.acceleration_at(&r, true)).norm();
                let vgap = (a.velocity_at(&d) - b.velocity_at(&r)).norm();
                worst.max(gap / lever).max(vgap / (lever * 0.03))
            })
        };
        assert!(worst(&moved) < 1e-9, "{:e}", worst(&moved));
        // First order only (Ω'_z ẑ × (−s)): off by about Φ = α/ω² = 0.11.
        let mut first = m.clone();
        first
            .linear
            .x
            .extend(m.angular.z.iter().map(|t| scale(t, s[1])));
        first
            .linear
            .y
            .extend(m.angular.z.iter().map(|t| scale(t, -s[0])));
        assert!(worst(&first) > 0.05, "{:e}", worst(&first));
        // The offset's harmonics against the Bessel series 2 J_h(Φ) (hω)² |s|:
        // odd ones along ẑ × s (y), even ones along s (x).
        let w = 2.0 * std::f64::consts::PI / 0.03;
        let phi = 4800.0 / (w * w);
        let j1 = phi / 2.0 - phi.powi(3) / 16.0 + phi.powi(5) / 384.0;
        let j2 = phi.powi(2) / 8.0 - phi.powi(4) / 96.0;
        let [ox, oy] = turned_offset_terms(&m.angular.z, 0.03, [0.01, 0.0]);
        let amp = |terms: &[FourierTerm], h: u32| {
            let t: Vec<_> = terms.iter().filter(|t| t.harmonic == h).collect();
            assert!(t.len() <= 1, "{t:?}");
            t.first().map_or(0.0, |t| t.amplitude)
        };
        assert!((amp(&oy, 1) / (2.0 * j1 * w * w * 0.01) - 1.0).abs() < 1e-9);
        assert!((amp(&ox, 2) / (2.0 * j2 * 4.0 * w * w * 0.01) - 1.0).abs() < 1e-6);
        assert_eq!((amp(&ox, 1), amp(&oy, 2)), (0.0, 0.0));
    }

    /// A worked example of `motion::signals::Signals::highest_harmonic`.
    #[test]
    fn example_signals_highest_harmonic() {
        use crate::motion::Signals;
        assert_eq!(Signals::example().highest_harmonic(), 2);
    }

    /// A worked example of `motion::signals::Signals::mirrored_in`.
    #[test]
    fn example_signals_mirrored_in() {
        use crate::motion::Signals;
        let m = Signals::example();
        assert_eq!(m.mirrored_in(0.3, [0.0, 0.0]), m.mirrored_about(0.3));
        // The mirror image of the mirror image is the motion again.
        let c = [0.004, -0.002];
        let twice = m.mirrored_in(0.3, c).mirrored_in(0.3, c);
        for t in [0.0, 0.007, 0.019] {
            let (a, b) = (m.kinematics(t, 9.81, true), twice.kinematics(t, 9.81, true));
            assert!((a.accel_center - b.accel_center).norm() < 1e-6, "{t}");
            assert!((a.alpha - b.alpha).norm() < 1e-9, "{t}");
        }
    }

    /// A worked example of `motion::signals::Signals::delivered`.
    #[test]
    fn example_signals_delivered() {
        use crate::motion::Signals;
        let m = Signals::example();
        let d = m.delivered(&|_, _| (1.05, 0.1));
        let (a, b) = (&m.linear.x[0], &d.linear.x[0]);
        assert!((b.amplitude - 1.05 * a.amplitude).abs() < 1e-12);
        assert!((b.phase - a.phase - 0.1).abs() < 1e-12);
        assert_eq!(m.delivered(&|_, _| (1.0, 0.0)), m);
    }
}
