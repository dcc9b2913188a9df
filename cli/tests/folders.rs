//! Issue 30: result folders hold one whole run (concurrent designs into one
//! folder, runs interrupted while they write), inputs are bounded (size,
//! regular files), a closed stdout ends a command quietly, a read-only
//! cache is refused before the build, duplicate sample points are refused,
//! and one schedule validation names the edited segment.

mod common;

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{design_args, platefield};

const BIN: &str = env!("CARGO_BIN_EXE_platefield");

/// A fresh temporary folder for one test.
fn temp_dir(name: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("platefield-folders-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A small sink target named "sink" (5 × 5 points, no mask) of `strength`,
/// written to `dir/file`; two strengths give two different runs into the
/// same folder `OUT/sink`.
fn sink_target(dir: &Path, file: &str, strength: f64) -> String {
    let t = serde_json::json!({
        "name": "sink",
        "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [5, 5]},
        "field": {"kind": "sink", "center": [0.0, 0.0], "strength": strength},
    });
    let path = dir.join(file);
    std::fs::write(&path, t.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

/// The design products in `folder` (name → bytes); hidden files, the
/// user's `notes.txt` and `verify/` left out.
fn products(folder: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    let Ok(entries) = std::fs::read_dir(folder) else {
        return files;
    };
    for e in entries {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        if name.starts_with('.') || name == "notes.txt" || name == "verify" {
            continue;
        }
        files.insert(name.clone(), std::fs::read(folder.join(&name)).unwrap());
    }
    files
}

/// The two runs A (strength 1) and B (strength 0.5), each designed alone
/// into `dir/out` (the folder the tests then design into, since report.md
/// states the command run) and removed: their target files and their
/// folders' products (which differ).
fn two_runs(dir: &Path) -> [(String, BTreeMap<String, Vec<u8>>); 2] {
    [("a.json", 1.0), ("b.json", 0.5)].map(|(file, strength)| {
        let target = sink_target(dir, file, strength);
        let out = dir.join("out");
        let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
        assert_eq!(code, 0, "{err}");
        let p = products(&out.join("sink"));
        std::fs::remove_dir_all(&out).unwrap();
        assert!(p.contains_key("schedule.json") && p.contains_key("report.md"));
        (target, p)
    })
}

/// Which of `runs` the folder holds whole ("A", "B"), or a panic naming
/// what it holds.
fn whole_run(folder: &Path, runs: &[(String, BTreeMap<String, Vec<u8>>); 2], case: &str) -> usize {
    let got = products(folder);
    runs.iter().position(|(_, p)| *p == got).unwrap_or_else(|| {
        let names: Vec<&String> = got.keys().collect();
        let from = |name: &str| {
            runs.iter()
                .position(|(_, p)| p.get(name) == got.get(name))
                .map_or("neither".to_string(), |i| ["A", "B"][i].to_string())
        };
        panic!(
            "{case}: the folder holds {names:?}: schedule.json from {}, report.md from {}",
            from("schedule.json"),
            from("report.md")
        )
    })
}

/// Issue 30: two designs into one folder at once, 20 times (the default
/// run) or 100 times (`cargo test --release --test folders -- --ignored`,
/// about 80 s): the folder always holds one whole run — the same bytes as
/// run A alone or run B alone (schedule.json, report.md and fit.svg from
/// the same run) — and keeps the user's own file. (Before, 2 of 41 pairs
/// left schedule.json of one run beside report.md of the other.)
#[test]
fn concurrent_designs_into_one_folder_leave_one_whole_run() {
    concurrent_pairs(20, "concurrent-20");
}

/// [`concurrent_designs_into_one_folder_leave_one_whole_run`], 100 pairs.
#[test]
#[ignore = "about 80 s: 100 pairs of concurrent designs"]
fn a_hundred_concurrent_pairs_leave_one_whole_run() {
    concurrent_pairs(100, "concurrent-100");
}

/// `n` pairs of concurrent designs into one folder (see
/// [`concurrent_designs_into_one_folder_leave_one_whole_run`]).
fn concurrent_pairs(n: usize, name: &str) {
    let dir = temp_dir(name);
    let runs = two_runs(&dir);
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let folder = out.join("sink");
    let mut seen = [0; 2];
    for pair in 0..n {
        let children: Vec<_> = runs
            .iter()
            .map(|(t, _)| {
                Command::new(BIN)
                    .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
                    .args(design_args(t, o))
                    .stdout(Stdio::null())
                    .stderr(Stdio::piped())
                    .spawn()
                    .unwrap()
            })
            .collect();
        for c in children {
            let done = c.wait_with_output().unwrap();
            let err = String::from_utf8_lossy(&done.stderr);
            assert!(done.status.success(), "pair {pair}: {err}");
        }
        seen[whole_run(&folder, &runs, &format!("pair {pair}"))] += 1;
        if pair == 0 {
            std::fs::write(folder.join("notes.txt"), "mine").unwrap();
        }
        assert_eq!(
            std::fs::read_to_string(folder.join("notes.txt"))
                .ok()
                .as_deref(),
            Some("mine"),
            "pair {pair}: the user's file was not kept"
        );
    }
    assert_eq!(seen[0] + seen[1], n);
    let left: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["sink"], "staging folders left behind");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: a design interrupted (SIGINT or SIGKILL) at a random moment
/// of its run — most of them late, in or near its write — leaves the folder
/// with one whole run: the previous one or the new one, never a mix (before,
/// a SIGINT in the write left the new schedule.json beside the previous
/// report.md). The delays are pseudo-random from a fixed seed, spread over
/// 0–1.3 × an uninterrupted run's time.
#[test]
fn interrupted_designs_leave_one_whole_run() {
    let dir = temp_dir("interrupt");
    let runs = two_runs(&dir);
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let folder = out.join("sink");
    let start = Instant::now();
    let (code, _, err) = platefield(&design_args(&runs[0].0, o));
    assert_eq!(code, 0, "{err}");
    let run_time = start.elapsed().as_secs_f64();
    let mut state: u64 = 0x9E37_79B9_7F4A_7C15;
    let mut uniform = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut held = [0; 2];
    for trial in 0..60 {
        let (target, _) = &runs[(trial + 1) % 2];
        let mut child = Command::new(BIN)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .args(design_args(target, o))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let delay = run_time * 1.3 * uniform().sqrt();
        std::thread::sleep(Duration::from_secs_f64(delay));
        let signal = if trial % 2 == 0 {
            libc::SIGINT
        } else {
            libc::SIGKILL
        };
        // SAFETY: kill(2) on the id of our own child, not yet reaped.
        unsafe { libc::kill(child.id() as libc::pid_t, signal) };
        child.wait().unwrap();
        held[whole_run(&folder, &runs, &format!("trial {trial} at {delay:.3} s"))] += 1;
    }
    // Both runs were in the folder at some point: the interrupts were not
    // all too early (or all too late) to test anything.
    assert!(held[0] > 0 && held[1] > 0, "{held:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: `field --out ok.json --svg` with the plot's folder unusable
/// (under a file) exits 2 naming `--svg`, before the work, and leaves
/// ok.json unwritten (before, ok.json was written); with both usable,
/// both are written.
#[test]
fn field_writes_out_and_svg_all_or_none() {
    let dir = temp_dir("field");
    let ok = dir.join("ok.json");
    let blocker = dir.join("a_file");
    std::fs::write(&blocker, "").unwrap();
    let bad_svg = blocker.join("plot.svg");
    let field = |svg: &Path| {
        platefield(&[
            "field",
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../targets/scenes/linesink.json"
            ),
            "--quiet",
            "--out",
            ok.to_str().unwrap(),
            "--svg",
            svg.to_str().unwrap(),
        ])
    };
    let (code, _, err) = field(&bad_svg);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--svg") && err.contains("not a folder"),
        "{err}"
    );
    assert!(!ok.exists(), "ok.json was written beside the refused plot");
    let svg = dir.join("plot.svg");
    let (code, _, err) = field(&svg);
    assert_eq!(code, 0, "{err}");
    assert!(ok.is_file() && svg.is_file());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Runs `platefield args` with a 20 s limit; returns (exit code, stderr),
/// or panics if it did not end (a hang on a FIFO).
fn run_limited(args: &[&str]) -> (i32, String) {
    let mut child = Command::new(BIN)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(20) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{args:?} did not end in 20 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let done = child.wait_with_output().unwrap();
    (
        done.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&done.stderr).into_owned(),
    )
}

/// Issue 30: an endless input (/dev/zero: 6.2 GB of memory before) and a
/// FIFO (a silent hang before) as target, scene or schedule are refused at
/// once as not regular files, and a 65 MiB file as over the 64 MiB cap;
/// each error names the file, exit 2, nothing written.
#[test]
fn inputs_must_be_regular_files_within_the_cap() {
    let dir = temp_dir("inputs");
    let fifo = dir.join("fifo.json");
    let made = Command::new("mkfifo").arg(&fifo).status().unwrap();
    assert!(made.success());
    let big = dir.join("big.json");
    std::fs::File::create(&big)
        .unwrap()
        .set_len(65 << 20)
        .unwrap();
    let out = dir.join("out");
    let o = out.to_str().unwrap();
    let csv = dir.join("s.csv");
    let c = csv.to_str().unwrap();
    for (input, why) in [
        ("/dev/zero", "not a regular file"),
        (fifo.to_str().unwrap(), "not a regular file"),
        (big.to_str().unwrap(), "cap of 64 MiB"),
    ] {
        for args in [
            vec!["design", input, "--out", o, "--quiet"],
            vec!["field", input, "--out", c, "--quiet"],
            vec!["export", input, "--out", c],
            vec!["verify", input, "--out", o, "--quiet"],
        ] {
            let (code, err) = run_limited(&args);
            assert_eq!(code, 2, "{args:?}: {err}");
            assert!(err.contains(input) && err.contains(why), "{args:?}: {err}");
            assert!(!out.exists() && !csv.exists(), "{args:?} wrote something");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: `platefield export SCHEDULE | head -2` panicked ("failed
/// printing to stdout: Broken pipe", exit 101). A reader that closes the
/// pipe after two lines ends the program quietly: exit 0, nothing on
/// stderr but the export's statement of peaks over the schedule's limits.
/// (The CSV is far larger than a pipe's buffer.)
#[test]
fn a_closed_stdout_ends_quietly() {
    let mut child = Command::new(BIN)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args([
            "export",
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../results/synthesized/sink/schedule.json"
            ),
            "--rate",
            "100000",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdout = child.stdout.take().unwrap();
    let mut head = [0u8; 200];
    std::io::Read::read_exact(&mut stdout, &mut head).unwrap();
    assert!(head.starts_with(b"# platefield export"));
    drop(stdout);
    let done = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&done.stderr);
    assert_eq!(done.status.code(), Some(0), "{err}");
    // Only the statement of the scale that keeps the ramps within the
    // schedule's limits (`Export::scaled`) may be on stderr: no error
    // about the pipe.
    assert!(
        err.lines().all(|l| l.starts_with("note: scaled: ")),
        "{err}"
    );
}

/// Issue 30: a basis cache folder that cannot be written failed after the
/// whole build with "Permission denied" and no word of `--no-cache`. It is
/// refused before the build (exit 2, naming the folder and `--no-cache`,
/// nothing written); `--no-cache` designs. The cache folder here is a link
/// to /sys, where even root may not create a file.
#[test]
fn an_unwritable_cache_is_refused_before_the_build_naming_no_cache() {
    let dir = temp_dir("cache");
    let target = sink_target(&dir, "t.json", 1.0);
    std::os::unix::fs::symlink("/sys", dir.join(".platefield-cache")).unwrap();
    let args = |cache: bool| {
        let mut a = vec![
            "design", &target, "--method", "sequence", "--quiet", "--out", "out",
        ];
        if !cache {
            a.push("--no-cache");
        }
        a.into_iter().map(String::from).collect::<Vec<_>>()
    };
    let design = |cache: bool| {
        Command::new(BIN)
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
            .args(args(cache))
            .current_dir(&dir)
            .output()
            .unwrap()
    };
    let refused = design(true);
    let err = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{err}");
    assert!(
        err.contains(".platefield-cache") && err.contains("--no-cache"),
        "{err}"
    );
    assert!(!err.contains("basis: "), "refused after the build: {err}");
    assert!(!dir.join("out").exists());
    let ok = design(false);
    assert!(
        ok.status.success(),
        "{}",
        String::from_utf8_lossy(&ok.stderr)
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: a sampled target with a point given twice was accepted
/// without a word. A repeat with a different vector is refused naming the
/// repeat's path, the point it repeats and both vectors; a repeat with the
/// same vector is refused too (it would weigh twice in the interpolation).
#[test]
fn repeated_sample_points_are_refused_naming_the_path() {
    let dir = temp_dir("samples");
    let out = dir.join("out");
    for (vector, needle) in [
        (
            [0.01, 0.0],
            "with a different vector: [0.02, 0.02] there, [0.01, 0] here",
        ),
        ([0.02, 0.02], "with the same vector"),
    ] {
        let t = serde_json::json!({
            "name": "dup",
            "field": {
                "kind": "sampled",
                "points": [[-0.02, -0.02], [0.02, 0.0], [0.0, 0.02], [-0.02, -0.02]],
                "vectors": [[0.02, 0.02], [-0.02, 0.0], [0.0, -0.02], vector],
            }
        });
        let file = dir.join("t.json");
        std::fs::write(&file, t.to_string()).unwrap();
        let (code, _, err) = platefield(&[
            "design",
            file.to_str().unwrap(),
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{err}");
        let want = "target.field.points[3]: repeats points[0] [-0.02, -0.02]";
        assert!(err.contains(want) && err.contains(needle), "{err}");
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue 30: `verify` accepted a mixed schedule whose segments play
/// different periods, which `export` refused, and `export` named
/// `segments[1]` when segment 0 was edited. Built here from the shipped
/// sequenced sink (primitives) with the shipped synthesized sink motion
/// appended as a ramped segment (one period, accepted by export): an
/// edited ω of segment 0, or an edited period of the motion, is refused by
/// both commands alike, naming the edited segment's key.
#[test]
fn one_period_check_names_the_edited_segment() {
    let dir = temp_dir("period");
    let read = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
    };
    let mut mixed = read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/sequenced/sink/schedule.json"
    ));
    let mut six = read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    ))["segments"][0]
        .clone();
    six["ramp_cycles"] = serde_json::json!(2);
    let segments = mixed["segments"].as_array_mut().unwrap();
    segments.push(six);
    let last = segments.len() - 1;
    let file = dir.join("schedule.json");
    let f = file.to_str().unwrap();
    let csv = dir.join("s.csv");
    let out = dir.join("out");
    let write = |s: &serde_json::Value| std::fs::write(&file, s.to_string()).unwrap();
    write(&mixed);
    let csv_out = csv.to_str().unwrap();
    let export = vec!["export", f, "--rate", "1000", "--out", csv_out];
    let (code, _, err) = platefield(&export);
    assert_eq!(code, 0, "the unedited mixed schedule exports: {err}");
    let mut omega = mixed.clone();
    let w = omega["segments"][0]["primitive"]["omega"].as_f64().unwrap();
    omega["segments"][0]["primitive"]["omega"] = serde_json::json!(w * 1.01);
    let mut period = mixed.clone();
    let t = period["segments"][last]["motion"]["period"]
        .as_f64()
        .unwrap();
    period["segments"][last]["motion"]["period"] = serde_json::json!(t * 1.01);
    for (edited, key) in [
        (&omega, "segments[0].primitive.omega".to_string()),
        (&period, format!("segments[{last}].motion.period")),
    ] {
        write(edited);
        for args in [
            export.clone(),
            ["verify", f]
                .into_iter()
                .chain("--points 2 --swarm 2 --rect-poses 0 --quiet --out".split(' '))
                .chain([out.to_str().unwrap()])
                .collect(),
        ] {
            let (code, _, err) = platefield(&args);
            assert_eq!(code, 2, "{key}: {} {err}", args[0]);
            assert!(
                err.contains(&format!("{key}: the segment plays cycles of")),
                "{key}: {} {err}",
                args[0]
            );
            assert!(!out.exists(), "{key}: verify wrote");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The writability probe is unique per thread as well as per process: many
/// threads of one process checking one folder at once all succeed and leave
/// nothing behind (the CI failure this guards against: two tests' designs in
/// one process probing one cache folder, `File exists`).
#[test]
fn concurrent_writability_checks_in_one_process_all_pass() {
    let dir = temp_dir("probe");
    std::thread::scope(|s| {
        let handles: Vec<_> = (0..16)
            .map(|_| {
                s.spawn(|| {
                    (0..200)
                        .filter(|_| ::platefield::output::check_writable(&dir, "--cache").is_err())
                        .count()
                })
            })
            .collect();
        let failures: usize = handles.into_iter().map(|h| h.join().unwrap()).sum();
        assert_eq!(failures, 0, "writability checks failed under concurrency");
    });
    let left = std::fs::read_dir(&dir).unwrap().count();
    assert_eq!(left, 0, "probe files left behind");
    let _ = std::fs::remove_dir_all(&dir);
}
