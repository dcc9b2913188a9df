//! Several plots side by side in one SVG (e.g. target | achieved | residual).

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::line::LinePlot;
use crate::plot::quiver::{QuiverPlot, AUTO_ARROW_FRACTION};
use crate::plot::svg::{self, num, write_atomic};

/// One panel of a [`Panels`] figure.
#[derive(Debug, Clone, PartialEq)]
pub enum Panel {
    /// A vector field.
    Quiver(QuiverPlot),
    /// A line plot.
    Line(LinePlot),
}

impl From<QuiverPlot> for Panel {
    fn from(q: QuiverPlot) -> Self {
        Panel::Quiver(q)
    }
}

impl From<LinePlot> for Panel {
    fn from(l: LinePlot) -> Self {
        Panel::Line(l)
    }
}

impl Panel {
    fn size(&self) -> (f64, f64) {
        match self {
            Panel::Quiver(q) => (q.width, q.height),
            Panel::Line(l) => (l.width, l.height),
        }
    }
}

/// Plots laid out left to right in one SVG, each at its own size, with an
/// optional overall title.
///
/// With `share_scale` (the default), all quiver panels that have no fixed
/// scale use one common arrow scale: the largest one for which the longest
/// arrow of every panel spans at most 0.9 × that panel's spacing. Arrows are
/// then comparable across panels (a small residual shows as short arrows).
#[derive(Debug, Clone, PartialEq)]
pub struct Panels {
    /// Overall title (empty: none).
    pub title: String,
    /// The panels, left to right.
    pub panels: Vec<Panel>,
    /// Use one arrow scale for all auto-scaled quiver panels.
    pub share_scale: bool,
    /// Horizontal gap between panels in px (default 10).
    pub gap: f64,
}

const TITLE_HEIGHT: f64 = 30.0;

impl Panels {
    /// An empty figure with the given title.
    pub fn new(title: impl Into<String>) -> Self {
        Panels {
            title: title.into(),
            panels: Vec::new(),
            share_scale: true,
            gap: 10.0,
        }
    }

    /// Adds a panel (a [`QuiverPlot`] or a [`LinePlot`]).
    pub fn panel(mut self, p: impl Into<Panel>) -> Self {
        self.panels.push(p.into());
        self
    }

    /// Sets whether auto-scaled quiver panels share one arrow scale.
    pub fn share_scale(mut self, share: bool) -> Self {
        self.share_scale = share;
        self
    }

    /// The common arrow scale (metres per m/s) used for auto-scaled quiver
    /// panels when `share_scale` is on; `None` if sharing is off or no panel
    /// has a non-zero vector.
    pub(crate) fn shared_scale(&self) -> Option<f64> {
        if !self.share_scale {
            return None;
        }
        self.panels
            .iter()
            .filter_map(|p| match p {
                Panel::Quiver(q) if q.scale.is_none() => {
                    let m = q.max_norm();
                    (m > 0.0).then(|| AUTO_ARROW_FRACTION * q.spacing() / m)
                }
                _ => None,
            })
            .reduce(f64::min)
    }

    /// Total image size in px.
    pub fn size(&self) -> (f64, f64) {
        let n = self.panels.len();
        let w: f64 = self.panels.iter().map(|p| p.size().0).sum::<f64>()
            + self.gap * n.saturating_sub(1) as f64;
        let h = self.panels.iter().map(|p| p.size().1).fold(0.0, f64::max);
        let title = if self.title.is_empty() {
            0.0
        } else {
            TITLE_HEIGHT
        };
        (w.max(1.0), (h + title).max(1.0))
    }

    /// Renders the figure as a standalone SVG document (deterministic).
    pub fn to_svg(&self) -> String {
        let (w, h) = self.size();
        let mut out = String::new();
        svg::open(&mut out, w, h);
        let top = if self.title.is_empty() {
            0.0
        } else {
            svg::text(
                &mut out,
                w / 2.0,
                20.0,
                "middle",
                r#"font-size="16" font-weight="bold""#,
                &self.title,
            );
            TITLE_HEIGHT
        };
        let shared = self.shared_scale();
        let mut x = 0.0;
        for (i, p) in self.panels.iter().enumerate() {
            let _ = writeln!(
                out,
                r#"<g class="panel" transform="translate({} {})">"#,
                num(x),
                num(top)
            );
            let id = format!("p{i}");
            match p {
                Panel::Quiver(q) => {
                    let scale = if q.scale.is_none() { shared } else { None };
                    q.render(&mut out, &id, scale);
                }
                Panel::Line(l) => l.render(&mut out, &id),
            }
            let _ = writeln!(out, "</g>");
            x += p.size().0 + self.gap;
        }
        svg::close(&mut out);
        out
    }

    /// Writes [`Panels::to_svg`] to `path` atomically.
    pub fn write(&self, path: impl AsRef<Path>) -> std::io::Result<()> {
        write_atomic(path.as_ref(), self.to_svg().as_bytes())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::plot::line::Series;
    use crate::plot::test_support::{arrow_lengths, assert_well_formed};

    fn grid_field(f: impl Fn([f64; 2]) -> [f64; 2]) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
        let mut pts = Vec::new();
        for iy in 0..9 {
            for ix in 0..9 {
                pts.push([-0.04 + 0.01 * ix as f64, -0.04 + 0.01 * iy as f64]);
            }
        }
        let v = pts.iter().map(|&p| f(p)).collect();
        (pts, v)
    }

    fn figure() -> Panels {
        let (p, t) = grid_field(|p| [-p[0], -p[1]]);
        let (_, a) = grid_field(|p| [-1.2 * p[0], -1.6 * p[1]]);
        let r: Vec<[f64; 2]> = t
            .iter()
            .zip(&a)
            .map(|(t, a)| [a[0] - t[0], a[1] - t[1]])
            .collect();
        Panels::new("sink: target | achieved | residual")
            .panel(QuiverPlot::new("target", p.clone(), t).auto_caption())
            .panel(QuiverPlot::new("achieved", p.clone(), a).auto_caption())
            .panel(QuiverPlot::new("residual", p, r).auto_caption())
            .panel(
                LinePlot::new("residual").series(Series::new("r", vec![[1.0, 0.1], [2.0, 0.01]])),
            )
    }

    #[test]
    fn deterministic_well_formed_and_unique_ids() {
        let a = figure().to_svg();
        assert_eq!(a, figure().to_svg());
        assert_well_formed(&a);
        for i in 0..4 {
            assert_eq!(a.matches(&format!(r#"id="p{i}-clip""#)).count(), 1);
        }
        assert_eq!(a.matches(r#"<g class="panel""#).count(), 4);
        let (w, _) = figure().size();
        assert_eq!(w, 3.0 * 420.0 + 640.0 + 3.0 * 10.0);
        assert!(a.starts_with(&format!(
            r#"<svg xmlns="http://www.w3.org/2000/svg" width="{}""#,
            num(w)
        )));
    }

    #[test]
    fn shared_scale_makes_arrows_comparable() {
        let fig = figure();
        let s = fig.shared_scale().unwrap();
        // The achieved field has the largest vector, 0.04 · √(1.2² + 1.6²) = 0.08 m/s.
        let want = 0.9 * 0.01 / 0.08;
        let achieved_max = match &fig.panels[1] {
            Panel::Quiver(q) => q.max_norm(),
            _ => unreachable!(),
        };
        assert!((s - 0.9 * 0.01 / achieved_max).abs() < 1e-12);
        assert!((s - want).abs() < 1e-9);
        // Arrows in the target panel are shorter than 0.9 spacing.
        let svg = fig.to_svg();
        let target_panel = svg.split(r#"<g class="panel""#).nth(1).unwrap();
        let Panel::Quiver(q) = &fig.panels[0] else {
            unreachable!()
        };
        let longest = arrow_lengths(target_panel).into_iter().fold(0.0, f64::max);
        let want_px = q.max_norm() * s * q.layout().px_per_m;
        assert!((longest - want_px).abs() < 0.02, "{longest} vs {want_px}");
        let own_auto = 0.9 * 0.01 * q.layout().px_per_m;
        assert!((longest / own_auto - 0.04 * 2f64.sqrt() / 0.08).abs() < 1e-3);
        assert_eq!(fig.clone().share_scale(false).shared_scale(), None);
    }

    #[test]
    fn empty_figure_is_valid() {
        let svg = Panels::new("").to_svg();
        assert_well_formed(&svg);
    }
}
