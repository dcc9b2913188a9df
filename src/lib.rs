//! # platefield
//!
//! Vibration-induced friction force fields on a rigid plate vibrated with up
//! to six degrees of freedom (Vose, Umbanhowar & Lynch; see the README):
//! forward simulation of the fields, and their inversion into schedules of
//! primitive plate motions.
//!
//! The modules follow the data path:
//! [`motion`] (plate kinematics) → [`dynamics`] (point parts with exact
//! stick-slip) → [`linesink`] (the paper's section II analysis).
#![warn(missing_docs)]

pub mod basis;
pub mod design;
pub mod dynamics;
pub mod error;
pub mod field;
pub mod fit;
pub mod linesink;
pub mod motion;
pub mod output;
pub mod plot;
pub mod reproduce;
pub mod scene;
pub mod synth;
pub mod target;
pub mod verify;

pub use error::{Error, Result};
