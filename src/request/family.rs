//! A seeded family of random targets: what robust design is measured on,
//! beyond the shipped examples.
//!
//! Every member is a target over the square ±4 cm (21 × 21 points, the
//! shipped targets' grid) with a friction range of ±33 % around a nominal
//! μ drawn uniformly from [0.2, 0.5]. The kinds, in this order and in
//! these proportions of the family (of 40: 8, 8, 6, 6, 7, 5):
//!
//! | kind | drawn |
//! |---|---|
//! | sink | centre at a uniform angle, distance uniform in [0, 1.5] cm |
//! | ellipse | line sinks at θ and θ + 90°, θ uniform in [0°, 180°), weights 1 and r, r uniform in [0.3, 1] |
//! | saddle | contracting axis uniform in [0°, 180°), centre as a sink's |
//! | line sink | angle uniform in [0°, 180°), offset uniform in ±1.5 cm |
//! | whirlpool | rotation ±(0.3 … 1.5), sign and size uniform |
//! | sampled | at the 21 × 21 points: a random affine field (entries of M standard normal, normalised to unit norm; b up to 1 cm × ‖M‖) plus a smooth wave of a quarter of its size (wavelength 8–16 cm, direction and phase uniform) |
//!
//! The proportions and the draws' ranges are fixed by what robust design
//! is asked to cover, and nothing is tuned to what a design achieves.

use super::field::{FieldSpec, Interpolation, SumTerm};
use super::grid::Grid;
use super::Target;
use crate::rng::SplitMix64;
use crate::scene::FrictionSpec;

/// Half the side of every member's square region (m).
pub const HALF_SIDE: f64 = 0.04;
/// Points per side of every member's grid.
pub const POINTS: usize = 21;
/// Farthest a centre (or a line's offset) is drawn from the plate centre (m).
pub const MAX_OFFSET: f64 = 0.015;
/// Relative half-width of every member's friction range.
pub const SPREAD: f64 = 0.33;
/// The nominal μ is drawn from this interval.
pub const NOMINAL_MU: [f64; 2] = [0.2, 0.5];

/// The kinds of a family, in order, with their shares of 40.
pub const KINDS: [(&str, usize); 6] = [
    ("sink", 8),
    ("ellipse", 8),
    ("saddle", 6),
    ("line_sink", 6),
    ("whirlpool", 7),
    ("sampled", 5),
];

/// `count` random targets from `seed` (module documentation): the kinds
/// in [`KINDS`]' proportions (rounded, each kind at least once when
/// `count` ≥ 6), named `<kind>_<k>`, each with its friction range.
///
/// ```
/// use platefield::request::family::family;
///
/// let targets = family(7, 40);
/// assert_eq!(targets.len(), 40);
/// assert_eq!(targets[0].name, "sink_0");
/// assert!(targets.iter().all(|t| t.friction.is_some_and(|f| f.kinetic.lo < f.kinetic.hi)));
/// assert_eq!(family(7, 40), targets); // seeded
/// ```
pub fn family(seed: u64, count: usize) -> Vec<Target> {
    let mut rng = SplitMix64::new(seed);
    let mut out = Vec::with_capacity(count);
    for (kind, n) in shares(count) {
        for k in 0..n {
            let field = draw(kind, &mut rng);
            let mu = NOMINAL_MU[0] + (NOMINAL_MU[1] - NOMINAL_MU[0]) * rng.uniform();
            out.push(Target {
                name: format!("{kind}_{k}"),
                grid: Some(grid()),
                field,
                weights: None,
                mask: Vec::new(),
                shaker: None,
                friction: Some(FrictionSpec::range(
                    mu * (1.0 - SPREAD),
                    mu * (1.0 + SPREAD),
                )),
                gravity: None,
                classes: Vec::new(),
            });
        }
    }
    out
}

/// How many of each kind a family of `count` has: [`KINDS`]' shares of 40
/// scaled to `count` by largest remainders.
fn shares(count: usize) -> Vec<(&'static str, usize)> {
    let total: usize = KINDS.iter().map(|k| k.1).sum();
    let exact: Vec<f64> = KINDS
        .iter()
        .map(|k| (k.1 * count) as f64 / total as f64)
        .collect();
    let mut n: Vec<usize> = exact.iter().map(|e| e.floor() as usize).collect();
    let mut order: Vec<usize> = (0..KINDS.len()).collect();
    order.sort_by(|&a, &b| (exact[b] - exact[b].floor()).total_cmp(&(exact[a] - exact[a].floor())));
    let left = count - n.iter().sum::<usize>();
    for &i in order.iter().take(left) {
        n[i] += 1;
    }
    KINDS.iter().zip(n).map(|(k, n)| (k.0, n)).collect()
}

/// The members' grid.
fn grid() -> Grid {
    Grid {
        x: [-HALF_SIDE, HALF_SIDE],
        y: [-HALF_SIDE, HALF_SIDE],
        n: [POINTS, POINTS],
    }
}

/// A centre at a uniform angle, at a distance uniform in [0, MAX_OFFSET].
fn centre(rng: &mut SplitMix64) -> [f64; 2] {
    let (r, a) = (
        MAX_OFFSET * rng.uniform(),
        std::f64::consts::TAU * rng.uniform(),
    );
    [r * a.cos(), r * a.sin()]
}

/// One field of `kind` (module documentation).
fn draw(kind: &str, rng: &mut SplitMix64) -> FieldSpec {
    match kind {
        "sink" => FieldSpec::Sink {
            center: centre(rng),
            strength: 1.0,
        },
        "ellipse" => {
            let (theta, r) = (180.0 * rng.uniform(), 0.3 + 0.7 * rng.uniform());
            let line = |angle: f64, weight: f64| SumTerm {
                weight,
                field: FieldSpec::LineSink {
                    center: [0.0; 2],
                    strength: 1.0,
                    angle,
                    offset: 0.0,
                },
            };
            FieldSpec::Sum {
                terms: vec![line(theta, 1.0), line(theta + 90.0, r)],
            }
        }
        "saddle" => FieldSpec::Saddle {
            center: centre(rng),
            strength: 1.0,
            angle: 180.0 * rng.uniform(),
        },
        "line_sink" => FieldSpec::LineSink {
            center: [0.0; 2],
            strength: 1.0,
            angle: 180.0 * rng.uniform(),
            offset: MAX_OFFSET * rng.symmetric(),
        },
        "whirlpool" => {
            let size = 0.3 + 1.2 * rng.uniform();
            let sign = if rng.uniform() < 0.5 { -1.0 } else { 1.0 };
            FieldSpec::Whirlpool {
                center: [0.0; 2],
                strength: 1.0,
                rotation: sign * size,
            }
        }
        _ => sampled(rng),
    }
}

/// A random smooth sampled field at the grid's points (module
/// documentation).
fn sampled(rng: &mut SplitMix64) -> FieldSpec {
    let mut m = [[0.0; 2]; 2];
    for row in &mut m {
        for v in row.iter_mut() {
            *v = rng.gaussian();
        }
    }
    let norm = m.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let m = m.map(|row| row.map(|v| v / norm));
    let b = [
        MAX_OFFSET * rng.symmetric() * 2.0 / 3.0,
        MAX_OFFSET * rng.symmetric() * 2.0 / 3.0,
    ];
    let wavelength = 0.08 + 0.08 * rng.uniform();
    let k = std::f64::consts::TAU / wavelength;
    let (dir, phase) = (
        std::f64::consts::TAU * rng.uniform(),
        std::f64::consts::TAU * rng.uniform(),
    );
    let wave_dir = std::f64::consts::TAU * rng.uniform();
    let size = 0.25 * HALF_SIDE;
    let points = grid().points();
    let vectors = points
        .iter()
        .map(|p| {
            let s = (k * (p[0] * dir.cos() + p[1] * dir.sin()) + phase).sin();
            std::array::from_fn(|i| {
                m[i][0] * (p[0] - b[0])
                    + m[i][1] * (p[1] - b[1])
                    + size * s * [wave_dir.cos(), wave_dir.sin()][i]
            })
        })
        .collect();
    FieldSpec::Sampled {
        points,
        vectors,
        interpolation: Interpolation::Idw,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The kinds' counts follow the shares for any size, and every member
    /// is a valid target (it samples) whose range is ±33 % around a μ in
    /// [0.2, 0.5].
    #[test]
    fn members_follow_the_shares_and_ranges() {
        assert_eq!(
            shares(40).iter().map(|s| s.1).collect::<Vec<_>>(),
            KINDS.iter().map(|k| k.1).collect::<Vec<_>>()
        );
        for count in [4, 6, 13, 40, 81] {
            assert_eq!(shares(count).iter().map(|s| s.1).sum::<usize>(), count);
        }
        for t in family(3, 40) {
            let json = serde_json::to_string(&t).expect("serialises");
            let back = Target::from_json_str(&json).expect("a valid target");
            assert!(back.sample().expect("samples").len() >= POINTS * POINTS);
            let f = t.friction.expect("a range");
            let (lo, hi) = (f.kinetic.lo, f.kinetic.hi);
            let mu = 0.5 * (lo + hi);
            assert!(
                (0.2 - 1e-12..=0.5 + 1e-12).contains(&mu),
                "{}: {mu}",
                t.name
            );
            assert!((hi / mu - 1.0 - SPREAD).abs() < 1e-12, "{}", t.name);
        }
    }
}
