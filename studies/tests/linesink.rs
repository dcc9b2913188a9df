//! Section II of the paper: the simulator against eq. 17, the stick deadband,
//! contact loss, symmetries and convergence.

use platefield::dynamics::{Friction, Model, Numerics, SlipScheme};
use platefield::motion::V3;
use platefield_studies::linesink::{LineSink, Wave};

fn shaker(wave: Wave, accel: f64, depth: f64, period: f64, mu: f64) -> LineSink {
    LineSink {
        wave,
        accel,
        depth,
        period,
        friction: Friction::uniform(mu),
        gravity: 9.81,
    }
}

fn steps(n: usize) -> Numerics {
    Numerics {
        steps_per_cycle: n,
        ..Numerics::default()
    }
}

/// `steps(n)` with the given 2-D slip scheme (the 1-D results must not
/// depend on it).
fn steps_with(n: usize, slip: SlipScheme) -> Numerics {
    Numerics { slip, ..steps(n) }
}

/// Eq. 17 to ≤ 1e-9 relative error wherever its assumptions hold, over
/// several parameter sets, axes above and below, and any step count (the
/// square wave is piecewise constant, so the integration is exact).
#[test]
fn square_wave_matches_eq17_to_1e9() {
    let sets = [
        // (α, h, T, μ)
        (180.0, 0.05, 0.03, 0.3),
        (300.0, 0.04, 0.02, 0.2),
        (90.0, 0.12, 0.05, 0.45),
        (500.0, 0.01, 0.01, 0.1),
        (180.0, -0.05, 0.03, 0.3),
    ];
    let mut checked = 0;
    for (alpha, h, t, mu) in sets {
        let ls = shaker(Wave::Square, alpha, h, t, mu);
        let r_max = (9.81 / alpha).min((h.abs() * alpha / mu - 9.81) / alpha);
        let rs: Vec<f64> = [-0.9, -0.4, 0.1, 0.35, 0.7, 0.95]
            .iter()
            .map(|f| f * r_max)
            .collect();
        for (n, slip) in [2, 7, 64]
            .into_iter()
            .flat_map(|n| [(n, SlipScheme::Legacy), (n, SlipScheme::Stiff)])
        {
            for row in ls.rows(&rs, Model::PAPER, steps_with(n, slip)) {
                let eq17 = row.eq17.expect("assumptions hold by construction");
                let v = row.v_ss.expect("steady state exists");
                assert!(
                    ((v - eq17) / eq17).abs() <= 1e-9,
                    "α={alpha} h={h} T={t} μ={mu} r={} n={n} {slip:?}: v={v} eq17={eq17}",
                    row.r
                );
                assert_eq!(row.stick_fraction, Some(0.0));
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 5 * 3 * 2 * 6);
}

/// Eq. 17 is withheld outside its assumptions, and eq. 21 is its limit.
#[test]
fn eq17_only_under_its_assumptions() {
    let ls = shaker(Wave::Square, 180.0, 0.05, 0.03, 0.3);
    assert!(ls.eq17(0.02).is_some());
    assert!(ls.eq17(0.06).is_none(), "r > g/α: contact lost");
    assert!(
        shaker(Wave::Square, 180.0, 0.01, 0.03, 0.3)
            .eq17(0.01)
            .is_none(),
        "sticks"
    );
    assert!(shaker(Wave::Sine, 180.0, 0.05, 0.03, 0.3)
        .eq17(0.01)
        .is_none());
    let deep = shaker(Wave::Square, 180.0, 5.0, 0.03, 0.3);
    let r = 1e-3;
    // Relative correction μ²g²/(3h²α²) ≈ 3.6e-6 here, plus (rα/g)² terms.
    assert!(((deep.eq17(r).unwrap() - deep.eq21(r)) / deep.eq21(r)).abs() < 1e-5);
}

/// The sine at h = 1 cm: inside the deadband the part sticks for the whole
/// cycle and v_ss is exactly 0; the edge agrees with the stick condition
/// |a_x| ≤ μ g_eff found by scanning the plate kinematics over the cycle.
#[test]
fn small_depth_deadband() {
    let ls = shaker(Wave::Sine, 220.0, 0.01, 0.03, 0.3);
    let edge = ls.deadband_edge().expect("h A < μ g");
    // Independent edge: bisect on r for max over phase of |a_x| − μ g_eff.
    let motion = ls.motion();
    let holds = |r: f64| {
        (0..20000).all(|i| {
            let t = i as f64 / 20000.0 * 0.03;
            let k = motion.kinematics(t, 9.81, false);
            let a = k.acceleration_at(&V3::new(r, 0.0, 0.0), false);
            a.x.abs() <= 0.3 * (9.81 + a.z)
        })
    };
    let (mut lo, mut hi) = (0.0, 0.05);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if holds(mid) {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert!((lo - edge).abs() < 1e-7, "scan {lo} vs formula {edge}");
    for slip in [SlipScheme::Legacy, SlipScheme::Stiff] {
        let inside = [0.0, 0.3 * edge, -0.7 * edge, 0.999 * edge];
        for row in ls.rows(&inside, Model::PAPER, steps_with(64, slip)) {
            assert_eq!(row.v_ss, Some(0.0), "r = {} {slip:?}", row.r);
            assert_eq!(row.stick_fraction, Some(1.0), "r = {} {slip:?}", row.r);
        }
        let outside = [1.002 * edge, 1.05 * edge, 1.5 * edge];
        for row in ls.rows(&outside, Model::PAPER, steps_with(64, slip)) {
            let (v, s) = (row.v_ss.unwrap(), row.stick_fraction.unwrap());
            assert!(
                v < 0.0 && s < 1.0,
                "r = {} {slip:?}: v = {v}, stuck {s}",
                row.r
            );
        }
    }
}

/// Contact is lost beyond r = g/α and reported with where and when.
#[test]
fn contact_loss_is_flagged() {
    for (wave, accel) in [(Wave::Square, 180.0), (Wave::Sine, 220.0)] {
        let ls = shaker(wave, accel, 0.05, 0.03, 0.3);
        let r_max = 9.81 / accel;
        let rows = ls.rows(&[0.98 * r_max, 1.02 * r_max], Model::PAPER, steps(64));
        assert!(!rows[0].contact_lost && rows[0].v_ss.is_some());
        assert!(rows[1].contact_lost && rows[1].v_ss.is_none());
        let c = rows[1].contact_loss.unwrap();
        assert!(c.normal < 0.0 && (0.0..1.0).contains(&c.phase));
        // g_eff = g + r α(t) < 0 happens only while α(t) < 0: the second half-cycle.
        assert!(c.phase >= 0.5, "phase {}", c.phase);
    }
}

/// The terms the paper drops change v_ss by a few percent, not more.
#[test]
fn full_model_differs_by_a_few_percent() {
    let ls = shaker(Wave::Sine, 220.0, 0.05, 0.03, 0.3);
    for r in [0.01, 0.02, 0.04] {
        let paper = ls.rows(&[r], Model::PAPER, steps(64))[0].v_ss.unwrap();
        let full = ls.rows(&[r], Model::FULL, steps(64))[0].v_ss.unwrap();
        let rel = ((full - paper) / paper).abs();
        assert!(rel > 0.005 && rel < 0.06, "r = {r}: {rel}");
    }
}

/// Mirror symmetry: a symmetric oscillation maps to itself under x → −x
/// with a half-period shift, so the frozen v_ss is odd in r.
#[test]
fn steady_velocity_is_odd_in_r() {
    for model in [
        Model::PAPER,
        Model {
            moving: false,
            ..Model::FULL
        },
    ] {
        let ls = shaker(Wave::Sine, 220.0, 0.03, 0.03, 0.3);
        let rows = ls.rows(&[0.015, -0.015, 0.0], model, steps(64));
        let (a, b) = (rows[0].v_ss.unwrap(), rows[1].v_ss.unwrap());
        assert!((a + b).abs() < 1e-12, "{a} vs {b}");
        assert!(rows[2].v_ss.unwrap().abs() < 1e-12);
    }
}

/// Fourth-order convergence for the sine (where integration is not exact),
/// against a converged 2¹⁴-step run.
#[test]
fn sine_converges_at_fourth_order() {
    let ls = shaker(Wave::Sine, 220.0, 0.02, 0.03, 0.3);
    let at = |n| ls.rows(&[0.02], Model::PAPER, steps(n))[0].v_ss.unwrap();
    let reference = at(16384);
    let err = |n| ((at(n) - reference) / reference).abs();
    let (e32, e128) = (err(32), err(128));
    assert!(e128 < 1e-8, "e128 = {e128}");
    // Two doublings at order 4 give 256×; demand at least 64×.
    assert!(e32 / e128 > 64.0, "e32 = {e32}, e128 = {e128}");
}
