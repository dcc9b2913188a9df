//! Basis fields: the primitive library simulated into fields, fitted to the
//! paper's Table I, reused by symmetry ([`symmetry`]), cached on disk
//! ([`cache`]), with the cheapest adequate model chosen per scene
//! ([`rung`]) and its speed against error measured ([`speed`]).

pub mod cache;
pub mod library;
pub mod primitives;
pub mod report;
pub mod rung;
pub mod speed;
pub mod symmetry;
pub mod table1;

pub use cache::{BasisCache, CacheStatus};
pub use library::{FieldEntry, FieldLibrary, Library, LibraryEntry};
pub use primitives::{Primitive, PrimitiveKind};
