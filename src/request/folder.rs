//! The folder a target's results are written to.

use std::path::Path;

use super::Target;
use crate::error::{Error, Result};

/// Longest folder name (bytes): what leaves room, within the file
/// system's 255 bytes per name, for the staging folder written beside it
/// ([`crate::output::MAX_FOLDER_NAME_BYTES`]).
pub(crate) const MAX_NAME_BYTES: usize = crate::output::MAX_FOLDER_NAME_BYTES;

impl Target {
    /// The name of the folder for this target's results: its `name`, or the
    /// stem of the file it was loaded from (`path`) when the name is blank.
    /// It must be a plain folder name (no `/`, `\`, NUL, no leading `.`,
    /// at most `MAX_NAME_BYTES` bytes), checked before any work.
    pub fn folder_name(&self, path: &Path) -> Result<String> {
        let name = if self.name.trim().is_empty() {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "target".into())
        } else {
            self.name.clone()
        };
        plain_folder_name(&name, "target.name")?;
        Ok(name)
    }
}

/// Checks that `name` (from `field`) is a plain folder name: not blank, no
/// `/`, `\` or NUL, no leading `.`, at most [`MAX_NAME_BYTES`] bytes. Used
/// for a target's name and for a schedule's `target` alike.
pub(crate) fn plain_folder_name(name: &str, field: &str) -> Result<()> {
    if name.trim().is_empty()
        || name.contains(['/', '\\', '\0'])
        || name.starts_with('.')
        || name.len() > MAX_NAME_BYTES
    {
        return Err(Error::invalid(
            field,
            format!(
                "must be a plain folder name (at most {MAX_NAME_BYTES} bytes, which leaves room for its staging folder within the file system's 255 per name; no /, \\ or NUL, not starting with .), got \"{}\" ({} bytes)",
                crate::input::short(name).escape_debug(),
                name.len()
            ),
        ));
    }
    Ok(())
}
