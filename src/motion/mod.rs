//! Plate motions and their kinematics in the plate frame.
//!
//! World frame W: z up, origin at the plate centre in its home pose. The plate
//! frame S moves with the plate, pose (R(t), p(t)) ∈ SE(3), periodic with
//! period T. For a plate point r = (x, y, 0) in S, the plate's velocity and
//! acceleration are expressed in the inertial frame S' momentarily aligned
//! with S (the paper's eqs. 23–24):
//!
//! ```text
//! v_s(r) = v_c + Ω × (r − c)
//! a_s(r) = a_c + Ω' × (r − c) + Ω × (Ω × (r − c))     (last term: centripetal)
//! g_S    = Rᵀ (0, 0, −g)                                (gravity tilt)
//! ```
//!
//! where c is a reference point fixed in the plate (the screw axis point h,
//! or the plate centre for six-signal motions), v_c and a_c its velocity and
//! acceleration, and Ω, Ω' the angular velocity and acceleration, all in S'.

mod held;
pub mod held_csv;
mod invariance;
mod prepared;
mod ramped;
pub mod rotation;
pub mod sample_hold;
mod screw;
mod signals;
pub(crate) mod trig;
mod waveform;

pub(crate) use held::Held;

/// Largest peak linear acceleration (m/s², about 1000 g) of a plate
/// motion: a scene's translation, a replayed export's sample.
pub const LINEAR_ACCEL: f64 = 1e4;
/// Largest peak angular acceleration (rad/s²) of a plate motion: a
/// scene's rotation, a replayed export's sample.
pub const ANGULAR_ACCEL: f64 = 1e5;
pub use invariance::Invariance;
pub(crate) use prepared::PreparedMotion;
pub(crate) use ramped::smoothstep;
pub use ramped::Ramped;
pub use screw::Screw;
pub use signals::{Axes, Signals};
pub use waveform::FourierTerm;
pub use waveform::Waveform;

use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

use crate::error::Result;

/// 3-vector of f64.
pub type V3 = Vector3<f64>;

/// Plate kinematics at one instant, in the inertial frame S' momentarily
/// aligned with the plate frame S.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Angular velocity Ω.
    pub omega: V3,
    /// Angular acceleration Ω'.
    pub alpha: V3,
    /// Reference point c (plate coordinates).
    pub center: V3,
    /// Velocity of the plate point at c.
    pub vel_center: V3,
    /// Acceleration of the plate point at c.
    pub accel_center: V3,
    /// Gravity g_S in the plate frame.
    pub gravity: V3,
}

impl Kinematics {
    /// Plate velocity v_s(r) at plate point `r`.
    #[inline]
    pub(crate) fn velocity_at(&self, r: &V3) -> V3 {
        self.vel_center + self.omega.cross(&(r - self.center))
    }

    /// Plate acceleration a_s(r) at plate point `r`; the centripetal term
    /// Ω × (Ω × (r − c)) is included only when `centripetal` is set.
    #[inline]
    pub fn acceleration_at(&self, r: &V3, centripetal: bool) -> V3 {
        let d = r - self.center;
        let mut a = self.accel_center + self.alpha.cross(&d);
        if centripetal {
            a += self.omega.cross(&self.omega.cross(&d));
        }
        a
    }
}

/// A periodic rigid-body motion of the plate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Motion {
    /// Screw primitive {k, h, ψ(t), d(t)}.
    Screw(Screw),
    /// General 6-DOF motion given as six plate-centre acceleration signals.
    Signals(Signals),
    /// A six-signal motion ramped in and out over a segment of whole
    /// cycles ([`Ramped`]); built by schedules, never read from a file.
    #[serde(skip)]
    Ramped(Ramped),
    /// Held acceleration samples, as a controller plays an exported file
    /// (`Held`); read from the file, never from a schedule.
    #[serde(skip)]
    Held(Held),
}

impl Motion {
    /// Period T (s).
    pub fn period(&self) -> f64 {
        match self {
            Motion::Screw(s) => s.period,
            Motion::Signals(s) => s.period,
            Motion::Ramped(r) => r.signals.period,
            Motion::Held(h) => h.period(),
        }
    }

    /// Time over which the motion is defined: one period for the periodic
    /// motions, the whole segment for a [`Ramped`] one.
    pub(crate) fn span(&self) -> f64 {
        match self {
            Motion::Ramped(r) => r.span(),
            Motion::Held(h) => h.span(),
            m => m.period(),
        }
    }

    /// Kinematics at time `t`, gravity magnitude `g`. With `tilt` off the
    /// plate's rotation is neglected where it changes directions (small-angle
    /// model): gravity stays (0, 0, −g) in the plate frame.
    #[inline]
    pub fn kinematics(&self, t: f64, g: f64, tilt: bool) -> Kinematics {
        self.kinematics_piece(t, t, g, tilt)
    }

    /// Kinematics at `t` on the smooth piece containing `piece_t` (see
    /// [`Waveform::eval_piece`]).
    #[inline]
    pub(crate) fn kinematics_piece(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        match self {
            Motion::Screw(s) => s.kinematics(t, piece_t, g, tilt),
            Motion::Signals(s) => s.kinematics(t, g, tilt),
            Motion::Ramped(r) => r.kinematics(t, g, tilt),
            Motion::Held(h) => h.kinematics(t, piece_t, g, tilt),
        }
    }

    /// Times in [0, T) where some acceleration jumps.
    pub(crate) fn breakpoints(&self) -> Vec<f64> {
        let mut b = match self {
            Motion::Screw(s) => s.breakpoints(),
            Motion::Held(h) => h.breakpoints(),
            Motion::Signals(_) | Motion::Ramped(_) => Vec::new(),
        };
        b.sort_by(f64::total_cmp);
        b.dedup();
        b
    }

    /// True when the motion is purely in the plate plane (no vertical
    /// translation, rotation only about the vertical): then N = g exactly.
    pub(crate) fn is_in_plane(&self) -> bool {
        match self {
            Motion::Screw(s) => s.is_in_plane(),
            Motion::Signals(s) => s.is_in_plane(),
            Motion::Ramped(r) => r.signals.is_in_plane(),
            Motion::Held(h) => h.is_in_plane(),
        }
    }

    /// The plate axis i (0 = x, 1 = y) along which every point's free
    /// acceleration lies, exactly, for a part slipping along it, at every
    /// instant and under every model switch (centripetal, tilt, Coriolis,
    /// moving); `None` when there is none or it is not known.
    ///
    /// With e the unit vector of axis i and ê the other in-plane one, that
    /// holds when Ω and Ω' are along ê and a_c along e (a screw rotating
    /// about ê and translating along e): at a plate point d = r − c (r in
    /// the plane) the ê components of a_c, Ω' × d, Ω × (Ω × d) and the
    /// Coriolis term 2 Ω × u (u along e) are sums of products each with an
    /// exact zero factor, and a tilted gravity,
    /// rotated about ê, keeps a zero ê component. So a slip starting at
    /// rest or along e stays on the line (its ê component exactly zero) and
    /// the integrator skips its 2-D checks for it (`src/dynamics/integrator.rs`).
    /// Six-signal motions return `None`.
    pub(crate) fn slip_axis(&self) -> Option<usize> {
        match self {
            Motion::Screw(s) => s.slip_axis(),
            Motion::Signals(_) | Motion::Ramped(_) | Motion::Held(_) => None,
        }
    }

    /// The families of plate points this motion moves alike
    /// ([`Invariance`]): a screw about a horizontal or vertical axis, a
    /// six-signal motion turning about one plate axis only, or a motion
    /// without rotation. A ramped segment or held samples return
    /// [`Invariance::None`] (their fields are not sampled).
    pub fn invariance(&self) -> Invariance {
        match self {
            Motion::Screw(s) => s.invariance(),
            Motion::Signals(s) => s.invariance(),
            Motion::Ramped(_) | Motion::Held(_) => Invariance::None,
        }
    }

    /// The same motion with every amplitude multiplied by `k` (what a
    /// shaker that plays a motion at k times its amplitude delivers): a
    /// screw's rotation ψ(t) and translation d(t), a six-signal motion's
    /// accelerations, a ramped one's signals. `k = 1` is the motion itself.
    ///
    /// # Errors
    /// Held samples (an export or recording replayed) are played as
    /// recorded and are not scaled.
    pub(crate) fn amplitude_scaled(&self, k: f64) -> Result<Motion> {
        if k == 1.0 {
            return Ok(self.clone());
        }
        Ok(match self {
            Motion::Screw(s) => Motion::Screw(Screw {
                rotation: s.rotation.scaled(k),
                translation: s.translation.scaled(k),
                ..s.clone()
            }),
            Motion::Signals(s) => Motion::Signals(s.scaled(k)),
            Motion::Ramped(r) => Motion::Ramped(Ramped {
                signals: r.signals.scaled(k),
                ..r.clone()
            }),
            Motion::Held(_) => {
                return Err(crate::Error::invalid(
                    "scale",
                    "held samples (an export or a recording) are played as recorded: their amplitude scale is not estimated",
                ))
            }
        })
    }

    /// Validates all parameters; errors name the field under `field`.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        match self {
            Motion::Screw(s) => s.validate(field),
            Motion::Signals(s) => s.validate(field),
            Motion::Ramped(r) => r.signals.validate(field),
            // Checked when built from the samples (`Held::new`).
            Motion::Held(_) => Ok(()),
        }
    }

    /// The same motion rotated about the world vertical by `angle` (rad)
    /// and shifted horizontally by `shift` (m).
    pub(crate) fn transformed(&self, angle: f64, shift: [f64; 2]) -> Motion {
        match self {
            Motion::Screw(s) => Motion::Screw(s.transformed(angle, shift)),
            Motion::Signals(s) => Motion::Signals(s.transformed(angle, shift)),
            Motion::Ramped(r) => Motion::Ramped(Ramped {
                signals: r.signals.transformed(angle, shift),
                ..r.clone()
            }),
            Motion::Held(h) => Motion::Held(h.transformed(angle, shift)),
        }
    }
}

/// Rotates `v` by angle `theta` about unit axis `k` (Rodrigues).
#[inline]
pub(crate) fn rotate(v: &V3, k: &V3, theta: f64) -> V3 {
    if theta == 0.0 {
        return *v;
    }
    rotate_sc(v, k, theta.sin_cos())
}

/// [`rotate`] with (sin θ, cos θ) at hand.
#[inline]
pub(crate) fn rotate_sc(v: &V3, k: &V3, (s, c): (f64, f64)) -> V3 {
    v * c + k.cross(v) * s + k * (k.dot(v) * (1.0 - c))
}

#[cfg(test)]
mod tests {
    /// A worked example of `motion::Motion::amplitude_scaled`.
    #[test]
    fn example_motion_amplitude_scaled() -> Result<(), crate::Error> {
        use crate::basis::{Primitive, PrimitiveKind};
        let m = Primitive::new(PrimitiveKind::LineSink).motion();
        assert_eq!(m.amplitude_scaled(1.0)?, m);
        assert_ne!(m.amplitude_scaled(0.95)?, m);
        Ok(())
    }
}

#[cfg(test)]
#[path = "../../tests/unit/convention.rs"]
mod convention_tests;
