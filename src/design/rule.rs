//! The rule that ranks two realised designs (`auto`'s choice between its
//! candidates, [`super::method`], and the played polish's keep,
//! [`super::polish`]): one rule, so a polished motion is kept only when the
//! choice would prefer it to the motion it started from.
//!
//! A design's key is (POOR, realised shape error, realised strength): a
//! design that is not POOR beats one that is; between two of the same
//! standing, realised shape errors within [`TIE_SHAPE_ERROR`] are a tie
//! broken by the higher realised strength, and otherwise the lower shape
//! error wins. Missing numbers rank last (shape +∞, strength −∞).
//!
//! `auto` over a friction range first asks which candidates hold the
//! target within the range's bound (their worst-case shape error at most
//! 6 %, `RANGE_HELD`, and not POOR) ([`better_within`]): one that does
//! beats one that does not, whatever their strengths, so the tie above
//! never trades a design that holds the range for a stronger one that
//! does not. Between two that both hold it, the higher worst-case
//! strength wins: once the shape is within what the range asks at every
//! friction, a stronger field moves parts sooner, and a lower shape error
//! below the bound buys the user nothing the bound does not already
//! promise (a robust design that holds 3 % at a tenth of another's
//! strength, which holds 5.5 %, is the slower feeder for no stated gain).

/// Fewest counted parts a realised measure is reported over. A shape is a
/// property of the field over the region: one or two parts sample it at
/// one or two places (a 2-D affine field has six coefficients; three
/// points in general position fix them), so fewer are reported as not
/// measured, POOR, with the reason, rather than as a strength and shape.
pub const MIN_MEASURED_POINTS: usize = 3;

/// Realised shape errors within this of each other are a tie, broken by
/// the realised strength.
pub const TIE_SHAPE_ERROR: f64 = 0.01;

/// The rule that decides between two candidates under `auto`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Rule {
    /// One is POOR and the other is not.
    OtherPoor,
    /// Realised shape errors within [`TIE_SHAPE_ERROR`]: the higher
    /// realised strength wins.
    HigherStrength,
    /// The lower realised shape error wins.
    LowerShapeError,
    /// Over a friction range only one of the two holds the target within
    /// the range's bound (`better_within`).
    HoldsRange,
    /// Over a friction range both hold the target within the range's
    /// bound: the higher worst-case strength wins (`better_within`).
    StrongerWithinRange,
}

impl Rule {
    /// The rule in words.
    pub(crate) fn text(self) -> &'static str {
        match self {
            Rule::OtherPoor => "the other is POOR",
            Rule::HigherStrength => {
                "shape errors within 1 percentage point: the higher realised strength wins"
            }
            Rule::LowerShapeError => "the lower realised shape error wins",
            Rule::HoldsRange => {
                "only it holds the target within 6 % at its worst over the friction range"
            }
            Rule::StrongerWithinRange => {
                "both hold the target within 6 % at their worst over the friction range: the higher worst-case strength wins"
            }
        }
    }
}

/// A design's key: POOR, realised shape error, realised strength (module
/// documentation).
pub type Key = (bool, f64, f64);

/// Whether `b` beats `a` by the rule over a friction range whose bound is
/// `bound` (`None`: `better`): a design that is not POOR and holds its
/// worst-case shape error within the bound beats one that does not, and
/// of two that both hold it the stronger wins (module documentation).
pub(crate) fn better_within(a: Key, b: Key, bound: Option<f64>) -> (bool, Rule) {
    if let Some(bound) = bound {
        let holds = |k: Key| !k.0 && k.1 <= bound;
        match (holds(a), holds(b)) {
            (true, true) => return (b.2 > a.2, Rule::StrongerWithinRange),
            (x, y) if x != y => return (y, Rule::HoldsRange),
            _ => {}
        }
    }
    better(a, b)
}

/// Whether `b` beats `a` by the rule, and the rule that decided.
pub(crate) fn better(a: Key, b: Key) -> (bool, Rule) {
    if a.0 != b.0 {
        (a.0, Rule::OtherPoor)
    } else if (a.1 - b.1).abs() <= TIE_SHAPE_ERROR {
        (b.2 > a.2, Rule::HigherStrength)
    } else {
        (b.1 < a.1, Rule::LowerShapeError)
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `design::rule::better_within`.
    #[test]
    fn example_better_within() {
        use crate::design::method::{better_within, Rule};
        // 5.9 % at 0.6 s⁻¹ against 6.5 % at 1.0 s⁻¹: within a point of each
        // other, but only the first holds 6 %.
        assert_eq!(
            better_within((false, 0.059, 0.6), (false, 0.065, 1.0), Some(0.06)),
            (false, Rule::HoldsRange)
        );
        assert_eq!(
            better_within((false, 0.059, 0.6), (false, 0.065, 1.0), None),
            (true, Rule::HigherStrength)
        );
        // 3.0 % at 0.1 s⁻¹ against 5.5 % at 1.0 s⁻¹: both hold 6 %.
        assert_eq!(
            better_within((false, 0.030, 0.1), (false, 0.055, 1.0), Some(0.06)),
            (true, Rule::StrongerWithinRange)
        );
    }
}
