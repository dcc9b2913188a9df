//! The `poses` command's outputs: the JSON of a [`PoseAnalysis`], a
//! picture of the part at each equilibrium with its basin, and a summary.

use std::fmt::Write as _;

use serde_json::{json, Value};

use crate::plot::{escape, num};
use platefield::dynamics::Friction;
use platefield::part::Part;
use platefield::pose::{
    Continuum, Equilibrium, LiftCheck, Motion, PlayedBasins, PlayedRest, Pose, PoseAnalysis,
    RestOutcome, Shape, Twist,
};

pub use platefield::pose::SCAN;

/// What a run adds to the lifted field's analysis.
#[derive(Debug, Clone, Copy, Default)]
pub struct Extras<'a> {
    /// The drops played by the planar simulator.
    pub played: Option<&'a PlayedBasins>,
    /// The poses of the [`SCAN`] that may rest for some admissible
    /// support (an unknown support's bounds).
    pub bounds: Option<&'a [Pose]>,
    /// The lifted field against the averaged field.
    pub lift_check: Option<&'a LiftCheck>,
    /// The played rests Newton found on the averaged field from the lifted equilibria.
    pub played_rests: Option<&'a [PlayedRest]>,
    /// Why the averaged field did not run, when it was skipped.
    pub averaged_skipped: Option<&'a str>,
}

/// A pose as JSON: `{"x", "y", "theta_deg"}` (m, degrees).
fn pose_json(p: &Pose) -> Value {
    json!({"x": p.r.x, "y": p.r.y, "theta_deg": p.theta.to_degrees()})
}

/// One refinement as JSON: the lifted equilibrium it started from and the
/// averaged field's (`"found"`), or why none (`"left_region"`,
/// `"unconverged"`, `"lost_contact"`).
fn rest_json(r: &PlayedRest) -> Value {
    let from = pose_json(&r.from.pose);
    match r.outcome {
        RestOutcome::Found {
            equilibrium: e,
            steps,
        } => json!({
            "from": from,
            "found": {"x": e.pose.r.x, "y": e.pose.r.y, "theta_deg": e.pose.theta.to_degrees(),
                      "stable": e.stable, "rates": e.rates, "newton_steps": steps},
        }),
        RestOutcome::Left(p) => json!({"from": from, "left_region": pose_json(&p)}),
        RestOutcome::Unconverged(p) => json!({"from": from, "unconverged": pose_json(&p)}),
        RestOutcome::Lost(c) => json!({"from": from, "lost_contact": c}),
    }
}

/// An equilibrium in a summary line: `x … mm  y … mm  θ …°  stable  `.
fn equilibrium_text(e: &Equilibrium) -> String {
    format!(
        "x {:+.2} mm  y {:+.2} mm  θ {:+7.2}°  {}",
        1e3 * e.pose.r.x,
        1e3 * e.pose.r.y,
        e.pose.theta.to_degrees(),
        if e.stable { "stable  " } else { "unstable" }
    )
}

/// One summary line per refinement.
fn rest_lines(refined: &[PlayedRest]) -> String {
    let mut s = String::from(
        "on the averaged field (the rigid part's own slip), Newton from each lifted equilibrium:\n",
    );
    for r in refined {
        let f = r.from.pose;
        let what = match (r.outcome, r.moved()) {
            (
                RestOutcome::Found {
                    equilibrium: e,
                    steps,
                },
                Some((d, t)),
            ) => format!(
                "{} ({steps} Newton steps; moved {:.2} mm, {:+.2}°)",
                equilibrium_text(&e),
                1e3 * d,
                t.to_degrees()
            ),
            (other, _) => other.failure().unwrap_or_default(),
        };
        let _ = writeln!(s, "  from θ {:+7.2}°: {what}", f.theta.to_degrees());
    }
    s
}

/// A twist as JSON: `{"vx", "vy", "omega"}` (m/s, rad/s).
fn twist_json(t: &Twist) -> Value {
    json!({"vx": t.v.x, "vy": t.v.y, "omega": t.omega})
}

/// The lift check as JSON.
fn lift_check_json(c: &LiftCheck) -> Value {
    let poses: Vec<Value> = c
        .poses
        .iter()
        .map(|r| {
            let a = r.averaged;
            json!({
                "x": r.pose.r.x,
                "y": r.pose.r.y,
                "theta_deg": r.pose.theta.to_degrees(),
                "lifted": twist_json(&r.lifted),
                "averaged": a.map(|a| twist_json(&a.twist)),
                "periods": a.map(|a| a.periods),
                "converged": a.map(|a| a.converged),
                "local": r.local,
            })
        })
        .collect();
    json!({
        "poses": poses,
        "translation_rms": c.translation_rms,
        "spin_rms": c.spin_rms,
        "by": "the lifted field's twist against the averaged field's (the rigid part's periodic slip at the pose, pose::AveragedField) at the equilibria and the first drop starts; RMS of the difference over the RMS of the averaged twist, over the poses where one period moves the part less than half its radius and 0.5 rad (\"local\") (the rest: the part travels to its rest within a period, and the averaged twist is that trip); \"averaged\": null where a support point loses contact",
    })
}

/// The bounds as JSON: how many scanned poses are kept, their extent and
/// the θ bins (of 360°/`SCAN[2]`) holding any.
fn bounds_json(kept: &[Pose]) -> Value {
    let range = |f: &dyn Fn(&Pose) -> f64| {
        let lo = kept.iter().map(f).fold(f64::INFINITY, f64::min);
        let hi = kept.iter().map(f).fold(f64::NEG_INFINITY, f64::max);
        if kept.is_empty() {
            Value::Null
        } else {
            json!([lo, hi])
        }
    };
    let mut bins: Vec<i64> = kept
        .iter()
        .map(|p| (p.theta.to_degrees() * SCAN[2] as f64 / 360.0).round() as i64)
        .collect();
    bins.sort_unstable();
    bins.dedup();
    json!({
        "scanned": SCAN,
        "kept": kept.len(),
        "of": SCAN.iter().product::<usize>(),
        "x": range(&|p| p.r.x),
        "y": range(&|p| p.r.y),
        "theta_bins_kept": bins.len(),
        "meaning": "poses (grid cell centres) that may be equilibria for some admissible support: an outer bound (pose::Bounds)",
    })
}

/// The spin range of `c` in °/s.
fn spin_deg(c: &Continuum) -> [f64; 2] {
    c.spin_range().map(f64::to_degrees)
}

/// The neutral bound of `c` in its own units: °/s for a curve through
/// every angle, mm/s otherwise (its smallest over the points).
fn neutral_text(c: &Continuum) -> String {
    let least = c.neutral.iter().copied().fold(f64::INFINITY, f64::min);
    match c.shape {
        Shape::AnyAngle { .. } => format!("{:.2e}°/s", least.to_degrees()),
        _ => format!("{:.2e} mm/s", 1e3 * least * c.radius),
    }
}

/// Where `c` is, in words: "at (x, y) mm (within d mm), any angle", "on
/// the line from … to … mm (L mm), at θ", or a curve's ends.
pub fn continuum_place(c: &Continuum) -> String {
    match c.shape {
        Shape::AnyAngle { at, spread } => format!(
            "at ({:+.2}, {:+.2}) mm (within {:.3} mm), any angle",
            1e3 * at.x,
            1e3 * at.y,
            1e3 * spread
        ),
        Shape::Line {
            from,
            to,
            theta,
            ..
        } => format!(
            "anywhere on the line from ({:+.2}, {:+.2}) to ({:+.2}, {:+.2}) mm ({:.1} mm), at θ {:+.2}°",
            1e3 * from.x,
            1e3 * from.y,
            1e3 * to.x,
            1e3 * to.y,
            1e3 * (to - from).norm(),
            theta.to_degrees()
        ),
        Shape::Curve => {
            let at = |p: &Pose| {
                format!(
                    "({:+.2} mm, {:+.2} mm, {:+.2}°)",
                    1e3 * p.r.x,
                    1e3 * p.r.y,
                    p.theta.to_degrees()
                )
            };
            let (first, last) = (c.points[0], c.points[c.points.len() - 1]);
            format!(
                "on a {}curve of {} poses from {} to {}",
                if c.closed { "closed " } else { "" },
                c.points.len(),
                at(&first),
                at(&last)
            )
        }
    }
}

/// How a part moves on `c`, in words.
pub fn continuum_motion(c: &Continuum) -> String {
    let [lo, hi] = spin_deg(c);
    let turning = matches!(c.shape, Shape::AnyAngle { .. });
    match c.motion() {
        Motion::Rest => format!(
            "neutral: it stays where it arrives (the drift along it is below {} everywhere)",
            neutral_text(c)
        ),
        Motion::Around if turning => {
            let slowest = lo.abs().min(hi.abs());
            format!(
                "it keeps turning at {lo:+.2}…{hi:+.2}°/s (a half turn in at most {:.0} s): the angle it shows depends on when the plate stops",
                180.0 / slowest
            )
        }
        Motion::Around => format!(
            "it keeps going round it at up to {:.3} mm/s and {:.2}°/s",
            1e3 * c.top_speed(),
            lo.abs().max(hi.abs())
        ),
        Motion::Drifts if turning => format!(
            "it turns slowly (at most {:.3}°/s) towards the isolated rests on it (listed above)",
            lo.abs().max(hi.abs())
        ),
        Motion::Drifts => format!(
            "it drifts slowly along it (at most {:.3} mm/s, {:.3}°/s) towards the isolated rests on it or off its ends",
            1e3 * c.top_speed(),
            lo.abs().max(hi.abs())
        ),
    }
}

/// One summary line per continuum.
fn continuum_lines(a: &PoseAnalysis) -> String {
    let mut s = String::new();
    for (c, b) in a.continua.iter().zip(&a.continuum_basins) {
        let _ = writeln!(
            s,
            "  rests {}; {}; {}, basin {:.1} %",
            continuum_place(c),
            continuum_motion(c),
            if c.attracting() {
                "attracting"
            } else {
                "not attracting (unstable across it)"
            },
            100.0 * b
        );
    }
    s
}

/// A continuum as JSON.
fn continuum_json(c: &Continuum, basin: f64) -> Value {
    let shape = match c.shape {
        Shape::AnyAngle { at, spread } => {
            json!({"kind": "any_angle", "x": at.x, "y": at.y, "spread": spread})
        }
        Shape::Line {
            from,
            to,
            theta,
            bend,
        } => json!({"kind": "line", "from": [from.x, from.y], "to": [to.x, to.y],
                     "theta_deg": theta.to_degrees(), "bend": bend}),
        Shape::Curve => json!({"kind": "curve"}),
    };
    let motion = match c.motion() {
        Motion::Rest => "rest",
        Motion::Around => "around",
        Motion::Drifts => "drifts",
    };
    let points: Vec<Value> = c
        .points
        .iter()
        .map(|p| json!([p.r.x, p.r.y, p.theta.to_degrees()]))
        .collect();
    json!({
        "shape": shape,
        "motion": motion,
        "text": format!("rests {}; {}", continuum_place(c), continuum_motion(c)),
        "attracting": c.attracting(),
        "basin": basin,
        "closed": c.closed,
        "spin_deg_per_s": spin_deg(c),
        "top_speed": c.top_speed(),
        "transverse_rate": c.transverse,
        "points": points,
    })
}

/// The analyses over a friction range as JSON: per value its friction,
/// equilibria, continua and unsettled fraction.
pub fn over_friction_json(at: &[(Friction, PoseAnalysis)]) -> Value {
    Value::Array(
        at.iter()
            .map(|(f, a)| {
                let eq: Vec<Value> = a
                    .equilibria
                    .iter()
                    .zip(&a.basins)
                    .map(|(e, b)| {
                        json!({"x": e.pose.r.x, "y": e.pose.r.y, "theta_deg": e.pose.theta.to_degrees(),
                               "stable": e.stable, "basin": b, "rates": e.rates})
                    })
                    .collect();
                let continua: Vec<Value> = a
                    .continua
                    .iter()
                    .zip(&a.continuum_basins)
                    .map(|(c, b)| continuum_json(c, *b))
                    .collect();
                json!({"friction": {"static": f.stat, "kinetic": f.kinetic},
                       "equilibria": eq, "continua": continua, "unsettled": a.unsettled})
            })
            .collect(),
    )
}

/// The analyses over a friction range in words: per value its stable
/// equilibria and continua with their basins (empty for one friction).
pub fn over_friction_lines(at: &[(Friction, PoseAnalysis)]) -> String {
    let mut s = String::new();
    if at.is_empty() {
        return s;
    }
    let _ = writeln!(s, "over the friction range ({} values):", at.len());
    for (f, a) in at {
        let mu = if f.stat == f.kinetic {
            format!("μ {}", f.kinetic)
        } else {
            format!("μ_s {} μ_k {}", f.stat, f.kinetic)
        };
        let _ = writeln!(
            s,
            "at {mu}: {} equilibria ({} stable), {} continu{}, {:.1} % unsettled",
            a.equilibria.len(),
            a.equilibria.iter().filter(|e| e.stable).count(),
            a.continua.len(),
            if a.continua.len() == 1 { "um" } else { "a" },
            100.0 * a.unsettled
        );
        for (e, b) in a.equilibria.iter().zip(&a.basins).filter(|(e, _)| e.stable) {
            let _ = writeln!(s, "  {}  basin {:.1} %", equilibrium_text(e), 100.0 * b);
        }
        s.push_str(&continuum_lines(a));
    }
    s
}

/// The played basins as JSON.
fn played_json(p: &PlayedBasins) -> Value {
    json!({
        "basins": p.basins,
        "agreement": p.agreement,
        "worst_end_distance": p.worst,
        "lost": p.lost,
        "seconds": p.time,
        "by": "each drop played by the planar simulator through the schedule, its end classified by the nearest stable pose (pose::played_basins)",
    })
}

/// `{"part", "support", "equilibria": [{"x", "y", "theta_deg", "stable",
/// "basin", "rates"}], "continua": [{"shape", "motion", "text",
/// "attracting", "basin", …, "points"}], "drops", "unsettled",
/// "basins_by", "continua_by"}` (positions in m),
/// with `"played"`, `"bounds"`, `"lifted_check"`, `"averaged_equilibria"`
/// and `"averaged_skipped"` when `extras` holds them.
pub fn to_json(part: &Part, a: &PoseAnalysis, extras: &Extras<'_>) -> Value {
    let eq: Vec<Value> = a
        .equilibria
        .iter()
        .zip(&a.basins)
        .map(|(e, b)| {
            json!({
                "x": e.pose.r.x,
                "y": e.pose.r.y,
                "theta_deg": e.pose.theta.to_degrees(),
                "stable": e.stable,
                "basin": b,
                "rates": e.rates,
            })
        })
        .collect();
    let support = match part.support {
        platefield::part::Support::Unknown { .. } => {
            "unknown: these are the uniform support's equilibria; \"bounds\" holds the poses that may rest for some admissible support"
        }
        platefield::part::Support::Points { .. } => "listed points",
        platefield::part::Support::Uniform { .. } => "uniform",
    };
    let continua: Vec<Value> = a
        .continua
        .iter()
        .zip(&a.continuum_basins)
        .map(|(c, b)| continuum_json(c, *b))
        .collect();
    let mut out = json!({
        "part": part.name,
        "support": support,
        "equilibria": eq,
        "continua": continua,
        "drops": a.drops,
        "unsettled": a.unsettled,
        "basins_by": "drops integrated along the lifted field (pose::settle_on)",
        "continua_by": "where the lifted field's Jacobian (position in part radii R, angle in rad) has a singular value below 0.1/ln(1/δ) of the next (δ = 1e-3: a drop's arrival tolerance), the slow curve through the pose is traced; it is a rest where the drift along it moves the part less than δ while the transverse directions settle to δ (|drift| ≤ δ σ₂ / ln(1/δ)); points are [x (m), y (m), θ (°)] (pose::rests)",
    });
    if let Some(p) = extras.played {
        out["played"] = played_json(p);
    }
    if let Some(b) = extras.bounds {
        out["bounds"] = bounds_json(b);
    }
    if let Some(c) = extras.lift_check {
        out["lifted_check"] = lift_check_json(c);
    }
    if let Some(r) = extras.played_rests {
        out["averaged_equilibria"] = Value::Array(r.iter().map(rest_json).collect());
    }
    if let Some(why) = extras.averaged_skipped {
        out["averaged_skipped"] = json!(why);
    }
    out
}

/// One line per equilibrium (with its played basin when played), then the
/// bounds' size.
pub fn summary(part: &Part, a: &PoseAnalysis, extras: &Extras<'_>) -> String {
    let continua = match a.continua.len() {
        0 => String::new(),
        1 => ", 1 continuum".to_string(),
        n => format!(", {n} continua"),
    };
    let mut s = format!(
        "{}: {} equilibria ({} stable){continua}, {} drops, {:.1} % unsettled\n",
        part.name,
        a.equilibria.len(),
        a.equilibria.iter().filter(|e| e.stable).count(),
        a.drops,
        100.0 * a.unsettled
    );
    for (i, (e, b)) in a.equilibria.iter().zip(&a.basins).enumerate() {
        let played = extras
            .played
            .map(|p| format!(", played {:.1} %", 100.0 * p.basins[i]))
            .unwrap_or_default();
        let _ = writeln!(
            s,
            "  {}  basin {:.1} %{played}",
            equilibrium_text(e),
            100.0 * b
        );
    }
    s.push_str(&continuum_lines(a));
    if let Some(p) = extras.played {
        let _ = writeln!(
            s,
            "played by the planar simulator for {:.1} s: {:.1} % of the drops end where the lifted field predicts, {} lost contact",
            p.time,
            100.0 * p.agreement,
            p.lost
        );
    }
    if let Some(b) = extras.bounds {
        let _ = writeln!(
            s,
            "unknown support: {} of {} scanned poses may rest for some admissible support",
            b.len(),
            SCAN.iter().product::<usize>()
        );
    }
    if let Some(c) = extras.lift_check {
        s.push_str(&lift_check_line(c));
    }
    if let Some(r) = extras.played_rests.filter(|r| !r.is_empty()) {
        s.push_str(&rest_lines(r));
    }
    if let Some(why) = extras.averaged_skipped {
        let _ = writeln!(s, "{why}");
    }
    s
}

/// The lift check in one line.
fn lift_check_line(c: &LiftCheck) -> String {
    let kept = c.poses.iter().filter(|p| p.averaged.is_some()).count();
    let pct = |e: Option<f64>| e.map_or("—".to_string(), |e| format!("{:.1} %", 100.0 * e));
    let lost = c.poses.len() - kept;
    let local = c.poses.iter().filter(|p| p.local).count();
    format!(
        "lifted field against the averaged part at {local} of {} poses (those a schedule period moves less than half the part's radius and 0.5 rad): translation RMS {}, spin RMS {}{}\n",
        c.poses.len(),
        pct(c.translation_rms),
        pct(c.spin_rms),
        if lost > 0 {
            format!(" ({lost} lost contact)")
        } else {
            String::new()
        }
    )
}

/// Colours of the stable poses' basins in the θ-against-position panels.
const BASIN_COLOURS: [&str; 6] = [
    "#1f77b4", "#ff7f0e", "#2ca02c", "#9467bd", "#8c564b", "#e377c2",
];

/// Height of the θ-against-position panels below the region (px).
const THETA_PANEL: f64 = 320.0;

/// The region with the part drawn at every equilibrium (stable: filled,
/// labelled with θ and its basin; unstable: dashed outline), and below it
/// θ against x and against y (each drop's start, coloured by its end).
pub fn picture(part: &Part, a: &PoseAnalysis) -> String {
    let (w, h, pad) = (520.0, 520.0, 40.0);
    let mut s = region_panel(part, a, w, h, pad);
    theta_panels(&mut s, a, w, h);
    s.push_str("</svg>\n");
    s
}

/// θ against position: every drop's start (x in the left panel, y in the
/// right; θ from −180° to 180° upwards) as a dot coloured by the stable
/// pose it settled at (grey: unsettled), each equilibrium as a ring
/// (stable: filled). A field that orients the part shows horizontal
/// bands: the end angle depends on the start angle, not on where it fell.
fn theta_panels(s: &mut String, a: &PoseAnalysis, w: f64, top: f64) {
    let (pad, gap) = (40.0, 30.0);
    let side = (w - 2.0 * pad - gap) / 2.0;
    let height = THETA_PANEL - 90.0;
    let y0 = top + 20.0;
    let stable: Vec<usize> = (0..a.equilibria.len())
        .filter(|&i| a.equilibria[i].stable)
        .collect();
    let colour = |end: Option<usize>| {
        end.and_then(|i| stable.iter().position(|&k| k == i))
            .map_or("#999", |k| BASIN_COLOURS[k % BASIN_COLOURS.len()])
    };
    // A continuum's colour follows the stable poses'.
    let on = |k: usize| BASIN_COLOURS[(stable.len() + k) % BASIN_COLOURS.len()];
    let starts = platefield::pose::drop_starts(&a.starts, a.drops);
    let theta_y = |t: f64| y0 + height * (0.5 - t / std::f64::consts::TAU);
    for (panel, (name, range)) in [("x", a.region.x), ("y", a.region.y)].iter().enumerate() {
        let left = pad + panel as f64 * (side + gap);
        let px = |v: f64| left + side * (v - range[0]) / (range[1] - range[0]);
        let _ = writeln!(
            s,
            "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>",
            num(left),
            num(y0),
            num(side),
            num(height)
        );
        let coord = |p: &Pose| if panel == 0 { p.r.x } else { p.r.y };
        for ((p, end), cont) in starts.iter().zip(&a.ends).zip(&a.continuum_ends) {
            let _ = writeln!(
                s,
                "<circle cx=\"{}\" cy=\"{}\" r=\"2\" fill=\"{}\"/>",
                num(px(coord(p))),
                num(theta_y(p.theta)),
                cont.map_or_else(|| colour(*end), on)
            );
        }
        for (k, c) in a.continua.iter().enumerate() {
            // θ against the coordinate, broken where θ wraps.
            let mut path = String::new();
            let mut last: Option<f64> = None;
            let n = c.points.len() + usize::from(c.closed);
            for i in 0..n {
                let p = &c.points[i % c.points.len()];
                let t = platefield::pose::wrap(p.theta);
                let jump = last.is_some_and(|l| (t - l).abs() > std::f64::consts::PI);
                let _ = write!(
                    path,
                    "{}{},{} ",
                    if last.is_none() || jump { "M" } else { "L" },
                    num(px(coord(p))),
                    num(theta_y(t))
                );
                last = Some(t);
            }
            let dash = if c.attracting() {
                ""
            } else {
                " stroke-dasharray=\"4 3\""
            };
            let _ = writeln!(
                s,
                "<path d=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"3\"{dash}/>",
                path.trim_end(),
                on(k)
            );
        }
        for (i, e) in a.equilibria.iter().enumerate() {
            let fill = if e.stable { colour(Some(i)) } else { "none" };
            let _ = writeln!(
                s,
                "<circle cx=\"{}\" cy=\"{}\" r=\"6\" fill=\"{fill}\" stroke=\"#000\"/>",
                num(px(coord(&e.pose))),
                num(theta_y(e.pose.theta))
            );
        }
        for (t, label) in [(180.0f64, "180°"), (0.0, "0°"), (-180.0, "−180°")] {
            let _ = writeln!(
                s,
                "<text x=\"{}\" y=\"{}\" text-anchor=\"end\" font-size=\"10\">{label}</text>",
                num(left - 3.0),
                num(theta_y(t.to_radians()) + 4.0)
            );
        }
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">start {name} ({} to {} mm)</text>",
            num(left + side / 2.0),
            num(y0 + height + 16.0),
            num(1e3 * range[0]),
            num(1e3 * range[1])
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#555\">θ against position: each drop's start, coloured by the stable pose it reached</text>",
        num(w / 2.0),
        num(y0 + height + 36.0)
    );
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#555\">(ring: stable pose; open ring: unstable; thick line: a continuum of rest, dashed when unstable; grey: unsettled)</text>",
        num(w / 2.0),
        num(y0 + height + 54.0)
    );
}

/// The region panel of [`picture`]: the `<svg>` opening (tall enough for
/// the θ panels) and the part at every equilibrium.
fn region_panel(part: &Part, a: &PoseAnalysis, w: f64, h: f64, pad: f64) -> String {
    let (x0, x1, y0, y1) = (a.region.x[0], a.region.x[1], a.region.y[0], a.region.y[1]);
    let scale = ((w - 2.0 * pad) / (x1 - x0)).min((h - 2.0 * pad) / (y1 - y0));
    let px = |x: f64| pad + (x - x0) * scale;
    let py = |y: f64| h - pad - (y - y0) * scale;
    let total = h + THETA_PANEL;
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{w}\" height=\"{total}\" viewBox=\"0 0 {w} {total}\" font-family=\"sans-serif\" font-size=\"12\">\n"
    );
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"20\" text-anchor=\"middle\">{}: equilibrium poses, basin fraction of {} drops</text>",
        num(w / 2.0),
        escape(&part.name),
        a.drops
    );
    let _ = writeln!(
        s,
        "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"#888\"/>",
        num(px(x0)),
        num(py(y1)),
        num((x1 - x0) * scale),
        num((y1 - y0) * scale)
    );
    let mut labels = 0;
    for (e, b) in a.equilibria.iter().zip(&a.basins) {
        let pts: Vec<String> = part
            .placed(e.pose.r, e.pose.theta)
            .iter()
            .map(|p| format!("{},{}", num(px(p.x)), num(py(p.y))))
            .collect();
        let style = if e.stable {
            "fill=\"#1f77b4\" fill-opacity=\"0.35\" stroke=\"#1f77b4\""
        } else {
            "fill=\"none\" stroke=\"#d62728\" stroke-dasharray=\"4 3\""
        };
        let _ = writeln!(s, "<polygon points=\"{}\" {style}/>", pts.join(" "));
        if e.stable {
            // The body x axis as a line to a dot, so θ and θ + 180° differ.
            let tip = e.pose.r
                + platefield::dynamics::V2::new(e.pose.theta.cos(), e.pose.theta.sin())
                    * part.radius();
            let _ = writeln!(
                s,
                "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#1f77b4\"/><circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"#1f77b4\"/>",
                num(px(e.pose.r.x)),
                num(py(e.pose.r.y)),
                num(px(tip.x)),
                num(py(tip.y)),
                num(px(tip.x)),
                num(py(tip.y))
            );
            labels += 1;
            let _ = writeln!(
                s,
                "<text x=\"{}\" y=\"{}\" fill=\"#1f77b4\">stable at ({:.1}, {:.1}) mm, θ {:.1}° (dot: body x axis): basin {:.0} %</text>",
                num(pad + 6.0),
                num(pad + 16.0 * labels as f64),
                1e3 * e.pose.r.x,
                1e3 * e.pose.r.y,
                e.pose.theta.to_degrees(),
                100.0 * b
            );
        }
    }
    let stable = a.equilibria.iter().filter(|e| e.stable).count();
    for (k, (c, b)) in a.continua.iter().zip(&a.continuum_basins).enumerate() {
        let colour = BASIN_COLOURS[(stable + k) % BASIN_COLOURS.len()];
        let dash = if c.attracting() {
            ""
        } else {
            " stroke-dasharray=\"4 3\""
        };
        // The part at twelve poses spread along the curve, and the curve's
        // positions as a thick line.
        for i in 0..12usize.min(c.points.len()) {
            let p = c.points[i * c.points.len() / 12usize.min(c.points.len())];
            let pts: Vec<String> = part
                .placed(p.r, p.theta)
                .iter()
                .map(|q| format!("{},{}", num(px(q.x)), num(py(q.y))))
                .collect();
            let _ = writeln!(
                s,
                "<polygon points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-opacity=\"0.45\"{dash}/>",
                pts.join(" ")
            );
        }
        let path: Vec<String> = c
            .points
            .iter()
            .map(|p| format!("{},{}", num(px(p.r.x)), num(py(p.r.y))))
            .collect();
        let _ = writeln!(
            s,
            "<polyline points=\"{}\" fill=\"none\" stroke=\"{colour}\" stroke-width=\"4\"{dash}/><circle cx=\"{}\" cy=\"{}\" r=\"3\" fill=\"{colour}\"/>",
            path.join(" "),
            num(px(c.points[0].r.x)),
            num(py(c.points[0].r.y))
        );
        labels += 1;
        let _ = writeln!(
            s,
            "<text x=\"{}\" y=\"{}\" fill=\"{colour}\">rests {}: basin {:.0} %</text>",
            num(pad + 6.0),
            num(pad + 16.0 * labels as f64),
            escape(&continuum_place(c)),
            100.0 * b
        );
    }
    let _ = writeln!(
        s,
        "<text x=\"{}\" y=\"{}\" text-anchor=\"middle\" fill=\"#555\">filled: stable (θ, basin); dashed: unstable; thick line: a continuum of rest (the part drawn along it); box: region {} × {} mm</text>",
        num(w / 2.0),
        num(h - 12.0),
        num(1e3 * (x1 - x0)),
        num(1e3 * (y1 - y0))
    );
    s
}
