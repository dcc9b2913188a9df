//! Time-only plate kinematics computed once per field.
//!
//! The plate's angular velocity and acceleration, the reference point's
//! velocity and acceleration and gravity in the plate frame
//! ([`Kinematics`]) depend on time only. A field integrates hundreds of
//! grid points (and, for force fields, every start phase) over the same
//! time spans with the same fixed RK4 steps, so each point evaluated the
//! same waveforms (and their `sin_cos`) at the same instants — about half
//! of a field's CPU time without this table.
//!
//! [`KinematicsTable`] holds the kinematics at every instant the integrator
//! asks for on its fixed-step path over given spans: for each smooth piece
//! (between acceleration breakpoints) the piece start and, for every step
//! [s, e], the stage times s + h/2 and s + h (h = e − s) and the step end e
//! — computed with exactly the integrator's arithmetic
//! ([`super::step_count`], [`super::step_end`]), so a lookup is keyed by the
//! exact bits of (t, piece): the piece by a hash of its key, the instant by
//! its step index (t − a) n/(b − a) and an exact comparison, no search. It is a memo of
//! the simulator's own evaluation ([`crate::motion::PreparedMotion`], which
//! is [`Motion::kinematics_piece`] to round-off): a hit returns the very
//! value an evaluation off the table would, so fields are bitwise unchanged
//! by it (and stay identical on any number of threads). The integrator's
//! whole fixed steps skip even that lookup: it finds each piece once and
//! hands every step its [`StepNodes`]. Event-located and shortened steps ask
//! for other instants; they miss and are evaluated (those known to be off
//! the grid without asking).
//!
//! The same memo serves every computation that advances many parts over
//! the same spans: the orbit contact check of a synthesis
//! (`synth::contact::orbit_least_normal`, one cycle per grid point) and
//! every played schedule (one table per segment, shared by every part and
//! every period: `play::Player::with_tables`). That halves the CPU of a
//! six-signal design (same bytes; measured: `docs/dev/forward-model.md`, **Measurements behind
//! the integrator's constants**), whose plays and
//! contact checks would otherwise evaluate the kinematics at every step.

use crate::motion::{Kinematics, Motion, PreparedMotion};

/// Kinematics at the nodes of one smooth piece [a, b] of n fixed steps, in
/// a fixed layout: slot 0 is a, slots 3i − 2, 3i − 1, 3i the stage time
/// s + h/2, the stage end s + h and the step end of step i (s its start, h
/// its length), so that the slot of an instant follows from (t − a) n/(b − a)
/// without a search.
#[derive(Debug, Clone)]
pub(super) struct PieceNodes {
    /// The piece key the integrator passes (0.5 (a + b)).
    piece: f64,
    /// Piece start a.
    a: f64,
    /// Piece end b.
    b: f64,
    /// Steps n.
    n: usize,
    /// n/(b − a): steps per unit time.
    rate: f64,
    /// Node times in the layout above.
    times: Vec<f64>,
    /// Kinematics at `times`.
    kinematics: Vec<Kinematics>,
}

impl PieceNodes {
    fn new(
        motion: &PreparedMotion<'_>,
        gravity: f64,
        tilt: bool,
        a: f64,
        b: f64,
        n: usize,
    ) -> PieceNodes {
        let piece = 0.5 * (a + b);
        let mut times = Vec::with_capacity(3 * n + 1);
        times.push(a);
        let mut s = a;
        for i in 1..=n {
            let e = super::step_end(a, b, n, i);
            let h = e - s;
            times.extend([s + 0.5 * h, s + h, e]);
            s = e;
        }
        let kinematics = times
            .iter()
            .map(|t| motion.kinematics_piece(*t, piece, gravity, tilt))
            .collect();
        PieceNodes {
            piece,
            a,
            b,
            n,
            rate: n as f64 / (b - a),
            times,
            kinematics,
        }
    }

    /// The nodes of step `i` (1 ≤ i ≤ n).
    #[inline]
    pub(super) fn step(&self, i: usize) -> StepNodes<'_> {
        let start = if i == 1 { 0 } else { 3 * (i - 1) };
        StepNodes {
            start: self.times[start],
            k: [
                &self.kinematics[start],
                &self.kinematics[3 * i - 2],
                &self.kinematics[3 * i - 1],
            ],
        }
    }

    #[inline]
    fn find(&self, t: f64) -> Option<&Kinematics> {
        if t == self.a {
            return Some(&self.kinematics[0]);
        }
        // x = (t − a) n/(b − a) is close to j − ½ at the stage time of step
        // j and to j at its end: try that slot first.
        let x = (t - self.a) * self.rate;
        if !(x >= 0.0 && x <= (self.n + 1) as f64) {
            return None;
        }
        let m = (2.0 * x + 0.5) as usize;
        let j = m.div_ceil(2);
        if j >= 1 && j <= self.n {
            let slot = if m % 2 == 1 { 3 * j - 2 } else { 3 * j };
            if self.times[slot] == t {
                return Some(&self.kinematics[slot]);
            }
        }
        // Step k contains t in (s, e]; round-off may put t one step off.
        let k = ((x as usize) + 1).clamp(1, self.n);
        for j in [k, k - 1, k + 1] {
            if j == 0 || j > self.n {
                continue;
            }
            for slot in 3 * j - 2..=3 * j {
                if self.times[slot] == t {
                    return Some(&self.kinematics[slot]);
                }
            }
        }
        None
    }
}

/// The tabulated kinematics of one fixed step [s, e] (h = e − s): at s,
/// s + h/2 and s + h, for the integrator to use without a lookup.
#[derive(Debug, Clone, Copy)]
pub(super) struct StepNodes<'t> {
    /// The step's start s.
    pub start: f64,
    /// Kinematics at s, s + h/2, s + h.
    pub k: [&'t Kinematics; 3],
}

impl<'t> StepNodes<'t> {
    /// The kinematics at t + h/2 and t + h of an RK4 step of size `h` from
    /// `t` to the step's end `target`, when it is the whole step (t = s,
    /// h = target − s: the instants tabulated with the same arithmetic).
    #[inline]
    pub(crate) fn stages(&self, t: f64, h: f64, target: f64) -> Option<[&'t Kinematics; 2]> {
        (t == self.start && h == target - t).then_some([self.k[1], self.k[2]])
    }

    /// The kinematics at `t` when it is the step's start.
    #[inline]
    pub(crate) fn at_start(&self, t: f64) -> Option<&'t Kinematics> {
        (t == self.start).then_some(self.k[0])
    }
}

/// Plate kinematics tabulated on the integrator's fixed-step time grid of
/// some spans, shared (read-only) by every point of a field.
#[derive(Debug)]
pub(crate) struct KinematicsTable<'a> {
    motion: &'a Motion,
    gravity: f64,
    tilt: bool,
    /// One entry per distinct (a, b, n) piece.
    pieces: Vec<PieceNodes>,
    /// Open-addressing index of `pieces` by the bits of their key (a piece
    /// key shared by pieces of different (a, b, n) keeps the first).
    slots: Vec<u32>,
    #[cfg(test)]
    misses: std::sync::atomic::AtomicUsize,
    #[cfg(test)]
    hits: std::sync::atomic::AtomicUsize,
}

/// Slot of a piece key in an index of 2^`bits` slots (Fibonacci hashing).
#[inline]
fn home(piece: f64, bits: u32) -> usize {
    (piece.to_bits().wrapping_mul(0x9E37_79B9_7F4A_7C15) >> (64 - bits)) as usize
}

impl<'a> KinematicsTable<'a> {
    /// The kinematics of `prepared` (the evaluation of `motion` under
    /// `gravity` and the tilt switch `tilt`) on the fixed-step path of
    /// nominal step `nominal` over each span `[t0, t1]` in `spans`.
    pub(super) fn tabulate(
        (motion, prepared): (&'a Motion, &PreparedMotion<'a>),
        (gravity, tilt): (f64, bool),
        nominal: f64,
        spans: &[(f64, f64)],
    ) -> KinematicsTable<'a> {
        let period = motion.period();
        let breakpoints = motion.breakpoints();
        let mut pieces: Vec<PieceNodes> = Vec::new();
        let mut seen = std::collections::HashSet::new();
        for &(t0, t1) in spans {
            let edges = super::piece_edges(t0, t1, period, &breakpoints);
            for w in edges.windows(2) {
                let (a, b) = (w[0], w[1]);
                let n = super::step_count(a, b, nominal);
                if seen.insert((a.to_bits(), b.to_bits(), n)) {
                    pieces.push(PieceNodes::new(prepared, gravity, tilt, a, b, n));
                }
            }
        }
        let bits = (2 * pieces.len().max(1))
            .next_power_of_two()
            .trailing_zeros()
            .max(1);
        let mut slots = vec![u32::MAX; 1 << bits];
        for (i, p) in pieces.iter().enumerate() {
            let mut h = home(p.piece, bits);
            loop {
                match slots[h] {
                    u32::MAX => {
                        slots[h] = i as u32;
                        break;
                    }
                    j if pieces[j as usize].piece.to_bits() == p.piece.to_bits() => break,
                    _ => h = (h + 1) & (slots.len() - 1),
                }
            }
        }
        KinematicsTable {
            motion,
            gravity,
            tilt,
            pieces,
            slots,
            #[cfg(test)]
            misses: std::sync::atomic::AtomicUsize::new(0),
            #[cfg(test)]
            hits: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// True when this table holds `motion`'s kinematics under gravity `g`
    /// and the tilt switch `tilt`.
    pub(crate) fn fits(&self, motion: &Motion, gravity: f64, tilt: bool) -> bool {
        (std::ptr::eq(self.motion, motion) || self.motion == motion)
            && self.gravity.to_bits() == gravity.to_bits()
            && self.tilt == tilt
    }

    /// The kinematics at exactly `t` on the piece keyed `piece`, when
    /// tabulated.
    #[inline]
    pub(crate) fn get(&self, t: f64, piece: f64) -> Option<&Kinematics> {
        let found = self.find(t, piece);
        #[cfg(test)]
        if found.is_none() {
            self.misses
                .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        } else {
            self.hits.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        }
        found
    }

    #[inline]
    fn find(&self, t: f64, piece: f64) -> Option<&Kinematics> {
        self.keyed(piece)?.find(t)
    }

    /// The piece keyed `piece` (its bits), if any.
    #[inline]
    fn keyed(&self, piece: f64) -> Option<&PieceNodes> {
        let bits = self.slots.len().trailing_zeros();
        let mut h = home(piece, bits);
        loop {
            let i = *self.slots.get(h)?;
            if i == u32::MAX {
                return None;
            }
            let p = &self.pieces[i as usize];
            if p.piece.to_bits() == piece.to_bits() {
                return Some(p);
            }
            h = (h + 1) & (self.slots.len() - 1);
        }
    }

    /// The nodes of the piece [`a`, `b`] of `n` steps keyed `piece`, when
    /// tabulated (one lookup per piece instead of one per instant).
    #[inline]
    pub(super) fn piece(&self, a: f64, b: f64, n: usize, piece: f64) -> Option<&PieceNodes> {
        self.keyed(piece)
            .filter(|p| p.a.to_bits() == a.to_bits() && p.b.to_bits() == b.to_bits() && p.n == n)
    }

    /// Lookups that (hit, missed) so far (test builds only).
    #[cfg(test)]
    pub(crate) fn lookups(&self) -> (usize, usize) {
        use std::sync::atomic::Ordering::Relaxed;
        (self.hits.load(Relaxed), self.misses.load(Relaxed))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::{Numerics, PartPhysics, PartState, Simulator, V2};
    use crate::motion::{FourierTerm, Screw, Waveform};

    fn screw(rotation: Waveform, translation: Waveform) -> Motion {
        Motion::Screw(Screw {
            axis: [0.0, 0.6, 0.8],
            point: [0.01, 0.0, -0.03],
            period: 0.03,
            rotation,
            translation,
        })
    }

    /// Full model, μ = 0.3, `steps` per cycle.
    fn simulator(motion: &Motion, steps: usize) -> Simulator<'_> {
        let numerics = Numerics {
            steps_per_cycle: steps,
            ..Numerics::default()
        };
        Simulator::new(motion, PartPhysics::full(0.3), numerics)
    }

    fn fourier() -> Waveform {
        Waveform::Fourier {
            terms: vec![
                FourierTerm {
                    amplitude: 300.0,
                    phase: 0.4,
                    harmonic: 1,
                },
                FourierTerm {
                    amplitude: 120.0,
                    phase: -1.1,
                    harmonic: 2,
                },
            ],
            offset: 0.0,
        }
    }

    /// Every tabulated value is the simulator's evaluation off the table,
    /// bit for bit, and instants off the grid miss.
    #[test]
    fn table_is_a_memo_of_the_simulators_evaluation() {
        let motion = screw(Waveform::Square { accel: 150.0 }, fourier());
        let sim = simulator(&motion, 16);
        let table = KinematicsTable::phases(&sim, 7);
        assert!(table.fits(&motion, 9.81, true));
        assert!(!table.fits(&motion, 9.8, true));
        assert!(!table.fits(&motion, 9.81, false));
        // Square-wave breakpoints split most spans into three pieces.
        assert!(table.pieces.len() > 7, "{}", table.pieces.len());
        let mut count = 0;
        for p in &table.pieces {
            for (t, k) in p.times.iter().zip(&p.kinematics) {
                assert_eq!(*k, sim.kin_off_grid(*t, p.piece));
                assert_eq!(table.get(*t, p.piece), Some(k));
                let off = t + 1e-7;
                if !p.times.contains(&off) {
                    assert!(table.get(off, p.piece).is_none());
                }
                count += 1;
            }
        }
        assert_eq!(
            count,
            table.pieces.iter().map(|p| p.times.len()).sum::<usize>()
        );
        assert!(table.get(0.0, 12.345).is_none());
    }

    /// The step nodes of every piece the integrator walks (square-wave
    /// breakpoints splitting the spans) are the kinematics at the instants
    /// its whole steps use — s, s + h/2, s + h with h = e − s — bit for bit,
    /// and answer only for that step's start and size.
    #[test]
    fn step_nodes_are_the_whole_steps_instants() {
        let motion = screw(Waveform::Square { accel: 150.0 }, fourier());
        let sim = simulator(&motion, 16);
        let phases = 7;
        let table = KinematicsTable::phases(&sim, phases);
        let nominal = 0.03 / 16.0;
        let mut steps = 0;
        for j in 0..phases {
            let t0 = 0.03 * j as f64 / phases as f64;
            let edges = crate::dynamics::piece_edges(t0, t0 + 0.03, 0.03, &motion.breakpoints());
            for w in edges.windows(2) {
                let (a, b) = (w[0], w[1]);
                let n = crate::dynamics::step_count(a, b, nominal);
                let piece = 0.5 * (a + b);
                let nodes = table.piece(a, b, n, piece).expect("a tabulated piece");
                assert!(table.piece(a, b, n + 1, piece).is_none());
                let mut s = a;
                for i in 1..=n {
                    let e = crate::dynamics::step_end(a, b, n, i);
                    let h = e - s;
                    let g = nodes.step(i);
                    let direct = |t: f64| sim.kin_off_grid(t, piece);
                    assert_eq!(*g.at_start(s).expect("the step's start"), direct(s));
                    let [km, k1] = g.stages(s, h, e).expect("the whole step");
                    assert_eq!(*km, direct(s + 0.5 * h));
                    assert_eq!(*k1, direct(s + h));
                    assert!(g.stages(s, 0.5 * h, e).is_none());
                    assert!(g.stages(s + 1e-9, e - s - 1e-9, e).is_none());
                    assert!(g.at_start(s + 0.5 * h).is_none());
                    s = e;
                    steps += 1;
                }
            }
        }
        assert!(steps > 16 * phases, "{steps} steps");
    }

    /// On a 1-D slip (the LineSink: rotation about a horizontal axis moves
    /// every point along x) the fixed steps find their instants in the
    /// table's step nodes — without lookups — and the table leaves the
    /// trajectory bitwise unchanged.
    #[test]
    fn fixed_step_path_hits_and_is_bitwise_unchanged() {
        let motion = Motion::Screw(Screw {
            axis: [0.0, 1.0, 0.0],
            point: [0.0, 0.0, -0.05],
            period: 0.03,
            rotation: Waveform::RestToRest { amplitude: 0.004 },
            translation: Waveform::Zero,
        });
        let sim = simulator(&motion, 32);
        let phases = 5;
        let table = KinematicsTable::phases(&sim, phases);
        // A motion with a slip axis is tabulated and evaluated with libm's
        // sin and cos: its 1-D fields keep their bits.
        for p in &table.pieces {
            for (t, k) in p.times.iter().zip(&p.kinematics) {
                assert_eq!(*k, motion.kinematics_piece(*t, p.piece, 9.81, true));
                assert_eq!(sim.kin_off_grid(t + 1e-7, p.piece), {
                    motion.kinematics_piece(t + 1e-7, p.piece, 9.81, true)
                });
            }
        }
        let fast = sim.clone().with_table(&table);
        let mut events = 0;
        for j in 0..phases {
            let t0 = 0.03 * j as f64 / phases as f64;
            let r = V2::new(0.03, 0.01);
            let k = motion.kinematics(t0, 9.81, true);
            let v = k.velocity_at(&crate::motion::V3::new(r.x, r.y, 0.0));
            let start = PartState::new(r, -V2::new(v.x, v.y));
            let (mut a, mut b) = (start, start);
            let oa = sim.advance(t0, t0 + 0.03, &mut a, &r, None).unwrap();
            let ob = fast.advance(t0, t0 + 0.03, &mut b, &r, None).unwrap();
            assert_eq!(a, b);
            assert_eq!(oa, ob);
            events += oa.events;
        }
        let (hits, misses) = table.lookups();
        println!("{events} events, {hits} hits, {misses} misses");
        assert!(events > 0, "the part sticks and slips");
        // Few lookups (the test prints their count), far fewer than steps. The
        // fixed steps take their kinematics from the step nodes
        // (`StepNodes`) without a lookup, event location evaluates directly
        // (`Simulator::kin_off_grid`): lookups are left for stuck parts'
        // margins and the instants just after events. Step nodes that
        // drifted from the integrator's arithmetic would send every fixed
        // step to a lookup (two or three each), a table that drifted too
        // would make them miss.
        let steps = 32 * phases;
        assert!(hits + misses < steps / 4, "{hits} hits, {misses} misses");
        assert!(misses <= 4 * events as usize, "{misses} misses");
    }
}
