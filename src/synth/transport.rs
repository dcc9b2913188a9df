//! Uniform transport by waveform asymmetry, calibrated by re-simulation.
//!
//! The seed's mechanism moves parts uniformly (the target's offset b) only
//! through the vertical acceleration a_z ([module documentation](super)).
//! Where a_z is limited — a shaker without a vertical axis, or limits taken
//! from a schedule of in-plane primitives — an in-plane translation whose
//! waveform is *asymmetric* transports parts instead, at every point alike:
//! with a second harmonic phase-locked to the first,
//!
//! ```text
//! a(t) = a₁(t) + A b̂ sin(2ωt + φ),
//! ```
//!
//! the plate's acceleration is larger one way than the other, so the part
//! slips back less than forward (the sawtooth of the paper's Trans
//! primitive, Table I, keeps only its two lowest harmonics here). Stick-slip
//! has no closed form for the drift, so [`calibrate`] finds φ and A by
//! re-simulation on the objective's coarse grid: [`PHASES`] phases at
//! amplitude A₀ = `FIRST_AMPLITUDE` of the in-plane limit along b̂, then
//! the amplitudes A₀·`AMPLITUDE_FACTORS` at the best phase. It returns the
//! best evaluation by the objective's cost, the start's own included, so it
//! never makes the start worse; peaks beyond the limits are clamped (and
//! penalised) by the objective as for any motion.
//!
//! Measured (squeeze plus transport, `targets/squeeze_trans.json` under its
//! sequenced schedule's peaks, vertical 0.109 m/s², 2 harmonics): the best
//! one-harmonic motion realises ŝ 0.15; the seed without b, calibrated
//! here, then refined, 0.89 on the 21 × 21 grid at 6.9 % shape error
//! (`platefield synthesis --rows squeeze_trans`), 0.91 at 8.8 % on 7 × 7
//! after 40 evaluations (test `transport_harmonic_carries_the_uniform_part`).

use std::f64::consts::TAU;

use super::objective::{Evaluation, Objective};
use super::params::Coefficients;

/// Phases tried at the first amplitude.
pub const PHASES: usize = 12;

/// First amplitude, as a fraction of the in-plane limit along b̂.
const FIRST_AMPLITUDE: f64 = 0.125;

/// Amplitudes tried at the best phase, relative to the first.
const AMPLITUDE_FACTORS: [f64; 3] = [0.5, 2.0, 4.0];

/// Signal indices of the in-plane translation (x, y).
const LIN_XY: [usize; 2] = [0, 1];

/// `c` with `a b̂ sin(2ωt + φ)` added to the in-plane translation.
fn with_transport(c: &Coefficients, dir: [f64; 2], a: f64, phi: f64) -> Coefficients {
    let mut out = c.clone();
    let (s, k) = phi.sin_cos();
    for (axis, d) in LIN_XY.into_iter().zip(dir) {
        if let Some(cs) = out.c[axis].get_mut(1) {
            *cs = [cs[0] + a * d * k, cs[1] + a * d * s];
        }
    }
    out
}

/// Calibrates a transport harmonic along `dir` on top of `start` (see the
/// module docs); returns the best evaluation, `start` included.
pub fn calibrate(objective: &Objective<'_>, start: &Evaluation, dir: [f64; 2]) -> Evaluation {
    let base = objective.motion(&start.params).0;
    if base.harmonics() < 2 {
        return start.clone();
    }
    let lim = objective.limits().axes();
    // The in-plane limit along b̂: the largest a with |a d_i| ≤ limit_i.
    let reach = LIN_XY
        .into_iter()
        .zip(dir)
        .filter(|(_, d)| d.abs() > 1e-12)
        .map(|(axis, d)| lim[axis] / d.abs())
        .fold(f64::INFINITY, f64::min);
    if !reach.is_finite() || reach <= 0.0 {
        return start.clone();
    }
    let a0 = FIRST_AMPLITUDE * reach;
    let mut best = start.clone();
    let try_one = |a: f64, phi: f64, best: &mut Evaluation| -> Option<f64> {
        if objective.spent() {
            return None;
        }
        let x = objective
            .layout()
            .to_vec(&with_transport(&base, dir, a, phi));
        let e = objective.evaluate(&x);
        let cost = e.cost;
        if cost < best.cost {
            *best = e;
        }
        Some(cost)
    };
    let mut phase = (f64::INFINITY, 0.0);
    for k in 0..PHASES {
        let phi = k as f64 * TAU / PHASES as f64;
        match try_one(a0, phi, &mut best) {
            Some(cost) if cost < phase.0 => phase = (cost, phi),
            Some(_) => {}
            None => return best,
        }
    }
    for f in AMPLITUDE_FACTORS {
        if try_one(f * a0, phase.1, &mut best).is_none() {
            break;
        }
    }
    best
}
