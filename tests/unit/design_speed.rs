//! The default design by least squares keeps its promise under the judge,
//! and the parallel synthesis gives the same bytes on one thread or two.
//! Quality only — timings live in `results/design_speed.md` and
//! `benches/design.rs`, never in tests.
//!
//! The synthesis promises its motion's steady-state field on the
//! target's full grid (`Checked`); the judge plays the motion at frozen
//! points of an 11 × 11 sub-grid of it until periodic, which for one
//! steady motion is the same field sampled on fewer points. So the two
//! agree within what the sub-grid changes: 2 % in strength and 1
//! percentage point in shape (measured 0.2–0.4 % and 0.1–0.4 points on
//! the three targets below).

use std::path::Path;

use crate::design::method::Method;
use crate::design::DesignOptions;
use crate::field::{FieldSettings, Grid};
use crate::request::Target;
use crate::synth::params::Layout;
use crate::synth::progress::ProgressMode;
use crate::synth::{synthesize, ShakerLimits, SynthOptions};

fn sink() -> Target {
    Target::load(Path::new("targets/sink.json")).expect("shipped target")
}

/// The default `auto` design of `target` (a fresh basis cache): its
/// synthesized candidate's judge (shape error, strength) and the
/// synthesis' promise on the full grid (shape error, strength).
fn default_design(target: &Target, name: &str) -> ((f64, f64), (f64, f64)) {
    let cache = std::env::temp_dir().join(format!(
        "platefield-design-speed-{name}-{}",
        std::process::id()
    ));
    let opts = DesignOptions::cached_quiet(&cache);
    let synth = SynthOptions {
        progress: ProgressMode::Quiet,
        ..SynthOptions::default()
    };
    let m = crate::inverse::run(target, &opts.by_method(Method::Auto, &synth))
        .and_then(|o| o.into_method())
        .expect("designs");
    let _ = std::fs::remove_dir_all(&cache);
    let c = m
        .candidates
        .iter()
        .find(|c| c.method == Method::Synthesize)
        .expect("a synthesized candidate");
    let p = c.played();
    let promise = &m.synthesis.as_ref().expect("synthesized").checked.realised;
    (
        (
            p.realised_shape_error.expect("judged"),
            p.realised_strength.expect("judged"),
        ),
        (promise.shape_error, promise.strength),
    )
}

/// The synthesized candidate's judge keeps the synthesis' promise (module
/// documentation), and the synthesis reaches at least 0.6 of the target's
/// strength within 8 % shape on each target (measured 0.67–0.69 at
/// 3.7–6.5 %). The default run checks the sink; the line sink at 30° and
/// the squeeze with translation run with `-- --ignored`.
fn keeps_its_promise(name: &str) {
    let t = Target::load(Path::new(&format!("targets/{name}.json"))).expect("shipped target");
    let ((shape, strength), (shape0, strength0)) = default_design(&t, name);
    println!(
        "{name}: judged {strength:.4} at {:.2} %, promised {strength0:.4} at {:.2} %",
        100.0 * shape,
        100.0 * shape0
    );
    assert!(
        (strength / strength0 - 1.0).abs() <= 0.02,
        "{name}: strength"
    );
    assert!((shape - shape0).abs() <= 0.01, "{name}: shape");
    assert!(strength >= 0.6 && shape <= 0.08, "{name}");
}

#[test]
fn default_sink_synthesis_keeps_its_promise() {
    keeps_its_promise("sink");
}

/// [`default_sink_synthesis_keeps_its_promise`] for the line sink at 30°
/// and the squeeze with translation (about 9 s of CPU for both).
#[test]
#[ignore = "about 9 s of CPU: cargo test --release --lib design::speed_tests -- --ignored"]
fn default_line_sink_30_synthesis_keeps_its_promise() {
    keeps_its_promise("line_sink_30");
}

/// See [`default_line_sink_30_synthesis_keeps_its_promise`].
#[test]
#[ignore = "about 9 s of CPU: cargo test --release --lib design::speed_tests -- --ignored"]
fn default_squeeze_trans_synthesis_keeps_its_promise() {
    keeps_its_promise("squeeze_trans");
}

#[test]
fn least_squares_synthesis_is_the_same_on_one_and_two_threads() {
    let t = sink();
    let g = t.grid.as_ref().expect("grid");
    let region = Grid {
        x: g.x,
        y: g.y,
        n: [9, 9],
    };
    let o = SynthOptions {
        max_evaluations: 40,
        coarse: [5, 5],
        progress: ProgressMode::Quiet,
        ..SynthOptions::default()
    };
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("pool")
            .install(|| {
                synthesize(
                    &t.field,
                    &region,
                    &ShakerLimits::lab_class(),
                    &FieldSettings::default(),
                    &o,
                )
                .expect("synthesizes")
            })
    };
    let (one, two) = (on(1), on(2));
    let json =
        |s: &crate::synth::Synthesis| serde_json::to_string(&s.checked.motion).expect("json");
    assert_eq!(json(&one), json(&two));
    assert_eq!(one.evaluations, two.evaluations);
    // The comparison covers a parallel batch: the least-squares run
    // evaluated at least one Jacobian (a column per parameter) after the
    // seed.
    let n = Layout::new(&ShakerLimits::lab_class()).len();
    assert!(
        one.evaluations > n + 1,
        "{} for {n} parameters",
        one.evaluations
    );
}
