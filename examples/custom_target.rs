//! A target built in code rather than read from a file: a whirl about an
//! off-centre point, sampled at points computed here, designed by the
//! sequence method through `platefield::inverse::run`.
//!
//! `cargo run --release --example custom_target`

use platefield::design::{DesignOptions, Method};
use platefield::inverse::{self, DesignOutcome};
use platefield::request::Target;

fn main() -> platefield::Result<()> {
    // Parts circling (x0, y0) = (5 mm, 0) anticlockwise, sampled on a 7 × 7
    // grid over ±3 cm; the field's scale is the target's strength.
    let centre = [0.005, 0.0];
    let mut points = Vec::new();
    let mut vectors = Vec::new();
    for i in 0..7 {
        for j in 0..7 {
            let (x, y) = (-0.03 + 0.01 * j as f64, -0.03 + 0.01 * i as f64);
            points.push([x, y]);
            vectors.push([-(y - centre[1]), x - centre[0]]);
        }
    }
    let json = serde_json::json!({
        "name": "whirl",
        "field": {"kind": "sampled", "points": points, "vectors": vectors}
    });
    let target = Target::from_json_str(&json.to_string())?;
    let options = DesignOptions {
        method: Method::Sequence,
        runtime: platefield::work::Runtime::QUIET,
        ..DesignOptions::default()
    };
    let DesignOutcome::Method(outcome) = inverse::run(&target, &options)? else {
        unreachable!("a target without classes or closed loop is designed by its method")
    };
    let kept = outcome.kept();
    let p = kept.played();
    println!(
        "whirl about (5 mm, 0): fit error {:.2} %, realised shape error {:?}, realised strength {:?}",
        100.0 * kept.schedule.fit.relative_l2_error,
        p.realised_shape_error,
        p.realised_strength
    );
    for seg in &kept.schedule.segments {
        println!("  {:>5} cycles  {}", seg.cycles, seg.label);
    }
    Ok(())
}
