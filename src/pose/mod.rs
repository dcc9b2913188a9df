//! Parts with planar extent in a vibration field: the lifted field on the
//! part's configuration space (x, y, θ) ([`LiftedField`]), its equilibrium
//! poses and their stability ([`equilibria`]), and the basins of the stable
//! ones ([`settle`]).

mod check;
mod equilibria;
mod lifted;
mod run;

pub use check::{check_twist, Measure, TwistCheck};
pub use equilibria::{equilibria, settle, wrap, Equilibrium, Region};
pub use lifted::{GridField, LiftedField, PointField, Pose, Twist};
pub use run::{analyse, PoseAnalysis, MAX_DROPS};
