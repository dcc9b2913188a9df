//! Pose analysis: a part with planar extent in a vibration field. The
//! lifted field on the part's configuration space (x, y, θ)
//! ([`LiftedField`]; checked by the [`AveragedField`] of the rigid part's
//! own periodic slip), its equilibrium poses and their stability
//! ([`equilibria`]), the basins of the stable ones predicted ([`settle`])
//! and played by the planar simulator ([`played_basins`]), a designed
//! schedule's point field ([`schedule_field`]), and the poses that may
//! rest for some support when the support is unknown ([`Bounds`]). Its
//! items are re-exported by [`crate::pose`].
//!
//! [`LiftedField`]: crate::pose::LiftedField
//! [`AveragedField`]: crate::pose::AveragedField
//! [`equilibria`]: crate::pose::equilibria
//! [`settle`]: crate::pose::settle
//! [`played_basins`]: crate::pose::played_basins
//! [`schedule_field`]: crate::pose::schedule_field
//! [`Bounds`]: crate::pose::Bounds

pub(super) mod averaged;
pub(super) mod bounds;
pub(super) mod check;
pub(super) mod continua;
pub(super) mod drops;
pub(super) mod equilibria;
pub(super) mod lifted;
pub(super) mod request;
pub(super) mod rests;
pub(super) mod run;
pub(super) mod source;
pub(super) mod work;
