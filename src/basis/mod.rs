//! Basis fields: the primitive library simulated into fields, fitted to the
//! paper's Table I, reused by symmetry.

pub mod primitives;
pub mod table1;

pub use primitives::{Primitive, PrimitiveKind};
