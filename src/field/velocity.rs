//! The steady-state velocity field at one point.

use super::Validity;
use crate::dynamics::{Simulator, SteadyFailure};

/// Steady-state velocity at `p`; frozen samples whose within-cycle
/// excursion exceeds `max_excursion` are flagged.
pub(crate) fn sample(sim: &Simulator<'_>, p: [f64; 2], max_excursion: f64) -> ([f64; 2], Validity) {
    match sim.steady_state(p) {
        Ok(s) => {
            let ok = !sim.is_frozen() || s.excursion <= max_excursion;
            (
                s.velocity,
                if ok {
                    Validity::Ok
                } else {
                    Validity::FrozenInvalid
                },
            )
        }
        Err(SteadyFailure::ContactLoss(_)) => ([0.0, 0.0], Validity::ContactLost),
        Err(SteadyFailure::NotConverged { .. }) => ([0.0, 0.0], Validity::NotConverged),
    }
}
