//! Writing result files atomically (a temporary file in the same folder,
//! then a rename; see [`replace_file`]), so that an interrupted run never
//! leaves a half-written file behind; a folder of several results is
//! written whole (`Staged`). Nothing that is not a regular file or a
//! folder this program wrote is ever renamed over or emptied: devices,
//! FIFOs and sockets are written directly or refused, and links are
//! followed, never replaced.

use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use crate::error::{Error, Result};

/// Writes `bytes` to `path` atomically, creating parent folders; errors
/// name the path. What is at `path` decides how ([`replace_file`]).
///
/// ```
/// let dir = std::env::temp_dir().join(format!("pf-doc-write-{}", std::process::id()));
/// let file = dir.join("a/b.txt");
/// platefield::output::write_atomic(&file, b"one")?;
/// assert_eq!(std::fs::read(&file)?, b"one");
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |e: std::io::Error| Error::Io {
        path: path.display().to_string(),
        source: e,
    };
    let _writing = writing();
    if let Some(dir) = path.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).map_err(io)?;
        }
    }
    write_file(path, bytes).map_err(io)
}

/// Held (shared) by every file write while it runs, and taken for good
/// by an interrupt before it removes the staging folders
/// ([`remove_stages_on_interrupt`]): a write under way finishes first, and
/// none starts after, so none re-creates a removed staging folder (the
/// parent folders a write creates).
static WRITES: std::sync::RwLock<()> = std::sync::RwLock::new(());

/// A share of [`WRITES`] for one file write.
fn writing() -> std::sync::RwLockReadGuard<'static, ()> {
    WRITES.read().unwrap_or_else(|e| e.into_inner())
}

/// Writes `bytes` to `path` atomically in a folder this program owns (the
/// basis cache's entries, whose names are its own): whatever is at `path`
/// — a FIFO, a link to a device left there — is replaced by the rename,
/// never written through. Errors name the path.
pub(crate) fn write_owned(path: &Path, bytes: &[u8]) -> Result<()> {
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    let _writing = writing();
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).map_err(io)?;
    }
    rename_into_place(path, bytes).map_err(io)
}

static TEMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// What [`replace_file`] finds at a path.
enum Existing {
    /// Nothing, or a regular file: replaced by a rename.
    Replaceable,
    /// A character or block device, or a FIFO: written in place.
    Special,
}

/// Classifies what is at `path` (after following links) for a write:
/// a folder, a socket, or a link to nothing are refused.
fn existing(path: &Path) -> std::io::Result<Existing> {
    let refuse = |what: &str| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{what}, not a file this program can replace"),
        )
    };
    let meta = match std::fs::metadata(path) {
        Ok(m) => m,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            return if path.symlink_metadata().is_ok() {
                Err(refuse("a link to a missing file"))
            } else {
                Ok(Existing::Replaceable)
            };
        }
        Err(e) => return Err(e),
    };
    let kind = meta.file_type();
    if kind.is_file() {
        Ok(Existing::Replaceable)
    } else if kind.is_dir() {
        Err(refuse("a folder"))
    } else if is_socket(&kind) {
        Err(refuse("a socket"))
    } else {
        Ok(Existing::Special)
    }
}

#[cfg(unix)]
fn is_socket(kind: &std::fs::FileType) -> bool {
    std::os::unix::fs::FileTypeExt::is_socket(kind)
}

#[cfg(not(unix))]
fn is_socket(_: &std::fs::FileType) -> bool {
    false
}

/// Writes `contents` to the file `path`, by what is there:
/// - nothing, or a regular file: the data go to a temporary file in the
///   same folder, are flushed to disk, and the temporary file is renamed
///   over `path`, so readers see either the old or the complete new file;
/// - a link: the same at the file it leads to (the link stays);
/// - a character or block device or a FIFO: written directly, as a shell's
///   `> path` would (a reader of the FIFO gets the data; `/dev/full`
///   fails with "No space left on device"), never replaced;
/// - a folder, a socket or a link to nothing: refused.
///
/// ```
/// let dir = std::env::temp_dir().join(format!("pf-doc-replace-{}", std::process::id()));
/// std::fs::create_dir_all(&dir)?;
/// let file = dir.join("x.txt");
/// platefield::output::replace_file(&file, b"one")?;
/// platefield::output::replace_file(&file, b"two")?;
/// assert_eq!(std::fs::read(&file)?, b"two");
/// let null = std::path::Path::new("/dev/null");
/// platefield::output::replace_file(null, b"written to the device")?;
/// assert!(!null.metadata()?.is_file());
/// assert!(platefield::output::replace_file(&dir, b"x").is_err());
/// std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn replace_file(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let _writing = writing();
    write_file(path, contents)
}

/// [`replace_file`] without taking a share of [`WRITES`].
fn write_file(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    if let Existing::Special = existing(path)? {
        let mut f = std::fs::OpenOptions::new().write(true).open(path)?;
        f.write_all(contents)?;
        return f.flush();
    }
    // A link is followed: the rename then replaces the file it leads to.
    let path = if path
        .symlink_metadata()
        .is_ok_and(|m| m.file_type().is_symlink())
    {
        std::fs::canonicalize(path)?
    } else {
        path.to_path_buf()
    };
    rename_into_place(&path, contents)
}

/// Writes `contents` to a temporary file beside `path`, flushed, and
/// renames it over whatever is at `path`.
fn rename_into_place(path: &Path, contents: &[u8]) -> std::io::Result<()> {
    let tmp = temporary_beside(path, "tmp")?;
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

/// A fresh hidden name beside `path`: `.NAME.<what>.<pid>.<n>`.
fn temporary_beside(path: &Path, what: &str) -> std::io::Result<PathBuf> {
    let file_name = path.file_name().ok_or_else(|| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidInput,
            format!("{}: not a file path", path.display()),
        )
    })?;
    Ok(path.with_file_name(format!(
        ".{}.{what}.{}.{}",
        file_name.to_string_lossy(),
        std::process::id(),
        TEMP_COUNTER.fetch_add(1, Ordering::Relaxed)
    )))
}

/// Writes several files all or none: each goes to a temporary file beside
/// it first, and only when every one of them is written are they renamed
/// into place (a failure removes the temporary files and leaves every
/// destination as it was). A link is followed; a destination that is not
/// a regular file (a device, a FIFO, a folder) is refused before anything
/// is written. Errors name the path.
pub fn write_all_atomic(files: &[(&Path, &[u8])]) -> Result<()> {
    let io = |path: &Path| {
        let path = path.display().to_string();
        move |source| Error::Io { path, source }
    };
    let mut targets = Vec::with_capacity(files.len());
    for (path, _) in files {
        if let Existing::Special = existing(path).map_err(io(path))? {
            return Err(Error::Io {
                path: path.display().to_string(),
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "a device or FIFO, not a file that can be written with others all or none",
                ),
            });
        }
        let target = if path
            .symlink_metadata()
            .is_ok_and(|m| m.file_type().is_symlink())
        {
            std::fs::canonicalize(path).map_err(io(path))?
        } else {
            path.to_path_buf()
        };
        targets.push(target);
    }
    let mut temps = Vec::new();
    let staged = files
        .iter()
        .zip(&targets)
        .try_for_each(|((_, bytes), path)| {
            let tmp = temporary_beside(path, "all").map_err(io(path))?;
            temps.push(tmp.clone());
            write_atomic(&tmp, bytes)
        });
    let placed = staged.and_then(|()| {
        targets
            .iter()
            .zip(&temps)
            .try_for_each(|(path, tmp)| std::fs::rename(tmp, path).map_err(io(path)))
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
    let resolved = resolve_folder(dir, arg, false)?;
    // `symlink_metadata`: a dangling link is there (and no folder), not
    // missing.
    let missing = |p: &Path| p.symlink_metadata().is_err();
    let mut probe_dir = resolved.as_path();
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

/// `e` as a percentage with three significant digits, for errors that
/// span decades (beside [`percent`]'s fixed decimals) ("0" when exact,
/// "n/a" when NaN).
///
/// ```
/// use platefield::output::significant_percent;
/// assert_eq!(significant_percent(0.0), "0");
/// assert_eq!(significant_percent(0.0656), "6.56 %");
/// ```
pub fn significant_percent(e: f64) -> String {
    if e.is_nan() {
        return "n/a".into();
    }
    if e == 0.0 {
        return "0".into();
    }
    let p = 100.0 * e;
    let decimals = (2 - p.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{p:.decimals$} %")
}

/// A friction coefficient (or any value set on a decimal grid) rounded to
/// nine decimals, so that a sum such as 0.1 + 0.2 reads 0.3.
///
/// ```
/// assert_eq!(platefield::output::coefficient(0.1 + 0.2), "0.3");
/// assert_eq!(platefield::output::coefficient(0.45), "0.45");
/// ```
pub fn coefficient(x: f64) -> String {
    format!("{}", (x * 1e9).round() / 1e9)
}

/// The part of a staging folder's name after the folder's own name
/// (`.sink.platefield-stage-<pid>-<n>` beside `sink`). Entries named so are
/// never carried over from one run to the next.
const STAGE_MARK: &str = ".platefield-stage-";

/// The longest name a file system takes for one folder entry (Linux's
/// `NAME_MAX`, and the limit of the common file systems elsewhere).
const NAME_MAX: usize = 255;

/// The longest result folder name (a target's `name`, a schedule's
/// `target`), in bytes: its staging folder
/// `.NAME.platefield-stage-<pid>-<n>` must fit in `NAME_MAX` bytes with
/// the longest process id (10 digits) and counter (20 digits).
pub const MAX_FOLDER_NAME_BYTES: usize = NAME_MAX - 1 - STAGE_MARK.len() - 10 - 1 - 20;

static STAGE_COUNTER: AtomicU64 = AtomicU64::new(0);

/// The staging folders of this process not yet committed nor dropped:
/// what an interrupt removes ([`remove_stages_on_interrupt`]). Held for
/// the whole of a commit, so that an interrupt never removes a staging
/// folder that holds a previous run.
static LIVE_STAGES: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// The live staging folders, even after a thread panicked holding them.
fn live_stages() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    LIVE_STAGES.lock().unwrap_or_else(|e| e.into_inner())
}

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
/// move.
///
/// A `dir` that is a link to a folder is followed: the staging folder is
/// made beside the folder it leads to, which receives the run (the link
/// stays, and a note on stderr says so); a link to anything else, or a
/// `dir` that is not a folder, is refused before anything is written.
///
/// An interrupted run leaves at most a hidden
/// `.NAME.platefield-stage-PID-N` folder beside `dir`: before the swap it
/// holds the unfinished run, after it the previous folder (with any kept
/// entries not yet moved back). The next commit into `dir` recovers such a
/// folder of a process that is no longer running — its kept entries are
/// moved into `dir`, the rest removed — and says so on stderr; SIGINT,
/// SIGTERM and SIGHUP remove the live staging folders when the program
/// called [`remove_stages_on_interrupt`]. A staging folder that is never
/// committed is removed when the [`Staged`] is dropped (an error return).
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
        let dir = resolve_folder(dir, "--out", true)?;
        let name = dir.file_name().ok_or_else(|| {
            Error::invalid("--out", format!("{}: not a folder name", dir.display()))
        })?;
        let parent = match dir.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent).map_err(io(&parent))?;
        let stage = parent.join(stage_name(&name.to_string_lossy()));
        let mut live = live_stages();
        std::fs::create_dir(&stage).map_err(io(&stage))?;
        live.push(stage.clone());
        Ok(Staged {
            dir,
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
    /// `products` are moved into the new one and the rest is removed; then
    /// any staging folder of `dir` left by an interrupted run is recovered
    /// the same way.
    pub fn commit(mut self, products: &[&str]) -> Result<()> {
        let io = |path: &Path| {
            let path = path.display().to_string();
            move |source| Error::Io { path, source }
        };
        let mut live = live_stages();
        live.retain(|s| s != &self.stage);
        let had_previous = swap_in(&self.stage, &self.dir).map_err(io(&self.dir))?;
        self.committed = true;
        if had_previous {
            // `self.stage` now holds the previous folder.
            carry_over(&self.stage, &self.dir, products).map_err(io(&self.stage))?;
        }
        drop(live);
        for note in recover_stale(&self.dir, products)? {
            crate::progress::say(&format!("note: {note}"));
        }
        Ok(())
    }
}

impl Drop for Staged {
    fn drop(&mut self) {
        if !self.committed {
            let mut live = live_stages();
            live.retain(|s| s != &self.stage);
            let _ = std::fs::remove_dir_all(&self.stage);
        }
    }
}

/// A fresh staging folder name for the folder `name`.
fn stage_name(name: &str) -> String {
    format!(
        ".{name}{STAGE_MARK}{}-{}",
        std::process::id(),
        STAGE_COUNTER.fetch_add(1, Ordering::Relaxed)
    )
}

/// `dir` as the folder a run is written into: itself when it is missing or
/// a folder; the folder a link leads to (said on stderr, when `say`);
/// refused, naming `arg` (the option it came from), when it is something
/// else or a link to something else.
fn resolve_folder(dir: &Path, arg: &str, say: bool) -> Result<PathBuf> {
    let refuse = |why: String| Error::invalid(arg, format!("{}: {why}", dir.display()));
    let Ok(meta) = dir.symlink_metadata() else {
        return Ok(dir.to_path_buf());
    };
    if meta.is_dir() {
        return Ok(dir.to_path_buf());
    }
    if !meta.file_type().is_symlink() {
        return Err(refuse(
            "is there and not a folder, so the results cannot be written as it".into(),
        ));
    }
    match std::fs::canonicalize(dir) {
        Ok(target) if target.is_dir() => {
            if say {
                crate::progress::say(&format!(
                    "note: {} is a link to the folder {}; writing the results there (the link stays)",
                    dir.display(),
                    target.display()
                ));
            }
            Ok(target)
        }
        Ok(target) => Err(refuse(format!(
            "is a link to {}, which is not a folder; remove the link or choose another {arg}",
            target.display()
        ))),
        Err(e) => Err(refuse(format!(
            "is a link that leads nowhere ({e}); remove the link or choose another {arg}"
        ))),
    }
}

/// Whether the process `pid` is running (or may be: it exists under
/// another user).
#[cfg(unix)]
fn process_running(pid: u32) -> bool {
    let Ok(pid) = libc::pid_t::try_from(pid) else {
        return false;
    };
    // SAFETY: signal 0 only checks that the process exists.
    let rc = unsafe { libc::kill(pid, 0) };
    rc == 0 || std::io::Error::last_os_error().raw_os_error() != Some(libc::ESRCH)
}

/// Elsewhere a process's presence is not checked: every staging folder
/// counts as another run's, and is left alone.
#[cfg(not(unix))]
fn process_running(_: u32) -> bool {
    true
}

/// Recovers the staging folders of `dir` left by processes that are no
/// longer running: each is first claimed (renamed to a staging name of
/// this process, so that two runs never recover one folder), then its
/// entries that are not `products` are moved into `dir` (unless `dir`
/// has the name) and the rest is removed. Returns one line per folder
/// recovered, saying what came back.
fn recover_stale(dir: &Path, products: &[&str]) -> Result<Vec<String>> {
    let (Some(name), Some(parent)) = (dir.file_name(), dir.parent()) else {
        return Ok(Vec::new());
    };
    let parent = if parent.as_os_str().is_empty() {
        Path::new(".")
    } else {
        parent
    };
    let prefix = format!(".{}{STAGE_MARK}", name.to_string_lossy());
    let Ok(entries) = std::fs::read_dir(parent) else {
        return Ok(Vec::new());
    };
    let mut notes = Vec::new();
    for entry in entries.flatten() {
        let entry_name = entry.file_name();
        let Some(pid) = entry_name
            .to_str()
            .and_then(|n| n.strip_prefix(&prefix))
            .and_then(|rest| rest.split_once('-'))
            .and_then(|(pid, _)| pid.parse::<u32>().ok())
        else {
            continue;
        };
        if pid == std::process::id() || process_running(pid) {
            continue;
        }
        let stale = entry.path();
        let claimed = parent.join(stage_name(&name.to_string_lossy()));
        if std::fs::rename(&stale, &claimed).is_err() {
            // Another run claimed it first.
            continue;
        }
        let kept: Vec<String> = std::fs::read_dir(&claimed)
            .into_iter()
            .flatten()
            .flatten()
            .filter_map(|e| e.file_name().to_str().map(str::to_string))
            .filter(|n| !products.contains(&n.as_str()) && !n.contains(STAGE_MARK))
            .filter(|n| dir.join(n).symlink_metadata().is_err())
            .collect();
        let io = |source| Error::Io {
            path: stale.display().to_string(),
            source,
        };
        std::fs::create_dir_all(dir).map_err(io)?;
        carry_over(&claimed, dir, products).map_err(io)?;
        notes.push(if kept.is_empty() {
            format!(
                "removed {}, the staging folder of an interrupted run (process {pid})",
                stale.display()
            )
        } else {
            format!(
                "recovered {} into {} from {}, the staging folder of an interrupted run (process {pid}), and removed it",
                kept.join(", "),
                dir.display(),
                stale.display()
            )
        });
    }
    notes.sort();
    Ok(notes)
}

/// Makes an interrupt (SIGINT, SIGTERM, SIGHUP) remove this process's
/// uncommitted staging folders ([`Staged`]) and end the program with
/// status 128 + the signal's number, as the default action would. A commit
/// under way finishes first. Call it first thing in `main`, before any
/// other thread starts: it blocks those signals in the calling thread
/// (threads started later inherit that) and waits for them on a thread of
/// its own.
///
/// ```no_run
/// platefield::output::remove_stages_on_interrupt();
/// ```
#[cfg(unix)]
pub fn remove_stages_on_interrupt() {
    // SAFETY: the set is initialised by sigemptyset before use; the calls
    // only read and write it and the calling thread's signal mask.
    let set = unsafe {
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            libc::sigaddset(&mut set, sig);
        }
        if libc::pthread_sigmask(libc::SIG_BLOCK, &set, std::ptr::null_mut()) != 0 {
            return;
        }
        set
    };
    std::thread::spawn(move || {
        let mut sig: libc::c_int = 0;
        // SAFETY: `set` is an initialised signal set and `sig` a valid
        // place for the signal's number.
        if unsafe { libc::sigwait(&set, &mut sig) } != 0 {
            return;
        }
        let _no_writes = WRITES.write().unwrap_or_else(|e| e.into_inner());
        let live = live_stages();
        if !live.is_empty() {
            crate::progress::say(&format!(
                "interrupted: removing {} unfinished staging folder(s)",
                live.len()
            ));
        }
        for stage in live.iter() {
            // The run's other threads go on writing into the folder while
            // it is removed: an entry made meanwhile fails the last step,
            // so the removal is repeated until the folder is gone.
            for _ in 0..100 {
                if std::fs::remove_dir_all(stage).is_ok() || stage.symlink_metadata().is_err() {
                    break;
                }
            }
        }
        std::process::exit(128 + sig);
    });
}

/// Elsewhere interrupts keep their default action; an interrupted run's
/// staging folder is recovered by the next run ([`Staged`]).
#[cfg(not(unix))]
pub(crate) fn remove_stages_on_interrupt() {}

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
