//! Progress of long work (library builds, `field`, `verify`'s parts, the
//! order search, synthesis), shown to the person running it and never in a
//! result: an indicatif bar when stderr is a terminal; otherwise (CI logs,
//! scripts, pipes) a plain line every `DEFAULT_INTERVAL` (or every
//! [`INTERVAL_ENV`] seconds), also while no count moves; nothing when
//! quiet. One abstraction for every command; it depends on nothing else in
//! the crate.
//!
//! **One observer.** Every line the library has for a person (plain
//! progress lines, work estimates, notes such as "scaled into the shaker
//! limits") goes through [`say`] to the process's [`Observer`]: by default
//! `Stderr`, the only place the library writes to stderr. A program that
//! embeds the library (a notebook, a GUI, a service's log) installs its own
//! with `set_observer`; while one is installed, progress comes as plain
//! lines to it, never as a terminal bar.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Condvar, Mutex, RwLock};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// Who hears the library's lines for a person (module docs).
pub trait Observer: Send + Sync {
    /// One line of text, without its newline.
    fn line(&self, text: &str);
}

/// The default [`Observer`]: each line on stderr.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Stderr;

impl Observer for Stderr {
    fn line(&self, text: &str) {
        eprintln!("{text}");
    }
}

/// The installed observer; `None` is [`Stderr`].
static OBSERVER: RwLock<Option<Arc<dyn Observer>>> = RwLock::new(None);

/// Installs `observer` for the whole process and returns the one it
/// replaces (`None`: the default `Stderr`); `None` restores the default.
#[cfg(test)]
pub(crate) fn set_observer(observer: Option<Arc<dyn Observer>>) -> Option<Arc<dyn Observer>> {
    let mut slot = OBSERVER.write().unwrap_or_else(|p| p.into_inner());
    std::mem::replace(&mut *slot, observer)
}

/// Gives `text` (one line, no newline) to the installed [`Observer`].
pub fn say(text: &str) {
    let installed = OBSERVER.read().unwrap_or_else(|p| p.into_inner()).clone();
    match installed {
        Some(o) => o.line(text),
        None => Stderr.line(text),
    }
}

/// Whether an observer other than [`Stderr`] is installed.
fn observed() -> bool {
    OBSERVER.read().unwrap_or_else(|p| p.into_inner()).is_some()
}

/// Seconds between plain progress lines by default.
pub(crate) const DEFAULT_INTERVAL: Duration = Duration::from_secs(3);

/// Environment variable overriding the seconds between plain lines (a
/// number ≥ 0; 0 prints a line at every update).
pub const INTERVAL_ENV: &str = "PLATEFIELD_PROGRESS_INTERVAL";

/// Where progress goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ProgressMode {
    /// Bar on a terminal, plain lines otherwise.
    #[default]
    Auto,
    /// Nothing.
    Quiet,
}

impl ProgressMode {
    /// [`ProgressMode::Quiet`] when `quiet`, else [`ProgressMode::Auto`].
    pub fn quiet_if(quiet: bool) -> ProgressMode {
        if quiet {
            ProgressMode::Quiet
        } else {
            ProgressMode::Auto
        }
    }
}

/// The interval between plain lines: [`INTERVAL_ENV`] when it holds a
/// finite number ≥ 0, else `DEFAULT_INTERVAL`.
pub(crate) fn interval() -> Duration {
    std::env::var(INTERVAL_ENV)
        .ok()
        .and_then(|s| s.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && *s >= 0.0 && *s < 1e6)
        .map_or(DEFAULT_INTERVAL, Duration::from_secs_f64)
}

/// One plain progress line: `label: pos/total unit (P %), elapsed, about
/// T left[, message]`; without a total (0: not known), `label: pos unit,
/// elapsed[, message]`.
pub(crate) fn line(
    label: &str,
    pos: u64,
    total: u64,
    unit: &str,
    message: &str,
    elapsed_s: f64,
) -> String {
    let mut s = if total > 0 {
        format!("{label}: {pos}/{total} {unit}")
    } else {
        format!("{label}: {pos} {unit}")
    };
    if total > 0 {
        let _ = std::fmt::Write::write_fmt(
            &mut s,
            format_args!(" ({:.0} %)", 100.0 * pos.min(total) as f64 / total as f64),
        );
    }
    s.push_str(&format!(", {} elapsed", seconds(elapsed_s)));
    if pos > 0 && pos < total {
        let left = elapsed_s * (total - pos) as f64 / pos as f64;
        s.push_str(&format!(", about {} left", seconds(left)));
    }
    if !message.is_empty() {
        s.push_str(", ");
        s.push_str(message);
    }
    s
}

/// Seconds as "12 s", "3.4 min" or "1.2 h".
fn seconds(s: f64) -> String {
    if s < 120.0 {
        format!("{s:.0} s")
    } else if s < 7200.0 {
        format!("{:.1} min", s / 60.0)
    } else {
        format!("{:.1} h", s / 3600.0)
    }
}

#[derive(Debug)]
struct State {
    pos: u64,
    message: String,
    last_line: Instant,
}

#[derive(Debug)]
struct Lines {
    label: String,
    unit: String,
    total: u64,
    start: Instant,
    interval: Duration,
    state: Mutex<State>,
    stop: AtomicBool,
    wake: Condvar,
}

impl Lines {
    fn lock(&self) -> std::sync::MutexGuard<'_, State> {
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Prints a line if the interval has passed since the last one.
    fn maybe_print(&self, s: &mut State) {
        if !self.stop.load(Ordering::Relaxed) && s.last_line.elapsed() >= self.interval {
            s.last_line = Instant::now();
            say(&line(
                &self.label,
                s.pos,
                self.total,
                &self.unit,
                &s.message,
                self.start.elapsed().as_secs_f64(),
            ));
        }
    }
}

/// Progress of one piece of long work over `total` units; shareable
/// between threads (`&Progress` is `Sync`). Dropping it finishes it.
#[derive(Debug)]
pub struct Progress {
    bar: Option<ProgressBar>,
    lines: Option<Arc<Lines>>,
    heartbeat: Mutex<Option<std::thread::JoinHandle<()>>>,
}

impl Progress {
    /// Progress of `label` over `total` `unit`s (e.g. "samples"), shown as
    /// `mode` says.
    pub fn new(label: &str, unit: &str, total: u64, mode: ProgressMode) -> Progress {
        if mode == ProgressMode::Quiet {
            return Progress::hidden();
        }
        if std::io::stderr().is_terminal() && !observed() {
            let bar = ProgressBar::new(total);
            let template = format!("{label} [{{bar:40}}] {{pos}}/{{len}} {unit} ({{eta}}) {{msg}}");
            if let Ok(style) = ProgressStyle::with_template(&template) {
                bar.set_style(style.progress_chars("=> "));
            }
            return Progress {
                bar: Some(bar),
                lines: None,
                heartbeat: Mutex::new(None),
            };
        }
        let interval = interval();
        let lines = Arc::new(Lines {
            label: label.to_string(),
            unit: unit.to_string(),
            total,
            start: Instant::now(),
            interval,
            state: Mutex::new(State {
                pos: 0,
                message: String::new(),
                last_line: Instant::now(),
            }),
            stop: AtomicBool::new(false),
            wake: Condvar::new(),
        });
        // A heartbeat: a line every interval even while no count moves.
        let beat = Arc::clone(&lines);
        let heartbeat = std::thread::Builder::new()
            .name("progress".into())
            .spawn(move || {
                let nap = beat.interval.max(Duration::from_millis(50));
                let mut s = beat.lock();
                while !beat.stop.load(Ordering::Relaxed) {
                    s = match beat.wake.wait_timeout(s, nap) {
                        Ok((s, _)) => s,
                        Err(p) => p.into_inner().0,
                    };
                    if !beat.stop.load(Ordering::Relaxed) {
                        beat.maybe_print(&mut s);
                    }
                }
            })
            .ok();
        Progress {
            bar: None,
            lines: Some(lines),
            heartbeat: Mutex::new(heartbeat),
        }
    }

    /// Progress that shows nothing.
    pub(crate) fn hidden() -> Progress {
        Progress {
            bar: None,
            lines: None,
            heartbeat: Mutex::new(None),
        }
    }

    /// Advances by `n` units.
    pub(crate) fn inc(&self, n: u64) {
        if let Some(bar) = &self.bar {
            bar.inc(n);
        }
        if let Some(l) = &self.lines {
            let mut s = l.lock();
            s.pos += n;
            l.maybe_print(&mut s);
        }
    }

    /// Sets the count of units done.
    pub(crate) fn set_position(&self, pos: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(pos);
        }
        if let Some(l) = &self.lines {
            let mut s = l.lock();
            s.pos = pos;
            l.maybe_print(&mut s);
        }
    }

    /// Sets the message shown after the counts (e.g. the primitive being
    /// built, the best result so far).
    pub(crate) fn set_message(&self, message: impl Into<String>) {
        let message = message.into();
        if let Some(bar) = &self.bar {
            bar.set_message(message);
        } else if let Some(l) = &self.lines {
            l.lock().message = message;
        }
    }

    /// Clears the bar and stops the plain lines (no further output).
    pub(crate) fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
        if let Some(l) = &self.lines {
            l.stop.store(true, Ordering::Relaxed);
            l.wake.notify_all();
        }
        let handle = self
            .heartbeat
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .take();
        if let Some(h) = handle {
            let _ = h.join();
        }
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        self.finish();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The plain line: counts, percentage, elapsed, the time left by
    /// linear extrapolation (30 s for 250 of 1000 → 90 s left), message.
    #[test]
    fn line_states_counts_percent_and_time_left() {
        assert_eq!(
            line("library velocity", 250, 1000, "samples", "LineSink", 30.0),
            "library velocity: 250/1000 samples (25 %), 30 s elapsed, about 90 s left, LineSink"
        );
        assert_eq!(
            line("verify", 0, 10, "parts", "", 0.4),
            "verify: 0/10 parts (0 %), 0 s elapsed"
        );
        assert_eq!(
            line("order search", 6, 6, "candidates", "", 300.0),
            "order search: 6/6 candidates (100 %), 5.0 min elapsed"
        );
        assert_eq!(
            line("a study", 4386, 0, "k steps", "", 93.0),
            "a study: 4386 k steps, 93 s elapsed"
        );
    }

    /// Quiet progress shows nothing and counts nothing; it can be shared
    /// between threads and finished twice.
    #[test]
    fn quiet_is_inert_and_sync() {
        fn sync<T: Sync>(_: &T) {}
        let p = Progress::new("x", "units", 10, ProgressMode::Quiet);
        sync(&p);
        p.inc(3);
        p.set_message("m");
        assert!(p.bar.is_none() && p.lines.is_none());
        p.finish();
        p.finish();
    }

    /// A worked example of `progress::set_observer`.
    #[test]
    fn example_set_observer() {
        use crate::progress::{say, set_observer, Observer};
        use std::sync::{Arc, Mutex};
        #[derive(Default)]
        struct Collect(Mutex<Vec<String>>);
        impl Observer for Collect {
            fn line(&self, text: &str) {
                self.0.lock().unwrap().push(text.to_string());
            }
        }
        let heard = Arc::new(Collect::default());
        let before = set_observer(Some(heard.clone()));
        say("note: heard by the observer, not on stderr");
        set_observer(before);
        assert!(heard
            .0
            .lock()
            .unwrap()
            .iter()
            .any(|l| l.starts_with("note: heard")));
    }
}
