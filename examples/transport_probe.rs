//! squeeze_trans (issue 11, task 3): does an in-plane 2nd harmonic on x
//! (the x limit the sequenced Trans sawtooth uses, beyond the circle's
//! share) add uniform transport to the closed-form seed? Coarse 7 × 7
//! steady-state fields of the seed with a_x's harmonic 2 at several
//! amplitudes and phases: mean x velocity and realised ŝ / shape.
//!
//! `cargo run --release --example transport_probe`

use std::path::{Path, PathBuf};

use platefield::design::{design, DesignOptions};
use platefield::field::{Field, FieldKind, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::studies::synthesis::limits_of;
use platefield::synth::objective::realised;
use platefield::synth::seed::seed;

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/squeeze_trans.json"))?;
    let schedule = design(
        &target,
        &DesignOptions {
            cache_dir: Some(PathBuf::from(".platefield-cache")),
            quiet: true,
            ..DesignOptions::default()
        },
    )?
    .schedule;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, 2)?;
    println!("limits {:?}", limits);
    let coarse = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [7, 7],
    };
    let sd = seed(
        &target.field,
        &coarse,
        &limits,
        settings.friction,
        settings.gravity,
    )?;
    let t: Vec<[f64; 2]> = coarse
        .points()
        .iter()
        .map(|p| target.field.eval(*p))
        .collect();
    let h1 = sd.coefficients.c[0][0];
    let a1 = h1[0].hypot(h1[1]);
    println!(
        "seed strength {:.4}, a_x harmonic 1 amplitude {a1:.3}",
        sd.strength
    );
    for amp in [0.0, 10.0, 20.0, 30.0] {
        for k in 0..(if amp == 0.0 { 1 } else { 8 }) {
            let phase = k as f64 * std::f64::consts::PI / 4.0;
            let mut c = sd.coefficients.clone();
            c.set(0, 2, amp, phase);
            let peak = c.peak(0);
            let f = Field::compute(
                &Motion::Signals(c.to_signals()),
                &coarse,
                FieldKind::Velocity,
                &settings,
                &|| {},
            );
            let r = realised(&f, &t);
            let n = f.vectors.len() as f64;
            let mx: f64 = f.vectors.iter().map(|v| v[0]).sum::<f64>() / n;
            let my: f64 = f.vectors.iter().map(|v| v[1]).sum::<f64>() / n;
            println!(
                "a_x h2 {amp:>4.1} phase {:>5.1}°: peak x {peak:.2}, mean v ({:+.5}, {:+.5}) m/s, ŝ {:.4} shape {:.1} %, invalid {}",
                phase.to_degrees(), mx, my, r.strength, 100.0 * r.shape_error, r.invalid
            );
        }
    }
    let full = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [21, 21],
    };
    let sd = seed(
        &target.field,
        &full,
        &limits,
        settings.friction,
        settings.gravity,
    )?;
    match platefield::synth::transport::transport_start(&sd, &limits, &full, &settings) {
        None => println!("transport_start: none"),
        Some((c, k)) => {
            let f = Field::compute(
                &Motion::Signals(c.to_signals()),
                &coarse,
                FieldKind::Velocity,
                &settings,
                &|| {},
            );
            let r = realised(&f, &t);
            println!("transport_start: predicted k {k:.4}; coarse ŝ {:.4} shape {:.1} % turn {:.1}°, invalid {}; peaks {:?}", r.strength, 100.0 * r.shape_error, r.turn.to_degrees(), r.invalid, c.peaks());
            for f in [0.25, 0.5, 0.75, 1.0] {
                for turn in [-10.0f64, 0.0, 10.0] {
                    let mut c2 = platefield::synth::calibrate::shifted(&c, turn.to_radians());
                    for a in [0usize, 3, 4] {
                        let from = if a == 0 { 1 } else { 0 };
                        for cs in &mut c2.c[a][from..] {
                            *cs = [cs[0] * f, cs[1] * f];
                        }
                    }
                    let fl = Field::compute(
                        &Motion::Signals(c2.to_signals()),
                        &coarse,
                        FieldKind::Velocity,
                        &settings,
                        &|| {},
                    );
                    let r = realised(&fl, &t);
                    let n = fl.vectors.len() as f64;
                    let mx: f64 = fl.vectors.iter().map(|v| v[0]).sum::<f64>() / n;
                    println!("  scale {f:.2} turn {turn:+.0}°: ŝ {:.4} shape {:.1} % turn {:.1}° mean vx {mx:.5}", r.strength, 100.0 * r.shape_error, r.turn.to_degrees());
                }
            }
        }
    }
    Ok(())
}
