//! A sort's swarm (see the parent module's **Judged by playing**): where
//! its parts start, where a lane's part first leaves the region, and the
//! time by which a share of the parts has arrived. The design ranks its
//! refits by them and `crate::verify::sort_play` measures its plays by
//! them.

use crate::request::{Edge, Target};

/// Swarm start points per axis (over the target grid's box).
pub(crate) const SORT_STARTS: [usize; 2] = [9, 5];

/// [`SORT_STARTS`] points over the box of the target's grid (for lanes,
/// at its cells' centres).
pub(crate) fn swarm_starts(target: &Target) -> Vec<[f64; 2]> {
    let g = target
        .grid
        .as_ref()
        .expect("a classes target has a grid (validated)");
    let axis = |r: [f64; 2], n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| r[0] + (r[1] - r[0]) * i as f64 / (n - 1) as f64)
            .collect()
    };
    // A lane's parts start strictly inside the region (at the centres of
    // SORT_STARTS cells per axis): one started on an edge would count as
    // leaving through it at its first move outward.
    let lanes = target.classes.iter().any(|c| c.exit.is_some());
    let inside = |r: [f64; 2], n: usize| -> Vec<f64> {
        (0..n)
            .map(|i| r[0] + (r[1] - r[0]) * (i as f64 + 0.5) / n as f64)
            .collect()
    };
    let (xs, ys) = if lanes {
        (inside(g.x, SORT_STARTS[0]), inside(g.y, SORT_STARTS[1]))
    } else {
        (axis(g.x, SORT_STARTS[0]), axis(g.y, SORT_STARTS[1]))
    };
    ys.iter()
        .flat_map(|&y| xs.iter().map(move |&x| [x, y]))
        .collect()
}

/// Where a part first leaves the box `x` × `y`: the edge and the time (s),
/// from its `path` (positions at the start and after every segment, the
/// segments of `durations` (s) played in turn), the crossing interpolated
/// along the straight move between two; `None` when it stays inside.
pub(crate) fn first_exit(
    path: &[[f64; 2]],
    durations: &[f64],
    x: [f64; 2],
    y: [f64; 2],
) -> Option<(Edge, f64)> {
    let mut t = 0.0;
    for (k, w) in path.windows(2).enumerate() {
        let dt = durations[k % durations.len()];
        if let Some((e, s)) = Edge::crossing(w[0], w[1], x, y) {
            return Some((e, t + s * dt));
        }
        t += dt;
    }
    None
}

/// The time by which `share` of the parts whose convergence times are
/// `arrivals` have converged: the ⌈share·n⌉-th smallest; `None` when fewer
/// converge.
pub(crate) fn time_to_share(arrivals: &[Option<f64>], share: f64) -> Option<f64> {
    let mut t: Vec<f64> = arrivals.iter().flatten().copied().collect();
    t.sort_by(f64::total_cmp);
    let k = ((share * arrivals.len() as f64) - 1e-9).ceil().max(1.0) as usize;
    t.get(k - 1).copied()
}
