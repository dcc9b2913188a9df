//! Writing a design made by `design --method` ([`MethodDesign`]): the kept
//! schedule (`schedule.json`, with its judge), `fit.svg`,
//! `report.md` (method choice, judge of every candidate, and the
//! kept design's own report), and for a synthesized motion `signals.svg`
//! (the six signals over one period, each over its limit).

use std::fmt::Write as _;
use std::path::Path;

use crate::plot::{LinePlot, Series};
use platefield::design::method::{number, percent, Candidate, Method, MethodDesign};
use platefield::error::Result;
use platefield::motion::{Motion, Signals};
use platefield::output::write_atomic;
use platefield::schedule::export::centre_acceleration;
use platefield::schedule::{AxisPeaks, Played, Schedule};
use platefield::synth::params::AXIS_NAMES;
use platefield::synth::{ShakerLimits, Synthesis};

/// Samples of the signals plot over one period.
const PLOT_SAMPLES: usize = 200;

/// The summary's first line: the kept design and its one realised
/// measure, named and explained in a line (the candidates follow).
pub fn headline(md: &MethodDesign) -> String {
    let c = md.kept();
    headline_of(&c.name(), c.played(), &c.schedule)
}

/// [`headline`] for the kept design named `name`, judged as `p`.
pub(crate) fn headline_of(name: &str, p: &Played, schedule: &Schedule) -> String {
    let field = schedule.target_spec.as_ref().map(|t| &t.field);
    format!(
        "kept {}:{} realised strength {} at realised shape error {}{} — the realised field at {} points over the whole region ({} valid), each part held at its point and played whole periods; ŝ is the scale of the target that field best matches, the shape error what ŝ × target leaves unmatched. Every candidate below.\n",
        name,
        platefield::design::method::worst_at(p),
        strength_with_unit(p.realised_strength, field),
        percent(p.realised_shape_error),
        if p.poor { ", POOR" } else { "" },
        p.points,
        p.valid,
    )
}

/// A realised strength ŝ (a multiple of the target's strength s) with its
/// unit: "ŝ·s s⁻¹ (ŝ × the target's s s⁻¹)" for the linear fields (s in
/// 1/s), m/s for the bounded ones (`trans`, `jet`); "ŝ (× the target's
/// strength)" for `sum` and `sampled` fields, whose strength is their
/// vectors' own scale.
pub(crate) fn strength_with_unit(
    s_hat: Option<f64>,
    field: Option<&platefield::request::FieldSpec>,
) -> String {
    use platefield::request::FieldSpec as F;
    let (Some(v), Some(field)) = (s_hat, field) else {
        return format!("{} (× the target's strength)", number(s_hat));
    };
    let (strength, unit) = match field {
        F::Sum { .. } | F::Sampled { .. } => {
            return format!("{} (× the target's strength)", number(s_hat))
        }
        F::Trans { strength, .. } | F::Jet { strength, .. } => (*strength, "m/s"),
        F::Sink { strength, .. }
        | F::Source { strength, .. }
        | F::LineSink { strength, .. }
        | F::Saddle { strength, .. }
        | F::Whirlpool { strength, .. }
        | F::Circle { strength, .. }
        | F::ScaledCircle { strength, .. }
        | F::SqueezeTrans { strength, .. } => (*strength, "s⁻¹"),
    };
    format!(
        "{} {unit} ({v:.4} × the target's {} {unit})",
        number(Some(v * strength)),
        platefield::input::num(strength)
    )
}

/// One terminal line per candidate and the choice.
pub fn summary(md: &MethodDesign) -> String {
    let mut out = String::new();
    for (i, c) in md.candidates.iter().enumerate() {
        let p = c.played();
        let _ = writeln!(
            out,
            "{} {}: predicted strength {:.4} (fit error {:.2} %); judged at {} points ({} valid):{} realised shape error {}, realised strength {}, error against the prediction {}; peaks {}; design {:.1} s, play {:.1} s{}",
            if i == md.chosen { "kept" } else { "not kept" },
            c.name(),
            p.predicted_strength,
            100.0 * c.schedule.fit.relative_l2_error,
            p.points,
            p.valid,
            platefield::design::method::worst_at(p),
            percent(p.realised_shape_error),
            number(p.realised_strength),
            percent(p.realised_error),
            peaks_text(&p.peaks, 3),
            c.design_s,
            c.play_s,
            poor_text(p)
        );
    }
    for f in &md.failures {
        let _ = writeln!(out, "{} failed: {}", f.method.name(), f.reason);
    }
    let _ = writeln!(out, "{}", md.why());
    if let Some(row) = md
        .sensitivity
        .as_ref()
        .and_then(|s| s.worst_row().map(|r| (s, r)))
    {
        let (s, row) = row;
        let _ = writeln!(
            out,
            "friction: the kept design {}: worst at μ_s {}, μ_k {}: realised shape error {}, realised strength {} (table in report.md)",
            s.span.describe(),
            platefield::output::coefficient(row.friction.stat),
            platefield::output::coefficient(row.friction.kinetic),
            platefield::output::percent(row.realised_shape_error.unwrap_or(f64::NAN), 1),
            number(row.realised_strength)
        );
    }
    if let Some(t) = &md.tolerance {
        let _ = writeln!(out, "{} (report.md)", super::verify::tolerance_line(t));
    }
    out.push_str(&model_text(&md.kept().schedule));
    out
}

/// The model the kept design was played and judged at, when not `full`
/// (`design --model`): the rung choice of `auto` (each segment's), or the
/// model asked for; empty under `full`.
fn model_text(schedule: &Schedule) -> String {
    match &schedule.rungs {
        Some(r) => super::verify::rungs_text("model auto: the kept design played and judged at", r),
        None if schedule.settings.model != platefield::dynamics::Model::FULL => format!(
            "model: the kept design played and judged at {}\n",
            schedule.settings.model.name()
        ),
        None => String::new(),
    }
}

/// `linear [x, y, z] m/s², angular [x, y, z] rad/s²`, each peak with
/// `digits` decimals.
fn peaks_text(peaks: &AxisPeaks, digits: usize) -> String {
    let list = |v: [f64; 3]| v.map(|x| format!("{x:.digits$}")).join(", ");
    format!(
        "linear [{}] m/s², angular [{}] rad/s²",
        list(peaks.linear),
        list(peaks.angular)
    )
}

fn poor_text(p: &Played) -> String {
    if p.poor {
        format!("\n  POOR (realised): {}", p.notes.join("; "))
    } else {
        String::new()
    }
}

/// The realised-check table of `report.md`.
fn played_md(cands: &[Candidate], chosen: usize) -> String {
    let mut md = String::from(
        "| method | kept | predicted strength | realised strength | realised shape error | error against prediction | points (valid) | POOR |\n|---|---|---|---|---|---|---|---|\n",
    );
    for (i, c) in cands.iter().enumerate() {
        let p = c.played();
        let _ = writeln!(
            md,
            "| {} | {} | {:.4} | {} | {} | {} | {} ({}) | {} |",
            c.name(),
            if i == chosen { "yes" } else { "no" },
            p.predicted_strength,
            number(p.realised_strength),
            percent(p.realised_shape_error),
            percent(p.realised_error),
            p.points,
            p.valid,
            if p.poor {
                p.notes.join("; ")
            } else {
                "no".into()
            }
        );
    }
    md
}

/// The method section of `report.md`.
pub(crate) fn method_md(md: &MethodDesign) -> String {
    let mut out = format!(
        "## Method and the judge\n\nMethod: `{}`; {}.\n\nEvery candidate is judged before it is reported: the realised field over the whole region, a point part held at each point of a regular sub-grid of the target (at least 9 × 9, both edges on it) and played whole schedule periods until its velocity runs periodic (`design::judge`), against the target; over a friction range the target states, its worst case. POOR: realised shape error above {:.0} %, or a part losing contact. Rule under `auto`: the lower realised shape error wins; within 1 percentage point, the higher realised strength. When every candidate is POOR, `auto` also designs the mix (primitives and a synthesized motion in one fit) and plays it.\n\n",
        md.asked.name(),
        md.why(),
        100.0 * platefield::fit::POOR_ERROR
    );
    out.push_str(&played_md(&md.candidates, md.chosen));
    for f in &md.failures {
        let _ = writeln!(out, "\n{} failed: {}", f.method.name(), f.reason);
    }
    let p = md.kept().played();
    let _ = writeln!(
        out,
        "\nPeaks the kept schedule commands: {}.",
        peaks_text(&p.peaks, 4)
    );
    let model = model_text(&md.kept().schedule);
    if !model.is_empty() {
        let _ = write!(
            out,
            "\n## Model\n\nEvery candidate is played and judged at the model `--model` asks for; the basis and the synthesis at full. Under `auto`, each candidate's rung is the cheapest that moves the part and is within the tolerance of full for every moving segment, its error measured on the sample points against full (`schedule.json`'s `rungs`).\n\n```text\n{model}```\n"
        );
    }
    if let Some(s) = &md.sensitivity {
        let _ = write!(out, "\n## Friction sensitivity\n\n{}", s.table_md());
    }
    if let Some(t) = &md.tolerance {
        out.push_str(&tolerance_md(t));
    }
    out
}

/// `report.md`'s section on the kept design judged over the shaker's
/// delivery errors: what was drawn, the distribution, and every draw.
fn tolerance_md(t: &platefield::design::tolerance::Spread) -> String {
    let [median, p90, worst] = t.shape();
    let [s_median, s_p10, weakest] = t.strength();
    let mut md = format!(
        "\n## Shaker tolerance\n\nThe kept design judged (the realised field at the judge's held points) as the \
         controller delivers it: {} seeded draws, each channel's gain at each harmonic within ±{} % and its \
         phase within ±{}°, at μ_k {} (the friction of its worst case over the range). \
         Segments of screw primitives are played as designed ({} of them; {} six-signal segments perturbed); \
         `platefield verify <schedule> --tolerance` repeats it.\n\n\
         | | median | 90th percentile | worst |\n|---|---|---|---|\n",
        t.shape_errors.len(),
        100.0 * t.tolerance.amplitude,
        t.tolerance.phase_deg,
        platefield::output::coefficient(t.friction),
        t.primitive_segments,
        t.perturbed_segments,
    );
    let _ = writeln!(
        md,
        "| realised shape error | {:.2} % | {:.2} % | {:.2} % |",
        100.0 * median,
        100.0 * p90,
        100.0 * worst
    );
    let _ = writeln!(
        md,
        "| realised strength (× the target's) | {s_median:.4} | {s_p10:.4} (10th percentile) | {weakest:.4} |"
    );
    md
}

/// The synthesized motion's section of `report.md`: the signals plot, each
/// axis's peak against its limit, the least normal force, the fit.
pub(crate) fn synthesis_md(syn: &Synthesis, limits: &ShakerLimits, gravity: f64) -> String {
    let mut md = format!(
        "## Synthesized motion\n\n![the six signals over one period](signals.svg)\n\nOne simultaneous six-signal motion, period {:.5} s, harmonics 1..={}: {}\n\n| axis | peak | limit |\n|---|---|---|\n",
        syn.checked.motion.period,
        limits.harmonics,
        syn.summary()
    );
    for p in &syn.checked.peaks {
        let unit = if p.axis.starts_with("linear") {
            "m/s²"
        } else {
            "rad/s²"
        };
        let _ = writeln!(
            md,
            "| {} | {:.4} {unit} | {:.4} {unit} |",
            p.axis, p.peak, p.limit
        );
    }
    let _ = writeln!(
        md,
        "\nLeast normal force over the region (kinematic check and simulated steady orbits): {:.4} m/s² = {:.3} g (margin asked: {} g).",
        syn.checked.least_normal,
        syn.checked.least_normal / gravity,
        limits.contact_margin
    );
    let _ = writeln!(
        md,
        "\nPrediction (steady-state field on the full {}×{} grid): strength {:.4}, shape error {}; on the coarse grid the optimizer saw: {:.4}, {}. Seed (averaged-friction analysis): {:.4} predicted, {:.4} at {} simulated.",
        syn.checked.field.grid.n[0],
        syn.checked.field.grid.n[1],
        syn.checked.realised.strength,
        platefield::output::percent(syn.checked.realised.shape_error, 2),
        syn.coarse.strength,
        platefield::output::percent(syn.coarse.shape_error, 2),
        syn.seed_strength,
        syn.seed_realised.strength,
        platefield::output::percent(syn.seed_realised.shape_error, 2)
    );
    if !syn.checked.notes.is_empty() {
        let _ = writeln!(md, "\nNotes: {}.", syn.checked.notes.join("; "));
    }
    md.push_str("\n`platefield export` writes it with a ramp-in from rest, `--steady-cycles` steady cycles (default 20) and a ramp-out to rest.\n");
    md
}

/// The six signals of `motion` over one period, each divided by its axis
/// limit (axes with a zero limit and no signal are left out).
pub(crate) fn signals_svg(motion: &Signals, limits: &ShakerLimits) -> String {
    let m = Motion::Signals(motion.clone());
    let t: Vec<f64> = (0..=PLOT_SAMPLES)
        .map(|i| motion.period * i as f64 / PLOT_SAMPLES as f64)
        .collect();
    let values: Vec<[f64; 6]> = t
        .iter()
        .map(|&ti| {
            let (l, a) = centre_acceleration(&m, ti);
            [l.x, l.y, l.z, a.x, a.y, a.z]
        })
        .collect();
    let axes = limits.axes();
    let mut plot = LinePlot::new(format!(
        "six signals over one period (T = {:.1} ms), each over its limit",
        1e3 * motion.period
    ))
    .labels("t (ms)", "acceleration / axis limit");
    // The time axis is the period, not the next round number past it.
    plot.x_range = Some([0.0, 1e3 * motion.period]);
    for k in 0..6 {
        if axes[k] <= 0.0 {
            continue;
        }
        let unit = if k < 3 { "m/s²" } else { "rad/s²" };
        let pts: Vec<[f64; 2]> = t
            .iter()
            .zip(&values)
            .map(|(ti, v)| [1e3 * ti, v[k] / axes[k]])
            .collect();
        plot = plot.series(Series::new(
            format!("{} (limit {:.3} {unit})", AXIS_NAMES[k], axes[k]),
            pts,
        ));
    }
    plot.to_svg()
}

/// Target (scaled), synthesized field and residual at the target's points.
pub(crate) fn synthesis_fit_svg(md: &MethodDesign, syn: &Synthesis) -> Option<String> {
    let target = md.kept().schedule.target_spec.as_ref()?;
    let sampled = target.sample().ok()?;
    (sampled.len() == syn.checked.field.vectors.len()).then(|| {
        super::design::fit_figure(
            &md.kept().schedule.target,
            &sampled,
            syn.checked.realised.strength,
            super::design::realised_strength(&md.kept().schedule),
            "synthesized (steady state)",
            &syn.checked.field.vectors,
        )
    })
}

/// Writes schedule.json (the kept candidate), fit.svg, report.md, and
/// signals.svg when a synthesis ran; order.md as [`super::design::write`].
/// Returns the names written.
pub fn write(md: &MethodDesign, dir: &Path) -> Result<Vec<&'static str>> {
    let kept = md.kept();
    let mut files = vec!["schedule.json", "report.md"];
    let mut report = format!(
        "# Design for target \"{}\"\n\nRegenerate: `{}`.\n\n",
        kept.schedule.target,
        super::invocation(&format!(
            "design <target file> --method {}",
            md.asked.name()
        ))
    );
    // The kept design first, its realised measure named in a line.
    report.push_str(&headline(md));
    report.push('\n');
    report.push_str(&method_md(md));
    // No plot rather than an empty one (a synthesis for a grid-less target
    // has no field at the target's points).
    let realised = super::design::realised_strength(&kept.schedule);
    let fit_svg = match (kept.method, &md.sequence, &md.synthesis) {
        (Method::Sequence, Some(d), _) => Some(super::design::fit_svg(d, realised)),
        (Method::Mix, _, _) if md.mixed.is_some() => md
            .mixed
            .as_ref()
            .map(|d| super::design::fit_svg(d, realised)),
        (_, _, Some(syn)) => synthesis_fit_svg(md, syn),
        _ => None,
    };
    if let Some(syn) = &md.synthesis {
        report.push('\n');
        report.push_str(&synthesis_md(
            syn,
            &md.limits,
            kept.schedule.settings.gravity,
        ));
    }
    for (heading, d) in [
        ("Sequenced design", &md.sequence),
        ("Mixed design", &md.mixed),
    ] {
        // A design's own report, one heading level down.
        let Some(d) = d else { continue };
        // Without its title and "Regenerate:" line (the design's own, above).
        let own = super::design::report_md(d);
        let body = own.split_once("\n\n## ").map_or("", |x| x.1);
        let _ = write!(
            report,
            "\n## {heading}\n\n### {}",
            body.replace("\n## ", "\n### ")
        );
    }
    write_atomic(
        &dir.join("schedule.json"),
        kept.schedule.to_json()?.as_bytes(),
    )?;
    if let Some(svg) = fit_svg {
        write_atomic(&dir.join("fit.svg"), svg.as_bytes())?;
        files.insert(1, "fit.svg");
    }
    write_atomic(&dir.join("report.md"), report.as_bytes())?;
    if let Some(syn) = &md.synthesis {
        write_atomic(
            &dir.join("signals.svg"),
            signals_svg(&syn.checked.motion, &md.limits).as_bytes(),
        )?;
        files.push("signals.svg");
    }
    if kept.method == Method::Sequence {
        if let Some(text) = md.sequence.as_ref().and_then(super::design::order_md) {
            write_atomic(&dir.join("order.md"), text.as_bytes())?;
            files.push("order.md");
        }
    }
    Ok(files)
}
