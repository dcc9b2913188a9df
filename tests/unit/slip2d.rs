//! Convergence of the zero-velocity force field with the number of steps per
//! cycle, per primitive (issue 12: high-order 2-D Coulomb slip near u = 0).
//!
//! The harness recomputes a force field serially, exactly as
//! `Field::compute` does (checked bitwise), counting RK4 steps and timing
//! the one-cycle simulations, and compares it with a reference field at many
//! more steps per cycle (relative L2 over all samples).
//!
//! * `order_2d` (default suite, seconds): the regularised scheme's error at
//!   64 steps and observed order for the five 2-D primitives on a small grid.
//! * `rotated_linesink` (default suite): a 1-D slip along a rotated line
//!   stays exact to 1e-6 in every scheme.
//! * `quick_velocity` (ignored, seconds): steady-state velocity fields per
//!   scheme against the regularised scheme at 1024 steps.
//! * `quick_table` (ignored, seconds): the same at 16…128 steps
//!   (`SLIP2D_STEPS=64,128,256` for others) for any
//!   scheme, with RK4 steps and CPU per cycle:
//!   `SLIP2D_SCHEME=legacy cargo test --release --lib dynamics::integrator::slip2d_tests -- --ignored --nocapture quick_table`.
//! * `convergence_table` (ignored; minutes): the full table, every primitive,
//!   11×11 grid, 30 phases, 8…128 steps against a 4096-step reference:
//!   `cargo test --release --lib dynamics::integrator::slip2d_tests -- --ignored --nocapture convergence_table`
//!   (`SLIP2D_REF=16384` for a finer reference, `SLIP2D_SCHEME=legacy` or
//!   `stiff` for the older schemes — against the stiff scheme's reference
//!   —, `SLIP2D_ONLY=Circle,Trans` for some primitives).

use std::time::Instant;

use crate::basis::{Library, Primitive, PrimitiveKind};
use crate::dynamics::{CycleOutcome, PartState, SlipScheme, TrajectoryPoint};
use crate::field::{Field, FieldKind, FieldSettings, Grid};
use crate::motion::{Invariance, Motion, V3};
use nalgebra::Vector2;

/// One serially computed force field and what it cost.
struct Measured {
    vectors: Vec<[f64; 2]>,
    /// RK4 steps per one-cycle simulation.
    steps_per_cycle: f64,
    /// CPU time per one-cycle simulation (µs), one thread.
    micros_per_cycle: f64,
}

fn settings(steps: usize, scheme: SlipScheme) -> FieldSettings {
    let mut s = FieldSettings::default();
    s.numerics.steps_per_cycle = steps;
    s.numerics.slip = scheme;
    s
}

/// The environment variable `key` parsed, or `default`.
fn env_or<T: std::str::FromStr>(key: &str, default: T) -> T {
    std::env::var(key)
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(default)
}

fn scheme_from_env() -> SlipScheme {
    match std::env::var("SLIP2D_SCHEME").as_deref() {
        Ok("legacy") => SlipScheme::Legacy,
        Ok("stiff") => SlipScheme::Stiff,
        _ => SlipScheme::Regularised,
    }
}

/// The force field of `p` on `grid`, serially, as `field::force::sample`.
fn measure(p: &Primitive, grid: &Grid, phases: usize, settings: &FieldSettings) -> Measured {
    let motion = p.motion();
    let sim = settings.simulator(&motion);
    let period = sim.period();
    let plate_velocity = |t: f64, r: &Vector2<f64>, anchor: &Vector2<f64>| {
        let k = sim.motion().kinematics(t, sim.gravity(), sim.model().tilt);
        let q = if sim.model().moving { r } else { anchor };
        let v = k.velocity_at(&V3::new(q.x, q.y, 0.0));
        Vector2::new(v.x, v.y)
    };
    let mut steps = 0u64;
    let mut cycles = 0u64;
    let start = Instant::now();
    let cpu0 = thread_cpu_seconds();
    let vectors = grid
        .points()
        .iter()
        .map(|p| {
            let anchor = Vector2::from(*p);
            let mut sum = Vector2::zeros();
            for j in 0..phases {
                let t0 = period * j as f64 / phases as f64;
                let mut state = PartState::new(anchor, -plate_velocity(t0, &anchor, &anchor));
                let out = sim
                    .advance(t0, t0 + period, &mut state, &anchor, None)
                    .expect("no contact loss in the default primitives");
                steps += out.rk4_steps as u64;
                cycles += 1;
                sum += (plate_velocity(t0 + period, &state.r, &anchor) + state.u) / period;
            }
            let f = sum / phases as f64;
            [f.x, f.y]
        })
        .collect();
    // CPU time of this thread where the platform reports it (the machine
    // is shared), wall time otherwise.
    let seconds = match (cpu0, thread_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => start.elapsed().as_secs_f64(),
    };
    Measured {
        vectors,
        steps_per_cycle: steps as f64 / cycles as f64,
        micros_per_cycle: 1e6 * seconds / cycles as f64,
    }
}

/// CPU time of the calling thread (s), from /proc/thread-self/schedstat
/// (nanoseconds on the CPU); `None` elsewhere.
fn thread_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

fn reference(p: &Primitive, grid: &Grid, phases: usize, settings: &FieldSettings) -> Field {
    let mut s = *settings;
    s.phases = phases;
    Field::compute(&p.motion(), grid, FieldKind::Force, &s, &|| {})
}

fn relative_l2(a: &[[f64; 2]], r: &[[f64; 2]]) -> f64 {
    let (mut num, mut den) = (0.0, 0.0);
    for (f, g) in a.iter().zip(r) {
        num += (f[0] - g[0]).powi(2) + (f[1] - g[1]).powi(2);
        den += g[0] * g[0] + g[1] * g[1];
    }
    (num / den).sqrt()
}

/// Errors of `p`'s force field at each of `steps` against `reference_steps`.
fn errors(
    p: &Primitive,
    grid: &Grid,
    phases: usize,
    steps: &[usize],
    reference_steps: usize,
    scheme: SlipScheme,
) -> Vec<(usize, f64, Measured)> {
    // The reference is the regularised scheme's, or the stiff one's for the
    // other schemes (the legacy scheme's own fine runs are not converged to
    // this level in 2-D).
    let reference_scheme = match scheme {
        SlipScheme::Regularised => SlipScheme::Regularised,
        _ => SlipScheme::Stiff,
    };
    let r = reference(
        p,
        grid,
        phases,
        &settings(reference_steps, reference_scheme),
    );
    steps
        .iter()
        .map(|&n| {
            let m = measure(p, grid, phases, &settings(n, scheme));
            (n, relative_l2(&m.vectors, &r.vectors), m)
        })
        .collect()
}

/// The primitives whose slip is 2-D.
const TWO_D: [PrimitiveKind; 5] = [
    PrimitiveKind::ScaledCircle,
    PrimitiveKind::Circle,
    PrimitiveKind::DivCircle,
    PrimitiveKind::SkewSink,
    PrimitiveKind::SkewSource,
];

fn small_grid() -> Grid {
    Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [4, 4],
    }
}

#[test]
fn harness_matches_field_compute() {
    let p = Primitive::new(PrimitiveKind::ScaledCircle);
    let s = settings(16, SlipScheme::Stiff);
    let m = measure(&p, &small_grid(), 5, &s);
    let mut s5 = s;
    s5.phases = 5;
    let (grid, none) = (small_grid(), Invariance::None);
    let every = Field::compute_by(&p.motion(), &grid, FieldKind::Force, &s5, none, &|| {});
    assert_eq!(m.vectors, every.vectors);
    // The engine's field simulates one point per circle about the axis
    // (`tests/unit/invariance.rs`): the same to round-off.
    let f = reference(&p, &small_grid(), 5, &s);
    assert!(relative_l2(&f.vectors, &m.vectors) < 1e-13);
}

/// Stiff- and regularised-scheme fields are bitwise identical on 1 and 2
/// threads.
#[test]
fn stiff_fields_thread_independent() {
    let p = Primitive::new(PrimitiveKind::DivCircle);
    for scheme in [SlipScheme::Stiff, SlipScheme::Regularised] {
        let s = settings(16, scheme);
        let on = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("pool")
                .install(|| reference(&p, &small_grid(), 5, &s))
        };
        assert_eq!(on(1), on(2));
    }
}

/// The stiff scheme at 64 steps per cycle: the 2-D primitives' force
/// fields (4×4 grid, 6 phases) within 2e-4 of a 1024-step reference, and at
/// least 10× closer to it than the legacy scheme at 64 steps. (The
/// references of the two schemes differ by less than that: the legacy
/// scheme's 1024-step field is checked against the stiff one too.)
#[test]
fn stiff_2d_beats_legacy() {
    for kind in [PrimitiveKind::DivCircle, PrimitiveKind::ScaledCircle] {
        let p = Primitive::new(kind);
        let g = small_grid();
        let r = reference(&p, &g, 6, &settings(1024, SlipScheme::Stiff)).vectors;
        let stiff = measure(&p, &g, 6, &settings(64, SlipScheme::Stiff));
        let legacy = measure(&p, &g, 6, &settings(64, SlipScheme::Legacy));
        let legacy_ref = reference(&p, &g, 6, &settings(1024, SlipScheme::Legacy)).vectors;
        let (es, el) = (
            relative_l2(&stiff.vectors, &r),
            relative_l2(&legacy.vectors, &r),
        );
        let refs = relative_l2(&legacy_ref, &r);
        eprintln!(
            "{}: stiff {es:.2e}, legacy {el:.2e}, references differ by {refs:.2e}",
            kind.name()
        );
        assert!(es <= 2e-4, "{}: stiff error {es:.2e}", kind.name());
        assert!(
            el >= 10.0 * es,
            "{}: legacy {el:.2e} vs stiff {es:.2e}",
            kind.name()
        );
        assert!(
            refs < el,
            "{}: references differ by {refs:.2e}",
            kind.name()
        );
    }
}

/// The regularised scheme (`src/dynamics/swing.rs`) on the five 2-D
/// primitives' force fields (4×4 grid, 6 phases) against its own 4096-step
/// field (`SLIP2D_ORDER_REF` to change; that field is within 8e-9 of a
/// 16384-step one): within 1e-4 at 64 steps per cycle, and an observed
/// order log₂(e(16)/e(64))/2 of at least 3 for every one, as issue 12
/// asks (measured 4.01, 4.31, 3.41, 3.16, 3.23 for ScaledCircle, Circle,
/// DivCircle, SkewSink, SkewSource). The legacy scheme fails both (errors 1e-3–4e-3 at 64
/// steps).
#[test]
fn order_2d() {
    let reference_steps = env_or("SLIP2D_ORDER_REF", 4096);
    for kind in [
        PrimitiveKind::ScaledCircle,
        PrimitiveKind::Circle,
        PrimitiveKind::DivCircle,
        PrimitiveKind::SkewSink,
        PrimitiveKind::SkewSource,
    ] {
        let least = 3.0;
        let p = Primitive::new(kind);
        let e = errors(
            &p,
            &small_grid(),
            6,
            &[16, 64],
            reference_steps,
            SlipScheme::Regularised,
        );
        let (e16, e64) = (e[0].1, e[1].1);
        let order = (e16 / e64).log2() / 2.0;
        eprintln!(
            "{}: errors {e16:.2e} (16), {e64:.2e} (64), order {order:.2}",
            kind.name()
        );
        assert!(e64 <= 1e-4, "{}: error {e64:.2e} at 64 steps", kind.name());
        assert!(
            order >= least,
            "{}: observed order {order:.2} < {least}",
            kind.name()
        );
    }
}

/// The full table (ignored: minutes). See the module docs for the command.
#[test]
#[ignore]
fn convergence_table() {
    let reference_steps: usize = env_or("SLIP2D_REF", 4096);
    let scheme = scheme_from_env();
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [11, 11],
    };
    let only = std::env::var("SLIP2D_ONLY").ok();
    println!(
    "force field 11×11×30 vs {reference_steps} steps, scheme {scheme:?}\n\
     | primitive | steps | rel. L2 | order | RK4 steps/cycle | µs/cycle |\n|---|---|---|---|---|---|"
);
    for p in Library::default_primitives() {
        if only
            .as_deref()
            .is_some_and(|o| !o.split(',').any(|n| n == p.kind.name()))
        {
            continue;
        }
        let e = errors(
            &p,
            &grid,
            30,
            &[8, 16, 32, 64, 128],
            reference_steps,
            scheme,
        );
        for (i, (n, err, m)) in e.iter().enumerate() {
            let order = if i == 0 {
                String::new()
            } else {
                format!("{:.2}", (e[i - 1].1 / err).log2())
            };
            println!(
                "| {} | {n} | {err:.2e} | {order} | {:.1} | {:.1} |",
                p.kind.name(),
                m.steps_per_cycle,
                m.micros_per_cycle
            );
        }
    }
}

/// One cycle from rest in the inertial frame at `pt` from `t0`, recorded.
fn one_cycle(
    motion: &Motion,
    steps: usize,
    scheme: SlipScheme,
    pt: [f64; 2],
    t0: f64,
) -> (PartState, CycleOutcome, Vec<TrajectoryPoint>) {
    let s = settings(steps, scheme);
    let sim = s.simulator(motion);
    let anchor = Vector2::from(pt);
    let k = sim.motion().kinematics(t0, sim.gravity(), sim.model().tilt);
    let v = k.velocity_at(&V3::new(pt[0], pt[1], 0.0));
    let mut state = PartState::new(anchor, -Vector2::new(v.x, v.y));
    let mut rec = Vec::new();
    let out = sim
        .advance(t0, t0 + sim.period(), &mut state, &anchor, Some(&mut rec))
        .expect("no contact loss in the default primitives");
    (state, out, rec)
}

/// Diagnostic (ignored): the worst single one-cycle simulations of a
/// primitive at `SLIP2D_N` steps against 1024.
#[test]
#[ignore]
fn worst_cycles() {
    let kind = PrimitiveKind::from_name(
        &std::env::var("SLIP2D_KIND").unwrap_or("DivCircle".into()),
        "kind",
    )
    .unwrap();
    let n: usize = env_or("SLIP2D_N", 64);
    let p = Primitive::new(kind);
    let motion = p.motion();
    let scheme = scheme_from_env();
    let run = |steps: usize, pt: [f64; 2], t0: f64| one_cycle(&motion, steps, scheme, pt, t0);
    let side: usize = env_or("SLIP2D_GRID", 4);
    let phases: usize = env_or("SLIP2D_PHASES", 6);
    let grid = Grid {
        n: [side, side],
        ..small_grid()
    };
    let wref: usize = env_or("SLIP2D_WREF", 1024);
    let mut rows = Vec::new();
    for pt in grid.points() {
        for j in 0..phases {
            let t0 = p.period() * j as f64 / phases as f64;
            let (a, oa, _) = run(n, pt, t0);
            let (b, ob, _) = run(wref, pt, t0);
            rows.push((
                (a.u - b.u).norm(),
                pt,
                j,
                oa.events,
                ob.events,
                oa.rk4_steps,
            ));
        }
    }
    rows.sort_by(|x, y| y.0.total_cmp(&x.0));
    for r in rows.iter().take(12) {
        println!("{r:?}");
    }
}

/// Diagnostic (ignored): one trajectory at `SLIP2D_N` steps and at 1024,
/// every `SLIP2D_EVERY`-th nominal step end with t/T in
/// [`SLIP2D_FROM`, `SLIP2D_TO`].
#[test]
#[ignore]
fn trace_cycle() {
    let env = |k: &str, d: &str| std::env::var(k).unwrap_or(d.into());
    let kind = PrimitiveKind::from_name(&env("SLIP2D_KIND", "DivCircle"), "kind").unwrap();
    let pt = [
        env("SLIP2D_X", "0.013333333333333336")
            .parse::<f64>()
            .unwrap(),
        env("SLIP2D_Y", "-0.013333333333333332")
            .parse::<f64>()
            .unwrap(),
    ];
    let j: f64 = env("SLIP2D_J", "0").parse().unwrap();
    let phases: f64 = env("SLIP2D_PHASES", "6").parse().unwrap();
    let p = Primitive::new(kind);
    let motion = p.motion();
    let t0 = p.period() * j / phases;
    for steps in [env("SLIP2D_N", "64").parse().unwrap(), 1024usize] {
        eprintln!("== {steps} steps");
        let (_, out, rec) = one_cycle(&motion, steps, scheme_from_env(), pt, t0);
        println!("steps {steps}: {out:?}");
        let every = env_or("SLIP2D_EVERY", (steps / 64).max(1));
        let window: [f64; 2] = [env_or("SLIP2D_FROM", 0.0), env_or("SLIP2D_TO", 1.0)];
        for (i, q) in rec.iter().enumerate() {
            let f = (q.t - t0) / p.period();
            if ((i + 1) % every == 0 || i + 1 == rec.len()) && f >= window[0] && f <= window[1] {
                println!(
                    "  t/T {:.9} u ({:+.12e}, {:+.12e}) stuck {}",
                    f, q.state.u.x, q.state.u.y, q.state.stuck
                );
            }
        }
    }
}

/// Diagnostic (ignored): the 2-D primitives' force fields on the small grid
/// (`SLIP2D_SIDE`, 6 phases) at 16…128 steps per cycle against
/// `SLIP2D_ORDER_REF` (4096) steps of the regularised scheme, for the
/// scheme `SLIP2D_SCHEME`: error, order, RK4 steps and µs per cycle.
#[test]
#[ignore]
fn quick_table() {
    let reference_steps: usize = env_or("SLIP2D_ORDER_REF", 4096);
    let side: usize = env_or("SLIP2D_SIDE", 4);
    let grid = Grid {
        n: [side, side],
        ..small_grid()
    };
    let scheme = scheme_from_env();
    let steps = std::env::var("SLIP2D_STEPS").unwrap_or("16,32,64,128".into());
    let steps: Vec<&str> = steps.split(',').collect();
    for kind in TWO_D {
        let p = Primitive::new(kind);
        let r_vectors = reference(
            &p,
            &grid,
            6,
            &settings(reference_steps, SlipScheme::Regularised),
        )
        .vectors;
        let mut last = f64::NAN;
        for n in steps.iter().filter_map(|s| s.parse().ok()) {
            let m = measure(&p, &grid, 6, &settings(n, scheme));
            let e = relative_l2(&m.vectors, &r_vectors);
            println!(
                "{} {scheme:?} {n}: {e:.2e} order {:.2} steps/cycle {:.1} µs/cycle {:.1}",
                kind.name(),
                (last / e).log2(),
                m.steps_per_cycle,
                m.micros_per_cycle
            );
            last = e;
        }
    }
}

/// Diagnostic (ignored): the 2-D primitives' steady-state velocity fields
/// (6×6 grid) at 16, 32, 64 steps per cycle for `SLIP2D_SCHEME` against the
/// regularised scheme at 1024: error, samples not converged, wall time.
#[test]
#[ignore]
fn quick_velocity() {
    let grid = Grid {
        n: [6, 6],
        ..small_grid()
    };
    let scheme = scheme_from_env();
    let velocity = |kind: PrimitiveKind, steps: usize, scheme: SlipScheme| {
        let p = Primitive::new(kind);
        let start = Instant::now();
        let f = Field::compute(
            &p.motion(),
            &grid,
            FieldKind::Velocity,
            &settings(steps, scheme),
            &|| {},
        );
        (f, start.elapsed().as_secs_f64())
    };
    for kind in TWO_D {
        let (r, _) = velocity(kind, 1024, SlipScheme::Regularised);
        for n in [16, 32, 64] {
            let (f, secs) = velocity(kind, n, scheme);
            let bad = f
                .validity
                .iter()
                .zip(&r.validity)
                .filter(|(a, b)| format!("{a:?}") != format!("{b:?}"))
                .count();
            println!(
                "{} {scheme:?} {n}: {:.2e} validity differs at {bad}, {secs:.3} s",
                kind.name(),
                relative_l2(&f.vectors, &r.vectors),
            );
        }
    }
}

/// LineSink rotated by 30° and shifted (a 1-D slip along a rotated line,
/// straight only to round-off) at 32 steps per cycle in each scheme against
/// the legacy scheme at 1024: all within 1e-6 (measured 2.9e-7 each). The
/// regularised scheme erred by 6e-3 when a round-off-sized slip across the
/// line sent the explicit steps' swing handling into short steps without
/// the swing allowance.
#[test]
fn rotated_linesink() {
    let p = Primitive {
        rotation_deg: 30.0,
        shift: [0.004, -0.002],
        ..Primitive::new(PrimitiveKind::LineSink)
    };
    let grid = Grid {
        n: [9, 9],
        ..small_grid()
    };
    let r = reference(&p, &grid, 6, &settings(1024, SlipScheme::Legacy));
    for scheme in [
        SlipScheme::Legacy,
        SlipScheme::Stiff,
        SlipScheme::Regularised,
    ] {
        let f = reference(&p, &grid, 6, &settings(32, scheme));
        let e = relative_l2(&f.vectors, &r.vectors);
        eprintln!("{scheme:?}: {e:.2e}");
        assert!(e <= 1e-6, "{scheme:?}: {e:.2e}");
    }
}

/// Two DivCircle cycles that went wrong at 1024 steps per cycle only (the
/// 11×11×30 engine-speed grid): a break-away just before a step's end left
/// |u| ≪ h μ_k N along a_free for an explicit step (2.0e-5 m/s off), and a
/// slip slowing to a stop with a_free nearly along û took explicit steps
/// that grew stiff (2.2e-7 m/s off). Each cycle's end velocity at 512,
/// 1024 and 2048 steps now agrees within 1e-8 m/s (measured ≤ 1.5e-8 over
/// all 3630 cycles of that grid, `worst_cycles`).
#[test]
fn fine_steps_agree_at_former_outliers() {
    let motion = Primitive::new(PrimitiveKind::DivCircle).motion();
    let period = motion.period();
    for (pt, j) in [([-0.024, -0.016], 2.0), ([0.008, -0.024], 21.0)] {
        let t0 = period * j / 30.0;
        let end = |n: usize| one_cycle(&motion, n, SlipScheme::Regularised, pt, t0).0.u;
        let (a, b, c) = (end(512), end(1024), end(2048));
        let (ab, bc) = ((a - b).norm(), (b - c).norm());
        assert!(
            ab <= 1e-8 && bc <= 1e-8,
            "{pt:?} phase {j}: {ab:.2e} {bc:.2e}"
        );
    }
}
