//! The plate points that a motion moves alike: its own symmetry.
//!
//! A part's dynamics at plate point r depend on the motion only through the
//! kinematics at r ([`super::Kinematics`]): v_s(r) = v_c + Ω × (r − c),
//! a_s(r) = a_c + Ω' × (r − c) + Ω × (Ω × (r − c)), the tilted gravity g_S
//! (the same at every point) and the Coriolis term 2 Ω × u. Three kinds of
//! motion move whole families of points alike, at every instant and under
//! every model switch (centripetal, tilt, Coriolis, moving):
//!
//! * **Uniform** — no rotation (Ω ≡ 0, R ≡ I): every point moves with the
//!   centre, v_s(r) = v_c, a_s(r) = a_c, g_S = (0, 0, −g). A field is the
//!   same vector everywhere.
//! * **Along e** — rotation about a *horizontal* axis k and translation
//!   along it (a screw about a horizontal axis): for s real,
//!   k × (r + s k − c) = k × (r − c) and Ω × (Ω × s k) = 0, so the points
//!   r + s k see exactly the kinematics of r, and a part started at r + s k
//!   follows the trajectory of one started at r shifted by s k (the moving
//!   model included: the shifted trajectory solves the same equations). A
//!   field is constant along e = k.
//! * **About c** — rotation about a *vertical* axis through c and
//!   translation along it: a rotation Q(θ) of the plane about c commutes
//!   with Ω = ψ' ẑ, so Q maps the kinematics at r to those at
//!   c + Q(r − c) and a trajectory to a trajectory. A field at
//!   c + Q(r − c) is Q times the field at r.
//!
//! Six-signal motions ([`super::Signals`]) fall in the same classes when
//! one angular signal alone is driven: about x or y (Ω, Ω' and the rotation
//! stay about that plate axis, whatever the linear signals: lines along
//! it), or about z with no horizontal translation (circles about the
//! centre).
//!
//! [`crate::field`] simulates one point per family and maps its sample to
//! the others; the mapped samples agree with direct simulation to the
//! integrator's round-off sensitivity (tested in `tests/unit/invariance.rs`).

/// Families of plate points that see the same motion (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Invariance {
    /// No family known: every point is simulated.
    None,
    /// Every point moves alike (pure translation).
    Uniform,
    /// Points on each line along this in-plane unit direction move alike
    /// (a screw about a horizontal axis).
    Along([f64; 2]),
    /// Points on each circle about this plate point move alike, their
    /// motion turned with them (a screw about a vertical axis).
    About([f64; 2]),
}

impl std::fmt::Display for Invariance {
    /// In words, for summaries: which points move alike.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Invariance::None => f.write_str("no two points known to move alike"),
            Invariance::Uniform => f.write_str("a translation: every point moves alike"),
            Invariance::Along(e) => write!(
                f,
                "a horizontal axis: the points of each line along ({:.4}, {:.4}) move alike",
                e[0], e[1]
            ),
            Invariance::About(c) => write!(
                f,
                "a vertical axis: the points of each circle about ({}, {}) m move alike",
                c[0], c[1]
            ),
        }
    }
}

#[cfg(test)]
#[path = "../../tests/unit/invariance.rs"]
mod invariance_tests;
