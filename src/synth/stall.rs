//! Stopping when the measure stops improving.
//!
//! A search (the synthesis's Nelder–Mead on the coarse cost, the played
//! polish on the played cost) records every evaluated cost in order. It has
//! *stalled* once `window` evaluations in a row have not lowered the best
//! cost by more than `tol` below the best at the start of the run of
//! evaluations: the last improvement of at least `tol` is `window` or more
//! evaluations old. Everything is counted in evaluations, never in time, so
//! the stop is deterministic (same input, same bytes).

/// The default stall rule of the synthesis: 60 coarse re-simulations
/// without lowering the cost by 0.005 (half a percent of the seed's
/// strength, or a quarter point of shape error over budget) end it.
pub const SYNTH_STALL: StallRule = StallRule {
    window: 60,
    tol: 0.005,
};

/// The default stall rule of the played polish
/// (`platefield::design::polish`): 40 plays without lowering the played
/// cost by 0.005 (half a percent of the start's played strength, or a
/// quarter point of shape error over budget) end it.
pub const POLISH_STALL: StallRule = StallRule {
    window: 40,
    tol: 0.005,
};

/// Stall rule: stop once `window` evaluations have not improved the best
/// cost by more than `tol`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StallRule {
    /// Evaluations without an improvement that end the search (≥ 1).
    pub window: usize,
    /// Least decrease of the best cost that counts as an improvement (≥ 0).
    pub tol: f64,
}

/// Tracks the best cost and when it last improved by more than the rule's
/// tolerance.
#[derive(Debug, Clone, Default)]
pub(crate) struct StallTracker {
    evaluations: usize,
    /// The best cost as of the last improvement that counted.
    reference: Option<f64>,
    last_improvement: usize,
}

impl StallTracker {
    /// Records the cost of the next evaluation.
    pub(crate) fn record(&mut self, cost: f64, rule: Option<&StallRule>) {
        self.evaluations += 1;
        let tol = rule.map_or(0.0, |r| r.tol);
        let improved = match self.reference {
            None => cost.is_finite(),
            Some(best) => cost < best - tol,
        };
        if improved {
            self.reference = Some(cost);
            self.last_improvement = self.evaluations;
        }
    }

    /// Counts the window from the current evaluation.
    pub(crate) fn restart(&mut self) {
        self.last_improvement = self.evaluations;
    }

    /// Whether `rule` (if any) says the search has stalled.
    pub(crate) fn stalled(&self, rule: Option<&StallRule>) -> bool {
        rule.is_some_and(|r| self.evaluations - self.last_improvement >= r.window.max(1))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RULE: StallRule = StallRule {
        window: 3,
        tol: 0.01,
    };

    fn feed(costs: &[f64], rule: Option<&StallRule>) -> Vec<bool> {
        let mut t = StallTracker::default();
        costs
            .iter()
            .map(|c| {
                t.record(*c, rule);
                t.stalled(rule)
            })
            .collect()
    }

    #[test]
    fn stalls_after_window_without_improvement() {
        // 1.0 (improves), then 0.995, 0.999, 0.992 (each less than tol
        // below 1.0): stalled at the third; 0.98 (0.02 below 1.0) counts,
        // then three more without: stalled again.
        let s = feed(
            &[1.0, 0.995, 0.999, 0.992, 0.98, 0.979, 0.975, 0.99],
            Some(&RULE),
        );
        assert_eq!(s, [false, false, false, true, false, false, false, true]);
    }

    #[test]
    fn small_steps_add_up_against_the_reference() {
        // Each step is 0.006 < tol, but two of them make 0.012 > tol below
        // the reference: the improvement counts at the third cost.
        let s = feed(&[1.0, 0.994, 0.988, 0.982, 0.982, 0.982], Some(&RULE));
        assert_eq!(s, [false, false, false, false, false, true]);
    }

    #[test]
    fn restart_counts_the_window_from_now() {
        let mut t = StallTracker::default();
        for c in [1.0, 1.0, 1.0, 1.0] {
            t.record(c, Some(&RULE));
        }
        assert!(t.stalled(Some(&RULE)));
        t.restart();
        assert!(!t.stalled(Some(&RULE)));
        for _ in 0..2 {
            t.record(1.0, Some(&RULE));
        }
        assert!(!t.stalled(Some(&RULE)));
        t.record(1.0, Some(&RULE));
        assert!(t.stalled(Some(&RULE)));
    }

    #[test]
    fn no_rule_never_stalls_and_nan_is_no_improvement() {
        assert!(feed(&[1.0; 10], None).iter().all(|s| !s));
        let s = feed(&[f64::NAN, f64::NAN, f64::NAN], Some(&RULE));
        assert_eq!(s, [false, false, true]);
    }
}
