//! Where the synthesized motions' realised-vs-predicted gap came from
//! (issue 11): the lab-class sink is synthesized as in `platefield
//! synthesis`, then played from rest at the study's points with different
//! warm-ups and measured spans. Each play is compared with four
//! predictions built from the motion's steady states F (see
//! `platefield::play::measure` and `platefield::play::lag`):
//!
//! * flow of F (the measure before this study),
//! * F iterated once per cycle (r ← r + T F(r): what F means),
//! * flow of the drift-lag-corrected F,
//! * the corrected F iterated once per cycle (the measure now, `verify`'s
//!   number, also printed from `against_prediction`).
//!
//! Then the cause of the lag part: the slip at phase 0 of a part played
//! 40 cycles against the steady orbit through its position, and the
//! first-order lag theory of `platefield::play::lag`.
//!
//! `cargo run --release --example vs_predicted_window`

use std::path::Path;

use platefield::design::closed_loop::measure::{play_motion, MeasureOptions};
use platefield::dynamics::{PartState, Simulator, V2};
use platefield::field::{FieldSettings, Grid};
use platefield::motion::Motion;
use platefield::play::lag::lagged_velocity;
use platefield::play::measure::{against_prediction, relative_l2, PlayOptions};
use platefield::request::Target;
use platefield::studies::synthesis::{starts, synthesized_motion, StudySettings};
use platefield::synth::{synthesize, ShakerLimits};

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/sink.json"))?;
    let limits = ShakerLimits::lab_class();
    let settings = FieldSettings::default();
    let Some(g) = target.grid.as_ref() else {
        return Err(platefield::Error::invalid(
            "grid",
            "targets/sink.json needs a grid",
        ));
    };
    let region = Grid {
        x: g.x,
        y: g.y,
        n: g.n,
    };
    let s = synthesize(
        &target.field,
        &region,
        &limits,
        &settings,
        &StudySettings::default().options(),
    )?;
    println!("lab sink: {}", s.summary());
    let sampled = target.sample()?;
    let points = starts(&target, &sampled);
    let sm = synthesized_motion(&s)?;
    let motion = Motion::Signals(s.motion.clone());
    let sim = settings.simulator(&motion);
    let t = sim.period();
    let steady = |r: [f64; 2]| sim.steady_state(r).map_err(|e| e.to_string());
    let mut plain = |r: [f64; 2]| steady(r).map(|s| s.velocity);
    let mut lagged = |r: [f64; 2]| {
        let s = steady(r)?;
        lagged_velocity(&sim, r, &s).map_err(|e| e.to_string())
    };
    println!("realised vs predicted (relative L2) by prediction:");
    println!("warm-up | measured | flow of F | F per cycle | flow of lagged F | lagged F per cycle | against_prediction");
    for (warmup_cycles, measured_cycles) in [(40, 1), (40, 20), (200, 20), (400, 20), (40, 100)] {
        let plays = play_motion(
            &sm,
            1,
            &sampled.points,
            &points,
            &settings,
            &MeasureOptions {
                warmup_cycles,
                measured_cycles,
                settle: true,
            },
        );
        let ok: Vec<_> = plays.iter().filter(|p| p.note.is_none()).collect();
        let real: Vec<[f64; 2]> = ok.iter().map(|p| p.realised).collect();
        let gap = |f: &mut dyn FnMut(
            &platefield::play::measure::PointPlay,
        ) -> Result<[f64; 2], String>| {
            let e: Result<Vec<[f64; 2]>, String> = ok.iter().map(|p| f(p)).collect();
            e.map_or(f64::NAN, |e| relative_l2(&real, &e))
        };
        let a = gap(&mut |p| p.expected(&mut plain));
        let b = gap(&mut |p| p.expected_cycles(&mut plain, t));
        let c = gap(&mut |p| p.expected(&mut lagged));
        let d = gap(&mut |p| p.expected_cycles(&mut lagged, t));
        let r = against_prediction(&sm, plays, &PlayOptions::from_settings(&settings));
        println!(
            "{warmup_cycles:>7} | {measured_cycles:>8} | {:>8.2} % | {:>10.2} % | {:>15.2} % | {:>17.2} % | {:.2} % (realised/predicted {:.4}, shape {:.2} %)",
            100.0 * a,
            100.0 * b,
            100.0 * c,
            100.0 * d,
            100.0 * r.relative_error,
            r.realised_scale,
            100.0 * r.shape_error
        );
    }
    lag_theory(&sim, &sampled.points, &points);
    Ok(())
}

/// The adiabatic-lag check: each point played 40 cycles from rest, then at
/// phase 0 the part's slip u against the steady orbit's u* through its
/// position, and the one-cycle realised velocity against F, against the
/// first-order lag theory (Jacobians by finite differences here, central in
/// r) and against `play::lag::lagged_velocity`.
fn lag_theory(sim: &Simulator<'_>, sampled: &[[f64; 2]], points: &[usize]) {
    let t = sim.period();
    let cyc = |r: V2, u: V2| -> (V2, V2) {
        let mut st = PartState::new(r, u);
        sim.advance(0.0, t, &mut st, &r, None).expect("contact");
        (st.r, st.u)
    };
    let mut lib_num = 0.0;
    let (mut num, mut den, mut dot, mut uu, mut us, mut lag_num, mut lag_den, mut th_num) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for &i in points {
        let p = sampled[i];
        let mut st = PartState::new(V2::new(p[0], p[1]), V2::zeros());
        for _ in 0..40 {
            let a = st.r;
            sim.advance(0.0, t, &mut st, &a, None).expect("contact");
        }
        let r = st.r;
        let u = st.u;
        let (r1, _) = cyc(r, u);
        let real = (r1 - r) / t;
        let ss = sim.steady_state([r.x, r.y]).expect("steady");
        let f = V2::new(ss.velocity[0], ss.velocity[1]);
        let ustar = V2::new(ss.start_slip[0], ss.start_slip[1]);
        // Jacobians at the fixed point: J = ∂u_end/∂u, D = ∂r_end/∂u, G = ∂u*/∂r.
        let du = 1e-5 * ustar.norm().max(1e-3);
        let (rb, ub) = cyc(r, ustar);
        let mut j = nalgebra::Matrix2::zeros();
        let mut d = nalgebra::Matrix2::zeros();
        for c in 0..2 {
            let mut e = V2::zeros();
            e[c] = du;
            let (rp, up) = cyc(r, ustar + e);
            j.set_column(c, &((up - ub) / du));
            d.set_column(c, &((rp - rb) / du));
        }
        let h = 1e-4;
        let mut gm = nalgebra::Matrix2::zeros();
        for c in 0..2 {
            let mut a = [r.x, r.y];
            let mut b = [r.x, r.y];
            a[c] += h;
            b[c] -= h;
            let sa = sim.steady_state(a).expect("steady").start_slip;
            let sb = sim.steady_state(b).expect("steady").start_slip;
            gm.set_column(c, &(V2::new(sa[0] - sb[0], sa[1] - sb[1]) / (2.0 * h)));
        }
        let step = f * t;
        let inv = (nalgebra::Matrix2::identity() - j)
            .try_inverse()
            .expect("I - J");
        let e_th = -(inv * (gm * step));
        let v_th = f + d * e_th / t;
        let lib = platefield::play::lag::lagged_velocity(sim, [r.x, r.y], &ss).expect("lag");
        lib_num += (real - V2::new(lib[0], lib[1])).norm_squared();
        num += (real - f).norm_squared();
        den += f.norm_squared();
        dot += real.dot(&f);
        uu += (u - ustar).norm_squared();
        us += ustar.norm_squared();
        lag_num += (u - ustar - e_th).norm_squared();
        lag_den += (u - ustar).norm_squared();
        th_num += (real - v_th).norm_squared();
        if i == points[points.len() / 4] {
            let ev = j.eigenvalues().map(|e| format!("{:.4} {:.4}", e[0], e[1]));
            println!("point {p:?}: J eigenvalues {ev:?} (or complex), |u*| {:.4} m/s, u-u* {:?}, theory {:?}", ustar.norm(), (u - ustar).as_slice(), e_th.as_slice());
        }
    }
    println!(
        "one-cycle realised vs F: {:.2} % (realised/F {:.4})",
        100.0 * (num / den).sqrt(),
        dot / den
    );
    println!(
        "slip at phase 0 off the steady orbit: |u - u*|/|u*| = {:.2} %",
        100.0 * (uu / us).sqrt()
    );
    println!(
        "first-order lag theory for u - u*: residual {:.1} % of |u - u*|",
        100.0 * (lag_num / lag_den).sqrt()
    );
    println!(
        "one-cycle realised vs lag-corrected F: {:.2} %",
        100.0 * (th_num / den).sqrt()
    );
    println!(
        "one-cycle realised vs play::lag::lagged_velocity: {:.2} %",
        100.0 * (lib_num / den).sqrt()
    );
}
