//! Deterministic SVG figures.

/// Placeholder until the plot module lands: Fig. 3 as a line plot.
pub fn fig3_svg(_header: &[String], _rs: &[f64], _cols: &[Vec<Option<f64>>]) -> String {
    String::new()
}
