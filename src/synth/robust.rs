//! Robust synthesis: the physics a motion is optimised under when the
//! parts' friction is known only within a range, and the worst case of a
//! measure over them.
//!
//! A friction error turns a synthesized field: the slip direction leads the
//! plate velocity by δ = asin(μg/A) (see the [crate docs](crate::synth)),
//! so a motion tuned at one μ realises a turned (and rescaled) field at
//! another. Over a stated range `[μ_lo, μ_hi]` the synthesis objective and
//! the played polish therefore judge every candidate at
//! `ROBUST_VALUES` frictions spread over the range (its ends and its
//! middle, the nominal), and score it by the worst case:
//!
//! ```text
//! ŝ_worst = min_k ŝ(μ_k),   e_worst = max_k e(μ_k)
//! ```
//!
//! The worst case between those values is what the design's judge
//! then reports over `crate::play::sensitivity::SWEEP_VALUES` values
//! (`auto` chooses by it).

use crate::field::FieldSettings;
use crate::scene::FrictionSpec;

/// Frictions per range a robust objective judges a motion at: the ends
/// and the middle.
pub(crate) const ROBUST_VALUES: usize = 3;

/// The physics a motion is judged under: `settings` at each of
/// `ROBUST_VALUES` frictions spread over `spec` when it is a range;
/// `settings` alone when `spec` is `None` or exact. Never empty.
///
/// # Examples
pub(crate) fn judged_under(
    settings: &FieldSettings,
    spec: Option<FrictionSpec>,
) -> Vec<FieldSettings> {
    let spread = match spec {
        Some(s) if !s.is_exact() => s.values(ROBUST_VALUES),
        _ => Vec::new(),
    };
    if spread.is_empty() {
        return vec![*settings];
    }
    spread
        .into_iter()
        .map(|friction| FieldSettings {
            friction,
            ..*settings
        })
        .collect()
}

#[cfg(test)]
mod tests {
    /// A worked example of `synth::robust::judged_under`.
    #[test]
    fn example_judged_under() {
        use crate::field::FieldSettings;
        use crate::scene::FrictionSpec;
        use crate::synth::robust::judged_under;

        let base = FieldSettings::default();
        let set = judged_under(&base, Some(FrictionSpec::range(0.2, 0.4)));
        let mu: Vec<f64> = set.iter().map(|s| s.friction.kinetic).collect();
        assert_eq!(mu.len(), 3);
        assert!((mu[0] - 0.2).abs() < 1e-12 && (mu[2] - 0.4).abs() < 1e-12);
        assert_eq!(judged_under(&base, None).len(), 1);
    }
}
