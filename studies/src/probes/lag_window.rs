//! Where the synthesized motions' model-check gap (moving parts against
//! the prediction) comes from: the lab-class sink is synthesized as in `platefield
//! synthesis`, then played from rest at the model check's start points
//! ([`check_starts`]) with different
//! warm-ups and measured spans. Each play is compared with four
//! predictions built from the motion's steady states F (see
//! [`platefield::play::measure`] and [`platefield::play::lag`]):
//!
//! * flow of F (the measure before),
//! * F iterated once per cycle (r ← r + T F(r): what F means),
//! * flow of the drift-lag-corrected F,
//! * the corrected F iterated once per cycle (the measure now, `verify`'s
//!   number, also from [`against_prediction`]).
//!
//! Then the cause of the lag part: the slip at phase 0 of a part played
//! 40 cycles against the steady orbit through its position, and the
//! first-order lag theory of [`platefield::play::lag`].

use std::path::Path;

use nalgebra::Matrix2;

use crate::synthesis::{check_starts, synthesized_motion, StudySettings};
use platefield::dynamics::{PartState, Simulator, SteadyState, V2};
use platefield::error::{Error, Result};
use platefield::field::FieldSettings;
use platefield::motion::Motion;
use platefield::play::lag::lagged_velocity;
use platefield::play::measure::{against_prediction, relative_l2, PlayOptions, PointPlay};
use platefield::play::windowed::{play_motion, MeasureOptions};
use platefield::request::Target;
use platefield::synth::{synthesize, ShakerLimits};
use platefield_report::table::Table;

/// A simulator failure as this probe reports it.
fn physical(e: impl std::fmt::Display) -> Error {
    Error::ContactLost(e.to_string())
}

/// The (warm-up, measured) cycle pairs played.
const WINDOWS: [(u32, u32); 5] = [(40, 1), (40, 20), (200, 20), (400, 20), (40, 100)];

/// The gap between `plays` and prediction `predict` (NaN where a steady
/// state fails).
fn gap(
    plays: &[&PointPlay],
    predict: &mut dyn FnMut(&PointPlay) -> std::result::Result<[f64; 2], String>,
) -> f64 {
    let real: Vec<[f64; 2]> = plays.iter().map(|p| p.realised).collect();
    let e: std::result::Result<Vec<[f64; 2]>, String> = plays.iter().map(|p| predict(p)).collect();
    e.map_or(f64::NAN, |e| relative_l2(&real, &e))
}

/// One table row: the four gaps and `against_prediction` for one window
/// (gaps, relative error and shape in %).
fn window_row(
    sim: &Simulator<'_>,
    sm: &platefield::play::ScheduleMotion,
    sampled: &[[f64; 2]],
    points: &[usize],
    settings: &FieldSettings,
    (warmup_cycles, measured_cycles): (u32, u32),
) -> Vec<String> {
    let t = sim.period();
    let steady = |r: [f64; 2]| sim.steady_state(r).map_err(|e| e.to_string());
    let mut plain = |r: [f64; 2]| steady(r).map(|s| s.velocity);
    let mut lagged = |r: [f64; 2]| {
        let s = steady(r)?;
        lagged_velocity(sim, r, &s).map_err(|e| e.to_string())
    };
    let options = MeasureOptions {
        warmup_cycles,
        measured_cycles,
        settle: true,
    };
    let plays = play_motion(sm, 1, sampled, points, settings, &options);
    let ok: Vec<&PointPlay> = plays.iter().filter(|p| p.note.is_none()).collect();
    let a = gap(&ok, &mut |p| p.expected(&mut plain));
    let b = gap(&ok, &mut |p| p.expected_cycles(&mut plain, t));
    let c = gap(&ok, &mut |p| p.expected(&mut lagged));
    let d = gap(&ok, &mut |p| p.expected_cycles(&mut lagged, t));
    let r = against_prediction(sm, plays, &PlayOptions::from_settings(settings));
    let pct = |x: f64| format!("{:.2}", 100.0 * x);
    vec![
        warmup_cycles.to_string(),
        measured_cycles.to_string(),
        pct(a),
        pct(b),
        pct(c),
        pct(d),
        pct(r.relative_error),
        format!("{:.4}", r.strength_ratio),
        pct(r.shape_error),
    ]
}

/// Sums of squares over the points of [`lag_theory`].
#[derive(Default)]
struct LagSums {
    /// |realised − F|², |F|², realised · F.
    off_f: f64,
    f: f64,
    dot: f64,
    /// |u − u*|², |u*|², |u − u* − e_theory|².
    slip_off: f64,
    slip: f64,
    theory_off: f64,
    /// |realised − v_theory|², |realised − lagged_velocity|².
    off_theory: f64,
    off_library: f64,
}

/// One cycle from phase 0 of a part at `r` slipping at `u`: where it ends
/// and its slip there.
fn cycle(sim: &Simulator<'_>, r: V2, u: V2) -> Result<(V2, V2)> {
    let mut st = PartState::new(r, u);
    sim.advance(0.0, sim.period(), &mut st, &r, None)
        .map_err(physical)?;
    Ok((st.r, st.u))
}

/// J = ∂u_end/∂u and D = ∂r_end/∂u at the fixed point u* (forward
/// differences of one cycle).
fn slip_jacobians(sim: &Simulator<'_>, r: V2, ustar: V2) -> Result<(Matrix2<f64>, Matrix2<f64>)> {
    let du = 1e-5 * ustar.norm().max(1e-3);
    let (rb, ub) = cycle(sim, r, ustar)?;
    let (mut j, mut d) = (Matrix2::zeros(), Matrix2::zeros());
    for c in 0..2 {
        let mut e = V2::zeros();
        e[c] = du;
        let (rp, up) = cycle(sim, r, ustar + e)?;
        j.set_column(c, &((up - ub) / du));
        d.set_column(c, &((rp - rb) / du));
    }
    Ok((j, d))
}

/// G = ∂u*/∂r (central differences of the steady state).
fn orbit_gradient(sim: &Simulator<'_>, r: V2) -> Result<Matrix2<f64>> {
    let h = 1e-4;
    let mut gm = Matrix2::zeros();
    for c in 0..2 {
        let (mut a, mut b) = ([r.x, r.y], [r.x, r.y]);
        a[c] += h;
        b[c] -= h;
        let sa = sim.steady_state(a).map_err(physical)?.start_slip;
        let sb = sim.steady_state(b).map_err(physical)?.start_slip;
        gm.set_column(c, &(V2::new(sa[0] - sb[0], sa[1] - sb[1]) / (2.0 * h)));
    }
    Ok(gm)
}

/// The part started at rest at `p`, played 40 cycles, then one more: its
/// contribution to `sums`.
fn lag_point(sim: &Simulator<'_>, p: [f64; 2], sums: &mut LagSums) -> Result<()> {
    let t = sim.period();
    let mut st = PartState::new(V2::new(p[0], p[1]), V2::zeros());
    for _ in 0..40 {
        let a = st.r;
        sim.advance(0.0, t, &mut st, &a, None).map_err(physical)?;
    }
    let (r, u) = (st.r, st.u);
    let real = (cycle(sim, r, u)?.0 - r) / t;
    let ss: SteadyState = sim.steady_state([r.x, r.y]).map_err(physical)?;
    let f = V2::from(ss.velocity);
    let ustar = V2::from(ss.start_slip);
    let (j, d) = slip_jacobians(sim, r, ustar)?;
    let gm = orbit_gradient(sim, r)?;
    let inv = (Matrix2::identity() - j)
        .try_inverse()
        .ok_or_else(|| physical("I − J is singular"))?;
    let e_th = -(inv * (gm * (f * t)));
    let v_th = f + d * e_th / t;
    let lib = V2::from(lagged_velocity(sim, [r.x, r.y], &ss).map_err(physical)?);
    sums.off_f += (real - f).norm_squared();
    sums.f += f.norm_squared();
    sums.dot += real.dot(&f);
    sums.slip_off += (u - ustar).norm_squared();
    sums.slip += ustar.norm_squared();
    sums.theory_off += (u - ustar - e_th).norm_squared();
    sums.off_theory += (real - v_th).norm_squared();
    sums.off_library += (real - lib).norm_squared();
    Ok(())
}

/// The adiabatic-lag check over the study's points: each played 40 cycles
/// from rest, then at phase 0 the part's slip u against the steady orbit's
/// u* through its position, and the one-cycle played velocity against F,
/// the first-order lag theory and [`lagged_velocity`].
fn lag_theory(sim: &Simulator<'_>, sampled: &[[f64; 2]], points: &[usize]) -> Result<String> {
    let mut s = LagSums::default();
    for &i in points {
        lag_point(sim, sampled[i], &mut s)?;
    }
    let pct = |a: f64, b: f64| 100.0 * (a / b).sqrt();
    Ok(format!(
        "- one-cycle played velocity against F: {:.2} % (played/F {:.4})\n\
         - slip at phase 0 off the steady orbit: |u − u*|/|u*| = {:.2} %\n\
         - first-order lag theory for u − u*: residual {:.1} % of |u − u*|\n\
         - one-cycle played velocity against the lag-corrected F of the theory: {:.2} %\n\
         - one-cycle played velocity against `play::lag::lagged_velocity`: {:.2} %\n",
        pct(s.off_f, s.f),
        s.dot / s.f,
        pct(s.slip_off, s.slip),
        pct(s.theory_off, s.slip_off),
        pct(s.off_theory, s.f),
        pct(s.off_library, s.f),
    ))
}

/// The section of `probes.md`.
pub(crate) fn section() -> Result<String> {
    let target = Target::load(Path::new("targets/sink.json"))?;
    let limits = ShakerLimits::lab_class();
    let settings = FieldSettings::default();
    let region = target
        .grid
        .ok_or_else(|| Error::invalid("grid", "targets/sink.json needs a grid"))?;
    let options = StudySettings::default().options();
    let s = synthesize(&target.field, &region, &limits, &settings, &options)?;
    let sampled = target.sample()?;
    let points = check_starts(&target, &sampled);
    let sm = synthesized_motion(&s)?;
    let motion = Motion::Signals(s.checked.motion.clone());
    let sim = settings.simulator(&motion);
    let mut md = format!(
        "\n## The model check over the measured window\n\n\
         The lab-class sink (`targets/sink.json`, `ShakerLimits::lab_class`) synthesized as in \
         `platefield study synthesis` ({}), moving parts played from rest at the model check's {} start \
         points. Relative L2 gap (%) between the parts' played displacement and each prediction from \
         the steady states F:\n\n",
        super::synthesis_line(&s),
        points.len()
    );
    let mut table = Table::new([
        "warm-up cycles",
        "measured cycles",
        "flow of F",
        "F per cycle",
        "flow of lagged F",
        "lagged F per cycle",
        "`against_prediction`",
        "its played/predicted",
        "its shape (%)",
    ]);
    for w in WINDOWS {
        table.row(window_row(
            &sim,
            &sm,
            &sampled.points,
            &points,
            &settings,
            w,
        ));
    }
    md.push_str(&table.markdown());
    md.push_str("\nThe lag at 40 cycles of warm-up, one cycle measured:\n\n");
    md.push_str(&lag_theory(&sim, &sampled.points, &points)?);
    Ok(md)
}
