//! A grid's points grouped by the motion's [`Invariance`]: one simulated
//! point per group (its *representative*), the others mapped from it.

use crate::motion::Invariance;

/// The grid points grouped into families that see the same motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Orbits {
    /// The grid index of each family's representative (its lowest index),
    /// in increasing order.
    pub representatives: Vec<usize>,
    /// For each grid point: its family (an index into `representatives`)
    /// and the rotation (cos θ, sin θ) that takes the representative's
    /// vector to the point's (identity but for [`Invariance::About`]).
    pub members: Vec<(usize, [f64; 2])>,
}

impl Orbits {
    /// Groups `points` by `invariance`. Two points belong together when
    /// their invariant coordinate (the offset across the lines for
    /// [`Invariance::Along`], the radius for [`Invariance::About`]) agrees
    /// within 1e-12 of the points' scale: the same point of the physics up
    /// to the round-off of the grid's coordinates.
    pub fn of(points: &[[f64; 2]], invariance: Invariance) -> Orbits {
        let Some((keys, tolerance)) = keys(points, invariance) else {
            return Orbits::identity(points.len());
        };
        let mut keyed: Vec<(f64, usize)> = keys.into_iter().zip(0..).collect();
        keyed.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let mut family_of = vec![0usize; points.len()];
        let mut firsts: Vec<usize> = Vec::new();
        let mut start = 0;
        for length in run_lengths(keyed.iter().map(|k| k.0), tolerance) {
            let run = &keyed[start..start + length];
            let first = run.iter().map(|k| k.1).min().unwrap_or(0);
            for k in run {
                family_of[k.1] = firsts.len();
            }
            firsts.push(first);
            start += length;
        }
        // Number the families by their representatives' grid order.
        let mut order: Vec<usize> = (0..firsts.len()).collect();
        order.sort_by_key(|&f| firsts[f]);
        let mut renumber = vec![0usize; firsts.len()];
        for (new, &old) in order.iter().enumerate() {
            renumber[old] = new;
        }
        let representatives: Vec<usize> = order.iter().map(|&f| firsts[f]).collect();
        let members = points
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let family = renumber[family_of[i]];
                let rotation = match invariance {
                    Invariance::About(c) => turn(c, &points[representatives[family]], p),
                    _ => [1.0, 0.0],
                };
                (family, rotation)
            })
            .collect();
        Orbits {
            representatives,
            members,
        }
    }

    /// The number of families [`Orbits::of`] finds, without the mapping
    /// (what a work estimate needs, on grids of up to a million points).
    pub(crate) fn count(points: &[[f64; 2]], invariance: Invariance) -> usize {
        let Some((mut keys, tolerance)) = keys(points, invariance) else {
            return points.len();
        };
        keys.sort_unstable_by(f64::total_cmp);
        run_lengths(keys.into_iter(), tolerance).len()
    }

    /// Every point its own family.
    fn identity(n: usize) -> Orbits {
        Orbits {
            representatives: (0..n).collect(),
            members: (0..n).map(|i| (i, [1.0, 0.0])).collect(),
        }
    }

    /// The vector at grid point `i` from its representative's `v`.
    #[inline]
    pub(crate) fn map(&self, i: usize, v: [f64; 2]) -> [f64; 2] {
        let [c, s] = self.members[i].1;
        if s == 0.0 && c == 1.0 {
            v
        } else {
            [c * v[0] - s * v[1], s * v[0] + c * v[1]]
        }
    }

    /// Number of grid points in each family, by family.
    pub(crate) fn sizes(&self) -> Vec<usize> {
        let mut n = vec![0; self.representatives.len()];
        for (f, _) in &self.members {
            n[*f] += 1;
        }
        n
    }
}

/// The families in `sorted` keys: runs of keys within `tolerance` of the
/// run's first, as run lengths.
fn run_lengths(sorted: impl Iterator<Item = f64>, tolerance: f64) -> Vec<usize> {
    let mut lengths: Vec<usize> = Vec::new();
    let mut first = f64::NEG_INFINITY;
    for k in sorted {
        match lengths.last_mut() {
            Some(n) if k - first <= tolerance => *n += 1,
            _ => {
                lengths.push(1);
                first = k;
            }
        }
    }
    lengths
}

/// Each point's invariant coordinate under `invariance` (module docs of
/// [`Orbits::of`]) and the tolerance within which two are one; `None`
/// when no two points are known to move alike.
fn keys(points: &[[f64; 2]], invariance: Invariance) -> Option<(Vec<f64>, f64)> {
    let key = |p: &[f64; 2]| match invariance {
        Invariance::Uniform => 0.0,
        Invariance::Along(e) => p[1] * e[0] - p[0] * e[1],
        Invariance::About(c) => (p[0] - c[0]).hypot(p[1] - c[1]),
        Invariance::None => f64::NAN,
    };
    let centre = match invariance {
        Invariance::None => return None,
        Invariance::About(c) => c[0].abs().max(c[1].abs()),
        Invariance::Uniform | Invariance::Along(_) => 0.0,
    };
    let scale = points
        .iter()
        .map(|p| p[0].abs().max(p[1].abs()))
        .fold(0.0, f64::max)
        + centre;
    Some((points.iter().map(key).collect(), 1e-12 * scale))
}

/// (cos θ, sin θ) of the turn about `c` from `from` to `to`; the identity
/// when either is at the centre.
fn turn(c: [f64; 2], from: &[f64; 2], to: &[f64; 2]) -> [f64; 2] {
    let a = [from[0] - c[0], from[1] - c[1]];
    let b = [to[0] - c[0], to[1] - c[1]];
    let (ra, rb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
    if ra == 0.0 || rb == 0.0 || a == b {
        return [1.0, 0.0];
    }
    let (ua, ub) = ([a[0] / ra, a[1] / ra], [b[0] / rb, b[1] / rb]);
    [ua[0] * ub[0] + ua[1] * ub[1], ua[0] * ub[1] - ua[1] * ub[0]]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::field::Grid;

    #[test]
    fn families_of_the_default_grid() {
        let points = Grid::DEFAULT.points();
        let count = |inv| {
            let n = Orbits::of(&points, inv).representatives.len();
            assert_eq!(Orbits::count(&points, inv), n);
            n
        };
        assert_eq!(count(Invariance::None), 441);
        assert_eq!(count(Invariance::Uniform), 1);
        // 21 columns x = const.
        assert_eq!(count(Invariance::Along([0.0, 1.0])), 21);
        // The distinct values of i² + j² for |i|, |j| ≤ 10.
        assert_eq!(count(Invariance::About([0.0, 0.0])), 61);
    }

    #[test]
    fn turns_take_representatives_onto_members() {
        let points = Grid::DEFAULT.points();
        let o = Orbits::of(&points, Invariance::About([0.0, 0.0]));
        assert_eq!(o.sizes().iter().sum::<usize>(), 441);
        for (i, p) in points.iter().enumerate() {
            let (f, _) = o.members[i];
            let r = points[o.representatives[f]];
            // The representative's position vector turns onto the point's.
            let q = o.map(i, r);
            assert!((q[0] - p[0]).abs() < 1e-15 && (q[1] - p[1]).abs() < 1e-15);
        }
    }
}
