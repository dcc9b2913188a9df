//! Reading an exported signal file back: the CSV `platefield export`
//! writes (`super::sample_hold::HoldSamples::to_csv`), as held samples
//! from rest at home.
//!
//! Lines starting with `#` are comments and blank lines are skipped. The
//! first other line is the header
//! `t_s,ax_m_s2,ay_m_s2,az_m_s2,alpha_x_rad_s2,alpha_y_rad_s2,alpha_z_rad_s2`;
//! every row after it holds 7 finite numbers. The times must start at 0
//! and be uniform: Δt = t_last/(n − 1) and every t_k within
//! `T_TOLERANCE` of kΔt (the export prints t to 1 ns). The accelerations
//! must be physical: at most [`super::LINEAR_ACCEL`], 1e4 m/s² (about
//! 1000 g), linear and [`super::ANGULAR_ACCEL`], 1e5 rad/s², angular (the
//! scenes' bounds; a shaker plays tens). Every error names
//! the file, the line and the column, and says what is allowed.

use std::path::Path;

use super::sample_hold::{CentreState, HoldSamples};
use crate::error::{Error, Result};
use crate::input::{read_capped, MAX_INPUT_BYTES};

/// The header comment that states the schedule's fingerprint, before it
/// (`# schedule fingerprint: HEX …`, written by `platefield export`).
pub const FINGERPRINT: &str = "schedule fingerprint: ";

/// The header `platefield export` writes.
pub const HEADER: &str = "t_s,ax_m_s2,ay_m_s2,az_m_s2,alpha_x_rad_s2,alpha_y_rad_s2,alpha_z_rad_s2";

/// How far a row's time may be from kΔt (s): the export prints t with 9
/// decimals (±5e-10 s), so 2e-9 s allows that and refuses a skipped or
/// repeated sample (Δt is at least 1e-7 s at the export's rates).
pub(crate) const T_TOLERANCE: f64 = 2e-9;

/// Reads the text of a file `verify --replay` takes (an export or a
/// recording) at `path`: at most [`MAX_INPUT_BYTES`], refused with the rate
/// that fits when larger, and UTF-8.
///
/// # Errors
/// An unreadable, oversized or non-UTF-8 file (names the file).
pub(crate) fn read_text(path: &Path) -> Result<String> {
    let io = |source| Error::Io {
        path: path.display().to_string(),
        source,
    };
    if let Some(too_big) = std::fs::metadata(path)
        .ok()
        .and_then(|m| over_replay_size(file_rate(path), m.len()))
    {
        return Err(Error::invalid(path.display().to_string(), too_big));
    }
    let bytes = read_capped(path, MAX_INPUT_BYTES).map_err(io)?;
    String::from_utf8(bytes).map_err(|_| {
        io(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "not UTF-8 text",
        ))
    })
}

/// What an export of `bytes` at `rate` samples/s (`None`: unknown) has to
/// say against the one size limit of a file `verify --replay` reads,
/// [`MAX_INPUT_BYTES`]: nothing when it fits, else its size, the limit
/// and the rate that fits (the size is proportional to the rate).
///
/// ```
/// use platefield::motion::held_csv::over_replay_size;
/// assert_eq!(over_replay_size(Some(1e4), 1 << 20), None);
/// let s = over_replay_size(Some(1e6), 157_000_000).unwrap();
/// assert!(s.contains("over the 64 MiB") && s.contains("--rate 427000 or lower"), "{s}");
/// ```
pub fn over_replay_size(rate: Option<f64>, bytes: u64) -> Option<String> {
    if bytes <= MAX_INPUT_BYTES {
        return None;
    }
    let mib = |b: u64| b as f64 / f64::from(1 << 20);
    let fits = match rate.filter(|r| r.is_finite() && *r > 0.0) {
        Some(r) => {
            // Three significant digits, rounded down, so that it fits.
            let fit = r * MAX_INPUT_BYTES as f64 / bytes as f64;
            let unit = 10f64.powi(fit.log10().floor() as i32 - 2);
            format!(
                "export it at --rate {} or lower to replay it",
                (fit / unit).floor() * unit
            )
        }
        None => "export it at a lower --rate to replay it (the size is proportional to the rate)"
            .to_string(),
    };
    Some(format!(
        "{:.1} MiB, over the {} MiB a file `verify --replay` reads: {fits}",
        mib(bytes),
        MAX_INPUT_BYTES >> 20
    ))
}

/// The sample rate of the export at `path`, from its first two rows'
/// times (read from its first 64 KiB); `None` when they are not there.
fn file_rate(path: &Path) -> Option<f64> {
    use std::io::Read;
    let mut head = Vec::new();
    std::fs::File::open(path)
        .ok()?
        .take(1 << 16)
        .read_to_end(&mut head)
        .ok()?;
    let text = String::from_utf8_lossy(&head);
    let mut times = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty() && !l.starts_with('#') && *l != HEADER)
        .filter_map(|l| l.split(',').next()?.trim().parse::<f64>().ok());
    let (t0, t1) = (times.next()?, times.next()?);
    Some(1.0 / (t1 - t0)).filter(|r| r.is_finite() && *r > 0.0)
}

/// The schedule fingerprint an export's header states (the comment
/// `# schedule fingerprint: HEX …` before the column header), if any.
///
/// ```
/// use platefield::motion::held_csv::{fingerprint, HEADER};
/// let csv = format!("# schedule fingerprint: 0123abcd0123abcd (of the schedule's segments)\n{HEADER}\n");
/// assert_eq!(fingerprint(&csv), Some("0123abcd0123abcd"));
/// assert_eq!(fingerprint(HEADER), None);
/// ```
pub fn fingerprint(text: &str) -> Option<&str> {
    let mark = FINGERPRINT;
    text.lines()
        .map(str::trim)
        .take_while(|l| l.is_empty() || l.starts_with('#'))
        .find_map(|l| l.trim_start_matches('#').trim_start().strip_prefix(mark))
        .and_then(|rest| rest.split_whitespace().next())
}

/// Parses an exported CSV (`source` names it in errors): the samples, Δt,
/// the whole file as one period, starting at rest in the home pose.
///
/// ```
/// use platefield::motion::held_csv::{parse, HEADER};
///
/// let csv = format!("# comment\n{HEADER}\n0,1,0,0,0,0,0\n0.001,-1,0,0,0,0,0\n");
/// let held = parse(&csv, "x.csv").unwrap();
/// assert_eq!(held.samples.len(), 2);
/// assert!((held.dt - 0.001).abs() < 1e-15);
/// let bad = format!("{HEADER}\n0,1,0,0,0,0,0\n0.001,-1,0,NaN,0,0,0\n");
/// let e = parse(&bad, "x.csv").unwrap_err().to_string();
/// assert!(e.contains("x.csv line 3 column 4 (az_m_s2)"), "{e}");
/// let huge = format!("{HEADER}\n0,1e300,0,0,0,0,0\n0.001,0,0,0,0,0,0\n");
/// let e = parse(&huge, "x.csv").unwrap_err().to_string();
/// assert!(e.contains("line 2 column 2 (ax_m_s2): 1e300 m/s² is not a physical plate acceleration: at most 1e4 m/s²"), "{e}");
/// ```
///
/// # Errors
/// A missing or wrong header, a row without 7 columns, a value that is not
/// a finite number, an acceleration over the bounds above, fewer than 2 rows, or times that do not start at 0 or
/// are not uniform: each names `source`, the line and the column.
pub fn parse(text: &str, source: &str) -> Result<HoldSamples> {
    let columns: Vec<&str> = HEADER.split(',').collect();
    let at = |line: usize, col: Option<usize>| match col {
        Some(c) => format!("{source} line {line} column {} ({})", c + 1, columns[c]),
        None => format!("{source} line {line}"),
    };
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    match lines.next() {
        Some((_, l)) if l == HEADER => {}
        Some((n, l)) => {
            return Err(Error::invalid(
                at(n, None),
                format!("expected the header \"{HEADER}\" (the CSV `platefield export` writes), got \"{l}\""),
            ))
        }
        None => {
            return Err(Error::invalid(
                source,
                format!("no header \"{HEADER}\" and no samples"),
            ))
        }
    }
    let mut rows: Vec<(usize, [f64; 7])> = Vec::new();
    for (n, l) in lines {
        let fields: Vec<&str> = l.split(',').collect();
        if fields.len() != columns.len() {
            return Err(Error::invalid(
                at(n, None),
                format!(
                    "{} columns, expected {} ({HEADER})",
                    fields.len(),
                    columns.len()
                ),
            ));
        }
        let mut row = [0.0; 7];
        for (c, f) in fields.iter().enumerate() {
            row[c] = f
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::invalid(
                        at(n, Some(c)),
                        format!("\"{}\" is not a finite number", f.trim()),
                    )
                })?;
        }
        for (c, x) in row.iter().enumerate().skip(1) {
            let (max, unit) = if c <= 3 {
                (super::LINEAR_ACCEL, "m/s²")
            } else {
                (super::ANGULAR_ACCEL, "rad/s²")
            };
            if x.abs() > max {
                return Err(Error::invalid(
                    at(n, Some(c)),
                    format!("{x:e} {unit} is not a physical plate acceleration: at most {max:e} {unit} in magnitude"),
                ));
            }
        }
        rows.push((n, row));
    }
    let dt = uniform_step(&rows, source, &at)?;
    Ok(HoldSamples {
        dt,
        rate: 1.0 / dt,
        samples_per_period: rows.len(),
        samples: rows
            .iter()
            .map(|(_, r)| std::array::from_fn(|i| r[i + 1]))
            .collect(),
        start: CentreState::default(),
    })
}

/// Δt = t_last/(n − 1), checked: t₀ = 0 and every t_k within
/// [`T_TOLERANCE`] of kΔt.
fn uniform_step(
    rows: &[(usize, [f64; 7])],
    source: &str,
    at: &dyn Fn(usize, Option<usize>) -> String,
) -> Result<f64> {
    if rows.len() < 2 {
        return Err(Error::invalid(
            source,
            format!(
                "{} sample rows, at least 2 needed (the hold time is their spacing)",
                rows.len()
            ),
        ));
    }
    let (first, last) = (rows[0], rows[rows.len() - 1]);
    if first.1[0] != 0.0 {
        return Err(Error::invalid(
            at(first.0, Some(0)),
            format!("the first sample must start at t = 0, got {}", first.1[0]),
        ));
    }
    let dt = last.1[0] / (rows.len() - 1) as f64;
    if dt <= 0.0 {
        return Err(Error::invalid(
            at(last.0, Some(0)),
            format!("times must increase, got the last at {} s", last.1[0]),
        ));
    }
    for (k, (n, r)) in rows.iter().enumerate() {
        let expected = k as f64 * dt;
        if (r[0] - expected).abs() > T_TOLERANCE {
            return Err(Error::invalid(
                at(*n, Some(0)),
                format!(
                    "{} s, expected {expected:.9} s: samples must be uniform (Δt = {dt:.9e} s from the first and last rows, each within {T_TOLERANCE:e} s)",
                    r[0]
                ),
            ));
        }
    }
    Ok(dt)
}

/// An accelerometer recording: the six plate accelerations (the export's
/// channels, world axes) at a uniform rate, read from a header-less
/// numeric CSV ([`parse_recording`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Recording {
    /// Time between rows (s).
    pub dt: f64,
    /// Per row a_x, a_y, a_z (m/s²), α_x, α_y, α_z (rad/s²).
    pub samples: Vec<[f64; 6]>,
}

/// True when the first line of `text` that is not a comment or blank is
/// all numbers: a header-less recording, not an export.
pub(crate) fn is_recording(text: &str) -> bool {
    text.lines()
        .map(str::trim)
        .find(|l| !l.is_empty() && !l.starts_with('#'))
        .is_some_and(|l| l.split(',').all(|f| f.trim().parse::<f64>().is_ok()))
}

/// Parses a header-less recording (`source` names it in errors): every
/// row `t,ax,ay,az,alpha_x,alpha_y,alpha_z` (7 columns, t in s from 0,
/// uniform as in an export) or, with `rate` (samples/s), the six channels
/// alone. `#` lines and blank lines are skipped.
///
/// ```
/// use platefield::motion::held_csv::parse_recording;
///
/// let r = parse_recording("0,1,0,0,0,0,0\n0.5,2,0,0,0,0,0\n", "m.csv", None).unwrap();
/// assert_eq!((r.dt, r.samples[1][0]), (0.5, 2.0));
/// let r = parse_recording("1,0,0,0,0,0\n2,0,0,0,0,0\n", "m.csv", Some(4.0)).unwrap();
/// assert_eq!(r.dt, 0.25);
/// let e = parse_recording("1,0,0,0,0,0\n", "m.csv", None).unwrap_err().to_string();
/// assert!(e.contains("m.csv line 1") && e.contains("--rate"), "{e}");
/// ```
///
/// # Errors
/// A row with the wrong number of columns, a value that is not a finite
/// number, fewer than 2 rows, non-uniform times, or a `rate` that is not
/// positive: each names `source`, the line and the column (or `--rate`).
pub fn parse_recording(text: &str, source: &str, rate: Option<f64>) -> Result<Recording> {
    if let Some(r) = rate {
        crate::error::positive("--rate", r)?;
    }
    let width = if rate.is_some() { 6 } else { 7 };
    let columns: Vec<&str> = HEADER.split(',').skip(7 - width).collect();
    let mut rows: Vec<(usize, [f64; 7])> = Vec::new();
    for (n, l) in text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
    {
        let fields: Vec<&str> = l.split(',').collect();
        if fields.len() != width {
            let hint = if rate.is_some() {
                "the six channels (with --rate)"
            } else {
                "t and the six channels (or the six channels alone with --rate)"
            };
            return Err(Error::invalid(
                format!("{source} line {n}"),
                format!(
                    "{} columns, expected {width}: {hint}, {}",
                    fields.len(),
                    columns.join(",")
                ),
            ));
        }
        let mut row = [0.0; 7];
        for (c, f) in fields.iter().enumerate() {
            row[c + 7 - width] = f
                .trim()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::invalid(
                        format!("{source} line {n} column {} ({})", c + 1, columns[c]),
                        format!("\"{}\" is not a finite number", f.trim()),
                    )
                })?;
        }
        if let Some(r) = rate {
            row[0] = rows.len() as f64 / r;
        }
        rows.push((n, row));
    }
    let at = |line: usize, col: Option<usize>| match col {
        Some(c) => format!(
            "{source} line {line} column {} ({})",
            c + 1,
            HEADER.split(',').nth(c).unwrap_or("")
        ),
        None => format!("{source} line {line}"),
    };
    let dt = match rate {
        Some(r) if rows.len() >= 2 => 1.0 / r,
        _ => uniform_step(&rows, source, &at)?,
    };
    Ok(Recording {
        dt,
        samples: rows
            .iter()
            .map(|(_, r)| std::array::from_fn(|i| r[i + 1]))
            .collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn csv(rows: &[&str]) -> String {
        format!("# a comment\n{HEADER}\n{}\n", rows.join("\n"))
    }

    fn error(rows: &[&str]) -> String {
        parse(&csv(rows), "f.csv").unwrap_err().to_string()
    }

    /// The export's own CSV reads back to its samples (to the 13
    /// significant digits it prints) and hold time.
    #[test]
    fn an_export_reads_back() {
        let motion = crate::motion::Motion::Signals(crate::motion::Signals::example());
        let file = crate::motion::sample_hold::periodic(&motion, 5_000.0).unwrap();
        let back = parse(&file.to_csv(), "e.csv").unwrap();
        assert_eq!(back.samples.len(), file.samples.len());
        assert!((back.dt - file.dt).abs() < 1e-12 * file.dt);
        for (a, b) in back.samples.iter().zip(&file.samples) {
            for i in 0..6 {
                assert!((a[i] - b[i]).abs() <= 1e-12 * (1.0 + b[i].abs()));
            }
        }
    }

    /// Bad rows name the line and column.
    #[test]
    fn bad_rows_name_line_and_column() {
        let e = error(&["0,1,0,0,0,0,0", "0.001,1,0,0,0,0"]);
        assert!(
            e.contains("f.csv line 4:") && e.contains("6 columns"),
            "{e}"
        );
        let e = error(&["0,1,0,0,0,0,0", "0.001,1,x,0,0,0,0"]);
        assert!(e.contains("f.csv line 4 column 3 (ay_m_s2)"), "{e}");
        let e = error(&["0,1,0,0,0,0,inf", "0.001,1,0,0,0,0,0"]);
        assert!(e.contains("line 3 column 7 (alpha_z_rad_s2)"), "{e}");
        let e = error(&[
            "0,1,0,0,0,0,0",
            "0.001,1,0,0,0,0,0",
            "0.0025,1,0,0,0,0,0",
            "0.003,1,0,0,0,0,0",
        ]);
        assert!(
            e.contains("line 5 column 1 (t_s)") && e.contains("uniform"),
            "{e}"
        );
        let e = error(&["0.5,1,0,0,0,0,0", "0.6,1,0,0,0,0,0"]);
        assert!(e.contains("line 3 column 1") && e.contains("t = 0"), "{e}");
        let e = error(&["0,1,0,0,0,0,0"]);
        assert!(e.contains("at least 2"), "{e}");
        let e = parse("t,a\n0,1\n", "f.csv").unwrap_err().to_string();
        assert!(e.contains("f.csv line 1") && e.contains("header"), "{e}");
    }
}
