//! Speed against error of the primitive library (DESIGN.md section 8):
//! `platefield speed` writes `results/library_speed.md`.
//!
//! The default 8-primitive *force* library (21 × 21 grid over ±4 cm, 30
//! start phases, [`FieldSettings::default`] otherwise: model full, μ = 0.3)
//! is built at [`SPEED_STEPS`] RK4 steps per cycle and at a converged
//! reference ([`REFERENCE_STEPS`]). For each build the wall time (best of
//! [`REPEATS`], rayon's default thread count) and each primitive's relative
//! L2 error against the reference (over samples valid in both) are
//! reported, with the target: a library in ≤ 0.3 s at ≤ 1e-4.
//!
//! What limits the speed: the integrator follows a 2-D slip velocity that
//! swings past u = 0 by shortening its steps (`src/dynamics/integrator.rs`),
//! which costs steps and caps the order of accuracy; primitives whose slip
//! stays on one line (LineSink, LineSource, Trans) have no swings and
//! converge at RK4's fourth order.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use super::library::Library;
use super::rung::relative_l2;
use crate::error::Result;
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::output::write_atomic;

/// Step counts measured.
pub const SPEED_STEPS: [usize; 4] = [8, 16, 32, 64];
/// Steps per cycle of the reference.
pub const REFERENCE_STEPS: usize = 512;
/// The target wall time (s).
pub const TARGET_SECONDS: f64 = 0.3;
/// The target relative L2 error.
pub const TARGET_ERROR: f64 = 1e-4;
/// Timed builds per step count (the best is reported).
pub const REPEATS: usize = 3;

/// One timed build of the default force library.
#[derive(Debug, Clone)]
pub struct Build {
    /// Steps per cycle.
    pub steps: usize,
    /// The force fields, in [`Library::default_primitives`] order.
    pub fields: Vec<Field>,
    /// Wall time of each primitive's field (s).
    pub seconds: Vec<f64>,
}

impl Build {
    /// Total wall time (s).
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }
}

/// Builds the default 8-primitive force library (21 × 21, 30 phases,
/// default settings) at `steps` RK4 steps per cycle, timing each field.
pub fn build_force_library(steps: usize) -> Build {
    let mut settings = FieldSettings::default();
    settings.numerics.steps_per_cycle = steps;
    let mut fields = Vec::new();
    let mut seconds = Vec::new();
    for p in Library::default_primitives() {
        let motion = p.motion();
        let start = Instant::now();
        fields.push(Field::compute(
            &motion,
            &Grid::DEFAULT,
            FieldKind::Force,
            &settings,
            &|| {},
        ));
        seconds.push(start.elapsed().as_secs_f64());
    }
    Build {
        steps,
        fields,
        seconds,
    }
}

/// The best (fastest) of `REPEATS` builds at `steps`.
fn best_build(steps: usize) -> Build {
    let mut best = build_force_library(steps);
    for _ in 1..REPEATS {
        let b = build_force_library(steps);
        if b.total() < best.total() {
            best = b;
        }
    }
    best
}

fn sci(x: f64) -> String {
    if x.is_nan() {
        "n/a".into()
    } else {
        format!("{x:.2e}")
    }
}

/// Measures and writes `out/library_speed.md`; returns it.
pub fn library_speed(out: &Path) -> Result<String> {
    let names: Vec<&str> = Library::default_primitives()
        .iter()
        .map(|p| p.kind.name())
        .collect();
    let reference = build_force_library(REFERENCE_STEPS);
    let builds: Vec<Build> = SPEED_STEPS.iter().map(|&s| best_build(s)).collect();
    let errors: Vec<Vec<f64>> = builds
        .iter()
        .map(|b| {
            b.fields
                .iter()
                .zip(&reference.fields)
                .map(|(f, r)| relative_l2(f, r).0)
                .collect()
        })
        .collect();
    let worst = |e: &[f64]| e.iter().copied().fold(0.0, |a: f64, x| a.max(x));
    let threads = rayon::current_num_threads();
    let g = Grid::DEFAULT;
    let s = FieldSettings::default();

    let mut md = format!(
        "# Library speed against error\n\n\
         The default 8-primitive zero-velocity force library: {}×{} grid over ±4 cm, {} start \
         phases, model `{}`, μ = {} ({} samples × {} one-cycle simulations). Wall time of the \
         whole build, best of {REPEATS}, rayon with {threads} threads on the machine that ran \
         `platefield speed` (timings vary with the machine and its load; the errors do not). \
         Error: relative L2 against a {REFERENCE_STEPS}-step reference (built in {:.2} s), over \
         samples valid in both.\n\n",
        g.n[0],
        g.n[1],
        s.phases,
        s.model.name(),
        s.friction.kinetic,
        8 * g.len(),
        s.phases,
        reference.total()
    );
    let _ = writeln!(
        md,
        "| steps per cycle | wall time (s) | worst error | {} |",
        names.join(" | ")
    );
    let _ = writeln!(md, "|---|---|---|{}", "---|".repeat(names.len()));
    for (b, e) in builds.iter().zip(&errors) {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {} | {} |",
            b.steps,
            b.total(),
            sci(worst(e)),
            e.iter().map(|x| sci(*x)).collect::<Vec<_>>().join(" | ")
        );
    }
    let _ = write!(
        md,
        "\nWall time per primitive (s):\n\n| steps per cycle | {} |\n|---|{}\n",
        names.join(" | "),
        "---|".repeat(names.len())
    );
    for b in builds.iter().chain(std::iter::once(&reference)) {
        let _ = writeln!(
            md,
            "| {} | {} |",
            b.steps,
            b.seconds
                .iter()
                .map(|x| format!("{x:.3}"))
                .collect::<Vec<_>>()
                .join(" | ")
        );
    }
    let _ = write!(
        md,
        "\nObserved order of convergence, log₂(e(n)/e(2n)):\n\n| steps n → 2n | {} |\n|---|{}\n",
        names.join(" | "),
        "---|".repeat(names.len())
    );
    for i in 1..builds.len() {
        let cells: Vec<String> = errors[i - 1]
            .iter()
            .zip(&errors[i])
            .map(|(a, b)| {
                let p = (a / b).log2();
                if p.is_finite() {
                    format!("{p:.2}")
                } else {
                    "n/a".into()
                }
            })
            .collect();
        let _ = writeln!(
            md,
            "| {} → {} | {} |",
            builds[i - 1].steps,
            builds[i].steps,
            cells.join(" | ")
        );
    }

    // The verdict, from the numbers.
    let met = builds
        .iter()
        .zip(&errors)
        .find(|(b, e)| b.total() <= TARGET_SECONDS && worst(e) <= TARGET_ERROR);
    let accurate = builds
        .iter()
        .zip(&errors)
        .find(|(_, e)| worst(e) <= TARGET_ERROR);
    let fast = builds
        .iter()
        .zip(&errors)
        .rfind(|(b, _)| b.total() <= TARGET_SECONDS);
    let _ = write!(
        md,
        "\n## Target: the library in ≤ {TARGET_SECONDS} s at ≤ {} relative error\n\n",
        sci(TARGET_ERROR)
    );
    match met {
        Some((b, e)) => {
            let _ = writeln!(
                md,
                "**Met** at {} steps per cycle: {:.3} s, worst error {}.",
                b.steps,
                b.total(),
                sci(worst(e))
            );
        }
        None => {
            let _ = write!(md, "**Not met** on this machine. ");
            match accurate {
                Some((b, e)) => {
                    let _ = write!(
                        md,
                        "The error target is first reached at {} steps per cycle (worst {}), \
                         in {:.3} s, {:.1}× the time target. ",
                        b.steps,
                        sci(worst(e)),
                        b.total(),
                        b.total() / TARGET_SECONDS
                    );
                }
                None => {
                    let _ = write!(
                        md,
                        "No measured step count reaches the error target (best worst-case error {} \
                         at {} steps, {:.3} s). ",
                        sci(errors.iter().map(|e| worst(e)).fold(f64::INFINITY, f64::min)),
                        builds.last().map_or(0, |b| b.steps),
                        builds.last().map_or(0.0, |b| b.total())
                    );
                }
            }
            match fast {
                Some((b, e)) => {
                    let _ = writeln!(
                        md,
                        "Within the time target the most accurate build is {} steps per cycle \
                         ({:.3} s), worst error {}.",
                        b.steps,
                        b.total(),
                        sci(worst(e))
                    );
                }
                None => {
                    let _ = writeln!(md, "No measured build is within the time target.");
                }
            }
        }
    }
    let one_d = ["LineSink", "LineSource", "Trans"];
    let order = |name: &str| -> f64 {
        let i = names.iter().position(|n| *n == name).unwrap_or(0);
        let k = errors.len() - 1;
        (errors[k - 1][i] / errors[k][i]).log2()
    };
    let fmt_orders = |pick: &dyn Fn(&str) -> bool| -> String {
        names
            .iter()
            .filter(|n| pick(n))
            .map(|n| format!("{n} {:.1}", order(n)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        md,
        "\nWhat limits it: primitives whose slip stays on one line ({}) converge at RK4's fourth \
         order (observed between the two finest builds: {}), so their error falls 16× per \
         doubling of the steps. The others slip in 2-D: their slip velocity swings past u = 0 \
         without stopping, and the integrator follows each swing by shortening its steps \
         (`src/dynamics/integrator.rs`: the step is cut at the closest approach, backed off, and \
         the turn followed with steps of a fraction of |u|/|a_⊥|). Those swings cost extra steps \
         whatever the nominal step count, and the error of locating and following them, not the \
         RK4 truncation, dominates, so these primitives converge more slowly (observed: {}) and \
         set the worst-case error. The cost is one one-cycle simulation per sample and phase \
         ({} per build), spread over {threads} threads.",
        one_d.join(", "),
        fmt_orders(&|n| one_d.contains(&n)),
        fmt_orders(&|n| !one_d.contains(&n)),
        8 * g.len() * s.phases
    );
    let _ = writeln!(
        md,
        "\nRegenerate: `platefield speed` (about a minute). Bench: `cargo bench --bench library` \
         (one build at 32 steps per cycle)."
    );
    write_atomic(&out.join("library_speed.md"), md.as_bytes())?;
    Ok(md)
}
