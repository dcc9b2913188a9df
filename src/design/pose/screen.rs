//! Spin candidates judged by play: probes from spread starts on the
//! centred spun motion, their ends clustered.
//!
//! **Why.** The lifted field of a spun sink ([`super::spin`]) is rough:
//! on the bracket's kept spin (1200 rad/s² at −0.8 rad) it gave one
//! stable pose, yet 26 of 100 played drops came to rest at a second pose
//! 130° from the asked one (at rest there: the same pose 20 s before the
//! end, `docs/parts.md`). A second played attractor is a property of the
//! motion, not of its placement (a placement turns and shifts the whole
//! physics, [`super::placement`]), so it is measured once per candidate on
//! the centred motion.
//!
//! **Measure.** [`PROBES`] drops at [`probe_starts`] (a 4 × 4 grid over the
//! region inset by the part's radius, angles stepped by the golden angle)
//! play [`PROBE_S`] each; an end's cluster is the ends within
//! [`super::TOL_MM`] and [`super::TOL_DEG`] of it (modulo the part's
//! symmetry); the candidate's score is the largest cluster's share of the
//! probes and its played pose that cluster's mean. A drop lost, at a
//! second pose or still moving after [`PROBE_S`] counts against it.

use super::search::{pose_error, wrap_symmetric};
use super::spin::{spun, Spin};
use super::PoseRequest;
use crate::dynamics::V2;
use crate::error::Result;
use crate::play::ScheduleMotion;
use crate::pose::{play_part, DropPlay, Pose, Region};
use crate::schedule::Schedule;

/// Probe drops per candidate.
pub const PROBES: usize = 16;
/// Seconds each probe plays.
pub const PROBE_S: f64 = 60.0;

/// A candidate judged by play.
#[derive(Debug, Clone, PartialEq)]
pub struct Screened {
    /// The spin.
    pub spin: Spin,
    /// Share of the probes in the largest cluster of ends (0 … 1).
    pub score: f64,
    /// That cluster's mean pose on the centred motion, `None` when every
    /// probe lost contact.
    pub pose: Option<Pose>,
}

/// The probe starts over `region` (module docs): a 4 × 4 grid of centres
/// at the cell middles, the k-th turned by k golden angles.
///
/// ```
/// use platefield::design::pose::screen::{probe_starts, PROBES};
/// use platefield::pose::Region;
/// let s = probe_starts(&Region { x: [-0.02, 0.02], y: [-0.02, 0.02] });
/// assert_eq!(s.len(), PROBES);
/// assert!((s[0].r.x + 0.015).abs() < 1e-15 && s[0].theta == 0.0);
/// ```
pub fn probe_starts(region: &Region) -> Vec<Pose> {
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    (0..PROBES)
        .map(|k| {
            let (i, j) = ((k % 4) as f64, (k / 4) as f64);
            let r = region.at((i + 0.5) / 4.0, (j + 0.5) / 4.0);
            Pose {
                r,
                theta: crate::pose::wrap(k as f64 * golden),
            }
        })
        .collect()
}

/// The largest cluster of `ends` (module docs): its share of `total` and
/// its mean pose (θ averaged as offsets modulo the symmetry `n` from the
/// cluster's seed).
///
/// ```
/// use platefield::design::pose::screen::largest_cluster;
/// use platefield::pose::Pose;
/// let ends = [Pose::new(0.0, 0.0, 0.0), Pose::new(0.0002, 0.0, 0.02), Pose::new(0.01, 0.0, 2.0)];
/// let (share, pose) = largest_cluster(&ends, 1, 4).unwrap();
/// assert_eq!(share, 0.5);
/// assert!((pose.r.x - 0.0001).abs() < 1e-15 && (pose.theta - 0.01).abs() < 1e-15);
/// ```
pub fn largest_cluster(ends: &[Pose], n: usize, total: usize) -> Option<(f64, Pose)> {
    let near = |a: &Pose, b: &Pose| {
        let (d, t) = pose_error(a, b, n);
        1e3 * d <= super::TOL_MM && t.abs().to_degrees() <= super::TOL_DEG
    };
    let members = |seed: &Pose| ends.iter().filter(|e| near(e, seed)).collect::<Vec<_>>();
    // The first seed with the most members (ties to the earlier drop).
    let seed = ends
        .iter()
        .enumerate()
        .max_by(|a, b| {
            let (ca, cb) = (members(a.1).len(), members(b.1).len());
            ca.cmp(&cb).then(b.0.cmp(&a.0))
        })?
        .1;
    let m = members(seed);
    let k = m.len() as f64;
    let (r, dt) = m.iter().fold((V2::zeros(), 0.0), |(r, dt), e| {
        (r + e.r, dt + wrap_symmetric(e.theta - seed.theta, n))
    });
    let pose = Pose {
        r: r / k,
        theta: crate::pose::wrap(seed.theta + dt / k),
    };
    Some((k / total.max(1) as f64, pose))
}

/// `spin` added to the centred `sink` and judged by play (module docs).
///
/// # Errors
/// `sink` is not one six-signal motion.
pub fn screen(req: &PoseRequest, sink: &Schedule, spin: Spin) -> Result<Screened> {
    let schedule = spun(sink, spin)?;
    let sm = ScheduleMotion::from_schedule(&schedule)?;
    let starts = probe_starts(&req.region.inset(req.part.radius()));
    let play = DropPlay::new(&schedule.settings, PROBE_S);
    let ends: Vec<Pose> = play_part(&req.part, &sm, &starts, &play)
        .into_iter()
        .filter_map(|run| run.ok().map(|(end, _)| end.pose))
        .collect();
    let best = largest_cluster(&ends, req.part.symmetry(), starts.len());
    Ok(Screened {
        spin,
        score: best.map_or(0.0, |b| b.0),
        pose: best.map(|b| b.1),
    })
}
