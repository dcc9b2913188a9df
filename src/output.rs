//! Writing result files atomically (a temporary file in the same folder,
//! then a rename; see [`replace_atomic`]), so that an interrupted
//! run never leaves a half-written file behind; a folder of several
//! results is written whole (`Staged`).

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::error::{Error, Result};

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// Writes `contents` to `path` atomically: the data goes to a temporary file
/// in the same directory, is flushed to disk, and is then renamed over
/// `path`, so readers see either the old or the complete new file.
pub fn replace_atomic(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let file_name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    let tmp = dir.join(format!(
        ".{}.tmp.{}.{}",
        file_name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    ));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(contents)?;
        f.sync_all()?;
        drop(f);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

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
    replace_atomic(path, bytes).map_err(io)
}

/// Writes several files all or none: each goes to a temporary file beside
/// it first, and only when every one of them is written are they renamed
/// into place (a failure removes the temporary files and leaves every
/// destination as it was). Errors name the path.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<()> {
    let mut temps = Vec::new();
    let staged = files.iter().try_for_each(|(path, bytes)| {
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        let tmp = path.with_file_name(format!(".{name}.all.{}", std::process::id()));
        temps.push(tmp.clone());
        write_atomic(&tmp, bytes)
    });
    let placed = staged.and_then(|()| {
        files.iter().zip(&temps).try_for_each(|((path, _), tmp)| {
            std::fs::rename(tmp, path).map_err(|source| Error::Io {
                path: path.display().to_string(),
                source,
            })
        })
    });
    if placed.is_err() {
        for tmp in &temps {
            let _ = std::fs::remove_file(tmp);
        }
    }
    placed
}

/// Makes the writability probe names unique between threads.
static PROBE_COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

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
    // Unique per process and per call: threads of one process (the tests,
    // a library user's parallel designs) probe the same folder at once.
    let n = PROBE_COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let probe = probe_dir.join(format!(".platefield-probe-{}-{n}", std::process::id()));
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

/// The part of a staging folder's name after the folder's own name
/// (`.sink.platefield-stage-<pid>-<n>` beside `sink`). Entries named so are
/// never carried over from one run to the next.
const STAGE_MARK: &str = ".platefield-stage-";

static STAGE_COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);

/// A result folder written as a whole: the run writes its files into a
/// fresh staging folder beside `dir` ([`Staged::path`]), and
/// [`Staged::commit`] swaps it with `dir` in one atomic exchange
/// (`renameat2(RENAME_EXCHANGE)`), so that a reader of `dir` sees either the
/// whole previous run or the whole new one, never a mix — whether runs
/// write the folder concurrently or a run is interrupted (SIGINT, SIGKILL)
/// at any point.
///
/// What is kept: after the swap, every entry of the previous folder that
/// is not one of the run's `products` (the files a run of this command may
/// write) — a `verify/` subfolder, the user's own files — is moved into the
/// new folder (unless the new folder already has that name); the previous
/// run's products are dropped, so the folder holds one run's products. The
/// kept entries are briefly absent from `dir` between the swap and their
/// move. An interrupted run leaves at most a hidden
/// `.NAME.platefield-stage-PID-N` folder beside `dir`: before the swap it
/// holds the unfinished run, after it the previous folder (with any kept
/// entries not yet moved back). A staging folder that is never committed
/// is removed when the [`Staged`] is dropped (an error return).
#[derive(Debug)]
pub struct Staged {
    dir: PathBuf,
    stage: PathBuf,
    committed: bool,
}

impl Staged {
    /// Creates the staging folder of `dir` (and `dir`'s parent folders).
    pub fn new(dir: &Path) -> Result<Staged> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| Error::Io { path, source }
        };
        let name = dir.file_name().ok_or_else(|| {
            Error::invalid("--out", format!("{}: not a folder name", dir.display()))
        })?;
        let parent = match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(io(&parent))?;
        let stage = parent.join(format!(
            ".{}{STAGE_MARK}{}-{}",
            name.to_string_lossy(),
            std::process::id(),
            STAGE_COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
        ));
        std::fs::create_dir(&stage).map_err(io(&stage))?;
        Ok(Staged {
            dir: dir.to_path_buf(),
            stage,
            committed: false,
        })
    }

    /// The staging folder: write the run's files here.
    pub fn path(&self) -> &Path {
        &self.stage
    }

    /// Puts the staged run in place of `dir` (see [`Staged`]): one atomic
    /// exchange, then the previous folder's entries that are not among
    /// `products` are moved into the new one and the rest is removed.
    pub fn commit(mut self, products: &[&str]) -> Result<()> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| Error::Io { path, source }
        };
        let had_previous = swap_in(&self.stage, &self.dir).map_err(io(&self.dir))?;
        self.committed = true;
        if had_previous {
            // `self.stage` now holds the previous folder.
            carry_over(&self.stage, &self.dir, products).map_err(io(&self.stage))?;
        }
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}

/// Puts folder `new` at `dir`: exchanged with the folder there (returns
/// true: the previous folder is now at `new`), or renamed into place when
/// there is none (false). Retries when another run creates or removes
/// `dir` in between.
fn swap_in(new: &Path, dir: &Path) -> std::io::Result<bool> {
    let mut tries = 0;
    loop {
        tries += 1;
        match exchange(new, dir) {
            Ok(()) => return Ok(true),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound && tries < 10 => {}
            Err(e) => return Err(e),
        }
        match std::fs::rename(new, dir) {
            Ok(()) => return Ok(false),
            // `dir` appeared meanwhile (a non-empty folder): exchange again.
            Err(_) if dir.exists() && tries < 10 => {}
            Err(e) => return Err(e),
        }
    }
}

/// Atomically exchanges the entries at `a` and `b` (both must exist).
#[cfg(target_os = "linux")]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    use std::os::unix::ffi::OsStrExt;
    let c = |p: &Path| {
        std::ffi::CString::new(p.as_os_str().as_bytes())
            .map_err(|e| std::io::Error::new(std::io::ErrorKind::InvalidInput, e))
    };
    let (a, b) = (c(a)?, c(b)?);
    // SAFETY: both are valid NUL-terminated paths that live across the
    // call; renameat2 does not keep them.
    let rc = unsafe {
        libc::renameat2(
            libc::AT_FDCWD,
            a.as_ptr(),
            libc::AT_FDCWD,
            b.as_ptr(),
            libc::RENAME_EXCHANGE,
        )
    };
    if rc == 0 {
        Ok(())
    } else {
        Err(std::io::Error::last_os_error())
    }
}

/// Elsewhere there is no atomic exchange: the previous folder is renamed
/// aside, then the new one into place (a reader may find `b` missing in
/// between, never mixed).
#[cfg(not(target_os = "linux"))]
fn exchange(a: &Path, b: &Path) -> std::io::Result<()> {
    let aside = a.with_extension("previous");
    std::fs::rename(b, &aside)?;
    std::fs::rename(a, b)?;
    std::fs::rename(&aside, a)
}

/// Moves the entries of the previous folder `old` that are not `products`
/// (nor staging folders) into `dir` unless `dir` has that name already,
/// then removes `old` with whatever is left. Rescans if an entry appears in
/// `old` meanwhile (a concurrent run moving its kept entries into what was
/// `dir`), so nothing kept is lost.
fn carry_over(old: &Path, dir: &Path, products: &[&str]) -> std::io::Result<()> {
    for _ in 0..5 {
        for entry in std::fs::read_dir(old)? {
            let name = entry?.file_name();
            let kept = name
                .to_str()
                .is_none_or(|n| !products.contains(&n) && !n.contains(STAGE_MARK));
            let (path, target) = (old.join(&name), dir.join(&name));
            if kept && target.symlink_metadata().is_err() {
                std::fs::rename(&path, &target)?;
                continue;
            }
            if path.symlink_metadata()?.is_dir() {
                std::fs::remove_dir_all(&path)?;
            } else {
                std::fs::remove_file(&path)?;
            }
        }
        if std::fs::remove_dir(old).is_ok() {
            return Ok(());
        }
    }
    std::fs::remove_dir_all(old)
}
