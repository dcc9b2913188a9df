//! Friction as a user knows it: one coefficient, or a range it is known
//! within. One loader and one validation for scenes and targets.
//!
//! ```text
//! "friction": 0.3                                   μ_s = μ_k = 0.3
//! "friction": [0.2, 0.4]                            μ_s = μ_k = μ, μ known within [0.2, 0.4]
//! "friction": {"static": 0.5, "kinetic": 0.4}       each a number or a range [lo, hi];
//! "friction": {"static": [0.4, 0.6], "kinetic": 0.4}  a missing one equals the other
//! ```
//!
//! Every coefficient lies in [0, [`MU`]]; a range is written low to high;
//! static is never below kinetic (at both ends of their ranges). A scene
//! simulates one friction, so it takes the exact forms only; a target may
//! state a range, which a design then holds over ([`FrictionSpec::values`]).
//! The nominal friction of a range is its middle ([`FrictionSpec::nominal`]).

use serde::de::Error as _;
use serde::{Deserialize, Deserializer, Serialize, Serializer};
use serde_json::{json, Value};

use crate::dynamics::Friction;
use crate::error::{Error, Result};
use crate::input::{self, num};

/// Largest friction coefficient: μ_s and μ_k lie in [0, MU]. Parts on a
/// vibratory plate sit near 0.1–1 (rubber on steel near 1); above 2 a
/// number is a typo, not a part.
pub const MU: f64 = 2.0;

/// Smallest kinetic friction of a part that is to be driven (a target's,
/// `verify --friction`): the plate moves a part only by friction, μ_k g
/// at most, so at μ_k = 0 nothing can be designed or played, and below
/// 1e-3 the drive is a thousandth of g. PTFE on steel, among the most
/// slippery real pairs, is near 0.04. A scene may still simulate μ = 0.
pub const MU_DRIVEN: f64 = 1e-3;

/// A coefficient known within `[lo, hi]` (`lo == hi`: known exactly).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Interval {
    /// Lowest value.
    pub lo: f64,
    /// Highest value.
    pub hi: f64,
}

impl Interval {
    /// A coefficient known exactly.
    pub(crate) fn exact(v: f64) -> Interval {
        Interval { lo: v, hi: v }
    }

    /// The middle of the range.
    pub(crate) fn mid(&self) -> f64 {
        0.5 * (self.lo + self.hi)
    }

    /// `true` when known exactly.
    pub(crate) fn is_exact(&self) -> bool {
        self.lo == self.hi
    }

    /// `n` values evenly spread from `lo` to `hi` (the middle alone for
    /// `n` = 1 or an exact value).
    pub(crate) fn spread(&self, n: usize) -> Vec<f64> {
        if self.is_exact() || n <= 1 {
            return vec![self.mid()];
        }
        (0..n)
            .map(|i| self.lo + (self.hi - self.lo) * i as f64 / (n - 1) as f64)
            .collect()
    }

    /// Checks each end is finite and in [0, [`MU`]] and the range is
    /// written low to high; `path` names where the value was written.
    fn validate(&self, path: &str) -> Result<()> {
        let ends: &[(String, f64)] = if self.is_exact() {
            &[(path.to_string(), self.lo)]
        } else {
            &[
                (format!("{path}[0]"), self.lo),
                (format!("{path}[1]"), self.hi),
            ]
        };
        for (at, v) in ends {
            if !(v.is_finite() && (0.0..=MU).contains(v)) {
                return Err(Error::invalid(
                    at,
                    format!("must be in [0, {}], got {}", num(MU), num(*v)),
                ));
            }
        }
        if self.lo > self.hi {
            return Err(Error::invalid(
                path,
                format!(
                    "a range is written [low, high]; got [{}, {}] (reversed)",
                    num(self.lo),
                    num(self.hi)
                ),
            ));
        }
        Ok(())
    }

    fn to_json(self) -> Value {
        if self.is_exact() {
            json!(self.lo)
        } else {
            json!([self.lo, self.hi])
        }
    }
}

/// The parts' friction: static and kinetic coefficients, each exact or a
/// range: `0.3`, `[0.2, 0.4]` or `{"static": .., "kinetic": ..}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionSpec {
    /// Static coefficient μ_s.
    pub stat: Interval,
    /// Kinetic coefficient μ_k.
    pub kinetic: Interval,
    /// Static and kinetic are one coefficient (`0.3`, `[0.2, 0.4]`, or an
    /// object giving only one of them): each value of the range is a
    /// friction with μ_s = μ_k.
    pub tied: bool,
}

impl FrictionSpec {
    /// One exact coefficient μ_s = μ_k = `mu`.
    pub fn uniform(mu: f64) -> FrictionSpec {
        FrictionSpec::range(mu, mu)
    }

    /// μ_s = μ_k = μ, known within `[lo, hi]`.
    pub fn range(lo: f64, hi: f64) -> FrictionSpec {
        FrictionSpec {
            stat: Interval { lo, hi },
            kinetic: Interval { lo, hi },
            tied: true,
        }
    }

    /// The exact friction `f` (tied when μ_s = μ_k).
    pub fn exact(f: Friction) -> FrictionSpec {
        FrictionSpec {
            stat: Interval::exact(f.stat),
            kinetic: Interval::exact(f.kinetic),
            tied: f.stat == f.kinetic,
        }
    }

    /// `true` when both coefficients are known exactly.
    ///
    /// ```
    /// use platefield::request::FrictionSpec;
    /// assert!(FrictionSpec::uniform(0.3).is_exact());
    /// assert!(!FrictionSpec::range(0.2, 0.4).is_exact());
    /// ```
    pub fn is_exact(&self) -> bool {
        self.stat.is_exact() && self.kinetic.is_exact()
    }

    /// The friction a design is made for: the middle of each range.
    pub fn nominal(&self) -> Friction {
        Friction {
            stat: self.stat.mid(),
            kinetic: self.kinetic.mid(),
        }
    }

    /// Frictions spread over the spec, `n` per range, in a fixed order:
    /// for a tied spec `n` values μ_s = μ_k from low to high; otherwise
    /// every pair of `n` static and `n` kinetic values with μ_s ≥ μ_k,
    /// static outer. An exact spec gives its one friction.
    pub fn values(&self, n: usize) -> Vec<Friction> {
        if self.tied {
            return self
                .kinetic
                .spread(n)
                .into_iter()
                .map(Friction::uniform)
                .collect();
        }
        let kinetic = self.kinetic.spread(n);
        self.stat
            .spread(n)
            .into_iter()
            .flat_map(|stat| {
                // Rounding in the spread (0.2 + 0.2/2 > 0.3) must not drop
                // μ_k = μ_s: equal within 1e-12 counts as equal.
                kinetic
                    .iter()
                    .filter(move |&&k| k <= stat + 1e-12)
                    .map(move |&k| Friction {
                        stat,
                        kinetic: k.min(stat),
                    })
            })
            .collect()
    }

    /// The spec around `f` within ±`fraction` of each coefficient (clipped
    /// to [0, [`MU`]]): what a report's sensitivity table sweeps when a
    /// single value is given.
    pub fn around(f: Friction, fraction: f64) -> FrictionSpec {
        let band = |v: f64| Interval {
            lo: (v * (1.0 - fraction)).max(0.0),
            hi: (v * (1.0 + fraction)).min(MU),
        };
        FrictionSpec {
            stat: band(f.stat),
            kinetic: band(f.kinetic),
            tied: f.stat == f.kinetic,
        }
    }

    /// Checks every coefficient (finite, in [0, [`MU`]], ranges low to
    /// high) and that static is not below kinetic, naming the JSON path
    /// under `path` (`target.friction`) where the value was written.
    pub(crate) fn validate(&self, path: &str) -> Result<()> {
        if self.tied {
            return self.kinetic.validate(path);
        }
        self.stat.validate(&format!("{path}.static"))?;
        self.kinetic.validate(&format!("{path}.kinetic"))?;
        if self.stat.lo < self.kinetic.lo || self.stat.hi < self.kinetic.hi {
            return Err(Error::invalid(
                format!("{path}.static"),
                format!(
                    "must be ≥ the kinetic coefficient {} (got {}): a part at rest holds at least as well as a sliding one",
                    self.kinetic.to_json(),
                    self.stat.to_json()
                ),
            ));
        }
        Ok(())
    }

    /// [`FrictionSpec::validate`], and that the kinetic coefficient (its
    /// low end, of a range) is at least `MU_DRIVEN`: parts on a
    /// frictionless plate cannot be driven. Errors name the key under
    /// `path` that holds the kinetic coefficient.
    pub(crate) fn validate_driven(&self, path: &str) -> Result<()> {
        self.validate(path)?;
        let lo = self.kinetic.lo;
        if lo >= MU_DRIVEN {
            return Ok(());
        }
        let key = if self.tied {
            path.to_string()
        } else {
            format!("{path}.kinetic")
        };
        let key = if self.kinetic.is_exact() {
            key
        } else {
            format!("{key}[0]")
        };
        Err(Error::invalid(
            key,
            format!(
                "μ_k = {} is {}a frictionless plate: parts on it cannot be driven (the plate moves a part only by friction, at most μ_k g); a part to drive needs μ_k ≥ {} (PTFE on steel is near 0.04)",
                num(lo.abs()),
                if lo == 0.0 { "" } else { "in effect " },
                num(MU_DRIVEN)
            ),
        ))
    }

    /// Reads a command-line friction `MU` (μ_s = μ_k = MU) or `LO:HI` (a
    /// range), checked by `FrictionSpec::validate_driven`; errors name
    /// `arg`.
    ///
    /// ```
    /// use platefield::scene::FrictionSpec;
    /// assert_eq!(FrictionSpec::parse_arg("0.3", "--friction")?, FrictionSpec::uniform(0.3));
    /// assert_eq!(FrictionSpec::parse_arg("0.2:0.4", "--friction")?, FrictionSpec::range(0.2, 0.4));
    /// let e = FrictionSpec::parse_arg("0.2:x", "--friction").unwrap_err().to_string();
    /// assert!(e.starts_with("--friction: expected MU (e.g. 0.25) or LO:HI"), "{e}");
    /// # Ok::<(), platefield::Error>(())
    /// ```
    pub fn parse_arg(text: &str, arg: &str) -> Result<FrictionSpec> {
        let bad = || {
            Error::invalid(
                arg,
                format!("expected MU (e.g. 0.25) or LO:HI (e.g. 0.2:0.4), got \"{text}\""),
            )
        };
        let number = |s: &str| s.trim().parse::<f64>().map_err(|_| bad());
        let spec = match text.split(':').collect::<Vec<_>>().as_slice() {
            [mu] => FrictionSpec::uniform(number(mu)?),
            [lo, hi] => FrictionSpec::range(number(lo)?, number(hi)?),
            _ => return Err(bad()),
        };
        spec.validate_driven(arg)?;
        Ok(spec)
    }

    /// The spec as JSON, in the shortest form that reads back to it.
    pub fn to_json(&self) -> Value {
        if self.tied {
            self.kinetic.to_json()
        } else {
            json!({"static": self.stat.to_json(), "kinetic": self.kinetic.to_json()})
        }
    }
}

impl Serialize for FrictionSpec {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        self.to_json().serialize(s)
    }
}

impl<'de> Deserialize<'de> for FrictionSpec {
    /// `μ`, `[lo, hi]`, or `{"static": .., "kinetic": ..}` with each a
    /// number or a range, a missing one equal to the other.
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let value = Value::deserialize(d)?;
        match value {
            Value::Object(map) => input::fields::<D, _>(map, &[], "", |b| {
                let stat: Option<Coefficient> = b.or("static", None);
                let kinetic: Option<Coefficient> = b.or("kinetic", None);
                let spec = match (stat, kinetic) {
                    (Some(s), Some(k)) => FrictionSpec {
                        stat: s.0,
                        kinetic: k.0,
                        tied: false,
                    },
                    (Some(one), None) | (None, Some(one)) => FrictionSpec {
                        stat: one.0,
                        kinetic: one.0,
                        tied: true,
                    },
                    (None, None) => FrictionSpec::uniform(0.3),
                };
                Some(spec)
            }),
            other => input::nested::<D, Coefficient>(other).map(|c| FrictionSpec {
                stat: c.0,
                kinetic: c.0,
                tied: true,
            }),
        }
    }
}

/// One coefficient as written: a number, or `[lo, hi]`.
#[derive(Debug, Clone, Copy, Default)]
struct Coefficient(Interval);

impl Default for Interval {
    fn default() -> Self {
        Interval::exact(f64::NAN)
    }
}

impl<'de> Deserialize<'de> for Coefficient {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        let value = Value::deserialize(d)?;
        let number = |v: &Value| v.as_f64();
        match &value {
            Value::Number(_) => Ok(Coefficient(Interval::exact(
                number(&value).unwrap_or(f64::NAN),
            ))),
            Value::Array(items) => match items.as_slice() {
                [lo, hi] => match (number(lo), number(hi)) {
                    (Some(lo), Some(hi)) => Ok(Coefficient(Interval { lo, hi })),
                    _ => Err(D::Error::custom(format!(
                        "a range must be two numbers [low, high], got [{}, {}]",
                        input::describe(lo),
                        input::describe(hi)
                    ))),
                },
                _ => Err(D::Error::custom(format!(
                    "a range must be two numbers [low, high], got {} values",
                    items.len()
                ))),
            },
            other => Err(D::Error::custom(format!(
                "must be a number μ, a range [low, high] or {{\"static\": .., \"kinetic\": ..}}, got {}",
                input::describe(other)
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str) -> std::result::Result<FrictionSpec, String> {
        let v: serde_json::Value =
            serde_json::from_str(&format!("{{\"friction\": {text}}}")).unwrap();
        #[derive(Deserialize)]
        struct W {
            friction: FrictionSpec,
        }
        let w: W = serde_json::from_value(v).map_err(|e| e.to_string())?;
        w.friction
            .validate("target.friction")
            .map_err(|e| e.to_string())?;
        Ok(w.friction)
    }

    #[test]
    fn forms_read_and_write_back() {
        for text in [
            "0.3",
            "[0.2,0.4]",
            "{\"kinetic\":0.4,\"static\":0.5}",
            "{\"kinetic\":[0.2,0.3],\"static\":[0.3,0.5]}",
        ] {
            let spec = read(text).unwrap();
            assert_eq!(spec.to_json().to_string(), text);
            assert_eq!(read(&spec.to_json().to_string()).unwrap(), spec);
        }
        assert_eq!(
            read("{\"static\": 0.25}").unwrap(),
            FrictionSpec::uniform(0.25)
        );
    }

    #[test]
    fn nominal_is_the_middle_and_values_span_the_range() {
        let spec = read("[0.2, 0.4]").unwrap();
        assert_eq!(spec.nominal(), Friction::uniform(0.30000000000000004));
        let v: Vec<f64> = spec.values(5).iter().map(|f| f.kinetic).collect();
        assert_eq!(v.len(), 5);
        assert!((v[0] - 0.2).abs() < 1e-15 && (v[4] - 0.4).abs() < 1e-15);
        assert!(v
            .iter()
            .all(|&k| spec.values(5).iter().any(|f| f.stat == k)));
        // Untied: pairs with μ_s ≥ μ_k only, static outer.
        let spec = read("{\"static\": [0.3, 0.5], \"kinetic\": [0.2, 0.4]}").unwrap();
        let pairs = spec.values(3);
        assert_eq!(pairs.len(), 8, "9 pairs less (0.3, 0.4)");
        assert!(pairs.iter().all(|f| f.stat >= f.kinetic));
        assert_eq!(
            FrictionSpec::uniform(0.3).values(5),
            vec![Friction::uniform(0.3)]
        );
    }

    #[test]
    fn bad_friction_names_the_path_and_range() {
        for (text, expected) in [
            ("-0.1", "target.friction: must be in [0, 2], got -0.1"),
            ("2.5", "target.friction: must be in [0, 2], got 2.5"),
            (
                "[0.4, 0.2]",
                "target.friction: a range is written [low, high]; got [0.4, 0.2] (reversed)",
            ),
            ("[0.2, 3]", "target.friction[1]: must be in [0, 2], got 3"),
            (
                "{\"static\": 0.2, \"kinetic\": 0.3}",
                "target.friction.static: must be ≥ the kinetic coefficient 0.3 (got 0.2)",
            ),
            (
                "{\"static\": [0.3, 0.35], \"kinetic\": [0.2, 0.4]}",
                "target.friction.static: must be ≥ the kinetic coefficient [0.2,0.4]",
            ),
        ] {
            let e = read(text).unwrap_err();
            assert!(e.contains(expected), "{text}: {e}");
        }
        for text in [
            "\"NaN\"",
            "[0.2]",
            "[0.2, \"a\"]",
            "{\"static\": 0.3, \"kinetik\": 0.3}",
        ] {
            assert!(read(text).is_err(), "{text}");
        }
    }

    #[test]
    fn around_is_plus_minus_the_fraction() {
        let s = FrictionSpec::around(Friction::uniform(0.3), 0.2);
        assert!(s.tied);
        assert!((s.kinetic.lo - 0.24).abs() < 1e-15 && (s.kinetic.hi - 0.36).abs() < 1e-15);
    }

    /// A worked example of `scene::friction::FrictionSpec::validate_driven`.
    #[test]
    fn example_frictionspec_validate_driven() {
        use crate::scene::FrictionSpec;
        assert!(FrictionSpec::uniform(0.3)
            .validate_driven("target.friction")
            .is_ok());
        let e = FrictionSpec::uniform(0.0)
            .validate_driven("target.friction")
            .unwrap_err();
        assert!(e
            .to_string()
            .starts_with("target.friction: μ_k = 0 is a frictionless plate"));
        let e = FrictionSpec::range(-0.0, 0.4)
            .validate_driven("target.friction")
            .unwrap_err();
        assert!(e.to_string().starts_with("target.friction[0]: μ_k = 0 "));
    }
}
