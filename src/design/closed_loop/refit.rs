//! One contextual re-fit of the closed loop (stage 3 of
//! [`super`]): each segment's realised velocity in its schedule context
//! replaces its steady-state field as a basis column, the time fractions are
//! re-fitted to the target with the design's conic fit, and the result is
//! quantised to whole cycles at a given total length.
//!
//! The basis column of a segment b is the time-weighted mean of its plays'
//! contributions, c_b = Σ_k T_k c_k / Σ_k T_k over the plays k of b (a
//! segment is played twice per period in a mirrored order). Rows are the
//! played points with weight > 0 at their mean positions q, the target is
//! t(q), and the target's weights multiply the residual rows, as in the
//! realised error. A rest segment keeps the remaining time 1 − Σf; its
//! realised contribution (parts sliding to a stop) is left out of the fit,
//! as the design leaves the plate at rest out (the zero field).

use nalgebra::{DMatrix, DVector};

use super::PointPlay;
use crate::basis::{Primitive, PrimitiveKind};
use crate::error::{Error, Result};
use crate::fit::{FitMode, FitOptions, FitProblem};
use crate::request::Target;
use crate::schedule::{quantize, Quantized, Schedule, Segment, DEFAULT_QUANTIZATION_TOL};

/// One contextual re-fit: the segments' realised velocities in context as
/// basis columns, the conic fit, whole cycles. Returns the new segments
/// (same indices as `base`, plus a rest segment at the end if one is newly
/// needed; unused ones with 0 cycles), the playing pattern without unused
/// segments, and the re-fit's strength.
pub(crate) fn refit(
    target: &Target,
    weights: &[f64],
    template: &Schedule,
    base: &[Segment],
    pattern: &[usize],
    plays: &[PointPlay],
    total: u32,
) -> Result<(Vec<Segment>, Vec<usize>, f64)> {
    let w = weights;
    let ok: Vec<&PointPlay> = plays
        .iter()
        .filter(|p| p.note.is_none() && w[p.index] > 0.0)
        .collect();
    let moving: Vec<usize> = (0..base.len())
        .filter(|&b| base[b].is_moving() && pattern.contains(&b))
        .collect();
    if ok.is_empty() || moving.is_empty() {
        return Err(Error::Internal("nothing to re-fit".into()));
    }
    let (a, t, d) = contextual_rows(target, w, base, pattern, &ok, &moving);
    let problem = FitProblem {
        a: &a,
        t: &t,
        row_weights: Some(&d),
    };
    let sol = crate::design::strongest(
        &problem,
        &FitOptions {
            mode: FitMode::Shape,
            ..FitOptions::default()
        },
    )?;
    if sol.strength.is_nan() || sol.strength <= 0.0 {
        return Err(Error::Unreachable(
            "the contextual fields do not reach the target's shape".into(),
        ));
    }
    // Whole cycles at the open-loop schedule's total length.
    let f = &sol.fractions;
    let wa = DMatrix::from_fn(a.nrows(), moving.len(), |i, j| d[i] * a[(i, j)]);
    let fv = DVector::from_column_slice(f);
    let norm = (&wa * &fv).norm().max(f64::MIN_POSITIVE);
    let field_error = |q: &[f64]| -> f64 {
        let dq = DVector::from_fn(f.len(), |j, _| q[j] - f[j]);
        (&wa * dq).norm() / norm
    };
    let periods: Vec<f64> = moving
        .iter()
        .map(|&b| base[b].cycle_period().unwrap_or(1.0))
        .collect();
    let rest_period = Primitive::new(PrimitiveKind::LineSink).period();
    let q = quantize(
        f,
        &periods,
        rest_period,
        template.min_cycles,
        Some(total),
        DEFAULT_QUANTIZATION_TOL,
        &field_error,
    );
    if q.cycles.iter().all(|c| *c == 0) {
        return Err(Error::Unreachable(format!(
            "no segment keeps a whole cycle at {total} cycles"
        )));
    }
    let (new_base, new_pattern) = with_cycles(base, pattern, &moving, &q, f, &periods, rest_period);
    Ok((new_base, new_pattern, sol.strength))
}

/// The re-fit's rows: columns c_b of the moving segments (time-weighted
/// means of their plays' contributions) at the `ok` plays' mean positions,
/// the target there, and the target's weights per row (x rows, then y).
fn contextual_rows(
    target: &Target,
    w: &[f64],
    base: &[Segment],
    pattern: &[usize],
    ok: &[&PointPlay],
    moving: &[usize],
) -> (DMatrix<f64>, DVector<f64>, DVector<f64>) {
    let played: Vec<&Segment> = pattern.iter().map(|&i| &base[i]).collect();
    let n = ok.len();
    let mut a = DMatrix::zeros(2 * n, moving.len());
    for (col, &b) in moving.iter().enumerate() {
        let plays_of_b: Vec<usize> = (0..pattern.len()).filter(|&k| pattern[k] == b).collect();
        let time: f64 = plays_of_b.iter().map(|&k| played[k].duration_s).sum();
        for (row, p) in ok.iter().enumerate() {
            for &k in &plays_of_b {
                let f = played[k].duration_s / time;
                a[(row, col)] += f * p.contributions[k][0];
                a[(row + n, col)] += f * p.contributions[k][1];
            }
        }
    }
    let mut t = DVector::zeros(2 * n);
    let mut d = DVector::zeros(2 * n);
    for (row, p) in ok.iter().enumerate() {
        let v = target.field.eval(p.position);
        t[row] = v[0];
        t[row + n] = v[1];
        d[row] = w[p.index];
        d[row + n] = w[p.index];
    }
    (a, t, d)
}

/// `base` with the quantised cycles `q` of the fractions `f` on its moving
/// segments (the others at 0 cycles), the rest segment set or appended, and
/// the playing pattern without segments of 0 cycles.
fn with_cycles(
    base: &[Segment],
    pattern: &[usize],
    moving: &[usize],
    q: &Quantized,
    f: &[f64],
    periods: &[f64],
    rest_period: f64,
) -> (Vec<Segment>, Vec<usize>) {
    let mut new_base: Vec<Segment> = base.to_vec();
    for g in new_base.iter_mut() {
        if g.is_moving() {
            g.cycles = 0;
            g.duration_s = 0.0;
            g.weight = 0.0;
        }
    }
    for (col, &b) in moving.iter().enumerate() {
        let g = &mut new_base[b];
        g.cycles = q.cycles[col];
        g.duration_s = f64::from(q.cycles[col]) * periods[col];
        g.weight = f[col];
    }
    let rest_weight = (1.0 - f.iter().sum::<f64>()).max(0.0);
    let mut new_pattern: Vec<usize> = pattern.to_vec();
    match new_base.iter().position(|g| !g.is_moving()) {
        Some(r) => {
            let g = &mut new_base[r];
            g.cycles = q.rest_cycles;
            g.duration_s = f64::from(q.rest_cycles) * rest_period;
            g.weight = rest_weight;
        }
        None if q.rest_cycles > 0 => {
            new_base.push(Segment {
                label: "Rest".into(),
                primitive: None,
                motion: None,
                ramp_cycles: None,
                weight: rest_weight,
                cycles: q.rest_cycles,
                duration_s: f64::from(q.rest_cycles) * rest_period,
            });
            new_pattern.push(new_base.len() - 1);
        }
        None => {}
    }
    new_pattern.retain(|&i| new_base[i].cycles > 0);
    (new_base, new_pattern)
}
