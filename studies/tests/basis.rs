//! Basis fields: mirror images, thread-count invariance, reuse by symmetry
//! against direct simulation, the library cache, model rungs.
//!
//! All on small grids (9 × 9 over ±4 cm at most) with few start phases, so
//! the whole file runs in seconds.

use std::collections::HashSet;
use std::path::PathBuf;

use platefield::basis::primitives::PSI0;
use platefield::basis::symmetry::{rotation_asymmetry, source_grid, transformed};
use platefield::basis::{
    BasisCache, CacheStatus, FieldLibrary, Library, Primitive, PrimitiveKind, StepsPlan,
};
use platefield::design::basis::{assemble, ExclusionReason, ISOTROPY_TOL};
use platefield::field::rung::{choose_rung, DEFAULT_RUNG_TOLERANCE};
use platefield::field::{Field, FieldKind, FieldSettings, Grid, Validity};
use platefield::progress::ProgressMode;

/// 9 × 9 over ±4 cm, symmetric about both axes.
const GRID9: Grid = Grid {
    x: [-0.04, 0.04],
    y: [-0.04, 0.04],
    n: [9, 9],
};

/// Full model, few phases, 32 steps per cycle.
fn settings(phases: usize) -> FieldSettings {
    let mut s = FieldSettings {
        phases,
        ..FieldSettings::default()
    };
    s.numerics.steps_per_cycle = 32;
    s
}

fn force(p: &Primitive, grid: &Grid, s: &FieldSettings) -> Field {
    Field::compute(&p.motion(), grid, FieldKind::Force, s, &|| {})
}

/// Largest |a − b| over samples valid in both, relative to b's largest
/// valid magnitude; and the number of samples compared.
fn max_rel_diff(a: &Field, b: &Field) -> (f64, usize) {
    let scale = b.max_magnitude();
    let mut worst: f64 = 0.0;
    let mut n = 0;
    for k in 0..b.vectors.len() {
        if a.validity[k] == Validity::Ok && b.validity[k] == Validity::Ok {
            let (u, v) = (a.vectors[k], b.vectors[k]);
            worst = worst.max((u[0] - v[0]).hypot(u[1] - v[1]) / scale);
            n += 1;
        }
    }
    (worst, n)
}

/// Relative L2 difference over samples valid in both.
fn rel_l2(a: &Field, b: &Field) -> f64 {
    platefield::field::rung::relative_l2(a, b).0
}

/// A 9 × 9 grid over ±5/128 m (≈ ±3.9 cm) whose coordinates are dyadic
/// rationals, so x and −x are both exact: the mirror images below are then
/// computed with mirrored arithmetic. (On ±4 cm the computed coordinates of
/// mirrored nodes differ in the last bit, and the integrator's 2-D slip
/// handling amplifies that: DivCircle's mirror images then differ by up to
/// 2e-2 of the largest magnitude at 4 phases and 32 steps.)
const DYADIC9: Grid = Grid {
    x: [-0.0390625, 0.0390625],
    y: [-0.0390625, 0.0390625],
    n: [9, 9],
};

/// A LineSink or DivCircle with amplitude −ψ0 (axes in the y–z plane) is
/// the mirror image under x → −x of the one with +ψ0, so its force field is
/// F₋(x, y) = (−F₊x(−x, y), F₊y(−x, y)): asserted to 1e-9 of the largest
/// magnitude on a symmetric 9 × 9 grid ([`DYADIC9`]; model full, 4 phases),
/// with identical validity flags at mirrored points. (Measured: 0, the
/// computation mirrors bit for bit.)
#[test]
fn negative_amplitude_is_the_mirror_image() {
    let s = settings(4);
    let grid = DYADIC9;
    for kind in [PrimitiveKind::LineSink, PrimitiveKind::DivCircle] {
        let with = |a: f64| Primitive {
            amplitude: Some(a),
            ..Primitive::new(kind)
        };
        let plus = force(&with(PSI0), &grid, &s);
        let minus = force(&with(-PSI0), &grid, &s);
        let scale = plus.max_magnitude();
        assert!(scale > 0.1, "{kind:?}: field too weak to test ({scale})");
        let n = grid.n[0];
        let mut compared = 0;
        for j in 0..grid.n[1] {
            for i in 0..n {
                let (k, m) = (j * n + i, j * n + (n - 1 - i));
                assert_eq!(minus.validity[k], plus.validity[m], "{kind:?} at {k}");
                if plus.validity[m] != Validity::Ok {
                    continue;
                }
                let want = [-plus.vectors[m][0], plus.vectors[m][1]];
                let got = minus.vectors[k];
                let d = (got[0] - want[0]).hypot(got[1] - want[1]) / scale;
                assert!(d <= 1e-9, "{kind:?} at {k}: {got:?} vs {want:?} ({d:e})");
                compared += 1;
            }
        }
        assert!(compared >= 60, "{kind:?}: only {compared} valid samples");
    }
}

/// A field computed on one rayon thread equals, bit for bit, the same field
/// on two threads (force field of ScaledCircle, velocity field of DivCircle:
/// 2-D slips and the steady-state Newton iteration).
#[test]
fn fields_are_bitwise_independent_of_thread_count() {
    let grid = Grid { n: [7, 7], ..GRID9 };
    let s = settings(4);
    let cases = [
        (PrimitiveKind::ScaledCircle, FieldKind::Force),
        (PrimitiveKind::DivCircle, FieldKind::Velocity),
    ];
    for (kind, field_kind) in cases {
        let motion = Primitive::new(kind).motion();
        let run = |threads: usize| {
            rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .expect("thread pool")
                .install(|| Field::compute(&motion, &grid, field_kind, &s, &|| {}))
        };
        let (one, two) = (run(1), run(2));
        let bits = |f: &Field| -> Vec<[u64; 2]> {
            f.vectors
                .iter()
                .map(|v| [v[0].to_bits(), v[1].to_bits()])
                .collect()
        };
        assert_eq!(bits(&one), bits(&two), "{kind:?} {field_kind:?}");
        assert_eq!(one.validity, two.validity, "{kind:?} {field_kind:?}");
        assert!(one.valid_count() > 0);
    }
}

/// A 90° copy resampled from one simulation equals a direct simulation of
/// the rotated primitive (`rotation_deg: 90`): on a grid symmetric about
/// the origin the preimages are nodes, so no interpolation happens, and
/// validity flags agree everywhere.
///
/// LineSink, LineSource and DivCircle (a 2-D slip): to 1e-9 of the
/// largest magnitude (measured ≤ 6e-14 for the line slips and 1.2e-15 for
/// DivCircle: round-off; 4 phases, 32 steps). A wrong rotation of the
/// vectors or of the points gives errors of order 1.
#[test]
fn rotation_by_90_degrees_is_exact() {
    let s = settings(4);
    let angle = 90f64.to_radians();
    for (kind, l2_tol, worst_tol) in [
        (PrimitiveKind::LineSink, 1e-9, 1e-9),
        (PrimitiveKind::LineSource, 1e-9, 1e-9),
        (PrimitiveKind::DivCircle, 1e-9, 1e-9),
    ] {
        let base = Primitive::new(kind);
        let source = force(&base, &GRID9, &s);
        let copy = transformed(&source, angle, [0.0, 0.0], &GRID9);
        let direct = force(
            &Primitive {
                rotation_deg: 90.0,
                ..base
            },
            &GRID9,
            &s,
        );
        assert_eq!(copy.validity, direct.validity, "{kind:?}");
        let (worst, n) = max_rel_diff(&copy, &direct);
        let l2 = rel_l2(&copy, &direct);
        assert!(n >= 60, "{kind:?}: {n} valid samples");
        assert!(
            l2 <= l2_tol && worst <= worst_tol,
            "{kind:?}: L2 {l2:e}, worst {worst:e}"
        );
    }
}

/// A 30° rotation plus a (0.004, −0.002) m shift, resampled by cubic
/// interpolation from a simulation on `source_grid` (the target's 1 cm
/// spacing), against direct simulation of the transformed primitive on the
/// 9 × 9 target (model full, 6 phases, 32 steps).
///
/// LineSink: measured relative L2 7.3e-5, worst 3.8e-5 of the largest
/// magnitude; tolerance 3e-4 for both. Its direct simulation is
/// reproducible (a 1e-12 m change of the shift changes it by 1e-8), so this
/// is the interpolation error, and it falls as h³, as the bound of
/// `basis::symmetry` says: with the source spacing halved (the source grid
/// of a 17 × 17 target) the L2 error is 7.4e-6 (ratio 9.9; asserted ≥ 4).
///
/// DivCircle: measured L2 2.1e-2, worst 1.9e-2; tolerance 3e-2 for both.
/// This too is the interpolation error (of a field less smooth than the
/// LineSink's): with the source spacing halved the L2 error is 5.2e-3
/// (ratio 4.0; asserted ≥ 3). The direct simulations are reproducible: a
/// 1e-12 m change of the shift changes them by 4e-11 (DivCircle) and 7e-9
/// (LineSink), relative L2 (asserted ≤ 1e-7), so the mismatch is not the
/// simulator's. A wrong rotation of the vectors or of the points gives
/// errors of order 1.
#[test]
fn rotation_and_shift_match_direct_simulation() {
    let s = settings(6);
    let (angle, shift) = (30f64.to_radians(), [0.004, -0.002]);
    let src_grid = source_grid(&GRID9, &[angle], &[shift]);
    assert!(
        (src_grid.spacing() - GRID9.spacing()).abs() < 1e-15,
        "{src_grid:?}"
    );
    let copy_of = |base: &Primitive, src_grid: &Grid| {
        let source = force(base, src_grid, &s);
        let copy = transformed(&source, angle, shift, &GRID9);
        let outside = copy
            .validity
            .iter()
            .filter(|v| **v == Validity::OutsideSource)
            .count();
        assert_eq!(outside, 0, "{:?}: source grid too small", base.kind);
        copy
    };
    for (kind, tol, halving) in [
        (PrimitiveKind::LineSink, 3e-4, 4.0),
        (PrimitiveKind::DivCircle, 3e-2, 3.0),
    ] {
        let base = Primitive::new(kind);
        let direct = force(
            &Primitive {
                rotation_deg: 30.0,
                shift,
                ..base.clone()
            },
            &GRID9,
            &s,
        );
        let copy = copy_of(&base, &src_grid);
        let (worst, n) = max_rel_diff(&copy, &direct);
        let l2 = rel_l2(&copy, &direct);
        eprintln!("{kind:?}: relative L2 {l2:.2e}, worst {worst:.2e} over {n} samples");
        assert!(n >= 50, "{kind:?}: {n} valid samples");
        assert!(
            l2 <= tol && worst <= tol,
            "{kind:?}: L2 {l2:e}, worst {worst:e}"
        );
        let fine = Grid {
            n: [17, 17],
            ..GRID9
        };
        let finer = copy_of(&base, &source_grid(&fine, &[angle], &[shift]));
        let l2_fine = rel_l2(&finer, &direct);
        eprintln!("{kind:?}: half spacing: relative L2 {l2_fine:.2e}");
        assert!(l2_fine * halving <= l2, "{kind:?}: {l2:e} → {l2_fine:e}");
        // The direct simulation's own reproducibility: a 1e-12 m change of
        // the shift.
        let nudged = force(
            &Primitive {
                rotation_deg: 30.0,
                shift: [shift[0] + 1e-12, shift[1]],
                ..base.clone()
            },
            &GRID9,
            &s,
        );
        let repro = rel_l2(&nudged, &direct);
        eprintln!("{kind:?}: direct simulation, shift + 1e-12 m: relative L2 {repro:.2e}");
        assert!(repro <= 1e-7, "{kind:?}: reproducibility {repro:e}");
    }
}

fn cache_dir(name: &str) -> PathBuf {
    let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("basis-cache-{name}"));
    let _ = std::fs::remove_dir_all(&d);
    d
}

/// A tiny library: two primitives on 3 × 3, 2 phases, 8 steps.
fn tiny() -> (Vec<Primitive>, Grid, FieldSettings) {
    let mut s = FieldSettings {
        phases: 2,
        ..FieldSettings::default()
    };
    s.numerics.steps_per_cycle = 8;
    let grid = Grid { n: [3, 3], ..GRID9 };
    (
        vec![
            Primitive::new(PrimitiveKind::LineSink),
            Primitive::new(PrimitiveKind::Trans),
        ],
        grid,
        s,
    )
}

/// A stored library loads back equal (bitwise: `FieldLibrary: PartialEq`
/// on f64), and `get_or_build` builds once, then hits. A velocity library
/// holds velocity fields only, equal to those of the two-kind
/// [`Library::build`]; asking for force fields afterwards is a different
/// key (built, not a hit), and the velocity hit never needed them.
#[test]
fn cache_round_trips_and_hits() {
    let (prims, grid, s) = tiny();
    let v = FieldKind::Velocity;
    let cache = BasisCache::new(cache_dir("roundtrip"));
    let key = BasisCache::key(&prims, &grid, &s, v);
    assert!(cache.load(&key).is_none());
    let (built, status) = cache
        .get_or_build(&prims, &grid, &s, v, ProgressMode::Quiet, || Ok(()))
        .expect("build");
    assert_eq!(status, CacheStatus::Built);
    assert_eq!(
        built,
        FieldLibrary::build(&prims, &grid, &s, v, ProgressMode::Quiet)
    );
    assert_eq!(built.kind, v);
    assert!(built.entries.iter().all(|e| e.field.kind == v));
    let both = Library::build(&prims, &grid, &s, StepsPlan::Uniform, ProgressMode::Quiet);
    for (e, b) in built.entries.iter().zip(&both.entries) {
        assert_eq!(e.field, b.velocity);
    }
    assert_eq!(cache.load(&key).as_ref(), Some(&built));
    let (again, status) = cache
        .get_or_build(&prims, &grid, &s, v, ProgressMode::Quiet, || Ok(()))
        .expect("hit");
    assert_eq!(status, CacheStatus::Hit);
    assert_eq!(again, built);
    let f = FieldKind::Force;
    let (forces, status) = cache
        .get_or_build(&prims, &grid, &s, f, ProgressMode::Quiet, || Ok(()))
        .expect("force");
    assert_eq!(status, CacheStatus::Built);
    for (e, b) in forces.entries.iter().zip(&both.entries) {
        assert_eq!(e.field, b.force);
    }
    let (again, status) = cache
        .get_or_build(&prims, &grid, &s, v, ProgressMode::Quiet, || Ok(()))
        .expect("hit");
    assert_eq!((status, again), (CacheStatus::Hit, built.clone()));
    // store/load directly, under another key.
    let other = BasisCache::key(&prims[..1], &grid, &s, v);
    cache.store(&other, &built).expect("store");
    assert_eq!(cache.load(&other), Some(built));
}

/// Every setting, grid parameter and primitive parameter, and the field
/// kind, is in the key: 29 variations of the base give 30 distinct
/// velocity keys, plus the base's force key, and the key is stable.
#[test]
fn cache_key_covers_every_setting() {
    let (prims, grid, s) = tiny();
    let v = FieldKind::Velocity;
    let base = BasisCache::key(&prims, &grid, &s, v);
    assert_eq!(base, BasisCache::key(&prims, &grid, &s, v));
    assert_eq!(base.len(), 64);
    let mut variants: Vec<(Vec<Primitive>, Grid, FieldSettings)> = Vec::new();
    let mut set = |f: &dyn Fn(&mut FieldSettings)| {
        let mut t = s;
        f(&mut t);
        variants.push((prims.clone(), grid, t));
    };
    set(&|t| t.friction.stat = 0.31);
    set(&|t| t.friction.kinetic = 0.29);
    set(&|t| t.gravity = 9.8);
    set(&|t| t.model.centripetal = false);
    set(&|t| t.model.tilt = false);
    set(&|t| t.model.coriolis = false);
    set(&|t| t.model.moving = false);
    set(&|t| t.numerics.steps_per_cycle = 9);
    set(&|t| t.numerics.event_tol = 1e-13);
    set(&|t| t.numerics.steady_tol = 1e-10);
    set(&|t| t.numerics.steady_accept = 1e-6);
    set(&|t| t.numerics.max_iterations = 201);
    set(&|t| t.phases = 3);
    set(&|t| t.frozen_excursion = 0.2);
    for g in [
        Grid { n: [3, 4], ..grid },
        Grid {
            x: [-0.04, 0.041],
            ..grid
        },
        Grid {
            y: [-0.039, 0.04],
            ..grid
        },
    ] {
        variants.push((prims.clone(), g, s));
    }
    let mut prim = |f: &dyn Fn(&mut Primitive)| {
        let mut p = prims.clone();
        f(&mut p[0]);
        variants.push((p, grid, s));
    };
    prim(&|p| p.kind = PrimitiveKind::LineSource);
    prim(&|p| p.omega = 210.0);
    prim(&|p| p.amplitude = Some(0.004));
    prim(&|p| p.amplitude = Some(PSI0)); // explicit default: a different request
    prim(&|p| p.translation = Some(1e-4));
    prim(&|p| p.depth = 0.04);
    prim(&|p| p.rotation_deg = 15.0);
    prim(&|p| p.shift = [0.001, 0.0]);
    prim(&|p| p.shift = [0.0, 0.001]);
    variants.push((prims.iter().rev().cloned().collect(), grid, s));
    variants.push((prims[..1].to_vec(), grid, s));
    variants.push((Vec::new(), grid, s));
    assert_eq!(variants.len(), 29);
    let mut keys: HashSet<String> = HashSet::new();
    keys.insert(base);
    for (p, g, t) in &variants {
        assert!(
            keys.insert(BasisCache::key(p, g, t, v)),
            "{p:?} {g:?} {t:?}"
        );
    }
    assert!(keys.insert(BasisCache::key(&prims, &grid, &s, FieldKind::Force)));
    assert_eq!(keys.len(), 31);
}

/// A truncated file and a flipped byte (a digit changed inside the payload,
/// which still parses, and a bit flipped in the header) are not trusted:
/// `load` gives None and `get_or_build` rebuilds (`CacheStatus::Rebuilt`,
/// with the reason) the same library, after which the file is good again.
#[test]
fn corrupt_cache_files_are_rebuilt() {
    let (prims, grid, s) = tiny();
    let cache = BasisCache::new(cache_dir("corrupt"));
    let v = FieldKind::Velocity;
    let key = BasisCache::key(&prims, &grid, &s, v);
    let (good, _) = cache
        .get_or_build(&prims, &grid, &s, v, ProgressMode::Quiet, || Ok(()))
        .expect("build");
    let path = cache.path(&key);
    let bytes = std::fs::read(&path).expect("cache file");
    assert!(bytes.starts_with(b"{\"format\":3,\"key\":\""));

    let truncated = bytes[..bytes.len() * 2 / 3].to_vec();
    // A digit in the middle of the payload, changed to another digit.
    let mut digit = bytes.clone();
    let at = (bytes.len() / 2..bytes.len())
        .find(|&i| bytes[i].is_ascii_digit() && bytes[i - 1].is_ascii_digit())
        .expect("a digit");
    digit[at] = if digit[at] == b'7' { b'3' } else { b'7' };
    let mut header_bit = bytes.clone();
    header_bit[30] ^= 0x01;
    for (what, corrupt, needle) in [
        ("truncated", truncated, "truncated or malformed"),
        ("digit", digit, "payload hash mismatch"),
        ("header bit", header_bit, ""),
    ] {
        std::fs::write(&path, &corrupt).expect("write");
        assert!(cache.load(&key).is_none(), "{what}: loaded a corrupt file");
        let (lib, status) = cache
            .get_or_build(&prims, &grid, &s, v, ProgressMode::Quiet, || Ok(()))
            .expect("rebuild");
        match &status {
            CacheStatus::Rebuilt { reason } => {
                assert!(reason.contains(needle), "{what}: {reason}")
            }
            other => panic!("{what}: {other:?}"),
        }
        assert_eq!(lib, good, "{what}");
        assert_eq!(std::fs::read(&path).expect("rewritten"), bytes, "{what}");
        assert_eq!(cache.load(&key).as_ref(), Some(&good), "{what}");
    }
}

/// Trans is an in-plane translation: N = g and Ω = 0, so all rungs agree
/// exactly; the cheapest (`paper`) is chosen, its measured error (0) is
/// within the tolerance, and the reason says in-plane.
#[test]
fn in_plane_translation_needs_only_the_paper_model() {
    let grid = Grid { n: [5, 5], ..GRID9 };
    let motion = Primitive::new(PrimitiveKind::Trans).motion();
    let r = choose_rung(
        &motion,
        &grid,
        FieldKind::Force,
        &settings(4),
        DEFAULT_RUNG_TOLERANCE,
    );
    assert!(r.error <= DEFAULT_RUNG_TOLERANCE, "{r:?}");
    assert!(r.reason.contains("in-plane"), "{}", r.reason);
    assert_eq!(r.rung, "paper", "{r:?}");
    assert_eq!(r.rungs.len(), 4);
    assert!(r
        .rungs
        .iter()
        .all(|x| x.error == 0.0 && x.flags_differ == 0));
}

/// LineSink tilts the plate: the paper model's error against full is
/// several per cent (the tilt and centripetal terms change N), so a richer
/// rung is chosen, and its measured error is within the tolerance.
#[test]
fn out_of_plane_motion_needs_more_than_the_paper_model() {
    let grid = Grid { n: [5, 5], ..GRID9 };
    let motion = Primitive::new(PrimitiveKind::LineSink).motion();
    let r = choose_rung(
        &motion,
        &grid,
        FieldKind::Force,
        &settings(4),
        DEFAULT_RUNG_TOLERANCE,
    );
    assert_ne!(r.rung, "paper", "{r:?}");
    assert!(r.rungs[0].error > DEFAULT_RUNG_TOLERANCE, "{r:?}");
    assert!(r.error <= DEFAULT_RUNG_TOLERANCE, "{r:?}");
    assert!(r.reason.contains("out-of-plane"), "{}", r.reason);
}

/// Isotropy by symmetry of the simulated field (not by name): on a 17×17
/// grid over ±4 cm (force fields, 4 phases), Circle changes by less than
/// [`ISOTROPY_TOL`] under rotations by 15°, 30° and 90° (resampling error
/// only), LineSink and Trans by more than 0.2 (Trans, a uniform field:
/// 2 sin 7.5° = 0.261 to 1e-6 at 15°). Assembled every 15°, the basis keeps
/// Circle at 0° only and reports its 23 rotated copies as isotropic copies
/// of `Circle@0°`, while LineSink and Trans keep all their valid copies.
#[test]
fn isotropic_copies_are_left_out() {
    let grid = Grid {
        n: [17, 17],
        ..GRID9
    };
    let s = settings(4);
    let kinds = [
        PrimitiveKind::Circle,
        PrimitiveKind::LineSink,
        PrimitiveKind::Trans,
    ];
    let prims: Vec<Primitive> = kinds.iter().map(|k| Primitive::new(*k)).collect();
    let lib = FieldLibrary::build(&prims, &grid, &s, FieldKind::Force, ProgressMode::Quiet);
    for (e, k) in lib.entries.iter().zip(kinds) {
        for deg in [15.0f64, 30.0, 90.0] {
            let change = rotation_asymmetry(&e.field, deg.to_radians()).expect("overlap");
            if k == PrimitiveKind::Circle {
                assert!(change < ISOTROPY_TOL, "{k:?} {deg}°: {change}");
            } else {
                assert!(change > 0.2, "{k:?} {deg}°: {change}");
            }
            if k == PrimitiveKind::Trans && deg == 15.0 {
                let exact = 2.0 * 7.5f64.to_radians().sin();
                assert!((change - exact).abs() < 1e-6, "{change} vs {exact}");
            }
        }
    }
    let rotations: Vec<f64> = (0..24).map(|i| 15.0 * i as f64).collect();
    let points = grid.points();
    let weights = vec![1.0; points.len()];
    let basis = assemble(
        &lib,
        &rotations,
        &[[0.0, 0.0]],
        Some(&grid),
        &points,
        &weights,
        true,
    );
    let count = |name: &str| {
        basis
            .columns
            .iter()
            .filter(|c| c.source.label().split('@').next() == Some(name))
            .count()
    };
    assert_eq!(count("Circle"), 1);
    assert_eq!(count("LineSink"), 24);
    assert_eq!(count("Trans"), 24);
    let iso: Vec<_> = basis
        .excluded
        .iter()
        .filter(|x| matches!(x.reason, ExclusionReason::IsotropicCopy { .. }))
        .collect();
    assert_eq!(iso.len(), 23);
    for x in iso {
        assert!(x.label.starts_with("Circle@"), "{}", x.label);
        match &x.reason {
            ExclusionReason::IsotropicCopy {
                copy_of,
                rotation_change,
            } => {
                assert_eq!(copy_of, "Circle@0°");
                assert!(*rotation_change < ISOTROPY_TOL);
            }
            other => panic!("{other:?}"),
        }
    }
}

/// A cache entry that is not a regular file — a FIFO (which blocks whoever
/// opens it) or a link to `/dev/zero` (which never ends) — is neither
/// waited on nor read: it is rebuilt, and the rebuilt entry is a regular
/// file that loads. Run on a thread with a 60 s limit, so that a hang fails
/// the test instead of stalling the suite.
#[test]
fn cache_entries_that_are_not_regular_files_are_rebuilt() {
    let (prims, grid, s) = tiny();
    let v = FieldKind::Velocity;
    let dir = cache_dir("special");
    std::fs::create_dir_all(&dir).expect("cache dir");
    let key = BasisCache::key(&prims, &grid, &s, v);
    let path = BasisCache::new(&dir).path(&key);
    let make_fifo = |p: &std::path::Path| {
        let ok = std::process::Command::new("mkfifo").arg(p).status();
        assert!(ok.is_ok_and(|s| s.success()), "mkfifo");
    };
    let make_zero_link = |p: &std::path::Path| {
        std::os::unix::fs::symlink("/dev/zero", p).expect("symlink");
    };
    for (what, make) in [
        ("fifo", &make_fifo as &dyn Fn(&std::path::Path)),
        ("link to /dev/zero", &make_zero_link),
    ] {
        let _ = std::fs::remove_file(&path);
        make(&path);
        let (tx, rx) = std::sync::mpsc::channel();
        let (p, g, st, d) = (prims.clone(), grid, s, dir.clone());
        std::thread::spawn(move || {
            let _ = tx.send(BasisCache::new(d).get_or_build(
                &p,
                &g,
                &st,
                v,
                ProgressMode::Quiet,
                || Ok(()),
            ));
        });
        let got = rx
            .recv_timeout(std::time::Duration::from_secs(60))
            .unwrap_or_else(|_| panic!("{what}: the cache read did not end in 60 s"));
        match got.expect("rebuild").1 {
            CacheStatus::Rebuilt { reason } => {
                assert!(reason.contains("not a regular file"), "{what}: {reason}")
            }
            other => panic!("{what}: {other:?}"),
        }
        let meta = std::fs::symlink_metadata(&path).expect("entry");
        assert!(meta.file_type().is_file(), "{what}: not replaced");
        assert!(BasisCache::new(&dir).load(&key).is_some(), "{what}");
    }
}
