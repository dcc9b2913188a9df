//! "Model only what the scene needs": the cheapest model rung whose field is
//! within a tolerance of the full model's.
//!
//! Rungs, cheapest first (switches of [`Model`], see [`platefield::dynamics`]):
//!
//! | rung | switches on | what it neglects |
//! |---|---|---|
//! | `paper` | none ([`Model::PAPER`]) | the part's motion within the cycle (kinematics frozen at the start point), centripetal, gravity tilt, Coriolis |
//! | `paper+moving` | moving | centripetal, tilt, Coriolis |
//! | `paper+moving+centripetal+tilt` | moving, centripetal, tilt | Coriolis |
//! | `full` | all ([`Model::FULL`]) | nothing |
//!
//! [`choose_rung`] computes the field at every rung, measures each one's
//! relative L2 error against `full` over the samples valid in both,
//! ‖F_rung − F_full‖₂ / ‖F_full‖₂, and picks the cheapest rung whose error
//! is within the tolerance *and* whose validity flags (contact lost, not
//! converged, frozen assumption broken) agree with `full`'s at every sample:
//! a cheaper model that misses a contact loss is not acceptable at any
//! error. `full` is always acceptable.
//!
//! The errors are measured, not predicted; the reason string adds the
//! physics that explains them, for example: an in-plane motion has N = g
//! exactly, so the terms that enter only the normal force vanish; a pure
//! translation has Ω = 0, so every plate point has the same acceleration and
//! all four rungs agree to the last bit.
//!
//! Compute times are reported in [`RungResult::seconds`] and printed by
//! `platefield study rungs`, but never written to `rungs.md`, which is
//! deterministic (fields are bitwise independent of the thread count).

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use serde::Serialize;

use platefield::basis::Library;
use platefield::dynamics::Model;
use platefield::error::{non_negative, Result};
use platefield::field::{Field, FieldKind, FieldSettings, Grid, Validity};
use platefield::motion::Motion;
use platefield::output::write_atomic;
use platefield_report::table::Table;

/// Default tolerance: 2 % relative L2 error against the full model. Two
/// per cent is below what separates a primitive's field from its Table I
/// form (the fits in `results/primitives/table1.md` leave relative residuals
/// √(1 − R²) of 3–17 %) and above the integrator's own error at the default
/// 64 steps per cycle (worst 3e-3 over the library,
/// `results/library_speed.md`), so a rung is accepted only when the terms
/// it drops change the field by less than the basis can resolve, and never
/// rejected because of numerical noise.
pub const DEFAULT_RUNG_TOLERANCE: f64 = 0.02;

/// The rungs, cheapest first: name and model.
pub(crate) const RUNGS: [(&str, Model); 4] = [
    ("paper", Model::PAPER),
    (
        "paper+moving",
        Model {
            centripetal: false,
            tilt: false,
            coriolis: false,
            moving: true,
        },
    ),
    (
        "paper+moving+centripetal+tilt",
        Model {
            centripetal: true,
            tilt: true,
            coriolis: false,
            moving: true,
        },
    ),
    ("full", Model::FULL),
];

/// One rung's measurement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RungResult {
    /// Rung name.
    pub name: &'static str,
    /// Its model switches.
    pub model: Model,
    /// Relative L2 error against `full` over samples valid in both
    /// (NaN when there are none).
    pub error: f64,
    /// Samples valid in both.
    pub compared: usize,
    /// Samples whose validity flag differs from `full`'s.
    pub flags_differ: usize,
    /// Within the tolerance with identical validity flags.
    pub acceptable: bool,
    /// Wall time of the field computation (s); not deterministic.
    pub seconds: f64,
}

/// The choice and its evidence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RungReport {
    /// The chosen rung's name.
    pub rung: &'static str,
    /// Its model.
    pub model: Model,
    /// Its measured error against `full`.
    pub error: f64,
    /// The tolerance used.
    pub tolerance: f64,
    /// The field compared.
    pub kind: FieldKind,
    /// Every rung, cheapest first.
    pub rungs: Vec<RungResult>,
    /// Why this rung.
    pub reason: String,
}

/// Relative L2 difference of `a` against `reference` over the samples
/// valid in both, with the number of such samples; 0 when both vanish
/// there, NaN when no sample is valid in both.
pub fn relative_l2(a: &Field, reference: &Field) -> (f64, usize) {
    let (mut num, mut den, mut n) = (0.0, 0.0, 0);
    for k in 0..reference.vectors.len().min(a.vectors.len()) {
        if a.validity[k] != Validity::Ok || reference.validity[k] != Validity::Ok {
            continue;
        }
        let (f, r) = (a.vectors[k], reference.vectors[k]);
        num += (f[0] - r[0]).powi(2) + (f[1] - r[1]).powi(2);
        den += r[0] * r[0] + r[1] * r[1];
        n += 1;
    }
    let e = if n == 0 {
        f64::NAN
    } else if den == 0.0 {
        if num == 0.0 {
            0.0
        } else {
            f64::INFINITY
        }
    } else {
        (num / den).sqrt()
    };
    (e, n)
}

/// True when the motion has no rotation at all (Ω = 0).
fn is_translation(motion: &Motion) -> bool {
    match motion {
        Motion::Screw(s) => s.rotation.is_zero(),
        Motion::Signals(s) | Motion::Ramped(platefield::motion::Ramped { signals: s, .. }) => {
            [&s.angular.x, &s.angular.y, &s.angular.z]
                .iter()
                .all(|terms| terms.iter().all(|t| t.amplitude == 0.0))
        }
        Motion::Held(h) => (0..=h.len()).all(|k| {
            let s = h.state_at(k);
            s.velocity[3..]
                .iter()
                .chain(&s.pose[3..])
                .all(|x| *x == 0.0)
        }),
    }
}

/// `e` as a percentage with three significant digits ("0" when exact).
fn percent(e: f64) -> String {
    if e.is_nan() {
        return "n/a".into();
    }
    if e == 0.0 {
        return "0".into();
    }
    let p = 100.0 * e;
    let decimals = (2 - p.abs().log10().floor() as i32).clamp(0, 12) as usize;
    format!("{p:.decimals$} %")
}

fn flags(n: usize) -> String {
    if n == 1 {
        "1 validity flag differs".into()
    } else {
        format!("{n} validity flags differ")
    }
}

/// Computes `kind` for `motion` on `grid` at every rung (with `settings`
/// otherwise), measures each against `full` and picks the cheapest rung
/// within `tolerance` (see the module docs).
pub fn choose_rung(
    motion: &Motion,
    grid: &Grid,
    kind: FieldKind,
    settings: &FieldSettings,
    tolerance: f64,
) -> RungReport {
    let fields: Vec<(Field, f64)> = RUNGS
        .iter()
        .map(|(_, model)| {
            let s = FieldSettings {
                model: *model,
                ..*settings
            };
            let start = Instant::now();
            let f = Field::compute(motion, grid, kind, &s, &|| {});
            (f, start.elapsed().as_secs_f64())
        })
        .collect();
    let full = &fields[RUNGS.len() - 1].0;
    let rungs: Vec<RungResult> = RUNGS
        .iter()
        .zip(&fields)
        .map(|((name, model), (field, seconds))| {
            let (error, compared) = relative_l2(field, full);
            let flags_differ = field
                .validity
                .iter()
                .zip(&full.validity)
                .filter(|(a, b)| a != b)
                .count();
            let acceptable =
                *model == Model::FULL || (error <= tolerance && flags_differ == 0 && compared > 0);
            RungResult {
                name,
                model: *model,
                error,
                compared,
                flags_differ,
                acceptable,
                seconds: *seconds,
            }
        })
        .collect();
    let chosen = rungs
        .iter()
        .position(|r| r.acceptable)
        .unwrap_or(RUNGS.len() - 1);
    let c = &rungs[chosen];
    let mut reason = rung_reason(&rungs, chosen, tolerance);
    reason.push_str(physics_reason(motion));
    RungReport {
        rung: c.name,
        model: c.model,
        error: c.error,
        tolerance,
        kind,
        rungs,
        reason,
    }
}

/// Why the rung at `chosen` is kept: the cheapest within `tolerance` of
/// full, and what the cheaper ones missed by.
fn rung_reason(rungs: &[RungResult], chosen: usize, tolerance: f64) -> String {
    let c = &rungs[chosen];
    let mut reason = format!(
        "{} is the cheapest rung within {} of full (its error {}{})",
        c.name,
        percent(tolerance),
        percent(c.error),
        if c.name == "full" {
            ", by definition"
        } else {
            ", validity flags identical"
        }
    );
    let missed: Vec<String> = rungs[..chosen]
        .iter()
        .map(|r| {
            let mut s = format!("{} {}", r.name, percent(r.error));
            if r.flags_differ > 0 {
                let _ = write!(s, " ({})", flags(r.flags_differ));
            }
            s
        })
        .collect();
    if !missed.is_empty() {
        let _ = write!(reason, "; cheaper rungs miss it: {}", missed.join(", "));
    }
    reason
}

/// Which of the model's terms the motion's kind makes vanish.
fn physics_reason(motion: &Motion) -> &'static str {
    if motion.is_in_plane() {
        if is_translation(motion) {
            "; in-plane motion: N = g exactly, so the normal-force terms (tilt, centripetal z) vanish, and with no rotation (Ω = 0) the centripetal and Coriolis terms vanish too and every \
             plate point has the same acceleration, so the frozen position is exact"
        } else {
            "; in-plane motion: N = g exactly, so the normal-force terms (tilt, centripetal z) vanish; the rotation about the vertical keeps in-plane centripetal and Coriolis terms"
        }
    } else {
        "; out-of-plane motion: the normal force varies over the cycle and the tilt, centripetal and \
         Coriolis terms enter it"
    }
}

/// The grid of `rungs.md`: 9 × 9 over ±4 cm.
pub(crate) const RUNG_GRID: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [9, 9],
};

/// Rung reports for the 8 default primitives on [`RUNG_GRID`], force and
/// velocity fields, default settings: (primitive name, report).
pub(crate) fn default_reports(tolerance: f64) -> Vec<(&'static str, RungReport)> {
    let settings = FieldSettings::default();
    let mut out = Vec::new();
    for kind in [FieldKind::Force, FieldKind::Velocity] {
        for p in Library::default_primitives() {
            let r = choose_rung(&p.motion(), &RUNG_GRID, kind, &settings, tolerance);
            out.push((p.kind.name(), r));
        }
    }
    out
}

/// `rungs.md` for `reports` (as from [`default_reports`]): deterministic,
/// no times.
pub(crate) fn rungs_markdown(reports: &[(&'static str, RungReport)], tolerance: f64) -> String {
    let s = FieldSettings::default();
    let g = RUNG_GRID;
    let mut md = format!(
        "# Model rungs: the cheapest model within tolerance\n\n\
         Each primitive's field computed at every model rung on a {}×{} grid over x ∈ [{}, {}] m, \
         y ∈ [{}, {}] m (μ = {}, {} start phases, {} RK4 steps per cycle), and compared with the \
         full model: relative L2 error ‖F_rung − F_full‖/‖F_full‖ over the samples valid in both. \
         The chosen rung is the cheapest with error ≤ {} and validity flags (contact lost, not \
         converged, frozen assumption broken) identical to full's at every sample. \
         Regenerate: `platefield study rungs --tolerance {tolerance}` (it also prints compute times, \
         which are not written here).\n\n\
         Rungs, cheapest first: `paper` (frozen position, no centripetal, tilt or Coriolis), \
         `paper+moving`, `paper+moving+centripetal+tilt`, `full` (adds Coriolis).\n",
        g.n[0],
        g.n[1],
        g.x[0],
        g.x[1],
        g.y[0],
        g.y[1],
        s.friction.kinetic,
        s.phases,
        s.numerics.steps_per_cycle,
        percent(tolerance),
    );
    for kind in [FieldKind::Force, FieldKind::Velocity] {
        let _ = write!(
            md,
            "\n## {}\n\n",
            match kind {
                FieldKind::Force => "Zero-velocity force fields",
                FieldKind::Velocity => "Steady-state velocity fields",
            }
        );
        let mut table = Table::new(
            ["primitive", "chosen"]
                .into_iter()
                .chain(RUNGS.map(|r| r.0))
                .chain(["why"]),
        );
        for (name, r) in reports.iter().filter(|(_, r)| r.kind == kind) {
            let cells: Vec<String> = r
                .rungs
                .iter()
                .map(|x| {
                    let mut c = percent(x.error);
                    if x.flags_differ > 0 {
                        let _ = write!(c, " ({})", flags(x.flags_differ));
                    }
                    c
                })
                .collect();
            let mut row = vec![name.to_string(), format!("**{}**", r.rung)];
            row.extend(cells);
            row.push(r.reason.to_string());
            table.row(row);
        }
        md.push_str(&table.markdown());
    }
    md
}

/// Writes `out/rungs.md` for `reports` and returns it.
pub(crate) fn write_reports(
    out: &Path,
    reports: &[(&'static str, RungReport)],
    tolerance: f64,
) -> Result<String> {
    let md = rungs_markdown(reports, tolerance);
    write_atomic(&out.join("rungs.md"), md.as_bytes())?;
    Ok(md)
}

/// Compute times of every rung (s), as a plain-text table for the terminal.
pub(crate) fn times_table(reports: &[(&'static str, RungReport)]) -> String {
    let mut t = format!("{:<14} {:<9}", "compute time", "field");
    for (name, _) in RUNGS {
        let _ = write!(t, " {name:>30}");
    }
    t.push('\n');
    for (name, r) in reports {
        let kind = match r.kind {
            FieldKind::Force => "force",
            FieldKind::Velocity => "velocity",
        };
        let _ = write!(t, "{name:<14} {kind:<9}");
        for x in &r.rungs {
            let _ = write!(t, " {:>29.3}s", x.seconds);
        }
        t.push('\n');
    }
    t
}

/// Default output folder of `platefield study rungs`.
pub const DIR: &str = "results/primitives";

/// `platefield study rungs`: every primitive's rungs at `tolerance`, written to
/// `out/rungs.md`; returns that table, the compute times and the file.
pub fn run(out: &Path, tolerance: f64) -> Result<String> {
    non_negative("--tolerance", tolerance)?;
    let reports = default_reports(tolerance);
    let mut s = write_reports(out, &reports, tolerance)?;
    let _ = write!(s, "\n{}", times_table(&reports));
    let _ = writeln!(s, "wrote {}", out.join("rungs.md").display());
    Ok(s)
}
