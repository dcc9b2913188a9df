use super::*;

fn err(json: &str) -> String {
    Part::from_json_str(json).unwrap_err().to_string()
}

const SQUARE: &str = "[[0, 0], [0.01, 0], [0.01, 0.01], [0, 0.01]]";

/// Every kind of bad part (a crossed, degenerate or oversized outline,
/// support points outside it or without weight, out-of-range contacts or
/// friction, an unknown key) is refused at its JSON path.
#[test]
fn bad_parts_name_their_path() {
    let cases = [
        (
            r#"{"name": "x", "polygon": [[0, 0], [0.01, 0.01], [0.01, 0], [0, 0.01]]}"#,
            "part.polygon: is not a simple polygon",
        ),
        (
            r#"{"name": "x", "polygon": [[0, 0], [0.01, 0], [0.02, 0]]}"#,
            "part.polygon:",
        ),
        (
            r#"{"name": "x", "polygon": [[0, 0], [0.01, 0]]}"#,
            "part.polygon: needs at least 3",
        ),
        (
            &format!(
                r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"points": {{"points": [[0.005, 0.005], [0.02, 0]]}}}}}}"#
            ),
            "part.support.points.points[1]: [0.02, 0] lies outside",
        ),
        (
            &format!(
                r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"points": {{"points": [[0.005, 0.005], [0.001, 0.001]], "weights": [1, -1]}}}}}}"#
            ),
            "part.support.points.weights[1]: must be a finite weight ≥ 0",
        ),
        (
            &format!(
                r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"points": {{"points": [[0.005, 0.005]], "weights": [0]}}}}}}"#
            ),
            "part.support.points.weights: are all zero",
        ),
        (
            &format!(
                r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"unknown": {{"contacts": 0}}}}}}"#
            ),
            "part.support.unknown.contacts: must be in 1..=64",
        ),
        (
            &format!(r#"{{"name": "x", "polygon": {SQUARE}, "friction": 3}}"#),
            "part.friction: must be in [0, 2]",
        ),
        (
            &format!(r#"{{"name": "x", "polygon": {SQUARE}, "colour": 3}}"#),
            "part.colour",
        ),
        (
            r#"{"name": "x", "polygon": [[0, 0], [0.01, 0], [0.01, 0], [0, 0.01]]}"#,
            "part.polygon: is not a simple polygon",
        ),
    ];
    for (json, want) in cases {
        let e = err(json);
        assert!(e.starts_with(want), "{json}\n got: {e}\nwant: {want}");
    }
    let zero = err(r#"{"name": "x", "polygon": [[0, 0], [0.01, 0], [0.02, 0]]}"#);
    assert!(
        zero.contains("simple") || zero.contains("zero area"),
        "{zero}"
    );
    let flat = err(r#"{"name": "x", "polygon": [[0, 0], [0.01, 0], [0.02, 1e-18]]}"#);
    assert!(flat.contains("zero area"), "{flat}");
    let part = Part::from_json_str(&format!(r#"{{"name": "x", "polygon": {SQUARE}}}"#)).unwrap();
    assert!(part.check_fits(0.02, 0.02, "target.grid").is_ok());
    let e = part
        .check_fits(0.05, 0.012, "target.grid")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("part.polygon: the part (1.4142e-2 m across) is larger"),
        "{e}"
    );
}

/// Support weights are ratios: three weights of 1e308 (whose sum
/// overflowed: no equilibria) and of 5e-324 (whose centre of mass
/// underflowed: rests 8 mm off) give the body of three weights of 1, to
/// the last bit.
#[test]
fn support_weights_at_the_limits_of_f64_are_ratios() {
    let with = |w: &str| {
        Part::from_json_str(&format!(
            r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"points": {{"points": [[0.001, 0.001], [0.009, 0.001], [0.005, 0.009]], "weights": {w}}}}}}}"#
        ))
        .unwrap()
    };
    let one = with("[1, 1, 1]");
    assert!((one.origin - V2::new(0.005, 0.011 / 3.0)).norm() < 1e-15);
    for w in ["[1e308, 1e308, 1e308]", "[5e-324, 5e-324, 5e-324]"] {
        let p = with(w);
        assert_eq!(p.origin, one.origin, "{w}");
        assert_eq!(p.body, one.body, "{w}");
    }
}

/// The body origin is the support's weighted centroid: listed weights
/// move it by their moment, a clockwise polygon is turned round, and the
/// uniform support of an axis-aligned rectangle is its exact cell grid.
#[test]
fn body_frame_is_the_centre_of_mass() {
    let p = Part::from_json_str(&format!(
        r#"{{"name": "x", "polygon": {SQUARE}, "support": {{"points": {{"points": [[0.001, 0.001], [0.009, 0.001]], "weights": [1, 3]}}}}}}"#
    ))
    .unwrap();
    assert!((p.origin - V2::new(0.007, 0.001)).norm() < 1e-15);
    assert!(signed_area(&p.polygon) > 0.0);
    let cw = Part::from_json_str(
        r#"{"name": "x", "polygon": [[0, 0], [0, 0.01], [0.01, 0.01], [0.01, 0]]}"#,
    )
    .unwrap();
    assert!(signed_area(&cw.polygon) > 0.0);
    assert!((cw.origin - V2::new(0.005, 0.005)).norm() < 1e-15);
    let rect = crate::dynamics::Rectangle::new(0.02, 0.005, 32, 8);
    let part = Part::load(Path::new("targets/parts/rectangle.json")).unwrap();
    let grid = rect.support_points();
    assert_eq!(part.body.points().len(), grid.len());
    for (a, b) in part.body.points().iter().zip(&grid) {
        assert!((a - b).norm() < 1e-16, "{a} {b}");
    }
    assert!((part.body.inertia_per_mass() - rect.inertia_per_mass()).abs() < 1e-18);
}

/// The shipped parts load; the L-bracket's centre of mass is its area
/// centroid (closed form by composite areas).
#[test]
fn shipped_parts_load() {
    for name in ["rectangle", "bracket", "triangle"] {
        let p = Part::load(Path::new(&format!("targets/parts/{name}.json"))).unwrap();
        assert!(p.body.points().len() >= 100, "{name}");
    }
    let b = Part::load(Path::new("targets/parts/bracket.json")).unwrap();
    // Bar 3 × 0.5 cm at (1.5, 0.25) cm, leg 0.5 × 1.5 cm at (0.25, 1.25) cm.
    // Cells clipped to the outline: exact to round-off.
    let c = V2::new(
        (1.5 * 1.5 + 0.75 * 0.25) / 2.25,
        (1.5 * 0.25 + 0.75 * 1.25) / 2.25,
    ) * 0.01;
    assert!((b.origin - c).norm() < 1e-15, "{} vs {c}", b.origin);
}
