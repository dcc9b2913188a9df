//! Basis fields: the primitive library simulated into fields, reused by
//! symmetry ([`symmetry`]) and cached on disk (`cache`). The fits to the
//! paper's Table I, the model rungs and the library's speed against error
//! are studies (the `platefield-studies` crate, `studies/`).

pub(crate) mod cache;
pub(crate) mod library;
pub mod primitives;
pub mod steps;
pub mod symmetry;

pub use cache::CacheStatus;
pub use library::{FieldLibrary, Library, LibraryEntry};
pub use primitives::Primitive;
pub use primitives::PrimitiveKind;
pub use steps::StepsPlan;
