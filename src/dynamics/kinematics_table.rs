//! Time-only plate kinematics computed once per field.
//!
//! The plate's angular velocity and acceleration, the reference point's
//! velocity and acceleration and gravity in the plate frame
//! ([`Kinematics`]) depend on time only. A field integrates hundreds of
//! grid points (and, for force fields, every start phase) over the same
//! time spans with the same fixed RK4 steps, so each point evaluated the
//! same waveforms (and their `sin_cos`) at the same instants — about half
//! of a field's CPU time before this table (issue 12).
//!
//! [`KinematicsTable`] holds the kinematics at every instant the integrator
//! asks for on its fixed-step path over given spans: for each smooth piece
//! (between acceleration breakpoints) the piece start and, for every step
//! [s, e], the stage times s + h/2 and s + h (h = e − s) and the step end e
//! — computed with exactly the integrator's arithmetic
//! ([`super::step_count`], [`super::step_end`]), so a lookup is keyed by the
//! exact bits of (t, piece). It is a memo of
//! [`Motion::kinematics_piece`]: a hit returns the very value a direct
//! evaluation would, so fields are bitwise unchanged by it (and stay
//! identical on any number of threads). Event-located and shortened steps
//! ask for other instants; they miss and are evaluated directly.

use super::integrator::Simulator;
use crate::motion::{Kinematics, Motion};

/// Kinematics at the nodes of one smooth piece, sorted by time.
#[derive(Debug, Clone)]
struct PieceNodes {
    /// The piece key the integrator passes (0.5 (a + b) of the piece [a, b]).
    piece: f64,
    /// Node times, ascending, distinct.
    times: Vec<f64>,
    /// Kinematics at `times`.
    kinematics: Vec<Kinematics>,
}

/// Plate kinematics tabulated on the integrator's fixed-step time grid of
/// some spans, shared (read-only) by every point of a field.
#[derive(Debug)]
pub struct KinematicsTable<'a> {
    motion: &'a Motion,
    gravity: f64,
    tilt: bool,
    /// Pieces sorted by `piece` (distinct).
    pieces: Vec<PieceNodes>,
    #[cfg(test)]
    misses: std::sync::atomic::AtomicUsize,
    #[cfg(test)]
    hits: std::sync::atomic::AtomicUsize,
}

impl<'a> KinematicsTable<'a> {
    /// The kinematics `sim` asks for when it advances over each span
    /// `[t0, t1]` in `spans` on its fixed-step path.
    pub fn new(sim: &Simulator<'a>, spans: &[(f64, f64)]) -> KinematicsTable<'a> {
        let motion = sim.motion();
        let (gravity, tilt) = (sim.gravity(), sim.model().tilt);
        let period = sim.period();
        let nominal = period / sim.numerics().steps_per_cycle as f64;
        let breakpoints = motion.breakpoints();
        let mut nodes: Vec<(f64, f64)> = Vec::new();
        for &(t0, t1) in spans {
            let edges = super::piece_edges(t0, t1, period, &breakpoints);
            for w in edges.windows(2) {
                let (a, b) = (w[0], w[1]);
                let piece = 0.5 * (a + b);
                let n = super::step_count(a, b, nominal);
                let mut s = a;
                nodes.push((piece, a));
                for i in 1..=n {
                    let e = super::step_end(a, b, n, i);
                    let h = e - s;
                    nodes.push((piece, s + 0.5 * h));
                    nodes.push((piece, s + h));
                    nodes.push((piece, e));
                    s = e;
                }
            }
        }
        nodes.sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
        nodes.dedup_by(|x, y| x.0.to_bits() == y.0.to_bits() && x.1.to_bits() == y.1.to_bits());
        let mut pieces: Vec<PieceNodes> = Vec::new();
        for (piece, t) in nodes {
            let k = motion.kinematics_piece(t, piece, gravity, tilt);
            match pieces.last_mut() {
                Some(p) if p.piece.to_bits() == piece.to_bits() => {
                    p.times.push(t);
                    p.kinematics.push(k);
                }
                _ => pieces.push(PieceNodes {
                    piece,
                    times: vec![t],
                    kinematics: vec![k],
                }),
            }
        }
        KinematicsTable {
            motion,
            gravity,
            tilt,
            pieces,
            #[cfg(test)]
            misses: std::sync::atomic::AtomicUsize::new(0),
            #[cfg(test)]
            hits: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// The table for one cycle [0, T] (steady-state velocity fields).
    pub fn cycle(sim: &Simulator<'a>) -> KinematicsTable<'a> {
        KinematicsTable::new(sim, &[(0.0, sim.period())])
    }

    /// The table for `phases` cycles starting at T j / `phases`, j = 0 …
    /// `phases` − 1 (zero-velocity force fields).
    pub fn phases(sim: &Simulator<'a>, phases: usize) -> KinematicsTable<'a> {
        let period = sim.period();
        let spans: Vec<(f64, f64)> = (0..phases)
            .map(|j| {
                let t0 = period * j as f64 / phases as f64;
                (t0, t0 + period)
            })
            .collect();
        KinematicsTable::new(sim, &spans)
    }

    /// Number of tabulated instants.
    pub fn len(&self) -> usize {
        self.pieces.iter().map(|p| p.times.len()).sum()
    }

    /// True when nothing is tabulated.
    pub fn is_empty(&self) -> bool {
        self.pieces.is_empty()
    }

    /// True when this table holds `motion`'s kinematics under gravity `g`
    /// and the tilt switch `tilt`.
    pub fn fits(&self, motion: &Motion, gravity: f64, tilt: bool) -> bool {
        (std::ptr::eq(self.motion, motion) || self.motion == motion)
            && self.gravity.to_bits() == gravity.to_bits()
            && self.tilt == tilt
    }

    /// The kinematics at exactly `t` on the piece keyed `piece`, when
    /// tabulated.
    #[inline]
    pub fn get(&self, t: f64, piece: f64) -> Option<&Kinematics> {
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
        let i = self
            .pieces
            .binary_search_by(|p| p.piece.total_cmp(&piece))
            .ok()?;
        let p = &self.pieces[i];
        let j = p.times.binary_search_by(|x| x.total_cmp(&t)).ok()?;
        Some(&p.kinematics[j])
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
    use crate::dynamics::{Friction, Model, Numerics, PartState, V2};
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

    /// Every tabulated value is the direct evaluation, bit for bit, and
    /// instants off the grid miss.
    #[test]
    fn table_is_a_memo_of_direct_evaluation() {
        let motion = screw(Waveform::Square { accel: 150.0 }, fourier());
        let sim = Simulator::new(
            &motion,
            Friction::uniform(0.3),
            9.81,
            Model::FULL,
            Numerics {
                steps_per_cycle: 16,
                ..Numerics::default()
            },
        );
        let table = KinematicsTable::phases(&sim, 7);
        assert!(table.fits(&motion, 9.81, true));
        assert!(!table.fits(&motion, 9.8, true));
        assert!(!table.fits(&motion, 9.81, false));
        // Square-wave breakpoints split most spans into three pieces.
        assert!(table.pieces.len() > 7, "{}", table.pieces.len());
        let mut count = 0;
        for p in &table.pieces {
            for (t, k) in p.times.iter().zip(&p.kinematics) {
                assert_eq!(*k, motion.kinematics_piece(*t, p.piece, 9.81, true));
                assert_eq!(table.get(*t, p.piece), Some(k));
                let off = t + 1e-7;
                if p.times.binary_search_by(|x| x.total_cmp(&off)).is_err() {
                    assert!(table.get(off, p.piece).is_none());
                }
                count += 1;
            }
        }
        assert_eq!(count, table.len());
        assert!(table.get(0.0, 12.345).is_none());
    }

    /// On a 1-D slip (the LineSink: rotation about a horizontal axis moves
    /// every point along x) the fixed steps find their instants in the
    /// table — only locating the few events misses — and the table leaves
    /// the trajectory bitwise unchanged.
    #[test]
    fn fixed_step_path_hits_and_is_bitwise_unchanged() {
        let motion = Motion::Screw(Screw {
            axis: [0.0, 1.0, 0.0],
            point: [0.0, 0.0, -0.05],
            period: 0.03,
            rotation: Waveform::RestToRest { amplitude: 0.004 },
            translation: Waveform::Zero,
        });
        let sim = Simulator::new(
            &motion,
            Friction::uniform(0.3),
            9.81,
            Model::FULL,
            Numerics {
                steps_per_cycle: 32,
                ..Numerics::default()
            },
        );
        let phases = 5;
        let table = KinematicsTable::phases(&sim, phases);
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
        // Measured: 10 events, 491 hits, 132 misses (about 13 direct
        // evaluations to locate each event). A grid that drifted from the
        // integrator's arithmetic would leave only the piece starts.
        assert!(hits >= 3 * misses, "{hits} hits, {misses} misses");
        assert!(misses <= 20 * events as usize, "{misses} misses");
    }
}
