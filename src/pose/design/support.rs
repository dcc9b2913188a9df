//! A pose design played over the supports the part may really rest on.
//!
//! The paper's open problem: the support distribution is usually unknown.
//! A part file states one, and a design is judged on it; here the same
//! drops are played on other supports the part could have, and the design
//! is reported by its worst one.
//!
//! **Admissible supports.** A flat rigid part on a flat plate carries its
//! weight on its contacts, and their normal forces balance its weight's
//! moment only when the contacts' weighted centroid lies under its centre
//! of mass. A support model is therefore points p_j of the part (its body
//! frame, the centre of mass at the origin) with weights c_j ≥ 0 and
//! Σ c_j p_j = 0. Given base weights b_j on points whose convex hull holds
//! the origin inside, the admissible weights nearest to them in relative
//! entropy are the exponential tilt
//!
//! ```text
//! c_j = b_j exp(λ·p_j/R),   λ = argmin_λ Σ_j b_j exp(λ·p_j/R)
//! ```
//!
//! (R the part's radius): the objective is convex, its gradient is
//! Σ c_j p_j/R, so its minimiser puts the centroid at the origin, and it
//! has one exactly when the origin is inside the hull. Three points give
//! the barycentric weights, the only admissible ones.
//!
//! **The models** ([`support_models`]): the part file's support (as the
//! design plays it, [`crate::pose::DropPlay::samples`]); uniform over the
//! area (tilted onto the centre of mass when the file's support is not
//! uniform); 3 and 4 points at vertices of the polygon's convex hull (of
//! all such triangles and quadrilaterals holding the centre of mass, the
//! one whose least weight is largest: the steadiest tripod and table; the
//! hull's edge midpoints join the candidates where the vertices alone give
//! none that holds it with every point loaded, as for a triangle's 4 points
//! or a rectangle's 3);
//! and `random` distributions on the uniform support's points, base
//! weights independent unit exponentials (a uniformly random distribution
//! over the simplex) from a seeded stream, each tilted. With 20 random
//! ones these are the 24 models the design question asks about.
//!
//! **Play** ([`play_over_supports`]): the design's drops (the same starts,
//! [`crate::pose::drop_starts`] over the region inset by the part's radius,
//! and duration) played on each model's body, counted at the pose as the
//! design counts them ([`super::at_pose`]); the report lists the models
//! worst first.

use rayon::prelude::*;

use super::{at_pose, PoseTarget};
use crate::dynamics::{PlanarBody, V2};
use crate::error::{Error, Result};
use crate::part::{Part, PartFile, Support};
use crate::play::ScheduleMotion;
use crate::pose::{drop_starts, play_drops, DropPlay, Uniform, DROP_SAMPLES};
use crate::progress::ProgressMode;

/// Random admissible supports the design question asks about.
pub const RANDOM_SUPPORTS: usize = 20;

/// Hull vertices searched for the 3- and 4-point supports, at most (evenly
/// spaced along the hull when it has more).
const HULL_VERTICES: usize = 16;

/// The least weight (of mean 1) a hull support's point must carry before
/// the hull's edge midpoints are searched too.
const LEAST_SHARE: f64 = 0.05;

/// One support model: its name and the body the drops play.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportModel {
    /// What it is: "part file", "uniform", "3 hull points",
    /// "4 hull points", "random 1" …
    pub name: String,
    /// The body: the model's points and weights, centroid at the part's
    /// centre of mass.
    pub body: PlanarBody,
}

/// How a design's drops ended on one support model.
#[derive(Debug, Clone, PartialEq)]
pub struct SupportPlay {
    /// The model's name.
    pub name: String,
    /// Fraction of the drops ending at the pose.
    pub fraction: f64,
    /// Drops that lost contact (counted as not at the pose).
    pub lost: usize,
}

/// Weights c_j = b_j exp(λ·p_j/`scale`) whose centroid Σ c_j p_j is the
/// origin (module docs), normalised to mean 1; `None` when the origin is
/// not strictly inside the hull of the points with b_j > 0.
///
/// Damped Newton on the convex objective, stopped when the centroid is
/// within 1e-13 of `scale` from the origin (within [`ROUND_OFF`] where
/// round-off stops it).
fn tilt(points: &[V2], base: &[f64], scale: f64) -> Option<Vec<f64>> {
    let weights = |l: &V2| -> Vec<f64> {
        points
            .iter()
            .zip(base)
            .map(|(p, b)| b * (l.dot(p) / scale).exp())
            .collect()
    };
    let objective = |l: &V2| weights(l).iter().sum::<f64>();
    let mut l = V2::zeros();
    for _ in 0..100 {
        let w = weights(&l);
        let total: f64 = w.iter().sum();
        let mut g = V2::zeros();
        let mut h = nalgebra::Matrix2::zeros();
        for (p, c) in points.iter().zip(&w) {
            let q = p / scale;
            g += q * *c;
            h += q * q.transpose() * *c;
        }
        if !total.is_finite() || total <= 0.0 {
            return None;
        }
        if g.norm() <= 1e-13 * total {
            return Some(normalised(&w, total));
        }
        let step = -h.cholesky()?.solve(&g);
        let (f, slope) = (total, g.dot(&step));
        let mut t = 1.0;
        // Where the objective's round-off cannot resolve the step (near the
        // minimiser), the full Newton step is taken.
        let flat = -slope <= 1e-12 * f;
        while !flat && objective(&(l + step * t)) > f + 1e-4 * t * slope {
            t *= 0.5;
            if t < 1e-12 {
                // Round-off: the objective cannot resolve the step.
                return (g.norm() <= ROUND_OFF * total).then(|| normalised(&w, total));
            }
        }
        l += step * t;
    }
    let w = weights(&l);
    let total: f64 = w.iter().sum();
    let g = points
        .iter()
        .zip(&w)
        .fold(V2::zeros(), |a, (p, c)| a + p * (*c / scale));
    (g.norm() <= ROUND_OFF * total).then(|| normalised(&w, total))
}

/// Where round-off stops the tilt's Newton short of 1e-13 (its line
/// search, or its iterations, stall a little above it), a centroid within
/// this of `scale` from the origin is accepted ([`PlanarBody::centred`]
/// then moves the body by that much, 1e-12 m on a centimetre part).
const ROUND_OFF: f64 = 1e-10;

/// Weights `w` of sum `total` scaled to mean 1.
fn normalised(w: &[f64], total: f64) -> Vec<f64> {
    let mean = total / w.len() as f64;
    w.iter().map(|c| c / mean).collect()
}

/// The convex hull of `v`, counter-clockwise, without collinear points
/// (Andrew's monotone chain).
fn convex_hull(v: &[V2]) -> Vec<V2> {
    let mut pts = v.to_vec();
    pts.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    pts.dedup();
    if pts.len() < 3 {
        return pts;
    }
    let cross = |o: &V2, a: &V2, b: &V2| (a - o).perp(&(b - o));
    let mut hull: Vec<V2> = Vec::with_capacity(2 * pts.len());
    for pass in 0..2 {
        let start = hull.len();
        let ordered: Box<dyn Iterator<Item = &V2>> = if pass == 0 {
            Box::new(pts.iter())
        } else {
            Box::new(pts.iter().rev())
        };
        for p in ordered {
            while hull.len() >= start + 2
                && cross(&hull[hull.len() - 2], &hull[hull.len() - 1], p) <= 0.0
            {
                hull.pop();
            }
            hull.push(*p);
        }
        hull.pop();
    }
    hull
}

/// Every `k`-subset of `0..n` in lexicographic order.
fn subsets(n: usize, k: usize) -> Vec<Vec<usize>> {
    let mut out = Vec::new();
    let mut pick: Vec<usize> = (0..k).collect();
    if k > n {
        return out;
    }
    loop {
        out.push(pick.clone());
        let Some(i) = (0..k).rev().find(|&i| pick[i] < n - k + i) else {
            return out;
        };
        pick[i] += 1;
        for j in i + 1..k {
            pick[j] = pick[j - 1] + 1;
        }
    }
}

/// The `k` points among `candidates` whose admissible weights have the
/// largest least weight, with those weights and that least weight.
fn steadiest(candidates: &[V2], k: usize, scale: f64) -> Option<(Vec<V2>, Vec<f64>, f64)> {
    let mut best: Option<(Vec<V2>, Vec<f64>, f64)> = None;
    for pick in subsets(candidates.len(), k) {
        let points: Vec<V2> = pick.iter().map(|&i| candidates[i]).collect();
        let Some(w) = tilt(&points, &vec![1.0; k], scale) else {
            continue;
        };
        let least = w.iter().cloned().fold(f64::INFINITY, f64::min);
        if best.as_ref().is_none_or(|b| least > b.2) {
            best = Some((points, w, least));
        }
    }
    best
}

/// The `k`-point hull support (module docs): `k` of the hull's vertices
/// (at most [`HULL_VERTICES`] of them) whose admissible weights have the
/// largest least weight; where no such choice gives every point at least
/// [`LEAST_SHARE`] (a triangle has no 4 vertices; a rectangle's centre of
/// mass lies on the diagonal of any 3 of its corners), the midpoints of
/// the hull's edges are candidates too.
fn hull_support(part: &Part, k: usize) -> Option<(Vec<V2>, Vec<f64>)> {
    let hull = convex_hull(&part.polygon);
    let every = hull.len().div_ceil(HULL_VERTICES).max(1);
    let hull: Vec<V2> = hull.into_iter().step_by(every).collect();
    let scale = part.radius();
    let vertices = steadiest(&hull, k, scale).filter(|b| b.2 >= LEAST_SHARE);
    let best = vertices.or_else(|| {
        let mut with_edges = hull.clone();
        let n = hull.len();
        with_edges.extend((0..n).map(|i| 0.5 * (hull[i] + hull[(i + 1) % n])));
        steadiest(&with_edges, k, scale)
    });
    best.map(|(p, w, _)| (p, w))
}

/// A body of admissible `points` and `weights` (centroid at the origin to
/// round-off; [`PlanarBody::centred`] removes that round-off).
fn body(points: &[V2], weights: &[f64]) -> PlanarBody {
    PlanarBody::centred(points, weights).0
}

/// The support models of `part` (module docs): the part file's, uniform,
/// 3 and 4 hull points, and `random` seeded random admissible ones.
///
/// # Errors
/// A model that cannot be made admissible (a part whose centre of mass is
/// not inside the hull of a model's points), naming it.
///
/// ```
/// use platefield::pose::design::support::support_models;
/// use platefield::part::Part;
/// let part = Part::load(std::path::Path::new("targets/parts/bracket.json"))?;
/// let models = support_models(&part, 2, 1)?;
/// assert_eq!(models.len(), 6);
/// assert_eq!(models[2].name, "3 hull points");
/// for m in &models {
///     // Every model's weighted centroid is the part's centre of mass.
///     let k = m.body.points().len() as f64;
///     let c = m.body.points().iter().zip(m.body.weights()).fold(
///         platefield::dynamics::V2::zeros(),
///         |a, (p, w)| a + p * (*w / k),
///     );
///     assert!(c.norm() < 1e-12, "{}: {c:?}", m.name);
/// }
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn support_models(part: &Part, random: usize, seed: u64) -> Result<Vec<SupportModel>> {
    let scale = part.radius();
    let refused = |name: &str| {
        Error::invalid(
            "part.support",
            format!("the {name} support cannot hold the part's centre of mass over its points (it lies outside their hull)"),
        )
    };
    let own = part
        .coarse_body(DROP_SAMPLES)
        .map_or_else(|| part.body.clone(), |(b, _)| b);
    let mut models = vec![SupportModel {
        name: "part file".into(),
        body: own,
    }];
    let uniform = Part::new(PartFile {
        name: part.name.clone(),
        polygon: part.polygon.iter().map(|p| [p.x, p.y]).collect(),
        support: Support::Uniform {
            samples: DROP_SAMPLES,
        },
        friction: part.friction,
    })?;
    // The uniform part's body is centred on the area's centroid, at
    // `origin` in this part's body frame.
    let grid: Vec<V2> = uniform
        .body
        .points()
        .iter()
        .map(|p| p + uniform.origin)
        .collect();
    let flat = tilt(&grid, uniform.body.weights(), scale).ok_or_else(|| refused("uniform"))?;
    models.push(SupportModel {
        name: "uniform".into(),
        body: body(&grid, &flat),
    });
    for k in [3usize, 4] {
        let name = format!("{k} hull points");
        let (points, weights) = hull_support(part, k).ok_or_else(|| refused(&name))?;
        models.push(SupportModel {
            name,
            body: body(&points, &weights),
        });
    }
    let mut stream = Uniform::new(seed);
    for i in 0..random {
        let base: Vec<f64> = grid.iter().map(|_| -(1.0 - stream.next()).ln()).collect();
        let name = format!("random {}", i + 1);
        let weights = tilt(&grid, &base, scale).ok_or_else(|| refused(&name))?;
        models.push(SupportModel {
            name,
            body: body(&grid, &weights),
        });
    }
    Ok(models)
}

/// Plays the first `drops` of the design's drops (the starts of
/// [`crate::pose::drop_starts`] over the region inset by the part's
/// radius) with `play` on every model, and counts those ending at the
/// pose target's pose; the models worst first (ties in the given order).
/// Progress goes to stderr when the estimate is 10 s or more
/// ([`crate::pose::drops_estimate`]).
///
/// ```no_run
/// use platefield::pose::design::support::{play_over_supports, support_models};
/// use platefield::pose::design::PoseTarget;
/// use platefield::play::ScheduleMotion;
/// use platefield::pose::DropPlay;
/// use platefield::schedule::Schedule;
/// use std::path::Path;
/// let req = PoseTarget::load(Path::new("targets/pose_bracket.json"))?.unwrap();
/// let schedule = Schedule::load(Path::new("results/poses/bracket/schedule.json"))?;
/// let sm = ScheduleMotion::from_schedule(&schedule)?;
/// let play = DropPlay::new(&schedule.settings, 120.0);
/// let models = support_models(&req.part, 20, 1)?;
/// let worst = &play_over_supports(&req, &sm, &play, 100, &models)[0];
/// println!("worst support: {} ({:.0} % at the pose)", worst.name, 100.0 * worst.fraction);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn play_over_supports(
    req: &PoseTarget,
    sm: &ScheduleMotion,
    play: &DropPlay,
    drops: usize,
    models: &[SupportModel],
) -> Vec<SupportPlay> {
    let starts = drop_starts(&req.region.inset(req.part.radius()), drops);
    let n = req.part.symmetry();
    let plays = (req, sm, play, drops * models.len());
    let mut out: Vec<SupportPlay> = super::watched_play(
        "pose drops over supports",
        plays,
        ProgressMode::Quiet,
        || {
            models
                .par_iter()
                .map(|m| {
                    let runs = play_drops(sm, &m.body, &starts, play);
                    let lost = runs.iter().filter(|r| r.is_err()).count();
                    let at = runs
                        .iter()
                        .flatten()
                        .filter(|end| at_pose(&end.pose, &req.pose, n))
                        .count();
                    SupportPlay {
                        name: m.name.clone(),
                        fraction: at as f64 / drops.max(1) as f64,
                        lost,
                    }
                })
                .collect()
        },
    );
    out.sort_by(|a, b| a.fraction.total_cmp(&b.fraction));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The tilt of three points is their barycentric weights (equal for a
    /// triangle centred on the origin); none when the origin is outside.
    #[test]
    fn tilt_gives_the_admissible_weights() {
        let tri = [V2::new(-1.0, -1.0), V2::new(2.0, -1.0), V2::new(-1.0, 2.0)];
        let w = tilt(&tri, &[1.0; 3], 1.0).unwrap();
        for c in &w {
            assert!((c - 1.0).abs() < 1e-12, "{w:?}");
        }
        // The origin at barycentric (1/2, 1/4, 1/4): weights of mean 1.
        let tri = [V2::new(-1.0, -1.0), V2::new(3.0, -1.0), V2::new(-1.0, 3.0)];
        let w = tilt(&tri, &[1.0; 3], 3.0).unwrap();
        for (c, want) in w.iter().zip([1.5, 0.75, 0.75]) {
            assert!((c - want).abs() < 1e-12, "{w:?}");
        }
        let outside = [V2::new(1.0, 1.0), V2::new(2.0, 1.0), V2::new(1.0, 2.0)];
        assert!(tilt(&outside, &[1.0; 3], 1.0).is_none());
    }

    /// The hull of an L drops its reflex vertex; subsets count C(n, k).
    #[test]
    fn hull_and_subsets() {
        let l = [
            V2::new(0.0, 0.0),
            V2::new(3.0, 0.0),
            V2::new(3.0, 1.0),
            V2::new(1.0, 1.0),
            V2::new(1.0, 3.0),
            V2::new(0.0, 3.0),
        ];
        let h = convex_hull(&l);
        assert_eq!(h.len(), 5);
        assert!(!h.contains(&V2::new(1.0, 1.0)));
        assert_eq!(subsets(5, 3).len(), 10);
        assert_eq!(subsets(16, 4).len(), 1820);
    }
}

#[cfg(test)]
#[path = "../../../tests/unit/pose_support.rs"]
mod support_tests;
