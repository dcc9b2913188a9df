//! Trust at the edges: files and folders that are not results are never
//! replaced or emptied, interrupted runs are cleaned up, work is bounded,
//! numbers at their limits are refused or normalised, and errors name
//! their cause.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::{design_args, platefield};

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
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
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
            .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
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

/// The CSV `export` writes for `schedule`, with every acceleration of every
/// row replaced by `value` (times and comments kept).
fn export_with_accelerations(schedule: &str, value: &str) -> String {
    let (code, csv, err) = platefield(&["export", schedule]);
    assert_eq!(code, 0, "{err}");
    csv.lines()
        .map(|l| {
            if l.starts_with('#') || l.starts_with("t_s") {
                return format!("{l}\n");
            }
            let t = l.split(',').next().unwrap();
            format!("{t},{}\n", [value; 6].join(","))
        })
        .collect()
}

/// Item 5: `verify --replay` of a file whose accelerations are all 1e300
/// (or 1e100) m/s² is refused at once, naming the file's line and column
/// and the bound 1e4 m/s², exit 2. Before, it ran for more than 300 s
/// inside an SVD that never converges on the non-finite played field.
#[test]
fn replay_of_non_physical_accelerations_is_refused_at_once() {
    let dir = temp_dir("huge");
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
    for value in ["1e300", "1e100", "2e4"] {
        let csv = dir.join(format!("{value}.csv"));
        std::fs::write(&csv, export_with_accelerations(schedule, value)).unwrap();
        let start = Instant::now();
        let (code, _, err) = platefield(&[
            "verify",
            schedule,
            "--replay",
            csv.to_str().unwrap(),
            "--out",
            dir.join("out").to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{value}: {err}");
        assert!(
            err.contains(&format!("{} line ", csv.display()))
                && err.contains("column 2 (ax_m_s2)")
                && err.contains("is not a physical plate acceleration: at most 1e4 m/s²"),
            "{value}: {err}"
        );
        assert!(start.elapsed() < Duration::from_secs(30), "{value}");
        assert!(!dir.join("out").exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A small sink target (5 × 5 points) with `friction` (a JSON value).
fn sink_with_friction(dir: &Path, file: &str, friction: serde_json::Value) -> String {
    let t = serde_json::json!({
        "name": "sink",
        "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [5, 5]},
        "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0},
        "friction": friction,
    });
    let path = dir.join(file);
    std::fs::write(&path, t.to_string()).unwrap();
    path.to_str().unwrap().to_string()
}

/// Item 9: μ_k = 0, −0.0 or 1e-300 in a target, or `verify --friction 0`,
/// is refused before any work, naming the key and saying that parts on a
/// frictionless plate cannot be driven (exit 2, nothing written). Before,
/// the design ran to a 150 s all-rest schedule and verify blamed lost
/// contact.
#[test]
fn a_frictionless_plate_is_refused_naming_the_key() {
    let dir = temp_dir("mu0");
    let out = dir.join("out");
    for (friction, key, shown) in [
        (
            serde_json::json!(0.0),
            "target.friction",
            "μ_k = 0 is a frictionless plate",
        ),
        (
            serde_json::json!(-0.0),
            "target.friction",
            "μ_k = 0 is a frictionless plate",
        ),
        (
            serde_json::json!(1e-300),
            "target.friction",
            "μ_k = 1e-300 is in effect a frictionless plate",
        ),
        (
            serde_json::json!([0.0, 0.4]),
            "target.friction[0]",
            "μ_k = 0 is a frictionless plate",
        ),
        (
            serde_json::json!({"static": 0.3, "kinetic": 0.0}),
            "target.friction.kinetic",
            "μ_k = 0 is a frictionless plate",
        ),
    ] {
        let target = sink_with_friction(&dir, "t.json", friction.clone());
        let (code, _, err) = platefield(&design_args(&target, out.to_str().unwrap()));
        assert_eq!(code, 2, "{friction}: {err}");
        assert!(
            err.contains(&format!("{key}: {shown}: parts on it cannot be driven")),
            "{friction}: {err}"
        );
        assert!(!out.exists());
    }
    for friction in ["0", "-0.0", "0:0.4:3"] {
        let (code, _, err) = platefield(&[
            "verify",
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../results/synthesized/sink/schedule.json"
            ),
            "--friction",
            friction,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 2, "{friction}: {err}");
        assert!(
            err.contains("--friction") && err.contains("parts on it cannot be driven"),
            "{friction}: {err}"
        );
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 10: the shipped sink target at μ = 2 (the documented maximum) with
/// `--method sequence` is designed. Before, its fit was refused with "kkt
/// residual 2.165e-6 exceeds tolerance 1e-6": the complementarity sum was
/// absolute while the answer combines fields whose total size is many
/// times the target's (the parts mostly stick at μ 2); it is now relative
/// to that scale, and the independent NNLS optimum still bounds the
/// answer's error. The design reports what μ 2 allows: a POOR, weak sink.
#[test]
#[ignore = "about 40 s of CPU: cargo test --release --test edges -- --ignored mu_2"]
fn mu_2_with_sequence_is_certified_relative_to_the_problem_scale() {
    let dir = temp_dir("mu2");
    let mut t: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"))
            .unwrap(),
    )
    .unwrap();
    t["friction"] = serde_json::json!(2.0);
    let target = dir.join("mu2.json");
    std::fs::write(&target, t.to_string()).unwrap();
    let out = dir.join("out");
    let (code, stdout, err) = platefield(&[
        "design",
        target.to_str().unwrap(),
        "--method",
        "sequence",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("POOR"), "{stdout}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 11: `verify --replay` of another schedule's export (the same
/// layout: the sink's schedule with its y harmonic's phase set to 2.5 rad)
/// is refused first, naming the file and both fingerprints, exit 2.
/// Before: exit 0 and "strength differs by 78.08 %".
#[test]
fn replay_of_another_schedules_export_is_refused_by_its_fingerprint() {
    let dir = temp_dir("other");
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
    let mut other: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(schedule).unwrap()).unwrap();
    other["segments"][0]["motion"]["linear"]["y"][0]["phase"] = serde_json::json!(2.5);
    let other_path = dir.join("other.json");
    std::fs::write(&other_path, other.to_string()).unwrap();
    let csv = dir.join("other.csv");
    let (code, _, err) = platefield(&[
        "export",
        other_path.to_str().unwrap(),
        "--rate",
        "2000",
        "--steady-cycles",
        "1",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&csv).unwrap();
    let stated = platefield::motion::held_csv::fingerprint(&text).unwrap();
    let out = dir.join("out");
    let replay = |file: &Path| {
        platefield(&[
            "verify",
            schedule,
            "--replay",
            file.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ])
    };
    let (code, _, err) = replay(&csv);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!(
            "{}: is the export of another schedule: its header states the schedule fingerprint {stated}, this schedule's is ",
            csv.display()
        )),
        "{err}"
    );
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 12: an export too large for `verify --replay` (500 kHz: 67 MiB)
/// warns with its size, the one limit (64 MiB) and the rate that fits;
/// replaying it is refused with the same words; an export at that rate
/// fits the limit. Before, the export said nothing and the replay refused
/// it without a rate.
#[test]
fn export_and_replay_state_one_size_limit() {
    let dir = temp_dir("size");
    let schedule = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../results/synthesized/sink/schedule.json"
    );
    let big = dir.join("big.csv");
    let (code, _, err) = platefield(&[
        "export",
        schedule,
        "--rate",
        "500000",
        "--out",
        big.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let advice = "MiB, over the 64 MiB a file `verify --replay` reads: export it at --rate ";
    let mib = std::fs::metadata(&big)
        .expect("the export was written")
        .len() as f64
        / 1048576.0;
    assert!(
        err.contains(&format!("warning: the file is {mib:.1} {advice}")),
        "{err}"
    );
    let rate = err
        .split("--rate ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap()
        .to_string();
    let (code, _, err) = platefield(&[
        "verify",
        schedule,
        "--replay",
        big.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("{}: ", big.display()))
            && err.contains(&format!(" {advice}{rate} or lower")),
        "{err}"
    );
    std::fs::remove_file(&big).unwrap();
    let (code, _, err) = platefield(&[
        "export",
        schedule,
        "--rate",
        &rate,
        "--out",
        big.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("verify --replay"), "{err}");
    assert!(std::fs::metadata(&big).unwrap().len() <= 64 << 20);
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 13: three errors now name their cause: a pose angle of 1e9 states
/// the limit; `poses` given a pose or sorting target says what it is and
/// what to give instead, with the file named once; a support object with
/// two keys says it has two, and which.
#[test]
fn errors_name_their_cause() {
    let dir = temp_dir("errors");
    let mut pose: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/pose_rectangle.json"
        ))
        .unwrap(),
    )
    .unwrap();
    pose["field"]["pose"][2] = serde_json::json!(1e9);
    pose["field"]["part"] = serde_json::json!(std::fs::canonicalize(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../targets/parts/rectangle.json"
    ))
    .unwrap()
    .to_str()
    .unwrap());
    let pose_file = dir.join("pose.json");
    std::fs::write(&pose_file, pose.to_string()).unwrap();
    let out = dir.join("out");
    let (code, _, err) = platefield(&design_args(
        pose_file.to_str().unwrap(),
        out.to_str().unwrap(),
    ));
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("target.field.pose[2]: must be a finite number in [-1e6, 1e6] degrees, got 1"),
        "{err}"
    );

    for (source, key, what) in [
        (
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../targets/pose_rectangle.json"
            ),
            "target.field.kind",
            "is a pose target",
        ),
        (
            concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sort_friction.json"),
            "target.classes",
            "is a sorting target",
        ),
    ] {
        let (code, _, err) = platefield(&[
            "poses",
            concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../targets/parts/rectangle.json"
            ),
            source,
        ]);
        assert_eq!(code, 2, "{err}");
        assert_eq!(err.matches(source).count(), 1, "{err}");
        assert!(
            err.contains(&format!("{source}: {key}: {what}"))
                && err.contains("give its schedule.json as SOURCE"),
            "{err}"
        );
    }

    let mut part: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/parts/rectangle.json"
        ))
        .unwrap(),
    )
    .unwrap();
    part["support"] = serde_json::json!({"uniform": {"samples": 64}, "unknown": {"contacts": 3}});
    let part_file = dir.join("part.json");
    std::fs::write(&part_file, part.to_string()).unwrap();
    let (code, _, err) = platefield(&[
        "poses",
        part_file.to_str().unwrap(),
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("part.support: must be an object with a single key, the kind it describes, got 2 keys (\"uniform\", \"unknown\")"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 7: a 100 000-vertex polygon is refused at once, naming
/// `part.polygon` and the 4096-vertex limit (before: 100 s of a quadratic
/// check); 4096 vertices load. `poses --drops 100000` states its work and
/// is refused without `--allow-long`, naming `--drops` (before: no
/// estimate and about a day of work), and so is the default 200 drops of
/// a part 2e-8 m across.
#[test]
fn poses_work_is_bounded_and_stated() {
    let dir = temp_dir("poses");
    let circle = |n: usize, r: f64| -> Vec<[f64; 2]> {
        (0..n)
            .map(|k| {
                let a = std::f64::consts::TAU * k as f64 / n as f64;
                [r * a.cos(), r * a.sin()]
            })
            .collect()
    };
    let part = |name: &str, polygon: Vec<[f64; 2]>| {
        let path = dir.join(name);
        let p = serde_json::json!({"name": "p", "polygon": polygon, "friction": 0.3});
        std::fs::write(&path, p.to_string()).unwrap();
        path.to_str().unwrap().to_string()
    };
    let huge = part("huge.json", circle(100_000, 0.005));
    let start = Instant::now();
    let (code, _, err) = platefield(&[
        "poses",
        &huge,
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
        "--drops",
        "1",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("part.polygon: has 100000 vertices, more than the 4096"),
        "{err}"
    );
    assert!(start.elapsed() < Duration::from_secs(10));
    let most = part("most.json", circle(4096, 0.005));
    let (code, _, err) = platefield(&[
        "poses",
        &most,
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
        "--drops",
        "1",
    ]);
    assert_eq!(code, 0, "{err}");

    let (code, _, err) = platefield(&[
        "poses",
        concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/parts/rectangle.json"
        ),
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
        "--drops",
        "100000",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--drops") && err.contains("settling the drops would take about"),
        "{err}"
    );
    let thin = part(
        "thin.json",
        vec![[0.0, 0.0], [2e-8, 0.0], [2e-8, 1e-8], [0.0, 1e-8]],
    );
    // 20000 steps a drop: 1000 drops are over the limit.
    let (code, _, err) = platefield(&[
        "poses",
        &thin,
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sink.json"),
        "--drops",
        "1000",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("settling the drops would take about"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 6: a sorting target (2 classes on a 9 × 5 grid: 149 s of CPU with
/// nothing on stderr before) states the design's work first (the
/// libraries, the syntheses, the aiming plays; the swarms' work is stated
/// again before they are played) and then reports its progress class by
/// class on stderr. The run is stopped once both have been seen.
#[test]
fn sorting_states_its_work_and_progress() {
    use std::io::BufRead;
    let dir = temp_dir("sort");
    let mut t: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../targets/sort_friction.json"
        ))
        .unwrap(),
    )
    .unwrap();
    t["grid"]["n"] = serde_json::json!([9, 5]);
    let target = dir.join("sort.json");
    std::fs::write(&target, t.to_string()).unwrap();
    let mut child = Command::new(BIN)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args([
            "design",
            target.to_str().unwrap(),
            "--no-cache",
            "--out",
            dir.join("out").to_str().unwrap(),
        ])
        .env("PLATEFIELD_PROGRESS_INTERVAL", "0.2")
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let (mut estimate, mut progress) = (None, false);
    for line in stderr.lines() {
        let line = line.unwrap();
        if line.starts_with("designing the sort would take about") {
            estimate = Some(line);
        } else if line.starts_with("sort: libraries: ") && line.contains("/2 classes") {
            // The first tick may come after a class is done (a loaded
            // machine): any count of the two classes is progress.
            assert!(estimate.is_some(), "progress before the estimate");
            progress = true;
            break;
        }
    }
    let _ = child.kill();
    let _ = child.wait();
    let estimate = estimate.expect("no estimate on stderr");
    assert!(estimate.contains("sort syntheses"), "{estimate}");
    assert!(progress, "no progress line");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The headings (`#` lines, without the hashes) of the markdown file at
/// `path`.
fn headings(path: &str) -> Vec<String> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| l.starts_with('#'))
        .map(|l| l.trim_start_matches('#').trim().to_string())
        .collect()
}

/// Item 15: cross-references stay true. Every section a text names in the
/// README ("the README's *X*", `README, "X"`; in `--help`, every mention
/// of the README) is a heading of README.md;
/// every `docs/…md` path the docs, the README or the commands' `--help`
/// name exists; and the README says where to load an export in Python
/// only where that is shown. Before: `design --help` named "the README's
/// target schema", `field --help` `README, "Scenes"`, docs/python.md "the
/// README's *Inverse design*" (none is a README section), and the README
/// sent Python users to docs/shaker.md, which does not show Python.
#[test]
fn cross_references_name_what_exists() {
    let readme = headings(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md"));
    let mut texts: Vec<(String, String)> = vec![(
        "README.md".into(),
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap(),
    )];
    for e in std::fs::read_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs")).unwrap() {
        let path = e.unwrap().path();
        if path.extension().is_some_and(|x| x == "md") {
            texts.push((
                path.display().to_string(),
                std::fs::read_to_string(&path).unwrap(),
            ));
        }
    }
    for command in ["design", "verify", "export", "field", "poses", "order"] {
        let (_, help, _) = platefield(&[command, "--help"]);
        texts.push((format!("{command} --help"), help));
    }
    for (name, text) in &texts {
        let text = text.replace('\n', " ");
        for mark in ["README's *", "README, \"", "README's "] {
            for rest in text.split(mark).skip(1) {
                let end = if mark.ends_with('*') { '*' } else { '"' };
                if mark == "README's " {
                    // In a command's help, a plain "the README's ..." must
                    // name one of its sections in italics or quotes
                    // (checked above).
                    if !name.ends_with("--help") {
                        continue;
                    }
                    assert!(
                        rest.starts_with('*') || rest.starts_with('"'),
                        "{name}: \"README's {}\" names no section",
                        &rest[..rest.len().min(30)]
                    );
                    continue;
                }
                let section = rest.split(end).next().unwrap();
                assert!(
                    readme.iter().any(|h| h == section),
                    "{name}: the README has no section \"{section}\""
                );
            }
        }
        for rest in text
            .split(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/"))
            .skip(1)
        {
            let path: String = rest
                .chars()
                .take_while(|c| c.is_alphanumeric() || matches!(c, '_' | '-' | '.' | '/'))
                .collect();
            let path = path.trim_end_matches('.');
            if path.ends_with(".md") {
                assert!(
                    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs"))
                        .join(path)
                        .is_file(),
                    "{name}: docs/{path} does not exist"
                );
            }
        }
    }
    let shaker =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/shaker.md")).unwrap();
    let readme_text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/../README.md")).unwrap();
    if !shaker.contains("import platefield") {
        assert!(
            !readme_text.contains("Loading these in MATLAB or Python: [docs/shaker.md]"),
            "the README sends Python users to docs/shaker.md"
        );
    }
}

/// Item 18: `fit.svg`'s title states the realised strength the headline
/// reports beside the predicted one it scales the target by, and the red
/// × marks of masked points have a legend; `signals.svg`'s time axis ends
/// at the period (before: 35 ms for a 30.1 ms period).
#[test]
fn plots_state_what_the_headline_states() {
    let dir = temp_dir("plots");
    let t = serde_json::json!({
        "name": "sink",
        "grid": {"x": [-0.04, 0.04], "y": [-0.04, 0.04], "n": [7, 7]},
        "field": {"kind": "sink", "center": [0.0, 0.0], "strength": 1.0},
        "mask": [{"circle": {"center": [0.0, 0.0], "radius": 0.005}}],
    });
    let target = dir.join("t.json");
    std::fs::write(&target, t.to_string()).unwrap();
    let out = dir.join("out");
    let (code, stdout, err) = platefield(&design_args(
        target.to_str().unwrap(),
        out.to_str().unwrap(),
    ));
    assert_eq!(code, 0, "{err}");
    let realised = stdout
        .split("realised strength ")
        .nth(1)
        .and_then(|r| r.split(' ').next())
        .unwrap();
    let svg = std::fs::read_to_string(out.join("sink/fit.svg")).unwrap();
    assert!(
        svg.contains(&format!("; realised {realised})")),
        "fit.svg's title lacks the realised strength {realised}"
    );
    assert!(
        svg.contains("masked (weight 0)"),
        "no legend for the × marks"
    );

    let (code, _, err) = platefield(&[
        "design",
        target.to_str().unwrap(),
        "--method",
        "synthesize",
        "--synth-evaluations",
        "20",
        "--polish-plays",
        "0",
        "--no-cache",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let svg = std::fs::read_to_string(out.join("sink/signals.svg")).unwrap();
    let period_ms: f64 = svg
        .split("(T = ")
        .nth(1)
        .and_then(|r| r.split(" ms").next())
        .unwrap()
        .parse()
        .unwrap();
    // The x tick labels sit below the plot, centred ("middle") on whole
    // numbers of ms: none may pass the period.
    let ticks: Vec<f64> = svg
        .split("text-anchor=\"middle\"")
        .skip(1)
        .filter_map(|r| r.split('>').nth(1)?.split('<').next()?.trim().parse().ok())
        .collect();
    assert!(!ticks.is_empty(), "no tick labels found");
    let last = ticks.iter().copied().fold(f64::MIN, f64::max);
    assert!(
        last <= period_ms + 1e-9,
        "the time axis runs to {last} ms for a {period_ms} ms period"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Item 16: `design --friction` sets the target's friction, as `verify
/// --friction` sets the friction played: the schedule records it; μ 0 is
/// refused naming `--friction`; a sorting target's classes keep theirs.
#[test]
fn design_friction_sets_the_targets_friction() {
    let dir = temp_dir("friction");
    let target = sink_target(&dir, "t.json", "sink");
    let out = dir.join("out");
    let with = |friction: &str| {
        let mut args = design_args(&target, out.to_str().unwrap());
        args.extend(["--friction", friction]);
        platefield(&args)
    };
    let (code, _, err) = with("0.45");
    assert_eq!(code, 0, "{err}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("sink/schedule.json")).unwrap())
            .unwrap();
    assert_eq!(s["target_spec"]["friction"], serde_json::json!(0.45));
    let (code, _, err) = with("0");
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--friction: μ_k = 0 is a frictionless plate"),
        "{err}"
    );
    let (code, _, err) = platefield(&[
        "design",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../targets/sort_friction.json"),
        "--friction",
        "0.3",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--friction: a sorting target's classes state their own friction"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
