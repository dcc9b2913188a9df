//! A spin about the vertical added to the synthesized sink: a point field
//! nonlinear at the part's scale, for parts without a 180° symmetry.
//!
//! **Why.** In any affine point field (and any time share of affine
//! fields) a part's flow on (x, y, θ) is the same at θ and θ + 180° (the
//! torque about the centre of mass depends on the second moments only), so
//! a part without a 180° symmetry keeps two stable poses 180° apart. A
//! unique pose needs a field nonlinear over the part (2–3 cm).
//!
//! **How.** The plate's in-plane velocity at p is v₀(t) + ω(t) ẑ × p. With
//! a translation of velocity amplitude V and a rotation of angular velocity
//! amplitude Ω = α/ω (α the added angular acceleration amplitude) out of
//! phase with it, the slip path at p is an ellipse spanned by V and
//! Ω ẑ × p: the part always slips (unlike a rotation alone, whose stick
//! disc is where the plate's acceleration is below μg), but the mean
//! friction direction turns across the plate on the length scale
//! r* = V/Ω. In the fully sliding regime the drift solves
//! ⟨N(t) (v(t, p) − u)/|v(t, p) − u|⟩ = 0, homogeneous of degree one in
//! (V, Ω ẑ × p, u) jointly but not linear in p, so with r* ≈ 1 cm the
//! averaged field is strongly nonlinear over the part while it moves at
//! the synthesized motion's rates: on the sink's synthesized motion the
//! affine residual over the region is several times larger with a spin of
//! α ≈ 10³ rad/s² than without (`tests/pose_rotation.rs`).
//!
//! **Choice** (`super::screen`): each candidate of [`CANDIDATES`] is
//! added to the centred motion as one more harmonic-1 term of its angular
//! z signal; those whose lifted field gives the part a stable pose in the
//! region (`try_all`) are judged by play on probes from spread starts,
//! since the lifted model misses played attractors of these fields (the
//! bracket's spin of 1200 rad/s² × 0.25 has one lifted pose and a second
//! played one holding about a quarter of the drops, `docs/parts.md`).
//!
//! **Refinement.** When the screen keeps none of [`CANDIDATES`], the same
//! lattice is tried again with every r* = V/Ω shortened by [`REFINE`]
//! ([`Spin::finer`]). The selecting torque comes from the field's
//! nonlinearity over the part, which grows as r* shrinks against the
//! part's size, so a compact or nearly symmetric part (whose third
//! moments, which tell θ from θ + 180°, are small) needs a shorter r*
//! than the parts the lattice was first tried on. A part for which the
//! lattice keeps a spin never pays for the second one. When neither keeps
//! a spin, `design` keeps the elliptic sink alone (two poses 180° apart).

use super::search::distinct_stable;
use super::PoseTarget;
use crate::error::Result;
use crate::field::Grid;
use crate::motion::{FourierTerm, Signals};
use crate::pose::{equilibria, schedule_field, Equilibrium, LiftedField};
use crate::schedule::Schedule;

/// A spin about the vertical: angular acceleration amplitude (rad/s²) and
/// phase (rad) of a harmonic-1 term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spin {
    /// Angular acceleration amplitude about z (rad/s²).
    pub alpha: f64,
    /// Phase of the term (rad), against the motion's own phases.
    pub phase: f64,
    /// Factor on the motion's in-plane (x, y) translation signals: a
    /// smaller translation shortens r* = V/Ω at the same spin.
    pub translation: f64,
}

impl Spin {
    /// Scales `motion`'s in-plane translation by [`Spin::translation`] and
    /// adds the spin as one more harmonic-1 term of its angular z signal.
    ///
    /// ```
    /// use platefield::pose::design::spin::CANDIDATES;
    /// let mut motion = platefield::motion::Signals::example();
    /// CANDIDATES[0].apply(&mut motion);
    /// assert_eq!(motion.angular.z.len(), 1);
    /// ```
    pub fn apply(&self, motion: &mut Signals) {
        for t in motion.linear.x.iter_mut().chain(motion.linear.y.iter_mut()) {
            t.amplitude *= self.translation;
        }
        motion.angular.z.push(FourierTerm {
            amplitude: self.alpha,
            phase: self.phase,
            harmonic: 1,
        });
    }
}

/// The spins tried, in order: the phase fixed at −1.6 rad (on the
/// isotropic sink the phase mostly turns the pattern, and the placement
/// turns it anyway: on the bracket, `tests/pose_rotation.rs`),
/// r* = V/Ω from about 9 mm (1200 rad/s², translation × 0.25) to about
/// 3 times that, where the bracket's played probes
/// all end at one pose (`pose::design::screen`), and one short r* for a
/// small part: 4800 rad/s² with translation × 0.15 (r* ≈ 1.4 mm, angular
/// amplitude α/ω² = 0.11 rad), where nearly all of the triangle's played
/// drops on the centred motion rest at one pose, more than at the spins
/// beside it (`explore_basins`; measured: `docs/parts.md`, **Measurements
/// behind the pose design's choices**).
/// Two more turn a small part faster (its lifted field's slowest rate sets
/// the cycle's spin stage, [`super::cycle::Stages`]): the triangle's spins
/// of 1200 rad/s² turn it too slowly for a stage of
/// [`super::cycle::MAX_STAGE_S`], while 2400 and 4800 rad/s² with
/// translation × 0.3 give it one lifted stable pose turning several times
/// faster (`explore_spin` in `tests/pose_rotation.rs`; each candidate's
/// stages: `results/poses.md`).
/// The placement moves such a spin exactly
/// ([`crate::motion::Signals::transformed`]); moved to first order only,
/// it put none of the triangle's drops at the asked pose.
pub const CANDIDATES: [Spin; 7] = [
    spin(1200.0, 0.25),
    spin(900.0, 0.25),
    spin(1200.0, 0.4),
    spin(1200.0, 0.6),
    spin(4800.0, 0.15),
    spin(2400.0, 0.3),
    spin(4800.0, 0.3),
];

const fn spin(alpha: f64, translation: f64) -> Spin {
    Spin {
        alpha,
        phase: -1.6,
        translation,
    }
}

/// The factor on a candidate's translation when the lattice is tried
/// again (module docs, **Refinement**): r* = V/Ω halved.
pub const REFINE: f64 = 0.5;

impl Spin {
    /// The same spin with r* = V/Ω shortened by [`REFINE`]: its
    /// translation scaled, α and the phase kept.
    ///
    /// ```
    /// use platefield::pose::design::spin::{CANDIDATES, REFINE};
    /// let finer = CANDIDATES[5].finer();
    /// assert_eq!(finer.alpha, CANDIDATES[5].alpha);
    /// assert_eq!(finer.translation, CANDIDATES[5].translation * REFINE);
    /// ```
    pub fn finer(&self) -> Spin {
        Spin {
            translation: self.translation * REFINE,
            ..*self
        }
    }
}

/// A part without a 180° symmetry is designed with a spin (module docs).
pub(crate) fn needs_spin(symmetry: usize) -> bool {
    symmetry % 2 == 1
}

/// `origin`'s one six-signal motion with its in-plane translation scaled
/// and `spin` added to its angular z signal.
///
/// # Errors
/// `origin` is not one six-signal motion.
pub fn spun(origin: &Schedule, spin: Spin) -> Result<Schedule> {
    super::placement::with_motion(origin, "a spin", |m| spin.apply(m))
}

/// A candidate's lifted outcome: its distinct stable poses.
#[derive(Debug, Clone)]
pub(crate) struct Tried {
    /// The spin.
    pub spin: Spin,
    /// The stable poses in the region, one per pose modulo the symmetry.
    pub stable: Vec<Equilibrium>,
}

/// The lifted stable poses of every spin of `lattice` for `req`'s part on
/// `grid`.
///
/// # Errors
/// A spun motion loses contact somewhere on the grid.
pub(crate) fn try_all(
    req: &PoseTarget,
    origin: &Schedule,
    grid: &Grid,
    lattice: &[Spin],
) -> Result<Vec<Tried>> {
    lattice
        .iter()
        .map(|&spin| {
            let field = schedule_field(&spun(origin, spin)?, grid)?;
            let eqs = equilibria(&LiftedField::new(&field, &req.part.body), &req.region);
            Ok(Tried {
                spin,
                stable: distinct_stable(&eqs, req.part.symmetry()),
            })
        })
        .collect()
}
