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

/// Checks, before a long computation, that `dir` can be created and written
/// to (`arg` names the option it came from): its nearest existing ancestor
/// must be a folder in which a file can be made. Probes with a file it
/// removes at once, so nothing is left behind whether it succeeds or not.
pub fn check_writable(dir: &Path, arg: &str) -> Result<()> {
    let refuse = |why: String| Error::invalid(arg, format!("{}: {why}", dir.display()));
    // `symlink_metadata`: a dangling link is there (and no folder), not
    // missing.
    let missing = |p: &Path| p.symlink_metadata().is_err();
    let mut probe_dir = dir;
    while !probe_dir.as_os_str().is_empty() && missing(probe_dir) {
        match probe_dir.parent() {
            Some(p) => probe_dir = p,
            None => break,
        }
    }
    let probe_dir = if probe_dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        probe_dir
    };
    if !probe_dir.is_dir() {
        return Err(refuse(format!(
            "{} is not a folder, so the results cannot be written under it",
            probe_dir.display()
        )));
    }
    let probe = probe_dir.join(format!(".platefield-probe-{}", std::process::id()));
    // `create_new`: never opens (or truncates) a file that is already there.
    std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&probe)
        .map_err(|e| refuse(format!("cannot write in {}: {e}", probe_dir.display())))?;
    std::fs::remove_file(&probe).map_err(|e| {
        refuse(format!(
            "could not remove the probe file {} after writing it: {e}",
            probe.display()
        ))
    })
}

/// `x` as a percentage with `digits` decimals, or `n/a` where it is not
/// finite (a shape error where the strength is not positive).
pub fn percent(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{:.digits$} %", 100.0 * x)
    } else {
        "n/a".into()
    }
}

/// Removes from `dir` the files among `products` that this run did not
/// write (`written`): a folder of results holds one run's files, not a mix
/// with an earlier run's (other files and folders are left alone).
pub fn remove_stale(dir: &Path, products: &[&str], written: &[&str]) -> Result<()> {
    for name in products.iter().filter(|n| !written.contains(n)) {
        let path = dir.join(name);
        if path.is_file() {
            std::fs::remove_file(&path).map_err(|e| Error::Io {
                path: path.display().to_string(),
                source: e,
            })?;
        }
    }
    Ok(())
}
