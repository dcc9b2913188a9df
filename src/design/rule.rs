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
}

impl Rule {
    /// The rule in words.
    pub fn text(self) -> &'static str {
        match self {
            Rule::OtherPoor => "the other is POOR",
            Rule::HigherStrength => {
                "shape errors within 1 percentage point: the higher realised strength wins"
            }
            Rule::LowerShapeError => "the lower realised shape error wins",
        }
    }
}

/// A design's key: POOR, realised shape error, realised strength (module
/// documentation).
pub type Key = (bool, f64, f64);

/// Whether `b` beats `a` by the rule, and the rule that decided.
pub fn better(a: Key, b: Key) -> (bool, Rule) {
    if a.0 != b.0 {
        (a.0, Rule::OtherPoor)
    } else if (a.1 - b.1).abs() <= TIE_SHAPE_ERROR {
        (b.2 > a.2, Rule::HigherStrength)
    } else {
        (b.1 < a.1, Rule::LowerShapeError)
    }
}
