//! A part's poses in one field: equilibria, stability and basin fractions
//! from random drops integrated along the lifted field.

use super::continua::Continuum;
use super::equilibria::{rests, settle_on, wrap, End, Equilibrium, Region};
use super::lifted::{LiftedField, PointField, Pose};
use crate::part::Part;

/// Most drops per analysis.
pub const MAX_DROPS: usize = 100_000;

/// What [`analyse`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseAnalysis {
    /// Every isolated equilibrium found, sorted by θ.
    pub equilibria: Vec<Equilibrium>,
    /// The continua of rest (or of endless turning) found
    /// ([`crate::pose::rests`]).
    pub continua: Vec<Continuum>,
    /// Fraction of the drops that ended on each continuum.
    pub continuum_basins: Vec<f64>,
    /// Per drop: the index in `continua` of the continuum it ended on.
    pub continuum_ends: Vec<Option<usize>>,
    /// Fraction of the drops that settled at each equilibrium (0 for the
    /// unstable ones).
    pub basins: Vec<f64>,
    /// Fraction of the drops that left the region or did not settle (at
    /// an equilibrium or on a continuum).
    pub unsettled: f64,
    /// Per drop ([`drop_starts`] order): the index in `equilibria` of the
    /// stable pose it settled at, `None` when it did not.
    pub ends: Vec<Option<usize>>,
    /// Drops played.
    pub drops: usize,
    /// The region (m).
    pub region: Region,
    /// Where the drops' centres start: the region inset by the part's
    /// radius (the whole part on the region), or its centre line where the
    /// region is narrower than the part.
    pub starts: Region,
}

/// A deterministic uniform stream in [0, 1) (64-bit LCG, fixed seed).
pub(crate) struct Uniform(u64);

impl Uniform {
    pub(crate) fn new(seed: u64) -> Uniform {
        Uniform(seed)
    }

    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// `drops` random start poses: centre uniform over `region`, θ uniform
/// (a fixed seed: the same starts for the same region and count).
pub fn drop_starts(region: &Region, drops: usize) -> Vec<Pose> {
    let mut rng = Uniform::new(28);
    (0..drops)
        .map(|_| Pose {
            r: region.at(rng.next(), rng.next()),
            theta: wrap(std::f64::consts::TAU * rng.next()),
        })
        .collect()
}

/// Equilibria of `part` in `field` over `region` and the basin of each
/// stable one from `drops` random drops ([`drop_starts`] over the region
/// inset by the part's radius, so that the dropped part lies on it;
/// integrated along the lifted field, [`super::equilibria::settle`]).
///
/// ```
/// use platefield::dynamics::V2;
/// use platefield::part::Part;
/// use platefield::pose::{analyse, Region};
/// let part = Part::load(std::path::Path::new("targets/parts/rectangle.json"))?;
/// let sink = |p: V2| V2::new(-0.3 * p.x, -p.y);
/// let region = Region { x: [-0.04, 0.04], y: [-0.04, 0.04] };
/// let a = analyse(&part, &sink, region, 200);
/// let stable: f64 = a.basins.iter().sum();
/// assert!((stable + a.unsettled - 1.0).abs() < 1e-12 && a.unsettled == 0.0);
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn analyse(part: &Part, field: &dyn PointField, region: Region, drops: usize) -> PoseAnalysis {
    analyse_with(part, field, region, drops, &|| {})
}

/// [`analyse`], calling `done` after each drop has settled (from the
/// worker threads: progress).
pub(crate) fn analyse_with(
    part: &Part,
    field: &dyn PointField,
    region: Region,
    drops: usize,
    done: &(dyn Fn() + Sync),
) -> PoseAnalysis {
    use rayon::prelude::*;
    let lifted = LiftedField::new(field, &part.body);
    let found = rests(&lifted, &region);
    let eq = found.equilibria;
    let index: Vec<usize> = (0..eq.len()).filter(|&i| eq[i].stable).collect();
    let stable: Vec<Equilibrium> = index.iter().map(|&i| eq[i]).collect();
    let starts = region.inset(part.radius());
    // Each drop is independent: the same ends on any number of threads.
    let outcomes: Vec<Option<End>> = drop_starts(&starts, drops)
        .par_iter()
        .map(|start| {
            let end = settle_on(&lifted, *start, &stable, &found.continua, &region);
            done();
            end
        })
        .collect();
    let ends: Vec<Option<usize>> = outcomes
        .iter()
        .map(|e| match e {
            Some(End::At(k)) => Some(index[*k]),
            _ => None,
        })
        .collect();
    let continuum_ends: Vec<Option<usize>> = outcomes
        .iter()
        .map(|e| match e {
            Some(End::On(k)) => Some(*k),
            _ => None,
        })
        .collect();
    let n = drops.max(1) as f64;
    let fraction = |ends: &[Option<usize>], i: usize| {
        ends.iter().filter(|e| **e == Some(i)).count() as f64 / n
    };
    let basins = (0..eq.len()).map(|i| fraction(&ends, i)).collect();
    let continuum_basins = (0..found.continua.len())
        .map(|i| fraction(&continuum_ends, i))
        .collect();
    let lost = outcomes.iter().filter(|e| e.is_none()).count();
    PoseAnalysis {
        equilibria: eq,
        continua: found.continua,
        continuum_basins,
        continuum_ends,
        basins,
        unsettled: lost as f64 / n,
        ends,
        drops,
        region,
        starts,
    }
}
