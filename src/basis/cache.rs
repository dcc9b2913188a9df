//! A content-addressed cache of built primitive libraries.
//!
//! Building a library (8 primitives on a grid, one [`FieldKind`] each)
//! takes seconds to minutes; the result depends only on its inputs, so it
//! is stored under the hash of those inputs and reused. A cached
//! [`FieldLibrary`] holds the fields of one kind only (a design of the
//! default velocity basis neither builds nor needs force fields).
//!
//! * **Key**: hex SHA-256 of a canonical serialization (compact JSON, fields
//!   in declaration order, shortest round-trip floats) of everything that
//!   determines the library: the field kind it holds (`"force"` or
//!   `"velocity"`), the primitives with all their parameters, in
//!   order, and the motions they resolve to (so a change of a primitive's
//!   defaults or waveform is a new key); the grid; the field settings
//!   (friction, gravity, model switches, numerics, phases, frozen-excursion
//!   limit); the crate version (`CARGO_PKG_VERSION`), the simulator's
//!   [`ENGINE_REVISION`](crate::dynamics::ENGINE_REVISION) and the cache
//!   [`FORMAT`]. A change in any of them is a different key. (A change of
//!   the simulator's results without a bump of its revision is not seen:
//!   bump it, or clear the folder.)
//! * **File**: `<dir>/<key>.json`, exactly
//!   `{"format":3,"key":"<key>","payload_sha256":"<hash>","payload":<FieldLibrary>}`
//!   and a newline, written atomically, replacing whatever is at the
//!   entry's path (`crate::output::write_owned`).
//!   `payload_sha256` is the SHA-256 of the payload's bytes as written.
//! * **Load** never trusts a file: it is used only if it parses, has this
//!   format and key, and its payload bytes hash to `payload_sha256`. A
//!   missing file is a miss; a truncated, corrupt, mismatched or foreign
//!   file is rebuilt and overwritten ([`CacheStatus::Rebuilt`] says why).
//!
//! Floats round-trip exactly through serde_json (shortest representation
//! that parses back to the same bits), so a loaded library is bitwise the
//! stored one; [`BasisCache::store`] checks this before writing.

use std::path::PathBuf;

use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use super::library::FieldLibrary;
use super::primitives::Primitive;
use crate::error::{Error, Result};
use crate::field::{FieldKind, FieldSettings, Grid};
use crate::output::write_owned;

/// Version of the cache file layout and key serialization, bumped whenever
/// either changes (each version's change: the workspace's `CHANGELOG.md`).
pub(crate) const FORMAT: u32 = 3;

/// Largest cache entry read: 256 MiB (a library on the default grids takes
/// under 1 MiB). An entry that is larger, or is not a regular file (a FIFO,
/// a link to a device), is not read but rebuilt and overwritten, so it can
/// neither hang a design nor fill memory.
pub(crate) const MAX_ENTRY_BYTES: u64 = 256 << 20;

/// What `BasisCache::get_or_build` did.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum CacheStatus {
    /// Loaded from the cache.
    Hit,
    /// Not in the cache: built and stored.
    Built,
    /// A cache file existed but was not usable: rebuilt and overwritten.
    Rebuilt {
        /// Why the file was not used.
        reason: String,
    },
    /// No cache asked for: built and not stored.
    NoCache,
}

impl std::fmt::Display for CacheStatus {
    /// In words, for the printed summary: "cache hit", "built and cached",
    /// "rebuilt (REASON)", "no cache".
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            CacheStatus::Hit => write!(f, "cache hit"),
            CacheStatus::Built => write!(f, "built and cached"),
            CacheStatus::Rebuilt { reason } => write!(f, "rebuilt ({reason})"),
            CacheStatus::NoCache => write!(f, "no cache"),
        }
    }
}

/// A folder of cached libraries.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct BasisCache {
    dir: PathBuf,
}

/// The canonical key input (serialized in this field order).
#[derive(Serialize)]
struct KeyInput<'a> {
    what: &'static str,
    format: u32,
    version: &'static str,
    /// The simulator's revision (see the module docs).
    engine: u32,
    kind: FieldKind,
    primitives: &'a [Primitive],
    /// The resolved motions: defaults and waveforms are part of the key,
    /// so a change of a primitive's definition invalidates the cache.
    motions: Vec<crate::motion::Motion>,
    grid: &'a Grid,
    settings: &'a FieldSettings,
}

/// The envelope's header, parsed to check it (the payload is skipped here
/// and hashed as bytes).
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Envelope {
    format: u32,
    key: String,
    payload_sha256: String,
    #[allow(dead_code)]
    payload: serde::de::IgnoredAny,
}

/// Why a cache file was not used.
enum Miss {
    /// No file.
    Absent,
    /// A file that cannot be trusted.
    Bad(String),
}

fn sha256_hex(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn is_key(key: &str) -> bool {
    key.len() == 64
        && key
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b))
}

fn header(key: &str, payload_sha256: &str) -> String {
    format!("{{\"format\":{FORMAT},\"key\":\"{key}\",\"payload_sha256\":\"{payload_sha256}\",\"payload\":")
}

const TRAILER: &[u8] = b"}\n";

impl BasisCache {
    /// A cache in `dir` (created when the first library is stored).
    pub fn new(dir: impl Into<PathBuf>) -> BasisCache {
        BasisCache { dir: dir.into() }
    }

    /// The file of `key`.
    pub fn path(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}.json"))
    }

    /// Hex SHA-256 of everything that determines the library of `kind`
    /// fields (see the module docs).
    pub fn key(
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        kind: FieldKind,
    ) -> String {
        let input = KeyInput {
            what: "platefield basis library",
            format: FORMAT,
            version: env!("CARGO_PKG_VERSION"),
            engine: crate::dynamics::ENGINE_REVISION,
            kind,
            primitives,
            motions: primitives.iter().map(Primitive::motion).collect(),
            grid,
            settings,
        };
        // Serializing plain structs of numbers, strings and enums cannot
        // fail; a failure would hash to a key no file has.
        let text = serde_json::to_string(&input).unwrap_or_default();
        sha256_hex(text.as_bytes())
    }

    fn check(&self, key: &str) -> std::result::Result<FieldLibrary, Miss> {
        if !is_key(key) {
            return Err(Miss::Bad(format!("\"{key}\" is not a hex SHA-256 key")));
        }
        let path = self.path(key);
        let bytes = match crate::input::read_capped(&path, MAX_ENTRY_BYTES) {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err(Miss::Absent),
            Err(e) => return Err(Miss::Bad(format!("unreadable: {e}"))),
        };
        let bad = |why: String| Err(Miss::Bad(why));
        let env: Envelope = match serde_json::from_slice(&bytes) {
            Ok(e) => e,
            Err(e) => return bad(format!("truncated or malformed: {e}")),
        };
        if env.format != FORMAT {
            return bad(format!("format {} (expected {FORMAT})", env.format));
        }
        if env.key != key {
            return bad(format!("holds key {} (expected {key})", env.key));
        }
        if !is_key(&env.payload_sha256) {
            return bad("payload_sha256 is not a hex SHA-256".into());
        }
        let head = header(key, &env.payload_sha256);
        if !bytes.starts_with(head.as_bytes()) || !bytes.ends_with(TRAILER) {
            return bad("not in the layout this version writes".into());
        }
        let payload = &bytes[head.len()..bytes.len() - TRAILER.len()];
        let got = sha256_hex(payload);
        if got != env.payload_sha256 {
            return bad(format!(
                "payload hash mismatch (file says {}, payload hashes to {got})",
                env.payload_sha256
            ));
        }
        serde_json::from_slice(payload).or_else(|e| bad(format!("payload does not parse: {e}")))
    }

    /// Checks, before a library is built, that the cache folder can be
    /// created and written (else a read-only folder would fail only when the
    /// built library is stored, after the whole build); the error names the
    /// folder and `--no-cache`, which designs without the cache.
    fn check_writable(&self) -> Result<()> {
        let refuse = |why: String| {
            Error::invalid(
                "basis cache",
                format!(
                    "{}: {why}; the library is not built. Make the folder writable, or run with --no-cache to design without the cache",
                    self.dir.display()
                ),
            )
        };
        std::fs::create_dir_all(&self.dir).map_err(|e| refuse(format!("cannot create it: {e}")))?;
        crate::output::check_writable(&self.dir, "basis cache").map_err(|e| match e {
            Error::Invalid { message, .. } => {
                let dir = format!("{}: ", self.dir.display());
                refuse(message.strip_prefix(&dir).unwrap_or(&message).to_string())
            }
            other => other,
        })
    }

    /// Stores `lib` under `key`, atomically. Fails (and writes nothing) if
    /// the library would not load back bitwise equal (non-finite values).
    pub fn store(&self, key: &str, lib: &FieldLibrary) -> Result<()> {
        let path = self.path(key);
        if !is_key(key) {
            return Err(Error::invalid(
                "key",
                format!("\"{key}\" is not a hex SHA-256 key"),
            ));
        }
        let payload = serde_json::to_vec(lib).map_err(|e| {
            Error::Internal(format!("{}: cannot serialize library: {e}", path.display()))
        })?;
        let back: Option<FieldLibrary> = serde_json::from_slice(&payload).ok();
        if back.as_ref() != Some(lib) {
            return Err(Error::Internal(format!(
                "{}: library does not round-trip through JSON (non-finite values?); not cached",
                path.display()
            )));
        }
        let mut bytes = header(key, &sha256_hex(&payload)).into_bytes();
        bytes.extend_from_slice(&payload);
        bytes.extend_from_slice(TRAILER);
        write_owned(&path, &bytes)
    }

    /// The `kind` fields of `primitives` on `grid` with `settings`: loaded from
    /// the cache when a trustworthy file exists, else built (with a progress
    /// bar as `progress` asks) and stored. Inputs are validated first, and the
    /// cache folder is created before the build so an unwritable cache
    /// fails before the work, not after it. `before_build` (e.g. a work
    /// estimate's check; `|| Ok(())`: none) is called only when the library
    /// must be built, and its error returned without building. Every field
    /// is built at the settings' steps per cycle
    /// ([`StepsPlan::Uniform`](super::StepsPlan): the key holds no other
    /// plan).
    pub fn get_or_build(
        &self,
        primitives: &[Primitive],
        grid: &Grid,
        settings: &FieldSettings,
        kind: FieldKind,
        progress: crate::progress::ProgressMode,
        before_build: impl FnOnce() -> Result<()>,
    ) -> Result<(FieldLibrary, CacheStatus)> {
        grid.validate("grid")?;
        settings.friction.validate("settings.friction")?;
        settings.numerics.validate("settings.numerics")?;
        crate::error::positive("settings.gravity", settings.gravity)?;
        crate::error::non_negative("settings.frozen_excursion", settings.frozen_excursion)?;
        if settings.phases == 0 {
            return Err(Error::invalid("settings.phases", "must be ≥ 1"));
        }
        for (i, p) in primitives.iter().enumerate() {
            p.validate(&format!("primitives[{i}]"))?;
        }
        let key = Self::key(primitives, grid, settings, kind);
        let status = match self.check(&key) {
            Ok(lib) => {
                let same = lib.grid == *grid
                    && lib.settings == *settings
                    && lib.kind == kind
                    && lib.entries.len() == primitives.len()
                    && lib
                        .entries
                        .iter()
                        .zip(primitives)
                        .all(|(e, p)| e.primitive == *p);
                if same {
                    return Ok((lib, CacheStatus::Hit));
                }
                CacheStatus::Rebuilt {
                    reason: "contents do not match the request".into(),
                }
            }
            Err(Miss::Absent) => CacheStatus::Built,
            Err(Miss::Bad(reason)) => CacheStatus::Rebuilt { reason },
        };
        before_build()?;
        self.check_writable()?;
        let lib = FieldLibrary::build(primitives, grid, settings, kind, progress);
        self.store(&key, &lib)?;
        Ok((lib, status))
    }
}

#[cfg(test)]
#[path = "../../tests/unit/basis_cache.rs"]
mod basis_cache_tests;
