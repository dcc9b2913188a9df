//! Basis fields: the primitive library simulated into fields, fitted to the
//! paper's Table I, reused by symmetry.

pub mod library;
pub mod primitives;
pub mod report;
pub mod table1;

pub use library::{Library, LibraryEntry};
pub use primitives::{Primitive, PrimitiveKind};
