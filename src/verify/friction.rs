//! `verify --friction`: a schedule played at another friction than the one
//! it was designed for, or across a sweep of frictions.
//!
//! * `--friction 0.25` plays the whole verification (realised grid and its
//!   prediction, swarm, rectangles) with μ_s = μ_k = 0.25.
//! * `--friction 0.2:0.4:5` plays the schedule's own friction as usual and,
//!   besides, the design's judge at 5 frictions from 0.2 to 0.4
//!   ([`crate::play::sensitivity`], judged by `design::method::sweep_schedule`
//!   in the report layer, above both): realised strength and shape error
//!   against the schedule's target at each, the table a design reports.

use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::request::FrictionSpec;

/// Most frictions in one sweep.
pub(crate) const MAX_SWEEP_VALUES: usize = 41;

/// What `--friction` asks.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionArg {
    /// Play everything at this friction (μ_s = μ_k).
    At(f64),
    /// Also sweep the judge over `n` frictions from `lo` to `hi`.
    Sweep {
        /// Lowest friction.
        lo: f64,
        /// Highest friction.
        hi: f64,
        /// Number of values (2..=`MAX_SWEEP_VALUES`).
        n: usize,
    },
}

impl FrictionArg {
    /// Reads `MU` or `LO:HI:N`, checking the range of every number
    /// (errors name `--friction`).
    pub fn parse(text: &str) -> Result<FrictionArg> {
        let bad = |why: &str| {
            Error::invalid(
                "--friction",
                format!(
                    "{why}; expected MU (e.g. 0.25) or LO:HI:N (e.g. 0.2:0.4:5), got \"{text}\""
                ),
            )
        };
        let number = |s: &str| s.trim().parse::<f64>().map_err(|_| bad("not a number"));
        let arg = match text.split(':').collect::<Vec<_>>().as_slice() {
            [mu] => FrictionArg::At(number(mu)?),
            [lo, hi, n] => FrictionArg::Sweep {
                lo: number(lo)?,
                hi: number(hi)?,
                n: n.trim()
                    .parse()
                    .map_err(|_| bad("N is not a whole number"))?,
            },
            _ => return Err(bad("wrong form")),
        };
        arg.validate()?;
        Ok(arg)
    }

    /// The friction values' ranges (the targets' one validation) and the
    /// sweep's count.
    pub(crate) fn validate(&self) -> Result<()> {
        let spec = match *self {
            FrictionArg::At(mu) => FrictionSpec::uniform(mu),
            FrictionArg::Sweep { lo, hi, n } => {
                if !(2..=MAX_SWEEP_VALUES).contains(&n) {
                    return Err(Error::invalid(
                        "--friction",
                        format!("N must be in 2..={MAX_SWEEP_VALUES}, got {n}"),
                    ));
                }
                FrictionSpec::range(lo, hi)
            }
        };
        spec.validate_driven("--friction")
    }

    /// The one friction everything is played at (`None`: the schedule's).
    pub fn played(&self) -> Option<Friction> {
        match *self {
            FrictionArg::At(mu) => Some(Friction::uniform(mu)),
            FrictionArg::Sweep { .. } => None,
        }
    }

    /// The sweep's frictions, low to high (empty for [`FrictionArg::At`]).
    pub(crate) fn sweep_values(&self) -> Vec<Friction> {
        match *self {
            FrictionArg::At(_) => Vec::new(),
            FrictionArg::Sweep { lo, hi, n } => FrictionSpec::range(lo, hi).values(n),
        }
    }
}
