//! The contact margin: the least normal force per unit mass N over a
//! region, checked rather than assumed.
//!
//! * [`kinematic_least_normal`]: N of a part at rest on the plate
//!   (u = 0, so no Coriolis term) at every point of a grid and at
//!   `TIME_SAMPLES` instants per period, with the model's own switches
//!   (centripetal, gravity tilt) — used inside the objective.
//! * `orbit_least_normal`: N along the simulated steady orbit of a part
//!   (its slip velocity included, so Coriolis counts) at every step of the
//!   integrator, at every grid point — the final check of a synthesis.
//!   A part that leaves the plate anywhere is a contact loss in the field
//!   itself ([`crate::field::Validity::ContactLost`]).

use rayon::prelude::*;

use crate::dynamics::{KinematicsTable, PartState, Simulator, V2};
use crate::field::{FieldSettings, Grid};
use crate::motion::{Motion, V3};

/// Instants per period of the kinematic check.
pub(crate) const TIME_SAMPLES: usize = 256;

/// Least N (m/s²) over the points of `grid` and `TIME_SAMPLES` instants
/// per period of the motion's span (one period; a ramped segment's whole
/// span, its ramps included), for a part at rest relative to the plate.
pub fn kinematic_least_normal(motion: &Motion, grid: &Grid, settings: &FieldSettings) -> f64 {
    let span = motion.span();
    let instants = TIME_SAMPLES * (span / motion.period()).round().max(1.0) as usize;
    let points = grid.points();
    let mut least = f64::INFINITY;
    for i in 0..instants {
        let t = span * i as f64 / instants as f64;
        let k = motion.kinematics(t, settings.gravity, settings.model.tilt);
        for p in &points {
            let (n, _) = settings
                .model
                .point_forces(&k, &V3::new(p[0], p[1], 0.0), &V2::zeros());
            least = least.min(n);
        }
    }
    least
}

/// Least N (m/s²) along the steady orbits started at the points of `grid`
/// (points without a steady state are skipped: the field flags them).
/// The plate kinematics of the cycle are tabulated once and shared by
/// every point ([`KinematicsTable`], a memo: the same bits as without it).
pub(crate) fn orbit_least_normal(motion: &Motion, grid: &Grid, settings: &FieldSettings) -> f64 {
    let direct = settings.simulator(motion);
    let table = KinematicsTable::cycle(&direct);
    least_normal_along_orbits(&direct.with_table(&table), motion, grid, settings)
}

/// [`orbit_least_normal`] with the simulator `sim` (of `motion` under
/// `settings`).
fn least_normal_along_orbits(
    sim: &Simulator<'_>,
    motion: &Motion,
    grid: &Grid,
    settings: &FieldSettings,
) -> f64 {
    let period = motion.period();
    grid.points()
        .par_iter()
        .map(|p| {
            let Ok(steady) = sim.steady_state(*p) else {
                return f64::INFINITY;
            };
            let anchor = V2::from(*p);
            let mut state = PartState::new(anchor, V2::from(steady.start_slip));
            let mut record = Vec::new();
            if sim
                .advance(0.0, period, &mut state, &anchor, Some(&mut record))
                .is_err()
            {
                return f64::NEG_INFINITY;
            }
            record
                .iter()
                .map(|tp| {
                    let k = motion.kinematics(tp.t, settings.gravity, settings.model.tilt);
                    let q = if settings.model.moving {
                        tp.state.r
                    } else {
                        anchor
                    };
                    let (n, _) =
                        settings
                            .model
                            .point_forces(&k, &V3::new(q.x, q.y, 0.0), &tp.state.u);
                    n
                })
                .fold(f64::INFINITY, f64::min)
        })
        .reduce(|| f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::motion::Signals;

    /// The table is a memo: the least N along the orbits is the same bits
    /// as with the kinematics evaluated at every step (and a number: the
    /// orbits were simulated, not skipped).
    #[test]
    fn tabled_orbit_check_is_the_direct_one() {
        let motion = Motion::Signals(Signals::example());
        let settings = FieldSettings::default();
        let grid = Grid {
            x: [-0.03, 0.03],
            y: [-0.02, 0.02],
            n: [3, 3],
        };
        let tabled = orbit_least_normal(&motion, &grid, &settings);
        let direct =
            least_normal_along_orbits(&settings.simulator(&motion), &motion, &grid, &settings);
        assert_eq!(tabled.to_bits(), direct.to_bits());
        assert!(tabled.is_finite(), "{tabled}");
    }
}
