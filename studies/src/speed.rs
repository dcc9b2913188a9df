//! Speed against error of the primitive library: `platefield study speed` writes
//! `results/library_speed.md`. Every numerical knob (steps per cycle here;
//! phases, grid spacing and model rung elsewhere) is a point on a
//! speed-against-error curve, measured against a converged reference.
//!
//! The default 8-primitive *force* library (21 × 21 grid over ±4 cm, 30
//! start phases, [`FieldSettings::default`] otherwise: model full, μ = 0.3)
//! is built at each of `SPEED_STEPS` RK4 steps per cycle, with each
//! primitive at its own calibrated count ([`StepsPlan::Calibrated`],
//! `src/basis/steps.rs`), and at a converged reference
//! (`REFERENCE_STEPS`). For each build the wall time (best of
//! `REPEATS`, rayon's default thread count) and each primitive's relative
//! L2 error against the reference (over samples valid in both) are
//! reported, with the target: a library in ≤ 0.3 s at ≤ 1e-4; the
//! report says whether the fewest counts it measures are the calibrated
//! ones.
//!
//! Two more measurements say what limits it: the 64-step build repeated
//! with every motion shifted by `PERTURBATION` (which changes the true
//! field by about 1e-10 relative) shows how reproducible each primitive's
//! field is under round-off-sized changes, and a Richardson estimate of the
//! reference's own error (from the observed order between 32 and 64 steps)
//! shows how far the comparison can be trusted. Primitives whose slip stays
//! on one line (LineSink, LineSource, Trans) converge at RK4's fourth order;
//! the others slip in 2-D, where the integrator follows a slip velocity
//! through its swings past u = 0 and its slow-downs to a stop in
//! regularised time (`src/dynamics/swing.rs`) and takes starts from rest
//! implicitly (`src/dynamics/radau.rs`).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use platefield::basis::steps::LADDER;
use platefield::basis::{Library, StepsPlan};
use platefield::error::Result;
use platefield::field::rung::relative_l2;
use platefield::field::{Field, FieldKind, FieldSettings, Grid, Orbits};
use platefield::output::write_atomic;

/// Step counts measured (the calibration's ladder, `src/basis/steps.rs`).
pub(crate) const SPEED_STEPS: [usize; 7] = LADDER;
/// Steps per cycle of the reference.
pub(crate) const REFERENCE_STEPS: usize = 512;
/// The target wall time (s).
pub(crate) const TARGET_SECONDS: f64 = 0.3;
/// The target relative L2 error.
pub(crate) const TARGET_ERROR: f64 = 1e-4;
/// Timed builds per step count (the best is reported).
pub(crate) const REPEATS: usize = 3;

/// The largest order the reference's Richardson error estimate assumes:
/// between 32 and 64 steps the 2-D primitives' fields converge at 5–6, above
/// the order 3.2–4.3 `tests/unit/slip2d.rs` `order_2d` measures from 16 to 64,
/// so the observed order there would make the estimate 10–100× too small.
pub(crate) const RICHARDSON_ORDER: f64 = 3.0;

/// Horizontal shift (m) of every motion in the reproducibility build.
pub(crate) const PERTURBATION: f64 = 1e-12;

/// One timed build of the default force library.
#[derive(Debug, Clone)]
pub struct Build {
    /// Steps per cycle requested (a [`StepsPlan::Calibrated`] build
    /// simulates each primitive at its own count: `per_primitive`).
    pub steps: usize,
    /// Steps per cycle each primitive was simulated with.
    pub per_primitive: Vec<usize>,
    /// The force fields, in [`Library::default_primitives`] order.
    pub fields: Vec<Field>,
    /// Wall time of each primitive's field (s).
    pub seconds: Vec<f64>,
    /// CPU time of the whole build over all threads (s), where the
    /// platform reports it (Linux).
    pub cpu_seconds: Option<f64>,
}

impl Build {
    /// Total wall time (s).
    pub fn total(&self) -> f64 {
        self.seconds.iter().sum()
    }
}

/// The 1-minute load average (Linux), for timing reports.
pub(crate) fn load_average() -> Option<String> {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|l| l.split_whitespace().next().map(str::to_string))
}

/// CPU time of this process over all threads (s), from /proc/self/stat
/// (utime + stime in USER_HZ = 100 ticks per second); `None` elsewhere.
pub(crate) fn process_cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // Fields after the command name (which is in parentheses).
    let rest = &stat[stat.rfind(')')? + 2..];
    let f: Vec<&str> = rest.split_whitespace().collect();
    let ticks = f.get(11)?.parse::<f64>().ok()? + f.get(12)?.parse::<f64>().ok()?;
    Some(ticks / 100.0)
}

fn build(plan: StepsPlan, steps: usize, shift_x: f64) -> Build {
    let mut settings = FieldSettings::default();
    settings.numerics.steps_per_cycle = steps;
    let mut fields = Vec::new();
    let mut seconds = Vec::new();
    let mut per_primitive = Vec::new();
    let cpu0 = process_cpu_seconds();
    for p in Library::default_primitives() {
        let mut p = p;
        p.shift[0] += shift_x;
        let motion = p.motion();
        let at = plan.settings(&p, FieldKind::Force, &Grid::DEFAULT, &settings);
        let start = Instant::now();
        fields.push(Field::compute(
            &motion,
            &Grid::DEFAULT,
            FieldKind::Force,
            &at,
            &|| {},
        ));
        seconds.push(start.elapsed().as_secs_f64());
        per_primitive.push(at.numerics.steps_per_cycle);
    }
    let cpu_seconds = match (cpu0, process_cpu_seconds()) {
        (Some(a), Some(b)) => Some(b - a),
        _ => None,
    };
    Build {
        steps,
        per_primitive,
        fields,
        seconds,
        cpu_seconds,
    }
}

/// Builds the default 8-primitive force library (21 × 21, 30 phases,
/// default settings) at `steps` RK4 steps per cycle, timing each field.
pub fn build_force_library(steps: usize) -> Build {
    build(StepsPlan::Uniform, steps, 0.0)
}

/// The default force library with each primitive at its calibrated steps
/// per cycle ([`StepsPlan::Calibrated`]), timing each field.
pub fn build_calibrated_force_library() -> Build {
    build(
        StepsPlan::Calibrated,
        FieldSettings::default().numerics.steps_per_cycle,
        0.0,
    )
}

/// The best (fastest) of `REPEATS` builds by `f`.
fn best_of(f: impl Fn() -> Build) -> Build {
    let mut best = f();
    for _ in 1..REPEATS {
        let b = f();
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

fn row(cells: impl IntoIterator<Item = String>) -> String {
    cells.into_iter().collect::<Vec<_>>().join(" | ")
}

/// Every build `platefield study speed` measures, and the errors, orders and
/// counts it reports.
struct Measured {
    names: Vec<&'static str>,
    reference: Build,
    builds: Vec<Build>,
    calibrated: Build,
    calibrated_errors: Vec<f64>,
    errors: Vec<Vec<f64>>,
    noise: Vec<f64>,
    orders: Vec<Vec<f64>>,
    /// The build with half the finest build's steps.
    half: usize,
    fine_order: Vec<f64>,
    ref_error: Vec<f64>,
    /// Points each field simulates.
    simulated: Vec<usize>,
    /// One-cycle simulations of one build.
    simulations: usize,
}

/// The largest of `e` (0 for none).
fn worst(e: &[f64]) -> f64 {
    e.iter().copied().fold(0.0, |a: f64, x| a.max(x))
}

/// A row of the error table with errors only: the worst, then each
/// primitive's.
fn error_only_row(md: &mut String, label: &str, e: &[f64]) {
    let _ = writeln!(
        md,
        "| {label} | | | {} | {} |",
        sci(worst(e)),
        row(e.iter().map(|x| sci(*x)))
    );
}

/// Each field's relative L2 error of `b` against `reference`.
fn errors_against(b: &Build, reference: &Build) -> Vec<f64> {
    b.fields
        .iter()
        .zip(&reference.fields)
        .map(|(f, r)| relative_l2(f, r).0)
        .collect()
}

/// The reference's own error, estimated by Richardson: e(n) = C n^-p gives
/// e_ref = e(n) / ((n_ref/n)^p − 1) from the errors `e` at `n` steps, with
/// p the observed `order`, at most [`RICHARDSON_ORDER`] (module docs).
fn richardson(e: &[f64], order: &[f64], n: usize) -> Vec<f64> {
    let ratio = REFERENCE_STEPS as f64 / n as f64;
    e.iter()
        .zip(order)
        .map(|(e, p)| {
            if p.is_finite() && *p > 0.0 {
                e / (ratio.powf(p.min(RICHARDSON_ORDER)) - 1.0)
            } else {
                f64::NAN
            }
        })
        .collect()
}

/// Builds the libraries and measures them.
fn measure() -> Measured {
    let names: Vec<&'static str> = Library::default_primitives()
        .iter()
        .map(|p| p.kind.name())
        .collect();
    let reference = build_force_library(REFERENCE_STEPS);
    let builds: Vec<Build> = SPEED_STEPS
        .iter()
        .map(|&s| best_of(|| build_force_library(s)))
        .collect();
    let calibrated = best_of(build_calibrated_force_library);
    let calibrated_errors = errors_against(&calibrated, &reference);
    let last = builds.len() - 1;
    let errors: Vec<Vec<f64>> = builds
        .iter()
        .map(|b| errors_against(b, &reference))
        .collect();
    let perturbed = build(StepsPlan::Uniform, builds[last].steps, PERTURBATION);
    let noise = errors_against(&perturbed, &builds[last]);
    let orders: Vec<Vec<f64>> = (1..builds.len())
        .map(|i| {
            errors[i - 1]
                .iter()
                .zip(&errors[i])
                .map(|(a, b)| {
                    (a / b).ln() / (builds[i].steps as f64 / builds[i - 1].steps as f64).ln()
                })
                .collect()
        })
        .collect();
    // The observed order between the finest build and the one with half its
    // steps (neighbouring counts differ by too little for a steady estimate).
    let half = builds
        .iter()
        .position(|b| 2 * b.steps == builds[last].steps)
        .unwrap_or(last - 1);
    let fine_order: Vec<f64> = errors[half]
        .iter()
        .zip(&errors[last])
        .map(|(a, b)| (a / b).ln() / (builds[last].steps as f64 / builds[half].steps as f64).ln())
        .collect();
    let ref_error = richardson(&errors[last], &fine_order, builds[last].steps);
    let g = Grid::DEFAULT;
    let s = FieldSettings::default();
    // Points each field simulates: one per family of points its motion
    // moves alike (`platefield::motion::Invariance`).
    let simulated: Vec<usize> = Library::default_primitives()
        .iter()
        .map(|p| {
            Orbits::of(&g.points(), p.motion().invariance())
                .representatives
                .len()
        })
        .collect();
    let simulations: usize = simulated.iter().sum::<usize>() * s.phases;
    Measured {
        names,
        reference,
        builds,
        calibrated,
        calibrated_errors,
        errors,
        noise,
        orders,
        half,
        fine_order,
        ref_error,
        simulated,
        simulations,
    }
}

/// Measures and writes `out/library_speed.md`; returns it.
pub fn library_speed(out: &Path) -> Result<String> {
    let m = measure();
    let mut md = error_table(&m);
    order_table(&m, &mut md);
    time_table(&m, &mut md);
    verdict(&m, &mut md);
    own_steps(&m, &mut md);
    error_limits(&m, &mut md);
    time_limits(&m, &mut md);
    write_atomic(&out.join("library_speed.md"), md.as_bytes())?;
    Ok(md)
}

/// The opening paragraph and the error table: every build's times and
/// errors, the calibrated build, the reference's own error and the
/// reproducibility row.
fn error_table(m: &Measured) -> String {
    let (names, reference, builds, calibrated) = (&m.names, &m.reference, &m.builds, &m.calibrated);
    let (calibrated_errors, errors, noise, ref_error) =
        (&m.calibrated_errors, &m.errors, &m.noise, &m.ref_error);
    let simulations = &m.simulations;
    let last = builds.len() - 1;
    let threads = rayon::current_num_threads();
    let g = Grid::DEFAULT;
    let s = FieldSettings::default();
    let dashes = "---|".repeat(names.len());
    let load = load_average().map_or(String::new(), |l| {
        format!(" The 1-minute load average when the report was written was {l}.")
    });
    let mut md = format!(
        "# Library speed against error\n\n\
         The default 8-primitive zero-velocity force library: {}×{} grid over ±4 cm, {} start \
         phases, model `{}`, μ = {} ({} samples × {} phases = {} one-cycle simulations point by \
         point; {simulations} with one point simulated per family of points a motion moves \
         alike, `src/motion/invariance.rs`: points simulated per primitive below). Wall time of \
         the whole build, best of {REPEATS}, rayon with {threads} threads, and the CPU time of \
         that build over all threads, on the machine that ran `platefield study speed`: timings vary \
         with the machine and its load (it was shared with other builds), the errors do \
         not.{load} Error: relative L2 against a {REFERENCE_STEPS}-step reference (built in \
         {:.2} s), over samples valid in both.\n\n\
         | steps per cycle | wall time (s) | CPU time (s) | worst error | {} |\n|---|---|---|---|{dashes}\n",
        g.n[0],
        g.n[1],
        s.phases,
        s.model.name(),
        s.friction.kinetic,
        8 * g.len(),
        s.phases,
        8 * g.len() * s.phases,
        reference.total(),
        names.join(" | "),
    );
    for (b, e) in builds.iter().zip(errors) {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {} | {} | {} |",
            b.steps,
            b.total(),
            b.cpu_seconds.map_or("n/a".into(), |c| format!("{c:.2}")),
            sci(worst(e)),
            row(e.iter().map(|x| sci(*x)))
        );
    }
    let _ = writeln!(
        md,
        "| calibrated: each primitive at its `force_steps` (below) | {:.3} | {} | {} | {} |",
        calibrated.total(),
        calibrated
            .cpu_seconds
            .map_or("n/a".into(), |c| format!("{c:.2}")),
        sci(worst(calibrated_errors)),
        row(calibrated_errors.iter().map(|x| sci(*x)))
    );
    error_only_row(&mut md, "reference's own error (estimate)", ref_error);
    let shifted = format!(
        "reproducibility: {} steps, motions shifted by {PERTURBATION:e} m",
        builds[last].steps
    );
    error_only_row(&mut md, &shifted, noise);
    md
}

/// The notes on the last rows, and the observed orders between
/// neighbouring step counts.
fn order_table(m: &Measured, md: &mut String) {
    let (names, builds, orders, half) = (&m.names, &m.builds, &m.orders, &m.half);
    let last = builds.len() - 1;
    let dashes = "---|".repeat(names.len());
    let _ = write!(
        md,
        "\n*Reference's own error*: Richardson estimate e({n}) / (({REFERENCE_STEPS}/{n})^p − 1) \
         with p the observed order between {} and {n} steps, at most {RICHARDSON_ORDER} (the \
         2-D fields converge faster there than they do from 16 steps on, `order_2d`). \
         *Reproducibility*: the \
         {n}-step build again with every motion shifted by {PERTURBATION:e} m, against the \
         unshifted one; the true fields change by about 1e-10 relative, so anything larger is \
         the integrator's sensitivity to round-off-sized changes of its input.\n\n\
         Observed order of convergence between neighbouring step counts n < n′, \
         ln(e(n)/e(n′))/ln(n′/n):\n\n| steps n → n′ | {} |\n|---|{dashes}\n",
        builds[*half].steps,
        names.join(" | "),
        n = builds[last].steps,
    );
    for (i, o) in orders.iter().enumerate() {
        let _ = writeln!(
            md,
            "| {} → {} | {} |",
            builds[i].steps,
            builds[i + 1].steps,
            row(o.iter().map(|p| if p.is_finite() {
                format!("{p:.2}")
            } else {
                "n/a".into()
            }))
        );
    }
}

/// Wall time per primitive, calibrated steps and points simulated.
fn time_table(m: &Measured, md: &mut String) {
    let (names, reference, builds, calibrated) = (&m.names, &m.reference, &m.builds, &m.calibrated);
    let simulated = &m.simulated;
    let g = Grid::DEFAULT;
    let dashes = "---|".repeat(names.len());
    let _ = write!(
        md,
        "\nWall time per primitive (s):\n\n| steps per cycle | {} |\n|---|{dashes}\n",
        names.join(" | ")
    );
    for b in builds.iter().chain(std::iter::once(reference)) {
        let _ = writeln!(
            md,
            "| {} | {} |",
            b.steps,
            row(b.seconds.iter().map(|x| format!("{x:.3}")))
        );
    }
    let _ = writeln!(
        md,
        "| calibrated | {} |",
        row(calibrated.seconds.iter().map(|x| format!("{x:.3}")))
    );
    let _ = writeln!(
        md,
        "| calibrated steps per cycle | {} |",
        row(calibrated.per_primitive.iter().map(|n| n.to_string()))
    );
    let _ = writeln!(
        md,
        "| points simulated (of {}) | {} |",
        g.len(),
        row(simulated.iter().map(|n| n.to_string()))
    );
}

/// The verdict against the time and error target, from the numbers.
fn verdict(m: &Measured, md: &mut String) {
    let (names, builds, calibrated, calibrated_errors) =
        (&m.names, &m.builds, &m.calibrated, &m.calibrated_errors);
    let errors = &m.errors;
    let threads = rayon::current_num_threads();
    let met = builds
        .iter()
        .zip(errors)
        .find(|(b, e)| b.total() <= TARGET_SECONDS && worst(e) <= TARGET_ERROR);
    let _ = write!(
        md,
        "\n## Target: the library in ≤ {TARGET_SECONDS} s at ≤ {} relative error\n\n",
        sci(TARGET_ERROR)
    );
    let plan_met = calibrated.total() <= TARGET_SECONDS && worst(calibrated_errors) <= TARGET_ERROR;
    let _ = write!(
        md,
        "**{}** with each primitive at its calibrated steps per cycle ({}; \
         `StepsPlan::Calibrated`, the force fields `platefield study primitives --calibrated` \
         builds): {:.3} s wall, best of {REPEATS} ({:.2}× the time target){}, worst error \
         {}.\n\nWith one step count for every primitive: ",
        if plan_met { "Met" } else { "Not met" },
        names
            .iter()
            .zip(&calibrated.per_primitive)
            .map(|(n, s)| format!("{n} {s}"))
            .collect::<Vec<_>>()
            .join(", "),
        calibrated.total(),
        calibrated.total() / TARGET_SECONDS,
        calibrated.cpu_seconds.map_or(String::new(), |c| format!(
            "; its CPU time over the {threads} threads, {:.3} s each, less sensitive to the \
             machine's load",
            c / threads as f64
        )),
        sci(worst(calibrated_errors))
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
            let _ = write!(md, "**Not met.** ");
            nearest_accurate(m, md);
            nearest_fast(m, md);
        }
    }
}

/// Not met: where the error target is first reached, or the best error.
fn nearest_accurate(m: &Measured, md: &mut String) {
    let (builds, errors) = (&m.builds, &m.errors);
    let last = builds.len() - 1;
    let accurate = builds
        .iter()
        .zip(errors)
        .find(|(_, e)| worst(e) <= TARGET_ERROR);
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
            let (at, best) = errors.iter().map(|e| worst(e)).enumerate().fold(
                (last, f64::INFINITY),
                |b, (i, e)| if e < b.1 { (i, e) } else { b },
            );
            let _ = write!(
                md,
                "No measured step count reaches the error target: the best worst-case \
                 error is {} ({:.0}× the target), at {} steps in {:.3} s. ",
                sci(best),
                best / TARGET_ERROR,
                builds[at].steps,
                builds[at].total()
            );
        }
    }
}

/// Not met: the most accurate build within the time target, or the
/// cheapest build's time (and its CPU time per thread).
fn nearest_fast(m: &Measured, md: &mut String) {
    let (builds, errors) = (&m.builds, &m.errors);
    let threads = rayon::current_num_threads();
    let fast = builds
        .iter()
        .zip(errors)
        .rfind(|(b, _)| b.total() <= TARGET_SECONDS);
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
            let _ = write!(
                md,
                "No build is within the time target either: the cheapest, {} steps per \
                 cycle, takes {:.3} s ({:.1}× the target)",
                builds[0].steps,
                builds[0].total(),
                builds[0].total() / TARGET_SECONDS
            );
            match builds[0].cpu_seconds {
                Some(c) => {
                    let free = c / threads as f64;
                    let _ = writeln!(
                        md,
                        ", and {free:.2} s ({:.1}× the target) even on {threads} free \
                         cores (its CPU time divided by the threads).",
                        free / TARGET_SECONDS
                    );
                }
                None => md.push_str(".\n"),
            }
        }
    }
}

/// Each primitive at its own fewest steps within the error target: the
/// per-primitive times already measured, summed (no new build).
fn own_steps(m: &Measured, md: &mut String) {
    let (names, builds, calibrated, errors) = (&m.names, &m.builds, &m.calibrated, &m.errors);
    let own: Vec<Option<usize>> = (0..names.len())
        .map(|i| errors.iter().position(|e| e[i] <= TARGET_ERROR))
        .collect();
    let never: Vec<&str> = names
        .iter()
        .zip(&own)
        .filter(|(_, o)| o.is_none())
        .map(|(n, _)| *n)
        .collect();
    if !never.is_empty() {
        let _ = writeln!(
            md,
            "\n**{} reach {} at no step count measured: the calibrated counts \
             (`PrimitiveKind::force_steps`) cannot hold; recalibrate.**",
            never.join(", "),
            sci(TARGET_ERROR)
        );
    }
    if own.iter().all(Option::is_some) {
        let picks: Vec<usize> = own.iter().flatten().copied().collect();
        let total: f64 = picks
            .iter()
            .enumerate()
            .map(|(i, &b)| builds[b].seconds[i])
            .sum();
        let _ = writeln!(
            md,
            "
**Each primitive at its own fewest steps** within {} in the uniform builds above ({}): \
             {total:.3} s, the sum of those per-primitive wall times ({:.2}× the time target). {}",
            sci(TARGET_ERROR),
            names
                .iter()
                .zip(&picks)
                .map(|(n, &b)| format!("{n} {}", builds[b].steps))
                .collect::<Vec<_>>()
                .join(", "),
            total / TARGET_SECONDS,
            if picks
                .iter()
                .map(|&b| builds[b].steps)
                .eq(calibrated.per_primitive.iter().copied())
            {
                "These are the calibrated counts (`PrimitiveKind::force_steps`).".to_string()
            } else {
                "**The calibrated counts (`PrimitiveKind::force_steps`) differ: recalibrate \
                 them from this table.**"
                    .to_string()
            }
        );
    }
}

/// What limits the error: 1-D against 2-D slips.
fn error_limits(m: &Measured, md: &mut String) {
    let (names, builds, errors, noise) = (&m.names, &m.builds, &m.errors, &m.noise);
    let (half, fine_order) = (&m.half, &m.fine_order);
    let last = builds.len() - 1;
    let one_d = ["LineSink", "LineSource", "Trans"];
    let pick = |want_1d: bool, v: &[f64], f: &dyn Fn(f64) -> String| -> String {
        names
            .iter()
            .zip(v)
            .filter(|(n, _)| one_d.contains(n) == want_1d)
            .map(|(n, x)| format!("{n} {}", f(*x)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let order_fmt = |p: f64| format!("{p:.1}");
    let col = |name: &str| names.iter().position(|n| *n == name);
    let one_d_cols: Vec<usize> = one_d.iter().filter_map(|n| col(n)).collect();
    let one_d_reach = builds
        .iter()
        .zip(errors)
        .find(|(_, e)| one_d_cols.iter().all(|&i| e[i] <= TARGET_ERROR))
        .map_or(
            "none of the measured builds reaches the error target for all of them".into(),
            |(b, _)| {
                format!(
                    "all of them reach the error target from {} steps per cycle",
                    b.steps
                )
            },
        );
    let _ = writeln!(
        md,
        "\n**What limits the error.** Primitives whose slip stays on one line ({}) converge at \
         RK4's fourth order (observed between {} and {} steps: {}); their fields are \
         reproducible to round-off (shifted by {PERTURBATION:e} m: {}); {one_d_reach}. The others \
         slip in 2-D. The integrator follows a 2-D slip velocity through its swings past u = 0 \
         and its slow-downs to a stop with RK4 steps in regularised time dτ = dt/|u| \
         (`src/dynamics/swing.rs`) and takes starts from rest and stiff slips with implicit \
         Radau IIA steps (`src/dynamics/radau.rs`); observed orders between those two \
         builds: {}. A {PERTURBATION:e} m shift of the motion changes their fields by {} at {} \
         steps, against errors of {} there. Where the two are of the same order the error is \
         set by the integrator's discontinuous response to round-off-sized changes (which side \
         of a threshold a swing or a stop falls on), not by truncation error that more steps \
         would remove; the reference's own error for these primitives (estimates above) says \
         how far their errors here can be trusted.",
        one_d.join(", "),
        builds[*half].steps,
        builds[last].steps,
        pick(true, fine_order, &order_fmt),
        pick(true, noise, &sci),
        pick(false, fine_order, &order_fmt),
        pick(false, noise, &sci),
        builds[last].steps,
        pick(false, &errors[last], &sci),
    );
}

/// What limits the time, and how to regenerate.
fn time_limits(m: &Measured, md: &mut String) {
    let (names, builds, simulated, simulations) =
        (&m.names, &m.builds, &m.simulated, &m.simulations);
    let threads = rayon::current_num_threads();
    let g = Grid::DEFAULT;
    let _ = writeln!(
        md,
        "\n**What limits the time.** Wall time against the nominal step count: {}; CPU time \
         (over all threads, less sensitive to the machine's load): {}. The 2-D primitives are \
         the slowest (per-primitive times above): their cost is the regularised τ-steps through \
         each swing and slow-down, each with four evaluations of the plate kinematics off the \
         tabulated time grid, whose number falls less than in proportion with fewer nominal \
         steps; locating stops and break-aways by root finding adds to it. A primitive whose \
         motion moves lines or circles of points alike simulates one point per line or circle \
         (points simulated, above); {} moves no two points alike and simulates all {}. One build is {simulations} one-cycle simulations on \
         {threads} threads; meeting {TARGET_SECONDS} s would need about {:.1} µs per simulation \
         per thread.",
        builds
            .iter()
            .map(|b| format!("{} steps {:.2} s", b.steps, b.total()))
            .collect::<Vec<_>>()
            .join(", "),
        builds
            .iter()
            .map(|b| format!(
                "{} steps {}",
                b.steps,
                b.cpu_seconds.map_or("n/a".into(), |c| format!("{c:.2} s"))
            ))
            .collect::<Vec<_>>()
            .join(", "),
        names
            .iter()
            .zip(simulated)
            .filter(|(_, n)| **n == g.len())
            .map(|(name, _)| *name)
            .collect::<Vec<_>>()
            .join(", "),
        g.len(),
        TARGET_SECONDS * threads as f64 / *simulations as f64 * 1e6
    );
    let _ = writeln!(
        md,
        "\nRegenerate: `platefield study speed` (about 12 s on the 2-core machine). Bench: `cargo bench --bench library` \
         (one build at 32 steps per cycle and one calibrated)."
    );
}

/// Default output folder of `platefield study speed`.
pub const DIR: &str = "results";

/// `platefield study speed`: [`library_speed`] and the file it wrote.
pub fn run(out: &Path) -> Result<String> {
    let mut s = library_speed(out)?;
    let _ = writeln!(s, "wrote {}", out.join("library_speed.md").display());
    Ok(s)
}
