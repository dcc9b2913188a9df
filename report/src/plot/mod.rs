//! Deterministic, dependency-free SVG figures.
//!
//! * [`LinePlot`] — series of points with nice 1-2-5 ticks, legend, optional
//!   log axes (e.g. log-log convergence plots);
//! * [`QuiverPlot`] — a vector field on sample points (axes in cm, equal
//!   aspect), red × at invalid samples, trajectory overlays, markers and a
//!   caption line;
//! * [`Panels`] — several plots side by side in one SVG, by default with a
//!   common arrow scale (e.g. target | achieved | residual).
//!
//! All output is hand-written SVG 1.1. The same input always produces
//! byte-identical output: every coordinate is written with exactly
//! [`COORD_DECIMALS`] (2) decimals, elements are emitted in input order, and
//! nothing depends on time, hashing or locale. Non-finite data never reaches
//! the file: such points are skipped (lines break there), and in quiver
//! plots a non-finite vector is drawn as an invalid sample (×).
//!
//! `write` methods write atomically (temporary file in the same directory,
//! then rename; see [`write_atomic`]).
//!
//! ```ignore
//! use platefield_report::plot::{Panels, QuiverPlot};
//! let fig = Panels::new("sink")
//!     .panel(QuiverPlot::new("target", pts.clone(), target).auto_caption())
//!     .panel(QuiverPlot::new("achieved", pts.clone(), achieved).auto_caption())
//!     .panel(QuiverPlot::new("residual", pts, residual).auto_caption());
//! fig.write("results/sink.svg")?;
//! ```

mod line;
mod panels;
mod quiver;
mod svg;
mod ticks;

pub use line::{LegendPosition, LinePlot, LineStyle, Series};
pub use panels::{Panel, Panels};
pub use quiver::{
    estimate_spacing, LegendEntry, LegendSymbol, Marker, MarkerShape, Overlay, Pivot, QuiverLayout,
    QuiverPlot, ARROW_COLOR, AUTO_ARROW_FRACTION, LEGEND_WIDTH,
};
pub use svg::{escape, fmt_sig, num, write_atomic, COORD_DECIMALS, INVALID_COLOR, PALETTE};

use platefield::field::{Field, FieldKind, Validity};

/// A quiver plot of the field (axes in cm, invalid samples marked ×).
pub fn field_quiver(field: &Field, title: &str) -> QuiverPlot {
    let units = match field.kind {
        FieldKind::Force => "m/s²",
        FieldKind::Velocity => "m/s",
    };
    let invalid: Vec<bool> = field.validity.iter().map(|v| *v != Validity::Ok).collect();
    let n_bad = invalid.iter().filter(|b| **b).count();
    QuiverPlot::new(title, field.grid.points(), field.vectors.clone())
        .invalid(invalid)
        .caption(format!(
            "max |f| = {:.4} {units}; {} of {} samples invalid (×)",
            field.max_magnitude(),
            n_bad,
            field.vectors.len()
        ))
}

#[doc(hidden)]
pub mod test_support {
    //! Helpers for checking rendered SVG in tests.

    /// Asserts the basic shape of an SVG document: starts with `<svg`, ends
    /// with `</svg>\n`, tags nest properly (so `<g>` is balanced) and no
    /// non-finite number leaked in.
    pub fn assert_well_formed(svg: &str) {
        assert!(svg.starts_with("<svg"), "must start with <svg");
        assert!(svg.ends_with("</svg>\n"), "must end with </svg>\\n");
        assert!(!svg.contains("NaN"), "NaN in output");
        assert_eq!(
            svg.matches("<g ").count() + svg.matches("<g>").count(),
            svg.matches("</g>").count(),
            "unbalanced <g>"
        );
        let mut stack: Vec<String> = Vec::new();
        let mut rest = svg;
        let mut roots = 0;
        while let Some(start) = rest.find('<') {
            let end = rest[start..].find('>').expect("unterminated tag") + start;
            let tag = &rest[start + 1..end];
            assert_eq!(
                tag.matches('"').count() % 2,
                0,
                "unbalanced quotes in <{tag}>"
            );
            if let Some(name) = tag.strip_prefix('/') {
                let open = stack.pop().unwrap_or_else(|| panic!("stray </{name}>"));
                assert_eq!(open, name, "mismatched </{name}>");
            } else if !tag.ends_with('/') {
                let name = tag.split_whitespace().next().unwrap_or("").to_string();
                if stack.is_empty() {
                    roots += 1;
                }
                stack.push(name);
            } else if stack.is_empty() {
                roots += 1;
            }
            rest = &rest[end + 1..];
        }
        assert!(stack.is_empty(), "unclosed tags {stack:?}");
        assert_eq!(roots, 1, "exactly one root element");
    }

    /// Lengths (px) of the arrow shafts (`M x0 y0 L x1 y1 ...` paths) inside
    /// every `<g class="arrows" ...>` group of `svg`.
    pub fn arrow_lengths(svg: &str) -> Vec<f64> {
        let mut out = Vec::new();
        for group in svg.split(r#"<g class="arrows""#).skip(1) {
            let body = group.split("</g>").next().unwrap();
            for line in body.lines().filter(|l| l.starts_with("<path d=\"M")) {
                let d = line.split('"').nth(1).unwrap();
                let nums: Vec<f64> = d
                    .split([' ', 'M', 'L'])
                    .filter(|s| !s.is_empty())
                    .take(4)
                    .map(|s| s.parse().unwrap())
                    .collect();
                out.push((nums[2] - nums[0]).hypot(nums[3] - nums[1]));
            }
        }
        out
    }
}
