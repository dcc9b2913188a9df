//! The command reference, `docs/reference/*.md`, is clap's `--help` of the
//! binary: one page per subcommand (the studies' as `study-<name>.md`) and
//! an index from `platefield --help`.
//! This test fails when a page is missing or stale, naming it; to
//! regenerate them all:
//!
//! ```sh
//! PLATEFIELD_WRITE_REFERENCE=1 cargo test --release --test reference
//! ```

use std::path::PathBuf;
use std::process::Command;

fn help(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_platefield"))
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/.."))
        .args(args)
        .arg("--help")
        .output()
        .expect("runs");
    assert!(out.status.success(), "platefield {args:?} --help");
    String::from_utf8(out.stdout).expect("utf-8")
}

/// The subcommands `platefield --help` lists (its `Commands:` section,
/// without `help`).
fn subcommands(top: &str) -> Vec<String> {
    top.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

fn page(title: &str, help: &str, note: &str) -> String {
    format!("# {title}\n\n{note}Generated from `{title} --help` by `tests/reference.rs`; do not edit.\n\n```text\n{}\n```\n", help.trim_end())
}

/// Every page: (file name, contents).
fn pages() -> Vec<(String, String)> {
    let top = help(&[]);
    let subs = subcommands(&top);
    // The user's commands and the studies' group, at most 8 entries.
    assert!(
        (6..=8).contains(&subs.len()) && subs.iter().any(|s| s == "design"),
        "{subs:?}"
    );
    let studies = subcommands(&help(&["study"]));
    assert!(studies.len() >= 10, "{studies:?}");
    let index: String = subs
        .iter()
        .map(|s| format!("- [`platefield {s}`]({s}.md)\n"))
        .collect();
    let mut pages = vec![(
        "README.md".to_string(),
        page(
            "platefield",
            &top,
            &format!("The command reference, one page per subcommand (the user guide: [docs/](../README.md)):\n\n{index}\n"),
        ),
    )];
    for s in &subs {
        pages.push((
            format!("{s}.md"),
            page(&format!("platefield {s}"), &help(&[s]), ""),
        ));
    }
    for s in &studies {
        pages.push((
            format!("study-{s}.md"),
            page(&format!("platefield study {s}"), &help(&["study", s]), ""),
        ));
    }
    pages
}

/// Every page is written for users: under 60 lines, with no rustdoc link,
/// no work-log reference and no pointer to a README section that is gone
/// (details live in docs/).
#[test]
fn help_pages_are_short_and_plain() {
    let issue = |text: &str| {
        let lower = text.to_lowercase();
        lower.match_indices("issue ").any(|(k, m)| {
            lower[k + m.len()..]
                .chars()
                .next()
                .is_some_and(|c| c.is_ascii_digit())
        })
    };
    let top = help(&[]);
    let mut commands: Vec<Vec<String>> = subcommands(&top).into_iter().map(|s| vec![s]).collect();
    commands.extend(
        subcommands(&help(&["study"]))
            .into_iter()
            .map(|s| vec!["study".to_string(), s]),
    );
    commands.push(Vec::new());
    for args in commands {
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        let (name, text) = (args.join(" "), help(&args));
        let lines = text.lines().count();
        assert!(lines < 60, "platefield {name} --help: {lines} lines");
        assert!(!text.contains("[`"), "{name} has a rustdoc link");
        assert!(!issue(&text), "{name} cites an issue");
        assert!(!text.contains("README's"), "{name} points into the README");
    }
    assert!(issue("before Issue 27") && !issue("the issue is"));
}

#[test]
fn reference_pages_are_the_current_help() {
    let dir = PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/..")).join("docs/reference");
    let write = std::env::var_os("PLATEFIELD_WRITE_REFERENCE").is_some();
    let mut stale = Vec::new();
    let pages = pages();
    for (name, text) in &pages {
        let path = dir.join(name);
        if std::fs::read_to_string(&path).ok().as_deref() == Some(text.as_str()) {
            continue;
        }
        if write {
            std::fs::create_dir_all(&dir).unwrap();
            std::fs::write(&path, text).unwrap();
        } else {
            stale.push(name.clone());
        }
    }
    // No page for a subcommand that is gone.
    for e in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.ends_with(".md") && !pages.iter().any(|(n, _)| *n == name) {
            if write {
                std::fs::remove_file(e.path()).unwrap();
            } else {
                stale.push(format!("{name} (no such subcommand)"));
            }
        }
    }
    assert!(
        stale.is_empty(),
        "docs/reference is stale: {stale:?}; regenerate with PLATEFIELD_WRITE_REFERENCE=1 cargo test --release --test reference"
    );
}
