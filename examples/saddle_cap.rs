//! Does a second harmonic in the in-plane translation lift the contact
//! margin's cap on the saddle? (issue 11, the saddle row; the answer and
//! its reason are in `platefield::synth`'s docs.)
//!
//! For each translation — the seed's circle at the x/y limits, and the
//! circle's harmonic 1 at (1 − f) of the limit plus a harmonic 2 of f on
//! x, on y or on both (phases in steps of 45°), each axis scaled back onto
//! its limit; and tilted ellipses (y's phase off by β) — it prints the
//! margin's cap k of [`platefield::synth::margin_cap`] (simulated linear
//! response, linear programme), with the tilts' harmonic 2 free and held
//! at zero, and the translation's own drift (the ratchet). The best are
//! then re-simulated with the programme's tilts on a 7 × 7 grid (realised
//! ŝ, shape error, least N at rest).
//!
//! `cargo run --release --example saddle_cap`

use std::f64::consts::PI;
use std::path::Path;

use platefield::field::{Field, FieldKind, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::studies::synthesis::{limits_of, sequenced};
use platefield::synth::contact::kinematic_least_normal;
use platefield::synth::margin_cap::{margin_cap, tilt_response, MarginCap};
use platefield::synth::objective::realised;
use platefield::synth::params::Coefficients;
use platefield::synth::seed::AffineFit;

/// The default ±4 cm region with n × n points.
fn square(n: usize) -> Grid {
    Grid {
        n: [n, n],
        ..Grid::DEFAULT
    }
}

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/saddle.json"))?;
    let schedule = sequenced(&target, Path::new(".platefield-cache"))?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, 2)?;
    println!("limits {limits:?}");
    let region = square(21);
    let m = AffineFit::of(&target.field, &region).m;
    let g = settings.gravity;
    let lim = limits.linear[0];
    let h = limits.harmonics as usize;
    let coarse = square(7);
    let target_vals: Vec<[f64; 2]> = coarse
        .points()
        .iter()
        .map(|p| target.field.eval(*p))
        .collect();
    // Circle a1 (counter-clockwise, y's phase off by beta) plus harmonic 2,
    // each in-plane axis scaled onto its limit.
    let translation = |a1: f64, beta: f64, h2: [(f64, f64); 2]| {
        let mut c = Coefficients::zero(limits.period, limits.harmonics);
        c.set(0, 1, a1, PI / 2.0);
        c.set(1, 1, a1, beta);
        for (a, (amp, phase)) in h2.into_iter().enumerate() {
            if amp > 0.0 {
                c.set(a, 2, amp, phase);
            }
            let p = c.peak(a);
            for cs in &mut c.c[a] {
                *cs = [cs[0] * lim / p, cs[1] * lim / p];
            }
        }
        c
    };
    let caps = |tr: &Coefficients| -> Option<(MarginCap, f64, [f64; 2])> {
        let r = tilt_response(tr, &region, &settings, h)?;
        let both = margin_cap(&r, m, &limits, &region, g, h)?;
        let h1 = margin_cap(&r, m, &limits, &region, g, 1)?;
        Some((both, h1.strength, r.drift))
    };
    let simulate = |tr: &Coefficients, cap: &MarginCap| {
        let mut c = tr.clone();
        for a in [3, 4] {
            c.c[a] = cap.tilts.c[a].clone();
        }
        let motion = Motion::Signals(c.to_signals());
        let f = Field::compute(&motion, &coarse, FieldKind::Velocity, &settings, &|| {});
        let r = realised(&f, &target_vals);
        let least = kinematic_least_normal(&motion, &region, &settings);
        println!(
            "    re-simulated 7×7: ŝ {:.4} at shape {:.1} % ({} invalid), least N {:.2} m/s² (margin {:.2}), peaks {:.1?}",
            r.strength,
            100.0 * r.shape_error,
            r.invalid,
            least,
            limits.contact_margin * g,
            c.peaks()
        );
    };
    let mut rows: Vec<(String, Coefficients)> =
        vec![("circle".into(), translation(lim, 0.0, [(0.0, 0.0); 2]))];
    for beta in [-30.0f64, -15.0, 15.0, 30.0] {
        rows.push((
            format!("ellipse, y phase {beta:+.0}°"),
            translation(lim, beta.to_radians(), [(0.0, 0.0); 2]),
        ));
    }
    for f in [0.05, 0.1, 0.2, 0.35] {
        let a2 = f * lim;
        for (on_x, on_y) in [(true, false), (false, true), (true, true)] {
            for i in 0..8 {
                for j in 0..(if on_x && on_y { 8 } else { 1 }) {
                    let px = f64::from(i) * PI / 4.0;
                    let py = if on_x && on_y {
                        f64::from(j) * PI / 4.0
                    } else {
                        px
                    };
                    let h2 = [
                        (if on_x { a2 } else { 0.0 }, px),
                        (if on_y { a2 } else { 0.0 }, py),
                    ];
                    rows.push((
                        format!(
                            "h2 {f:.2} on{}{} phases {:>3.0}° {:>3.0}°",
                            if on_x { " x" } else { "" },
                            if on_y { " y" } else { "" },
                            px.to_degrees(),
                            py.to_degrees()
                        ),
                        translation(lim * (1.0 - f), 0.0, h2),
                    ));
                }
            }
        }
    }
    let mut results = Vec::new();
    for (label, tr) in rows {
        let Some((cap, k1, drift)) = caps(&tr) else {
            println!("{label}: no steady state or no solution");
            continue;
        };
        println!(
            "{label}: cap {:.4} (tilts harmonic 1 only {k1:.4}), translation drift ({:+.5}, {:+.5}) m/s",
            cap.strength, drift[0], drift[1]
        );
        results.push((cap, label, tr));
    }
    let k0 = results[0].0.strength;
    simulate(&results[0].2, &results[0].0);
    results.sort_by(|a, b| b.0.strength.total_cmp(&a.0.strength));
    println!("\nbest caps against the circle's {k0:.4}:");
    for (cap, label, tr) in results.iter().take(4) {
        println!(
            "{label}: {:.4} = {:.3} × the circle's",
            cap.strength,
            cap.strength / k0
        );
        simulate(tr, cap);
    }
    Ok(())
}
