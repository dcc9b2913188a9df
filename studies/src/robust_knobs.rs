//! Study: the mirror-image time-share's knobs measured on the family,
//! `results/robust_knobs.md`.
//!
//! A robust design over a friction range rests on two choices the product
//! makes for every target ([`platefield::design::mirror`]):
//! - **segment cycles** ([`platefield::design::mirror::MIRROR_SEGMENT_CYCLES`]):
//!   how long each of the two motions of the share plays, its ramps from
//!   and to rest included. Longer segments spend less of the period in the
//!   ramps (which realise a weaker, turned field) and more in the steady
//!   field; shorter ones join the two halves more often, so a part drifts
//!   less under either half alone before the other corrects it;
//! - **frictions judged** over the range (the judge's sweep,
//!   [`crate::robust_family::VALUES`] evenly, ends included): fewer cost
//!   less and may miss a worst case between them.
//!
//! For each member of the seeded family ([`platefield::request::family`],
//! seed [`crate::robust_family::SEED`]) that a reflection maps to itself
//! ([`platefield::design::mirror::mirror_axis`]: the sinks, ellipses,
//! saddles and line sinks), `mirror` designs it over its range (the
//! synthesis for the range's middle within the design's limits), and its
//! mirror-image share about that line is built at each of [`CYCLES`]
//! segment cycles and judged ([`platefield::design::judge`]) at
//! [`FRICTIONS`] frictions evenly over the range. The sweeps of 3 and 5
//! frictions are every fourth and every second of those 9, so the second
//! knob is read off the same plays. Work is counted in point-part steps
//! (deterministic; CPU seconds are printed only). The counter-rotating
//! share (the targets without a mirror line) is built with the same
//! segment length; this study does not measure it there.

use std::path::Path;

use platefield::design::method::Method;
use platefield::design::mirror::{mirror_axis, mirror_share, MirrorLine, MIRROR_SEGMENT_CYCLES};
use platefield::design::tolerance::quantile;
use platefield::dynamics::steps_taken;
use platefield::error::{Error, Result};
use platefield::play::sensitivity::FrictionRow;
use platefield::request::family::family;
use platefield::request::{FrictionSpec, Target};
use platefield_report::table::Table;

use super::robust::{designed, judged};
use super::robust_family::{COUNT, GOALS, SEED};
use super::speed::process_cpu_seconds;

/// Default output folder.
pub const DIR: &str = "results";
/// The segment cycles compared (each more than the two ramps' 8 cycles).
pub const CYCLES: [u32; 5] = [12, 20, 28, 40, 56];
/// Frictions each share is judged at, evenly over the range, ends
/// included: 9, so that 5 (every second) and 3 (every fourth) are among
/// them.
pub const FRICTIONS: usize = 9;
/// The family's members that a reflection maps to themselves: its sinks,
/// ellipses, saddles and line sinks (`studies/tests/robust_knobs.rs`
/// counts them).
pub const MEMBERS: usize = 28;
/// The sweeps compared, as strides into the [`FRICTIONS`] values.
const SWEEPS: [(usize, usize); 3] = [(3, 4), (5, 2), (9, 1)];

/// One family member's shares, judged.
#[derive(Debug, Clone)]
pub struct Member {
    /// The target.
    pub target: Target,
    /// The mirror line: its angle, and its signed distance from the plate
    /// centre.
    pub line: String,
    /// For each of [`CYCLES`]: the judge at each of the [`FRICTIONS`]
    /// values, and its counted steps.
    pub shares: Vec<(Vec<FrictionRow>, u64)>,
    /// For each of [`CYCLES`]: the CPU seconds of its judge (printed only).
    pub cpu_s: Vec<f64>,
}

impl Member {
    /// Worst shape error and weakest strength of the share at
    /// `CYCLES[c]`, over the sweep of `n` frictions: 3, 5 or 9 (any other
    /// `n`: all 9). A friction where the judge measured nothing counts as
    /// the worst (an infinite shape error, no strength).
    pub fn worst(&self, c: usize, n: usize) -> (f64, f64) {
        let stride = SWEEPS.iter().find(|(k, _)| *k == n).map_or(1, |(_, s)| *s);
        self.shares[c]
            .0
            .iter()
            .step_by(stride)
            .fold((0.0_f64, f64::INFINITY), |(e, s), r| {
                (
                    e.max(r.realised_shape_error.unwrap_or(f64::INFINITY)),
                    s.min(r.realised_strength.unwrap_or(0.0)),
                )
            })
    }
}

/// The first `count` members of the family of [`COUNT`] that a reflection
/// maps to themselves, in the family's order (its sinks first, then its
/// ellipses, saddles and line sinks).
///
/// # Errors
/// A member's points cannot be sampled.
pub fn members(count: usize) -> Result<Vec<Target>> {
    let mut out = Vec::new();
    for t in family(SEED, COUNT) {
        if out.len() == count {
            break;
        }
        if mirror_axis(&t, &t.sample()?).is_some() {
            out.push(t);
        }
    }
    Ok(out)
}

/// Designs `target` by `mirror` over its range and judges its share at
/// each of [`CYCLES`] ([`Member`]).
///
/// # Errors
/// The design fails, or the target has no mirror line.
pub fn member(target: &Target, quiet: bool) -> Result<Member> {
    let spec = target.friction.unwrap_or(FrictionSpec::range(0.2, 0.4));
    let mu: Vec<f64> = spec.values(FRICTIONS).iter().map(|f| f.kinetic).collect();
    let line = mirror_axis(target, &target.sample()?)
        .ok_or_else(|| Error::invalid("target", "no mirror line"))?;
    let md = designed(target, Method::Mirror, quiet)?;
    let base = md
        .synthesized
        .as_ref()
        .ok_or_else(|| Error::invalid("target", "mirror made no synthesis"))?;
    let mut shares = Vec::new();
    let mut cpu_s = Vec::new();
    for cycles in CYCLES {
        let share = mirror_share(base, &md.limits, &line, cycles)?;
        let (before, start) = (steps_taken(), process_cpu_seconds());
        let rows = judged(target, &share, &mu)?;
        shares.push((rows, steps_taken() - before));
        cpu_s.push(
            process_cpu_seconds()
                .zip(start)
                .map_or(f64::NAN, |(b, a)| b - a),
        );
    }
    Ok(Member {
        target: target.clone(),
        line: describe(&line),
        shares,
        cpu_s,
    })
}

/// A mirror line: its angle, and its distance from the plate centre where
/// it misses the centre by 0.05 mm or more.
fn describe(line: &MirrorLine) -> String {
    let cm = 100.0 * line.offset();
    if cm.abs() < 0.005 {
        format!("{:.1}° through the centre", line.angle_deg)
    } else {
        format!("{:.1}°, {cm:.2} cm off the centre", line.angle_deg)
    }
}

fn pct(x: f64) -> String {
    platefield::output::percent(x, 1)
}

/// `robust_knobs.md` from the members.
pub fn render(members: &[Member]) -> String {
    let n = members.len();
    let mut md = format!(
        "# The robust share's knobs over the family\n\nGenerated by `platefield study robust-knobs` (see `platefield_studies::robust_knobs`): the {n} members of the seeded family of `results/robust_family.md` (seed {SEED}) that a reflection maps to themselves. Each is designed by `mirror` over its friction range; its mirror-image share is built at each segment length and judged (`design::judge`) at {FRICTIONS} frictions evenly over the range, ends included. Shape error ‖R − ŝt‖/‖ŝt‖, strength ŝ (× the target's). Work in point-part steps of the judge per friction (seconds per step: `results/design_speed.md`). The design's own segment length is {MIRROR_SEGMENT_CYCLES} cycles.\n\n## Segment cycles (worst over {FRICTIONS} frictions)\n\n"
    );
    let mut table = Table::new([
        "segment cycles",
        "worst shape: median",
        "90th percentile",
        "maximum",
        "targets ≤ 6 %",
        "weakest strength: median",
        "judge steps per friction: median",
    ]);
    for (c, cycles) in CYCLES.iter().enumerate() {
        let shape: Vec<f64> = members.iter().map(|m| m.worst(c, FRICTIONS).0).collect();
        let strength: Vec<f64> = members.iter().map(|m| m.worst(c, FRICTIONS).1).collect();
        let steps: Vec<f64> = members
            .iter()
            .map(|m| m.shares[c].1 as f64 / FRICTIONS as f64)
            .collect();
        let held = shape.iter().filter(|e| **e <= GOALS.0).count();
        table.row([
            cycles.to_string(),
            pct(quantile(&shape, 0.5)),
            pct(quantile(&shape, 0.9)),
            pct(quantile(&shape, 1.0)),
            format!("{held} of {n}"),
            format!(
                "{:.3}",
                -quantile(&strength.iter().map(|s| -s).collect::<Vec<_>>(), 0.5)
            ),
            format!("{:.3e}", quantile(&steps, 0.5)),
        ]);
    }
    md.push_str(&table.markdown());
    md.push_str(&format!(
        "\n## Frictions judged (the share at {MIRROR_SEGMENT_CYCLES} cycles)\n\nA sweep of fewer frictions misses the worst case where it falls between them: \"missed\" counts the targets whose worst over the sweep is more than 0.5 percentage point below the worst over {FRICTIONS}.\n\n"
    ));
    let design = CYCLES
        .iter()
        .position(|c| *c == MIRROR_SEGMENT_CYCLES)
        .unwrap_or(0);
    let mut table = Table::new([
        "frictions",
        "worst shape: median",
        "maximum",
        "missed (> 0.5 pp)",
        "largest miss",
    ]);
    for (k, _) in SWEEPS {
        let shape: Vec<f64> = members.iter().map(|m| m.worst(design, k).0).collect();
        let miss: Vec<f64> = members
            .iter()
            .map(|m| m.worst(design, FRICTIONS).0 - m.worst(design, k).0)
            .collect();
        let missed = miss.iter().filter(|d| **d > 0.005).count();
        table.row([
            k.to_string(),
            pct(quantile(&shape, 0.5)),
            pct(quantile(&shape, 1.0)),
            format!("{missed} of {n}"),
            format!("{:.1} pp", 100.0 * miss.iter().copied().fold(0.0, f64::max)),
        ]);
    }
    md.push_str(&table.markdown());
    md.push_str(&format!(
        "\n## Each member (worst shape over {FRICTIONS} frictions)\n\n"
    ));
    let mut head = vec!["target".to_string(), "μ range".into(), "mirror line".into()];
    head.extend(CYCLES.iter().map(|c| format!("{c} cycles")));
    let mut table = Table::new(head);
    for m in members {
        let rows = &m.shares[0].0;
        let range = match (rows.first(), rows.last()) {
            (Some(a), Some(b)) => format!("[{:.3}, {:.3}]", a.friction.kinetic, b.friction.kinetic),
            _ => "n/a".into(),
        };
        let mut row = vec![m.target.name.clone(), range, m.line.clone()];
        row.extend((0..CYCLES.len()).map(|c| pct(m.worst(c, FRICTIONS).0)));
        table.row(row);
    }
    md.push_str(&table.markdown());
    md
}

/// `platefield study robust-knobs`: the first `count` mirror-symmetric
/// members ([`members`]), writes `OUT/robust_knobs.md` and returns the
/// text with each member's CPU seconds (printed only).
///
/// # Errors
/// `out` is not writable, or a design fails.
pub fn run(out: &Path, count: usize, quiet: bool) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let targets = members(count)?;
    let n = targets.len();
    let mut done = Vec::new();
    let mut cpu = String::new();
    for (k, t) in targets.iter().enumerate() {
        platefield::progress::say(&format!("robust-knobs: {} ({} of {n})", t.name, k + 1));
        let start = process_cpu_seconds();
        let m = member(t, quiet)?;
        let spent = process_cpu_seconds()
            .zip(start)
            .map_or(f64::NAN, |(b, a)| b - a);
        cpu.push_str(&format!("{}: {spent:.1} s CPU\n", t.name));
        done.push(m);
    }
    for (c, cycles) in CYCLES.iter().enumerate() {
        let spent: f64 = done.iter().map(|m| m.cpu_s[c]).sum();
        let shape: Vec<f64> = done.iter().map(|m| m.worst(c, FRICTIONS).0).collect();
        cpu.push_str(&format!(
            "{cycles} cycles: {spent:.1} s CPU judging {n} shares at {FRICTIONS} frictions, median worst shape {}\n",
            pct(quantile(&shape, 0.5))
        ));
    }
    let md = render(&done);
    let path = out.join("robust_knobs.md");
    platefield::output::write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\n{cpu}wrote {}\n", path.display()))
}
