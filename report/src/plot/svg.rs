//! Low-level SVG helpers: number formatting, escaping, atomic writes.

use std::fmt::Write as _;

/// Decimals used for every coordinate and length written to SVG.
pub const COORD_DECIMALS: usize = 2;

/// Default colour cycle for series and overlays (colour-blind-friendly
/// "tableau 10" subset).
pub const PALETTE: [&str; 8] = [
    "#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf",
];

/// Colour of the × drawn at invalid samples.
pub const INVALID_COLOR: &str = "#d62728";

/// Formats a coordinate with [`COORD_DECIMALS`] decimals.
///
/// Never produces `NaN`/`inf` (callers filter non-finite data; as a last
/// resort non-finite values are written as `0.00` and huge values are
/// clamped to ±1e9) and never `-0.00`.
pub fn num(v: f64) -> String {
    let v = if v.is_finite() {
        v.clamp(-1e9, 1e9)
    } else {
        0.0
    };
    let s = format!("{v:.COORD_DECIMALS$}");
    if s.starts_with('-') && s[1..].bytes().all(|b| b == b'0' || b == b'.') {
        s[1..].to_string()
    } else {
        s
    }
}

/// Escapes text for use in SVG character data and attribute values.
pub fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c if (c as u32) < 0x20 && c != '\t' && c != '\n' => {}
            c => out.push(c),
        }
    }
    out
}

/// Formats `v` with `sig` significant digits, trailing zeros removed;
/// scientific notation for very small or large magnitudes. Non-finite values
/// give `"-"`.
pub fn fmt_sig(v: f64, sig: usize) -> String {
    if !v.is_finite() {
        return "-".to_string();
    }
    if v == 0.0 {
        return "0".to_string();
    }
    let sig = sig.max(1);
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        let s = format!("{:.*e}", sig - 1, v);
        // Trim zeros in the mantissa: "1.50e-5" -> "1.5e-5".
        let (m, e) = s.split_once('e').unwrap_or((&s, "0"));
        let m = trim_zeros(m);
        return format!("{m}e{e}");
    }
    let decimals = (sig as i32 - 1 - mag).max(0) as usize;
    trim_zeros(&format!("{v:.decimals$}")).to_string()
}

fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

/// Opening `<svg>` element (with a white background) for a `w × h` image.
pub(crate) fn open(out: &mut String, w: f64, h: f64) {
    let _ = writeln!(
        out,
        r#"<svg xmlns="http://www.w3.org/2000/svg" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="Helvetica, Arial, sans-serif" font-size="12">"#,
        w = num(w),
        h = num(h)
    );
    let _ = writeln!(
        out,
        r#"<rect x="0" y="0" width="{}" height="{}" fill="white"/>"#,
        num(w),
        num(h)
    );
}

/// Closing `</svg>` plus final newline.
pub(crate) fn close(out: &mut String) {
    out.push_str("</svg>\n");
}

/// A `<text>` element; `anchor` is `start`, `middle` or `end`; `extra` holds
/// further attributes (already escaped), e.g. `font-weight="bold"`.
pub(crate) fn text(out: &mut String, x: f64, y: f64, anchor: &str, extra: &str, content: &str) {
    let sep = if extra.is_empty() { "" } else { " " };
    let _ = writeln!(
        out,
        r#"<text x="{}" y="{}" text-anchor="{anchor}"{sep}{extra}>{}</text>"#,
        num(x),
        num(y),
        escape(content)
    );
}

/// A plot's bold title centred over its `width` (none when empty).
pub(crate) fn title(out: &mut String, width: f64, title: &str) {
    if !title.is_empty() {
        text(
            out,
            width / 2.0,
            22.0,
            "middle",
            r#"font-size="14" font-weight="bold""#,
            title,
        );
    }
}

/// Colour of a plot's frame, ticks and tick labels.
pub(crate) const AXIS_COLOR: &str = "#333333";

/// Opens a plot's axes group and draws its frame `[left, top, right,
/// bottom]` (px); the ticks follow ([`x_tick`], [`y_tick`]), then `</g>`.
pub(crate) fn open_axes(out: &mut String, [left, top, right, bottom]: [f64; 4]) {
    let _ = writeln!(
        out,
        r#"<g class="axes" stroke="{AXIS_COLOR}" stroke-width="1" fill="none">"#
    );
    let _ = writeln!(
        out,
        r#"<rect x="{}" y="{}" width="{}" height="{}"/>"#,
        num(left),
        num(top),
        num(right - left),
        num(bottom - top)
    );
}

/// A tick mark at `x` below the frame's bottom edge, `len` px long.
pub(crate) fn x_tick(out: &mut String, x: f64, bottom: f64, len: f64) {
    let _ = writeln!(
        out,
        r#"<line x1="{x}" y1="{}" x2="{x}" y2="{}"/>"#,
        num(bottom),
        num(bottom + len),
        x = num(x)
    );
}

/// A tick mark at `y` left of the frame's left edge, `len` px long.
pub(crate) fn y_tick(out: &mut String, y: f64, left: f64, len: f64) {
    let _ = writeln!(
        out,
        r#"<line x1="{}" y1="{y}" x2="{}" y2="{y}"/>"#,
        num(left - len),
        num(left),
        y = num(y)
    );
}

/// Path data (`M x y L x y ...`) for a polyline, starting a new subpath
/// after every run of skipped points; `None` entries are gaps.
pub(crate) fn path_data(points: impl IntoIterator<Item = Option<[f64; 2]>>) -> String {
    let mut d = String::new();
    let mut pen_down = false;
    for p in points {
        match p {
            Some([x, y]) => {
                let cmd = if pen_down { 'L' } else { 'M' };
                if !d.is_empty() {
                    d.push(' ');
                }
                let _ = write!(d, "{cmd}{} {}", num(x), num(y));
                pen_down = true;
            }
            None => pen_down = false,
        }
    }
    d
}

/// Writes `contents` to `path` atomically: see
/// [`platefield::output::replace_file`] (a temporary file renamed over a
/// regular file; devices and FIFOs written directly; links followed).
pub use platefield::output::replace_file as write_atomic;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn num_is_fixed_and_never_negative_zero_or_nan() {
        assert_eq!(num(1.0), "1.00");
        assert_eq!(num(-0.001), "0.00");
        assert_eq!(num(-0.0), "0.00");
        assert_eq!(num(-1.234), "-1.23");
        assert_eq!(num(f64::NAN), "0.00");
        assert_eq!(num(f64::INFINITY), "0.00");
    }

    #[test]
    fn escaping() {
        assert_eq!(escape("a<b & \"c\""), "a&lt;b &amp; &quot;c&quot;");
    }

    #[test]
    fn significant_digits() {
        assert_eq!(fmt_sig(0.012, 3), "0.012");
        assert_eq!(fmt_sig(0.0123456, 3), "0.0123");
        assert_eq!(fmt_sig(123.456, 3), "123");
        assert_eq!(fmt_sig(1.5e-7, 3), "1.5e-7");
        assert_eq!(fmt_sig(0.0, 3), "0");
        assert_eq!(fmt_sig(f64::NAN, 3), "-");
    }

    #[test]
    fn path_data_breaks_at_gaps() {
        let d = path_data([Some([0.0, 0.0]), Some([1.0, 1.0]), None, Some([2.0, 2.0])]);
        assert_eq!(d, "M0.00 0.00 L1.00 1.00 M2.00 2.00");
    }

    #[test]
    fn atomic_write_replaces_file() {
        let dir = std::env::temp_dir().join(format!("pf-plot-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("a.svg");
        write_atomic(&p, b"one").unwrap();
        write_atomic(&p, b"two").unwrap();
        assert_eq!(std::fs::read_to_string(&p).unwrap(), "two");
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp."))
            .collect();
        assert!(leftovers.is_empty());
        assert!(write_atomic(&dir.join("missing/x.svg"), b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
