//! squeeze_trans (issue 11, task 3): does an in-plane 2nd harmonic on x
//! (the x limit the sequenced Trans sawtooth uses, beyond the circle's
//! share) add uniform transport to the closed-form seed? Coarse 7 × 7
//! steady-state fields of the seed with a_x's harmonic 2 at several
//! amplitudes and phases: mean velocity and realised ŝ / shape; then the
//! start `platefield::synth::transport::transport_start` builds, scaled and
//! turned.
//!
//! `cargo run --release --example transport_probe`

use std::path::Path;

use platefield::field::{Field, FieldKind, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::studies::synthesis::{limits_of, sequenced};
use platefield::synth::calibrate::shifted;
use platefield::synth::objective::{realised, Realised};
use platefield::synth::params::Coefficients;
use platefield::synth::seed::seed;
use platefield::synth::transport::transport_start;

/// The default ±4 cm region with n × n points.
fn square(n: usize) -> Grid {
    Grid {
        n: [n, n],
        ..Grid::DEFAULT
    }
}

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/squeeze_trans.json"))?;
    let schedule = sequenced(&target, Path::new(".platefield-cache"))?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, 2)?;
    println!("limits {limits:?}");
    let coarse = square(7);
    let t: Vec<[f64; 2]> = coarse
        .points()
        .iter()
        .map(|p| target.field.eval(*p))
        .collect();
    // Realised ŝ / shape and the mean velocity of a motion on the coarse grid.
    let eval = |c: &Coefficients| -> (Realised, [f64; 2]) {
        let m = Motion::Signals(c.to_signals());
        let f = Field::compute(&m, &coarse, FieldKind::Velocity, &settings, &|| {});
        let n = f.vectors.len() as f64;
        let mean = f
            .vectors
            .iter()
            .fold([0.0; 2], |a, v| [a[0] + v[0] / n, a[1] + v[1] / n]);
        (realised(&f, &t), mean)
    };
    let sd = seed(
        &target.field,
        &coarse,
        &limits,
        settings.friction,
        settings.gravity,
    )?;
    println!("seed strength {:.4}", sd.strength);
    for amp in [0.0, 10.0, 20.0, 30.0] {
        for k in 0..(if amp == 0.0 { 1 } else { 8 }) {
            let phase = k as f64 * std::f64::consts::PI / 4.0;
            let mut c = sd.coefficients.clone();
            c.set(0, 2, amp, phase);
            let (r, v) = eval(&c);
            println!(
                "a_x h2 {amp:>4.1} phase {:>5.1}°: peak x {:.2}, mean v ({:+.5}, {:+.5}) m/s, ŝ {:.4} shape {:.1} %, invalid {}",
                phase.to_degrees(),
                c.peak(0),
                v[0],
                v[1],
                r.strength,
                100.0 * r.shape_error,
                r.invalid
            );
        }
    }
    let full = square(21);
    let sd = seed(
        &target.field,
        &full,
        &limits,
        settings.friction,
        settings.gravity,
    )?;
    let Some((c, k)) = transport_start(&sd, &limits, &full, &settings) else {
        println!("transport_start: none");
        return Ok(());
    };
    println!("transport_start: predicted k {k:.4}, peaks {:?}", c.peaks());
    for f in [0.25, 0.5, 0.75, 1.0] {
        for turn in [-10.0f64, 0.0, 10.0] {
            let mut s = shifted(&c, turn.to_radians());
            for (a, from) in [(0usize, 1usize), (3, 0), (4, 0)] {
                for cs in &mut s.c[a][from..] {
                    *cs = [cs[0] * f, cs[1] * f];
                }
            }
            let (r, v) = eval(&s);
            println!(
                "  scale {f:.2} turn {turn:+.0}°: ŝ {:.4} shape {:.1} % turn {:.1}° mean vx {:.5}",
                r.strength,
                100.0 * r.shape_error,
                r.turn.to_degrees(),
                v[0]
            );
        }
    }
    Ok(())
}
