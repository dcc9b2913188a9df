//! A linear feeder: the conveying speed of a point part on a flat track
//! against the throw number Γ and the phase between the track's two
//! vibrations, for several frictions, set against the classic theory of
//! throw conveying (`platefield study feeder` writes `feeder.md`).
//!
//! The track is the plate without rotation: its acceleration along the
//! track and normal to it is
//!
//! ```text
//! ẍ = X sin ωt,      z̈ = Z sin(ωt + φ),      Γ = Z / g,      X = Z / tan ψ
//! ```
//!
//! (at φ = 0 the straight-line vibration at the angle ψ to the track of a
//! single-drive linear feeder; φ ≠ 0 needs two drives). The part is played
//! by the product's flight rung ([`platefield::dynamics::flight`]: the
//! stick-slip dynamics in contact, the exact ballistic flight once the
//! normal force per unit mass N = g + z̈ reaches 0, a completely inelastic
//! landing whose tangential impulse is bounded by μ times the normal one).
//! For Γ ≤ 1 the part never leaves the track and is conveyed by sliding
//! alone, forward and backward by turns.
//!
//! **The classic theory** ([`throw_theory`]) is that of the throw conveyor:
//! the part takes off where N reaches 0, flies, and on landing takes on the
//! track's velocity and rests on it until it takes off again (the limit
//! μ → ∞ of the model above: nothing slides). Its speed is the horizontal
//! distance each flight gains on the track over the time between flights.
//! It is found here by events (take-off at ωt + φ = π + asin(1/Γ), the
//! landing as the first root of the gap), independently of the simulator;
//! the product at μ = 1000 must reproduce it (`studies/tests/feeder.rs`),
//! and the table gives how far finite friction departs from it. The point
//! mass model with rest, slide and flight phases is that of Sloot and
//! Kruyt (1996); the theory of sliding and hopping on linear feeders that of
//! Redford and Boothroyd (1967) (`docs/feeder.md`).

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

use rayon::prelude::*;

use platefield::dynamics::{
    Flight, Friction, Model, Numerics, PartPhase, PartPhysics, PartState, Simulator, V2,
};
use platefield::error::{Error, Result};
use platefield::motion::{Axes, FourierTerm, Motion, Signals};
use platefield::output::write_atomic;

/// Default output folder.
pub const DIR: &str = "results";

/// Gravity (m/s²).
pub const G: f64 = 9.81;

/// The track's period (s): 50 Hz, the mains frequency an electromagnetic
/// feeder is driven at. The speed over the track's velocity amplitude
/// ([`Conveying::kv`]) does not depend on it.
pub const PERIOD: f64 = 0.02;

/// The vibration angle ψ (degrees) between the straight-line vibration and
/// the track at φ = 0, which sets X = Z / tan ψ.
pub const VIBRATION_ANGLE_DEG: f64 = 30.0;

/// The throw numbers of the sweep: 0.5 to 3 in steps of 0.25.
pub const GAMMAS: [f64; 11] = [0.5, 0.75, 1.0, 1.25, 1.5, 1.75, 2.0, 2.25, 2.5, 2.75, 3.0];

/// The phases φ of the normal vibration against the track's (degrees).
pub const PHASES_DEG: [f64; 7] = [-90.0, -60.0, -30.0, 0.0, 30.0, 60.0, 90.0];

/// The frictions of the sweep.
pub const FRICTIONS: [f64; 3] = [0.2, 0.3, 0.5];

/// A friction high enough that nothing slides but for a vanishing time
/// around each take-off: the product's stand-in for the theory's μ → ∞.
pub const STICKING: f64 = 1000.0;

/// Cycles played before the speed is measured (the part starts at rest).
pub const TRANSIENT_CYCLES: u32 = 60;

/// Cycles the speed is measured over.
pub const MEASURED_CYCLES: u32 = 40;

/// One setting of the track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Track {
    /// Throw number Γ = Z / g.
    pub gamma: f64,
    /// Phase φ of the normal vibration (rad).
    pub phase: f64,
    /// Vibration angle ψ (rad): X = Z / tan ψ.
    pub angle: f64,
    /// Period (s).
    pub period: f64,
}

impl Track {
    /// The track at throw number `gamma` and phase `phase_deg` (degrees),
    /// at the study's [`VIBRATION_ANGLE_DEG`] and [`PERIOD`].
    ///
    /// ```
    /// use platefield_studies::feeder::{Track, G};
    /// let t = Track::new(2.0, 0.0);
    /// let (x, z) = t.amplitudes();
    /// assert!((z - 2.0 * G).abs() < 1e-12 && (x - z * 3f64.sqrt()).abs() < 1e-9);
    /// ```
    pub fn new(gamma: f64, phase_deg: f64) -> Track {
        Track {
            gamma,
            phase: phase_deg.to_radians(),
            angle: VIBRATION_ANGLE_DEG.to_radians(),
            period: PERIOD,
        }
    }

    /// ω (rad/s).
    pub fn omega(&self) -> f64 {
        2.0 * PI / self.period
    }

    /// The acceleration amplitudes (X along the track, Z normal to it), m/s².
    pub fn amplitudes(&self) -> (f64, f64) {
        let z = self.gamma * G;
        (z / self.angle.tan(), z)
    }

    /// The track's velocity amplitude along it, X / ω (m/s).
    pub fn velocity_amplitude(&self) -> f64 {
        self.amplitudes().0 / self.omega()
    }

    /// The plate motion: the two sines, nothing else.
    pub fn motion(&self) -> Motion {
        let (x, z) = self.amplitudes();
        let term = |amplitude: f64, phase: f64| {
            vec![FourierTerm {
                amplitude,
                phase,
                harmonic: 1,
            }]
        };
        Motion::Signals(Signals {
            period: self.period,
            linear: Axes {
                x: term(x, 0.0),
                y: Vec::new(),
                z: term(z, self.phase),
            },
            angular: Axes::default(),
        })
    }
}

/// A part's steady conveying on a track.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Conveying {
    /// Mean speed along the track (m/s; positive along +x).
    pub speed: f64,
    /// Share of the measured time in flight.
    pub airborne: f64,
    /// The track's velocity amplitude X / ω (m/s).
    pub scale: f64,
}

impl Conveying {
    /// The speed over the track's velocity amplitude, v ω / X.
    pub fn kv(&self) -> f64 {
        self.speed / self.scale
    }
}

/// The mean speed between the first and the last of `landings` (time,
/// position along the track), or `None` with fewer than two.
fn between_landings(landings: &[(f64, f64)]) -> Option<f64> {
    let (first, last) = (landings.first()?, landings.last()?);
    (last.0 > first.0).then(|| (last.1 - first.1) / (last.0 - first.0))
}

/// The part played on `track` at friction `mu` from rest by the product's
/// simulator with flight: its mean speed over [`MEASURED_CYCLES`] after
/// [`TRANSIENT_CYCLES`], between its first and last landing there when it
/// hops, else between the span's ends.
///
/// ```
/// use platefield_studies::feeder::{played, Track};
/// // Below Γ = 1 a part that cannot slide rests on the track.
/// let c = played(&Track::new(0.5, 0.0), 1000.0).unwrap();
/// assert_eq!((c.speed, c.airborne), (0.0, 0.0));
/// ```
///
/// # Errors
/// The simulator refuses the motion or loses the part.
pub fn played(track: &Track, mu: f64) -> Result<Conveying> {
    played_over(track, mu, (TRANSIENT_CYCLES, MEASURED_CYCLES))
}

/// [`played`] measured over `measured` cycles after `transient`.
///
/// # Errors
/// As [`played`].
pub fn played_over(track: &Track, mu: f64, (transient, measured): (u32, u32)) -> Result<Conveying> {
    let motion = track.motion();
    let physics = PartPhysics::new(Friction::uniform(mu), G, Model::FULL);
    let sim =
        Simulator::new(&motion, physics, Numerics::default()).with_flight(Flight::INELASTIC)?;
    let t = |cycles: u32| f64::from(cycles) * track.period;
    let (t1, t2) = (t(transient), t(transient + measured));
    let anchor = V2::zeros();
    let mut part = PartPhase::Contact(PartState::new(V2::zeros(), V2::zeros()));
    let lost = |l: platefield::dynamics::ContactLoss| {
        Error::ContactLost(format!(
            "feeder at Γ {}, φ {:.0}°, μ {mu}: the part left the track at t = {:.4} s without a flight",
            track.gamma,
            track.phase.to_degrees(),
            l.time
        ))
    };
    sim.advance_flying(0.0, t1, &mut part, &anchor)
        .map_err(lost)?;
    let x1 = contact_x(&part);
    let out = sim
        .advance_flying(t1, t2, &mut part, &anchor)
        .map_err(lost)?;
    let landings: Vec<(f64, f64)> = out.hops.iter().map(|h| (h.landing, h.to[0])).collect();
    let speed = between_landings(&landings)
        .or_else(|| Some((contact_x(&part)? - x1?) / (t2 - t1)))
        .unwrap_or(f64::NAN);
    Ok(Conveying {
        speed,
        airborne: out.airborne_time / (t2 - t1),
        scale: track.velocity_amplitude(),
    })
}

/// The part's position along the track when it is on it.
fn contact_x(part: &PartPhase) -> Option<f64> {
    match part {
        PartPhase::Contact(s) => Some(s.r.x),
        PartPhase::Flying(_) => None,
    }
}

/// The track's displacement, velocity and acceleration along an axis of
/// acceleration amplitude `a` and phase `phi` at `t`.
fn axis(track: &Track, (a, phi): (f64, f64), t: f64) -> (f64, f64, f64) {
    let w = track.omega();
    let arg = w * t + phi;
    (-a / (w * w) * arg.sin(), -a / w * arg.cos(), a * arg.sin())
}

/// The first root in (a, b] of `gap`, positive just after `a`: sampled at
/// `spacing`, then bisected to round-off.
fn first_root(gap: &impl Fn(f64) -> f64, a: f64, b: f64, spacing: f64) -> Option<f64> {
    let mut lo = a;
    while lo < b {
        let hi = (lo + spacing).min(b);
        if gap(hi) <= 0.0 {
            let (mut l, mut h) = (lo, hi);
            for _ in 0..200 {
                let m = 0.5 * (l + h);
                if gap(m) > 0.0 {
                    l = m;
                } else {
                    h = m;
                }
            }
            return Some(h);
        }
        lo = hi;
    }
    None
}

/// The classic throw conveyor's mean speed on `track` (module docs: the
/// part rests on the track but in flight, μ → ∞): take-offs where
/// N = g + z̈ falls through 0 (at once after a landing where N < 0),
/// landings at the first root of the gap (sampled at T/1000, then
/// bisected), each flight's gain on the track x(t₀) + ẋ(t₀)(t_L − t₀) −
/// x(t_L) added up; the speed between the first and last landing of
/// [`MEASURED_CYCLES`] after 10 cycles, as [`played`] measures it.
/// Zero for Γ ≤ 1.
///
/// ```
/// use platefield_studies::feeder::{throw_theory, Track};
/// assert_eq!(throw_theory(&Track::new(0.75, 0.0)), 0.0);
/// assert!(throw_theory(&Track::new(2.0, 0.0)) > 0.0);
/// ```
pub fn throw_theory(track: &Track) -> f64 {
    if track.gamma <= 1.0 {
        return 0.0;
    }
    let (xa, za) = track.amplitudes();
    let (w, period) = (track.omega(), track.period);
    let along = |t: f64| axis(track, (xa, 0.0), t);
    let normal = |t: f64| axis(track, (za, track.phase), t);
    let force = |t: f64| G + normal(t).2;
    let lift = PI + (1.0 / track.gamma).asin();
    // Its own transient is short: a landing that sticks where N ≥ 0 starts
    // the period-1 orbit (rest until the take-off phase).
    let t1 = f64::from(THEORY_TRANSIENT_CYCLES) * period;
    let t2 = t1 + f64::from(MEASURED_CYCLES) * period;
    let (mut t, mut gained) = (0.0, 0.0);
    let mut landings = Vec::new();
    while t < t2 {
        let t0 = if force(t) < 0.0 {
            t
        } else {
            let k = ((w * t + track.phase - lift) / (2.0 * PI)).ceil();
            (lift + 2.0 * PI * k - track.phase) / w
        };
        let (z0, vz0, _) = normal(t0);
        let gap = |s: f64| {
            let tau = s - t0;
            z0 + vz0 * tau - 0.5 * G * tau * tau - normal(s).0
        };
        let Some(tl) = first_root(&gap, t0, t0 + 4.0 * period, period / 1000.0) else {
            break;
        };
        let (x0, vx0, _) = along(t0);
        gained += x0 + vx0 * (tl - t0) - along(tl).0;
        if (t1..=t2).contains(&tl) {
            landings.push((tl, gained));
        }
        t = tl;
    }
    between_landings(&landings).unwrap_or(0.0)
}

/// Cycles [`throw_theory`] plays before it measures.
const THEORY_TRANSIENT_CYCLES: u32 = 10;

/// One row of the sweep: the track and the part's conveying at each of
/// [`FRICTIONS`], then at [`STICKING`], and the throw theory's speed.
#[derive(Debug, Clone)]
pub struct Row {
    /// The track.
    pub track: Track,
    /// At each of [`FRICTIONS`].
    pub at: Vec<Conveying>,
    /// At [`STICKING`].
    pub sticking: Conveying,
    /// The throw theory's speed (m/s).
    pub theory: f64,
}

/// The sweep over [`GAMMAS`] × [`PHASES_DEG`], rows in that order.
///
/// # Errors
/// A play fails ([`played`]).
pub fn sweep() -> Result<Vec<Row>> {
    let tracks: Vec<Track> = GAMMAS
        .iter()
        .flat_map(|&g| PHASES_DEG.iter().map(move |&p| Track::new(g, p)))
        .collect();
    tracks
        .par_iter()
        .map(|track| {
            let at = FRICTIONS
                .iter()
                .map(|&mu| played(track, mu))
                .collect::<Result<Vec<_>>>()?;
            Ok(Row {
                track: *track,
                at,
                sticking: played(track, STICKING)?,
                theory: throw_theory(track),
            })
        })
        .collect()
}

/// `x` with three decimals, or "n/a".
fn num(x: f64) -> String {
    if x.is_finite() {
        format!("{x:+.3}")
    } else {
        "n/a".into()
    }
}

/// The report of `rows` ([`sweep`]).
pub fn report(rows: &[Row]) -> String {
    let mut md = String::from(
        "# A linear feeder: conveying speed against throw number and phase\n\n\
         Regenerate: `platefield study feeder` (deterministic). ",
    );
    let _ = writeln!(
        md,
        "A flat track vibrated along it, ẍ = X sin ωt, and normal to it, z̈ = Z sin(ωt + φ), \
         at {:.0} Hz; Γ = Z/g, X = Z / tan {VIBRATION_ANGLE_DEG:.0}° (at φ = 0 the straight-line \
         vibration of a single-drive feeder at {VIBRATION_ANGLE_DEG:.0}° to the track). A point \
         part from rest played by the flight rung (`dynamics::flight`: stick-slip in contact, exact \
         flight once N = g + z̈ reaches 0, inelastic landings with the tangential impulse bounded \
         by μ; static = kinetic friction); its mean speed over {MEASURED_CYCLES} cycles after \
         {TRANSIENT_CYCLES}, between its first and last landing there when it hops. \
         Kv = v ω / X: the speed over the track's velocity amplitude along it (independent of the \
         frequency). The throw theory (`studies::feeder::throw_theory`) is the classic throw \
         conveyor's: nothing slides (μ → ∞), each flight's gain on the track is the whole \
         conveying; the product at μ = {STICKING:.0} is set beside it.\n",
        1.0 / PERIOD
    );
    straight_line(&mut md, rows);
    for (k, mu) in FRICTIONS.iter().enumerate() {
        grid(&mut md, &format!("μ = {mu}"), rows, &|r| r.at[k].kv());
    }
    grid(&mut md, "the throw theory (μ → ∞)", rows, &|r| {
        r.theory / r.track.velocity_amplitude()
    });
    peaks(&mut md, rows);
    against_theory(&mut md, rows);
    md
}

/// The φ = 0 table: Kv at each friction, the sticking play and the theory.
fn straight_line(md: &mut String, rows: &[Row]) {
    let _ = writeln!(
        md,
        "\n## Straight-line vibration (φ = 0)\n\n| Γ | Kv at μ {} | Kv at μ = {STICKING:.0} | Kv, throw theory | airborne at μ {} | speed at μ {} (mm/s) |\n|---|{}---|---|---|---|",
        FRICTIONS.map(|m| m.to_string()).join(" | Kv at μ "),
        FRICTIONS[1],
        FRICTIONS[1],
        "---|".repeat(FRICTIONS.len())
    );
    for r in rows.iter().filter(|r| r.track.phase == 0.0) {
        let kvs: Vec<String> = r.at.iter().map(|c| num(c.kv())).collect();
        let _ = writeln!(
            md,
            "| {:.2} | {} | {} | {} | {:.1} % | {:.1} |",
            r.track.gamma,
            kvs.join(" | "),
            num(r.sticking.kv()),
            num(r.theory / r.track.velocity_amplitude()),
            100.0 * r.at[1].airborne,
            1e3 * r.at[1].speed
        );
    }
}

/// A Γ × φ table of `value`.
fn grid(md: &mut String, title: &str, rows: &[Row], value: &dyn Fn(&Row) -> f64) {
    let _ = writeln!(
        md,
        "\n## Kv, {title}\n\n| Γ \\ φ | {} |\n|---|{}",
        PHASES_DEG.map(|p| format!("{p:+.0}°")).join(" | "),
        "---|".repeat(PHASES_DEG.len())
    );
    for chunk in rows.chunks(PHASES_DEG.len()) {
        let cells: Vec<String> = chunk.iter().map(|r| num(value(r))).collect();
        let _ = writeln!(
            md,
            "| {:.2} | {} |",
            chunk[0].track.gamma,
            cells.join(" | ")
        );
    }
}

/// The fastest setting of the sweep at each friction.
fn peaks(md: &mut String, rows: &[Row]) {
    let _ = writeln!(
        md,
        "\n## Peak speed\n\n| μ | Kv | speed (mm/s) | Γ | φ | airborne |\n|---|---|---|---|---|---|"
    );
    let last = GAMMAS[GAMMAS.len() - 1];
    let mut at_edge = false;
    for (k, mu) in FRICTIONS.iter().enumerate() {
        let Some(best) = rows
            .iter()
            .filter(|r| r.at[k].speed.is_finite())
            .max_by(|a, b| a.at[k].speed.total_cmp(&b.at[k].speed))
        else {
            continue;
        };
        let c = best.at[k];
        let _ = writeln!(
            md,
            "| {mu} | {} | {:.1} | {:.2} | {:+.0}° | {:.1} % |",
            num(c.kv()),
            1e3 * c.speed,
            best.track.gamma,
            best.track.phase.to_degrees(),
            100.0 * c.airborne
        );
        at_edge |= best.track.gamma == last;
    }
    if at_edge {
        let _ = writeln!(
            md,
            "\nA peak at Γ = {last}, the sweep's edge: the speed still rises there, as each flight \
             nears a whole period (the inelastic bouncing ball's period-1 flights end near Γ = 3.3)."
        );
    }
}

/// The largest gap between the sticking play and the theory, in Kv.
pub fn theory_gap(rows: &[Row]) -> f64 {
    rows.iter()
        .map(|r| ((r.sticking.speed - r.theory) / r.track.velocity_amplitude()).abs())
        .fold(0.0, f64::max)
}

/// The product at μ = [`STICKING`] against the throw theory.
fn against_theory(md: &mut String, rows: &[Row]) {
    let mut widest = (0.0, &rows[0], 0);
    for r in rows.iter().filter(|r| r.track.gamma > 1.0) {
        for (k, c) in r.at.iter().enumerate() {
            let d = ((c.speed - r.theory) / r.track.velocity_amplitude()).abs();
            if d > widest.0 {
                widest = (d, r, k);
            }
        }
    }
    let _ = writeln!(
        md,
        "\n## Against the throw theory\n\nOver the {} settings, the product at μ = {STICKING:.0} \
         and the throw theory differ by at most {:.1e} in Kv: the part slips in the instant before \
         each take-off, where μN falls below the track's pull, a gap that falls as 1/μ \
         (`studies/tests/feeder.rs`). Friction departs from the theory far more: below Γ = 1 \
         the theory conveys nothing and sliding does; above it the slides after each landing \
         and before each take-off differ from the theory by up to {:.3} in Kv (at Γ {:.2}, \
         φ {:+.0}°, μ {}: {} against {}).",
        rows.len(),
        theory_gap(rows),
        widest.0,
        widest.1.track.gamma,
        widest.1.track.phase.to_degrees(),
        FRICTIONS[widest.2],
        num(widest.1.at[widest.2].kv()),
        num(widest.1.theory / widest.1.track.velocity_amplitude()),
    );
}

/// `platefield study feeder`: the sweep, written to `out/feeder.md`.
///
/// # Errors
/// A play fails, or the file cannot be written.
pub fn run(out: &Path) -> Result<String> {
    let rows = sweep()?;
    let md = report(&rows);
    let path = out.join("feeder.md");
    write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\nwrote {}\n", path.display()))
}
