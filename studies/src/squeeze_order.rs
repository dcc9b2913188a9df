//! The paper's observation that segment order shifts the squeeze line of
//! SqueezeTrans (section V: "we would predict that the squeeze line of the
//! SqueezeTrans field … would be centered on the plate based on the two
//! individual primitives. The fact that it is not illustrates an offset
//! that depends on the phasing of the two primitives"), reproduced and
//! quantified.
//!
//! **Setup.** LineSink@90° squeezes parts onto the line y = y_LS along x
//! (its axis is along x; the field is ≈ a(0, −(y − y_LS))), Trans@0° moves
//! them along it. LineSink@270° is the same field mirrored in y: its
//! rest-to-rest waveform ψ0(1 − cos ωt) has a mean tilt ψ0 whose gravity
//! component g ψ0 shifts each LineSink's line by about 2 mm (full model),
//! one way for 90° and the other for 270°. Schedules: (a) the paper's two
//! primitives, LineSink@90° or @270° then Trans@0° or @180°, n cycles each;
//! (b) the design's three segments (`results/squeeze_trans/schedule.json`:
//! LineSink@270°, LineSink@90°, Trans@0°) in its two distinct cyclic
//! orders A = (LS90, LS270, Trans) and B = (LS90, Trans, LS270). With and
//! without k cycles of rest at every join.
//!
//! **The line.** Over 3 × 5 points (x = −2, 0, 2 cm; y = −2 … 2 cm) the
//! normal velocity is fitted by least squares as v_y = a (y − y0) (common
//! slope and intercept), for the realised mean velocities (at the parts'
//! mean positions when they move) and for the time-weighted steady-state
//! prediction; the offset is y0(realised) − y0(predicted).
//!
//! **Why the offset occurs.** At its line a LineSink's periodic orbit is
//! not at rest at phase 0 although the plate is: the part still slides
//! across the line with the slip u* left by the previous cycle (for
//! LineSink@90°, frozen, full model, a backward slide of the order of a
//! centimetre per second). A LineSink segment
//! that follows Trans or rest starts with no normal slip, so until the
//! orbit is reached (about a cycle) the part lacks that backward slide and
//! is displaced by about +0.3–0.5 mm; the slip it leaves at the end of the
//! segment is then carried into the next one: at rest it stops after
//! u*²/(2 μ g) = 0.04 mm, but under Trans the part slides along x and
//! friction, directed along the total slip, barely brakes the normal
//! component, which drifts about −0.24 mm before it decays and cancels most
//! of the start transient. Net, a fixed displacement per schedule period
//! whose sign is the LineSink's rotation sign, i.e. a normal bias velocity
//! b = Δ/P and a line offset −b/a: it falls as the period P grows (more
//! cycles per segment) and grows with rest (which removes the Trans
//! cancellation). In the three-segment schedule (10 cycles each, frozen),
//! order A starts LS90 cold (+0.29 mm), then LS270 enters with LS90's exit
//! slip (−15.1 mm/s, the opposite of its own orbit's +15.1 mm/s: −0.68 mm)
//! and Trans carries LS270's exit slip (+0.22 mm): −0.16 mm per period.
//! Order B is A mirrored in y (and rotated), so its offset is the
//! opposite; with rest at every join every segment starts from rest
//! whatever precedes it, and with frozen positions the two orders are then
//! identical. [`join_budget`] measures these per-segment displacements.

use std::fmt::Write as _;
use std::path::Path;

use serde::Serialize;

use platefield::basis::{Primitive, PrimitiveKind};
use platefield::dynamics::{Model, PartPhysics, PartState};
use platefield::error::{Error, Result};
use platefield::play::measure::{verify_points, PlayOptions as VerifyOptions};
use platefield::play::{periods_for, PlayedSegment, ScheduleMotion, V2};
use platefield_report::table::Table;

/// Cycles per segment studied.
pub(crate) const CYCLES: [u32; 3] = [1, 3, 10];
/// Warm-up of every measurement: at least this many primitive cycles.
pub(crate) const WARMUP_CYCLES: u32 = 40;
/// Measured span: at least this many primitive cycles.
pub(crate) const MEASURED_CYCLES: u32 = 20;

/// The 3 × 5 points the line is fitted over (m).
pub(crate) fn line_points() -> Vec<[f64; 2]> {
    let mut p = Vec::with_capacity(15);
    for x in [-0.02, 0.0, 0.02] {
        for y in [-0.02, -0.01, 0.0, 0.01, 0.02] {
            p.push([x, y]);
        }
    }
    p
}

/// A primitive segment with the paper's defaults, rotated by `deg`.
pub fn segment(kind: PrimitiveKind, deg: f64, cycles: u32) -> PlayedSegment {
    let p = Primitive {
        rotation_deg: deg,
        ..Primitive::new(kind)
    };
    PlayedSegment::moving(format!("{}@{deg}°", kind.name()), p.motion(), cycles)
}

/// `segments` with `rest_cycles` LineSink periods of rest after each one.
pub fn with_rest(segments: Vec<PlayedSegment>, rest_cycles: u32) -> Result<ScheduleMotion> {
    let t = Primitive::new(PrimitiveKind::LineSink).period();
    let mut out = Vec::with_capacity(2 * segments.len());
    for s in segments {
        out.push(s);
        if rest_cycles > 0 {
            out.push(PlayedSegment::rest(f64::from(rest_cycles) * t));
        }
    }
    ScheduleMotion::new(out)
}

/// (a) LineSink@`ls_deg` then Trans@`trans_deg`, `cycles` each, with
/// `rest_cycles` of rest at both joins.
pub fn two_primitive(
    ls_deg: f64,
    trans_deg: f64,
    cycles: u32,
    rest_cycles: u32,
) -> Result<ScheduleMotion> {
    with_rest(
        vec![
            segment(PrimitiveKind::LineSink, ls_deg, cycles),
            segment(PrimitiveKind::Trans, trans_deg, cycles),
        ],
        rest_cycles,
    )
}

/// The two distinct cyclic orders of the design's three segments.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ThreeOrder {
    /// LineSink@90° → LineSink@270° → Trans@0°.
    A,
    /// LineSink@90° → Trans@0° → LineSink@270°.
    B,
}

/// (b) The design's three segments in `order`, with cycles
/// `[LineSink@90°, LineSink@270°, Trans@0°]` and `rest_cycles` at every join.
pub fn three_segment(
    order: ThreeOrder,
    cycles: [u32; 3],
    rest_cycles: u32,
) -> Result<ScheduleMotion> {
    let ls90 = segment(PrimitiveKind::LineSink, 90.0, cycles[0]);
    let ls270 = segment(PrimitiveKind::LineSink, 270.0, cycles[1]);
    let trans = segment(PrimitiveKind::Trans, 0.0, cycles[2]);
    let segs = match order {
        ThreeOrder::A => vec![ls90, ls270, trans],
        ThreeOrder::B => vec![ls90, trans, ls270],
    };
    with_rest(segs, rest_cycles)
}

/// A fitted squeeze line v_y = a (y − y0).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineFit {
    /// Slope a (1/s; negative for a sink).
    pub slope: f64,
    /// Line position y0 (m).
    pub y0: f64,
    /// RMS residual of the fit over RMS of v_y.
    pub residual: f64,
}

/// Least-squares v_y = a (y − y0) over `positions` and `velocities`;
/// `None` with fewer than two distinct y or a zero slope.
pub(crate) fn fit_line(positions: &[[f64; 2]], velocities: &[[f64; 2]]) -> Option<LineFit> {
    let n = positions.len().min(velocities.len());
    if n < 2 {
        return None;
    }
    let nf = n as f64;
    let my = positions[..n].iter().map(|p| p[1]).sum::<f64>() / nf;
    let mv = velocities[..n].iter().map(|v| v[1]).sum::<f64>() / nf;
    let (mut syy, mut syv) = (0.0, 0.0);
    for (p, v) in positions[..n].iter().zip(&velocities[..n]) {
        syy += (p[1] - my).powi(2);
        syv += (p[1] - my) * (v[1] - mv);
    }
    if syy <= 0.0 || syv == 0.0 {
        return None;
    }
    let a = syv / syy;
    let b = mv - a * my;
    let (mut res, mut tot) = (0.0, 0.0);
    for (p, v) in positions[..n].iter().zip(&velocities[..n]) {
        res += (v[1] - a * p[1] - b).powi(2);
        tot += v[1] * v[1];
    }
    Some(LineFit {
        slope: a,
        y0: -b / a,
        residual: if tot > 0.0 { (res / tot).sqrt() } else { 0.0 },
    })
}

/// The realised and predicted squeeze lines of a schedule.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct LineOffset {
    /// Fitted to the realised mean velocities.
    pub realised: LineFit,
    /// Fitted to the time-weighted steady-state prediction.
    pub predicted: LineFit,
    /// Relative L2 error realised vs predicted over the points.
    pub relative_error: f64,
    /// Moving time / period.
    pub moving_fraction: f64,
}

impl LineOffset {
    /// y0(realised) − y0(predicted) (m).
    pub fn offset(&self) -> f64 {
        self.realised.y0 - self.predicted.y0
    }
}

/// Verification options for a squeeze measurement of `sm` under `model`:
/// paper defaults, warm-up ≥ [`WARMUP_CYCLES`] and measured span ≥
/// [`MEASURED_CYCLES`] primitive cycles, both in whole periods (≥ 1).
pub(crate) fn squeeze_options(sm: &ScheduleMotion, model: Model) -> VerifyOptions {
    let t = Primitive::new(PrimitiveKind::LineSink).period();
    VerifyOptions {
        model,
        warmup_periods: periods_for(WARMUP_CYCLES, t, sm.period()),
        periods: periods_for(MEASURED_CYCLES, t, sm.period()),
        ..VerifyOptions::default()
    }
}

/// Measures the realised and predicted squeeze lines of `sm` over
/// `line_points` (see the module docs).
pub fn line_offset(sm: &ScheduleMotion, model: Model) -> Result<LineOffset> {
    let pts = line_points();
    let v = verify_points(sm, &pts, &squeeze_options(sm, model));
    v.require_all_valid("squeeze line")?;
    let pos: Vec<[f64; 2]> = v.points.iter().map(|p| p.position).collect();
    let real: Vec<[f64; 2]> = v.points.iter().map(|p| p.realised).collect();
    let pred: Vec<[f64; 2]> = v.points.iter().map(|p| p.predicted).collect();
    let fit = |vel: &[[f64; 2]], what: &str| {
        fit_line(&pos, vel).ok_or_else(|| {
            Error::Unreachable(format!(
                "squeeze line: the {what} normal velocity has no slope"
            ))
        })
    };
    let moving = sm.moving_time();
    Ok(LineOffset {
        realised: fit(&real, "realised")?,
        predicted: fit(&pred, "predicted")?,
        relative_error: v.relative_error,
        moving_fraction: moving / sm.period(),
    })
}

/// What one segment does to a part at a fixed point over one period
/// (frozen kinematics), normal to the line (y).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct JoinBudget {
    /// Segment label.
    pub label: String,
    /// Normal slip when the segment starts, after the join (m/s).
    pub entry_slip: f64,
    /// Normal slip of the segment's own periodic orbit at phase 0 (m/s;
    /// 0 for rest): what the part would need to start on the orbit.
    pub orbit_slip: f64,
    /// Normal slip at the segment's end (m/s).
    pub exit_slip: f64,
    /// Normal displacement over the segment minus duration × its
    /// steady-state normal velocity (m): the transient's contribution.
    pub excess: f64,
}

/// Plays `sm` at `anchor` (frozen full model, paper defaults) for the
/// warm-up of `squeeze_options` and then one period, segment by segment,
/// and returns each segment's [`JoinBudget`]. Σ excess / period is the
/// normal bias velocity the joins add to the prediction at `anchor`.
pub fn join_budget(sm: &ScheduleMotion, anchor: [f64; 2]) -> Result<Vec<JoinBudget>> {
    let opts = squeeze_options(sm, Model::FROZEN);
    let player = sm.player(
        PartPhysics::new(opts.friction, opts.gravity, opts.model),
        opts.numerics,
    );
    let a = V2::from(anchor);
    let mut state = PartState::new(a, V2::zeros());
    player
        .play_periods(&mut state, &a, 0, opts.warmup_periods, |_, _, _| {})
        .map_err(|e| Error::ContactLost(format!("join budget: {e}")))?;
    let n = sm.segments().len();
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        player.join(if i == 0 { n - 1 } else { i - 1 }, i, &mut state, &a);
        let entry = state.u.y;
        let y_start = state.r.y;
        player
            .play_segment(i, &mut state, &a)
            .map_err(|loss| Error::ContactLost(format!("join budget, segment {i}: {loss}")))?;
        let seg = &sm.segments()[i];
        let (orbit, steady) = match player.simulator(i) {
            None => (0.0, 0.0),
            Some(sim) => {
                let s = sim
                    .steady_state(anchor)
                    .map_err(|e| Error::ContactLost(format!("join budget, segment {i}: {e}")))?;
                (s.start_slip[1], s.velocity[1])
            }
        };
        out.push(JoinBudget {
            label: seg.label.clone(),
            entry_slip: entry,
            orbit_slip: orbit,
            exit_slip: state.u.y,
            excess: state.r.y - y_start - steady * seg.duration,
        });
    }
    Ok(out)
}

/// One measured configuration.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct OffsetRow {
    /// `two-primitive` or `three-segment`.
    pub case: String,
    /// Segments in playing order.
    pub sequence: String,
    /// Cycles per segment, e.g. `3` or `11/11/10`.
    pub cycles: String,
    /// Rest cycles at every join.
    pub rest_cycles: u32,
    /// Model name (`frozen`: full with positions frozen).
    pub model: String,
    /// The lines.
    pub line: LineOffset,
}

fn model_name(m: Model) -> String {
    if m == Model::FROZEN {
        "frozen".into()
    } else {
        m.name()
    }
}

/// Measures every configuration of the study (both parts, both models).
pub(crate) fn offset_rows() -> Result<Vec<OffsetRow>> {
    let mut rows = Vec::new();
    for model in [Model::FROZEN, Model::FULL] {
        for &n in &CYCLES {
            for ls in [90.0, 270.0] {
                for tr in [0.0, 180.0] {
                    for rest in [0, 1] {
                        let sm = two_primitive(ls, tr, n, rest)?;
                        rows.push(OffsetRow {
                            case: "two-primitive".into(),
                            sequence: format!("LineSink@{ls}° → Trans@{tr}°"),
                            cycles: n.to_string(),
                            rest_cycles: rest,
                            model: model_name(model),
                            line: line_offset(&sm, model)?,
                        });
                    }
                }
            }
        }
        let counts: Vec<[u32; 3]> = CYCLES
            .iter()
            .map(|&n| [n, n, n])
            .chain(std::iter::once([11, 11, 10]))
            .collect();
        for c in counts {
            for order in [ThreeOrder::A, ThreeOrder::B] {
                for rest in [0, 1, 2] {
                    let sm = three_segment(order, c, rest)?;
                    rows.push(OffsetRow {
                        case: "three-segment".into(),
                        sequence: order_label(order).into(),
                        cycles: if c[0] == c[2] {
                            c[0].to_string()
                        } else {
                            format!("{}/{}/{}", c[0], c[1], c[2])
                        },
                        rest_cycles: rest,
                        model: model_name(model),
                        line: line_offset(&sm, model)?,
                    });
                }
            }
        }
    }
    Ok(rows)
}

/// The label of a three-segment order.
pub(crate) fn order_label(order: ThreeOrder) -> &'static str {
    match order {
        ThreeOrder::A => "A: LineSink@90° → LineSink@270° → Trans@0°",
        ThreeOrder::B => "B: LineSink@90° → Trans@0° → LineSink@270°",
    }
}

/// The rows as CSV.
pub(crate) fn offset_csv(rows: &[OffsetRow]) -> String {
    let mut s = String::from("case,sequence,cycles_per_segment,rest_cycles,model,realised_y0_mm,predicted_y0_mm,offset_mm,realised_slope_per_s,predicted_slope_per_s,realised_fit_residual,relative_error,moving_fraction\n");
    for r in rows {
        let l = &r.line;
        let _ = writeln!(
            s,
            "{},\"{}\",{},{},{},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6},{:.6}",
            r.case,
            r.sequence,
            r.cycles,
            r.rest_cycles,
            r.model,
            1e3 * l.realised.y0,
            1e3 * l.predicted.y0,
            1e3 * l.offset(),
            l.realised.slope,
            l.predicted.slope,
            l.realised.residual,
            l.relative_error,
            l.moving_fraction
        );
    }
    s
}

fn find<'a>(
    rows: &'a [OffsetRow],
    case: &str,
    seq: &str,
    cycles: &str,
    rest: u32,
    model: &str,
) -> Option<&'a OffsetRow> {
    rows.iter().find(|r| {
        r.case == case
            && r.sequence == seq
            && r.cycles == cycles
            && r.rest_cycles == rest
            && r.model == model
    })
}

fn two_primitive_table(md: &mut String, rows: &[OffsetRow], model: &str) {
    let mut table = Table::new([
        "schedule",
        "cycles per segment",
        "rest cycles at each join",
        "predicted y0 (mm)",
        "realised y0 (mm)",
        "offset (mm)",
        "slope realised / predicted (1/s)",
        "relative error",
        "moving fraction",
    ]);
    for r in rows
        .iter()
        .filter(|r| r.case == "two-primitive" && r.model == model)
    {
        let l = &r.line;
        table.row([
            r.sequence.to_string(),
            r.cycles.to_string(),
            r.rest_cycles.to_string(),
            format!("{:+.3}", 1e3 * l.predicted.y0),
            format!("{:+.3}", 1e3 * l.realised.y0),
            format!("{:+.3}", 1e3 * l.offset()),
            format!("{:.3} / {:.3}", l.realised.slope, l.predicted.slope),
            format!("{:.1} %", 100.0 * l.relative_error),
            format!("{:.3}", l.moving_fraction),
        ]);
    }
    md.push_str(&table.markdown());
}

fn three_segment_table(md: &mut String, rows: &[OffsetRow], model: &str) {
    let mut table = Table::new([
        "cycles per segment (LS90/LS270/Trans)",
        "rest cycles at each join",
        "predicted y0 (mm)",
        "offset A (mm)",
        "offset B (mm)",
        "A − B (mm)",
        "relative error A / B",
        "moving fraction",
    ]);
    let a = order_label(ThreeOrder::A);
    let b = order_label(ThreeOrder::B);
    for ra in rows
        .iter()
        .filter(|r| r.case == "three-segment" && r.model == model && r.sequence == a)
    {
        let Some(rb) = find(rows, &ra.case, b, &ra.cycles, ra.rest_cycles, model) else {
            continue;
        };
        table.row([
            ra.cycles.to_string(),
            ra.rest_cycles.to_string(),
            format!("{:+.3}", 1e3 * ra.line.predicted.y0),
            format!("{:+.3}", 1e3 * ra.line.offset()),
            format!("{:+.3}", 1e3 * rb.line.offset()),
            format!("{:+.3}", 1e3 * (ra.line.offset() - rb.line.offset())),
            format!(
                "{:.1} % / {:.1} %",
                100.0 * ra.line.relative_error,
                100.0 * rb.line.relative_error
            ),
            format!("{:.3}", ra.line.moving_fraction),
        ]);
    }
    md.push_str(&table.markdown());
}

fn budget_table(
    md: &mut String,
    title: &str,
    sm: &ScheduleMotion,
    anchor: [f64; 2],
    slope: f64,
    measured: f64,
) -> Result<()> {
    let b = join_budget(sm, anchor)?;
    let _ = writeln!(
        md,
        "\n**{title}** (anchor y = {:+.3} mm on the predicted line):\n",
        1e3 * anchor[1]
    );
    let mut table = Table::new([
        "segment",
        "normal slip at entry (mm/s)",
        "its orbit's slip at phase 0 (mm/s)",
        "normal slip at exit (mm/s)",
        "transient displacement (mm)",
    ]);
    for s in &b {
        table.row([
            s.label.to_string(),
            format!("{:+.2}", 1e3 * s.entry_slip),
            format!("{:+.2}", 1e3 * s.orbit_slip),
            format!("{:+.2}", 1e3 * s.exit_slip),
            format!("{:+.4}", 1e3 * s.excess),
        ]);
    }
    md.push_str(&table.markdown());
    let total: f64 = b.iter().map(|s| s.excess).sum();
    let bias = total / sm.period();
    let _ = writeln!(
        md,
        "\nPer period {:+.4} mm, bias b = {:+.3} mm/s; offset −b/a = {:+.3} mm (a = {:.3}/s, realised) against {:+.3} mm measured by the line fit.",
        1e3 * total,
        1e3 * bias,
        -1e3 * bias / slope,
        slope,
        1e3 * measured
    );
    Ok(())
}

/// Runs the study, writes `out/squeeze_trans_order.md` and
/// `out/squeeze_trans_order.csv`, and returns the markdown.
pub(crate) fn squeeze_order_report(out: &Path) -> Result<String> {
    let rows = offset_rows()?;
    let mut md = String::new();
    md.push_str("# SqueezeTrans: segment order and phasing shift the squeeze line\n\nGenerated by `platefield study squeeze-order` (`platefield_studies::squeeze_order`); all rows in `squeeze_trans_order.csv`.\n\n");
    md.push_str("The paper (section V): \"we would predict that the squeeze line of the SqueezeTrans field of Figure 8 would be centered on the plate based on the two individual primitives. The fact that it is not illustrates an offset that depends on the phasing of the two primitives.\"\n\n");
    md.push_str("Setup: paper defaults (ω = 209 rad/s, ψ0 = 0.005 rad, LineSink axis 5 cm below the plate, Trans d0 = 0.5 mm, μ = 0.3), rest-to-rest waveforms. LineSink@90° squeezes onto a line along x (its tilt ψ0 shifts the line by about +2 mm; LineSink@270° is its mirror image in y, −2 mm). The normal velocity is fitted as v_y = a (y − y0) over 3 × 5 points (x = −2, 0, 2 cm; y = −2 … 2 cm), for the realised mean velocity (warm-up ≥ 40 cycles, measured ≥ 20 cycles, whole schedule periods) and for the time-weighted steady-state prediction; offset = y0(realised) − y0(predicted). *frozen*: full model with positions frozen (a clean field comparison); *full*: parts move.\n\n");
    md.push_str("## Why\n\nAt its line a LineSink's periodic orbit is not at rest at phase 0, although the plate is: the part still slides across the line with the slip left by the previous cycle. A LineSink segment that starts after Trans or rest starts with no normal slip; until it reaches its orbit (about one cycle) the part misses that backward slide and is displaced, once per segment. The slip it leaves at its end is carried into the next segment: at rest the part stops after u²/(2μg), but under Trans it slides along x and friction, directed along the total slip, hardly brakes the normal component, which drifts back and cancels most of the start transient. The net displacement per period Δ, always the same way for a given LineSink sign, is a normal bias velocity b = Δ/P and a line offset −b/a. Measured per segment at the predicted line (frozen):\n");
    let anchor_y = |ls: f64| {
        find(
            &rows,
            "two-primitive",
            &format!("LineSink@{ls}° → Trans@0°"),
            "1",
            0,
            "frozen",
        )
        .map_or(0.0, |r| r.line.predicted.y0)
    };
    for &(n, rest) in &[(1u32, 0u32), (10, 0), (10, 1)] {
        let seq = "LineSink@90° → Trans@0°";
        if let Some(r) = find(&rows, "two-primitive", seq, &n.to_string(), rest, "frozen") {
            budget_table(
                &mut md,
                &format!("{seq}, {n} cycles each, rest {rest}"),
                &two_primitive(90.0, 0.0, n, rest)?,
                [0.0, anchor_y(90.0)],
                r.line.realised.slope,
                r.line.offset(),
            )?;
        }
    }
    for order in [ThreeOrder::A, ThreeOrder::B] {
        if let Some(r) = find(
            &rows,
            "three-segment",
            order_label(order),
            "10",
            0,
            "frozen",
        ) {
            budget_table(
                &mut md,
                &format!("{}, 10 cycles each, no rest", order_label(order)),
                &three_segment(order, [10, 10, 10], 0)?,
                [0.0, r.line.predicted.y0],
                r.line.realised.slope,
                r.line.offset(),
            )?;
        }
    }
    for model in ["frozen", "full"] {
        let _ = writeln!(md, "\n## (a) The paper's two primitives, {model} model\n");
        two_primitive_table(&mut md, &rows, model);
    }
    let worst = rows
        .iter()
        .map(|r| r.line.realised.residual)
        .fold(0.0, f64::max);
    let _ = writeln!(
        md,
        "\nWhere |y0| exceeds 20 mm (1 cycle per segment with rest) the line lies outside the fitted points: y0 is extrapolated from the linear fit, whose RMS residual is at most {:.1} % of the RMS of v_y over all rows (`realised_fit_residual` in the CSV).",
        100.0 * worst
    );
    for model in ["frozen", "full"] {
        let _ = writeln!(
            md,
            "\n## (b) The design's three segments, both cyclic orders, {model} model\n"
        );
        three_segment_table(&mut md, &rows, model);
    }
    md.push_str(&summary(&rows));
    platefield::output::write_atomic(&out.join("squeeze_trans_order.md"), md.as_bytes())?;
    platefield::output::write_atomic(
        &out.join("squeeze_trans_order.csv"),
        offset_csv(&rows).as_bytes(),
    )?;
    Ok(md)
}

/// Sentences quantifying the dependences, from the rows.
fn summary(rows: &[OffsetRow]) -> String {
    let mut md = String::from("\n## Summary\n\n");
    for model in ["frozen", "full"] {
        let off = |case: &str, seq: &str, c: &str, rest: u32| {
            find(rows, case, seq, c, rest, model).map_or(f64::NAN, |r| 1e3 * r.line.offset())
        };
        let s90 = "LineSink@90° → Trans@0°";
        let s270 = "LineSink@270° → Trans@0°";
        let s90b = "LineSink@90° → Trans@180°";
        let a = order_label(ThreeOrder::A);
        let b = order_label(ThreeOrder::B);
        let _ = writeln!(
            md,
            "- **{model}**, two primitives: offset {:+.2} / {:+.2} / {:+.2} mm at 1 / 3 / 10 cycles per segment (LineSink@90°); LineSink@270° gives {:+.2} / {:+.2} / {:+.2} mm (the mirror image); reversing Trans changes nothing ({:+.2} mm at 1 cycle). With 1 rest cycle at both joins: {:+.2} / {:+.2} / {:+.2} mm — rest makes it worse, because it removes the cancellation by the Trans segment.",
            off("two-primitive", s90, "1", 0),
            off("two-primitive", s90, "3", 0),
            off("two-primitive", s90, "10", 0),
            off("two-primitive", s270, "1", 0),
            off("two-primitive", s270, "3", 0),
            off("two-primitive", s270, "10", 0),
            off("two-primitive", s90b, "1", 0),
            off("two-primitive", s90, "1", 1),
            off("two-primitive", s90, "3", 1),
            off("two-primitive", s90, "10", 1),
        );
        let d = |c: &str, rest: u32| {
            off("three-segment", a, c, rest) - off("three-segment", b, c, rest)
        };
        let why = if model == "frozen" {
            "every segment then starts from rest whatever precedes it, so with frozen positions the order cannot matter"
        } else {
            "the frozen model's exact zero does not survive moving parts: the order also changes where the part is when each segment acts; not analysed further"
        };
        let _ = writeln!(
            md,
            "- **{model}**, three segments: order A − order B = {:+.2} / {:+.2} / {:+.2} mm at 1 / 3 / 10 cycles per segment, {:+.2} mm as designed (11/11/10); with 1 rest cycle at every join {:+.3} / {:+.3} / {:+.3} mm ({why}).",
            d("1", 0),
            d("3", 0),
            d("10", 0),
            d("11/11/10", 0),
            d("1", 1),
            d("3", 1),
            d("10", 1),
        );
    }
    md
}

/// Default output folder of `platefield study squeeze-order`.
pub const DIR: &str = "results/verify";

/// `platefield study squeeze-order`: `squeeze_order_report`, the files it
/// wrote and the compute time (printed, never written).
pub fn run(out: &Path) -> Result<String> {
    let start = std::time::Instant::now();
    let mut s = squeeze_order_report(out)?;
    s.push_str(&format!(
        "wrote {} and {} ({:.1} s)\n",
        out.join("squeeze_trans_order.md").display(),
        out.join("squeeze_trans_order.csv").display(),
        start.elapsed().as_secs_f64()
    ));
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The line fit recovers an exact line (slope, position, zero residual)
    /// whatever the x positions and however v_x varies.
    #[test]
    fn fit_line_recovers_an_exact_line() {
        let pts = line_points();
        let v: Vec<[f64; 2]> = pts
            .iter()
            .map(|p| [p[0] * 7.0 - 1.0, -0.3 * (p[1] - 0.0021)])
            .collect();
        let f = fit_line(&pts, &v).unwrap();
        assert!((f.slope + 0.3).abs() < 1e-12, "{f:?}");
        assert!((f.y0 - 0.0021).abs() < 1e-12, "{f:?}");
        assert!(f.residual < 1e-12, "{f:?}");
        assert!(fit_line(&pts[..1], &v[..1]).is_none());
        let flat: Vec<[f64; 2]> = pts.iter().map(|_| [0.0, 1.0]).collect();
        assert!(fit_line(&pts, &flat).is_none());
    }
}
