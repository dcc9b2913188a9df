//! Study: robust design over a seeded family of random targets,
//! `results/robust_family.md`.
//!
//! The family is [`platefield::request::family::family`] (seed
//! [`SEED`], [`COUNT`] targets: off-centre sinks, ellipses at any angle,
//! saddles and line sinks at random angles and offsets, whirlpools,
//! random smooth sampled fields; each with a friction range of ±33 %
//! around a random μ in [0.2, 0.5]). Each target is designed twice:
//! - **robust**: `design`'s default (`auto`) over the target's range —
//!   every candidate judged by its worst case over the range, the
//!   mirror-image share about the target's symmetry axis or, without one,
//!   the counter-rotating share (`platefield::design::mirror`); when none
//!   holds 6 %, the syntheses `auto` adds: within the sequenced peaks,
//!   within the contact margin raised halfway to g
//!   (`platefield::design::method::gentle_limits`: the whirlpools, saddles
//!   and line sinks whose tilts swing the normal force to the margin), and
//!   for the worst case;
//! - **nominal**: `auto` again, for the range's middle as an exact
//!   friction: the design a user who states no range gets (its basis is
//!   the robust design's, read from the cache).
//!
//! Both are judged (`platefield::design::judge`: the realised field at
//! ≥ 9 × 9 held points over the whole region, whole periods) at
//! [`VALUES`] frictions spread evenly over the range, ends included. The
//! file gives each target's worst case of both, the robust design's
//! strength against the nominal design's at its own μ, and the
//! distribution over the family (median, 90th percentile, maximum). The
//! work each design was estimated at is in the file; CPU seconds are
//! printed only (they vary from run to run).

use std::path::Path;

use platefield::design::method::Method;
use platefield::design::tolerance::quantile;
use platefield::error::Result;
use platefield::play::sensitivity::FrictionRow;
use platefield::request::family::family;
use platefield::request::{FieldSpec, FrictionSpec, Target};
use platefield_report::table::Table;

use super::robust::{design_row, designed, judged, kept_rows, Row};
use super::speed::process_cpu_seconds;

/// Default output folder.
pub const DIR: &str = "results";
/// The family's seed.
pub const SEED: u64 = 45;
/// Targets in the family.
pub const COUNT: usize = 40;
/// Frictions each design is judged at, evenly over the range.
pub const VALUES: usize = 5;
/// Goals: worst shape error of 90 % of the targets, of every target, and
/// the least strength against the nominal design's.
pub const GOALS: (f64, f64, f64) = (0.06, 0.10, 0.6);

/// One target's two designs, judged over its range.
#[derive(Debug, Clone)]
pub struct Outcome {
    /// The target.
    pub target: Target,
    /// The robust design's judge at each friction.
    pub robust: Row,
    /// The nominal design's judge at each friction.
    pub nominal: Row,
    /// CPU seconds of both designs and their sweeps (printed only).
    pub cpu_s: f64,
}

impl Outcome {
    /// The nominal design's strength at its own μ (the middle value).
    pub fn nominal_strength(&self) -> f64 {
        self.nominal.rows[VALUES / 2]
            .realised_strength
            .unwrap_or(f64::NAN)
    }

    /// The nominal design's shape error at its own μ: what the product
    /// reaches for this target at one friction, a floor no robust design
    /// is expected to beat (a target outside what plate motions realise,
    /// such as a sampled field's short wave, misses 6 % here already).
    pub fn nominal_shape(&self) -> f64 {
        self.nominal.rows[VALUES / 2]
            .realised_shape_error
            .unwrap_or(f64::NAN)
    }

    /// The robust design's weakest strength against
    /// [`Outcome::nominal_strength`].
    pub fn strength_ratio(&self) -> f64 {
        self.robust.worst().1 / self.nominal_strength()
    }
}

/// The frictions over `spec`'s range.
pub(crate) fn values(spec: FrictionSpec) -> Vec<f64> {
    spec.values(VALUES).iter().map(|f| f.kinetic).collect()
}

/// Designs and judges one target ([`Outcome`]) by `methods`, the robust
/// design's and the nominal one's (`auto` for both in the study; tests
/// use the cheaper `mirror` and `synthesize`). Under `mirror` the motion
/// its shares are built from is the synthesis for the range's middle,
/// which is the nominal design `synthesize` makes (the same synthesis of
/// the same target field at the same friction; byte for byte, by the
/// ignored test `the_mirror_base_is_the_nominal_synthesis` in
/// `studies/tests/robust_family.rs`): that schedule is judged instead of
/// being designed again.
///
/// # Errors
/// A design fails.
pub fn outcome(target: &Target, methods: (Method, Method), quiet: bool) -> Result<Outcome> {
    let (method, nominal_method) = methods;
    let cpu = process_cpu_seconds();
    let spec = target.friction.unwrap_or(FrictionSpec::range(0.2, 0.4));
    let mu = values(spec);
    let md = designed(target, method, quiet)?;
    let robust = kept_rows(target, ("robust", &md), &mu, false)?.remove(0);
    let mut nominal = target.clone();
    nominal.friction = Some(FrictionSpec::exact(spec.nominal()));
    let base = md
        .synthesized
        .as_ref()
        .filter(|_| method == Method::Mirror && nominal_method == Method::Synthesize);
    let mut row = match base {
        Some(schedule) => Row {
            target: target.name.clone(),
            design: "nominal".into(),
            method: Method::Synthesize.name().into(),
            rows: judged(&nominal, schedule, &mu)?,
        },
        None => design_row(&nominal, ("nominal", nominal_method), &mu, quiet)?,
    };
    row.target.clone_from(&target.name);
    Ok(Outcome {
        target: target.clone(),
        robust,
        nominal: row,
        cpu_s: process_cpu_seconds()
            .zip(cpu)
            .map_or(f64::NAN, |(b, a)| b - a),
    })
}

/// The part of a sampled field no affine field matches: the relative
/// residual ‖v − (A r + b)‖/‖v‖ of the least-squares affine fit over its
/// sample points (`None` for analytic fields, for fewer than three points,
/// or where the fit's normal equations have no inverse).
///
/// What it diagnoses: a rigid plate's acceleration is affine in the
/// position (a(r) = a_c + Ω' × d + Ω × (Ω × d)), and the robust designs of
/// the family's sampled members leave about as much of the target
/// unmatched as the best affine field does (`studies/tests/robust_family.rs`
/// checks the committed rows against this residual).
pub fn affine_residual(field: &FieldSpec) -> Option<f64> {
    use nalgebra::{Matrix3, Vector3};
    let FieldSpec::Sampled {
        points, vectors, ..
    } = field
    else {
        return None;
    };
    if points.len() < 3 {
        return None;
    }
    let row = |p: &[f64; 2]| Vector3::new(p[0], p[1], 1.0);
    let normal: Matrix3<f64> = points.iter().map(|p| row(p) * row(p).transpose()).sum();
    let solve = normal.try_inverse()?;
    let (mut left, mut total) = (0.0, 0.0);
    for k in 0..2 {
        let rhs: Vector3<f64> = points.iter().zip(vectors).map(|(p, v)| row(p) * v[k]).sum();
        let c = solve * rhs;
        for (p, v) in points.iter().zip(vectors) {
            left += (c.dot(&row(p)) - v[k]).powi(2);
            total += v[k] * v[k];
        }
    }
    (total > 0.0).then(|| (left / total).sqrt())
}

/// A short description of a family member's field.
fn describe(field: &FieldSpec) -> String {
    let cm = |c: [f64; 2]| format!("({:.2}, {:.2}) cm", 100.0 * c[0], 100.0 * c[1]);
    match field {
        FieldSpec::Sink { center, .. } => format!("sink at {}", cm(*center)),
        FieldSpec::Saddle { center, angle, .. } => {
            format!("saddle at {}, {angle:.1}°", cm(*center))
        }
        FieldSpec::LineSink { angle, offset, .. } => {
            format!("line sink at {angle:.1}°, offset {:.2} cm", 100.0 * offset)
        }
        FieldSpec::Whirlpool { rotation, .. } => format!("whirlpool, rotation {rotation:.2}"),
        FieldSpec::Sum { terms } => match terms.as_slice() {
            [a, b] => match (&a.field, &b.field) {
                (FieldSpec::LineSink { angle, .. }, _) => {
                    format!("ellipse at {angle:.1}°, axis ratio {:.2}", b.weight)
                }
                _ => "sum".into(),
            },
            _ => "sum".into(),
        },
        FieldSpec::Sampled { .. } => "random smooth sampled field".into(),
        _ => "other".into(),
    }
}

fn strength(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.3}")
    } else {
        "n/a".into()
    }
}

fn pct(x: f64) -> String {
    platefield::output::percent(x, 1)
}

/// The μ where a row's shape error is worst.
fn worst_mu(rows: &[FrictionRow]) -> f64 {
    rows.iter()
        .max_by(|a, b| {
            let e = |r: &FrictionRow| r.realised_shape_error.unwrap_or(f64::INFINITY);
            e(a).total_cmp(&e(b))
        })
        .map_or(f64::NAN, |r| r.friction.kinetic)
}

/// `robust_family.md` from the outcomes.
pub fn render(outcomes: &[Outcome]) -> String {
    let mut md = format!(
        "# Robust design over a family of random targets\n\nGenerated by `platefield study robust-family` (see `platefield_studies::robust_family`): {COUNT} targets from the seeded generator `platefield::request::family` (seed {SEED}), each with a friction range of ±33 % around a random μ in [0.2, 0.5]. **Robust**: `design`'s default (`auto`) over the range. **Nominal**: `auto` for the range's middle as an exact friction (what a user who states no range gets). Both judged (`design::judge`: the realised field at ≥ 9 × 9 held points over the whole region, whole schedule periods) at {VALUES} frictions evenly over the range, ends included; shape error ‖R − ŝt‖/‖ŝt‖, strength ŝ (× the target's). Ratio: the robust design's weakest strength over the nominal design's strength at its own μ. Goals: 90 % of the targets ≤ {:.0} % worst shape, every target ≤ {:.0} %, ratio ≥ {}.\n\n",
        100.0 * GOALS.0,
        100.0 * GOALS.1,
        GOALS.2
    );
    let mut table = Table::new([
        "target",
        "field",
        "μ range",
        "robust kept",
        "robust worst shape (at μ)",
        "robust weakest strength",
        "nominal worst shape (at μ)",
        "nominal shape at its μ",
        "nominal strength at its μ",
        "ratio",
    ]);
    for o in outcomes {
        let (shape, weakest) = o.robust.worst();
        let (n_shape, _) = o.nominal.worst();
        let mu = values(o.target.friction.unwrap_or(FrictionSpec::range(0.2, 0.4)));
        table.row([
            o.target.name.clone(),
            describe(&o.target.field),
            format!("[{:.3}, {:.3}]", mu[0], mu[VALUES - 1]),
            o.robust.method.clone(),
            format!("{} ({:.3})", pct(shape), worst_mu(&o.robust.rows)),
            strength(weakest),
            format!("{} ({:.3})", pct(n_shape), worst_mu(&o.nominal.rows)),
            pct(o.nominal_shape()),
            strength(o.nominal_strength()),
            strength(o.strength_ratio()),
        ]);
    }
    md.push_str(&table.markdown());
    md.push_str("\n## Over the family\n\n");
    let robust: Vec<f64> = outcomes.iter().map(|o| o.robust.worst().0).collect();
    let nominal: Vec<f64> = outcomes.iter().map(|o| o.nominal.worst().0).collect();
    let ratio: Vec<f64> = outcomes.iter().map(Outcome::strength_ratio).collect();
    let mut table = Table::new(["measure", "median", "90th percentile", "maximum"]);
    for (name, xs) in [
        ("robust worst shape", &robust),
        ("nominal worst shape", &nominal),
    ] {
        table.row([
            name.into(),
            pct(quantile(xs, 0.5)),
            pct(quantile(xs, 0.9)),
            pct(quantile(xs, 1.0)),
        ]);
    }
    let neg: Vec<f64> = ratio.iter().map(|r| -r).collect();
    table.row([
        "ratio (median, 10th percentile, minimum)".into(),
        strength(-quantile(&neg, 0.5)),
        strength(-quantile(&neg, 0.9)),
        strength(-quantile(&neg, 1.0)),
    ]);
    md.push_str(&table.markdown());
    let n = outcomes.len();
    let within = robust.iter().filter(|e| **e <= GOALS.0).count();
    // NaN (not measured) counts against the goals.
    let over = robust
        .iter()
        .filter(|e| e.is_nan() || **e > GOALS.1)
        .count();
    let weak = ratio.iter().filter(|r| r.is_nan() || **r < GOALS.2).count();
    let floor = outcomes
        .iter()
        .filter(|o| o.nominal_shape().is_nan() || o.nominal_shape() > GOALS.0)
        .count();
    md.push_str(&format!(
        "\n{within} of {n} targets ({:.0} %) hold ≤ {:.0} % worst shape over their range (goal 90 %); {over} exceed {:.0} % (goal 0); {weak} fall below {} of the nominal design's strength (goal 0). For {floor} of the {n} targets the nominal design misses {:.0} % at its own μ already (column \"nominal shape at its μ\"): at one friction `auto` comes no closer, so over a range it cannot be expected to.\n",
        100.0 * within as f64 / n.max(1) as f64,
        100.0 * GOALS.0,
        100.0 * GOALS.1,
        GOALS.2,
        100.0 * GOALS.0
    ));
    md
}

/// `platefield study robust-family`: designs a family of `count` targets
/// ([`COUNT`] by default; the kinds in their shares), writes `OUT/robust_family.md`
/// and returns the text with each target's CPU seconds (printed only).
pub fn run(out: &Path, count: usize, quiet: bool) -> Result<String> {
    platefield::output::check_writable(out, "--out")?;
    let mut outcomes = Vec::new();
    let mut cpu = String::new();
    let members = family(SEED, count);
    let n = members.len();
    for (k, target) in members.iter().enumerate() {
        eprintln!("robust-family: {} ({} of {n})", target.name, k + 1);
        let o = outcome(target, (Method::Auto, Method::Auto), quiet)?;
        cpu.push_str(&format!(
            "{}: {:.1} s CPU, robust worst {}\n",
            target.name,
            o.cpu_s,
            pct(o.robust.worst().0)
        ));
        outcomes.push(o);
    }
    let md = render(&outcomes);
    let path = out.join("robust_family.md");
    platefield::output::write_atomic(&path, md.as_bytes())?;
    Ok(format!("{md}\n{cpu}wrote {}\n", path.display()))
}
