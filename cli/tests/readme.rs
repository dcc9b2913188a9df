//! Every command in README.md is run (issue 29: "every command in it run by
//! a test"). The README's ```sh blocks are read line by line (a `#` after
//! whitespace outside quotes starts a comment) and each command is handled
//! by its kind, in README order, in one scratch folder holding a copy of
//! `targets/` (so the files one command writes are the next one's input,
//! as for a reader following the worked example):
//!
//! - `cargo run --release -- SUBCOMMAND …` runs the built binary:
//!   - `export` and `field` as written (quick);
//!   - `design` with a small budget appended: `--method synthesize
//!     --synth-evaluations 30 --polish-plays 0 --quiet` (the default run
//!     synthesizes 300 evaluations and polishes 300 plays, about 25 s; what
//!     it keeps for the sink is `results/sink/`); its summary must open
//!     with the kept design;
//!   - `verify` with a small play appended: `--points 2 --swarm 2
//!     --rect-poses 0 --repetitions 1 --quiet`; its files must land beside
//!     the schedule;
//!   - any other subcommand with `--help` only (argument parsing).
//! - `.ci/run` (the test command itself, which runs this test) is checked
//!   as a file: executable, `bash -n` clean, and running `cargo test
//!   --release` and the Python tests.
//! - `pip install ./python` and `python -c …` are run by `.ci/run`: it
//!   installs the package exactly so, and `python/tests/test_readme.py`
//!   runs the README's `python -c` lines; here the package and that test
//!   must exist.
//!
//! A README command of any other kind fails the test, so a new one must be
//! given a rule here. The README's target JSON must also be
//! `targets/sink.json`'s content.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository root.
fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
}

fn readme() -> String {
    std::fs::read_to_string(root().join("README.md")).expect("README.md")
}

/// The lines of every fenced block tagged `lang`.
fn fenced(text: &str, lang: &str) -> Vec<Vec<String>> {
    let mut blocks = Vec::new();
    let mut current: Option<Vec<String>> = None;
    for line in text.lines() {
        let t = line.trim();
        match &mut current {
            None if t == format!("```{lang}") => current = Some(Vec::new()),
            Some(_) if t == "```" => blocks.push(current.take().unwrap()),
            Some(b) => b.push(t.to_string()),
            None => {}
        }
    }
    blocks
}

/// `line` without its trailing comment, split into words (double quotes
/// group words and are removed).
fn words(line: &str) -> Vec<String> {
    let (mut out, mut word, mut quoted, mut prev_space) = (Vec::new(), String::new(), false, true);
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            '#' if !quoted && prev_space => break,
            c if c.is_whitespace() && !quoted => {
                if !word.is_empty() {
                    out.push(std::mem::take(&mut word));
                }
            }
            c => word.push(c),
        }
        prev_space = c.is_whitespace() && !quoted;
    }
    if !word.is_empty() {
        out.push(word);
    }
    out
}

/// Every command of the README's ```sh blocks, as words.
fn readme_commands() -> Vec<Vec<String>> {
    fenced(&readme(), "sh")
        .into_iter()
        .flatten()
        .map(|l| words(&l))
        .filter(|w| !w.is_empty())
        .collect()
}

/// Runs the binary in `dir`; returns (exit code, stdout, stderr).
fn run_in(dir: &Path, args: &[String]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_platefield"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let e = e.unwrap();
        let dest = to.join(e.file_name());
        if e.file_type().unwrap().is_dir() {
            copy_dir(&e.path(), &dest);
        } else {
            std::fs::copy(e.path(), dest).unwrap();
        }
    }
}

fn strings(s: &[&str]) -> Vec<String> {
    s.iter().map(|x| x.to_string()).collect()
}

/// What a README `design` runs with (see the module documentation).
const DESIGN_BUDGET: &str = "--method synthesize --synth-evaluations 30 --polish-plays 0 --quiet";

/// What a README `verify` runs with (see the module documentation).
const VERIFY_PLAY: &str = "--points 2 --swarm 2 --rect-poses 0 --repetitions 1 --quiet";

/// Runs one `platefield SUBCOMMAND …` line of the README in `dir` by the
/// rules of the module documentation.
fn run_subcommand(dir: &Path, args: &[String]) {
    let mut args = args.to_vec();
    let sub = args[0].clone();
    match sub.as_str() {
        "design" => args.extend(words(DESIGN_BUDGET)),
        "verify" => args.extend(words(VERIFY_PLAY)),
        "export" | "field" => {}
        _ => args = vec![sub.clone(), "--help".to_string()],
    }
    let (code, out, err) = run_in(dir, &args);
    assert_eq!(
        code,
        0,
        "README command `platefield {}`: {err}",
        args.join(" ")
    );
    match sub.as_str() {
        "design" => assert!(
            out.starts_with("kept "),
            "design's summary opens with the kept design: {out}"
        ),
        "verify" => {
            let schedule = Path::new(&args[1]);
            let beside = dir.join(schedule.parent().unwrap()).join("verify");
            assert!(
                beside.join("summary.json").is_file(),
                "verify writes beside the schedule: {out}"
            );
        }
        "export" => {
            let i = args
                .iter()
                .position(|a| a == "--out")
                .expect("the README's exports write files");
            let file =
                std::fs::read_to_string(dir.join(&args[i + 1])).expect("export wrote its file");
            assert!(
                file.contains("stroke"),
                "every export states the peaks: {file:.300}"
            );
        }
        _ => {}
    }
}

#[test]
fn every_readme_command_runs() {
    let commands = readme_commands();
    let dir = std::env::temp_dir().join(format!("platefield-readme-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    copy_dir(&root().join("targets"), &dir.join("targets"));
    let mut ran = Vec::new();
    for w in &commands {
        let line = w.join(" ");
        match w.iter().map(String::as_str).collect::<Vec<_>>().as_slice() {
            ["cargo", "run", "--release", "--", rest @ ..] => run_subcommand(&dir, &strings(rest)),
            [".ci/run"] => check_ci_run(),
            ["pip", "install", "./python"] => {
                assert!(root().join("python/pyproject.toml").is_file(), "{line}")
            }
            ["python", "-c", _] => assert!(
                root().join("python/tests/test_readme.py").is_file(),
                "{line}: run by python/tests/test_readme.py"
            ),
            _ => panic!("README command without a rule in tests/readme.rs: `{line}`"),
        }
        ran.push(line);
    }
    let _ = std::fs::remove_dir_all(&dir);
    // The README's commands: the two set-up ones, the worked example, the
    // Python quick start.
    assert!(ran.len() >= 6, "{ran:?}");
    assert_eq!(
        ran.iter().take(2).cloned().collect::<Vec<_>>(),
        ["cargo run --release -- design targets/sink.json", ".ci/run"],
        "the two set-up commands come first"
    );
}

/// `.ci/run`: executable, valid bash, running both test suites.
fn check_ci_run() {
    let path = root().join(".ci/run");
    let text = std::fs::read_to_string(&path).expect(".ci/run");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(&path).unwrap().permissions().mode();
        assert!(mode & 0o111 != 0, ".ci/run is executable");
    }
    let ok = Command::new("bash")
        .arg("-n")
        .arg(&path)
        .status()
        .expect("bash");
    assert!(ok.success(), ".ci/run: bash -n");
    assert!(text.contains("cargo test --release") && text.contains("pytest"));
}

#[test]
fn readme_is_short_and_its_target_is_the_shipped_one() {
    let text = readme();
    assert!(
        text.lines().count() <= 150,
        "README.md: {} lines",
        text.lines().count()
    );
    let json = fenced(&text, "json");
    assert_eq!(json.len(), 1);
    let shown: serde_json::Value =
        serde_json::from_str(&json[0].join("\n")).expect("the README's target parses");
    let mut shipped: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(root().join("targets/sink.json")).unwrap())
            .unwrap();
    shipped.as_object_mut().unwrap().remove("weights"); // null: the default
    assert_eq!(shown, shipped);
}

/// The design's first line the README quotes is the committed design's
/// (`results/sink/report.md`), up to its explanation.
#[test]
fn readme_quotes_the_committed_designs_first_line() {
    let text = readme();
    let quoted = fenced(&text, "text")
        .into_iter()
        .flatten()
        .find(|l| l.starts_with("kept "))
        .expect("the README quotes the design's first line");
    let quoted = quoted.trim_end_matches('…').trim_end();
    let report = std::fs::read_to_string(root().join("results/sink/report.md")).unwrap();
    let first = report
        .lines()
        .find(|l| l.starts_with("kept "))
        .expect("report.md opens with the kept design");
    assert!(
        first.starts_with(quoted),
        "README: {quoted}\nreport.md: {first}"
    );
}

/// Every page the README links to exists.
#[test]
fn readme_links_resolve() {
    let text = readme();
    for part in text.split("](").skip(1) {
        let link = &part[..part.find(')').unwrap()];
        if link.starts_with("http") {
            continue;
        }
        assert!(
            root().join(link).exists(),
            "README links to {link}, which does not exist"
        );
    }
}
