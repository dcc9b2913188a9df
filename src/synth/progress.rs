//! Progress of a synthesis, shown by an argmin observer through the shared
//! [`crate::progress::Progress`]: an indicatif bar on a terminal, a plain
//! line on stderr every few seconds otherwise, nothing when quiet.
//! Progress output never enters the result.

use std::sync::Arc;

use argmin::core::observers::Observe;
use argmin::core::{Error, KV};

pub use crate::progress::ProgressMode;

/// Shared progress of one synthesis.
#[derive(Debug)]
pub(crate) struct SynthesisProgress(crate::progress::Progress);

impl SynthesisProgress {
    /// Progress over `total` evaluations.
    pub(crate) fn new(mode: ProgressMode, total: usize) -> SynthesisProgress {
        SynthesisProgress(crate::progress::Progress::new(
            "synthesis",
            "evaluations",
            total as u64,
            mode,
        ))
    }

    /// Records the evaluation count and the best evaluation so far, as its
    /// realised (strength, shape error) (called by the objective).
    pub(crate) fn update(&self, evaluations: usize, best: Option<(f64, f64)>) {
        if let Some((strength, shape_error)) = best {
            self.0.set_message(format!(
                "best: strength {strength:.4}, shape error {}",
                crate::output::percent(shape_error, 2)
            ));
        }
        self.0.set_position(evaluations as u64);
    }

    /// Called once per iteration; the display itself keeps time (a line
    /// at most every interval, also between updates).
    pub(crate) fn show(&self) {}

    /// Clears the bar and stops the lines.
    pub(crate) fn finish(&self) {
        self.0.finish();
    }
}

/// The argmin observer that drives [`SynthesisProgress`] once per iteration.
pub(crate) struct Observer(pub Arc<SynthesisProgress>);

impl<I> Observe<I> for Observer {
    fn observe_iter(&mut self, _state: &I, _kv: &KV) -> Result<(), Error> {
        self.0.show();
        Ok(())
    }
}
