//! Example target files (also usable as templates).

/// The grid used by all analytic examples: ±4 cm, 21 × 21 points.
const GRID: &str = r#"{"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [21, 21]}"#;

/// Builds an example file from its parts.
fn file(name: &str, field: &str, mask: &str) -> String {
    format!(
        "{{\n  \"name\": \"{name}\",\n  \"grid\": {GRID},\n  \"field\": {field},\n  \"weights\": null,\n  \"mask\": {mask}\n}}\n"
    )
}

/// Example target files as `(file name, JSON text)`, in this order:
/// `sink.json`, `saddle.json`, `whirlpool.json`, `squeeze_trans.json`,
/// `jet.json`, `line_sink.json`, `circle.json`, `sampled.json`.
///
/// All cover ±4 cm; the analytic ones use a 21 × 21 grid, `sampled.json` is
/// a sink (strength 1) sampled on its own 5 × 5 points without a grid.
/// Every example parses, validates and samples.
pub fn examples() -> Vec<(&'static str, String)> {
    let center_disc = r#"[{"circle": {"center": [0.0, 0.0], "radius": 0.005}}]"#;
    vec![
        (
            "sink.json",
            file(
                "sink",
                r#"{"kind": "sink", "center": [0.0, 0.0], "strength": 1.0}"#,
                center_disc,
            ),
        ),
        (
            "saddle.json",
            file(
                "saddle",
                r#"{"kind": "saddle", "center": [0.0, 0.0], "strength": 1.0, "angle": 0.0}"#,
                "[]",
            ),
        ),
        (
            "whirlpool.json",
            file(
                "whirlpool",
                r#"{"kind": "whirlpool", "center": [0.0, 0.0], "strength": 1.0, "rotation": 1.0}"#,
                "[]",
            ),
        ),
        (
            "squeeze_trans.json",
            file(
                "squeeze_trans",
                r#"{"kind": "squeeze_trans", "center": [0.0, 0.0], "strength": 1.0, "angle": 0.0, "transport": 1.0}"#,
                "[]",
            ),
        ),
        (
            "jet.json",
            file(
                "jet",
                r#"{"kind": "jet", "center": [0.0, 0.0], "strength": 0.02, "direction": 0.0, "width": 0.01}"#,
                "[]",
            ),
        ),
        (
            "line_sink.json",
            file(
                "line_sink",
                r#"{"kind": "line_sink", "center": [0.0, 0.0], "strength": 1.0, "angle": 90.0, "offset": 0.0}"#,
                "[]",
            ),
        ),
        (
            "circle.json",
            file(
                "circle",
                r#"{"kind": "circle", "center": [0.0, 0.0], "strength": 0.02}"#,
                center_disc,
            ),
        ),
        ("sampled.json", sampled()),
    ]
}

/// A sink `f = -p` sampled at the 5 × 5 points of a 2 cm lattice on ±4 cm.
fn sampled() -> String {
    let coords = [-0.04, -0.02, 0.0, 0.02, 0.04];
    let mut points = Vec::new();
    let mut vectors = Vec::new();
    for &y in &coords {
        for &x in &coords {
            points.push(format!("[{x:.2}, {y:.2}]"));
            let v = |c: f64| if c == 0.0 { 0.0 } else { -c };
            vectors.push(format!("[{:.2}, {:.2}]", v(x), v(y)));
        }
    }
    let join = |items: &[String]| {
        items
            .chunks(5)
            .map(|row| row.join(", "))
            .collect::<Vec<_>>()
            .join(",\n      ")
    };
    format!(
        "{{\n  \"name\": \"sampled_sink\",\n  \"field\": {{\n    \"kind\": \"sampled\",\n    \"interpolation\": \"idw\",\n    \"points\": [\n      {}\n    ],\n    \"vectors\": [\n      {}\n    ]\n  }}\n}}\n",
        join(&points),
        join(&vectors)
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::request::{FieldSpec, Target};

    #[test]
    fn sampled_example_is_a_sink() {
        let (_, json) = examples().pop().unwrap();
        let t = Target::from_json_str(&json).unwrap();
        let FieldSpec::Sampled {
            points, vectors, ..
        } = &t.field
        else {
            panic!("not sampled");
        };
        assert_eq!(points.len(), 25);
        for (p, v) in points.iter().zip(vectors) {
            assert!((v[0] + p[0]).abs() < 1e-15 && (v[1] + p[1]).abs() < 1e-15);
        }
    }

    #[test]
    fn examples_are_valid_json_objects_with_names() {
        for (name, json) in examples() {
            let v: serde_json::Value = serde_json::from_str(&json).unwrap();
            assert!(v["name"].is_string(), "{name}");
            assert!(json.ends_with("}\n"));
        }
    }
}
