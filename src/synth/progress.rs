//! Progress of a synthesis, shown by an argmin observer: an indicatif bar
//! on a terminal, a plain line on stderr every few seconds otherwise,
//! nothing when quiet. Progress output never enters the result.

use std::io::IsTerminal;
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use argmin::core::observers::Observe;
use argmin::core::{Error, KV};
use indicatif::{ProgressBar, ProgressStyle};

use super::objective::Evaluation;

/// Seconds between plain progress lines.
const LINE_INTERVAL: Duration = Duration::from_secs(3);

/// Where progress goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ProgressMode {
    /// Bar on a terminal, plain lines otherwise.
    #[default]
    Auto,
    /// Nothing.
    Quiet,
}

#[derive(Debug)]
struct State {
    evaluations: usize,
    line: String,
    last_line: Instant,
}

/// Shared progress of one synthesis.
#[derive(Debug)]
pub struct Progress {
    mode: ProgressMode,
    bar: Option<ProgressBar>,
    total: usize,
    state: Mutex<State>,
}

impl Progress {
    /// Progress over `total` evaluations.
    pub fn new(mode: ProgressMode, total: usize) -> Progress {
        let bar = (mode == ProgressMode::Auto && std::io::stderr().is_terminal()).then(|| {
            let b = ProgressBar::new(total as u64);
            if let Ok(style) =
                ProgressStyle::with_template("synthesis {bar:30} {pos}/{len} evaluations {msg}")
            {
                b.set_style(style);
            }
            b
        });
        Progress {
            mode,
            bar,
            total,
            state: Mutex::new(State {
                evaluations: 0,
                line: String::new(),
                last_line: Instant::now(),
            }),
        }
    }

    /// Records the evaluation count and the best evaluation so far (called
    /// by the objective; shows nothing).
    pub fn update(&self, evaluations: usize, best: Option<&Evaluation>) {
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        s.evaluations = evaluations;
        if let Some(b) = best {
            s.line = format!(
                "best: strength {:.4}, shape error {:.2} %",
                b.realised.strength,
                100.0 * b.realised.shape_error
            );
        }
    }

    /// Shows the current state (bar, or a line if enough time has passed).
    pub fn show(&self) {
        if self.mode == ProgressMode::Quiet {
            return;
        }
        let mut s = self.state.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(bar) = &self.bar {
            bar.set_position(s.evaluations as u64);
            bar.set_message(s.line.clone());
        } else if s.last_line.elapsed() >= LINE_INTERVAL {
            s.last_line = Instant::now();
            eprintln!(
                "synthesis: {}/{} evaluations, {}",
                s.evaluations, self.total, s.line
            );
        }
    }

    /// Clears the bar.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}

/// The argmin observer that drives [`Progress`] once per iteration.
pub struct Observer(pub Arc<Progress>);

impl<I> Observe<I> for Observer {
    fn observe_iter(&mut self, _state: &I, _kv: &KV) -> Result<(), Error> {
        self.0.show();
        Ok(())
    }
}
