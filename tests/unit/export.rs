//! `platefield export` as a controller plays it: every shipped design's
//! exported CSV, each sample held for its interval and the file looped, must
//! bring the plate back to rest in the home pose every period (issue 11:
//! point samples drifted 4.8e-3 rad per period at 20 kHz).

use crate::schedule::export::{export, signals_csv, RAMP_CYCLES};
use crate::schedule::Schedule;

#[path = "../common/plate.rs"]
mod plate;

/// Plays the six held signals of `csv` over `loops` loops of the file as
/// the header states them (`common/plate.rs`: the linear channels per
/// axis, the angular ones composed as a rotation) and returns the largest
/// distance and angle from home and |velocity| at the end of any loop.
fn drift(csv: &str, loops: usize) -> (f64, f64) {
    let (dt, rows) = plate::read_export(csv);
    let mut p = plate::Plate::rest();
    let (mut pose, mut vel) = (0.0_f64, 0.0_f64);
    for _ in 0..loops {
        for a in &rows {
            p.hold(a, dt, 1);
        }
        let home = plate::angle_between(&p.q, &[1.0, 0.0, 0.0, 0.0]);
        pose = p.x.iter().fold(pose.max(home), |m, x| m.max(x.abs()));
        vel = p.v.iter().chain(&p.w).fold(vel, |m, x| m.max(x.abs()));
    }
    (pose, vel)
}

#[test]
fn every_shipped_export_returns_to_rest_each_period() {
    for name in [
        "sink",
        "saddle",
        "squeeze_trans",
        "whirlpool",
        "line_sink",
        "jet",
        "line_sink_30",
        "sink_trans",
        "sequenced/sink",
        "sequenced/saddle",
        "sequenced/whirlpool",
        "sequenced/line_sink_30",
        "sequenced/squeeze_trans",
    ] {
        let path = format!("results/{name}/schedule.json");
        let schedule = Schedule::load(std::path::Path::new(&path)).unwrap();
        let csv = signals_csv(&schedule, 20_000.0).unwrap();
        let (pose, vel) = drift(&csv, 15);
        assert!(
            pose < 1e-6 && vel < 1e-6,
            "{name}: after 15 periods pose {pose:.2e} (m, rad), velocity {vel:.2e} (m/s, rad/s)"
        );
    }
}

/// A lab-like six-signal motion as a schedule segment's `motion` object
/// (scene `signals` format): circular x/y translation and two tilts.
fn lab_motion_json() -> serde_json::Value {
    serde_json::json!({
        "period": 0.05,
        "linear": {
            "x": [{"amplitude": 10.0, "phase": std::f64::consts::FRAC_PI_2}],
            "y": [{"amplitude": 10.0, "phase": 0.0}]
        },
        "angular": {
            "x": [{"amplitude": 70.0, "phase": 0.4}],
            "y": [{"amplitude": 70.0, "phase": 2.0}]
        }
    })
}

/// The sequenced sink schedule (`results/sequenced/sink`) with its segments replaced by `segments`.
fn with_segments(segments: serde_json::Value) -> String {
    let text = std::fs::read_to_string("results/sequenced/sink/schedule.json").unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["segments"] = segments;
    v.to_string()
}

/// A schedule segment holding a six-signal motion loads (duration derived
/// from its period), is played by `PlayedSegment::from_segment`, and its
/// export ramps in from rest, plays the steady cycles and ramps out: the
/// file integrated as a sample-and-hold controller plays it ends at rest at
/// home to < 1e-6, over 15 loops of the file; the steady part's samples
/// equal the motion's mean acceleration per interval (peak within 0.1 % of
/// the amplitude, 1000 samples per cycle).
#[test]
fn a_six_signal_segment_exports_with_ramps_back_to_rest() {
    let text = with_segments(serde_json::json!([{
        "label": "synthesized", "motion": lab_motion_json(),
        "weight": 1.0, "cycles": 20, "duration_s": 0.0
    }]));
    let s = Schedule::from_json_str(&text, "text").unwrap();
    assert!((s.segments[0].duration_s - 1.0).abs() < 1e-12);
    assert!((s.period_s - 1.0).abs() < 1e-12);
    let played = crate::play::ScheduleMotion::from_schedule(&s).unwrap();
    assert!(matches!(
        played.segments()[0].motion,
        Some(crate::motion::Motion::Signals(_))
    ));
    let e = export(&s, 20_000.0, 20).unwrap();
    assert_eq!(e.ramped, Some(20));
    assert_eq!(
        e.samples.samples.len(),
        1000 * (20 + 2 * RAMP_CYCLES as usize)
    );
    assert!(
        e.describe().contains("ramp-in from rest"),
        "{}",
        e.describe()
    );
    let csv = e.samples.to_csv();
    assert_eq!(csv, signals_csv(&s, 20_000.0).unwrap());
    let (pose, vel) = drift(&csv, 15);
    assert!(
        pose < 1e-6 && vel < 1e-6,
        "pose {pose:.2e}, velocity {vel:.2e}"
    );
    let steady_peak = e.samples.samples
        [1000 * RAMP_CYCLES as usize..1000 * (RAMP_CYCLES as usize + 20)]
        .iter()
        .map(|a| a[0].abs())
        .fold(0.0, f64::max);
    assert!((steady_peak / 10.0 - 1.0).abs() < 1e-3, "{steady_peak}");
    // Without the ramp the same motion played from rest drifts: the
    // steady cycle alone does not return to rest at home.
    let looped =
        crate::motion::sample_hold::periodic(&s.segments[0].plate_motion().unwrap(), 20_000.0)
            .unwrap()
            .to_csv();
    let (pose_loop, _) = drift(&looped, 1);
    assert!(pose_loop > 1e-4, "{pose_loop}");
}

/// Schedules without a six-signal segment keep their format: the `motion`
/// key is absent when written, and the shipped file reads back to the same
/// schedule. Bad signals, or a primitive and a motion in one segment, are
/// errors naming the JSON path.
#[test]
fn motion_segments_keep_the_format_and_name_paths() {
    let path = std::path::Path::new("results/sequenced/sink/schedule.json");
    let s = Schedule::load(path).unwrap();
    let json = s.to_json().unwrap();
    assert!(!json.contains("\"motion\""));
    assert_eq!(Schedule::from_json_str(&json, "text").unwrap(), s);

    let mut bad = lab_motion_json();
    bad["linear"]["x"][0]["harmonic"] = serde_json::json!(0);
    let text = with_segments(serde_json::json!([{
        "label": "m", "motion": bad, "weight": 1.0, "cycles": 1, "duration_s": 0.0
    }]));
    let e = Schedule::from_json_str(&text, "f").unwrap_err().to_string();
    assert!(e.contains("segments[0].motion.linear.x"), "{e}");

    let mut bad = lab_motion_json();
    bad["linear"]["x"][0]["amplitud"] = serde_json::json!(1.0);
    let text = with_segments(serde_json::json!([{
        "label": "m", "motion": bad, "weight": 1.0, "cycles": 1, "duration_s": 0.0
    }]));
    let e = Schedule::from_json_str(&text, "f").unwrap_err().to_string();
    assert!(
        e.contains("segments[0].motion.linear.x[0]") && e.contains("amplitud"),
        "{e}"
    );

    let text = std::fs::read_to_string(path).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["segments"][0]["motion"] = lab_motion_json();
    let e = Schedule::from_json_str(&v.to_string(), "f")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("segments[0].motion") && e.contains("not both"),
        "{e}"
    );
    // A six-signal segment beside primitives must ramp (`ramp_cycles`).
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["segments"][0]["primitive"] = serde_json::Value::Null;
    v["segments"][0]["motion"] = lab_motion_json();
    let e = Schedule::from_json_str(&v.to_string(), "f")
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("segments[0].ramp_cycles") && e.contains("ramp in"),
        "{e}"
    );
}

/// A mixed schedule — a primitive and a six-signal motion that ramps in
/// from rest and out to rest inside its own cycles (`ramp_cycles`) — loads,
/// is played with the windowed motion, and exports as one looped period
/// whose sample-and-hold integration returns to rest at home every period
/// (< 1e-6 over 15 loops), with the ramp's acceleration overshoot within
/// its bound 1.875/(πR) + 0.146/R² of the steady peak. Without
/// `ramp_cycles` the six-signal segment would make the plate jump at its
/// joins: an error naming the path.
#[test]
fn a_mixed_schedule_ramps_its_six_signal_segment_and_returns_to_rest() {
    let text = std::fs::read_to_string("results/sequenced/sink/schedule.json").unwrap();
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let primitive = v["segments"][0].clone();
    let period = Schedule::from_json_str(&text, "t").unwrap().segments[0]
        .cycle_period()
        .unwrap();
    let mut motion = lab_motion_json();
    motion["period"] = serde_json::json!(period);
    let (ramp, cycles) = (4_u32, 12_u32);
    let mixed = |ramp: Option<u32>| {
        let mut seg = serde_json::json!({
            "label": "Synthesized", "motion": motion.clone(),
            "weight": 0.5, "cycles": cycles, "duration_s": 0.0
        });
        if let Some(r) = ramp {
            seg["ramp_cycles"] = serde_json::json!(r);
        }
        with_segments(serde_json::json!([primitive.clone(), seg]))
    };
    let e = Schedule::from_json_str(&mixed(None), "text").unwrap_err();
    assert!(e.to_string().contains("segments[1].ramp_cycles"), "{e}");
    let e = Schedule::from_json_str(&mixed(Some(7)), "text").unwrap_err();
    assert!(e.to_string().contains("segments[1].ramp_cycles"), "{e}");

    let s = Schedule::from_json_str(&mixed(Some(ramp)), "text").unwrap();
    let played = crate::play::ScheduleMotion::from_schedule(&s).unwrap();
    assert!(matches!(
        played.segments()[1].motion,
        Some(crate::motion::Motion::Ramped(_))
    ));
    let e = export(&s, 20_000.0, 20).unwrap();
    assert_eq!(e.ramped, None, "a mixed schedule is one looped period");
    let csv = e.samples.to_csv();
    let (pose, vel) = drift(&csv, 15);
    assert!(
        pose < 1e-6 && vel < 1e-6,
        "pose {pose:.2e}, velocity {vel:.2e}"
    );
    let n = e.samples.samples.len();
    let first = (s.segments[0].duration_s / e.samples.dt).round() as usize;
    let six = &e.samples.samples[first..n];
    let peak = six.iter().map(|a| a[0].abs()).fold(0.0, f64::max);
    let r = f64::from(ramp);
    let bound = 10.0 * (1.0 + 1.875 / (std::f64::consts::PI * r) + 0.146 / (r * r));
    assert!(peak > 9.9 && peak <= bound, "{peak} vs {bound}");
    // The segment begins and ends at rest: its first and last samples are
    // the ramp's, a few percent of the steady amplitude.
    assert!(six[0][0].abs() < 0.05 && six[six.len() - 1][0].abs() < 0.05);
}

/// The mean over [t0, t0 + h] of `f` by 4-point Gauss–Legendre (exact for
/// polynomials of degree 7; the signals are smooth within a sample).
fn gauss_mean(f: &dyn Fn(f64) -> [f64; 6], t0: f64, h: f64) -> [f64; 6] {
    let (a, b) = (0.339_981_043_584_856_3, 0.861_136_311_594_052_6);
    let (wa, wb) = (0.652_145_154_862_546_1, 0.347_854_845_137_453_9);
    let mut m = [0.0; 6];
    for (x, w) in [(-b, wb), (-a, wa), (a, wa), (b, wb)] {
        let v = f(t0 + 0.5 * h * (1.0 + x));
        for i in 0..6 {
            m[i] += 0.5 * w * v[i];
        }
    }
    m
}

/// (linear, world angular) plate-centre acceleration of `motion` at `t`, as six numbers.
fn six(motion: &crate::motion::Motion, t: f64) -> [f64; 6] {
    let (l, a) = crate::schedule::export::world_acceleration(motion, t);
    [l.x, l.y, l.z, a.x, a.y, a.z]
}

/// Each exported sample is the mean plate-centre acceleration over its
/// interval (the sample-and-hold exactness the return-to-rest tests rely
/// on, here checked against an independent evaluation): every sample of the
/// sequenced sink schedule (LineSinks, joins on sample boundaries) against
/// a Gauss–Legendre mean of `centre_acceleration` over that interval of its
/// segment, and the steady samples of a six-signal motion likewise; within
/// 1e-9 of the peak of its group, linear or angular (measured: about 1e-13). A periodic but wrong
/// velocity (a sign, a phase) still returns to rest; this does not.
#[test]
fn every_sample_is_the_mean_acceleration_over_its_interval() {
    let check = |samples: &[[f64; 6]], dt: f64, at: &dyn Fn(f64) -> [f64; 6], label: &str| {
        // Per group (linear, angular): an angular z made only of the
        // tilts' second-order rotation peaks at 1e-4 of the tilts.
        let mut peak = [0.0_f64; 6];
        for s in samples {
            for (i, v) in s.iter().enumerate() {
                let g = 3 * (i / 3);
                peak[g] = peak[g].max(v.abs());
            }
        }
        for i in [1, 2, 4, 5] {
            peak[i] = peak[3 * (i / 3)];
        }
        let mut worst = 0.0_f64;
        for (k, s) in samples.iter().enumerate() {
            let m = gauss_mean(at, k as f64 * dt, dt);
            for i in 0..6 {
                if peak[i] > 0.0 {
                    worst = worst.max((s[i] - m[i]).abs() / peak[i]);
                }
            }
        }
        assert!(
            worst < 1e-9,
            "{label}: worst sample off by {worst:.2e} of its axis peak"
        );
        println!("{label}: worst {worst:.2e} of the axis peak");
    };
    // Primitives, one period of the schedule.
    let s = Schedule::load(std::path::Path::new("results/sequenced/sink/schedule.json")).unwrap();
    let e = export(&s, 20_000.0, 20).unwrap();
    let segs: Vec<(f64, f64, crate::motion::Motion)> = {
        let mut t = 0.0;
        s.segments
            .iter()
            .map(|g| {
                let start = t;
                t += g.duration_s;
                (start, t, g.plate_motion().expect("a moving segment"))
            })
            .collect()
    };
    let at = |t: f64| -> [f64; 6] {
        let (start, _, m) = segs
            .iter()
            .find(|(a, b, _)| t >= *a && t < *b)
            .unwrap_or(&segs[segs.len() - 1]);
        six(m, t - start)
    };
    check(&e.samples.samples, e.samples.dt, &at, "sequenced sink");
    // A six-signal motion: its steady cycles, after the ramp-in's whole cycles.
    let text = with_segments(serde_json::json!([{
        "label": "synthesized", "motion": lab_motion_json(),
        "weight": 1.0, "cycles": 20, "duration_s": 0.0
    }]));
    let s = Schedule::from_json_str(&text, "text").unwrap();
    let e = export(&s, 20_000.0, 20).unwrap();
    let m: crate::motion::Signals = serde_json::from_value(lab_motion_json()).unwrap();
    let m = crate::motion::Motion::Signals(m);
    let n = e.samples.samples_per_period;
    let ramp = n * RAMP_CYCLES as usize;
    let steady = &e.samples.samples[ramp..ramp + 20 * n];
    let t0 = ramp as f64 * e.samples.dt;
    check(
        steady,
        e.samples.dt,
        &|t| six(&m, t0 + t),
        "six-signal steady part",
    );
}

/// Every export's peaks, closed form for one harmonic: a channel
/// A sin(nωt + φ) has peak velocity A/(nω) and stroke A/(nω)² (its
/// zero-mean integrals), to the sampling's 1 − cos(π/4096) ≈ 3e-7.
#[test]
fn steady_peaks_of_one_harmonic_are_the_closed_form() {
    use crate::motion::{Axes, FourierTerm, Signals};
    use crate::schedule::export::harmonics::of_signals;
    let term = |amplitude, harmonic, phase| FourierTerm {
        amplitude,
        phase,
        harmonic,
    };
    let period = 0.05;
    let s = Signals {
        period,
        linear: Axes {
            x: vec![term(10.0, 1, 0.3)],
            ..Axes::default()
        },
        angular: Axes {
            z: vec![term(-70.0, 2, -1.1)],
            ..Axes::default()
        },
    };
    let h = of_signals(&s);
    let w = std::f64::consts::TAU / period;
    for (axis, a, n) in [(0, 10.0, 1.0), (5, 70.0, 2.0)] {
        let p = &h.peaks;
        let rel = |got: f64, want: f64| (got / want - 1.0).abs();
        assert!(rel(p.acceleration[axis], a) < 1e-6, "{p:?}");
        assert!(rel(p.velocity[axis], a / (n * w)) < 1e-6, "{p:?}");
        assert!(rel(p.stroke[axis], a / (n * w * n * w)) < 1e-6, "{p:?}");
    }
    assert_eq!(h.peaks.stroke[1], 0.0);
    // The negative amplitude is written as |A| at φ + π: the same signal.
    for k in 0..50 {
        let t = period * k as f64 / 50.0;
        let want = -70.0 * (2.0 * w * t - 1.1).sin();
        assert!((h.value(5, t) - want).abs() < 1e-12);
    }
}

/// The peaks an export states for a schedule (the held samples integrated
/// as played) against the exact kinematics of its screws (`centre_state`
/// sampled densely over each segment's period) and, for the rest-to-rest
/// LineSinks of the sequenced sink (ψ = ψ₀(1 − cos ωt), ψ₀ = 0.005 rad),
/// the closed form: angular stroke 2ψ₀, angular velocity ψ₀ω, on x and y.
#[test]
fn played_peaks_match_the_exact_kinematics() {
    use crate::motion::sample_hold::centre_state;
    let s = Schedule::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/results/sequenced/sink/schedule.json"
    )))
    .unwrap();
    let p = export(&s, 20_000.0, 0).unwrap().peaks();
    let (mut v, mut x) = ([0.0_f64; 6], [0.0_f64; 6]);
    for m in s.segments.iter().filter_map(|g| g.plate_motion()) {
        for k in 0..4096 {
            let st = centre_state(&m, m.period() * k as f64 / 4096.0);
            for i in 0..6 {
                v[i] = v[i].max(st.velocity[i].abs());
                x[i] = x[i].max(st.pose[i].abs());
            }
        }
    }
    for i in 0..6 {
        // Held samples: velocities exact at the hold ends (96 per cycle),
        // so a peak is under-sampled by at most 1 − cos(π/96) ≈ 5e-4.
        let close = |a: f64, b: f64| (a - b).abs() <= 2e-3 * b.max(1e-12) + 1e-12;
        assert!(
            close(p.velocity[i], v[i]),
            "axis {i}: velocity {} against {}",
            p.velocity[i],
            v[i]
        );
        assert!(
            close(p.stroke[i], x[i]),
            "axis {i}: stroke {} against {}",
            p.stroke[i],
            x[i]
        );
    }
    let (psi0, omega) = (0.005, 209.0);
    for i in [3, 4] {
        assert!((p.stroke[i] / (2.0 * psi0) - 1.0).abs() < 2e-3, "{p:?}");
        assert!((p.velocity[i] / (psi0 * omega) - 1.0).abs() < 2e-3, "{p:?}");
    }
}

/// A six-signal export keeps within the shaker limits its schedule
/// records. The quintic pose ramp w(t)·x(t) has acceleration
/// w ẍ + 2ẇẋ + ẅx, which over 10 ramp cycles exceeds the steady amplitude
/// by at most 2.1e-4 for one harmonic (computed from that formula over 12
/// phases at 4e5 points per ramp). With the limits at the motion's
/// amplitudes the export plays the signals scaled by a factor in
/// [1/(1 + 2.1e-4), 1) and says so, and the file is within every limit;
/// with them 3e-4 higher it is not scaled; a stroke limit 0.9 of the
/// steady stroke A/ω² scales it to about 0.9 (the ramps' stroke is the
/// steady one's at most, so within 1e-3 of it). A forbidden angular axis
/// the exact rotation turns is its own line, not an excess.
#[test]
fn six_signal_exports_state_peaks_over_the_schedules_limits() {
    let text = with_segments(serde_json::json!([{
        "label": "synthesized", "motion": lab_motion_json(),
        "weight": 1.0, "cycles": 20, "duration_s": 0.0
    }]));
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let limits = |scale: f64, stroke: Option<f64>| {
        let mut l = serde_json::json!({
            "period": 0.05, "linear": [10.0 * scale, 10.0 * scale, 0.0],
            "angular": [70.0 * scale, 70.0 * scale, 1.0], "harmonics": 1, "contact_margin": 0.1
        });
        if let Some(s) = stroke {
            l["stroke"] = serde_json::json!({"linear": [s, s, 1.0]});
        }
        l
    };
    let export_with = |v: &mut serde_json::Value, l: serde_json::Value| {
        v["played"]["limits"] = l;
        let s = Schedule::from_json_str(&v.to_string(), "text").unwrap();
        export(&s, 20_000.0, 5).unwrap()
    };
    // Forbidden, the angular z axis is turned by the tilts' exact rotation
    // (second order in the tilt angles), and its own line says so.
    let mut none_about_z = limits(1.0003, None);
    none_about_z["angular"][2] = serde_json::json!(0.0);
    let coning = export_with(&mut v, none_about_z);
    assert!(
        coning.over_limits().is_empty(),
        "{:?}",
        coning.over_limits()
    );
    let turns = coning.undriven_turns();
    assert_eq!(turns.len(), 1, "{turns:?}");
    assert!(
        turns[0].contains("angular.z") && turns[0].contains("the exact rotation"),
        "{turns:?}"
    );
    let e = export_with(&mut v, limits(1.0, None));
    assert!(e.over_limits().is_empty(), "{:?}", e.over_limits());
    assert!(
        e.scale < 1.0 && e.scale >= 1.0 / (1.0 + 2.1e-4),
        "{}",
        e.scale
    );
    let line = e.scaled().unwrap();
    assert!(
        line.contains("ramps keep within the shaker limits"),
        "{line}"
    );
    assert!(e.to_csv().contains(&format!("# {line}")));
    let roomy = export_with(&mut v, limits(1.0003, None));
    assert_eq!(roomy.scale, 1.0);
    assert!(roomy.scaled().is_none() && roomy.over_limits().is_empty());
    let steady_stroke = 10.0 / (std::f64::consts::TAU / 0.05).powi(2);
    let stroke = export_with(&mut v, limits(1.0003, Some(0.9 * steady_stroke)));
    assert!(
        stroke.over_limits().is_empty(),
        "{:?}",
        stroke.over_limits()
    );
    assert!((stroke.scale - 0.9).abs() < 1e-3, "{}", stroke.scale);
    assert_eq!(
        export_with(&mut v, limits(1.0003, Some(1.001 * steady_stroke))).scale,
        1.0
    );
}
