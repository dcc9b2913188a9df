//! The docs' tables of numbers state what a command produced.
//!
//! Every markdown table in `README.md`, `docs/*.md` and `docs/dev/*.md` is listed in
//! [`TABLES`] by its header row, with what keeps it true: either the
//! generated file it is checked against (by a test here or in
//! `python/tests/test_docs.py`), or that it holds no measured number (a
//! schema, a list of pages, formulas). A table that is not listed fails
//! [`every_table_is_accounted_for`], so a new table of measurements has to
//! come with its check, or point to the generated file in `results/`
//! instead of copying it.

use std::path::{Path, PathBuf};

/// The repository root (the library crate's manifest folder).
fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn read(path: &str) -> String {
    std::fs::read_to_string(root().join(path)).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// How a listed table stays true.
enum Kept {
    /// It holds no measured number (names, schema, formulas, ranges).
    NoMeasurement,
    /// It is checked to equal what the named command wrote (the test that
    /// checks it is named in the text).
    Checked(&'static str),
}

/// Every table of the docs, by file and header row.
const TABLES: &[(&str, &str, Kept)] = &[
    ("README.md", "| topic | page |", Kept::NoMeasurement),
    ("docs/README.md", "| page | what it covers |", Kept::NoMeasurement),
    (
        "docs/commands.md",
        "| command | what it does |",
        Kept::NoMeasurement,
    ),
    (
        "docs/measures.md",
        "| name | where you see it | what is played | what it answers |",
        Kept::NoMeasurement,
    ),
    (
        "docs/scenes.md",
        "| key | meaning | default |",
        Kept::NoMeasurement,
    ),
    ("docs/shaker.md", "| reading | formula |", Kept::NoMeasurement),
    (
        "docs/dev/api.md",
        "| kind | count |",
        Kept::Checked("tests/api.rs: the_api_list_is_the_librarys"),
    ),
    (
        "docs/dev/README.md",
        "| moved to `--ignored` | its command | kept in the default run |",
        Kept::NoMeasurement,
    ),
    (
        "docs/python.md",
        "| exception | when | attributes |",
        Kept::NoMeasurement,
    ),
    (
        "docs/python.md",
        "| function | returns | the CLI's |",
        Kept::NoMeasurement,
    ),
    (
        "docs/python.md",
        "| μ | limit on \\|a_x\\|, \\|a_y\\| (m/s²) | kept | predicted strength (s⁻¹) | realised strength (s⁻¹) | realised shape error | |",
        Kept::Checked(
            "generated from docs/python/sweep.json by `python docs/python/sweep_example.py` \
             (`--doc` rewrites it); python/tests/test_docs.py checks it equals sweep.json's table",
        ),
    ),
    (
        "docs/verify.md",
        "| cycles per segment | realised error before → after | realised shape error before → after | strength promised → realised |",
        Kept::Checked(
            "results/closed_loop/min<m>/sink/closed_loop.json, written by `platefield design \
             targets/sink.json --min-cycles <m> --closed-loop`: closed_loop_table_is_the_results",
        ),
    ),
];

/// The header rows of every markdown table in `text` (a `|` line followed
/// by a `|---` line), outside fenced code.
fn table_headers(text: &str) -> Vec<String> {
    let lines: Vec<&str> = text.lines().collect();
    let mut fenced = false;
    let mut out = Vec::new();
    for (i, line) in lines.iter().enumerate() {
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        }
        let next = lines.get(i + 1).map_or("", |l| l.trim());
        if !fenced && line.trim().starts_with('|') && next.starts_with("|---") {
            out.push(line.trim().to_string());
        }
    }
    out
}

/// The rows of the table whose header is `header` in `text` (after the
/// `|---` line, up to the first line that is not a row).
fn table_rows<'a>(text: &'a str, header: &str) -> Vec<&'a str> {
    let start = text
        .find(header)
        .unwrap_or_else(|| panic!("no table headed {header}"));
    text[start..]
        .lines()
        .skip(2)
        .take_while(|l| l.trim().starts_with('|'))
        .collect()
}

#[test]
fn every_table_is_accounted_for() {
    let mut files = vec![PathBuf::from("README.md")];
    let mut docs: Vec<PathBuf> = ["docs", "docs/dev"]
        .iter()
        .flat_map(|dir| {
            std::fs::read_dir(root().join(dir))
                .unwrap_or_else(|e| panic!("{dir}/: {e}"))
                .map(move |e| Path::new(dir).join(e.expect("an entry").file_name()))
        })
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    let mut unlisted = Vec::new();
    for file in &files {
        let name = file.to_str().expect("a UTF-8 path");
        for header in table_headers(&read(name)) {
            if !TABLES.iter().any(|(f, h, _)| *f == name && *h == header) {
                unlisted.push(format!("{name}: {header}"));
            }
        }
    }
    assert!(
        unlisted.is_empty(),
        "tables not listed in tests/docs.rs (say how each is generated and checked, or point to \
         the generated file in results/ instead):\n{}",
        unlisted.join("\n")
    );
    // And every listed table is still there.
    for (file, header, kept) in TABLES {
        let how = match kept {
            Kept::NoMeasurement => "no measured number",
            Kept::Checked(how) => how,
        };
        assert!(
            table_headers(&read(file)).iter().any(|h| h == header),
            "{file} no longer has the table {header} ({how}): update tests/docs.rs"
        );
    }
}

/// A fraction as the docs print a percentage: one decimal.
fn pct(x: f64) -> String {
    format!("{:.1} %", 100.0 * x)
}

fn number(v: &serde_json::Value, path: &str) -> f64 {
    v.pointer(path)
        .and_then(serde_json::Value::as_f64)
        .unwrap_or_else(|| panic!("closed_loop.json has no number at {path}"))
}

/// `docs/verify.md`'s closed-loop table is the four shipped closed-loop
/// designs' `closed_loop.json`: the open-loop candidate (the first, stage
/// `design`) before, the kept one (`best`) after.
#[test]
fn closed_loop_table_is_the_results() {
    let header = TABLES
        .iter()
        .find(|(f, _, _)| *f == "docs/verify.md")
        .expect("the verify.md table is listed")
        .1;
    let doc = read("docs/verify.md");
    let rows = table_rows(&doc, header);
    let want: Vec<String> = [1, 2, 3, 10]
        .iter()
        .map(|m| {
            let path = format!("results/closed_loop/min{m}/sink/closed_loop.json");
            let v: serde_json::Value =
                serde_json::from_str(&read(&path)).unwrap_or_else(|e| panic!("{path}: {e}"));
            let best = v["best"].as_u64().expect("best") as usize;
            let before = "/candidates/0/error";
            let after = format!("/candidates/{best}/error");
            assert_eq!(v["candidates"][0]["stage"], "design", "{path}");
            format!(
                "| {m} | {} → {} | {} → {} | {:.3} → {:.3} |",
                pct(number(&v, &format!("{before}/error"))),
                pct(number(&v, &format!("{after}/error"))),
                pct(number(&v, &format!("{before}/shape_error"))),
                pct(number(&v, &format!("{after}/shape_error"))),
                number(&v, "/design_strength"),
                number(&v, &format!("{after}/realised_strength")),
            )
        })
        .collect();
    assert_eq!(
        rows, want,
        "docs/verify.md's closed-loop table against results/closed_loop"
    );
}
