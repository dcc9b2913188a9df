//! Quiver plots of vector fields on the plate (axes in cm).

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::svg::{self, fmt_sig, num, write_atomic, AXIS_COLOR, INVALID_COLOR, PALETTE};
use crate::plot::ticks::nice_ticks;

/// Fraction of the sample spacing spanned by the longest arrow when the
/// scale is automatic.
pub const AUTO_ARROW_FRACTION: f64 = 0.9;

/// Default arrow colour.
pub const ARROW_COLOR: &str = "#1f3a80";

/// Where an arrow sits relative to its sample point.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Pivot {
    /// The arrow's midpoint is at the sample point (default).
    #[default]
    Middle,
    /// The arrow starts at the sample point.
    Tail,
}

/// A polyline drawn over the field, e.g. a particle trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Overlay {
    /// Vertices in metres; non-finite vertices break the line.
    pub points: Vec<[f64; 2]>,
    /// CSS colour; `None` picks from [`PALETTE`] (skipping the blue and red
    /// entries used for arrows and invalid samples) by overlay index.
    pub color: Option<String>,
    /// Stroke width in px (default 1.5).
    pub width: f64,
    /// Dashed stroke.
    pub dashed: bool,
}

impl Overlay {
    /// A solid polyline with the default colour and width.
    pub fn new(points: Vec<[f64; 2]>) -> Self {
        Overlay {
            points,
            color: None,
            width: 1.5,
            dashed: false,
        }
    }

    /// Sets the colour.
    pub(crate) fn color(mut self, color: impl Into<String>) -> Self {
        self.color = Some(color.into());
        self
    }

    /// Dashed stroke.
    pub fn dashed(mut self) -> Self {
        self.dashed = true;
        self
    }
}

/// Shape of a [`Marker`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MarkerShape {
    /// Filled circle (default).
    #[default]
    Circle,
    /// Filled square.
    Square,
    /// Filled diamond.
    Diamond,
    /// "+" sign.
    Plus,
}

/// A point marker drawn over the field (e.g. a part's start position).
#[derive(Debug, Clone, PartialEq)]
pub struct Marker {
    /// Position in metres (skipped if not finite).
    pub pos: [f64; 2],
    /// Shape.
    pub shape: MarkerShape,
    /// CSS colour.
    pub color: String,
    /// Half-size in px (default 4).
    pub size: f64,
    /// Optional text drawn to the right of the marker.
    pub label: Option<String>,
}

impl Marker {
    /// A black circle of half-size 4 px.
    pub fn new(pos: [f64; 2]) -> Self {
        Marker {
            pos,
            shape: MarkerShape::Circle,
            color: "#000000".into(),
            size: 4.0,
            label: None,
        }
    }

    /// Sets the shape.
    pub fn shape(mut self, shape: MarkerShape) -> Self {
        self.shape = shape;
        self
    }

    /// Sets the colour.
    pub(crate) fn color(mut self, color: impl Into<String>) -> Self {
        self.color = color.into();
        self
    }

    /// Sets the label.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = Some(label.into());
        self
    }
}

/// A vector field drawn as arrows at sample points, with equal x/y scale and
/// axes in centimetres.
///
/// Positions are in metres and vectors in m/s. Arrow length is
/// `|v| × scale` metres (in plot coordinates); with `scale = None` it is
/// chosen so that the longest valid arrow spans [`AUTO_ARROW_FRACTION`]
/// (0.9) × the sample spacing (see [`estimate_spacing`]). Points flagged in
/// `invalid`, and points whose vector is not finite, get a red × instead of
/// an arrow; points with a non-finite position are skipped.
#[derive(Debug, Clone, PartialEq)]
pub struct QuiverPlot {
    /// Title above the plot (empty: none).
    pub title: String,
    /// Sample positions (metres).
    pub points: Vec<[f64; 2]>,
    /// Vectors (m/s), one per point.
    pub vectors: Vec<[f64; 2]>,
    /// Per-point "invalid sample" flags (empty: all valid).
    pub invalid: Vec<bool>,
    /// Arrow scale in metres per (m/s); `None`: automatic.
    pub scale: Option<f64>,
    /// Arrow placement.
    pub pivot: Pivot,
    /// Arrow colour (CSS).
    pub color: String,
    /// Polylines (trajectories) drawn over the arrows.
    pub overlays: Vec<Overlay>,
    /// Markers drawn on top.
    pub markers: Vec<Marker>,
    /// Caption line below the axes, e.g. `max |f| = 0.012 m/s`.
    pub caption: Option<String>,
    /// Fixed x range in metres (otherwise the data extent plus half a
    /// spacing).
    pub x_range: Option<[f64; 2]>,
    /// Fixed y range in metres.
    pub y_range: Option<[f64; 2]>,
    /// Image width in px (default 420).
    pub width: f64,
    /// Image height in px (default 460).
    pub height: f64,
    /// Clip the arrows and markers to the axes frame, as overlays always
    /// are (default: no; the field plots in `results/` are drawn
    /// unclipped).
    pub clip: bool,
    /// Legend entries, drawn in a column right of the axes (empty: none).
    pub legend: Vec<LegendEntry>,
}

/// The symbol of a [`LegendEntry`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LegendSymbol {
    /// An arrow (the plot's vectors).
    Arrow,
    /// A solid line (an [`Overlay`]).
    Line,
    /// A dashed line (a dashed [`Overlay`]).
    Dashed,
    /// A small rectangle outline.
    Outline,
    /// A dashed rectangle outline.
    DashedOutline,
    /// A [`Marker`] of this shape.
    Marker(MarkerShape),
    /// A × (an invalid sample).
    Cross,
}

/// One legend entry: a symbol in a colour and its label.
#[derive(Debug, Clone, PartialEq)]
pub struct LegendEntry {
    /// Text.
    pub label: String,
    /// CSS colour of the symbol.
    pub color: String,
    /// Symbol.
    pub symbol: LegendSymbol,
}

impl LegendEntry {
    /// An entry `label` drawn as `symbol` in `color`.
    pub fn new(label: impl Into<String>, color: impl Into<String>, symbol: LegendSymbol) -> Self {
        LegendEntry {
            label: label.into(),
            color: color.into(),
            symbol,
        }
    }
}

/// Width (px) reserved right of the axes for a legend.
pub const LEGEND_WIDTH: f64 = 220.0;

/// Pixel layout of a quiver plot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuiverLayout {
    /// Pixels per metre (same for x and y).
    pub px_per_m: f64,
    /// Axes frame `[left, top, right, bottom]` in px.
    pub frame: [f64; 4],
    /// Data x range shown, metres.
    pub x_range: [f64; 2],
    /// Data y range shown, metres.
    pub y_range: [f64; 2],
}

impl QuiverLayout {
    /// Pixel position of a point in metres (y up in data, down in SVG).
    pub fn map(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.frame[0] + (p[0] - self.x_range[0]) * self.px_per_m,
            self.frame[1] + (self.y_range[1] - p[1]) * self.px_per_m,
        ]
    }
}

fn finite2(p: [f64; 2]) -> bool {
    p[0].is_finite() && p[1].is_finite()
}

/// Distinct values of `v` (sorted), merging values closer than `tol`.
fn distinct(mut v: Vec<f64>, tol: f64) -> Vec<f64> {
    v.sort_by(f64::total_cmp);
    let mut out: Vec<f64> = Vec::with_capacity(v.len());
    for x in v {
        if out.last().is_none_or(|&l| x - l > tol) {
            out.push(x);
        }
    }
    out
}

/// Typical spacing (metres) between sample points.
///
/// If the finite points form a lattice (every combination of the distinct x
/// and y values occurs exactly once), the smallest gap between neighbouring
/// distinct coordinates; otherwise `sqrt(bounding-box area / N)` (or
/// `extent / (N - 1)` for collinear points). Fewer than two points: 0.01.
pub fn estimate_spacing(points: &[[f64; 2]]) -> f64 {
    let pts: Vec<[f64; 2]> = points.iter().copied().filter(|p| finite2(*p)).collect();
    if pts.len() < 2 {
        return 0.01;
    }
    let ext = |i: usize| {
        let lo = pts.iter().map(|p| p[i]).fold(f64::INFINITY, f64::min);
        let hi = pts.iter().map(|p| p[i]).fold(f64::NEG_INFINITY, f64::max);
        hi - lo
    };
    let (lx, ly) = (ext(0), ext(1));
    let tol = 1e-6 * lx.max(ly);
    if tol == 0.0 {
        return 0.01; // all points coincide
    }
    let xs = distinct(pts.iter().map(|p| p[0]).collect(), tol);
    let ys = distinct(pts.iter().map(|p| p[1]).collect(), tol);
    if xs.len() * ys.len() == pts.len() {
        let min_gap = |v: &[f64]| {
            v.windows(2)
                .map(|w| w[1] - w[0])
                .fold(f64::INFINITY, f64::min)
        };
        let s = min_gap(&xs).min(min_gap(&ys));
        if s.is_finite() && s > 0.0 {
            return s;
        }
    }
    let n = pts.len() as f64;
    if lx > tol && ly > tol {
        (lx * ly / n).sqrt()
    } else {
        lx.max(ly) / (n - 1.0)
    }
}

const MARGIN_LEFT: f64 = 58.0;
const MARGIN_RIGHT: f64 = 16.0;

impl QuiverPlot {
    /// A quiver plot of `vectors` at `points` (default size 420 × 460).
    pub fn new(title: impl Into<String>, points: Vec<[f64; 2]>, vectors: Vec<[f64; 2]>) -> Self {
        QuiverPlot {
            title: title.into(),
            points,
            vectors,
            invalid: Vec::new(),
            scale: None,
            pivot: Pivot::Middle,
            color: ARROW_COLOR.into(),
            overlays: Vec::new(),
            markers: Vec::new(),
            caption: None,
            x_range: None,
            y_range: None,
            width: 420.0,
            height: 460.0,
            clip: false,
            legend: Vec::new(),
        }
    }

    /// Clips the arrows and markers to the axes frame.
    pub fn clip(mut self) -> Self {
        self.clip = true;
        self
    }

    /// Adds a legend entry (the legend takes [`LEGEND_WIDTH`] px right of
    /// the axes).
    pub fn legend(mut self, entry: LegendEntry) -> Self {
        self.legend.push(entry);
        self
    }

    /// Sets the per-point invalid flags.
    pub fn invalid(mut self, flags: Vec<bool>) -> Self {
        self.invalid = flags;
        self
    }

    /// Fixes the arrow scale (metres of arrow per m/s).
    pub fn scale(mut self, scale: f64) -> Self {
        self.scale = Some(scale);
        self
    }

    /// Sets the arrow pivot.
    pub fn pivot(mut self, pivot: Pivot) -> Self {
        self.pivot = pivot;
        self
    }

    /// Adds an overlay polyline.
    pub(crate) fn overlay(mut self, o: Overlay) -> Self {
        self.overlays.push(o);
        self
    }

    /// Adds a marker.
    pub(crate) fn marker(mut self, m: Marker) -> Self {
        self.markers.push(m);
        self
    }

    /// Sets the caption line.
    pub(crate) fn caption(mut self, caption: impl Into<String>) -> Self {
        self.caption = Some(caption.into());
        self
    }

    /// Sets the caption to `max |f| = <value> m/s` (3 significant digits).
    pub fn auto_caption(mut self) -> Self {
        self.caption = Some(format!("max |f| = {} m/s", fmt_sig(self.max_norm(), 3)));
        self
    }

    /// Fixes the shown region (metres).
    pub fn ranges(mut self, x: [f64; 2], y: [f64; 2]) -> Self {
        self.x_range = Some(x);
        self.y_range = Some(y);
        self
    }

    /// Sets the image size in px.
    pub fn size(mut self, width: f64, height: f64) -> Self {
        self.width = width;
        self.height = height;
        self
    }

    /// `true` if point `i` gets an arrow (finite position and vector, not
    /// flagged invalid).
    fn is_valid(&self, i: usize) -> bool {
        !self.invalid.get(i).copied().unwrap_or(false)
            && self.points.get(i).is_some_and(|p| finite2(*p))
            && self.vectors.get(i).is_some_and(|v| finite2(*v))
    }

    /// Largest `|v|` (m/s) over valid points (0 if none).
    pub(crate) fn max_norm(&self) -> f64 {
        (0..self.points.len().min(self.vectors.len()))
            .filter(|&i| self.is_valid(i))
            .map(|i| self.vectors[i][0].hypot(self.vectors[i][1]))
            .fold(0.0, f64::max)
    }

    /// Sample spacing used for automatic scaling (see
    /// [`estimate_spacing`]).
    pub fn spacing(&self) -> f64 {
        estimate_spacing(&self.points)
    }

    /// The automatic scale: 0.9 × spacing / max |v| (metres per m/s), or 0
    /// when every vector is zero.
    pub(crate) fn auto_scale(&self) -> f64 {
        let m = self.max_norm();
        if m > 0.0 {
            AUTO_ARROW_FRACTION * self.spacing() / m
        } else {
            0.0
        }
    }

    /// The scale in use: the fixed one, or [`QuiverPlot::auto_scale`].
    pub(crate) fn arrow_scale(&self) -> f64 {
        match self.scale {
            Some(s) if s.is_finite() && s >= 0.0 => s,
            _ => self.auto_scale(),
        }
    }

    /// Computes the pixel layout (equal aspect, centred in the plot area).
    pub fn layout(&self) -> QuiverLayout {
        let pad = 0.5 * self.spacing();
        let mut bb: Option<[f64; 4]> = None;
        let mut grow = |p: [f64; 2]| {
            if finite2(p) {
                bb = Some(match bb {
                    None => [p[0], p[1], p[0], p[1]],
                    Some([a, b, c, d]) => [a.min(p[0]), b.min(p[1]), c.max(p[0]), d.max(p[1])],
                });
            }
        };
        self.points.iter().for_each(|p| grow(*p));
        self.overlays
            .iter()
            .flat_map(|o| o.points.iter())
            .for_each(|p| grow(*p));
        self.markers.iter().for_each(|m| grow(m.pos));
        let [x0, y0, x1, y1] = bb.unwrap_or([-0.01, -0.01, 0.01, 0.01]);
        let fix = |r: Option<[f64; 2]>, lo: f64, hi: f64| match r {
            Some([a, b]) if a.is_finite() && b.is_finite() && a < b => [a, b],
            _ => [lo - pad, hi + pad],
        };
        let xr = fix(self.x_range, x0, x1);
        let yr = fix(self.y_range, y0, y1);
        let top = if self.title.is_empty() { 14.0 } else { 36.0 };
        let bottom_margin = if self.caption.is_some() { 62.0 } else { 44.0 };
        let (left, right) = (
            MARGIN_LEFT,
            (self.width
                - MARGIN_RIGHT
                - if self.legend.is_empty() {
                    0.0
                } else {
                    LEGEND_WIDTH
                })
            .max(MARGIN_LEFT + 10.0),
        );
        let bottom = (self.height - bottom_margin).max(top + 10.0);
        let (aw, ah) = (right - left, bottom - top);
        let k = (aw / (xr[1] - xr[0])).min(ah / (yr[1] - yr[0]));
        let (fw, fh) = ((xr[1] - xr[0]) * k, (yr[1] - yr[0]) * k);
        let fl = left + (aw - fw) / 2.0;
        let ft = top + (ah - fh) / 2.0;
        QuiverLayout {
            px_per_m: k,
            frame: [fl, ft, fl + fw, ft + fh],
            x_range: xr,
            y_range: yr,
        }
    }

    /// Renders the plot as a standalone SVG document (deterministic).
    pub fn to_svg(&self) -> String {
        let mut out = String::new();
        svg::open(&mut out, self.width, self.height);
        self.render(&mut out, "qp", None);
        svg::close(&mut out);
        out
    }

    /// Writes [`QuiverPlot::to_svg`] to `path` atomically.
    pub fn write(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        write_atomic(path.as_ref(), self.to_svg().as_bytes())
    }

    /// Renders the elements (no `<svg>` wrapper) at the origin; `id`
    /// prefixes element ids, `scale` overrides the arrow scale.
    pub(crate) fn render(&self, out: &mut String, id: &str, scale: Option<f64>) {
        let lay = self.layout();
        let [fl, ft, fr, fb] = lay.frame;
        let _ = writeln!(out, r#"<g class="quiver-plot">"#);
        svg::title(out, self.width, &self.title);
        self.render_axes(out, &lay);

        let clip = format!("{id}-clip");
        let _ = writeln!(
            out,
            r#"<defs><clipPath id="{clip}"><rect x="{}" y="{}" width="{}" height="{}"/></clipPath></defs>"#,
            num(fl),
            num(ft),
            num(fr - fl),
            num(fb - ft)
        );
        let clip_attr = if self.clip {
            format!(r#" clip-path="url(#{clip})""#)
        } else {
            String::new()
        };
        let scale = scale.unwrap_or_else(|| self.arrow_scale());
        let crosses = self.render_arrows(out, &lay, scale, &clip_attr);
        render_crosses(out, &crosses);
        self.render_overlays(out, &lay, &clip);
        if !self.markers.is_empty() {
            let _ = writeln!(out, r#"<g class="markers"{clip_attr}>"#);
            for m in self.markers.iter().filter(|m| finite2(m.pos)) {
                render_marker(out, m, lay.map(m.pos));
            }
            let _ = writeln!(out, "</g>");
        }

        if let Some(c) = &self.caption {
            svg::text(out, (fl + fr) / 2.0, self.height - 12.0, "middle", "", c);
        }
        self.render_legend(out, fr + 18.0, ft + 6.0);
        let _ = writeln!(out, "</g>");
    }

    /// The arrows of the valid points (a dot where an arrow would be
    /// shorter than half a pixel); returns the pixel positions of the
    /// invalid points, drawn as crosses by [`render_crosses`].
    fn render_arrows(
        &self,
        out: &mut String,
        lay: &QuiverLayout,
        scale: f64,
        clip_attr: &str,
    ) -> Vec<[f64; 2]> {
        let color = svg::escape(&self.color);
        let _ = writeln!(
            out,
            r#"<g class="arrows"{clip_attr} stroke="{color}" fill="none" stroke-width="1.2" stroke-linecap="round" stroke-linejoin="round">"#
        );
        let mut crosses = Vec::new();
        for (i, &p) in self.points.iter().enumerate() {
            if !finite2(p) {
                continue;
            }
            if !self.is_valid(i) {
                crosses.push(lay.map(p));
                continue;
            }
            let v = self.vectors[i];
            let norm = v[0].hypot(v[1]);
            let len = norm * scale * lay.px_per_m;
            let c = lay.map(p);
            if !(len.is_finite() && len >= 0.5) {
                let _ = writeln!(
                    out,
                    r#"<circle cx="{}" cy="{}" r="0.8" fill="{color}" stroke="none"/>"#,
                    num(c[0]),
                    num(c[1])
                );
                continue;
            }
            let u = [v[0] / norm, -v[1] / norm];
            let back = match self.pivot {
                Pivot::Middle => 0.5 * len,
                Pivot::Tail => 0.0,
            };
            let tail = [c[0] - back * u[0], c[1] - back * u[1]];
            render_arrow(out, tail, u, len);
        }
        let _ = writeln!(out, "</g>");
        crosses
    }

    /// The overlay polylines, clipped to the frame.
    fn render_overlays(&self, out: &mut String, lay: &QuiverLayout, clip: &str) {
        if self.overlays.is_empty() {
            return;
        }
        let _ = writeln!(
            out,
            r#"<g class="overlays" clip-path="url(#{clip})" fill="none">"#
        );
        for (i, o) in self.overlays.iter().enumerate() {
            let d = svg::path_data(o.points.iter().map(|p| finite2(*p).then(|| lay.map(*p))));
            if d.is_empty() {
                continue;
            }
            let color = o
                .color
                .clone()
                .unwrap_or_else(|| PALETTE[(i + 2) % PALETTE.len()].into());
            let dash = if o.dashed {
                r#" stroke-dasharray="5 3""#
            } else {
                ""
            };
            let width = if o.width.is_finite() && o.width > 0.0 {
                o.width
            } else {
                1.5
            };
            let _ = writeln!(
                out,
                r#"<path d="{d}" stroke="{}" stroke-width="{}" stroke-linejoin="round"{dash}/>"#,
                svg::escape(&color),
                num(width)
            );
        }
        let _ = writeln!(out, "</g>");
    }

    /// The legend column: one row of symbol and label per entry, from
    /// (`x`, `y`) down.
    fn render_legend(&self, out: &mut String, x: f64, y: f64) {
        if self.legend.is_empty() {
            return;
        }
        let _ = writeln!(out, r#"<g class="legend" font-size="12">"#);
        for (i, e) in self.legend.iter().enumerate() {
            let cy = y + 10.0 + 20.0 * i as f64;
            let color = svg::escape(&e.color);
            let (x0, x1) = (x, x + 24.0);
            let line = |out: &mut String, dash: &str| {
                let _ = writeln!(
                    out,
                    r#"<path d="M{} {} L{} {}" stroke="{color}" stroke-width="1.5" fill="none"{dash}/>"#,
                    num(x0),
                    num(cy),
                    num(x1),
                    num(cy)
                );
            };
            let outline = |out: &mut String, dash: &str| {
                let _ = writeln!(
                    out,
                    r#"<rect x="{}" y="{}" width="20" height="7" stroke="{color}" stroke-width="1.5" fill="none"{dash}/>"#,
                    num(x0 + 2.0),
                    num(cy - 3.5)
                );
            };
            const DASH: &str = r#" stroke-dasharray="5 3""#;
            match e.symbol {
                LegendSymbol::Line => line(out, ""),
                LegendSymbol::Dashed => line(out, DASH),
                LegendSymbol::Outline => outline(out, ""),
                LegendSymbol::DashedOutline => outline(out, DASH),
                LegendSymbol::Arrow => {
                    let _ = writeln!(
                        out,
                        r#"<path d="M{} {} L{} {} M{} {} L{} {} L{} {}" stroke="{color}" stroke-width="1.2" fill="none" stroke-linecap="round"/>"#,
                        num(x0),
                        num(cy),
                        num(x1),
                        num(cy),
                        num(x1 - 6.0),
                        num(cy - 3.0),
                        num(x1),
                        num(cy),
                        num(x1 - 6.0),
                        num(cy + 3.0)
                    );
                }
                LegendSymbol::Cross => {
                    let (cx, r) = (x0 + 12.0, 3.5);
                    let _ = writeln!(
                        out,
                        r#"<path d="M{} {} L{} {} M{} {} L{} {}" stroke="{color}" stroke-width="1.5"/>"#,
                        num(cx - r),
                        num(cy - r),
                        num(cx + r),
                        num(cy + r),
                        num(cx - r),
                        num(cy + r),
                        num(cx + r),
                        num(cy - r)
                    );
                }
                LegendSymbol::Marker(shape) => {
                    let m = Marker::new([0.0, 0.0]).shape(shape).color(e.color.clone());
                    render_marker(out, &m, [x0 + 12.0, cy]);
                }
            }
            svg::text(out, x1 + 8.0, cy + 4.0, "start", "", &e.label);
        }
        let _ = writeln!(out, "</g>");
    }

    fn render_axes(&self, out: &mut String, lay: &QuiverLayout) {
        let [fl, ft, fr, fb] = lay.frame;
        let target = |px: f64| (px / 70.0).round().clamp(3.0, 8.0) as usize;
        let xt = nice_ticks(
            lay.x_range[0] * 100.0,
            lay.x_range[1] * 100.0,
            target(fr - fl),
        );
        let yt = nice_ticks(
            lay.y_range[0] * 100.0,
            lay.y_range[1] * 100.0,
            target(fb - ft),
        );
        svg::open_axes(out, lay.frame);
        for v in xt.values() {
            svg::x_tick(out, lay.map([v / 100.0, 0.0])[0], fb, 5.0);
        }
        for v in yt.values() {
            svg::y_tick(out, lay.map([0.0, v / 100.0])[1], fl, 5.0);
        }
        let _ = writeln!(out, "</g>");
        let _ = writeln!(out, r#"<g class="tick-labels" fill="{AXIS_COLOR}">"#);
        for (v, label) in xt.values().into_iter().zip(xt.labels()) {
            let x = lay.map([v / 100.0, 0.0])[0];
            svg::text(out, x, fb + 18.0, "middle", "", &label);
        }
        for (v, label) in yt.values().into_iter().zip(yt.labels()) {
            let y = lay.map([0.0, v / 100.0])[1];
            svg::text(out, fl - 8.0, y + 4.0, "end", "", &label);
        }
        let _ = writeln!(out, "</g>");
        svg::text(out, (fl + fr) / 2.0, fb + 34.0, "middle", "", "x (cm)");
        let (x, y) = (16.0, (ft + fb) / 2.0);
        let _ = writeln!(
            out,
            r#"<text x="{x}" y="{y}" text-anchor="middle" transform="rotate(-90 {x} {y})">y (cm)</text>"#,
            x = num(x),
            y = num(y)
        );
    }
}

/// One arrow from `tail` along the unit direction `u` (pixels, y down),
/// `len` pixels long, with a head of 0.3 `len` (at most 6 px).
fn render_arrow(out: &mut String, tail: [f64; 2], u: [f64; 2], len: f64) {
    let tip = [tail[0] + len * u[0], tail[1] + len * u[1]];
    let h = (0.3 * len).min(6.0);
    let hw = 0.5 * h;
    let base = [tip[0] - h * u[0], tip[1] - h * u[1]];
    let nrm = [-u[1], u[0]];
    let _ = writeln!(
        out,
        r#"<path d="M{} {} L{} {} M{} {} L{} {} L{} {}"/>"#,
        num(tail[0]),
        num(tail[1]),
        num(tip[0]),
        num(tip[1]),
        num(base[0] + hw * nrm[0]),
        num(base[1] + hw * nrm[1]),
        num(tip[0]),
        num(tip[1]),
        num(base[0] - hw * nrm[0]),
        num(base[1] - hw * nrm[1]),
    );
}

/// A cross at each invalid point.
fn render_crosses(out: &mut String, crosses: &[[f64; 2]]) {
    if crosses.is_empty() {
        return;
    }
    let _ = writeln!(
        out,
        r#"<g class="invalid" stroke="{INVALID_COLOR}" stroke-width="1.5" stroke-linecap="round">"#
    );
    let s = 3.5;
    for &[x, y] in crosses {
        let _ = writeln!(
            out,
            r#"<path d="M{} {} L{} {} M{} {} L{} {}"/>"#,
            num(x - s),
            num(y - s),
            num(x + s),
            num(y + s),
            num(x - s),
            num(y + s),
            num(x + s),
            num(y - s)
        );
    }
    let _ = writeln!(out, "</g>");
}

fn render_marker(out: &mut String, m: &Marker, [x, y]: [f64; 2]) {
    let s = if m.size.is_finite() && m.size > 0.0 {
        m.size
    } else {
        4.0
    };
    let color = svg::escape(&m.color);
    let _ = match m.shape {
        MarkerShape::Circle => writeln!(
            out,
            r#"<circle cx="{}" cy="{}" r="{}" fill="{color}"/>"#,
            num(x),
            num(y),
            num(s)
        ),
        MarkerShape::Square => writeln!(
            out,
            r#"<rect x="{}" y="{}" width="{}" height="{}" fill="{color}"/>"#,
            num(x - s),
            num(y - s),
            num(2.0 * s),
            num(2.0 * s)
        ),
        MarkerShape::Diamond => writeln!(
            out,
            r#"<path d="M{} {} L{} {} L{} {} L{} {} Z" fill="{color}"/>"#,
            num(x),
            num(y - s),
            num(x + s),
            num(y),
            num(x),
            num(y + s),
            num(x - s),
            num(y)
        ),
        MarkerShape::Plus => writeln!(
            out,
            r#"<path d="M{} {} L{} {} M{} {} L{} {}" stroke="{color}" stroke-width="2"/>"#,
            num(x - s),
            num(y),
            num(x + s),
            num(y),
            num(x),
            num(y - s),
            num(x),
            num(y + s)
        ),
    };
    if let Some(label) = &m.label {
        svg::text(out, x + s + 3.0, y + 4.0, "start", "", label);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::test_support::{arrow_lengths, assert_well_formed};

    /// A 21 × 21 sink on ±4 cm.
    fn sink() -> QuiverPlot {
        let mut pts = Vec::new();
        for iy in 0..21 {
            for ix in 0..21 {
                pts.push([-0.04 + 0.004 * ix as f64, -0.04 + 0.004 * iy as f64]);
            }
        }
        let vecs = pts.iter().map(|p| [-0.3 * p[0], -0.3 * p[1]]).collect();
        QuiverPlot::new("sink", pts, vecs)
    }

    /// A legend takes [`LEGEND_WIDTH`] px right of the axes (the frame
    /// ends before it, the legend rows start after it), one row per entry
    /// with its label; `clip` puts the arrows and markers under the axes'
    /// clip path, and without it (the default) nothing else changes.
    #[test]
    fn legend_column_and_clipping() {
        let plain = sink().size(600.0, 460.0);
        let with = plain
            .clone()
            .clip()
            .legend(LegendEntry::new(
                "velocity",
                ARROW_COLOR,
                LegendSymbol::Arrow,
            ))
            .legend(LegendEntry::new("path", "#2ca02c", LegendSymbol::Line))
            .legend(LegendEntry::new(
                "end",
                "#000000",
                LegendSymbol::Marker(MarkerShape::Square),
            ))
            .legend(LegendEntry::new(
                "invalid",
                INVALID_COLOR,
                LegendSymbol::Cross,
            ))
            .marker(Marker::new([0.0, 0.0]));
        let (a, b) = (plain.layout().frame, with.layout().frame);
        assert!(b[2] <= 600.0 - MARGIN_RIGHT - LEGEND_WIDTH + 1e-9, "{b:?}");
        assert!(a[2] > b[2], "the legend narrows the axes: {a:?} {b:?}");
        let svg = with.to_svg();
        assert_well_formed(&svg);
        let legend = &svg[svg.find(r#"<g class="legend""#).expect("legend")..];
        for label in ["velocity", "path", "end", "invalid"] {
            assert!(legend.contains(&format!(">{label}</text>")), "{label}");
        }
        assert!(
            svg.contains(r#"<g class="arrows" clip-path="url(#qp-clip)""#),
            "{svg}"
        );
        assert!(svg.contains(r#"<g class="markers" clip-path="url(#qp-clip)">"#));
        let plain_svg = plain.to_svg();
        assert!(!plain_svg.contains(r#"class="legend""#));
        assert!(!plain_svg.contains(r#"<g class="arrows" clip-path"#));
    }

    #[test]
    fn deterministic_and_well_formed() {
        let make = || {
            let mut q = sink()
                .overlay(Overlay::new(vec![[0.03, 0.03], [0.01, 0.012], [0.0, 0.0]]))
                .overlay(Overlay::new(vec![[-0.03, 0.0], [f64::NAN, 0.0], [0.0, 0.01]]).dashed())
                .marker(Marker::new([0.03, 0.03]).label("start"))
                .marker(
                    Marker::new([0.0, 0.0])
                        .shape(MarkerShape::Diamond)
                        .color("#d62728"),
                )
                .marker(Marker::new([0.01, 0.0]).shape(MarkerShape::Square))
                .marker(Marker::new([0.02, 0.0]).shape(MarkerShape::Plus))
                .auto_caption();
            q.invalid = vec![false; q.points.len()];
            q.invalid[5] = true;
            q
        };
        let a = make().to_svg();
        assert_eq!(a, make().to_svg());
        assert_well_formed(&a);
        assert!(a.contains("max |f| = 0.017 m/s"), "caption");
        assert!(a.contains(r#"<g class="invalid""#));
        assert!(a.contains(">x (cm)</text>") && a.contains(">4</text>"));
        assert!(!a.contains("NaN"));
    }

    #[test]
    fn spacing_of_grid_and_scatter() {
        let q = sink();
        assert!((q.spacing() - 0.004).abs() < 1e-12);
        let scatter = [[0.0, 0.0], [0.01, 0.003], [0.004, 0.01], [0.01, 0.01]];
        let s = estimate_spacing(&scatter);
        assert!((s - (0.01f64 * 0.01 / 4.0).sqrt()).abs() < 1e-12);
        assert_eq!(estimate_spacing(&[[0.0, 0.0]]), 0.01);
        assert!((estimate_spacing(&[[0.0, 0.0], [0.0, 0.02], [0.0, 0.04]]) - 0.02).abs() < 1e-12);
    }

    #[test]
    fn longest_arrow_spans_09_spacing() {
        let q = sink();
        let lay = q.layout();
        let want = 0.9 * 0.004 * lay.px_per_m;
        let lengths = arrow_lengths(&q.to_svg());
        assert_eq!(lengths.len(), 21 * 21 - 1); // the centre has a zero vector
        let longest = lengths.iter().cloned().fold(0.0, f64::max);
        assert!((longest - want).abs() < 0.02, "{longest} vs {want}");
        // Arrow lengths are proportional to |v|: a point at half the
        // distance has half the length.
        let half = lengths
            .iter()
            .filter(|&&l| (l - want / 2.0).abs() < 0.02)
            .count();
        assert!(half >= 4);
    }

    #[test]
    fn fixed_scale_is_honoured() {
        // 0.01 m/s at 1 m per (m/s) = 1 cm long arrow.
        let q = QuiverPlot::new(
            "",
            vec![[0.0, 0.0], [0.02, 0.0]],
            vec![[0.01, 0.0], [0.0, 0.0]],
        )
        .scale(1.0)
        .pivot(Pivot::Tail);
        let want = 0.01 * q.layout().px_per_m;
        let l = arrow_lengths(&q.to_svg());
        assert_eq!(l.len(), 1);
        assert!((l[0] - want).abs() < 0.02, "{} vs {want}", l[0]);
    }

    #[test]
    fn nan_samples_become_crosses_or_are_skipped() {
        let q = QuiverPlot::new(
            "nan",
            vec![[0.0, 0.0], [0.01, 0.0], [f64::NAN, 0.0], [0.0, 0.01]],
            vec![
                [0.01, 0.0],
                [f64::NAN, 0.0],
                [0.01, 0.0],
                [f64::INFINITY, 1.0],
            ],
        )
        .auto_caption();
        let svg = q.to_svg();
        assert_well_formed(&svg);
        assert!(!svg.contains("NaN") && !svg.contains("inf"), "{svg}");
        assert_eq!(arrow_lengths(&svg).len(), 1);
        let crosses = svg.split(r#"<g class="invalid""#).nth(1).unwrap();
        let crosses = crosses.split("</g>").next().unwrap();
        assert_eq!(crosses.matches("<path").count(), 2);
        assert!(svg.contains("max |f| = 0.01 m/s"));
    }

    #[test]
    fn equal_aspect_layout() {
        let q = QuiverPlot::new("", vec![[0.0, 0.0], [0.08, 0.02]], vec![[0.0, 0.0]; 2]);
        let lay = q.layout();
        let [l, t, r, b] = lay.frame;
        let wx = (lay.x_range[1] - lay.x_range[0]) * lay.px_per_m;
        let wy = (lay.y_range[1] - lay.y_range[0]) * lay.px_per_m;
        assert!((r - l - wx).abs() < 1e-9 && (b - t - wy).abs() < 1e-9);
        let p = lay.map([0.0, 0.0]);
        let p2 = lay.map([0.01, 0.01]);
        assert!(((p2[0] - p[0]) + (p2[1] - p[1])).abs() < 1e-9); // y is flipped
    }
}
