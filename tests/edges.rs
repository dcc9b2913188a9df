//! Trust at the edges: files and folders that are not results are never
//! replaced or emptied, interrupted runs are cleaned up, work is bounded,
//! numbers at their limits are refused or normalised, and errors name
//! their cause.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::platefield;

const BIN: &str = env!("CARGO_BIN_EXE_platefield");

/// A fresh temporary folder for one test, under `base`.
fn temp_in(base: &Path, name: &str) -> PathBuf {
    let dir = base.join(format!("platefield-edges-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// A fresh temporary folder for one test.
fn temp_dir(name: &str) -> PathBuf {
    temp_in(&std::env::temp_dir(), name)
}

/// A small sink target named `name` (5 × 5 points), written to `dir/file`.
fn sink_target(dir: &Path, file: &str, name: &str) -> String {
    let t = serde_json::json!({
        "name": name,
        "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [5, 5]},
        "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0},
    });
    let path = dir.join(file);
    std::fs::write(&path, t.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

/// The arguments of a fast design (0.1 s) of `target` into `out`.
fn design_args<'a>(target: &'a str, out: &'a str) -> Vec<&'a str> {
    let fast = "--method sequence --primitives LineSink --rotation-step 90 --no-cache --quiet";
    ["design", target]
        .into_iter()
        .chain(fast.split(' '))
        .chain(["--out", out])
        .collect()
}

/// The names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut n: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    n.sort();
    n
}

/// The staging folders left in `dir`.
fn stages(dir: &Path) -> Vec<String> {
    names(dir)
        .into_iter()
        .filter(|n| n.contains(".platefield-stage-"))
        .collect()
}

/// A process id that is no longer running: a finished child's.
fn dead_pid() -> u32 {
    let mut child = Command::new("true").spawn().unwrap();
    let pid = child.id();
    child.wait().unwrap();
    pid
}

/// Item 1: `export --out` to a FIFO writes into the FIFO (its reader gets
/// the whole CSV) and leaves it a FIFO; to `/dev/full` it fails with the
/// device's "No space left on device", exit 2, and `/dev/full` stays a
/// character device. Before, both were replaced by a regular file (the
/// FIFO's reader got nothing) and the run said "wrote".
#[test]
fn export_writes_into_special_files_never_over_them() {
    use std::os::unix::fs::FileTypeExt;
    let dir = temp_dir("special");
    let fifo = dir.join("fifo.csv");
    assert!(Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap()
        .success());
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(&fifo).unwrap())
    };
    let schedule = "results/sink/schedule.json";
    let (code, _, err) = platefield(&["export", schedule, "--out", fifo.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    let got = reader.join().unwrap();
    let (code, direct, err) = platefield(&["export", schedule]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(got, direct.as_bytes(), "the FIFO's reader got another text");
    assert!(std::fs::symlink_metadata(&fifo)
        .unwrap()
        .file_type()
        .is_fifo());

    let (code, out, err) = platefield(&["export", schedule, "--out", "/dev/full"]);
    assert_eq!(code, 2, "{out}{err}");
    assert!(
        err.contains("/dev/full") && err.contains("No space left on device"),
        "{err}"
    );
    assert!(std::fs::symlink_metadata("/dev/full")
        .unwrap()
        .file_type()
        .is_char_device());

    // A folder at --out is refused by name.
    let (code, _, err) = platefield(&["export", schedule, "--out", dir.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("a folder, not a file this program can replace"),
        "{err}"
    );

    // A link to a file is followed: the file gets the CSV, the link stays.
    let file = dir.join("real.csv");
    std::fs::write(&file, "old").unwrap();
    let link = dir.join("link.csv");
    std::os::unix::fs::symlink(&file, &link).unwrap();
    let (code, _, err) = platefield(&["export", schedule, "--out", link.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert_eq!(std::fs::read(&file).unwrap(), direct.as_bytes());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 2: `OUT/sink` a link to an earlier result folder (holding the
/// user's notes.txt), on the same file system and across file systems
/// (/dev/shm when it is another one): the design follows the link, says
/// so, writes the new run into the linked folder, keeps notes.txt there,
/// and the link stays a link. Before, the linked folder was emptied and
/// notes.txt moved out, and across file systems the run failed with
/// "Invalid cross-device link".
#[test]
fn result_folder_through_a_link_is_followed() {
    let dir = temp_dir("link");
    let target = sink_target(&dir, "t.json", "sink");
    let mut bases = vec![dir.clone()];
    let shm = Path::new("/dev/shm");
    let device = |p: &Path| std::os::unix::fs::MetadataExt::dev(&p.metadata().unwrap());
    if shm.is_dir() && device(shm) != device(&dir) {
        bases.push(temp_in(shm, "link"));
    }
    for base in &bases {
        let earlier = base.join("earlier");
        let out = dir.join("out");
        let _ = std::fs::remove_dir_all(&out);
        let (code, _, err) = platefield(&design_args(&target, earlier.to_str().unwrap()));
        assert_eq!(code, 0, "{err}");
        let linked = earlier.join("sink");
        std::fs::write(linked.join("notes.txt"), "mine").unwrap();
        std::fs::remove_file(linked.join("report.md")).unwrap();
        std::fs::create_dir_all(&out).unwrap();
        std::os::unix::fs::symlink(&linked, out.join("sink")).unwrap();
        let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
        assert_eq!(code, 0, "{base:?}: {err}");
        assert!(err.contains("is a link to the folder"), "{err}");
        assert!(std::fs::symlink_metadata(out.join("sink"))
            .unwrap()
            .file_type()
            .is_symlink());
        assert_eq!(
            std::fs::read_to_string(linked.join("notes.txt")).unwrap(),
            "mine"
        );
        assert!(linked.join("report.md").is_file() && linked.join("schedule.json").is_file());
        assert!(stages(&earlier).is_empty() && stages(&out).is_empty());
        // A link to a file, and a link to nothing, are refused by name.
        std::fs::remove_file(out.join("sink")).unwrap();
        std::os::unix::fs::symlink(linked.join("notes.txt"), out.join("sink")).unwrap();
        let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("--out") && err.contains("not a folder"),
            "{err}"
        );
        std::fs::remove_file(out.join("sink")).unwrap();
        std::os::unix::fs::symlink(base.join("nowhere"), out.join("sink")).unwrap();
        let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
        assert_eq!(code, 2, "{err}");
        assert!(
            err.contains("--out") && err.contains("leads nowhere"),
            "{err}"
        );
    }
    for base in &bases {
        let _ = std::fs::remove_dir_all(base);
    }
}

/// Item 3: the staging folders a killed run left (one after its swap,
/// holding the user's notes.txt and verify/ and the previous products; one
/// before it, holding only products) are recovered by the next run into
/// the folder: notes.txt and verify/ come back, the staging folders are
/// gone, and stderr says so. Before, they stayed hidden for good.
#[test]
fn stale_stages_are_recovered_and_said() {
    let dir = temp_dir("stale");
    let target = sink_target(&dir, "t.json", "sink");
    let out = dir.join("out");
    let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
    assert_eq!(code, 0, "{err}");
    let pid = dead_pid();
    let after_swap = out.join(format!(".sink.platefield-stage-{pid}-0"));
    std::fs::create_dir_all(after_swap.join("verify")).unwrap();
    std::fs::write(after_swap.join("verify/summary.json"), "{}").unwrap();
    std::fs::write(after_swap.join("notes.txt"), "mine").unwrap();
    std::fs::write(after_swap.join("report.md"), "previous").unwrap();
    let before_swap = out.join(format!(".sink.platefield-stage-{pid}-1"));
    std::fs::create_dir_all(&before_swap).unwrap();
    std::fs::write(before_swap.join("schedule.json"), "unfinished").unwrap();
    // A live process's staging folder (ours) is another run's: kept.
    let live = out.join(format!(".sink.platefield-stage-{}-0", std::process::id()));
    std::fs::create_dir_all(&live).unwrap();

    let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
    assert_eq!(code, 0, "{err}");
    let folder = out.join("sink");
    assert_eq!(
        std::fs::read_to_string(folder.join("notes.txt")).unwrap(),
        "mine"
    );
    assert!(folder.join("verify/summary.json").is_file());
    assert_ne!(
        std::fs::read_to_string(folder.join("report.md")).unwrap(),
        "previous"
    );
    assert!(
        err.contains("note: recovered notes.txt, verify into")
            && err.contains(&format!("interrupted run (process {pid})")),
        "{err}"
    );
    assert!(err.contains("note: removed"), "{err}");
    assert_eq!(
        stages(&out),
        [format!(".sink.platefield-stage-{}-0", std::process::id())]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 3: SIGINT while the run writes its folder leaves no staging folder
/// (before, 19 of 20 interrupted runs left one) and ends with status 130.
/// Each trial signals the run as soon as its staging folder appears.
#[test]
fn sigint_removes_the_staging_folder() {
    let dir = temp_dir("sigint");
    let target = sink_target(&dir, "t.json", "sink");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let mut caught = 0;
    for trial in 0..20 {
        let mut child = Command::new(BIN)
            .args(design_args(&target, out.to_str().unwrap()))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        let start = Instant::now();
        let mut seen = false;
        while child.try_wait().unwrap().is_none() && start.elapsed() < Duration::from_secs(20) {
            if !stages(&out).is_empty() {
                seen = true;
                // SAFETY: kill(2) on the id of our own child, not yet reaped.
                unsafe { libc::kill(child.id() as libc::pid_t, libc::SIGINT) };
                break;
            }
        }
        let status = child.wait().unwrap();
        if seen && status.code() == Some(130) {
            caught += 1;
        }
        let left = stages(&out);
        assert!(
            left.is_empty(),
            "trial {trial} ({status:?}): left {left:?} holding {:?}",
            left.first().map(|s| names(&out.join(s)))
        );
    }
    assert!(caught > 0, "no run was interrupted while it wrote");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 4: a target name too long for its staging folder (240 bytes:
/// under the file system's 255, over the 205 that leave room for the
/// staging folder's suffix) is refused before any work, naming
/// `target.name` and the limit, exit 2, nothing written; 205 bytes are
/// designed. Before: "File name too long" on the staging path.
#[test]
fn long_target_names_are_refused_by_name() {
    let dir = temp_dir("long");
    let out = dir.join("out");
    let long = sink_target(&dir, "long.json", &"n".repeat(240));
    let (code, _, err) = platefield(&design_args(&long, out.to_str().unwrap()));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("target.name: must be a plain folder name (at most 205 bytes")
            && err.contains("(240 bytes)"),
        "{err}"
    );
    assert!(!out.exists());
    let longest = sink_target(&dir, "longest.json", &"n".repeat(205));
    let (code, _, err) = platefield(&design_args(&longest, out.to_str().unwrap()));
    assert_eq!(code, 0, "{err}");
    assert!(out.join("n".repeat(205)).join("schedule.json").is_file());
    let _ = std::fs::remove_dir_all(&dir);
}
