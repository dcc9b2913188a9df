//! The folder a target's results are written to.

use std::path::Path;

use super::Target;
use crate::error::{Error, Result};

impl Target {
    /// The name of the folder for this target's results: its `name`, or the
    /// stem of the file it was loaded from (`path`) when the name is blank.
    /// It must be a plain folder name (no `/`, `\`, no leading `.`).
    pub fn folder_name(&self, path: &Path) -> Result<String> {
        let name = if self.name.trim().is_empty() {
            path.file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "target".into())
        } else {
            self.name.clone()
        };
        if name.contains(['/', '\\']) || name.starts_with('.') {
            return Err(Error::invalid(
                "target.name",
                format!("must be a plain folder name, got \"{name}\""),
            ));
        }
        Ok(name)
    }
}
