//! Screw primitive {k, h, ψ(t), d(t)}: rotation ψ about the unit axis k
//! through the point h (W coordinates; h_z < 0 is below the plate surface)
//! and translation d along k:
//!
//! ```text
//! R(t) = exp(ψ(t) [k]×),   p(t) = (I − R(t)) h + d(t) k
//! ```
//!
//! Because Rᵀk = k, the plate-frame expressions are exact for any ψ:
//! Ω = ψ' k, Ω' = ψ'' k, c = h, v_c = d' k, a_c = d'' k, so that
//! a_s(r) = ψ'' k × (r − h) + ψ'² k × (k × (r − h)) + d'' k.

use serde::{Deserialize, Serialize};

use super::{rotate, Invariance, Kinematics, Waveform, V3};
use crate::error::{positive, Error, Result};

/// A screw motion about a fixed axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Screw {
    /// Axis direction k (normalised on use).
    pub axis: [f64; 3],
    /// A point h on the axis (m, world frame).
    pub point: [f64; 3],
    /// Period T (s).
    pub period: f64,
    /// Rotation ψ(t) about the axis (rad).
    #[serde(default)]
    pub rotation: Waveform,
    /// Translation d(t) along the axis (m).
    #[serde(default)]
    pub translation: Waveform,
}

impl Screw {
    fn k(&self) -> V3 {
        V3::from(self.axis).normalize()
    }

    /// Kinematics at time `t` on the waveform piece containing `piece_t`
    /// (see the module docs).
    #[inline]
    pub(crate) fn kinematics(&self, t: f64, piece_t: f64, g: f64, tilt: bool) -> Kinematics {
        let k = self.k();
        let psi = self.rotation.eval_piece(t, self.period, piece_t);
        let d = self.translation.eval_piece(t, self.period, piece_t);
        let down = V3::new(0.0, 0.0, -g);
        Kinematics {
            omega: k * psi.dq,
            alpha: k * psi.ddq,
            center: V3::from(self.point),
            vel_center: k * d.dq,
            accel_center: k * d.ddq,
            gravity: if tilt {
                rotate(&down, &k, -psi.q)
            } else {
                down
            },
        }
    }

    /// Acceleration breakpoints in [0, T).
    pub(crate) fn breakpoints(&self) -> Vec<f64> {
        let mut b = self.rotation.breakpoints(self.period);
        b.extend(self.translation.breakpoints(self.period));
        b
    }

    /// True when rotation is about the vertical only and translation is horizontal.
    pub(crate) fn is_in_plane(&self) -> bool {
        let k = self.k();
        let vertical = k.x == 0.0 && k.y == 0.0;
        (self.rotation.is_zero() || vertical) && (self.translation.is_zero() || k.z == 0.0)
    }

    /// The plate axis (0 = x, 1 = y) of a screw that rotates about the
    /// other in-plane axis and translates along this one only (either may
    /// be zero): the LineSink, LineSource and Trans. See
    /// [`Motion::slip_axis`](super::Motion::slip_axis).
    pub(crate) fn slip_axis(&self) -> Option<usize> {
        let k = self.k();
        let turns = !self.rotation.is_zero();
        let moves = !self.translation.is_zero();
        (0..2).find(|&i| {
            let j = 1 - i;
            (!turns || (k[i] == 0.0 && k.z == 0.0)) && (!moves || (k[j] == 0.0 && k.z == 0.0))
        })
    }

    /// The points this screw moves alike ([`Invariance`]): all of them
    /// without rotation, lines along a horizontal axis, circles about a
    /// vertical one (exact zero components: a rotated copy of an axis in or
    /// normal to the plane keeps them zero).
    pub(crate) fn invariance(&self) -> Invariance {
        let k = self.k();
        if self.rotation.is_zero() {
            Invariance::Uniform
        } else if k.z == 0.0 {
            Invariance::Along([k.x, k.y])
        } else if k.x == 0.0 && k.y == 0.0 {
            Invariance::About([self.point[0], self.point[1]])
        } else {
            Invariance::None
        }
    }

    /// Validates parameters.
    pub(crate) fn validate(&self, field: &str) -> Result<()> {
        positive(&format!("{field}.period"), self.period)?;
        for (name, v) in [("axis", self.axis), ("point", self.point)] {
            if v.iter().any(|x| !x.is_finite()) {
                return Err(Error::invalid(
                    format!("{field}.{name}"),
                    format!("must be three finite numbers, got {v:?}"),
                ));
            }
        }
        if V3::from(self.axis).norm() == 0.0 {
            return Err(Error::invalid(
                format!("{field}.axis"),
                "must be a non-zero vector",
            ));
        }
        self.rotation.validate(&format!("{field}.rotation"))?;
        self.translation.validate(&format!("{field}.translation"))
    }

    /// The same screw rotated about the world vertical by `angle` (rad),
    /// then shifted horizontally by `shift` (m).
    pub(crate) fn transformed(&self, angle: f64, shift: [f64; 2]) -> Screw {
        let z = V3::z();
        let k = rotate(&V3::from(self.axis), &z, angle);
        let h = rotate(&V3::from(self.point), &z, angle) + V3::new(shift[0], shift[1], 0.0);
        Screw {
            axis: [k.x, k.y, k.z],
            point: [h.x, h.y, h.z],
            ..self.clone()
        }
    }
}
