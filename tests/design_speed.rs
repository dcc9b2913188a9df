//! Issue 27: the default design by least squares keeps its quality, and
//! the parallel synthesis gives the same bytes on one thread or two.
//! Quality only — timings live in `results/design_speed.md` and
//! `benches/design.rs`, never in tests.
//!
//! The sink designed by `auto` with the default options (≈ 10 s CPU):
//! its played check within the goal, shape ≤ 5 % at strength
//! ≥ 0.65 s⁻¹ (the Nelder–Mead path of before: 4.74 % at 0.701); and
//! line_sink_30 and squeeze_trans (≈ 11 s CPU each) within 5 % of the
//! Nelder–Mead strength and 0.5 points of its shape error.

use std::path::Path;

use platefield::design::method::Method;
use platefield::design::DesignOptions;
use platefield::field::{FieldSettings, Grid};
use platefield::request::Target;
use platefield::synth::params::Layout;
use platefield::synth::progress::ProgressMode;
use platefield::synth::{synthesize, ShakerLimits, SynthOptions};

fn sink() -> Target {
    Target::load(Path::new("targets/sink.json")).expect("shipped target")
}

/// The default `auto` design of `target` (a fresh basis cache): the kept
/// method and its played shape error and strength.
fn default_design(target: &Target, name: &str) -> (Method, f64, f64) {
    let cache = std::env::temp_dir().join(format!(
        "platefield-design-speed-{name}-{}",
        std::process::id()
    ));
    let opts = DesignOptions::cached_quiet(&cache);
    let synth = SynthOptions {
        progress: ProgressMode::Quiet,
        ..SynthOptions::default()
    };
    let m = platefield::design::run(target, &opts.by_method(Method::Auto, &synth))
        .and_then(|o| o.into_method())
        .expect("designs");
    let _ = std::fs::remove_dir_all(&cache);
    let kept = m.kept();
    let p = kept.played();
    (
        kept.method,
        p.realised_shape_error.expect("played"),
        p.realised_strength.expect("played"),
    )
}

#[test]
fn default_sink_design_meets_the_played_goal() {
    let (method, shape, strength) = default_design(&sink(), "sink");
    assert_eq!(method, Method::Synthesize);
    assert!(shape <= 0.05, "played shape {shape}");
    assert!(strength >= 0.65, "played strength {strength}");
}

/// Issue 27's bar for least squares: within 5 % of the Nelder–Mead path's
/// played strength (line_sink_30: 3.93 % at 0.408 s⁻¹) at a shape error at
/// most 0.5 points above its. Measured (issue 27, session 5, "speed6"):
/// 3.66 % at 0.725 s⁻¹ since the synthesis's shape block steers by the
/// whole shape error with the strength row's reach 4
/// (`platefield::synth::objective`); 2.78 % at 0.350 before, with the
/// cost's hinge as the block (the first Gauss–Newton step went for
/// strength alone, to 34.8 % shape, and the run crept on).
#[test]
fn default_line_sink_30_keeps_the_nelder_mead_strength() {
    meets_the_nelder_mead_bar("line_sink_30", 0.0393, 0.408);
}

/// Issue 27's bar for squeeze_trans: the Nelder–Mead path played 3.32 %
/// at 0.790 s⁻¹, so ≤ 3.82 % at ≥ 0.751 s⁻¹. Measured (session 6,
/// "speed7"): 2.39 % at 0.773 s⁻¹ since the played polish of a start
/// within its budget steers by the whole played shape error and keeps a
/// motion whose steps went past the peak limits before the clamp
/// (`platefield::design::polish`); 2.46 % at 0.710 before, when its
/// strength-only steps traded 3 points of shape for 5 % of strength and
/// every better step was refused for its clamped excess.
#[test]
fn default_squeeze_trans_keeps_the_nelder_mead_strength() {
    meets_the_nelder_mead_bar("squeeze_trans", 0.0332, 0.790);
}

/// Issue 27's bar: the default design of the shipped target `name` is
/// synthesized and plays a shape error at most 0.5 points above the
/// Nelder–Mead path's `shape` and a strength at least 95 % of its
/// `strength`.
fn meets_the_nelder_mead_bar(name: &str, shape0: f64, strength0: f64) {
    let t = Target::load(Path::new(&format!("targets/{name}.json"))).expect("shipped target");
    let (method, shape, strength) = default_design(&t, name);
    assert_eq!(method, Method::Synthesize);
    assert!(shape <= shape0 + 0.005, "{name}: played shape {shape}");
    assert!(
        strength >= 0.95 * strength0,
        "{name}: played strength {strength}"
    );
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
        |s: &platefield::synth::Synthesis| serde_json::to_string(&s.checked.motion).expect("json");
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
