//! Line plots (convergence curves, sweeps), optionally log-log.

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::svg::{self, num, write_atomic, AXIS_COLOR, PALETTE};
use crate::plot::ticks::{log_ticks, nice_range};

/// How a series is stroked.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LineStyle {
    /// Solid line.
    #[default]
    Solid,
    /// Dashed line.
    Dashed,
    /// No line (markers only, if enabled).
    None,
}

/// One data series of a [`LinePlot`].
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry (empty: not listed in the legend).
    pub name: String,
    /// Data points `[x, y]`. Non-finite points (and non-positive ones on a
    /// log axis) are skipped; lines break there.
    pub points: Vec<[f64; 2]>,
    /// CSS colour; `None` picks from [`PALETTE`] by series index.
    pub color: Option<String>,
    /// Line style.
    pub line: LineStyle,
    /// Draw a circular marker at every point.
    pub markers: bool,
}

impl Series {
    /// A solid line without markers.
    pub fn new(name: impl Into<String>, points: Vec<[f64; 2]>) -> Self {
        Series {
            name: name.into(),
            points,
            color: None,
            line: LineStyle::Solid,
            markers: false,
        }
    }

    /// Builds the points from separate x and y slices (the shorter length
    /// wins).
    pub fn from_xy(name: impl Into<String>, x: &[f64], y: &[f64]) -> Self {
        Series::new(name, x.iter().zip(y).map(|(&a, &b)| [a, b]).collect())
    }

    /// Sets the colour.
    pub fn color(mut self, color: impl Into<String>) -> Self {
        self.color = Some(color.into());
        self
    }

    /// Dashed line.
    pub fn dashed(mut self) -> Self {
        self.line = LineStyle::Dashed;
        self
    }

    /// Adds markers (keeps the line).
    pub fn markers(mut self) -> Self {
        self.markers = true;
        self
    }

    /// Markers only, no line.
    pub fn markers_only(mut self) -> Self {
        self.markers = true;
        self.line = LineStyle::None;
        self
    }
}

/// Where the legend goes (inside the plot area).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum LegendPosition {
    /// Top right corner (default).
    #[default]
    TopRight,
    /// Top left corner.
    TopLeft,
    /// Bottom left corner.
    BottomLeft,
    /// Bottom right corner.
    BottomRight,
    /// No legend.
    Hidden,
}

/// A line plot with nice 1-2-5 ticks (or decades on log axes) and a legend.
///
/// ```ignore
/// use platefield_report::plot::{LinePlot, Series};
/// let plot = LinePlot::new("convergence")
///     .labels("iteration", "residual (m/s)")
///     .log_y()
///     .series(Series::new("LP", pts).markers());
/// plot.write(Path::new("results/convergence.svg"))?;
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LinePlot {
    /// Title above the plot (empty: none).
    pub title: String,
    /// Label below the x axis.
    pub x_label: String,
    /// Label left of the y axis (rotated).
    pub y_label: String,
    /// The data.
    pub series: Vec<Series>,
    /// Logarithmic x axis.
    pub log_x: bool,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Fixed x range (otherwise from the data, widened to nice ticks).
    pub x_range: Option<[f64; 2]>,
    /// Fixed y range (otherwise from the data, widened to nice ticks).
    pub y_range: Option<[f64; 2]>,
    /// Legend placement.
    pub legend: LegendPosition,
    /// Image width in px (default 640).
    pub width: f64,
    /// Image height in px (default 420).
    pub height: f64,
}

/// Mapping of one axis from data to pixels.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    pub px0: f64,
    pub px1: f64,
}

impl Axis {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// Pixel coordinate of `v` (`None` if not representable).
    pub fn map(&self, v: f64) -> Option<f64> {
        if !v.is_finite() || (self.log && v <= 0.0) {
            return None;
        }
        let (a, b) = (self.t(self.lo), self.t(self.hi));
        let px = self.px0 + (self.t(v) - a) / (b - a) * (self.px1 - self.px0);
        px.is_finite().then_some(px)
    }
}

/// A line plot's area: its axes' mappings and ticks.
struct Frame {
    ax: Axis,
    ay: Axis,
    xticks: TickList,
    yticks: TickList,
}

impl Frame {
    /// The plot area's pixel bounds `[left, top, right, bottom]`.
    fn bounds(&self) -> [f64; 4] {
        [self.ax.px0, self.ay.px1, self.ax.px1, self.ay.px0]
    }

    /// Grid lines at the major ticks.
    fn render_grid(&self, out: &mut String) {
        let [left, top, right, bottom] = self.bounds();
        let _ = writeln!(
            out,
            r#"<g class="grid" stroke="{GRID_COLOR}" stroke-width="1">"#
        );
        for (v, _, _) in self.xticks.iter().filter(|t| t.2) {
            if let Some(x) = self.ax.map(*v) {
                let _ = writeln!(
                    out,
                    r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
                    num(top),
                    num(bottom),
                    x = num(x)
                );
            }
        }
        for (v, _, _) in self.yticks.iter().filter(|t| t.2) {
            if let Some(y) = self.ay.map(*v) {
                let _ = writeln!(
                    out,
                    r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}"/>"#,
                    num(left),
                    num(right),
                    y = num(y)
                );
            }
        }
        let _ = writeln!(out, "</g>");
    }

    /// The frame and its tick marks (major 5 px, minor 3 px).
    fn render_axes(&self, out: &mut String) {
        let bounds = self.bounds();
        let [left, _, _, bottom] = bounds;
        svg::open_axes(out, bounds);
        for (v, _, major) in &self.xticks {
            if let Some(x) = self.ax.map(*v) {
                svg::x_tick(out, x, bottom, if *major { 5.0 } else { 3.0 });
            }
        }
        for (v, _, major) in &self.yticks {
            if let Some(y) = self.ay.map(*v) {
                svg::y_tick(out, y, left, if *major { 5.0 } else { 3.0 });
            }
        }
        let _ = writeln!(out, "</g>");
    }

    /// The major ticks' labels.
    fn render_tick_labels(&self, out: &mut String) {
        let [left, _, _, bottom] = self.bounds();
        let _ = writeln!(out, r#"<g class="tick-labels" fill="{AXIS_COLOR}">"#);
        for (v, label, major) in &self.xticks {
            if let (true, Some(x)) = (*major, self.ax.map(*v)) {
                let _ = writeln!(
                    out,
                    r#"<text x="{}" y="{}" text-anchor="middle">{label}</text>"#,
                    num(x),
                    num(bottom + 18.0)
                );
            }
        }
        for (v, label, major) in &self.yticks {
            if let (true, Some(y)) = (*major, self.ay.map(*v)) {
                let _ = writeln!(
                    out,
                    r#"<text x="{}" y="{}" text-anchor="end">{label}</text>"#,
                    num(left - 8.0),
                    num(y + 4.0)
                );
            }
        }
        let _ = writeln!(out, "</g>");
    }
}

const MARGIN_LEFT: f64 = 72.0;
const MARGIN_RIGHT: f64 = 20.0;
const MARGIN_TOP: f64 = 36.0;
const MARGIN_BOTTOM: f64 = 52.0;
const GRID_COLOR: &str = "#e6e6e6";

/// Data range of the values accepted on an axis.
fn data_range(values: impl Iterator<Item = f64>, log: bool) -> Option<[f64; 2]> {
    let mut r: Option<[f64; 2]> = None;
    for v in values.filter(|v| v.is_finite() && (!log || *v > 0.0)) {
        r = Some(match r {
            None => [v, v],
            Some([a, b]) => [a.min(v), b.max(v)],
        });
    }
    r
}

/// Tick marks of one axis: `(value, label markup, is_major)`.
type TickList = Vec<(f64, String, bool)>;

/// Resolves the final axis range and its ticks.
fn axis_ticks(
    range: Option<[f64; 2]>,
    fixed: bool,
    log: bool,
    target: usize,
) -> ([f64; 2], TickList) {
    if log {
        let [lo, hi] = range.unwrap_or([1.0, 10.0]);
        let (r, majors, minors) = log_ticks(lo, hi);
        let r = if fixed { [lo, hi] } else { r };
        let mut ticks: TickList = majors
            .iter()
            .map(|&e| {
                let v: f64 = format!("1e{e}").parse().unwrap_or(f64::NAN);
                let label = format!(r#"10<tspan dy="-5" font-size="9">{e}</tspan>"#);
                (v, label, true)
            })
            .collect();
        ticks.extend(minors.into_iter().map(|v| (v, String::new(), false)));
        ticks.retain(|(v, _, _)| *v >= r[0] * (1.0 - 1e-9) && *v <= r[1] * (1.0 + 1e-9));
        return (r, ticks);
    }
    let [mut lo, mut hi] = range.unwrap_or([0.0, 1.0]);
    if hi <= lo {
        let pad = if lo == 0.0 { 1.0 } else { 0.5 * lo.abs() };
        lo -= pad;
        hi += pad;
    }
    let (r, ticks) = nice_range(lo, hi, target);
    let r = if fixed { [lo, hi] } else { r };
    let labels = ticks.labels();
    let list = ticks
        .values()
        .into_iter()
        .zip(labels)
        .filter(|(v, _)| {
            let eps = 1e-9 * (r[1] - r[0]);
            *v >= r[0] - eps && *v <= r[1] + eps
        })
        .map(|(v, l)| (v, svg::escape(&l), true))
        .collect();
    (r, list)
}

impl LinePlot {
    /// An empty plot with the given title and default size 640 × 420.
    pub fn new(title: impl Into<String>) -> Self {
        LinePlot {
            title: title.into(),
            x_label: String::new(),
            y_label: String::new(),
            series: Vec::new(),
            log_x: false,
            log_y: false,
            x_range: None,
            y_range: None,
            legend: LegendPosition::TopRight,
            width: 640.0,
            height: 420.0,
        }
    }

    /// Sets the axis labels.
    pub fn labels(mut self, x: impl Into<String>, y: impl Into<String>) -> Self {
        self.x_label = x.into();
        self.y_label = y.into();
        self
    }

    /// Adds a series.
    pub fn series(mut self, s: Series) -> Self {
        self.series.push(s);
        self
    }

    /// Logarithmic x axis.
    pub(crate) fn log_x(mut self) -> Self {
        self.log_x = true;
        self
    }

    /// Logarithmic y axis.
    pub fn log_y(mut self) -> Self {
        self.log_y = true;
        self
    }

    /// Logarithmic x and y axes (convergence plots).
    pub fn log_log(self) -> Self {
        self.log_x().log_y()
    }

    /// Sets the image size in px.
    pub fn size(mut self, width: f64, height: f64) -> Self {
        self.width = width;
        self.height = height;
        self
    }

    /// Sets the legend position.
    pub fn legend(mut self, pos: LegendPosition) -> Self {
        self.legend = pos;
        self
    }

    /// Renders the plot as a standalone SVG document (deterministic: the same
    /// plot always gives the same bytes).
    pub fn to_svg(&self) -> String {
        let mut out = String::new();
        svg::open(&mut out, self.width, self.height);
        self.render(&mut out, "lp");
        svg::close(&mut out);
        out
    }

    /// Writes [`LinePlot::to_svg`] to `path` atomically.
    pub fn write(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        write_atomic(path.as_ref(), self.to_svg().as_bytes())
    }

    /// Renders the plot's elements (no `<svg>` wrapper) at the origin;
    /// `id` prefixes element ids so several plots can share a document.
    pub(crate) fn render(&self, out: &mut String, id: &str) {
        let f = self.frame();
        let _ = writeln!(out, r#"<g class="line-plot">"#);
        svg::title(out, self.width, &self.title);
        f.render_grid(out);
        f.render_axes(out);
        f.render_tick_labels(out);
        self.render_axis_labels(out, &f);
        self.render_series(out, &f, id);
        self.render_legend(out, f.bounds());
        let _ = writeln!(out, "</g>");
    }

    /// The plot area, its axes' mappings and ticks.
    fn frame(&self) -> Frame {
        let (w, h) = (self.width, self.height);
        let title_space = if self.title.is_empty() {
            12.0
        } else {
            MARGIN_TOP
        };
        let (left, right) = (MARGIN_LEFT, (w - MARGIN_RIGHT).max(MARGIN_LEFT + 10.0));
        let (top, bottom) = (title_space, (h - MARGIN_BOTTOM).max(title_space + 10.0));

        let xs = self
            .series
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p[0]));
        let ys = self.series.iter().flat_map(|s| {
            s.points
                .iter()
                .filter(|p| p[0].is_finite() && (!self.log_x || p[0] > 0.0))
                .map(|p| p[1])
        });
        let xr = self.x_range.or_else(|| data_range(xs, self.log_x));
        let yr = self.y_range.or_else(|| data_range(ys, self.log_y));
        let target_x = ((right - left) / 80.0).round().clamp(3.0, 10.0) as usize;
        let target_y = ((bottom - top) / 60.0).round().clamp(3.0, 10.0) as usize;
        let (xr, xticks) = axis_ticks(xr, self.x_range.is_some(), self.log_x, target_x);
        let (yr, yticks) = axis_ticks(yr, self.y_range.is_some(), self.log_y, target_y);
        Frame {
            ax: Axis {
                lo: xr[0],
                hi: xr[1],
                log: self.log_x,
                px0: left,
                px1: right,
            },
            ay: Axis {
                lo: yr[0],
                hi: yr[1],
                log: self.log_y,
                px0: bottom,
                px1: top,
            },
            xticks,
            yticks,
        }
    }

    /// The x and y axis labels.
    fn render_axis_labels(&self, out: &mut String, f: &Frame) {
        let [left, top, right, bottom] = f.bounds();
        if !self.x_label.is_empty() {
            svg::text(
                out,
                (left + right) / 2.0,
                bottom + 38.0,
                "middle",
                "",
                &self.x_label,
            );
        }
        if !self.y_label.is_empty() {
            let (x, y) = (18.0, (top + bottom) / 2.0);
            let _ = writeln!(
                out,
                r#"<text x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">{}</text>"#,
                svg::escape(&self.y_label),
                x = num(x),
                y = num(y)
            );
        }
    }

    /// The data, clipped to the plot area: a path per series (unless
    /// [`LineStyle::None`]) and its markers.
    fn render_series(&self, out: &mut String, f: &Frame, id: &str) {
        let [left, top, right, bottom] = f.bounds();
        let clip = format!("{id}-clip");
        let _ = writeln!(
            out,
            r#"<defs><clipPath id="{clip}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath></defs>"#,
            num(left),
            num(top),
            num(right - left),
            num(bottom - top)
        );
        let _ = writeln!(out, r#"<g class="series" clip-path="url(#{clip})">"#);
        for (i, s) in self.series.iter().enumerate() {
            let color = s
                .color
                .clone()
                .unwrap_or_else(|| PALETTE[i % PALETTE.len()].into());
            let color = svg::escape(&color);
            let mapped: Vec<Option<[f64; 2]>> = s
                .points
                .iter()
                .map(|p| Some([f.ax.map(p[0])?, f.ay.map(p[1])?]))
                .collect();
            if s.line != LineStyle::None {
                let d = svg::path_data(mapped.iter().copied());
                if !d.is_empty() {
                    let dash = if s.line == LineStyle::Dashed {
                        r#" stroke-dasharray="6 4""#
                    } else {
                        ""
                    };
                    let _ = writeln!(
                        out,
                        r#"<path d="{d}" fill="none" stroke="{color}" stroke-width="1.8" stroke-linejoin="round"{dash}/>"#
                    );
                }
            }
            if s.markers {
                let _ = writeln!(out, r#"<g fill="{color}">"#);
                for [x, y] in mapped.iter().flatten() {
                    let _ = writeln!(out, r#"<circle cx="{}" cy="{}" r="3"/>"#, num(*x), num(*y));
                }
                let _ = writeln!(out, "</g>");
            }
        }
        let _ = writeln!(out, "</g>");
    }

    fn render_legend(&self, out: &mut String, [left, top, right, bottom]: [f64; 4]) {
        let entries: Vec<(usize, &Series)> = self
            .series
            .iter()
            .enumerate()
            .filter(|(_, s)| !s.name.is_empty())
            .collect();
        if entries.is_empty() || self.legend == LegendPosition::Hidden {
            return;
        }
        let row = 16.0;
        // Rough text width estimate: 6.5 px per character at 12 px.
        let longest = entries
            .iter()
            .map(|(_, s)| s.name.chars().count())
            .max()
            .unwrap_or(0) as f64;
        let bw = 40.0 + 6.5 * longest;
        let bh = 8.0 + row * entries.len() as f64;
        let x = match self.legend {
            LegendPosition::TopLeft | LegendPosition::BottomLeft => left + 8.0,
            _ => right - 8.0 - bw,
        };
        let y = match self.legend {
            LegendPosition::BottomLeft | LegendPosition::BottomRight => bottom - 8.0 - bh,
            _ => top + 8.0,
        };
        let _ = writeln!(out, r#"<g class="legend">"#);
        let _ = writeln!(
            out,
            r##"<rect x="{}" y="{}" width="{}" height="{}" fill="white" fill-opacity="0.85" stroke="#999999" stroke-width="0.8"/>"##,
            num(x),
            num(y),
            num(bw),
            num(bh)
        );
        for (row_i, (i, s)) in entries.iter().enumerate() {
            let color = s
                .color
                .clone()
                .unwrap_or_else(|| PALETTE[i % PALETTE.len()].into());
            let color = svg::escape(&color);
            let cy = y + 4.0 + row * (row_i as f64 + 0.5);
            if s.line != LineStyle::None {
                let dash = if s.line == LineStyle::Dashed {
                    r#" stroke-dasharray="6 4""#
                } else {
                    ""
                };
                let _ = writeln!(
                    out,
                    r#"<line x1="{}" y1="{cy}" x2="{}" y2="{cy}" stroke="{color}" stroke-width="1.8"{dash}/>"#,
                    num(x + 6.0),
                    num(x + 30.0),
                    cy = num(cy)
                );
            }
            if s.markers {
                let _ = writeln!(
                    out,
                    r#"<circle cx="{}" cy="{}" r="3" fill="{color}"/>"#,
                    num(x + 18.0),
                    num(cy)
                );
            }
            svg::text(out, x + 36.0, cy + 4.0, "start", "", &s.name);
        }
        let _ = writeln!(out, "</g>");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::test_support::assert_well_formed;

    fn sample() -> LinePlot {
        LinePlot::new("Convergence <LP & QP>")
            .labels("iteration", "residual (m/s)")
            .series(Series::new("LP", vec![[0.0, 0.05], [1.0, 0.02], [2.0, 0.011]]).markers())
            .series(
                Series::from_xy("QP", &[0.0, 1.0, 2.0, 3.0], &[0.04, f64::NAN, 0.01, 0.005])
                    .dashed(),
            )
    }

    #[test]
    fn deterministic_and_well_formed() {
        let a = sample().to_svg();
        let b = sample().to_svg();
        assert_eq!(a, b);
        assert_well_formed(&a);
        assert!(a.contains("Convergence &lt;LP &amp; QP&gt;"));
        assert!(!a.contains("NaN"));
        assert!(a.contains("stroke-dasharray"));
        assert!(a.contains(r#"<g class="legend">"#));
    }

    #[test]
    fn nan_points_are_skipped_and_break_the_line() {
        let svg = sample().to_svg();
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
        // The QP line has a gap: two M commands in its path.
        let qp = svg
            .lines()
            .find(|l| l.contains("stroke-dasharray") && l.starts_with("<path"))
            .unwrap();
        assert_eq!(qp.matches('M').count(), 2, "{qp}");
    }

    #[test]
    fn all_nan_and_empty_plots_render() {
        let p = LinePlot::new("").series(Series::new("x", vec![[f64::NAN, f64::NAN]]));
        let svg = p.to_svg();
        assert_well_formed(&svg);
        assert!(!svg.contains("NaN"));
        assert_well_formed(&LinePlot::new("empty").log_log().to_svg());
    }

    #[test]
    fn log_log_axes() {
        let pts: Vec<[f64; 2]> = (1..=100)
            .map(|i| [i as f64, 1.0 / (i * i) as f64])
            .collect();
        let p = LinePlot::new("rate")
            .log_log()
            .series(Series::new("1/n²", pts))
            .series(Series::new(
                "bad",
                vec![[0.0, 1.0], [-1.0, 2.0], [5.0, 0.0]],
            ));
        let svg = p.to_svg();
        assert_well_formed(&svg);
        assert!(svg.contains(r#"10<tspan dy="-5" font-size="9">-4</tspan>"#));
        assert!(svg.contains(r#"10<tspan dy="-5" font-size="9">2</tspan>"#));
        assert!(!svg.contains("NaN") && !svg.contains("inf"));
    }

    #[test]
    fn linear_axis_uses_nice_ticks() {
        let p = LinePlot::new("t").series(Series::new("a", vec![[0.0, 0.0], [0.05, 0.047]]));
        let svg = p.to_svg();
        for label in ["0.01", "0.02", "0.05"] {
            assert!(svg.contains(&format!(">{label}</text>")), "{label}");
        }
        assert!(!svg.contains("0.030000"));
    }

    #[test]
    fn write_is_atomic_and_identical() {
        let dir = std::env::temp_dir().join(format!("pf-lineplot-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("p.svg");
        sample().write(&path).unwrap();
        assert_eq!(std::fs::read_to_string(&path).unwrap(), sample().to_svg());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
