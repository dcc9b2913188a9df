//! The basis library cache (`crate::basis::BasisCache`): a stored library
//! loads back equal, every setting is in the key, and corrupt entries or
//! entries that are not regular files are rebuilt.
//!
//! All on a 3 × 3 grid with 2 start phases and 8 steps per cycle, so the
//! whole file runs in seconds.

use std::collections::HashSet;
use std::path::{Path, PathBuf};

use crate::basis::cache::BasisCache;
use crate::basis::primitives::PSI0;
use crate::basis::{CacheStatus, FieldLibrary, Library, Primitive, PrimitiveKind, StepsPlan};
use crate::field::{FieldKind, FieldSettings, Grid};
use crate::progress::ProgressMode;

/// The library stored under `key`, or `None` when there is none or the
/// file is not trustworthy.
fn load(cache: &BasisCache, key: &str) -> Option<FieldLibrary> {
    cache.check(key).ok()
}

fn cache_dir(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("target/tmp")
        .join(format!("basis-cache-{name}"));
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
    let grid = Grid {
        x: [-0.04, 0.04],
        y: [-0.04, 0.04],
        n: [3, 3],
    };
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
    assert!(load(&cache, &key).is_none());
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
    assert_eq!(load(&cache, &key).as_ref(), Some(&built));
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
    assert_eq!(load(&cache, &other), Some(built));
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
        assert!(
            load(&cache, &key).is_none(),
            "{what}: loaded a corrupt file"
        );
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
        assert_eq!(load(&cache, &key).as_ref(), Some(&good), "{what}");
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
        assert!(load(&BasisCache::new(&dir), &key).is_some(), "{what}");
    }
}
