//! Why realised and predicted differ for a synthesized motion (issue 11).
//!
//! Lab-class sink synthesized as in `platefield synthesis`; each start point
//! played 40 cycles from rest, then per cycle k at phase 0 the part's
//! position r_k and slip u_k are compared with the steady orbit through r_k
//! (`steady_state(r_k)`: slip u*, mean velocity F). Printed: the one-cycle
//! realised velocity against F, ‖u − u*‖, and the first-order adiabatic-lag
//! prediction of u − u* from the cycle map's Jacobians.
//!
//! `cargo run --release --example vs_predicted_cause`

use std::path::Path;

use platefield::dynamics::{PartState, Simulator, V2};
use platefield::field::{FieldSettings, Grid};
use platefield::motion::Motion;
use platefield::request::Target;
use platefield::studies::synthesis::{starts, StudySettings};
use platefield::synth::{synthesize, ShakerLimits};

fn main() -> platefield::Result<()> {
    let target = Target::load(Path::new("targets/sink.json"))?;
    let limits = ShakerLimits::lab_class();
    let settings = FieldSettings::default();
    let g = target.grid.as_ref().expect("grid");
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
    let pts = starts(&target, &sampled);
    let motion = Motion::Signals(s.motion.clone());
    let sim = Simulator::new(
        &motion,
        settings.friction,
        settings.gravity,
        settings.model,
        settings.numerics,
    );
    let t = sim.period();
    let cyc = |r: V2, u: V2| -> (V2, V2) {
        let mut st = PartState::new(r, u);
        sim.advance(0.0, t, &mut st, &r, None).expect("contact");
        (st.r, st.u)
    };
    let mut lib_num = 0.0;
    let (mut num, mut den, mut dot, mut uu, mut us, mut lag_num, mut lag_den, mut th_num) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for &i in &pts {
        let p = sampled.points[i];
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
        let lib = platefield::play::lag::lagged_velocity(&sim, [r.x, r.y], &ss).expect("lag");
        lib_num += (real - V2::new(lib[0], lib[1])).norm_squared();
        num += (real - f).norm_squared();
        den += f.norm_squared();
        dot += real.dot(&f);
        uu += (u - ustar).norm_squared();
        us += ustar.norm_squared();
        lag_num += (u - ustar - e_th).norm_squared();
        lag_den += (u - ustar).norm_squared();
        th_num += (real - v_th).norm_squared();
        if i == pts[pts.len() / 4] {
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
    Ok(())
}
