//! Parts that leave the plate: ballistic flight, the landing, the impact.
//!
//! Off by default ([`Simulator::advance`] reports N < 0 as a
//! [`ContactLoss`]); a simulator given a [`Flight`]
//! ([`Simulator::with_flight`]) follows the part through it with
//! [`Simulator::advance_flying`]. Assumptions: a point part of unit mass,
//! no air drag, no rotation of the part; in flight only gravity acts.
//!
//! * **Take-off.** In contact the part obeys the stick-slip dynamics of
//!   [`crate::dynamics`]. It leaves the plate at the first time t₀ at which
//!   the normal force per unit mass N reaches 0, located to the event
//!   tolerance (`Numerics::event_tol` × T) by bisection on "the contact
//!   integration from the start of the fixed step to t ends with N ≥ 0".
//!   Its world position and velocity there are those of the plate point
//!   under it plus its slip velocity:
//!
//!   ```text
//!   x₀ = p + R r,      v₀ = v_c + ω × (R r) + R u        (r, u in the plate plane)
//!   ```
//!
//!   with (p, R) the plate's pose, v_c its centre's velocity and ω its
//!   angular velocity, all in the world frame
//!   ([`crate::motion::sample_hold::centre_state`]).
//! * **Flight**, in the world frame: x(t) = x₀ + v₀ τ + ½ g_W τ², τ = t − t₀,
//!   g_W = (0, 0, −g). Exact: nothing is integrated.
//! * **Landing**: the first root t_L > t₀ of the gap (the part's height
//!   above the plate surface, in the plate frame)
//!
//!   ```text
//!   G(t) = [Rᵀ(t) (x(t) − p(t))]_z,
//!   ```
//!
//!   sampled at half the nominal step, with every sampled local minimum
//!   refined by Brent's minimisation (a brief dip below zero between
//!   samples is not missed) and the bracketed root found by the Illinois
//!   method to the event tolerance. Near take-off G = O(τ³) (the relative
//!   velocity and acceleration across the plate are zero there), so the
//!   first interval is searched for its maximum first.
//! * **Impact** at the landing point q = [Rᵀ(x − p)]_{x,y}, with the
//!   relative velocity w = Rᵀ(v − v_c − ω × (x − p)) split into its normal
//!   part w_n < 0 and tangential part w_t. The normal impulse (per unit
//!   mass) is P_n = −(1 + e) w_n with the restitution coefficient e ∈ [0, 1]
//!   (0 by default: completely inelastic). The tangential impulse follows
//!   Coulomb's law for a part sliding during the impact: it opposes w_t and
//!   is at most μ_k P_n, so that
//!
//!   ```text
//!   w_t' = 0                              if |w_t| ≤ μ_k P_n   (the part sticks)
//!   w_t' = w_t − μ_k P_n w_t / |w_t|      otherwise
//!   w_n' = −e w_n
//!   ```
//!
//!   A rebound w_n' shorter than the event tolerance (w_n' ≤ g × tolerance)
//!   ends the bouncing; otherwise the part flies again from q. Without a
//!   rebound the part resumes the contact dynamics at q with slip velocity
//!   w_t' (and takes off again at once if N < 0 there).
//!
//! The flight is the plate's exact motion, while the contact dynamics
//! follow the model's switches ([`Model`]); the two agree on N (the
//! curvature of G at take-off is −N) only when the centripetal, tilt and
//! Coriolis switches are on, or for a plate that does not rotate (then the
//! switches change nothing). A simulator with one of them off and a
//! rotating plate is refused.
//!
//! **A frozen part** ([`Model::FROZEN`]: `moving` off, the kinematics held
//! at the part's anchor, as the judge holds each point) flies from its
//! anchor too: the flight starts at the plate point `anchor` with the
//! part's slip velocity, so that G's curvature at take-off is the −N the
//! contact dynamics evaluated there, and lands near it. Its position is
//! bookkeeping, as in contact: a landing at plate point q books the
//! take-off position plus q − anchor (its travel over the plate in
//! flight), and a rebound flies from the anchor again.
//!
//! **A held part and its airborne fraction** ([`Simulator::held_orbit`]):
//! a part held at a plate point r₀ (put back there once a period, its
//! velocity relative to the plate kept) settles on a periodic orbit that
//! may include flights; its realised velocity is the period's mean
//! velocity, and its **airborne fraction** the time it spends in flight
//! over the period divided by T (the fraction of the cycle during which
//! the part does not touch the plate and no friction acts on it). This is
//! the judge's point play with flight: designs that may fly are measured
//! by it (`platefield study flight-strength`, `results/flight_strength.md`).
//!
//! **Why flight lifts the margin's cap, and what it buys.** A design that
//! keeps contact holds N ≥ m g at every point of the region at every
//! instant, and N is smallest at the region's corners, where the tilts
//! swing it most: that margin, not the shaker's peaks, caps the tilts'
//! amplitude and with it the strength ([`crate::synth`]). A design that
//! may fly lets N reach 0 at the corners for part of the cycle (the part
//! flies, without friction, then lands), so its tilts may grow to the
//! peaks. What that buys at a bounded shape error is measured in
//! `results/flight_strength.md` and read in `docs/design.md` ("Designs
//! that may fly"): the shape error grows with the strength along one curve
//! in contact and in flight, and the airborne fraction rises steeply once
//! N dips below 0, since the flight lasts in proportion to the square root
//! of the dip.

use serde::{Deserialize, Serialize};

use super::integrator::brent_min;
use super::simulator::Simulator;
use super::state::{CycleOutcome, PartState, V2};
use super::{ContactLoss, Model};
use crate::error::{Error, Result};
use crate::motion::{rotation, sample_hold, Invariance, V3};

/// Consecutive flights of zero length (take-off and landing at the same
/// instant) after which the part is reported as lost: the contact model
/// and the exact motion disagree on N there.
const MAX_ZERO_FLIGHTS: u32 = 4;

/// Settings of the flight model (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Flight {
    /// Restitution coefficient e ∈ [0, 1] of the normal impact (0:
    /// completely inelastic).
    pub restitution: f64,
}

impl Default for Flight {
    fn default() -> Self {
        Flight::INELASTIC
    }
}

impl Flight {
    /// Completely inelastic impacts (e = 0).
    pub const INELASTIC: Flight = Flight { restitution: 0.0 };

    /// Validates e ∈ [0, 1]; errors name `field`.restitution.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        let e = self.restitution;
        if !(0.0..=1.0).contains(&e) {
            return Err(Error::invalid(
                format!("{field}.restitution"),
                format!("must be in [0, 1], got {}", crate::input::num(e)),
            ));
        }
        Ok(())
    }
}

/// A part in ballistic flight: where and how it left the plate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Airborne {
    /// Take-off time t₀ (s).
    pub t0: f64,
    /// World position at take-off (m).
    pub position: V3,
    /// World velocity at take-off (m/s).
    pub velocity: V3,
    /// Plate-frame point it left from (m).
    pub from: V2,
}

impl Airborne {
    /// World position and velocity at `t` under gravity `g`.
    fn at(&self, t: f64, g: f64) -> (V3, V3) {
        let tau = t - self.t0;
        let down = V3::new(0.0, 0.0, -g);
        (
            self.position + self.velocity * tau + down * (0.5 * tau * tau),
            self.velocity + down * tau,
        )
    }
}

/// A part on the plate or in flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PartPhase {
    /// In contact: the stick-slip state.
    Contact(PartState),
    /// In flight.
    Flying(Airborne),
}

/// One flight that ended in a landing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hop {
    /// Take-off time (s).
    pub take_off: f64,
    /// Landing time (s).
    pub landing: f64,
    /// Plate-frame take-off point (m).
    pub from: [f64; 2],
    /// Plate-frame landing point (m).
    pub to: [f64; 2],
    /// Speed towards the plate at impact, −w_n (m/s).
    pub impact_speed: f64,
}

/// What [`Simulator::advance_flying`] produced over a span.
#[derive(Debug, Clone, PartialEq)]
pub struct FlightOutcome {
    /// The part at the span's end.
    pub phase: PartPhase,
    /// The flights that landed in the span, in order.
    pub hops: Vec<Hop>,
    /// Time spent in flight (s).
    pub airborne_time: f64,
    /// Time spent stuck (s).
    pub stuck_time: f64,
    /// Stop and break-away events of the contact phases.
    pub events: u32,
    /// RK4 steps of the contact phases (take-off location included).
    pub rk4_steps: u32,
}

/// Fewest periods [`Simulator::held_orbit`] plays.
pub const HELD_MIN_PERIODS: u32 = 3;
/// Most periods [`Simulator::held_orbit`] plays before it reports the
/// orbit as not settled.
pub const HELD_MAX_PERIODS: u32 = 80;
/// Change of a held part's period-mean velocity between two periods, as
/// a fraction of the velocity scale μ_k g T, below which its orbit has
/// settled.
pub const HELD_TOL: f64 = 1e-5;

/// The steady orbit of a part held at one plate point and followed
/// through its flights ([`Simulator::held_orbit`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HeldOrbit {
    /// Mean velocity over the last period (m/s), plate frame.
    pub velocity: [f64; 2],
    /// Fraction of the last period spent in flight, in [0, 1].
    pub airborne_fraction: f64,
    /// Flights that landed in the last period.
    pub hops: usize,
    /// Periods played.
    pub periods: u32,
    /// Change of the period-mean velocity over the last period (m/s).
    pub change: f64,
    /// Whether that change is within [`HELD_TOL`] of the velocity scale.
    pub settled: bool,
}

/// The plate's world pose and velocity at one instant.
struct PlatePose {
    p: V3,
    rot: nalgebra::UnitQuaternion<f64>,
    v: V3,
    omega: V3,
}

impl Simulator<'_> {
    /// The same simulator following parts through flight with `flight`'s
    /// impacts ([`Simulator::advance_flying`]; the module docs of
    /// `src/dynamics/flight.rs` state the model).
    ///
    /// # Errors
    /// A restitution outside [0, 1] (named `flight.restitution`), or a
    /// rotating plate under a model with the centripetal, tilt or Coriolis
    /// switch off (`model`).
    pub fn with_flight(mut self, flight: Flight) -> Result<Self> {
        flight.validate("flight")?;
        let full = Model::FULL;
        let m = self.model;
        let consistent =
            m.centripetal == full.centripetal && m.tilt == full.tilt && m.coriolis == full.coriolis;
        if !consistent && self.motion.invariance() != Invariance::Uniform {
            return Err(Error::invalid(
                "model",
                format!(
                    "flight follows the plate's exact motion and needs the centripetal, tilt and Coriolis switches on for a rotating plate (got {})",
                    m.name()
                ),
            ));
        }
        self.flight = Some(flight);
        Ok(self)
    }

    /// The flight settings, when parts are followed through flight.
    #[cfg(test)]
    pub(crate) fn flight(&self) -> Option<Flight> {
        self.flight
    }

    /// Advances `phase` from `t0` to `t1`, through flights when the
    /// simulator has a [`Flight`] (module docs of `src/dynamics/flight.rs`),
    /// else exactly as [`Simulator::advance`]. The contact phases are
    /// integrated fixed step by fixed step on the grid
    /// [`Simulator::advance`] uses over the same span (restarted at each
    /// landing), so that without a take-off the part ends bitwise where
    /// [`Simulator::advance`] leaves it.
    ///
    /// ```
    /// use platefield::dynamics::{Flight, Numerics, PartPhase, PartPhysics, PartState, Simulator, V2};
    /// use platefield::motion::{Axes, FourierTerm, Motion, Signals};
    /// // A plate shaken vertically at 2 g: the part takes off once a cycle.
    /// let shake = FourierTerm { amplitude: 2.0 * 9.81, phase: 0.0, harmonic: 1 };
    /// let m = Motion::Signals(Signals { period: 0.02, linear: Axes { z: vec![shake], ..Axes::default() }, angular: Axes::default() });
    /// let sim = Simulator::new(&m, PartPhysics::full(0.3), Numerics::default())
    ///     .with_flight(Flight::INELASTIC)?;
    /// let mut part = PartPhase::Contact(PartState::new(V2::zeros(), V2::zeros()));
    /// let out = sim.advance_flying(0.0, 0.1, &mut part, &V2::zeros()).unwrap();
    /// assert!(out.hops.len() >= 4 && out.airborne_time > 0.0);
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// Without a [`Flight`], the contact loss as [`Simulator::advance`];
    /// with one, a contact loss where the contact model keeps N < 0 but the
    /// part does not leave the plate (`MAX_ZERO_FLIGHTS` flights of zero
    /// length in a row).
    pub fn advance_flying(
        &self,
        t0: f64,
        t1: f64,
        phase: &mut PartPhase,
        anchor: &V2,
    ) -> std::result::Result<FlightOutcome, ContactLoss> {
        let mut out = FlightOutcome {
            phase: *phase,
            hops: Vec::new(),
            airborne_time: 0.0,
            stuck_time: 0.0,
            events: 0,
            rk4_steps: 0,
        };
        let mut t = t0;
        let mut zero_flights = 0;
        while t < t1 {
            match *phase {
                PartPhase::Flying(b) => match self.landing(&b, t, t1) {
                    None => {
                        out.airborne_time += t1 - t;
                        t = t1;
                    }
                    Some(tl) => {
                        out.airborne_time += tl - t;
                        let (next, hop) = self.impact(&b, tl, anchor);
                        zero_flights = if tl - b.t0 <= self.event_tolerance() {
                            zero_flights + 1
                        } else {
                            0
                        };
                        out.hops.push(hop);
                        *phase = next;
                        t = tl;
                    }
                },
                PartPhase::Contact(mut state) => {
                    let took_off = self.contact_until_take_off(t, t1, &mut state, anchor, &mut out);
                    match took_off {
                        Ok(None) => {
                            *phase = PartPhase::Contact(state);
                            t = t1;
                        }
                        Ok(Some(tk))
                            if self.flight.is_some() && zero_flights < MAX_ZERO_FLIGHTS =>
                        {
                            *phase = PartPhase::Flying(self.launch(tk, &state, anchor));
                            t = tk;
                        }
                        Ok(Some(tk)) => {
                            let (n, _) =
                                self.forces(&self.kin_off_grid(tk, tk), &state.r, &state.u, anchor);
                            return Err(self.contact_loss(tk, &state.r, anchor, n));
                        }
                        Err(loss) => return Err(loss),
                    }
                }
            }
        }
        out.phase = *phase;
        Ok(out)
    }

    /// The steady orbit of a point part **held** at plate point `r0` and
    /// followed through its flights: the part starts at rest on the plate
    /// at `r0` and plays whole periods with [`Simulator::advance_flying`];
    /// at the end of each period it is put back at `r0` (in contact, its
    /// position set to `r0`; in flight, its trajectory moved by the plate
    /// displacement that takes the plate point under it to `r0`, with that
    /// point's velocity change ω × R δ), keeping its velocity relative to
    /// the plate. The period's mean velocity is its plate-frame
    /// displacement over T. Played until that mean changes by less than
    /// [`HELD_TOL`] μ_k g T between two periods (at least
    /// [`HELD_MIN_PERIODS`], at most [`HELD_MAX_PERIODS`]).
    ///
    /// This is the steady state of [`Simulator::steady_state`] (the part
    /// put back at r₀ once a period; under [`Model::FROZEN`] its
    /// kinematics held at r₀ throughout, in flight too, as the judge
    /// plays each point), found by plain iteration because a part in
    /// flight at the period's start has a state a slip velocity does not
    /// describe. Its **airborne fraction** is the time in flight over the
    /// last period divided by T.
    ///
    /// ```
    /// use platefield::dynamics::{Flight, Numerics, PartPhysics, Simulator};
    /// use platefield::motion::{Axes, FourierTerm, Motion, Signals};
    /// // A plate shaken vertically at 1.5 g: one flight a cycle, no drift.
    /// let shake = FourierTerm { amplitude: 1.5 * 9.81, phase: 0.0, harmonic: 1 };
    /// let m = Motion::Signals(Signals { period: 0.02, linear: Axes { z: vec![shake], ..Axes::default() }, angular: Axes::default() });
    /// let sim = Simulator::new(&m, PartPhysics::full(0.3), Numerics::default())
    ///     .with_flight(Flight::INELASTIC)?;
    /// let orbit = sim.held_orbit([0.01, 0.0]).unwrap();
    /// assert_eq!(orbit.hops, 1);
    /// assert!(orbit.airborne_fraction > 0.1 && orbit.airborne_fraction < 0.9);
    /// assert!(orbit.velocity[0].abs() < 1e-9);
    /// # Ok::<(), platefield::Error>(())
    /// ```
    ///
    /// # Errors
    /// The contact loss [`Simulator::advance_flying`] reports.
    pub fn held_orbit(&self, r0: [f64; 2]) -> std::result::Result<HeldOrbit, ContactLoss> {
        let r0 = V2::from(r0);
        let period = self.period;
        let tol = HELD_TOL * self.velocity_scale();
        let mut phase = PartPhase::Contact(PartState::new(r0, V2::zeros()));
        let mut last: Option<V2> = None;
        let mut k = 0u32;
        loop {
            let (a, b) = (f64::from(k) * period, f64::from(k + 1) * period);
            let out = self.advance_flying(a, b, &mut phase, &r0)?;
            k += 1;
            let end = self.plate_point(&phase, b, &r0);
            let v = (end - r0) / period;
            let change = last.map_or(f64::INFINITY, |l| (v - l).norm());
            let settled = change <= tol;
            if (settled && k >= HELD_MIN_PERIODS) || k >= HELD_MAX_PERIODS {
                return Ok(HeldOrbit {
                    velocity: [v.x, v.y],
                    airborne_fraction: (out.airborne_time / period).clamp(0.0, 1.0),
                    hops: out.hops.len(),
                    periods: k,
                    change,
                    settled,
                });
            }
            last = Some(v);
            self.put_back(&mut phase, b, &r0);
        }
    }

    /// The plate-frame point of `phase` at `t` (in flight, the point of
    /// the plate surface under it; for a frozen part, its take-off point
    /// moved by its travel over the plate since, `anchor` its kinematics
    /// point).
    fn plate_point(&self, phase: &PartPhase, t: f64, anchor: &V2) -> V2 {
        match phase {
            PartPhase::Contact(s) => s.r,
            PartPhase::Flying(b) => {
                let plate = self.plate_pose(t);
                let (x, _) = b.at(t, self.gravity);
                let q = plate.rot.inverse_transform_vector(&(x - plate.p));
                self.booked(b, V2::new(q.x, q.y), anchor)
            }
        }
    }

    /// The position a flight of `b` over plate point `q` books: `q`
    /// itself, or for a frozen part (which flies from its kinematics point
    /// `anchor`) its take-off point moved by q − `anchor`.
    fn booked(&self, b: &Airborne, q: V2, anchor: &V2) -> V2 {
        if self.model.moving {
            q
        } else {
            b.from + (q - anchor)
        }
    }

    /// `phase` at `t` moved to plate point `r0`, its velocity relative to
    /// the plate kept ([`Simulator::held_orbit`]).
    fn put_back(&self, phase: &mut PartPhase, t: f64, r0: &V2) {
        let delta = r0 - self.plate_point(phase, t, r0);
        let moving = self.model.moving;
        match phase {
            PartPhase::Contact(s) => s.r = *r0,
            PartPhase::Flying(b) if !moving => b.from += delta,
            PartPhase::Flying(b) => {
                let plate = self.plate_pose(t);
                let arm = plate.rot * V3::new(delta.x, delta.y, 0.0);
                let dv = plate.omega.cross(&arm);
                // The trajectory moves by `arm` at t, its velocity by `dv`.
                b.position += arm - dv * (t - b.t0);
                b.velocity += dv;
            }
        }
    }

    /// The event tolerance (s).
    fn event_tolerance(&self) -> f64 {
        self.numerics.event_tol * self.period
    }

    /// The contact dynamics of `state` from `t0` towards `t1`, fixed step
    /// by fixed step: `None` when it reaches `t1` in contact, else the
    /// take-off time (the state there in `state`). Without a [`Flight`] a
    /// contact loss is returned as [`Simulator::advance`] does.
    fn contact_until_take_off(
        &self,
        t0: f64,
        t1: f64,
        state: &mut PartState,
        anchor: &V2,
        out: &mut FlightOutcome,
    ) -> std::result::Result<Option<f64>, ContactLoss> {
        let nominal = self.period / self.numerics.steps_per_cycle as f64;
        let edges = super::piece_edges(t0, t1, self.period, &self.breakpoints);
        for w in edges.windows(2) {
            let (a, b) = (w[0], w[1]);
            let n = super::step_count(a, b, nominal);
            let mut start = a;
            for i in 1..=n {
                let end = super::step_end(a, b, n, i);
                let before = *state;
                match self.advance(start, end, state, anchor, None) {
                    Ok(o) => {
                        out.stuck_time += o.stuck_time;
                        out.events += o.events;
                        out.rk4_steps += o.rk4_steps;
                    }
                    Err(loss) => {
                        if self.flight.is_none() {
                            return Err(loss);
                        }
                        *state = before;
                        return Ok(Some(self.take_off(start, end, state, anchor, out)));
                    }
                }
                start = end;
            }
        }
        Ok(None)
    }

    /// The take-off time in the fixed step [`a`, `b`] whose contact
    /// integration from `state` (at `a`) failed with N < 0: the last time
    /// t, to the event tolerance, at which the integration from `a` to t
    /// succeeds with N ≥ 0 at its end (bisection). `state` is left there.
    fn take_off(
        &self,
        a: f64,
        b: f64,
        state: &mut PartState,
        anchor: &V2,
        out: &mut FlightOutcome,
    ) -> f64 {
        let start = *state;
        let piece = 0.5 * (a + b);
        // The contact state at `t` when the part is still on the plate there.
        let on_plate = |t: f64| -> Option<(PartState, CycleOutcome)> {
            let mut s = start;
            let o = if t == a {
                CycleOutcome::starting(start)
            } else {
                self.advance(a, t, &mut s, anchor, None).ok()?
            };
            let (n, _) = self.forces(&self.kin_off_grid(t, piece), &s.r, &s.u, anchor);
            (n >= 0.0).then_some((s, o))
        };
        let tol = self.event_tolerance();
        let (mut lo, mut hi) = (a, b);
        let Some(mut best) = on_plate(a) else {
            return a;
        };
        while hi - lo > tol {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            match on_plate(mid) {
                Some(found) => {
                    out.rk4_steps += found.1.rk4_steps;
                    (lo, best) = (mid, found);
                }
                None => hi = mid,
            }
        }
        let (s, o) = best;
        *state = s;
        out.stuck_time += o.stuck_time;
        out.events += o.events;
        lo
    }

    /// The plate's world pose and velocity at `t`.
    fn plate_pose(&self, t: f64) -> PlatePose {
        let s = sample_hold::centre_state(self.motion, t);
        let v3 = |x: &[f64; 6], o: usize| V3::new(x[o], x[o + 1], x[o + 2]);
        PlatePose {
            p: v3(&s.pose, 0),
            rot: rotation::orientation(&v3(&s.pose, 3)),
            v: v3(&s.velocity, 0),
            omega: v3(&s.velocity, 3),
        }
    }

    /// The flight of a part leaving the plate at `t` in `state`: from its
    /// position, or for a frozen part from its kinematics point `anchor`
    /// (module docs).
    fn launch(&self, t: f64, state: &PartState, anchor: &V2) -> Airborne {
        let plate = self.plate_pose(t);
        let at = if self.model.moving { state.r } else { *anchor };
        let arm = plate.rot * V3::new(at.x, at.y, 0.0);
        let slip = plate.rot * V3::new(state.u.x, state.u.y, 0.0);
        Airborne {
            t0: t,
            position: plate.p + arm,
            velocity: plate.v + plate.omega.cross(&arm) + slip,
            from: state.r,
        }
    }

    /// The gap G(t) between the flying part and the plate surface (module docs).
    fn gap(&self, b: &Airborne, t: f64) -> f64 {
        let plate = self.plate_pose(t);
        let (x, _) = b.at(t, self.gravity);
        plate.rot.inverse_transform_vector(&(x - plate.p)).z
    }

    /// The first landing of `b` in (`t`, `t1`], if any (module docs).
    fn landing(&self, b: &Airborne, t: f64, t1: f64) -> Option<f64> {
        let gap = |s: f64| self.gap(b, s);
        let neg_gap = |s: f64| -self.gap(b, s);
        let (n, time) = self.half_step_samples(t, t1, 1);
        let tol = |lo: f64, hi: f64| (1e-9 * (hi - lo)).max(1e-3 * self.event_tolerance());
        // (time, gap) of the last two samples.
        let mut last: [(f64, f64); 2] = [(t, f64::NAN), (t, gap(t))];
        for i in 1..=n {
            let ti = time(i);
            let gi = gap(ti);
            let (tp, gp) = last[1];
            if gi <= 0.0 {
                if gi == 0.0 {
                    return Some(ti);
                }
                // A positive point before the root: the last sample, or
                // (just after take-off, where G = O(τ³)) the interval's maximum.
                let high = if gp > 0.0 {
                    Some((tp, gp))
                } else {
                    let (tm, fm) = brent_min(&neg_gap, tp, ti, tol(tp, ti));
                    (fm < 0.0).then_some((tm, -fm))
                };
                return Some(match high {
                    Some((ta, ga)) => self.illinois(&gap, ta, ga, ti, gi),
                    None => tp,
                });
            }
            // A sampled local minimum may dip below zero between samples.
            let (tpp, gpp) = last[0];
            if gp <= gpp && gp <= gi {
                let (tm, fm) = brent_min(&gap, tpp, ti, tol(tpp, ti));
                if fm <= 0.0 {
                    return Some(self.illinois(&gap, tpp, gpp, tm, fm));
                }
            }
            last = [last[1], (ti, gi)];
        }
        None
    }

    /// The impact of `b` landing at `tl` (module docs): the part after it,
    /// and the hop.
    fn impact(&self, b: &Airborne, tl: f64, anchor: &V2) -> (PartPhase, Hop) {
        let plate = self.plate_pose(tl);
        let (x, v) = b.at(tl, self.gravity);
        let arm = x - plate.p;
        let q = plate.rot.inverse_transform_vector(&arm);
        let w = plate
            .rot
            .inverse_transform_vector(&(v - plate.v - plate.omega.cross(&arm)));
        let (wn, wt) = (w.z.min(0.0), V2::new(w.x, w.y));
        let pn = -(1.0 + self.flight.unwrap_or_default().restitution) * wn;
        let bound = self.friction.kinetic * pn;
        let speed = wt.norm();
        let wt_after = if speed <= bound {
            V2::zeros()
        } else {
            wt * (1.0 - bound / speed)
        };
        let rebound = -self.flight.unwrap_or_default().restitution * wn;
        let r = self.booked(b, V2::new(q.x, q.y), anchor);
        let hop = Hop {
            take_off: b.t0,
            landing: tl,
            from: [b.from.x, b.from.y],
            to: [r.x, r.y],
            impact_speed: -wn,
        };
        if rebound > self.gravity * self.event_tolerance() {
            let at = if self.model.moving { r } else { *anchor };
            let surface = plate.rot * V3::new(at.x, at.y, 0.0);
            let rel = plate.rot * V3::new(wt_after.x, wt_after.y, rebound);
            let next = Airborne {
                t0: tl,
                position: plate.p + surface,
                velocity: plate.v + plate.omega.cross(&surface) + rel,
                from: r,
            };
            return (PartPhase::Flying(next), hop);
        }
        (PartPhase::Contact(PartState::new(r, wt_after)), hop)
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `dynamics::flight::Flight::validate`.
    #[test]
    fn example_flight_validate() {
        use crate::dynamics::Flight;
        assert!(Flight { restitution: 0.5 }.validate("flight").is_ok());
        let e = Flight { restitution: 1.5 }.validate("flight").unwrap_err();
        assert!(e.to_string().contains("flight.restitution"));
    }

    /// A worked example of `dynamics::flight::Simulator<'_>::with_flight`.
    #[test]
    fn example_simulator_with_flight() -> Result<(), crate::Error> {
        use crate::dynamics::{Flight, Numerics, PartPhysics, Simulator};
        use crate::motion::{Axes, FourierTerm, Motion, Signals};
        let shake = FourierTerm {
            amplitude: 2.0 * 9.81,
            phase: 0.0,
            harmonic: 1,
        };
        let m = Motion::Signals(Signals {
            period: 0.02,
            linear: Axes {
                z: vec![shake],
                ..Axes::default()
            },
            angular: Axes::default(),
        });
        let sim = Simulator::new(&m, PartPhysics::full(0.3), Numerics::default())
            .with_flight(Flight::INELASTIC)?;
        assert_eq!(sim.flight(), Some(Flight::INELASTIC));
        Ok(())
    }
}

#[cfg(test)]
#[path = "../../tests/unit/flight.rs"]
mod flight_tests;
