//! The flight model (`src/dynamics/flight.rs`) against solutions written
//! here from the stated equations, nothing taken from the library's
//! integrator:
//!
//! * `bouncing_ball`: a point on a plate vibrating vertically,
//!   z_p = A sin ωt with peak acceleration Γg (Γ = 1.5, 2.5, 3.3): the
//!   take-off phase is asin(1/Γ), and every take-off and landing over eight
//!   cycles matches the completely inelastic bouncing ball (landing: the
//!   first root of z_p(t₀) + ż_p(t₀)τ − gτ²/2 − z_p(t₀ + τ), found by
//!   scanning and 200 bisections), within 1e-8 s.
//! * `bouncing_ball_with_restitution`: the same with e = 0.3, 0.6, 0.5,
//!   the flights before the chatter of a part coming to rest.
//! * `conveying`: a plate vibrating horizontally and vertically (two sines
//!   with a phase between them, seeded random amplitudes, phases and μ):
//!   the mean conveying velocity after a transient, against an event-driven
//!   solution of the plate-frame equations whose phases (stuck, slipping,
//!   flying) are integrated in closed form (the forcing is sinusoidal, so
//!   the antiderivatives are exact and no step size needs converging),
//!   events by scanning and bisection, within 1e-6 relative at the default
//!   64 steps per cycle and 1e-9 at 512.

use std::f64::consts::PI;

use crate::dynamics::{
    Flight, Friction, Hop, Model, Numerics, PartPhase, PartPhysics, PartState, Simulator, V2,
};
use crate::motion::{Axes, FourierTerm, Motion, Signals};

const G: f64 = 9.81;

/// A plate translating with accelerations X sin(ωt + φx) along x and
/// Z sin(ωt + φz) along z.
fn shaker(period: f64, (x, phase_x): (f64, f64), (z, phase_z): (f64, f64)) -> Motion {
    let term = |amplitude: f64, phase: f64| FourierTerm {
        amplitude,
        phase,
        harmonic: 1,
    };
    Motion::Signals(Signals {
        period,
        linear: Axes {
            x: vec![term(x, phase_x)],
            y: Vec::new(),
            z: vec![term(z, phase_z)],
        },
        angular: Axes::default(),
    })
}

/// The library's hops over `[0, cycles T]` from rest on the plate.
fn library_hops(motion: &Motion, mu: f64, steps: usize, cycles: f64) -> Vec<Hop> {
    bouncing_hops(motion, mu, steps, cycles, Flight::INELASTIC)
}

/// [`library_hops`] with the impacts of `flight`.
fn bouncing_hops(motion: &Motion, mu: f64, steps: usize, cycles: f64, flight: Flight) -> Vec<Hop> {
    let numerics = Numerics {
        steps_per_cycle: steps,
        ..Numerics::default()
    };
    let physics = PartPhysics::new(Friction::uniform(mu), G, Model::FULL);
    let sim = Simulator::new(motion, physics, numerics)
        .with_flight(flight)
        .expect("valid flight");
    let mut part = PartPhase::Contact(PartState::new(V2::zeros(), V2::zeros()));
    let out = sim
        .advance_flying(0.0, cycles * motion.period(), &mut part, &V2::zeros())
        .expect("flight never fails here");
    out.hops
}

/// First t in (a, b] with f(t) ≤ 0, f positive just after a: samples at
/// `spacing`, then 200 bisections.
fn first_root(f: &impl Fn(f64) -> f64, a: f64, b: f64, spacing: f64) -> Option<f64> {
    if a >= b {
        return None;
    }
    let mut lo = a;
    loop {
        let hi = (lo + spacing).min(b);
        if f(hi) <= 0.0 {
            let (mut l, mut h) = (lo, hi);
            for _ in 0..200 {
                let m = 0.5 * (l + h);
                if f(m) > 0.0 {
                    l = m;
                } else {
                    h = m;
                }
            }
            return Some(h);
        }
        if hi >= b {
            return None;
        }
        lo = hi;
    }
}

/// The bouncing ball on z_p = A sin ωt, A = Γg/ω², with restitution
/// `e` (0: completely inelastic): (take-off, landing) pairs landing before
/// `end`. A rebound below g × 1e-14 T (the library's event tolerance at the
/// default settings) ends the bouncing; with e > 0 the pairs stop at the
/// first flight of at most 1e-3 T (the start of a chatter).
fn bouncing_ball(gamma: f64, period: f64, end: f64, e: f64) -> Vec<(f64, f64)> {
    let w = 2.0 * PI / period;
    let a = gamma * G / (w * w);
    let z = |t: f64| a * (w * t).sin();
    let v = |t: f64| a * w * (w * t).cos();
    let normal = |t: f64| G - a * w * w * (w * t).sin();
    let phase = (1.0 / gamma).asin();
    let mut hops = Vec::new();
    let (mut t, mut rebound) = (0.0, 0.0);
    loop {
        // Leaves at once after a rebound or where N < 0 (after a landing),
        // else at the next time the plate's downward acceleration reaches g.
        let t0 = if rebound > 0.0 || normal(t) < 0.0 {
            t
        } else {
            let k = ((w * t - phase) / (2.0 * PI)).ceil();
            (phase + 2.0 * PI * k) / w
        };
        let v0 = v(t0) + rebound;
        let gap = |s: f64| z(t0) + v0 * (s - t0) - 0.5 * G * (s - t0) * (s - t0) - z(s);
        match first_root(&gap, t0, end, period / 4000.0) {
            Some(tl) => {
                hops.push((t0, tl));
                if e > 0.0 && tl - t0 <= 1e-3 * period {
                    // The chatter of a part coming to rest: not compared.
                    return hops;
                }
                let approach = v0 - G * (tl - t0) - v(tl);
                rebound = -e * approach;
                if rebound <= G * 1e-14 * period {
                    rebound = 0.0;
                }
                t = tl;
            }
            None => return hops,
        }
    }
}

#[test]
fn bouncing_ball_against_closed_form() {
    let period = 0.02;
    let cycles = 8.0;
    for gamma in [1.5, 2.5, 3.3] {
        // Plate acceleration −Γg sin ωt: z_p = A sin ωt.
        let motion = shaker(period, (0.0, 0.0), (gamma * G, PI));
        let hops = library_hops(&motion, 0.3, 64, cycles);
        let want = bouncing_ball(gamma, period, cycles * period, 0.0);
        assert_eq!(hops.len(), want.len(), "Γ = {gamma}: hops {hops:?}");
        let first = hops[0].take_off / period * 2.0 * PI;
        let phase_error = (first - (1.0 / gamma).asin()).abs();
        let mut worst: f64 = 0.0;
        for (h, (t0, tl)) in hops.iter().zip(&want) {
            worst = worst
                .max((h.take_off - t0).abs())
                .max((h.landing - tl).abs());
        }
        println!(
            "Γ = {gamma}: {} hops in {cycles} cycles, first flight {:.6} of the cycle, take-off phase error {phase_error:.2e} rad, worst time error {worst:.2e} s",
            hops.len(),
            (hops[0].landing - hops[0].take_off) / period
        );
        assert!(phase_error < 1e-8 * 2.0 * PI / period, "Γ = {gamma}");
        assert!(worst < 1e-8, "Γ = {gamma}: worst time error {worst:e} s");
    }
}

/// The plate-frame equations of a part on a plate translating with
/// a_x = X sin(ωt + φx), a_z = Z sin(ωt + φz) (no rotation), friction μ:
/// N = g + a_z; stuck while |a_x| ≤ μN; slipping with sign s,
/// u̇ = −a_x − μ N s; flying, u̇ = −a_x and the height h over the plate
/// ḧ = −N; a landing with normal speed w < 0 gives a normal impulse −w and
/// a tangential one of at most μ(−w) against u.
struct Conveyor {
    w: f64,
    x: (f64, f64),
    z: (f64, f64),
    mu: f64,
}

#[derive(Clone, Copy, Debug)]
enum Mode {
    Stuck,
    Slip(f64),
    Fly,
}

impl Conveyor {
    /// Plate (position, velocity, acceleration) along an axis of
    /// amplitude and phase `(a, phi)` at `t`.
    fn plate(&self, (a, phi): (f64, f64), t: f64) -> (f64, f64, f64) {
        let arg = self.w * t + phi;
        (
            -a / (self.w * self.w) * arg.sin(),
            -a / self.w * arg.cos(),
            a * arg.sin(),
        )
    }

    fn normal(&self, t: f64) -> f64 {
        G + self.plate(self.z, t).2
    }

    /// ∫ₐᵗ ∫ₐˢ of the acceleration along `axis` (the plate's displacement
    /// less its start velocity times τ) and ∫ₐᵗ of it.
    fn integrals(&self, axis: (f64, f64), a: f64, t: f64) -> (f64, f64) {
        let (pa, va, _) = self.plate(axis, a);
        let (p, v, _) = self.plate(axis, t);
        (p - pa - va * (t - a), v - va)
    }

    /// (x, u, h, ḣ) at `t` of a phase started at `a` in `mode` with
    /// (x, u) = `start` (h = ḣ = 0 at a contact start or take-off).
    fn state(&self, mode: Mode, a: f64, start: (f64, f64), t: f64) -> (f64, f64, f64, f64) {
        let tau = t - a;
        let (x0, u0) = start;
        let (dx, dv) = self.integrals(self.x, a, t);
        let (dz, dw) = self.integrals(self.z, a, t);
        match mode {
            Mode::Stuck => (x0, 0.0, 0.0, 0.0),
            Mode::Slip(s) => {
                let f = self.mu * s;
                (
                    x0 + u0 * tau - dx - f * (0.5 * G * tau * tau + dz),
                    u0 - dv - f * (G * tau + dw),
                    0.0,
                    0.0,
                )
            }
            Mode::Fly => (
                x0 + u0 * tau - dx,
                u0 - dv,
                -0.5 * G * tau * tau - dz,
                -G * tau - dw,
            ),
        }
    }

    /// The mode a part at rest on the plate at `t` enters.
    fn mode_at_rest(&self, t: f64) -> Mode {
        let ax = self.plate(self.x, t).2;
        if self.normal(t) < 0.0 {
            Mode::Fly
        } else if ax.abs() <= self.mu * self.normal(t) {
            Mode::Stuck
        } else {
            Mode::Slip(-ax.signum())
        }
    }

    /// The landings (time, x) over `[0, end]` from rest at x = 0.
    fn landings(&self, end: f64) -> Vec<(f64, f64)> {
        let spacing = 2.0 * PI / self.w / 4000.0;
        let (mut a, mut start, mut mode) = (0.0, (0.0, 0.0), self.mode_at_rest(0.0));
        let mut out = Vec::new();
        loop {
            let st = |t: f64| self.state(mode, a, start, t);
            let next = match mode {
                Mode::Stuck => first_root(
                    &|t| self.mu * self.normal(t) - self.plate(self.x, t).2.abs(),
                    a,
                    end,
                    spacing,
                ),
                Mode::Slip(s) => {
                    let stop = first_root(&|t| st(t).1 * s, a, end, spacing);
                    let leave = first_root(&|t| self.normal(t), a, end, spacing);
                    match (stop, leave) {
                        (Some(p), Some(q)) => Some(p.min(q)),
                        (p, q) => p.or(q),
                    }
                }
                Mode::Fly => first_root(&|t| st(t).2, a, end, spacing),
            };
            let Some(t) = next else {
                return out;
            };
            let (x, u, _, hdot) = st(t);
            (a, start, mode) = match mode {
                // Broken away (μN − |a_x| ≤ 0 at t): slips along −a_x.
                Mode::Stuck if self.normal(t) < 0.0 => (t, (x, 0.0), Mode::Fly),
                Mode::Stuck => (t, (x, 0.0), Mode::Slip(-self.plate(self.x, t).2.signum())),
                Mode::Slip(_) if self.normal(t) <= 0.0 => (t, (x, u), Mode::Fly),
                Mode::Slip(_) => (t, (x, 0.0), self.mode_at_rest(t)),
                Mode::Fly => {
                    out.push((t, x));
                    let bound = self.mu * -hdot.min(0.0);
                    let u = if u.abs() <= bound {
                        0.0
                    } else {
                        u - bound * u.signum()
                    };
                    let mode = if self.normal(t) < 0.0 {
                        Mode::Fly
                    } else if u == 0.0 {
                        self.mode_at_rest(t)
                    } else {
                        Mode::Slip(u.signum())
                    };
                    (t, (x, u), mode)
                }
            };
        }
    }
}

/// A tiny deterministic generator (xorshift64*), uniform in [0, 1).
struct Seeded(u64);

impl Seeded {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn conveying_velocity_against_event_driven_solution() {
    let period = 0.02;
    let (transient, measured) = (20, 10);
    let cycles = (transient + measured + 2) as f64;
    let mut rng = Seeded(0x5eed_f11e);
    let mut errors = Vec::new();
    for case in 0..6 {
        let gamma = 1.1 + 1.4 * rng.next();
        let horizontal = (0.5 + 2.0 * rng.next()) * G;
        let phase = PI * (2.0 * rng.next() - 1.0);
        let mu = [0.2, 0.3, 0.5][case % 3];
        let motion = shaker(period, (horizontal, 0.0), (gamma * G, phase));
        let conveyor = Conveyor {
            w: 2.0 * PI / period,
            x: (horizontal, 0.0),
            z: (gamma * G, phase),
            mu,
        };
        let want = conveyor.landings(cycles * period);
        let speed = |landings: &[(f64, f64)]| {
            // Landings from the first one after the transient over (about)
            // `measured` cycles.
            let i = landings
                .iter()
                .position(|l| l.0 >= transient as f64 * period)
                .expect("landings after the transient");
            let j = landings
                .iter()
                .rposition(|l| l.0 <= landings[i].0 + measured as f64 * period + 1e-9)
                .expect("a later landing");
            (landings[j].1 - landings[i].1) / (landings[j].0 - landings[i].0)
        };
        let v_ref = speed(&want);
        for steps in [64, 512] {
            let hops = library_hops(&motion, mu, steps, cycles);
            let got: Vec<(f64, f64)> = hops.iter().map(|h| (h.landing, h.to[0])).collect();
            assert_eq!(got.len(), want.len(), "case {case}, {steps} steps");
            let v = speed(&got);
            let rel = (v - v_ref).abs() / v_ref.abs();
            println!(
                "case {case}: Γ = {gamma:.3}, X = {:.3} g, phase {phase:+.3} rad, μ = {mu}: {} landings, conveying {v_ref:+.6e} m/s, {steps} steps: relative error {rel:.2e}",
                horizontal / G,
                want.len()
            );
            errors.push((steps, rel));
        }
    }
    // The default 64 steps per cycle within 1e-6; converging at 512.
    for (steps, bound) in [(64, 1e-6), (512, 1e-9)] {
        let worst = errors
            .iter()
            .filter(|e| e.0 == steps)
            .fold(0.0, |w: f64, e| w.max(e.1));
        assert!(
            worst < bound,
            "{steps} steps: worst relative error {worst:e}"
        );
    }
}

/// Partly elastic impacts (e = 0.3, 0.6, 0.5): the flights of the bouncing
/// ball against the reference with restitution, every hop longer than
/// 1e-3 T before the first shorter one (the chatter of a part coming to
/// rest is a Zeno sequence of ever shorter flights, cut at the event
/// tolerance), within 1e-8 s.
#[test]
fn bouncing_ball_with_restitution() {
    let period = 0.02;
    let cycles = 10.0;
    for (gamma, e) in [(1.5, 0.3), (2.5, 0.6), (3.3, 0.5)] {
        let motion = shaker(period, (0.0, 0.0), (gamma * G, PI));
        let flight = Flight { restitution: e };
        let hops = bouncing_hops(&motion, 0.3, 64, cycles, flight);
        let want = bouncing_ball(gamma, period, cycles * period, e);
        let long = want
            .iter()
            .take_while(|(t0, tl)| tl - t0 > 1e-3 * period)
            .count();
        assert!(
            long >= 3 && hops.len() >= long,
            "Γ = {gamma}, e = {e}: {hops:?}"
        );
        let mut worst: f64 = 0.0;
        for (h, (t0, tl)) in hops.iter().zip(&want).take(long) {
            worst = worst
                .max((h.take_off - t0).abs())
                .max((h.landing - tl).abs());
        }
        println!(
            "Γ = {gamma}, e = {e}: {long} flights compared ({} and {} in all), worst time error {worst:.2e} s",
            want.len(),
            hops.len()
        );
        assert!(
            worst < 1e-8,
            "Γ = {gamma}, e = {e}: worst time error {worst:e} s"
        );
    }
}

/// Without a take-off, `advance_flying` (fixed step by fixed step) leaves
/// the part bitwise where `advance` (the whole span at once) does: a
/// six-signal motion with tilts, 2-D slips, parts at seeded points.
#[test]
fn in_contact_flying_is_advance_bitwise() {
    let motion = Motion::Signals(Signals::example());
    let sim = Simulator::new(&motion, PartPhysics::full(0.3), Numerics::default());
    let flying = sim.clone().with_flight(Flight::INELASTIC).expect("valid");
    let mut rng = Seeded(0xb17_5eed);
    for _ in 0..8 {
        let r = V2::new(
            0.1 * (2.0 * rng.next() - 1.0),
            0.1 * (2.0 * rng.next() - 1.0),
        );
        let end = 3.0 * motion.period();
        let mut state = PartState::new(r, V2::zeros());
        sim.advance(0.0, end, &mut state, &r, None)
            .expect("stays in contact");
        let mut part = PartPhase::Contact(PartState::new(r, V2::zeros()));
        let out = flying
            .advance_flying(0.0, end, &mut part, &r)
            .expect("stays in contact");
        assert!(out.hops.is_empty());
        assert_eq!(part, PartPhase::Contact(state), "from {r:?}");
    }
}

/// A part held at a point of a vertically vibrating plate (Γ = 1.5, 2.5):
/// [`Simulator::held_orbit`] settles on one flight a period, and its
/// airborne fraction is the completely inelastic bouncing ball's flight
/// time over T (the steady flight of [`bouncing_ball`]), within 1e-9; no
/// horizontal forcing, no drift.
#[test]
fn held_orbit_airborne_fraction_is_the_bouncing_balls() {
    let period = 0.02;
    for gamma in [1.5, 2.5] {
        let motion = shaker(period, (0.0, 0.0), (gamma * G, PI));
        let physics = PartPhysics::new(Friction::uniform(0.3), G, Model::FULL);
        let sim = Simulator::new(&motion, physics, Numerics::default())
            .with_flight(Flight::INELASTIC)
            .expect("valid flight");
        let orbit = sim.held_orbit([0.01, -0.02]).expect("held");
        let hops = bouncing_ball(gamma, period, 8.0 * period, 0.0);
        let (t0, tl) = hops[hops.len() - 1];
        let want = (tl - t0) / period;
        println!(
            "Γ = {gamma}: airborne fraction {:.10} against {want:.10}, {} periods",
            orbit.airborne_fraction, orbit.periods
        );
        assert!(orbit.settled && orbit.hops == 1, "Γ = {gamma}: {orbit:?}");
        assert!(
            (orbit.airborne_fraction - want).abs() < 1e-9,
            "Γ = {gamma}: {} against {want}",
            orbit.airborne_fraction
        );
        assert!(orbit.velocity[0].abs() < 1e-12 && orbit.velocity[1].abs() < 1e-12);
    }
}

/// A plate translating and tilting in circles (harmonic 1, T = 30 ms):
/// N swings with the position but stays positive over the region.
fn tilting_plate() -> Motion {
    let term = |amplitude: f64, phase: f64| FourierTerm {
        amplitude,
        phase,
        harmonic: 1,
    };
    Motion::Signals(Signals {
        period: 0.03,
        linear: Axes {
            x: vec![term(10.0, 0.5 * PI)],
            y: vec![term(10.0, 0.0)],
            z: Vec::new(),
        },
        angular: Axes {
            x: vec![term(100.0, 0.3)],
            y: vec![term(100.0, 0.3 + 0.5 * PI)],
            z: Vec::new(),
        },
    })
}

/// On a tilting plate that keeps the part in contact, the held orbit
/// (plain iteration, the part put back once a period) is the free steady
/// state's fixed point found by Newton's method
/// ([`Simulator::steady_state`], model `full`): the same mean velocity
/// within 2e-5 of the velocity scale μ g T (the held orbit settles to
/// 1e-5 of it a period), and no time in flight.
#[test]
fn held_orbit_in_contact_is_the_steady_state() {
    held_orbit_is_the_steady_state(Model::FULL, &[[0.03, 0.02], [-0.035, 0.01], [0.0, -0.04]]);
}

/// Under `model`, on [`tilting_plate`], the held orbit from each of
/// `starts` settles in contact (no flight, no hop) to the steady state's
/// mean velocity within 2e-5 of μ g T.
fn held_orbit_is_the_steady_state(model: Model, starts: &[[f64; 2]]) {
    let physics = PartPhysics::new(Friction::uniform(0.3), G, model);
    let motion = tilting_plate();
    let plain = Simulator::new(&motion, physics, Numerics::default());
    let sim = plain
        .clone()
        .with_flight(Flight::INELASTIC)
        .expect("flight");
    let scale = sim.velocity_scale();
    for &r0 in starts {
        let held = sim.held_orbit(r0).expect("held");
        let steady = plain.steady_state(r0).expect("steady");
        let d =
            (held.velocity[0] - steady.velocity[0]).hypot(held.velocity[1] - steady.velocity[1]);
        println!(
            "{model:?} {r0:?}: held {:?} in {} periods, steady {:?}: {:.2e} of μgT",
            held.velocity,
            held.periods,
            steady.velocity,
            d / scale
        );
        assert!(held.settled && held.airborne_fraction == 0.0 && held.hops == 0);
        assert!(d < 2e-5 * scale, "{r0:?}: {d:e} m/s");
    }
}

/// The frozen held orbit ([`Model::FROZEN`], kinematics held at the
/// point, the judge's play) on the tilting plate of
/// `held_orbit_in_contact_is_the_steady_state` is the frozen steady
/// state's fixed point (Newton's method, [`Simulator::steady_state`])
/// within 2e-5 of μ g T; and on a vertically vibrating plate (Γ = 1.5),
/// where a frozen and a moving part are alike, its airborne fraction is
/// the bouncing ball's within 1e-9.
#[test]
fn frozen_held_orbit_is_the_frozen_steady_state() {
    held_orbit_is_the_steady_state(Model::FROZEN, &[[0.03, 0.02], [-0.035, 0.01]]);
    let period = 0.02;
    let vertical = shaker(period, (0.0, 0.0), (1.5 * G, PI));
    let physics = PartPhysics::new(Friction::uniform(0.3), G, Model::FROZEN);
    let sim = Simulator::new(&vertical, physics, Numerics::default())
        .with_flight(Flight::INELASTIC)
        .expect("flight");
    let orbit = sim.held_orbit([0.02, 0.01]).expect("held");
    let (t0, tl) = *bouncing_ball(1.5, period, 8.0 * period, 0.0)
        .last()
        .expect("hops");
    assert!(orbit.hops == 1 && (orbit.airborne_fraction - (tl - t0) / period).abs() < 1e-9);
}
