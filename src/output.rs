//! Writing result files atomically (a temporary file in the same folder,
//! then a rename; see [`crate::plot::write_atomic`]), so that an interrupted
//! run never leaves a half-written file behind.

use std::path::Path;

use crate::error::{Error, Result};

/// Writes `bytes` to `path` atomically, creating parent folders; errors
/// name the path.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |e: std::io::Error| Error::Io {
        path: path.display().to_string(),
        source: e,
    };
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
    }
    crate::plot::write_atomic(path, bytes).map_err(io)
}
