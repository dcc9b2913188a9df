//! `platefield export --response RESPONSE.json`: the drive signals that
//! make a shaker with a measured response play a design.
//!
//! **The response.** Per harmonic n of the design's fundamental ω = 2π/T,
//! a complex 6 × 6 matrix H_n from the six drive channels to the six plate
//! accelerations of the export (`super::CHANNELS`: linear, then world
//! angular), in phasors: a drive d_j(t) = Im(D_j e^{inωt}) makes the plate
//! play a_i(t) = Im(Σ_j H_n\[i\]\[j\] D_j e^{inωt}) in steady state. A term
//! A sin(nωt + φ) is the phasor A e^{iφ}. The file:
//!
//! ```text
//! {"harmonics": [
//!   {"harmonic": 1, "matrix": [[[re, im], … 6 columns], … 6 rows]},
//!   {"harmonic": 2, "diagonal": [[re, im], … 6]}
//! ]}
//! ```
//!
//! each entry a full matrix (row i = plate channel i, column j = drive
//! channel j) or its diagonal (channel i driven by drive i alone).
//!
//! **The drive** ([`drive`]): per harmonic the design's accelerations A_n
//! ([`super::harmonics`], so a schedule of one steady six-signal motion)
//! and D_n = H_n⁻¹ A_n. A harmonic the design holds but the response
//! lacks is refused, naming it. So is one whose H_n has a condition number
//! κ = σ_max/σ_min above [`MAX_CONDITION`]: the drive's relative error is
//! up to κ times the response's, and an FRF known to 0.1 % then gives a
//! drive off by up to 100 %, so beyond 1e3 the inverse amplifies
//! the measurement more than it corrects the shaker (the round-off of the
//! solve, κ·1e-16, stays below 1e-12 of the drive).

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::Path;

use nalgebra::{Complex, Matrix6, Vector6};
use serde::Deserialize;

use super::harmonics::{Harmonics, Term};
use super::FRAME;
use crate::error::{Error, Result};

/// Largest condition number of a harmonic's response that is inverted
/// (see the module documentation).
pub const MAX_CONDITION: f64 = 1e3;

/// One harmonic of a response file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct Entry {
    harmonic: u32,
    #[serde(default)]
    matrix: Option<Vec<Vec<[f64; 2]>>>,
    #[serde(default)]
    diagonal: Option<Vec<[f64; 2]>>,
}

#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    harmonics: Vec<Entry>,
}

/// A measured shaker response: per harmonic the 6 × 6 matrix from drive
/// to plate accelerations (see the module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Response {
    /// H_n by harmonic n.
    pub harmonics: BTreeMap<u32, Matrix6<Complex<f64>>>,
}

impl Response {
    /// Reads a response file (`source` names it in errors).
    ///
    /// # Errors
    /// Bad JSON or a bad entry: names the JSON path (`{source}.harmonics[i]…`)
    /// and what is allowed.
    pub(crate) fn from_json_str(text: &str, source: &str) -> Result<Response> {
        let file: File =
            crate::input::from_str(text, source).map_err(|e| Error::invalid(e.path, e.message))?;
        let mut harmonics = BTreeMap::new();
        for (i, e) in file.harmonics.iter().enumerate() {
            let at = format!("{source}.harmonics[{i}]");
            if e.harmonic == 0 {
                return Err(Error::invalid(format!("{at}.harmonic"), "must be ≥ 1"));
            }
            let finite = |v: &[f64; 2]| v.iter().all(|x| x.is_finite());
            let m = match (&e.matrix, &e.diagonal) {
                (Some(rows), None) => {
                    if rows.len() != 6 || rows.iter().any(|r| r.len() != 6) {
                        return Err(Error::invalid(
                            format!("{at}.matrix"),
                            "must be 6 rows of 6 [re, im] pairs (row: plate channel, column: drive channel)",
                        ));
                    }
                    if !rows.iter().flatten().all(finite) {
                        return Err(Error::invalid(
                            format!("{at}.matrix"),
                            "every entry must be finite",
                        ));
                    }
                    Matrix6::from_fn(|r, c| Complex::new(rows[r][c][0], rows[r][c][1]))
                }
                (None, Some(d)) => {
                    if d.len() != 6 || !d.iter().all(finite) {
                        return Err(Error::invalid(
                            format!("{at}.diagonal"),
                            "must be 6 finite [re, im] pairs (one per channel)",
                        ));
                    }
                    Matrix6::from_diagonal(&Vector6::from_fn(|r, _| Complex::new(d[r][0], d[r][1])))
                }
                _ => {
                    return Err(Error::invalid(
                        at,
                        "needs exactly one of \"matrix\" (6 × 6) and \"diagonal\" (6)",
                    ))
                }
            };
            if harmonics.insert(e.harmonic, m).is_some() {
                return Err(Error::invalid(
                    format!("{at}.harmonic"),
                    format!("harmonic {} is given twice", e.harmonic),
                ));
            }
        }
        Ok(Response { harmonics })
    }

    /// Reads the response file at `path`.
    ///
    /// # Errors
    /// An unreadable file (names it), or `Response::from_json_str`'s.
    pub fn read(path: &Path) -> Result<Response> {
        let text = crate::input::read_input(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        Response::from_json_str(&text, &path.display().to_string())
    }
}

/// The condition number σ_max/σ_min of `m` (infinite when singular).
pub(crate) fn condition(m: &Matrix6<Complex<f64>>) -> f64 {
    let s = m.singular_values();
    let (hi, lo) = (s.max(), s.min());
    if lo > 0.0 {
        hi / lo
    } else {
        f64::INFINITY
    }
}

/// The six phasors of `terms` at each harmonic.
pub(crate) fn phasors(terms: &[Term]) -> BTreeMap<u32, Vector6<Complex<f64>>> {
    let mut out: BTreeMap<u32, Vector6<Complex<f64>>> = BTreeMap::new();
    for t in terms {
        out.entry(t.harmonic).or_insert_with(Vector6::zeros)[t.channel] +=
            Complex::from_polar(t.amplitude, t.phase);
    }
    out
}

/// The drive signals of a design through a response: per drive channel the
/// terms A sin(nωt + φ) (module documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct Drive {
    /// Period T (s) of the fundamental.
    pub period: f64,
    /// The drive's terms: `channel` j is drive channel j (column j of H).
    pub terms: Vec<Term>,
    /// The condition number of each harmonic's response used.
    pub conditions: Vec<(u32, f64)>,
}

/// The drive that makes the response `r` play `design` (see the module
/// documentation).
///
/// # Errors
/// A harmonic of the design the response lacks, or whose response has a
/// condition number above [`MAX_CONDITION`] (both name `--response` and
/// the harmonic).
pub fn drive(design: &Harmonics, r: &Response) -> Result<Drive> {
    let mut terms = Vec::new();
    let mut conditions = Vec::new();
    for (n, a) in phasors(&design.terms) {
        let Some(h) = r.harmonics.get(&n) else {
            return Err(Error::invalid(
                "--response",
                format!(
                    "has no harmonic {n}, which the design holds (largest phasor {:.3e}); measure the response there too",
                    a.iter().fold(0.0_f64, |m, c| m.max(c.norm()))
                ),
            ));
        };
        let k = condition(h);
        if k.is_nan() || k > MAX_CONDITION {
            return Err(Error::invalid(
                "--response",
                format!(
                    "harmonic {n}: the response's condition number is {k:.3e}, over {MAX_CONDITION:e} (its inverse would amplify the measurement's error {k:.1e} times): measure it again or drive fewer channels there"
                ),
            ));
        }
        let Some(d) = h.full_piv_lu().solve(&a) else {
            return Err(Error::invalid(
                "--response",
                format!("harmonic {n}: the response is singular"),
            ));
        };
        conditions.push((n, k));
        for (channel, c) in d.iter().enumerate() {
            if c.norm() > 0.0 {
                terms.push(Term {
                    channel,
                    harmonic: n,
                    amplitude: c.norm(),
                    phase: c.arg(),
                });
            }
        }
    }
    terms.sort_by_key(|t| (t.channel, t.harmonic));
    Ok(Drive {
        period: design.period,
        terms,
        conditions,
    })
}

impl Drive {
    /// The CSV `export --response` writes: comment lines (`# `) stating the
    /// form, the response's condition numbers and the design's frame, then
    /// `channel,harmonic,amplitude,phase_rad` rows with drive channels
    /// `drive_1` … `drive_6` (column j of the response is `drive_j+1`).
    pub fn to_csv(&self) -> String {
        let mut out = format!(
            "# platefield export --response: the drive signals d_j(t) = amplitude · sin(harmonic · ω t + phase), ω = 2π/T, T = {} s, that make a shaker with the given response play the design's steady cycle (drive_j is column j of each harmonic's matrix); ramp them in from rest\n",
            self.period
        );
        let k: Vec<String> = self
            .conditions
            .iter()
            .map(|(n, k)| format!("{n}: {k:.3e}"))
            .collect();
        let _ = writeln!(
            out,
            "# the response's condition number per harmonic (refused above {MAX_CONDITION:e}): {}",
            k.join(", ")
        );
        let _ = writeln!(out, "# the plate accelerations it plays: {FRAME}");
        out.push_str("channel,harmonic,amplitude,phase_rad\n");
        for t in &self.terms {
            let _ = writeln!(
                out,
                "drive_{},{},{},{}",
                t.channel + 1,
                t.harmonic,
                t.amplitude,
                t.phase
            );
        }
        out
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `schedule::export::response::Response::from_json_str`.
    #[test]
    fn example_response_from_json_str() {
        use crate::schedule::export::response::Response;
        let r = Response::from_json_str(
            r#"{"harmonics": [{"harmonic": 1,
            "diagonal": [[2, 0], [2, 0], [2, 0], [1, 1], [1, 1], [1, 1]]}]}"#,
            "r.json",
        )
        .unwrap();
        assert_eq!(r.harmonics[&1][(3, 3)].im, 1.0);
        let e = Response::from_json_str(
            r#"{"harmonics": [{"harmonic": 1, "diagonal": [[1, 0]]}]}"#,
            "r.json",
        );
        assert!(e
            .unwrap_err()
            .to_string()
            .contains("r.json.harmonics[0].diagonal"));
    }

    /// A worked example of `schedule::export::response::drive`.
    #[test]
    fn example_drive() {
        use crate::motion::Signals;
        use crate::schedule::export::{
            harmonics::of_signals,
            response::{drive, phasors, Response},
        };
        use nalgebra::{Complex, Matrix6};

        let design = of_signals(&Signals::example());
        // A shaker that plays every channel at half the drive, a quarter turn late.
        let h = Matrix6::identity() * Complex::new(0.0, -0.5);
        let r = Response {
            harmonics: (1..=2).map(|n| (n, h)).collect(),
        };
        let d = drive(&design, &r).unwrap();
        let (want, got) = (phasors(&design.terms), phasors(&d.terms));
        for (n, a) in &want {
            assert!((h * got[n] - a).norm() < 1e-12 * a.norm());
        }
    }
}
