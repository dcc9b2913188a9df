//! squeeze_trans: does an in-plane harmonic 2 on x (the
//! x limit the sequenced Trans sawtooth uses, beyond the circle's share)
//! add uniform transport to the closed-form seed? Coarse 7 × 7 steady-state
//! fields of the seed with a_x's harmonic 2 at several amplitudes and
//! phases: mean velocity and realised ŝ / shape; then the start
//! [`transport_start`] builds, scaled and turned.

use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

use super::square;
use crate::synthesis::{limits_of, sequenced};
use platefield::error::Result;
use platefield::field::{Field, FieldKind, FieldSettings, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::synth::calibrate::shifted;
use platefield::synth::objective::{realised, Realised};
use platefield::synth::params::Coefficients;
use platefield::synth::seed::seed;
use platefield::synth::transport::transport_start;
use platefield_report::table::Table;

/// The coarse grid, the target on it and the settings a motion is
/// evaluated with.
struct Coarse {
    grid: Grid,
    target_values: Vec<[f64; 2]>,
    settings: FieldSettings,
}

impl Coarse {
    /// Realised ŝ / shape and the mean velocity (m/s) of motion `c`.
    fn eval(&self, c: &Coefficients) -> (Realised, [f64; 2]) {
        let m = Motion::Signals(c.to_signals());
        let f = Field::compute(&m, &self.grid, FieldKind::Velocity, &self.settings, &|| {});
        let n = f.vectors.len() as f64;
        let mean = f
            .vectors
            .iter()
            .fold([0.0; 2], |a, v| [a[0] + v[0] / n, a[1] + v[1] / n]);
        (realised(&f, &self.target_values), mean)
    }
}

/// The seed with a_x's harmonic 2 at 0–30 m/s², every 45°.
fn ratchet_rows(md: &mut String, coarse: &Coarse, start: &Coefficients) {
    let mut table = Table::new([
        "a_x harmonic 2 (m/s²)",
        "phase (°)",
        "peak x (m/s²)",
        "mean v (m/s)",
        "abs. mean v (cm/s)",
        "ŝ (s⁻¹)",
        "shape (%)",
        "invalid",
    ]);
    for amp in [0.0, 10.0, 20.0, 30.0] {
        for k in 0..(if amp == 0.0 { 1 } else { 8 }) {
            let phase = f64::from(k) * PI / 4.0;
            let mut c = start.clone();
            c.set(0, 2, amp, phase);
            let (r, v) = coarse.eval(&c);
            table.row([
                format!("{amp:.1}"),
                format!("{:.1}", phase.to_degrees()),
                format!("{:.2}", c.peak(0)),
                format!("({:+.5}, {:+.5})", v[0], v[1]),
                format!("{:.3}", 100.0 * v[0].hypot(v[1])),
                format!("{:.4}", r.strength),
                format!("{:.1}", 100.0 * r.shape_error),
                r.invalid.to_string(),
            ]);
        }
    }
    md.push_str(&table.markdown());
}

/// [`transport_start`]'s start scaled by f and turned.
fn start_rows(md: &mut String, coarse: &Coarse, c: &Coefficients) {
    let mut table = Table::new([
        "scale",
        "turn (°)",
        "ŝ (s⁻¹)",
        "shape (%)",
        "realised turn (°)",
        "mean v_x (m/s)",
    ]);
    for f in [0.25, 0.5, 0.75, 1.0] {
        for turn in [-10.0f64, 0.0, 10.0] {
            let mut s = shifted(c, turn.to_radians());
            for (a, from) in [(0usize, 1usize), (3, 0), (4, 0)] {
                for cs in &mut s.c[a][from..] {
                    *cs = [cs[0] * f, cs[1] * f];
                }
            }
            let (r, v) = coarse.eval(&s);
            table.row([
                format!("{f:.2}"),
                format!("{turn:+.0}"),
                format!("{:.4}", r.strength),
                format!("{:.1}", 100.0 * r.shape_error),
                format!("{:.1}", r.turn.to_degrees()),
                format!("{:.5}", v[0]),
            ]);
        }
    }
    md.push_str(&table.markdown());
}

/// The section of `probes.md`.
pub(crate) fn section(cache: &Path) -> Result<String> {
    let target = Target::load(Path::new("targets/squeeze_trans.json"))?;
    let schedule = sequenced(&target, cache)?;
    let settings = schedule.settings;
    let limits = limits_of(&schedule, 2)?;
    let grid = square(7);
    let target_values = grid
        .points()
        .iter()
        .map(|p| target.field.eval(*p))
        .collect();
    let coarse = Coarse {
        grid,
        target_values,
        settings,
    };
    let (mu, g) = (settings.friction, settings.gravity);
    let sd = seed(&target.field, &coarse.grid, &limits, mu, g)?;
    let mut md = format!(
        "\n## The in-plane harmonic-2 ratchet on squeeze_trans\n\n\
         `targets/squeeze_trans.json` under its sequenced schedule's limits (T = {:.4} s, \
         a_z ≤ {:.3} m/s²): the closed-form seed on 7 × 7 has strength {:.4} s⁻¹ and x peak \
         {:.2} m/s²; with a_x's harmonic 2 added (7 × 7 steady-state velocity fields):\n\n",
        limits.period,
        limits.linear[2],
        sd.strength,
        sd.coefficients.peak(0)
    );
    ratchet_rows(&mut md, &coarse, &sd.coefficients);
    let full = square(21);
    let sd = seed(&target.field, &full, &limits, mu, g)?;
    match transport_start(&sd, &limits, &full, &settings) {
        None => md.push_str("\n`transport_start` (seed on 21 × 21): none.\n"),
        Some((c, k)) => {
            let _ = writeln!(
                md,
                "\n`transport_start` (seed on 21 × 21): predicted k {k:.4} s⁻¹, peaks {:.2?}; scaled by f \
                 (translation's harmonics ≥ 1 and the tilts) and turned:\n",
                c.peaks()
            );
            start_rows(&mut md, &coarse, &c);
        }
    }
    Ok(md)
}
