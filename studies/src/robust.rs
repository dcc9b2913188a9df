//! Study: designs for the paper's μ = 0.3 against designs robust over
//! μ ∈ [0.2, 0.4], played across that range: `results/robust.md`.
//!
//! For each of sink, saddle, whirlpool, squeeze_trans and line_sink_30 the
//! shipped target is designed twice with `design`'s defaults (`auto`):
//! as shipped (μ = 0.3), and with `"friction": [0.2, 0.4]`, which judges
//! every candidate by its worst case over the range and adds the
//! mirror-image time-share (about the target's symmetry axis, or with a
//! partner synthesized for its mirror image where no reflection maps the
//! target to itself)
//! ([`platefield::design::mirror`]). Each kept design is then played at
//! μ = 0.2, 0.25, 0.3, 0.35 and 0.4 by the judge
//! ([`platefield::design::judge`]: the realised field at ≥ 9 × 9 held
//! points over the whole region, whole schedule periods until periodic):
//! realised strength ŝ and shape error ‖R − ŝt‖/‖ŝt‖ against the target. Each of these two kept
//! designs is also exported as `platefield export` writes it (10 kHz,
//! held samples) and the file **replayed** by the same check
//! ([`platefield::design::replay`]): a row "…, export replayed" under it.
//! Two more rows per target
//! do the same for the sequenced method alone: fitted at μ 0.3, and by the
//! stacked worst-case fit over the range ([`platefield::design::stacked`]).
//! A second table designs
//! the sink and the whirlpool for a single μ of 0.15 and 0.6 and gives the
//! realised shape at that μ.

use std::path::Path;

use platefield::design::method::{design_by_method, judge_check, Method, MethodDesign};
use platefield::design::replay::{exported, judge_replay};
use platefield::design::DesignOptions;
use platefield::dynamics::Friction;
use platefield::error::Result;
use platefield::play::replay::replay_motion;
use platefield::play::sensitivity::{friction_sweep, FrictionRow, Sensitivity};
use platefield::request::{FrictionSpec, Target};
use platefield::schedule::Schedule;
use platefield::synth::SynthOptions;
use platefield_report::table::Table;

/// Default output folder.
pub const DIR: &str = "results";

/// The targets compared.
pub const TARGETS: [&str; 5] = [
    "sink",
    "saddle",
    "whirlpool",
    "squeeze_trans",
    "line_sink_30",
];

/// The frictions every design is played at.
pub(crate) const FRICTIONS: [f64; 5] = [0.2, 0.25, 0.3, 0.35, 0.4];

/// The range the robust designs hold over.
pub(crate) const RANGE: [f64; 2] = [0.2, 0.4];

/// The goals over the range: (worst shape error, least worst
/// strength) per target.
pub fn goal(target: &str) -> (f64, Option<f64>) {
    match target {
        "sink" => (0.06, Some(0.4)),
        "whirlpool" => (0.08, Some(0.3)),
        _ => (0.08, None),
    }
}

/// One kept design played across `FRICTIONS`.
#[derive(Debug, Clone)]
pub struct Row {
    /// Target name.
    pub target: String,
    /// `μ 0.3` or `robust [0.2, 0.4]`.
    pub design: String,
    /// The kept candidate's name (its method, marked by the synthesis it
    /// comes from: `design::method::Candidate::name`).
    pub method: String,
    /// One row per friction.
    pub rows: Vec<FrictionRow>,
}

impl Row {
    /// Whether its worst case over the range meets the target's [`goal`].
    pub(crate) fn meets_goal(&self) -> bool {
        let (shape, strength) = self.worst();
        let (g_shape, g_strength) = goal(&self.target);
        shape <= g_shape && g_strength.is_none_or(|g| strength >= g)
    }

    /// Worst shape error and weakest strength over the rows.
    pub fn worst(&self) -> (f64, f64) {
        self.rows
            .iter()
            .fold((0.0_f64, f64::INFINITY), |(e, s), r| {
                (
                    e.max(r.realised_shape_error.unwrap_or(f64::INFINITY)),
                    s.min(r.realised_strength.unwrap_or(f64::NEG_INFINITY)),
                )
            })
    }
}

/// `design`'s default options designing by `method`, progress unless
/// `quiet`; with `robust_synthesis`, as `design --robust-synthesis`.
fn options(method: Method, quiet: bool, robust_synthesis: bool) -> DesignOptions {
    let runtime = platefield::work::Runtime {
        quiet,
        allow_long: false,
    };
    DesignOptions {
        method,
        synthesis: SynthOptions {
            progress: runtime.progress(),
            robust_synthesis,
            ..SynthOptions::default()
        },
        runtime,
        ..DesignOptions::default()
    }
}

/// How [`design_rows`] designs and plays: without progress (`quiet`), the
/// export replayed too (`replay`, a second row labelled `…, export
/// replayed`), as `design --robust-synthesis` (`robust_synthesis`).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct RowOptions {
    /// No progress output.
    pub quiet: bool,
    /// Also replay the kept design's export.
    pub replay: bool,
    /// Design as `design --robust-synthesis` does.
    pub robust_synthesis: bool,
}

/// Designs `target` with `method` and plays the kept design at
/// `frictions` (and its export, as `how` says).
pub(crate) fn design_rows(
    target: &Target,
    (label, method): (&str, Method),
    frictions: &[f64],
    how: RowOptions,
) -> Result<Vec<Row>> {
    let md = design_by_method(target, &options(method, how.quiet, how.robust_synthesis))?;
    kept_rows(target, (label, &md), frictions, how.replay)
}

/// `target` designed by `method` as `design` does, progress unless `quiet`.
pub(crate) fn designed(target: &Target, method: Method, quiet: bool) -> Result<MethodDesign> {
    design_by_method(target, &options(method, quiet, false))
}

/// The rows of `md`, `target`'s design labelled `label`: its kept design
/// played at `frictions`, and its export replayed when `replay`.
pub(crate) fn kept_rows(
    target: &Target,
    (label, md): (&str, &MethodDesign),
    frictions: &[f64],
    replay: bool,
) -> Result<Vec<Row>> {
    let kept = &md.kept().schedule;
    let values: Vec<Friction> = frictions.iter().map(|&m| Friction::uniform(m)).collect();
    let row = |design: String, rows: Vec<FrictionRow>| Row {
        target: target.name.clone(),
        design,
        method: md.kept().name(),
        rows,
    };
    let played = match judged_at(md.sensitivity.as_ref(), &values) {
        Some(rows) => rows,
        None => judged(target, kept, frictions)?,
    };
    let mut out = vec![row(label.into(), played)];
    if replay {
        let sampled = target.sample()?;
        let sm = replay_motion(kept, &exported(kept)?, "export")?;
        let replayed = friction_sweep(&kept.settings, &values, &|settings| {
            Ok(judge_replay(target, &sampled, &sm, settings))
        })?;
        out.push(row(format!("{label}, export replayed"), replayed));
    }
    Ok(out)
}

/// `schedule` judged for `target` (the design's judge) at each of
/// `frictions`.
pub(crate) fn judged(
    target: &Target,
    schedule: &Schedule,
    frictions: &[f64],
) -> Result<Vec<FrictionRow>> {
    let sampled = target.sample()?;
    let values: Vec<Friction> = frictions.iter().map(|&m| Friction::uniform(m)).collect();
    friction_sweep(&schedule.settings, &values, &|settings| {
        judge_check(target, &sampled, schedule, settings)
    })
}

/// The kept design's own judge at exactly `values`, when the design
/// judged it there (its sensitivity over the target's range: the same
/// judge of the same schedule, so the same rows as playing it again).
fn judged_at(sensitivity: Option<&Sensitivity>, values: &[Friction]) -> Option<Vec<FrictionRow>> {
    let s = sensitivity?;
    let at: Vec<Friction> = s.rows.iter().map(|r| r.friction).collect();
    (at == values).then(|| s.rows.clone())
}

/// [`design_rows`] without the replay: the one row.
pub(crate) fn design_row(
    target: &Target,
    design: (&str, Method),
    frictions: &[f64],
    quiet: bool,
) -> Result<Row> {
    let mut rows = design_rows(
        target,
        design,
        frictions,
        RowOptions {
            quiet,
            ..RowOptions::default()
        },
    )?;
    Ok(rows.remove(0))
}

pub(crate) fn load(name: &str) -> Result<Target> {
    let mut t = Target::load(&Path::new("targets").join(format!("{name}.json")))?;
    t.name = name.into();
    Ok(t)
}

/// Label of the sequenced design over [`RANGE`] (the stacked worst-case
/// fit, [`platefield::design::stacked`]).
pub(crate) const STACKED: &str = "sequenced, stacked worst case [0.2, 0.4]";

/// The label of the robust rows designed as `design --robust-synthesis`
/// does (the synthesis and its polish optimise the worst case over the
/// range, three frictions per evaluation: about 3× the CPU), for a
/// target whose default robust design misses its goal.
pub(crate) const ROBUST_SYNTHESIS: &str = "robust synthesis";

/// The comparison rows of one target: `auto` as shipped and robust over
/// [`RANGE`], each played and its export replayed; the sequenced method
/// fitted at μ 0.3 and by the stacked worst case over [`RANGE`].
pub(crate) fn target_rows(name: &str, quiet: bool) -> Result<Vec<Row>> {
    let nominal = load(name)?;
    let mut robust = nominal.clone();
    robust.friction = Some(FrictionSpec::range(RANGE[0], RANGE[1]));
    let how = RowOptions {
        quiet,
        replay: true,
        robust_synthesis: false,
    };
    let mut rows = design_rows(&nominal, ("μ 0.3", Method::Auto), &FRICTIONS, how)?;
    let auto = design_rows(
        &robust,
        ("robust [0.2, 0.4]", Method::Auto),
        &FRICTIONS,
        how,
    )?;
    let missed = !auto[0].meets_goal();
    rows.extend(auto);
    if missed {
        let label = format!("robust [0.2, 0.4], {ROBUST_SYNTHESIS}");
        rows.extend(design_rows(
            &robust,
            (&label, Method::Auto),
            &FRICTIONS,
            RowOptions {
                robust_synthesis: true,
                ..how
            },
        )?);
    }
    rows.extend([
        design_row(
            &nominal,
            ("sequenced, μ 0.3", Method::Sequence),
            &FRICTIONS,
            quiet,
        )?,
        design_row(&robust, (STACKED, Method::Sequence), &FRICTIONS, quiet)?,
    ]);
    Ok(rows)
}

/// The designs for a single μ of 0.15 and 0.6, each played at its μ.
pub(crate) fn single_rows(quiet: bool) -> Result<Vec<Row>> {
    let mut rows = Vec::new();
    for name in ["sink", "whirlpool"] {
        for mu in [0.15, 0.6] {
            let mut t = load(name)?;
            t.friction = Some(FrictionSpec::uniform(mu));
            let label = format!("μ {mu}");
            rows.push(design_row(&t, (&label, Method::Auto), &[mu], quiet)?);
        }
    }
    Ok(rows)
}

/// A judge's cell: strength / shape error.
pub(crate) fn cell(r: &FrictionRow) -> String {
    format!(
        "{} / {}",
        r.realised_strength
            .map_or_else(|| "n/a".into(), |s| format!("{s:.3}")),
        platefield::output::percent(r.realised_shape_error.unwrap_or(f64::NAN), 1)
    )
}

/// The weakest strength, "n/a" where not measured.
pub(crate) fn weakest(strength: f64) -> String {
    if strength.is_finite() {
        format!("{strength:.3}")
    } else {
        "n/a".into()
    }
}

/// `robust.md` from the comparison and the single-μ rows.
pub fn render(rows: &[Row], single: &[Row]) -> String {
    let mut md = String::from(
        "# Designs over the parts' friction\n\nGenerated by `platefield study robust` (see `platefield_studies::robust`). Each design is `design`'s default (`auto`) for the shipped target, as shipped (μ 0.3) and with `\"friction\": [0.2, 0.4]` (every candidate judged by its worst case over the range; the mirror-image time-share added, about the target's symmetry axis or, where no reflection maps the target to itself, with a partner synthesized for its mirror image, `design::mirror`). Every kept design is judged at each μ (`design::judge`: the realised field at ≥ 9 × 9 held points over the whole region, whole schedule periods until periodic), realised strength ŝ (× the target's strength, s⁻¹ for these linear fields) and realised shape error ‖R − ŝt‖/‖ŝt‖. Cells: strength / shape error. The sequenced rows compare the sequenced method (a schedule of primitives) fitted at μ 0.3 with the same method fitting one set of time weights against the basis simulated at μ 0.2, 0.3 and 0.4 (more where the worst case falls between), minimising the worst shape error over them (the stacked worst-case fit, `fit::worst`, `design::stacked`); the goal column applies to both robust rows. A target whose default robust design misses its goal also gets a row \"robust [0.2, 0.4], robust synthesis\": the same target designed as `design --robust-synthesis` does (the synthesis and its polish optimise the worst case at μ 0.2, 0.3 and 0.4, about 3× the CPU). Rows \"…, export replayed\" play the same design's export instead of its motions: the CSV `platefield export` writes (10 kHz; a synthesized motion's 10 ramp-in cycles from rest at home, then its steady cycles), its held samples integrated exactly from rest at home and cut into the schedule's segments (`play::replay`), by the same check on the same parts (`design::replay`).\n\n",
    );
    let mut table = Table::new([
        "target",
        "design",
        "kept",
        "μ 0.2",
        "μ 0.25",
        "μ 0.3",
        "μ 0.35",
        "μ 0.4",
        "worst shape",
        "weakest strength",
        "goal",
        "met",
    ]);
    for r in rows {
        let (shape, strength) = r.worst();
        let (g_shape, g_strength) = goal(&r.target);
        let goal_text = match g_strength {
            Some(s) => format!("≤ {:.0} % at ≥ {s}", 100.0 * g_shape),
            None => format!("≤ {:.0} %", 100.0 * g_shape),
        };
        let met = r.meets_goal();
        let mut cells = vec![r.target.clone(), r.design.clone(), r.method.clone()];
        cells.extend(r.rows.iter().map(cell));
        cells.extend([
            // Not measured at some μ (no valid part): said so, not ±inf.
            platefield::output::percent(shape, 1),
            weakest(strength),
            goal_text,
            if r.design.contains("[0.2, 0.4]") {
                if met {
                    "yes"
                } else {
                    "no"
                }
            } else {
                "—"
            }
            .into(),
        ]);
        table.row(cells);
    }
    md.push_str(&table.markdown());
    md.push_str("\n## A single friction far from 0.3\n\nThe target with `\"friction\": μ`, designed by `auto` and played at that μ (goal: shape error ≤ 6 %).\n\n");
    let mut table = Table::new(["target", "μ", "kept", "realised strength / shape", "met"]);
    for r in single {
        let e = r.rows[0].realised_shape_error.unwrap_or(f64::INFINITY);
        table.row([
            r.target.clone(),
            r.design.clone(),
            r.method.clone(),
            cell(&r.rows[0]),
            if e <= 0.06 { "yes" } else { "no" }.into(),
        ]);
    }
    md.push_str(&table.markdown());
    md
}

/// Every target's rows by `rows`, each target announced on stderr as
/// "`study`: name" unless `quiet`.
pub(crate) fn rows_of(
    (study, names): (&str, &[&str]),
    quiet: bool,
    rows: impl Fn(&str, bool) -> Result<Vec<Row>>,
) -> Result<Vec<Row>> {
    let mut out = Vec::new();
    for name in names {
        if !quiet {
            eprintln!("{study}: {name}");
        }
        out.extend(rows(name, quiet)?);
    }
    Ok(out)
}

/// `platefield study robust`: designs, plays and writes `OUT/robust.md`;
/// returns the file's text and where it was written.
pub fn run(out: &Path, quiet: bool) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let rows = rows_of(("robust", &TARGETS), quiet, target_rows)?;
    let single = single_rows(quiet)?;
    let md = render(&rows, &single);
    let path = out.join("robust.md");
    platefield::output::write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\nwrote {}\n", path.display()))
}
