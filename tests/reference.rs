//! The command reference, `docs/reference/*.md`, is clap's `--help` of the
//! binary: one page per subcommand and an index from `platefield --help`.
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
    assert!(
        subs.len() >= 10 && subs.iter().any(|s| s == "design"),
        "{subs:?}"
    );
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
    pages
}

#[test]
fn reference_pages_are_the_current_help() {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("docs/reference");
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
