//! The six-signal motion as a parameter vector.
//!
//! Each of the six plate-centre signals (linear x, y, z, angular x, y, z;
//! see [`crate::motion::Signals`]) is a sum over the allowed harmonics
//! n = 1..=H of `A sin(nωt + φ) = c sin(nωt) + s cos(nωt)` with
//! c = A cos φ, s = A sin φ. The optimizer works on (c, s) rather than
//! (A, φ): the map is smooth through A = 0 and has no phase wrap. Amplitude
//! and phase are recovered as A = hypot(c, s), φ = atan2(s, c).
//!
//! The parameter vector holds, for every axis whose limit is > 0 and every
//! harmonic, the pair (c, s) divided by the axis limit, so every entry is of
//! order one; axes with limit 0 are not in the vector and stay zero.

use std::f64::consts::PI;

use super::limits::ShakerLimits;
use crate::motion::{Axes, FourierTerm, Signals};

pub use crate::schedule::export::peaks::AXIS_NAMES;

/// Time samples per harmonic used to bracket a signal's peak before the
/// Newton polish (see [`Coefficients::peak`]).
const PEAK_SAMPLES_PER_HARMONIC: usize = 64;

/// Fourier coefficients of the six signals: `c[axis][n − 1] = [c, s]`
/// (physical units: m/s² or rad/s²).
#[derive(Debug, Clone, PartialEq)]
pub struct Coefficients {
    /// Fundamental period T (s).
    pub period: f64,
    /// Per axis, per harmonic: [A cos φ, A sin φ].
    pub c: [Vec<[f64; 2]>; 6],
}

impl Coefficients {
    /// All zero, `harmonics` harmonics per axis.
    pub fn zero(period: f64, harmonics: u32) -> Coefficients {
        let h = harmonics as usize;
        Coefficients {
            period,
            c: std::array::from_fn(|_| vec![[0.0; 2]; h]),
        }
    }

    /// Harmonics per axis.
    pub(crate) fn harmonics(&self) -> usize {
        self.c[0].len()
    }

    /// Sets axis `axis`, harmonic `n` (≥ 1) to `A sin(nωt + φ)`.
    pub fn set(&mut self, axis: usize, n: usize, amplitude: f64, phase: f64) {
        self.c[axis][n - 1] = [amplitude * phase.cos(), amplitude * phase.sin()];
    }

    /// The coefficients of `signals` with up to `harmonics` harmonics (terms
    /// of the same harmonic are summed; higher harmonics are dropped).
    pub(crate) fn from_signals(signals: &Signals, harmonics: u32) -> Coefficients {
        let mut out = Coefficients::zero(signals.period, harmonics);
        let groups = [&signals.linear, &signals.angular];
        for (g, axes) in groups.iter().enumerate() {
            for (i, terms) in [&axes.x, &axes.y, &axes.z].into_iter().enumerate() {
                for t in terms {
                    let n = t.harmonic as usize;
                    if (1..=out.harmonics()).contains(&n) {
                        let e = &mut out.c[3 * g + i][n - 1];
                        e[0] += t.amplitude * t.phase.cos();
                        e[1] += t.amplitude * t.phase.sin();
                    }
                }
            }
        }
        out
    }

    /// The six-signal motion (zero terms left out; amplitudes ≥ 0, phases
    /// in (−π, π]).
    pub fn to_signals(&self) -> Signals {
        let terms = |axis: usize| -> Vec<FourierTerm> {
            self.c[axis]
                .iter()
                .enumerate()
                .filter(|(_, cs)| cs[0] != 0.0 || cs[1] != 0.0)
                .map(|(k, cs)| FourierTerm {
                    amplitude: cs[0].hypot(cs[1]),
                    phase: cs[1].atan2(cs[0]),
                    harmonic: k as u32 + 1,
                })
                .collect()
        };
        let axes = |first: usize| Axes {
            x: terms(first),
            y: terms(first + 1),
            z: terms(first + 2),
        };
        Signals {
            period: self.period,
            linear: axes(0),
            angular: axes(3),
        }
    }

    /// Value and time derivative of signal `axis` at time `t`.
    fn eval(&self, axis: usize, t: f64) -> (f64, f64) {
        let w = 2.0 * PI / self.period;
        let mut v = 0.0;
        let mut dv = 0.0;
        for (k, cs) in self.c[axis].iter().enumerate() {
            let wn = w * (k + 1) as f64;
            let (s, c) = (wn * t).sin_cos();
            v += cs[0] * s + cs[1] * c;
            dv += wn * (cs[0] * c - cs[1] * s);
        }
        (v, dv)
    }

    /// Peak |value| of signal `axis` over the period: exact (the amplitude)
    /// for a single harmonic; otherwise the largest of 64 samples per
    /// harmonic, each local maximum polished by Newton's method on the
    /// derivative (second derivative by central difference), so the result
    /// is the true maximum to round-off once the grid brackets it.
    pub fn peak(&self, axis: usize) -> f64 {
        let c = &self.c[axis];
        let active: Vec<usize> = (0..c.len())
            .filter(|&k| c[k][0] != 0.0 || c[k][1] != 0.0)
            .collect();
        match active.as_slice() {
            [] => return 0.0,
            [k] => return c[*k][0].hypot(c[*k][1]),
            _ => {}
        }
        let n = PEAK_SAMPLES_PER_HARMONIC * c.len();
        let dt = self.period / n as f64;
        let vals: Vec<f64> = (0..n)
            .map(|i| self.eval(axis, i as f64 * dt).0.abs())
            .collect();
        let mut best = 0.0_f64;
        for i in 0..n {
            let (prev, next) = (vals[(i + n - 1) % n], vals[(i + 1) % n]);
            if vals[i] < prev || vals[i] < next {
                continue;
            }
            let mut t = i as f64 * dt;
            for _ in 0..8 {
                let h = 1e-4 * dt;
                let d1 = self.eval(axis, t).1;
                let d2 = (self.eval(axis, t + h).1 - self.eval(axis, t - h).1) / (2.0 * h);
                if d2 == 0.0 {
                    break;
                }
                let step = (d1 / d2).clamp(-dt, dt);
                t -= step;
                if step.abs() < 1e-15 * self.period {
                    break;
                }
            }
            best = best.max(vals[i]).max(self.eval(axis, t).0.abs());
        }
        best
    }

    /// Per-axis peaks.
    pub fn peaks(&self) -> [f64; 6] {
        std::array::from_fn(|a| self.peak(a))
    }

    /// Scales every axis whose peak exceeds its limit down onto the limit
    /// (axes with limit 0 are zeroed). Returns the total relative excess
    /// Σ max(0, peak/limit − 1) before scaling (a forbidden axis with a
    /// non-zero signal counts its peak relative to the largest limit).
    ///
    /// Then, where `limits` give a velocity or stroke limit, every axis
    /// whose summed velocity or displacement ([`Coefficients::antiderivative`])
    /// peaks above it is scaled onto it too, its relative excess added.
    pub(crate) fn clamp(&mut self, limits: &ShakerLimits) -> f64 {
        let excess = self.clamp_acceleration(limits);
        if limits.velocity.is_none() && limits.stroke.is_none() {
            return excess;
        }
        excess + self.clamp_travel(limits)
    }

    /// The peak-acceleration part of [`Coefficients::clamp`].
    /// An axis is forbidden where [`ShakerLimits::axes`] is 0 (a velocity
    /// or stroke limit of 0 forbids it too); the others are held to the
    /// acceleration limits as given.
    fn clamp_acceleration(&mut self, limits: &ShakerLimits) -> f64 {
        let (lim, allowed) = (limits.acceleration_axes(), limits.axes());
        let scale_ref = lim.iter().copied().fold(0.0, f64::max).max(1e-300);
        let mut excess = 0.0;
        for (a, l) in lim.iter().enumerate() {
            let p = self.peak(a);
            if allowed[a] <= 0.0 {
                excess += p / scale_ref;
                self.c[a].iter_mut().for_each(|cs| *cs = [0.0; 2]);
            } else if p > *l {
                excess += p / l - 1.0;
                let k = l / p;
                self.c[a]
                    .iter_mut()
                    .for_each(|cs| *cs = [cs[0] * k, cs[1] * k]);
            }
        }
        excess
    }

    /// The velocity and stroke part of [`Coefficients::clamp`]: each axis
    /// scaled by min(1, v_max / v, s_max / s) with v and s the peaks of its
    /// first and second antiderivatives.
    fn clamp_travel(&mut self, limits: &ShakerLimits) -> f64 {
        let velocity = self.antiderivative();
        let stroke = velocity.antiderivative();
        let (v_max, s_max) = (limits.velocity_axes(), limits.stroke_axes());
        let mut excess = 0.0;
        for a in 0..6 {
            let over = [(velocity.peak(a), v_max[a]), (stroke.peak(a), s_max[a])]
                .into_iter()
                // Round-off: an axis already scaled onto its limit stays.
                .filter(|&(peak, max)| peak > max * (1.0 + 1e-12))
                .map(|(peak, max)| peak / max)
                .fold(1.0_f64, f64::max);
            if over > 1.0 {
                excess += over - 1.0;
                self.c[a]
                    .iter_mut()
                    .for_each(|cs| *cs = [cs[0] / over, cs[1] / over]);
            }
        }
        excess
    }

    /// The coefficients of every signal's zero-mean antiderivative: a term
    /// c sin(nωt) + s cos(nωt) integrates to (s sin(nωt) − c cos(nωt))/(nω).
    /// Applied to accelerations it gives velocities; applied twice, the
    /// displacement from the mean pose.
    pub(crate) fn antiderivative(&self) -> Coefficients {
        let w = 2.0 * PI / self.period;
        let mut out = self.clone();
        for axis in &mut out.c {
            for (k, cs) in axis.iter_mut().enumerate() {
                let wn = w * (k + 1) as f64;
                *cs = [cs[1] / wn, -cs[0] / wn];
            }
        }
        out
    }
}

/// How a parameter vector maps onto [`Coefficients`] for given limits.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Layout {
    /// Fundamental period (s).
    pub period: f64,
    /// Harmonics per axis.
    pub harmonics: u32,
    /// Per-axis limits; axes with limit 0 are not parameters.
    pub limits: [f64; 6],
}

impl Layout {
    /// The layout for `limits`.
    pub fn new(limits: &ShakerLimits) -> Layout {
        Layout {
            period: limits.period,
            harmonics: limits.harmonics,
            limits: limits.axes(),
        }
    }

    /// Free axes (limit > 0).
    fn free(&self) -> impl Iterator<Item = usize> + '_ {
        (0..6).filter(|&a| self.limits[a] > 0.0)
    }

    /// Length of the parameter vector: 2 H per free axis.
    pub fn len(&self) -> usize {
        self.free().count() * 2 * self.harmonics as usize
    }

    /// Parameter vector of `c` (entries divided by the axis limit).
    pub(crate) fn to_vec(&self, c: &Coefficients) -> Vec<f64> {
        let mut v = Vec::with_capacity(self.len());
        for a in self.free() {
            for k in 0..self.harmonics as usize {
                let cs = c.c[a].get(k).copied().unwrap_or([0.0; 2]);
                v.push(cs[0] / self.limits[a]);
                v.push(cs[1] / self.limits[a]);
            }
        }
        v
    }

    /// Coefficients of parameter vector `v` (of length [`Layout::len`]).
    pub(crate) fn from_vec(&self, v: &[f64]) -> Coefficients {
        let mut c = Coefficients::zero(self.period, self.harmonics);
        let mut it = v.iter();
        for a in self.free() {
            for k in 0..self.harmonics as usize {
                let x = it.next().copied().unwrap_or(0.0);
                let y = it.next().copied().unwrap_or(0.0);
                c.c[a][k] = [x * self.limits[a], y * self.limits[a]];
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `synth::params::Coefficients::antiderivative`.
    #[test]
    fn example_coefficients_antiderivative() {
        use crate::synth::params::Coefficients;
        let mut c = Coefficients::zero(0.05, 2);
        c.set(0, 2, 10.0, 0.3); // 10 m/s² at harmonic 2
        let w = 2.0 * std::f64::consts::TAU / 0.05;
        let stroke = c.antiderivative().antiderivative();
        assert!((stroke.peak(0) - 10.0 / (w * w)).abs() < 1e-15);
    }
}
