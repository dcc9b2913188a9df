//! A seeded family of random parts, each with a pose asked of it: what
//! pose design is measured on, beyond the shipped parts.
//!
//! Every member is a part file's polygon with the shipped parts' support
//! (uniform, `DEFAULT_SAMPLES` cells), a friction μ drawn
//! uniformly from [`crate::request::family::NOMINAL_MU`] (the target
//! family's), and a pose: the centre of mass at a uniform angle and a
//! distance uniform in [0, [`crate::request::family::MAX_OFFSET`]] from the
//! plate centre (the target family's sink centres), the part's x axis at a
//! uniform angle in [−180°, 180°). The kinds, in this order and in these
//! proportions of the family (of 8: 3, 3, 2):
//!
//! | kind | drawn |
//! |---|---|
//! | polygon | 3 to 7 vertices (uniform) about the origin, the k-th of n at angle 2π(k + 0.1 + 0.8u)/n and radius R(0.5 + 0.5u), R uniform in [0.8, 1.6] cm: a star-shaped outline, convex or not, generically without symmetry |
//! | bracket | an L: outer width uniform in [1.5, 3] cm, height in [1, 2.5] cm, each arm 15–35 % of the other side thick |
//! | rectangle | length uniform in [1.5, 3.5] cm, width 20–70 % of it (a 180° symmetry: no spin) |
//!
//! The sizes span the shipped parts' (2–3 cm across) by about a factor of
//! two either way while leaving the region (±4 cm) room for the part at
//! any drawn pose; nothing is tuned to what a design achieves.

use super::{Part, PartFile, Support, DEFAULT_SAMPLES};
use crate::error::Result;
use crate::request::family::{MAX_OFFSET, NOMINAL_MU};
use crate::rng::SplitMix64;
use crate::scene::FrictionSpec;

/// The kinds of a family, in order, with their shares of 8.
pub const KINDS: [(&str, usize); 3] = [("polygon", 3), ("bracket", 3), ("rectangle", 2)];

/// `count` random parts from `seed`, each with the pose (x m, y m, θ°)
/// asked of it (module documentation): the kinds in [`KINDS`]' proportions
/// (rounded, each kind at least once when `count` ≥ 3), named
/// `<kind>_<k>`.
///
/// # Errors
/// None for the drawn outlines (each is a simple polygon); the part
/// checks' own otherwise.
///
/// ```
/// use platefield::part::family::family;
///
/// let parts = family(48, 8)?;
/// assert_eq!(parts.len(), 8);
/// assert_eq!(parts[0].0.name, "polygon_0");
/// assert_eq!(parts[7].0.symmetry(), 2); // a rectangle
/// assert!(parts.iter().all(|(_, pose)| pose[0].hypot(pose[1]) <= 0.015));
/// assert_eq!(family(48, 8)?, parts); // seeded
/// # Ok::<(), platefield::Error>(())
/// ```
pub fn family(seed: u64, count: usize) -> Result<Vec<(Part, [f64; 3])>> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::with_capacity(count);
    for (kind, n) in counts(count) {
        for k in 0..n {
            let polygon = match kind {
                "polygon" => star(&mut rng),
                "bracket" => bracket(&mut rng),
                _ => rectangle(&mut rng),
            };
            let mu = NOMINAL_MU[0] + (NOMINAL_MU[1] - NOMINAL_MU[0]) * rng.uniform();
            let part = Part::new(PartFile {
                name: format!("{kind}_{k}"),
                polygon,
                support: Support::Uniform {
                    samples: DEFAULT_SAMPLES,
                },
                friction: FrictionSpec::uniform(mu),
            })?;
            let (at, far) = (
                std::f64::consts::TAU * rng.uniform(),
                MAX_OFFSET * rng.uniform(),
            );
            let theta = 180.0 * rng.symmetric();
            out.push((part, [far * at.cos(), far * at.sin(), theta]));
        }
    }
    Ok(out)
}

/// Members per kind for a family of `count`: [`KINDS`]' shares scaled
/// and rounded, the rounding's remainder to the first kinds, each kind at
/// least once when there is room.
fn counts(count: usize) -> Vec<(&'static str, usize)> {
    let total: usize = KINDS.iter().map(|k| k.1).sum();
    let mut n: Vec<usize> = KINDS
        .iter()
        .map(|k| {
            let share = (k.1 * count) as f64 / total as f64;
            (share.floor() as usize).max(usize::from(count >= KINDS.len()))
        })
        .collect();
    let kinds = n.len();
    let mut i = 0;
    while n.iter().sum::<usize>() < count {
        n[i % kinds] += 1;
        i += 1;
    }
    while n.iter().sum::<usize>() > count {
        let last = n.iter().rposition(|&v| v > 0).unwrap_or(0);
        n[last] -= 1;
    }
    KINDS.iter().map(|k| k.0).zip(n).collect()
}

/// A star-shaped polygon (module documentation).
fn star(rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    let n = 3 + (rng.uniform() * 5.0) as usize;
    let size = 0.008 + 0.008 * rng.uniform();
    (0..n)
        .map(|k| {
            let a = std::f64::consts::TAU * (k as f64 + 0.1 + 0.8 * rng.uniform()) / n as f64;
            let r = size * (0.5 + 0.5 * rng.uniform());
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

/// An L bracket (module documentation).
fn bracket(rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    let w = 0.015 + 0.015 * rng.uniform();
    let h = 0.01 + 0.015 * rng.uniform();
    let arm = |side: f64, u: f64| side * (0.15 + 0.2 * u);
    let (t_low, t_side) = (arm(h, rng.uniform()), arm(w, rng.uniform()));
    vec![
        [0.0, 0.0],
        [w, 0.0],
        [w, t_low],
        [t_side, t_low],
        [t_side, h],
        [0.0, h],
    ]
}

/// A rectangle about the origin (module documentation).
fn rectangle(rng: &mut SplitMix64) -> Vec<[f64; 2]> {
    let l = 0.015 + 0.02 * rng.uniform();
    let w = l * (0.2 + 0.5 * rng.uniform());
    let (a, b) = (0.5 * l, 0.5 * w);
    vec![[-a, -b], [a, -b], [a, b], [-a, b]]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shares of 8 are KINDS' own; smaller families keep each kind
    /// once; the counts always add up.
    #[test]
    fn counts_follow_the_shares() {
        assert_eq!(
            counts(8),
            vec![("polygon", 3), ("bracket", 3), ("rectangle", 2)]
        );
        assert_eq!(
            counts(3),
            vec![("polygon", 1), ("bracket", 1), ("rectangle", 1)]
        );
        for n in 0..40 {
            assert_eq!(counts(n).iter().map(|c| c.1).sum::<usize>(), n, "{n}");
        }
    }

    /// Every drawn part of a larger family is valid, no larger across than
    /// its kind's draws allow (a star: twice the largest radius, 1.6 cm; a
    /// bracket: the diagonal of 3 × 2.5 cm; a rectangle: 3.5 cm long and
    /// 70 % of that wide) nor smaller than the least radius, 0.4 cm, and
    /// only the rectangles have a 180° symmetry.
    #[test]
    fn drawn_parts_are_as_documented() {
        for (part, pose) in family(7, 60).unwrap() {
            let across = part.size();
            let most = match part.name.split('_').next() {
                Some("polygon") => 0.032,
                Some("bracket") => 0.03f64.hypot(0.025),
                _ => 0.035 * 1.49f64.sqrt(),
            };
            assert!((0.004..=most).contains(&across), "{}: {across}", part.name);
            let rect = part.name.starts_with("rectangle");
            assert_eq!(part.symmetry(), if rect { 2 } else { 1 }, "{}", part.name);
            assert!(pose[0].hypot(pose[1]) <= MAX_OFFSET + 1e-15);
            assert!((-180.0..180.0).contains(&pose[2]));
        }
    }
}
