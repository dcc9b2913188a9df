//! The search for a motion whose lifted field makes the asked pose the
//! unique stable equilibrium (modulo the part's symmetry).
//!
//! **Candidates** ([`Family`]): requested point fields, each designed by
//! the sequenced fit ([`crate::design::design`]) and judged by the
//! equilibria of the lifted field of the designed schedule's point field
//! ([`crate::pose::schedule_field`], [`crate::pose::equilibria`]):
//! - an elliptic sink: line sinks of strengths `ratio` and 1 whose weaker
//!   contraction runs along the angle. A linear field v = A p + b turns a
//!   part by its second moments only, so the part's major axis
//!   ([`crate::part::Part::principal_angle`]) aligns with the weaker contraction up to
//!   180°: one pose for a part symmetric under 180° (the rectangle), two
//!   180° apart for the others.
//! - a radial sink of unit speed (linear within [`CORE`] of its centre)
//!   plus a small uniform field of speed `unit` along the angle
//!   (Böhringer et al.): the radial part alone leaves every turn about its
//!   centre an equilibrium; the uniform part pushes the part off it, and
//!   the field's nonlinearity brings in the part's third moments, which
//!   picks one angle for most parts.
//!
//! **Placement.** A field turned by Δ about its centre turns its
//! equilibria by Δ, and shifted by s shifts them by s (for the requested
//! field exactly; for the designed one up to the fit, whose basis turns in
//! 15° steps). So the stable equilibrium nearest the asked pose is moved
//! onto it by turning the candidate by −Δθ about its centre and shifting
//! the centre by the remaining position error, a fixed-point iteration:
//! first on the requested field's lifted field (cheap), then on the
//! designed schedule's, until within [`PLACED_MM`] and [`PLACED_DEG`] or
//! [`PLACE_STEPS`] designs.

use crate::design::{design, Design, DesignOptions};
use crate::dynamics::V2;
use crate::error::Result;
use crate::field::Grid;
use crate::pose::{equilibria, schedule_field, wrap, Equilibrium, LiftedField, PointField, Pose};
use crate::request::{FieldSpec, Interpolation, SumTerm, Target};

use super::request::PoseRequest;

/// Half-width of the radial sink's linear core (m): the field speed is
/// |d| / CORE within it, 1 outside.
pub const CORE: f64 = 0.004;
/// Placement stops when the equilibrium is this close to the pose (mm).
pub const PLACED_MM: f64 = 0.05;
/// … and this close in angle (degrees).
pub const PLACED_DEG: f64 = 0.2;
/// Most designs per candidate in the placement.
pub const PLACE_STEPS: usize = 4;
/// Most placement steps on the requested field.
const REQUESTED_STEPS: usize = 8;
/// Stable equilibria closer than this (m) and [`SAME_RAD`] modulo the
/// part's symmetry are one pose.
const SAME_M: f64 = 5e-4;
const SAME_RAD: f64 = 0.0175;

/// A family of requested point fields, placed by a centre and an angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Family {
    /// Elliptic sink: contraction `ratio` along the angle, 1 across it.
    Ellipse {
        /// Weaker / stronger contraction, in (0, 1).
        ratio: f64,
    },
    /// Unit radial sink plus a uniform field of speed `unit` along the
    /// angle.
    Radial {
        /// Speed of the uniform part (relative to the radial part's 1).
        unit: f64,
    },
}

/// The candidates tried, in order.
pub const FAMILIES: [Family; 4] = [
    Family::Ellipse { ratio: 0.3 },
    Family::Ellipse { ratio: 0.5 },
    Family::Radial { unit: 0.15 },
    Family::Radial { unit: 0.3 },
];

impl Family {
    /// A short name.
    pub fn label(&self) -> String {
        match self {
            Family::Ellipse { ratio } => format!("elliptic sink (ratio {ratio})"),
            Family::Radial { unit } => format!("radial sink + uniform {unit}"),
        }
    }

    /// The requested field centred at `c` (m) along `angle` (degrees),
    /// sampled on `grid` where it is not a sum of analytic kinds.
    pub fn field(&self, c: V2, angle: f64, grid: &Grid) -> FieldSpec {
        let line = |strength: f64, angle: f64| SumTerm {
            weight: 1.0,
            field: FieldSpec::LineSink {
                center: [c.x, c.y],
                strength,
                angle,
                offset: 0.0,
            },
        };
        match *self {
            Family::Ellipse { ratio } => FieldSpec::Sum {
                terms: vec![line(ratio, angle + 90.0), line(1.0, angle)],
            },
            Family::Radial { unit } => {
                let points = grid.points();
                let (s, co) = angle.to_radians().sin_cos();
                let vectors = points
                    .iter()
                    .map(|p| {
                        let d = V2::new(p[0] - c.x, p[1] - c.y);
                        let v = -d / d.norm().max(CORE) + V2::new(co, s) * unit;
                        [v.x, v.y]
                    })
                    .collect();
                FieldSpec::Sampled {
                    points,
                    vectors,
                    interpolation: Interpolation::Idw,
                }
            }
        }
    }
}

/// θ reduced modulo the symmetry turn 2π/`n`, into (−π/n, π/n].
pub fn wrap_symmetric(theta: f64, n: usize) -> f64 {
    let n = n.max(1) as f64;
    wrap(theta * n) / n
}

/// How far `pose` is from `asked` modulo the symmetry `n`: (|Δr| m, Δθ rad).
pub fn pose_error(pose: &Pose, asked: &Pose, n: usize) -> (f64, f64) {
    (
        (pose.r - asked.r).norm(),
        wrap_symmetric(pose.theta - asked.theta, n),
    )
}

/// The stable equilibrium nearest `asked` modulo `n` in the metric
/// |Δr|/`radius` + |Δθ|.
pub fn nearest_stable(
    eqs: &[Equilibrium],
    asked: &Pose,
    n: usize,
    radius: f64,
) -> Option<Equilibrium> {
    let metric = |e: &Equilibrium| {
        let (d, t) = pose_error(&e.pose, asked, n);
        d / radius + t.abs()
    };
    eqs.iter()
        .filter(|e| e.stable)
        .min_by(|a, b| metric(a).total_cmp(&metric(b)))
        .copied()
}

/// The stable equilibria, one per pose modulo the symmetry `n`.
pub fn distinct_stable(eqs: &[Equilibrium], n: usize) -> Vec<Equilibrium> {
    let mut out: Vec<Equilibrium> = Vec::new();
    for e in eqs.iter().filter(|e| e.stable) {
        let same = |f: &Equilibrium| {
            let (d, t) = pose_error(&e.pose, &f.pose, n);
            d <= SAME_M && t.abs() <= SAME_RAD
        };
        if !out.iter().any(same) {
            out.push(*e);
        }
    }
    out
}

/// One candidate placed: the requested field, its design and the lifted
/// field's equilibria.
#[derive(Debug, Clone)]
pub struct Trial {
    /// The family.
    pub family: Family,
    /// The field's centre (m) and angle (degrees) after placement.
    pub center: V2,
    /// Angle (degrees).
    pub angle: f64,
    /// The target with the requested field.
    pub target: Target,
    /// The sequenced design of it.
    pub design: Design,
    /// Equilibria of the lifted field of the designed schedule.
    pub equilibria: Vec<Equilibrium>,
    /// The stable one nearest the asked pose.
    pub nearest: Option<Equilibrium>,
    /// Stable poses modulo the part's symmetry.
    pub distinct: usize,
    /// Designs made in the placement.
    pub designs: usize,
}

impl Trial {
    /// Distance of the nearest stable pose from the asked one: (mm, degrees).
    pub fn error(&self, asked: &Pose, n: usize) -> Option<(f64, f64)> {
        self.nearest.map(|e| {
            let (d, t) = pose_error(&e.pose, asked, n);
            (1e3 * d, t.to_degrees())
        })
    }

    /// The slowest decay rate at the nearest stable pose (1/s).
    pub fn slowest_rate(&self) -> f64 {
        self.nearest.map_or(0.0, |e| -e.rates[0])
    }
}

/// One placement step: the centre and angle that move `eq` onto `asked`.
pub fn replace(c: V2, angle: f64, eq: &Pose, asked: &Pose, n: usize) -> (V2, f64) {
    let dt = wrap_symmetric(eq.theta - asked.theta, n);
    let (s, co) = (-dt).sin_cos();
    let d = eq.r - c;
    let turned = c + V2::new(co * d.x - s * d.y, s * d.x + co * d.y);
    (c + (asked.r - turned), angle - dt.to_degrees())
}

/// Whether `eq` is within the placement tolerance of `asked`.
fn placed(eq: &Pose, asked: &Pose, n: usize) -> bool {
    let (d, t) = pose_error(eq, asked, n);
    d <= 1e-3 * PLACED_MM && t.abs().to_degrees() <= PLACED_DEG
}

/// The equilibria of `part` in `field` over the request's region.
fn lifted_equilibria(req: &PoseRequest, field: &dyn PointField) -> Vec<Equilibrium> {
    equilibria(&LiftedField::new(field, &req.part.body), &req.region)
}

/// Places `family` on the requested field's lifted field (cheap): the
/// centre and angle to start the designed placement from.
fn place_requested(req: &PoseRequest, family: Family, grid: &Grid) -> (V2, f64) {
    let n = req.part.symmetry();
    let mut c = req.pose.r;
    let mut angle = (req.pose.theta + req.part.principal_angle()).to_degrees();
    for _ in 0..REQUESTED_STEPS {
        let spec = family.field(c, angle, grid);
        let eqs = lifted_equilibria(req, &spec);
        let Some(eq) = nearest_stable(&eqs, &req.pose, n, req.part.radius()) else {
            break;
        };
        if placed(&eq.pose, &req.pose, n) {
            break;
        }
        (c, angle) = replace(c, angle, &eq.pose, &req.pose, n);
    }
    (c, angle)
}

/// Designs `family` at (`c`, `angle`) and finds its lifted equilibria.
pub fn trial_at(
    req: &PoseRequest,
    opts: &DesignOptions,
    (family, c, angle): (Family, V2, f64),
    grid: &Grid,
) -> Result<Trial> {
    let mut target = req.target.clone();
    target.field = family.field(c, angle, grid);
    let design = design(&target, opts)?;
    let field = schedule_field(&design.schedule, grid)?;
    let eqs = lifted_equilibria(req, &field);
    let n = req.part.symmetry();
    Ok(Trial {
        family,
        center: c,
        angle,
        target,
        design,
        nearest: nearest_stable(&eqs, &req.pose, n, req.part.radius()),
        distinct: distinct_stable(&eqs, n).len(),
        equilibria: eqs,
        designs: 0,
    })
}

/// `family` placed (module docs): at most [`PLACE_STEPS`] designs.
pub fn place(req: &PoseRequest, opts: &DesignOptions, family: Family) -> Result<Trial> {
    let grid = req.target.grid.unwrap_or(Grid::DEFAULT);
    let n = req.part.symmetry();
    let (c, angle) = place_requested(req, family, &grid);
    let mut trial = trial_at(req, opts, (family, c, angle), &grid)?;
    let mut designs = 1;
    while designs < PLACE_STEPS {
        let Some(eq) = trial.nearest.filter(|e| !placed(&e.pose, &req.pose, n)) else {
            break;
        };
        let (c, angle) = replace(trial.center, trial.angle, &eq.pose, &req.pose, n);
        trial = trial_at(req, opts, (family, c, angle), &grid)?;
        designs += 1;
    }
    trial.designs = designs;
    Ok(trial)
}

/// Every family of [`FAMILIES`] placed; the errors of a family that could
/// not be designed are kept as its reason.
pub fn search(req: &PoseRequest, opts: &DesignOptions) -> Vec<(Family, Result<Trial>)> {
    FAMILIES.iter().map(|&f| (f, place(req, opts, f))).collect()
}

/// The best trial: a unique stable pose (modulo symmetry) first, then the
/// smaller pose error (|Δr| in mm + |Δθ| in degrees, rounded to 0.1 so
/// that equal placements tie), then the faster slowest rate.
pub fn best<'a>(trials: &'a [Trial], asked: &Pose, n: usize) -> Option<&'a Trial> {
    let key = |t: &Trial| {
        let (d, a) = t.error(asked, n).unwrap_or((f64::INFINITY, f64::INFINITY));
        (
            (t.distinct != 1) as u8,
            (10.0 * (d + a.abs())).round(),
            -t.slowest_rate(),
        )
    };
    trials.iter().min_by(|a, b| {
        let (ka, kb) = (key(a), key(b));
        ka.0.cmp(&kb.0)
            .then(ka.1.total_cmp(&kb.1))
            .then(ka.2.total_cmp(&kb.2))
    })
}
