//! Tests of the 1-D stop location and the break-away minimum search
//! (`Simulator::stop_in_step`, `hermite_root`, `brent_min`).

use super::*;
use crate::dynamics::{Numerics, PartPhysics};
use crate::motion::{Motion, Screw, Waveform};

/// The step from `t` to `target` on the piece keyed `piece`.
fn at<'s>(
    (t, target, piece): (f64, f64, f64),
    anchor: &'s V2,
    state: &'s mut PartState,
    out: &'s mut CycleOutcome,
) -> Step<'s> {
    Step {
        t,
        target,
        piece,
        anchor,
        state,
        out,
    }
}

/// The LineSink: rotation about a horizontal axis below the plate moves
/// every point along x (a 1-D slip).
fn line_sink() -> Motion {
    Motion::Screw(Screw {
        axis: [0.0, 1.0, 0.0],
        point: [0.0, 0.0, -0.05],
        period: 0.03,
        rotation: Waveform::RestToRest { amplitude: 0.004 },
        translation: Waveform::Zero,
    })
}

/// Every 1-D stop met on fixed steps of T/`steps` over a few cycles, each
/// located by `stop_in_step` and by Newton from s = 0 (`locate_stop`, run
/// to |δ| ≤ tolerance): the same root within the event tolerance, the
/// velocity there zero to 1e-9 of the step's start, and at most three
/// trial steps (Newton from s = 0 takes five or more at 8 steps).
#[test]
fn stop_in_step_finds_newtons_root_in_fewer_trials() {
    let motion = line_sink();
    for steps in [8, 64] {
        let numerics = Numerics {
            steps_per_cycle: steps,
            ..Numerics::default()
        };
        let sim = Simulator::new(&motion, PartPhysics::full(0.3), numerics);
        let period = sim.period();
        let h = period / steps as f64;
        let tol = numerics.event_tol * period;
        let (mut stops, mut new_trials, mut old_trials) = (0, 0, 0);
        for x0 in [-0.03, 0.01, 0.035] {
            let anchor = V2::new(x0, 0.0);
            let mut state = PartState::new(anchor, V2::new(0.02, 0.0));
            let mut t = 0.0;
            for _ in 0..3 * steps {
                let k0 = sim.kin(t, t + 0.5 * h);
                if state.u == V2::zeros() {
                    // Slip from rest: nudge along a_free to stay in the test.
                    let (_, free) = sim.forces(&k0, &state.r, &state.u, &anchor);
                    state.u = free * 1e-6;
                }
                let piece = t + 0.5 * h;
                let mut tally = CycleOutcome::starting(state);
                let mut here = state;
                let span = (t, t + h, piece);
                let (r1, u1, k1) = sim
                    .rk4(&at(span, &anchor, &mut here, &mut tally), h, &k0, false)
                    .unwrap();
                assert_eq!(u1.y, 0.0, "the LineSink slip stays on x");
                if u1.dot(&state.u) <= 0.0 {
                    let mut new = CycleOutcome::starting(state);
                    let mut old = new;
                    let end = (&r1, &u1, &k1);
                    let (s, rs, us) = sim
                        .stop_in_step(&mut at(span, &anchor, &mut here, &mut new), h, &k0, end)
                        .unwrap();
                    let s_old = sim
                        .locate_stop(&mut at(span, &anchor, &mut here, &mut old), h, &k0, 0.0)
                        .unwrap();
                    let (rs_old, _, _) = sim
                        .rk4(&at(span, &anchor, &mut here, &mut tally), s_old, &k0, false)
                        .unwrap();
                    assert!((s - s_old).abs() <= 2.0 * tol, "{s} vs {s_old}");
                    assert!(us.norm() <= 1e-9 * state.u.norm(), "{us:?}");
                    assert!((rs - rs_old).norm() <= 1e-12 * (rs_old.norm() + 1e-3));
                    assert!(new.rk4_steps <= 3, "{} trials", new.rk4_steps);
                    (stops, new_trials, old_trials) = (
                        stops + 1,
                        new_trials + new.rk4_steps,
                        old_trials + old.rk4_steps,
                    );
                    state.r = rs;
                    state.u = V2::zeros();
                } else {
                    state.r = r1;
                    state.u = u1;
                }
                t += h;
            }
        }
        println!("{steps} steps: {stops} stops, {new_trials} vs {old_trials} trials");
        assert!(stops >= 6, "{stops} stops");
        assert!(new_trials < old_trials, "{new_trials} vs {old_trials}");
    }
}

/// The cubic Hermite root on a cubic with a known root: exact data give the
/// root itself.
#[test]
fn hermite_root_of_a_cubic() {
    // p(θ) = (0.37 − θ)(1 + θ + θ²): p(0) = 0.37, root 0.37.
    let p = |x: f64| (0.37 - x) * (1.0 + x + x * x);
    let dp = |x: f64| -(1.0 + x + x * x) + (0.37 - x) * (1.0 + 2.0 * x);
    let root = hermite_root(p(0.0), dp(0.0), p(1.0), dp(1.0));
    assert!((root - 0.37).abs() < 1e-12, "{root}");
}

/// Brent's minimization finds the minimum of a smooth dip (position and
/// value against the closed form) in few evaluations, and stops at the
/// first value below zero.
#[test]
fn brent_min_finds_smooth_minimum() {
    use std::cell::Cell;
    let count = Cell::new(0);
    // φ(t) = 0.2 + 1 − cos(t − 0.4): minimum 0.2 at t = 0.4.
    let phi = |t: f64| {
        count.set(count.get() + 1);
        1.2 - (t - 0.4).cos()
    };
    let (t, f) = brent_min(&phi, 0.0, 1.0, 1e-9);
    assert!((t - 0.4).abs() < 1e-7, "{t}");
    assert!((f - 0.2).abs() < 1e-14, "{f}");
    assert!(count.get() <= 20, "{} evaluations", count.get());
    // The same dip reaching below zero: stops at a negative value.
    let dip = |t: f64| 0.99 - (t - 0.4).cos();
    let (t, f) = brent_min(&dip, 0.0, 1.0, 1e-9);
    assert!(f < 0.0 && (t - 0.4).abs() < 0.15, "{t} {f}");
}
