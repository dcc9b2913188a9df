//! Aiming a sort candidate by play (see the parent module's **Aim**):
//! its classes' targets moved (sinks) and turned and scaled (lanes) until
//! the parts played under its schedule do what the class asks.

use super::interleave::{class_excursion, interleaved, sub_periods};
use super::{fit_stack, swarm, SortDesign, SortMethod, Stack};
use crate::error::Result;
use crate::play::{PlayOptions, ScheduleMotion, V2};
use crate::request::{Edge, Target};

/// Most refits of a synthesized candidate aimed by its settled parts.
pub const AIM_STEPS: usize = 3;
/// Aiming stops once every class settles within this (m) of its attractor.
pub const AIM_TOL: f64 = 1e-3;
/// Time (s) the aiming parts are played (whole schedule periods).
pub const AIM_PLAY_S: f64 = 20.0;
/// Offsets (m) of the aiming parts from the attractor: the attractor and
/// four points this far along x and y.
pub(super) const AIM_SPREAD: f64 = 3e-3;
/// Time (s) a lane's aiming parts are played (whole schedule periods): at
/// a few mm/s they cross a few centimetres, and the drift is a mean.
pub const LANE_PLAY_S: f64 = 10.0;
/// Time (s) every refit of an aimed candidate is played by the design's
/// swarms to rank it (`played_sort`): the sort's goals (lanes out by
/// 20 s, two sinks by 30 s) and 10 s more to see the classes stay sorted,
/// shorter than the candidates' final plays (at least 90 s,
/// `crate::verify::sort_play::MIN_SORT_PLAY_S` and `SORT_HOLD_S`).
pub const AIM_SWARM_S: f64 = 40.0;
/// A lane's steering stops once every lane's correction (the complex
/// ratio of the drift asked for to the drift played, normalised) is
/// within this of 1: about 1° of turn and 2 % of speed.
pub const LANE_TOL: f64 = 0.02;
/// The share of a lane's parts that must leave through its own edge (the
/// sort's goal, `crate::verify::sort_play::SORT_SHARE`), used to rank the
/// steering's refits by their drift.
pub const LANE_SHARE: f64 = 0.95;

/// The complex product of the vector `v` and the factor `k` (re, im):
/// `v` turned by arg k and scaled by |k|.
pub(super) fn turn(v: [f64; 2], k: [f64; 2]) -> [f64; 2] {
    [k[0] * v[0] - k[1] * v[1], k[1] * v[0] + k[0] * v[1]]
}

/// Strength of a lane's keeping field, relative to its speed, times the
/// lane's width W: κ = LANE_KEEP / W (1/m; module docs, **Lanes**).
pub const LANE_KEEP: f64 = 0.4;

/// A lane's fitted vector at `p`: its (steered) transport `v` plus the
/// keeping field toward the lane's axis (the line through the region's
/// centre along the edge's outward normal), −κ |v| y n_across, with y the
/// distance of `p` from the axis and κ = [`LANE_KEEP`] / W. Under it a
/// part whose drift runs off the lane at t = v_across / v_along settles at
/// y* = t / κ from the axis instead of leaving through a side edge: with
/// κ = 0.4 / W, a drift 0.1 off the lane (5.7°) is held within W/4, 0.2
/// within W/2.
pub(super) fn lane_kept(target: &Target, edge: Edge, p: [f64; 2], v: [f64; 2]) -> [f64; 2] {
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let (_, width) = lane_extent(target, edge);
    let kappa = LANE_KEEP / width;
    let n = edge.outward();
    let across = [-n[1], n[0]];
    let centre = [0.5 * (g.x[0] + g.x[1]), 0.5 * (g.y[0] + g.y[1])];
    let y = (p[0] - centre[0]) * across[0] + (p[1] - centre[1]) * across[1];
    let pull = -kappa * v[0].hypot(v[1]) * y;
    [v[0] + pull * across[0], v[1] + pull * across[1]]
}

/// The complex quotient a / b.
fn quotient(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let m = b[0] * b[0] + b[1] * b[1];
    [
        (a[0] * b[0] + a[1] * b[1]) / m,
        (a[1] * b[0] - a[0] * b[1]) / m,
    ]
}

/// How a refit ranks while it is aimed, the least first: for lanes, its
/// played time to sort ([`played_sort`]), then the higher least share at
/// the own attractor less the share mixed up; then, per lane, the
/// time its drift predicts for [`LANE_SHARE`] of its parts to leave
/// through its own edge, and the share it predicts through the side
/// edges ([`lane_outlook`]), the worst lane's; then the worst sink's
/// settled offset (m).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Rank {
    played: f64,
    share: f64,
    lane_time: f64,
    lane_other: f64,
    offset: f64,
}

impl Rank {
    fn better(&self, other: &Rank) -> bool {
        self.played
            .total_cmp(&other.played)
            .then(other.share.total_cmp(&self.share))
            .then(self.lane_time.total_cmp(&other.lane_time))
            .then(self.lane_other.total_cmp(&other.lane_other))
            .then(self.offset.total_cmp(&other.offset))
            .is_lt()
    }
}

/// `fit_stack` aimed (module docs, **Aim**): up to [`AIM_STEPS`] refits,
/// each sink class's target moved against the offset of where its parts,
/// started at and around its attractor and played [`AIM_PLAY_S`], settle,
/// and each lane class's target steered by the drift of its parts played
/// [`LANE_PLAY_S`] ([`steering`]); the refit that ranks first ([`Rank`])
/// is kept (a refit that fails ends the aim there). A lane target keeps
/// the class scales the first fit chose, so that the steering alone sets
/// the lanes' relative speeds.
pub(super) fn aimed(target: &Target, stack: &Stack, budget: Option<f64>) -> Result<SortDesign> {
    let n = target.classes.len();
    let lanes = target.classes.iter().any(|c| c.exit.is_some());
    let mut aim = vec![[0.0; 2]; n];
    let mut steer = vec![[1.0, 0.0]; n];
    let refit = |aim: &[[f64; 2]], steer: &[[f64; 2]], scales: Option<&[f64]>| {
        fit_stack(
            target,
            stack,
            SortMethod::Synthesized,
            budget,
            aim,
            steer,
            scales,
        )
    };
    let mut d = refit(&aim, &steer, None).and_then(|d| cut(target, d))?;
    let scales: Option<Vec<f64>> = lanes.then(|| d.classes.iter().map(|c| c.scale).collect());
    let mut best: Option<(Rank, SortDesign)> = None;
    for step in 0..=AIM_STEPS {
        let offsets = settle_offsets(target, &d)?;
        let drifts = lane_drifts(target, &d)?;
        let outlooks: Vec<(f64, f64)> = target
            .classes
            .iter()
            .zip(&drifts)
            .filter_map(|(c, v)| Some(lane_outlook(target, c.exit?, (*v)?)))
            .collect();
        let (played, share) = if lanes {
            played_sort(target, &d)?
        } else {
            (0.0, 0.0)
        };
        let rank = Rank {
            played,
            share,
            lane_time: outlooks.iter().map(|o| o.0).fold(0.0, f64::max),
            lane_other: outlooks.iter().map(|o| o.1).fold(0.0, f64::max),
            offset: offsets
                .iter()
                .flatten()
                .map(|e| e[0].hypot(e[1]))
                .fold(0.0, f64::max),
        };
        if best.as_ref().is_none_or(|b| rank.better(&b.0)) {
            best = Some((rank, d.clone()));
        }
        let corrections = steering(target, &drifts);
        let steered = corrections
            .iter()
            .flatten()
            .all(|r| (r[0] - 1.0).hypot(r[1]) < LANE_TOL);
        if (rank.offset < AIM_TOL && steered) || step == AIM_STEPS {
            break;
        }
        for (a, e) in aim.iter_mut().zip(&offsets) {
            if let Some(e) = e {
                *a = [a[0] - e[0], a[1] - e[1]];
            }
        }
        for (k, r) in steer.iter_mut().zip(&corrections) {
            if let Some(r) = r {
                *k = turn(*k, *r);
            }
        }
        // A refit the conic solver cannot verify (its KKT residual over
        // tolerance) ends the aim: the best refit so far is kept.
        match refit(&aim, &steer, scales.as_deref()) {
            Ok(next) => d = cut(target, next)?,
            Err(_) => break,
        }
    }
    Ok(best.map(|b| b.1).unwrap_or(d))
}

/// The lanes of `d` played as the design plays them
/// (`crate::verify::sort_play`: every lane class's swarm, [`swarm`]'s
/// starts, at its own friction) for [`AIM_SWARM_S`] (whole periods): the
/// time (s) by which [`LANE_SHARE`] of every lane class has left through
/// its own edge (infinite when a class has not within the play), and the
/// least over the lane classes of the share out through its own edge less
/// the share out through another.
fn played_sort(target: &Target, d: &SortDesign) -> Result<(f64, f64)> {
    use rayon::prelude::*;
    let sm = ScheduleMotion::from_schedule(&d.schedule)?;
    let periods = ((AIM_SWARM_S / d.schedule.period_s).ceil() as u32).max(1);
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let starts = swarm::swarm_starts(target);
    let durations: Vec<f64> = sm.segments().iter().map(|s| s.duration).collect();
    let n = starts.len().max(1) as f64;
    let (mut time, mut share) = (0.0_f64, f64::INFINITY);
    for (i, class) in target.classes.iter().enumerate() {
        let Some(edge) = class.exit else {
            continue;
        };
        let v = PlayOptions::from_settings(&target.class_target(i).physics(&d.schedule.settings));
        let exits: Vec<Option<(Edge, f64)>> = starts
            .par_iter()
            .map(|p| {
                let player = v.moving_player(&sm);
                let anchor = V2::from(*p);
                let mut state = crate::dynamics::PartState::new(anchor, V2::zeros());
                let mut path = Vec::new();
                // A part that loses contact counts by where it went first.
                let _ = player.play_periods(&mut state, &anchor, 0, periods, |_, _, s| {
                    path.push([s.r.x, s.r.y]);
                });
                swarm::first_exit(&path, &durations, g.x, g.y)
            })
            .collect();
        let own: Vec<Option<f64>> = exits
            .iter()
            .map(|e| e.filter(|e| e.0 == edge).map(|e| e.1))
            .collect();
        let other = exits.iter().flatten().filter(|e| e.0 != edge).count();
        let out = own.iter().flatten().count();
        time = time.max(swarm::time_to_share(&own, LANE_SHARE).unwrap_or(f64::INFINITY));
        share = share.min((out as f64 - other as f64) / n);
    }
    Ok((time, share))
}

/// `d` with its schedule cut into the sub-periods its parts' excursion
/// asks for when `target` has lanes (parent module docs,
/// **Interleaving**: on sinks, the cut loses the sorts).
fn cut(target: &Target, mut d: SortDesign) -> Result<SortDesign> {
    if target.classes.iter().all(|c| c.exit.is_none()) {
        return Ok(d);
    }
    let k = sub_periods(class_excursion(target, &d.schedule)?);
    d.schedule = interleaved(&d.schedule, k);
    d.sub_periods = k;
    Ok(d)
}

/// The region's extent (m) along a lane through `edge` (its length L)
/// and across it (its width W).
fn lane_extent(target: &Target, edge: Edge) -> (f64, f64) {
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let (dx, dy) = (g.x[1] - g.x[0], g.y[1] - g.y[0]);
    match edge {
        Edge::Left | Edge::Right => (dx, dy),
        Edge::Bottom | Edge::Top => (dy, dx),
    }
}

/// What a uniform drift `v` (m/s) predicts for a lane through `edge`:
/// parts started uniformly over the region (length L along the lane,
/// width W across), each carried straight at `v`, at t = |v_across| /
/// v_along off the lane: a part started D from its own edge leaves through
/// a side edge when it starts within D·t of it, so the share through the
/// sides is the mean of D·t / W over D uniform in [0, L], L·t / (2W)
/// (capped at 1); the parts through their own edge take D / v_along, and
/// the [`LANE_SHARE`] of all of them are out by the (LANE_SHARE + that
/// share)-quantile of D, (LANE_SHARE + side share)·L / v_along (infinite
/// when more than 1 − LANE_SHARE leave through the sides or the drift does
/// not point out through the edge). Returns (that time (s), the side
/// share).
///
/// On `results/sort_lanes/`, before steering, the μ 0.2 drift's side
/// share predicts the share of its swarm that leaves through the side
/// edge to within a few parts of the swarm.
pub(crate) fn lane_outlook(target: &Target, edge: Edge, v: [f64; 2]) -> (f64, f64) {
    let (length, width) = lane_extent(target, edge);
    let n = edge.outward();
    let along = v[0] * n[0] + v[1] * n[1];
    let across = (v[0] * n[1] - v[1] * n[0]).abs();
    if along <= 0.0 {
        return (f64::INFINITY, 1.0);
    }
    let side = (length * across / (along * 2.0 * width)).min(1.0);
    let time = if side > 1.0 - LANE_SHARE {
        f64::INFINITY
    } else {
        (LANE_SHARE + side) * length / along
    };
    (time, side)
}

/// Per class, the correction its lane's target factor is multiplied by
/// (`None` for a class without an exit or whose drift is unknown): the
/// complex ratio of the drift asked for, L·n (its lane's length along the
/// edge's outward normal n, so that every lane is crossed in the same
/// time), to the drift played, divided by the geometric mean of the
/// ratios' moduli (the fit's strength sets the common speed). If each
/// class's drift were its target's vectors times a complex gain of its
/// own (turned by the slip lead and the segments' joins, scaled), one
/// correction would put every drift on its lane at equal crossing times.
fn steering(target: &Target, drifts: &[Option<[f64; 2]>]) -> Vec<Option<[f64; 2]>> {
    let ratios: Vec<Option<[f64; 2]>> = target
        .classes
        .iter()
        .zip(drifts)
        .map(|(c, v)| {
            let edge = c.exit?;
            let v = (*v)?;
            let (length, _) = lane_extent(target, edge);
            let n = edge.outward();
            (v[0].hypot(v[1]) > 0.0).then(|| quotient([length * n[0], length * n[1]], v))
        })
        .collect();
    let moduli: Vec<f64> = ratios.iter().flatten().map(|r| r[0].hypot(r[1])).collect();
    if moduli.is_empty() {
        return ratios;
    }
    let mean = (moduli.iter().map(|m| m.ln()).sum::<f64>() / moduli.len() as f64).exp();
    ratios
        .into_iter()
        .map(|r| r.map(|r| [r[0] / mean, r[1] / mean]))
        .collect()
}

/// The path `(t, position)` at segment ends of a part started at rest at
/// `start` and played `periods` periods of `sm` under `v`'s physics (the
/// part moving); `None` when it loses contact.
pub(super) fn played_path(
    sm: &ScheduleMotion,
    v: &PlayOptions,
    start: [f64; 2],
    periods: u32,
) -> Option<Vec<(f64, [f64; 2])>> {
    use crate::dynamics::PartState;
    let player = v.moving_player(sm);
    let anchor = V2::from(start);
    let mut state = PartState::new(anchor, V2::zeros());
    let mut path: Vec<(f64, [f64; 2])> = vec![(0.0, start)];
    player
        .play_periods(&mut state, &anchor, 0, periods, |t, _, s| {
            path.push((t, [s.r.x, s.r.y]));
        })
        .ok()
        .map(|()| path)
}

/// Per class with an exit, the mean drift (m/s) of five parts started at
/// the region's centre and halfway to each edge, played [`LANE_PLAY_S`]
/// under `d`'s schedule at the class's friction: each part's displacement
/// from the end of its first period (the start-up transient) to the end,
/// over the time; `None` for a class without an exit or whose parts all
/// lose contact.
fn lane_drifts(target: &Target, d: &SortDesign) -> Result<Vec<Option<[f64; 2]>>> {
    use rayon::prelude::*;
    let sm = ScheduleMotion::from_schedule(&d.schedule)?;
    let periods = ((LANE_PLAY_S / sm.period()).ceil() as u32).max(2);
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let centre = [0.5 * (g.x[0] + g.x[1]), 0.5 * (g.y[0] + g.y[1])];
    let half = [0.25 * (g.x[1] - g.x[0]), 0.25 * (g.y[1] - g.y[0])];
    let starts = [[0.0, 0.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]
        .map(|u| [centre[0] + half[0] * u[0], centre[1] + half[1] * u[1]]);
    let segments = sm.segments().len();
    let mut out = Vec::new();
    for (i, class) in target.classes.iter().enumerate() {
        if class.exit.is_none() {
            out.push(None);
            continue;
        }
        let ct = target.class_target(i);
        let v = PlayOptions::from_settings(&ct.physics(&d.schedule.settings));
        let drifts: Vec<[f64; 2]> = starts
            .par_iter()
            .filter_map(|p| {
                let path = played_path(&sm, &v, *p, periods)?;
                let (t0, p0) = path[segments];
                let &(t1, p1) = path.last()?;
                Some([(p1[0] - p0[0]) / (t1 - t0), (p1[1] - p0[1]) / (t1 - t0)])
            })
            .collect();
        if drifts.is_empty() {
            out.push(None);
            continue;
        }
        let k = drifts.len() as f64;
        out.push(Some(
            drifts
                .iter()
                .fold([0.0; 2], |s, e| [s[0] + e[0] / k, s[1] + e[1] / k]),
        ));
    }
    Ok(out)
}

/// The time average over the last `period` (s) of the path `(t, position)`
/// recorded at segment ends, linear between them: the centre of the orbit
/// a settled part repeats every period. `None` for a path shorter than two
/// points.
fn orbit_centre(path: &[(f64, [f64; 2])], period: f64) -> Option<[f64; 2]> {
    let (&(t_end, _), _) = path.split_last()?;
    let from = t_end - period * (1.0 - 1e-9);
    let mut sum = [0.0; 2];
    let mut time = 0.0;
    for w in path.windows(2) {
        let ((t0, p0), (t1, p1)) = (w[0], w[1]);
        if t0 < from {
            continue;
        }
        let dt = t1 - t0;
        sum = [
            sum[0] + dt * 0.5 * (p0[0] + p1[0]),
            sum[1] + dt * 0.5 * (p0[1] + p1[1]),
        ];
        time += dt;
    }
    (time > 0.0).then(|| [sum[0] / time, sum[1] / time])
}

/// Per class, where parts started at and around its attractor settle under
/// `d`'s schedule at the class's friction, as an offset (m) from the
/// attractor (for a line, its normal part); `None` for a class without an
/// attractor or whose parts all lose contact.
fn settle_offsets(target: &Target, d: &SortDesign) -> Result<Vec<Option<[f64; 2]>>> {
    use rayon::prelude::*;
    let sm = ScheduleMotion::from_schedule(&d.schedule)?;
    let periods = ((AIM_PLAY_S / sm.period()).ceil() as u32).max(1);
    let mut out = Vec::new();
    for i in 0..target.classes.len() {
        let ct = target.class_target(i);
        let Some(a) = crate::request::Attractor::of(&ct.field) else {
            out.push(None);
            continue;
        };
        let (centre, normal) = match a {
            crate::request::Attractor::Point { center, .. } => (center, None),
            crate::request::Attractor::Line {
                point, direction, ..
            } => (point, Some([-direction[1], direction[0]])),
        };
        let v = PlayOptions::from_settings(&ct.physics(&d.schedule.settings));
        let starts = [[0.0, 0.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]]
            .map(|u| [centre[0] + AIM_SPREAD * u[0], centre[1] + AIM_SPREAD * u[1]]);
        let ends: Vec<Option<[f64; 2]>> = starts
            .par_iter()
            .map(|p| {
                played_path(&sm, &v, *p, periods).and_then(|path| orbit_centre(&path, sm.period()))
            })
            .collect();
        let kept: Vec<[f64; 2]> = ends.into_iter().flatten().collect();
        if kept.is_empty() {
            out.push(None);
            continue;
        }
        let k = kept.len() as f64;
        let m = kept
            .iter()
            .fold([0.0; 2], |s, e| [s[0] + e[0] / k, s[1] + e[1] / k]);
        let e = [m[0] - centre[0], m[1] - centre[1]];
        out.push(Some(match normal {
            None => e,
            Some(nv) => {
                let along = e[0] * nv[0] + e[1] * nv[1];
                [along * nv[0], along * nv[1]]
            }
        }));
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lanes() -> Target {
        Target::from_json_str(
            r#"{"grid": {"x": [-0.03, 0.03], "y": [-0.01, 0.01], "n": [13, 5]},
                "classes": [
                  {"name": "a", "friction": 0.2, "exit": "left", "field": {"kind": "trans", "direction": 180}},
                  {"name": "b", "friction": 0.45, "exit": "right", "field": {"kind": "trans"}}]}"#,
        )
        .unwrap()
    }

    /// If each class's drift is its target's vectors times a complex gain
    /// of its own (turned and scaled, unknown to the steering), one
    /// correction puts every drift on its lane (no across part) at equal
    /// crossing times, whatever the gains.
    #[test]
    fn one_steering_step_corrects_per_class_gains() {
        let t = lanes();
        let unit = [[-1.0, 0.0], [1.0, 0.0]];
        let polar = |m: f64, deg: f64| [m * deg.to_radians().cos(), m * deg.to_radians().sin()];
        for gains in [
            [polar(2.45e-3, -3.3), polar(2.9e-3, 1.7)],
            [polar(1e-3, 20.0), polar(4e-3, -12.0)],
        ] {
            let drift = |steer: &[[f64; 2]]| -> Vec<Option<[f64; 2]>> {
                (0..2)
                    .map(|i| Some(turn(turn(unit[i], steer[i]), gains[i])))
                    .collect()
            };
            let first = drift(&[[1.0, 0.0]; 2]);
            let r = steering(&t, &first);
            let steer: Vec<[f64; 2]> = r.iter().map(|r| turn([1.0, 0.0], r.unwrap())).collect();
            let after: Vec<[f64; 2]> = drift(&steer).into_iter().flatten().collect();
            for (v, u) in after.iter().zip(unit) {
                assert!(v[1].abs() < 1e-15, "{v:?}");
                assert!(v[0] * u[0] > 0.0, "{v:?}");
            }
            assert!((after[0][0].abs() / after[1][0].abs() - 1.0).abs() < 1e-12);
            // Corrected again, nothing changes.
            for c in steering(&t, &drift(&steer)).into_iter().flatten() {
                assert!((c[0] - 1.0).hypot(c[1]) < 1e-12, "{c:?}");
            }
        }
    }

    /// The unkept outlook of the μ 0.2 lane of `results/sort_lanes/`
    /// before steering, and of a drift along the lane.
    #[test]
    fn lane_outlook_of_a_drift() {
        let t = lanes();
        let (time, side) = lane_outlook(&t, Edge::Left, [-2.45e-3, 0.14e-3]);
        assert!((side - 0.06 * (0.14 / 2.45) / 0.04).abs() < 1e-12, "{side}");
        assert!(time.is_infinite());
        let (time, side) = lane_outlook(&t, Edge::Left, [-3e-3, 0.0]);
        assert_eq!(side, 0.0);
        assert!((time - LANE_SHARE * 0.06 / 3e-3).abs() < 1e-9, "{time}");
        assert!(lane_outlook(&t, Edge::Right, [-3e-3, 0.0]).0.is_infinite());
    }

    /// The keeping pull: −κ|v|y across the lane, κ = LANE_KEEP / W, zero
    /// on the axis.
    #[test]
    fn lane_kept_pulls_toward_the_axis() {
        let t = lanes();
        let v = [-3e-3, 0.0];
        assert_eq!(lane_kept(&t, Edge::Left, [0.01, 0.0], v), v);
        let k = lane_kept(&t, Edge::Left, [0.01, 0.005], v);
        let pull = LANE_KEEP / 0.02 * 3e-3 * 0.005;
        assert!((k[0] - v[0]).abs() < 1e-18);
        assert!((k[1] + pull).abs() < 1e-15, "{k:?}");
    }
}
