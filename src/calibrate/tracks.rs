//! Camera tracks: `t_s,part,x_m,y_m[,theta_rad]` rows, read and checked.
//!
//! A header line names the columns (in any order; `theta_rad` optional and
//! not used by the point-part model); `#` lines and blank lines are
//! skipped. Each row is one observed frame of one part: time (s, on the
//! schedule's clock: t = 0 where the schedule's first period starts),
//! the part's label, and its position (m, plate frame). Frames may come at
//! any rate, interleaved between parts and with gaps.
//!
//! Every error names the file, the line and the column, and says what is
//! allowed: a value that is not a finite number, a part whose times do not
//! increase, a part with fewer than [`MIN_FRAMES`] frames, a position
//! outside the plate region (`Tracks::check_region`), tracks that
//! do not fit the played motion's duration (`Tracks::check_duration`).

use std::collections::BTreeMap;
use std::path::Path;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::field::Grid;

/// Fewest frames of a part's track: a start point and a motion need three.
pub const MIN_FRAMES: usize = 3;

/// The columns a tracks file must have, and the optional one.
pub const COLUMNS: [&str; 4] = ["t_s", "part", "x_m", "y_m"];

/// A tracks file's columns: names, where the required ones are, the
/// file's name for errors.
struct Columns<'a> {
    names: Vec<&'a str>,
    /// Positions of t_s, part, x_m, y_m.
    index: [usize; 4],
    theta: Option<usize>,
    source: &'a str,
}

impl<'a> Columns<'a> {
    /// The columns of `header` (on line `line`).
    fn new(header: &'a str, line: usize, source: &'a str) -> Result<Columns<'a>> {
        let names: Vec<&str> = header.split(',').map(str::trim).collect();
        let find = |name: &str| names.iter().position(|n| *n == name);
        let mut index = [0usize; 4];
        for (k, name) in COLUMNS.iter().enumerate() {
            index[k] = find(name).ok_or_else(|| {
                Error::invalid(
                    format!("{source} line {line}"),
                    format!(
                        "the header \"{header}\" has no column \"{name}\": expected {} (theta_rad optional)",
                        COLUMNS.join(",")
                    ),
                )
            })?;
        }
        let theta = find("theta_rad");
        Ok(Columns {
            names,
            index,
            theta,
            source,
        })
    }

    /// "FILE line L column C (name)".
    fn at(&self, line: usize, c: usize) -> String {
        format!(
            "{} line {line} column {} ({})",
            self.source,
            c + 1,
            self.names[c]
        )
    }

    /// Row `l` (on line `n`): time, position, part label.
    fn row<'l>(&self, n: usize, l: &'l str) -> Result<(f64, [f64; 2], &'l str)> {
        let fields: Vec<&str> = l.split(',').map(str::trim).collect();
        if fields.len() != self.names.len() {
            return Err(Error::invalid(
                format!("{} line {n}", self.source),
                format!(
                    "{} columns, expected {} ({})",
                    fields.len(),
                    self.names.len(),
                    self.names.join(",")
                ),
            ));
        }
        let number = |c: usize| -> Result<f64> {
            fields[c]
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    Error::invalid(
                        self.at(n, c),
                        format!("\"{}\" is not a finite number", fields[c]),
                    )
                })
        };
        let t = number(self.index[0])?;
        let r = [number(self.index[2])?, number(self.index[3])?];
        if let Some(c) = self.theta {
            number(c)?;
        }
        let part = fields[self.index[1]];
        if part.is_empty() {
            return Err(Error::invalid(
                self.at(n, self.index[1]),
                "empty part label",
            ));
        }
        Ok((t, r, part))
    }
}

/// One observed frame.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Frame {
    /// Time (s).
    pub t: f64,
    /// Position (m).
    pub r: [f64; 2],
    /// The file's line (1-based), for errors.
    #[serde(skip)]
    pub line: usize,
}

/// One part's frames in increasing time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Track {
    /// The part's label (the `part` column).
    pub part: String,
    /// Frames, times strictly increasing.
    pub frames: Vec<Frame>,
}

/// Every part's track, in order of the parts' first rows.
#[derive(Debug, Clone, PartialEq)]
pub struct Tracks {
    /// The file's name in errors.
    pub source: String,
    /// One track per part.
    pub tracks: Vec<Track>,
    /// Column (1-based) of t_s, x_m and y_m, for errors.
    columns: [usize; 3],
}

impl Tracks {
    /// Reads and parses a tracks file (`Tracks::parse`).
    ///
    /// # Errors
    /// The file cannot be read, or `Tracks::parse` refuses it.
    pub fn load(path: &Path) -> Result<Tracks> {
        let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
            path: path.display().to_string(),
            source,
        })?;
        Tracks::parse(&text, &path.display().to_string())
    }

    /// Parses tracks text; `source` names the file in errors.
    ///
    /// # Errors
    /// A missing header or column, a row with another number of columns, a
    /// value that is not a finite number, a part whose times do not
    /// strictly increase, a part with fewer than `MIN_FRAMES` frames:
    /// each names `source`, the line and the column.
    pub(crate) fn parse(text: &str, source: &str) -> Result<Tracks> {
        let mut lines = text
            .lines()
            .enumerate()
            .map(|(i, l)| (i + 1, l.trim()))
            .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
        let (hline, header) = lines.next().ok_or_else(|| {
            Error::invalid(
                source,
                format!(
                    "no header ({},theta_rad optional) and no frames",
                    COLUMNS.join(",")
                ),
            )
        })?;
        let cols = Columns::new(header, hline, source)?;
        let index = cols.index;
        let at = |line: usize, c: usize| cols.at(line, c);
        let mut order: Vec<String> = Vec::new();
        let mut by_part: BTreeMap<String, Vec<Frame>> = BTreeMap::new();
        for (n, l) in lines {
            let (t, r, part) = cols.row(n, l)?;
            let frames = by_part.entry(part.to_string()).or_insert_with(|| {
                order.push(part.to_string());
                Vec::new()
            });
            if let Some(prev) = frames.last() {
                if t <= prev.t {
                    return Err(Error::invalid(
                        at(n, index[0]),
                        format!(
                            "part \"{part}\": time {t} s does not increase (line {} has {} s); each part's times must strictly increase",
                            prev.line, prev.t
                        ),
                    ));
                }
            }
            frames.push(Frame { t, r, line: n });
        }
        if order.is_empty() {
            return Err(Error::invalid(source, "no frames after the header"));
        }
        let tracks: Vec<Track> = order
            .into_iter()
            .map(|part| {
                let frames = by_part.remove(&part).unwrap_or_default();
                Track { part, frames }
            })
            .collect();
        for tr in &tracks {
            if tr.frames.len() < MIN_FRAMES {
                let last = tr.frames.last().map_or(1, |f| f.line);
                return Err(Error::invalid(
                    at(last, index[1]),
                    format!(
                        "part \"{}\" has {} frame(s): a track needs at least {MIN_FRAMES}",
                        tr.part,
                        tr.frames.len()
                    ),
                ));
            }
        }
        Ok(Tracks {
            source: source.to_string(),
            tracks,
            columns: [index[0] + 1, index[2] + 1, index[3] + 1],
        })
    }

    /// Tracks made in memory (simulated): no file lines, the standard
    /// column order.
    pub(crate) fn from_tracks(tracks: Vec<Track>) -> Tracks {
        Tracks {
            source: "simulated tracks".into(),
            tracks,
            columns: [1, 3, 4],
        }
    }

    /// The tracks as a tracks file (`t_s,part,x_m,y_m`, frames in time
    /// order, parts in track order at equal times; positions to 0.1 µm).
    pub fn to_csv(&self) -> String {
        let mut rows: Vec<(f64, usize, [f64; 2])> = self
            .tracks
            .iter()
            .enumerate()
            .flat_map(|(i, tr)| tr.frames.iter().map(move |f| (f.t, i, f.r)))
            .collect();
        rows.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut out = format!("{}\n", COLUMNS.join(","));
        for (t, i, r) in rows {
            out.push_str(&format!(
                "{t:.6},{},{:.7},{:.7}\n",
                self.tracks[i].part, r[0], r[1]
            ));
        }
        out
    }

    /// Refuses a position outside `region` (the plate region the played
    /// motion's field is known on), naming its line and column.
    ///
    /// # Errors
    /// The first frame outside, with the region's extent.
    pub(crate) fn check_region(&self, region: &Grid) -> Result<()> {
        for tr in &self.tracks {
            for f in &tr.frames {
                for (axis, range, v) in [(0, region.x, f.r[0]), (1, region.y, f.r[1])] {
                    if !(range[0]..=range[1]).contains(&v) {
                        let (c, name) = (self.columns[1 + axis], ["x_m", "y_m"][axis]);
                        return Err(Error::invalid(
                            format!("{} line {} column {c} ({name})", self.source, f.line),
                            format!(
                                "part \"{}\" at {v} m is outside the plate region [{}, {}] m (the schedule's target grid, where its field is known)",
                                tr.part, range[0], range[1]
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Refuses tracks that do not fit the played motion: a frame before 0,
    /// tracks spanning less than one schedule `period` (the schedule's
    /// segments were not all seen), a frame after `played` seconds (how
    /// long the motion was played, when known). Names the frame's line
    /// and its t_s column.
    ///
    /// # Errors
    /// As above, with the durations involved.
    pub(crate) fn check_duration(&self, period: f64, played: Option<f64>) -> Result<()> {
        let c = self.columns[0];
        let at = |f: &Frame| format!("{} line {} column {c} (t_s)", self.source, f.line);
        let frames = || self.tracks.iter().flat_map(|t| &t.frames);
        let first = frames().min_by(|a, b| a.t.total_cmp(&b.t));
        let last = frames().max_by(|a, b| a.t.total_cmp(&b.t));
        let (Some(first), Some(last)) = (first, last) else {
            return Ok(());
        };
        if first.t < 0.0 {
            return Err(Error::invalid(
                at(first),
                format!("time {} s is before the schedule's start (t = 0 where its first period starts)", first.t),
            ));
        }
        if last.t - first.t < period {
            return Err(Error::invalid(
                at(last),
                format!(
                    "the tracks span {:.4} s, less than one schedule period ({period:.4} s): they cannot have seen every segment; is this the schedule that was played?",
                    last.t - first.t
                ),
            ));
        }
        if let Some(played) = played {
            if last.t > played {
                return Err(Error::invalid(
                    at(last),
                    format!("time {} s is after the played motion's end ({played:.4} s): is this the motion that was played?", last.t),
                ));
            }
        }
        Ok(())
    }

    /// Number of frames over all parts.
    pub(crate) fn frames(&self) -> usize {
        self.tracks.iter().map(|t| t.frames.len()).sum()
    }

    /// The tracks' position noise σ (m), estimated from the frames alone:
    /// over runs of three consecutive evenly spaced frames (spacings equal
    /// within 1 %), the second difference r₊ − 2r + r₋ of independent
    /// position noise of standard deviation σ per axis has variance 6σ²,
    /// while a smooth motion adds only a·Δt² (about 2e-5 m at a = 2 cm/s² and
    /// 30 frames per second). `None` without such a run.
    pub(crate) fn noise(&self) -> Option<f64> {
        let (mut sum, mut n) = (0.0, 0usize);
        for tr in &self.tracks {
            for w in tr.frames.windows(3) {
                let (h1, h2) = (w[1].t - w[0].t, w[2].t - w[1].t);
                if (h1 - h2).abs() > 0.01 * h1 {
                    continue;
                }
                for k in 0..2 {
                    let d = w[2].r[k] - 2.0 * w[1].r[k] + w[0].r[k];
                    sum += d * d;
                    n += 1;
                }
            }
        }
        (n > 0).then(|| (sum / n as f64 / 6.0).sqrt())
    }
}

#[cfg(test)]
mod tests {
    /// A worked example of `calibrate::tracks::Tracks::parse`.
    #[test]
    fn example_tracks_parse() -> Result<(), crate::Error> {
        use crate::calibrate::Tracks;
        let text = "t_s,part,x_m,y_m\n0,a,0.01,0\n0.1,a,0.009,0\n0.2,a,0.008,0\n";
        let tracks = Tracks::parse(text, "t.csv")?;
        assert_eq!(tracks.tracks[0].frames.len(), 3);
        let late = "t_s,part,x_m,y_m\n0,a,0.01,0\n0.2,a,0.009,0\n0.1,a,0.008,0\n";
        let e = Tracks::parse(late, "t.csv").unwrap_err().to_string();
        assert!(e.contains("t.csv line 4 column 1 (t_s)"), "{e}");
        Ok(())
    }
}
