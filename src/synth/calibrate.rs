//! Phase calibration of the closed-form seed by re-simulation.
//!
//! The seed's lead δ = asin(μg/A) is that of a part under N = g that does
//! not drift ([module documentation](super)); the simulated field of the
//! seed comes out *turned* against the target (by about ten degrees on the
//! lab sink and the saddle with the sequenced limits: a shape error near
//! 20 % at nearly the predicted strength; `tests/unit/synth.rs`
//! `seed_predicts_the_simulated_sink`). Shifting the phase of harmonic 1 of
//! every normal-force signal (a_z, α_x, α_y) by φ turns the predicted
//! velocity (W/g)(Q_N, P_N) clockwise by φ (Q_N + iP_N → e^{−iφ}(Q_N + iP_N))
//! and leaves each signal's amplitude unchanged, so the peaks and the
//! normal-force swing at every point (the contact margin) are those of the
//! seed. `calibrate` measures the turn Δ of the simulated field
//! ([`super::objective::Realised::turn`]) and iterates φ ← φ + Δ; it
//! returns the best evaluation by the objective's cost, the seed's own
//! included, so it never makes the start worse.

use super::objective::{Evaluation, Objective};
use super::params::Coefficients;

/// Calibration steps (one coarse re-simulation each).
pub(crate) const STEPS: usize = 3;

/// A turn below this (rad, 0.2°) ends the calibration.
const TURN_TOL: f64 = 0.2 * std::f64::consts::PI / 180.0;

/// Axes whose harmonic 1 is the normal-force modulation: a_z, α_x, α_y.
pub(crate) const NORMAL_AXES: [usize; 3] = [2, 3, 4];

/// `c` with harmonic 1 of a_z, α_x and α_y shifted in phase by `phi`.
pub fn shifted(c: &Coefficients, phi: f64) -> Coefficients {
    let mut out = c.clone();
    let (s, k) = phi.sin_cos();
    for a in NORMAL_AXES {
        if let Some(cs) = out.c[a].first_mut() {
            *cs = [cs[0] * k - cs[1] * s, cs[0] * s + cs[1] * k];
        }
    }
    out
}

/// Calibrates the phase of `seed` (evaluated as `seed_eval`) on
/// `objective`; returns the best evaluation (see the module docs).
pub(crate) fn calibrate(
    objective: &Objective<'_>,
    seed: &Coefficients,
    seed_eval: &Evaluation,
) -> Evaluation {
    let mut best = seed_eval.clone();
    let mut phi = 0.0;
    let mut turn = seed_eval.realised.turn;
    for _ in 0..STEPS {
        if !turn.is_finite() || turn.abs() < TURN_TOL || objective.spent() {
            break;
        }
        phi += turn;
        let x = objective.layout().to_vec(&shifted(seed, phi));
        let e = objective.evaluate(&x);
        turn = e.realised.turn;
        if e.cost < best.cost {
            best = e;
        }
    }
    best
}
