//! One-way architecture: the `use crate::…` graph between the top-level
//! modules of `src/` has no cycle.
//!
//! Every file of the library (`src/**/*.rs` but `main.rs`) belongs to the
//! top-level module named by its first path component (`src/play/measure.rs`
//! → `play`). Its code — comments, doc comments, string and character
//! literals and `#[cfg(test)]` items removed — is scanned for paths that
//! name another top-level module: `crate::x` anywhere (in `use`
//! declarations, grouped `use crate::{a, b::c}`, and paths in code), and
//! `super::x` where `super` reaches the crate root. An edge a → b means a
//! uses b. The test fails on a cycle and prints it.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// Module graph: module → the modules it uses.
type Graph = BTreeMap<String, BTreeSet<String>>;

/// `text` with comments and the contents of string and char literals
/// removed (replaced by a space), so that only code remains.
fn strip_comments_and_literals(text: &str) -> String {
    let c: Vec<char> = text.chars().collect();
    let mut out = String::with_capacity(text.len());
    let mut i = 0;
    while i < c.len() {
        let next = c.get(i + 1).copied();
        if c[i] == '/' && next == Some('/') {
            while i < c.len() && c[i] != '\n' {
                i += 1;
            }
        } else if c[i] == '/' && next == Some('*') {
            let mut depth = 0;
            while i < c.len() {
                if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                    depth += 1;
                    i += 2;
                } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                    depth -= 1;
                    i += 2;
                    if depth == 0 {
                        break;
                    }
                } else {
                    i += 1;
                }
            }
            out.push(' ');
        } else if c[i] == 'r' && (next == Some('"') || next == Some('#')) && is_raw_start(&c, i) {
            // Raw string r"…" or r#"…"#.
            let mut j = i + 1;
            let mut hashes = 0;
            while c[j] == '#' {
                hashes += 1;
                j += 1;
            }
            j += 1;
            loop {
                if j >= c.len() {
                    break;
                }
                if c[j] == '"' && (0..hashes).all(|h| c.get(j + 1 + h) == Some(&'#')) {
                    j += 1 + hashes;
                    break;
                }
                j += 1;
            }
            out.push_str("\"\"");
            i = j;
        } else if c[i] == '"' {
            i += 1;
            while i < c.len() && c[i] != '"' {
                if c[i] == '\\' {
                    i += 1;
                }
                i += 1;
            }
            i += 1;
            out.push_str("\"\"");
        } else if c[i] == '\'' {
            // A char literal ('a', '\n', '\u{..}') or a lifetime ('a).
            if next == Some('\\') {
                let mut j = i + 2;
                while j < c.len() && c[j] != '\'' {
                    j += 1;
                }
                i = j + 1;
                out.push_str("' '");
            } else if c.get(i + 2) == Some(&'\'') {
                i += 3;
                out.push_str("' '");
            } else {
                out.push('\'');
                i += 1;
            }
        } else {
            out.push(c[i]);
            i += 1;
        }
    }
    out
}

/// True when the `r` at `i` starts a raw string (not the end of an identifier).
fn is_raw_start(c: &[char], i: usize) -> bool {
    let ident_before = i > 0 && (c[i - 1].is_alphanumeric() || c[i - 1] == '_');
    if ident_before {
        return false;
    }
    let mut j = i + 1;
    while j < c.len() && c[j] == '#' {
        j += 1;
    }
    c.get(j) == Some(&'"')
}

/// `code` (already stripped) without the items that follow `#[cfg(test)]`
/// (a `mod … { … }` block, or any item up to its closing brace or `;`).
fn strip_cfg_test(code: &str) -> String {
    let mut out = String::with_capacity(code.len());
    let mut rest = code;
    while let Some(k) = rest.find("#[cfg(test)]") {
        out.push_str(&rest[..k]);
        let after = &rest[k + "#[cfg(test)]".len()..];
        // Skip to the end of the next item: a balanced {…} block or a `;`.
        let mut depth = 0usize;
        let mut end = after.len();
        for (j, ch) in after.char_indices() {
            match ch {
                '{' => depth += 1,
                '}' => {
                    depth -= 1;
                    if depth == 0 {
                        end = j + 1;
                        break;
                    }
                }
                ';' if depth == 0 => {
                    end = j + 1;
                    break;
                }
                _ => {}
            }
        }
        rest = &after[end..];
    }
    out.push_str(rest);
    out
}

/// The identifier at the start of `s` (after whitespace).
fn ident(s: &str) -> Option<&str> {
    let s = s.trim_start();
    let end = s
        .find(|ch: char| !(ch.is_alphanumeric() || ch == '_'))
        .unwrap_or(s.len());
    (end > 0).then(|| &s[..end])
}

/// The first identifiers of the comma-separated items of a `{…}` group at
/// the start of `s` (nested groups are items of their own path, so only
/// depth-1 items count).
fn group_heads(s: &str) -> Vec<String> {
    let mut heads = Vec::new();
    let mut depth = 0usize;
    let mut item_start = true;
    for (j, ch) in s.char_indices() {
        match ch {
            '{' => {
                depth += 1;
                if depth == 1 {
                    item_start = true;
                    continue;
                }
            }
            '}' => {
                depth -= 1;
                if depth == 0 {
                    break;
                }
            }
            ',' if depth == 1 => {
                item_start = true;
                continue;
            }
            _ => {}
        }
        if depth == 1 && item_start && !ch.is_whitespace() {
            if let Some(id) = ident(&s[j..]) {
                heads.push(id.to_string());
            }
            item_start = false;
        }
    }
    heads
}

/// Top-level modules named by `crate::` and root-reaching `super::` paths in
/// `code`, for a file whose module path has `depth` components.
fn used_modules(code: &str, depth: usize) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut add = |after: &str| {
        let after = after.trim_start();
        if after.starts_with('{') {
            out.extend(group_heads(after));
        } else if let Some(id) = ident(after) {
            out.insert(id.to_string());
        }
    };
    for (k, _) in code.match_indices("crate::") {
        let before = code[..k].chars().next_back();
        if before.is_some_and(|ch| ch.is_alphanumeric() || ch == '_' || ch == '$') {
            continue;
        }
        add(&code[k + "crate::".len()..]);
    }
    for (k, _) in code.match_indices("super::") {
        let before = code[..k].chars().next_back();
        if before.is_some_and(|ch| ch.is_alphanumeric() || ch == '_' || ch == ':') {
            continue;
        }
        let mut rest = &code[k..];
        let mut ups = 0;
        while let Some(r) = rest.strip_prefix("super::") {
            ups += 1;
            rest = r.trim_start();
        }
        if ups >= depth {
            add(rest);
        }
    }
    out.remove("self");
    out.remove("super");
    out
}

/// The module path of a file relative to `src/` (`play/measure.rs` →
/// [play, measure], `play/mod.rs` → [play]).
fn module_path(rel: &Path) -> Vec<String> {
    let mut parts: Vec<String> = rel
        .iter()
        .map(|p| p.to_string_lossy().trim_end_matches(".rs").to_string())
        .collect();
    if parts.last().is_some_and(|p| p == "mod") {
        parts.pop();
    }
    parts
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .expect("read src")
        .map(|e| e.expect("entry").path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The graph of the library under `src`.
fn crate_graph(src: &Path) -> Graph {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut graph = Graph::new();
    for f in files {
        let rel = f.strip_prefix(src).expect("under src");
        let path = module_path(rel);
        let top = match path.first().map(String::as_str) {
            None | Some("lib") | Some("main") => continue,
            Some(t) => t.to_string(),
        };
        let text = std::fs::read_to_string(&f).expect("read file");
        let code = strip_cfg_test(&strip_comments_and_literals(&text));
        let used = used_modules(&code, path.len());
        let entry = graph.entry(top.clone()).or_default();
        entry.extend(used.into_iter().filter(|m| *m != top));
    }
    graph
}

/// A cycle of `graph` (its modules in order, the first repeated at the
/// end), or `None`.
fn find_cycle(graph: &Graph) -> Option<Vec<String>> {
    #[derive(Clone, Copy, PartialEq)]
    enum Mark {
        New,
        Open,
        Done,
    }
    fn visit(
        g: &Graph,
        m: &str,
        marks: &mut BTreeMap<String, Mark>,
        stack: &mut Vec<String>,
    ) -> Option<Vec<String>> {
        marks.insert(m.to_string(), Mark::Open);
        stack.push(m.to_string());
        for next in g.get(m).into_iter().flatten() {
            match marks.get(next).copied().unwrap_or(Mark::New) {
                Mark::Open => {
                    let at = stack.iter().position(|s| s == next).expect("on stack");
                    let mut cycle = stack[at..].to_vec();
                    cycle.push(next.clone());
                    return Some(cycle);
                }
                Mark::New => {
                    if let Some(c) = visit(g, next, marks, stack) {
                        return Some(c);
                    }
                }
                Mark::Done => {}
            }
        }
        stack.pop();
        marks.insert(m.to_string(), Mark::Done);
        None
    }
    let mut marks = BTreeMap::new();
    for m in graph.keys() {
        if marks.get(m).copied().unwrap_or(Mark::New) == Mark::New {
            if let Some(c) = visit(graph, m, &mut marks, &mut Vec::new()) {
                return Some(c);
            }
        }
    }
    None
}

#[test]
fn top_level_modules_have_no_import_cycle() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = crate_graph(&src);
    assert!(graph.len() >= 10, "too few modules found: {graph:?}");
    if let Some(cycle) = find_cycle(&graph) {
        let edges: Vec<String> = graph
            .iter()
            .map(|(m, used)| {
                format!(
                    "  {m} → {}",
                    used.iter().cloned().collect::<Vec<_>>().join(", ")
                )
            })
            .collect();
        panic!(
            "import cycle between top-level modules: {}\ngraph:\n{}",
            cycle.join(" → "),
            edges.join("\n")
        );
    }
}

/// The layers named in the brief import only downwards.
#[test]
fn layers_import_downwards() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graph = crate_graph(&src);
    for (from, not) in [
        (
            "schedule",
            ["play", "design", "verify", "report"].as_slice(),
        ),
        ("play", &["design", "verify", "report"]),
        ("design", &["verify", "report"]),
        ("verify", &["design", "report"]),
    ] {
        let used = graph.get(from).cloned().unwrap_or_default();
        for m in not {
            assert!(!used.contains(*m), "{from} imports {m}: {used:?}");
        }
    }
}

fn graph_of(edges: &[(&str, &str)]) -> Graph {
    let mut g = Graph::new();
    for (a, b) in edges {
        g.entry(a.to_string()).or_default().insert(b.to_string());
        g.entry(b.to_string()).or_default();
    }
    g
}

/// The detector finds a planted cycle and prints it in order; a DAG
/// (with a diamond) has none.
#[test]
fn detector_finds_a_planted_cycle() {
    let dag = graph_of(&[("a", "b"), ("a", "c"), ("b", "d"), ("c", "d")]);
    assert_eq!(find_cycle(&dag), None);
    let cyclic = graph_of(&[("a", "b"), ("b", "c"), ("c", "d"), ("d", "b"), ("a", "e")]);
    assert_eq!(
        find_cycle(&cyclic),
        Some(vec!["b".into(), "c".into(), "d".into(), "b".into()])
    );
    assert!(find_cycle(&graph_of(&[("x", "x")])).is_some());
}

/// The scanner: grouped uses, paths in code, `super::` to the root; not
/// comments, doc comments, strings or `#[cfg(test)]` modules.
#[test]
fn scanner_reads_uses_and_skips_comments_strings_and_tests() {
    let text = r##"
//! Doc: crate::docmod is only mentioned.
use crate::{alpha, beta::Thing, gamma::{self, X}};
use super::delta::Y;
use super::super::eta;
/* block crate::blockmod */
fn f() -> crate::epsilon::T {
    let s = "crate::stringmod";
    let r = r#"crate::rawmod"#;
    let c = '"';
    let zeta = crate::zeta::make();
    my_crate::nope();
}
#[cfg(test)]
mod tests {
    use crate::testmod;
}
"##;
    let code = strip_cfg_test(&strip_comments_and_literals(text));
    // A file at depth 1 (src/m.rs): super:: reaches the root.
    let used = used_modules(&code, 1);
    let expect: BTreeSet<String> = ["alpha", "beta", "gamma", "delta", "epsilon", "zeta", "eta"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(used, expect);
    // At depth 2 (src/m/n.rs) one super stays inside m; two reach the root.
    let used = used_modules(&code, 2);
    assert!(!used.contains("delta") && used.contains("eta"), "{used:?}");
    // A planted cycle in real-looking sources is found by the whole path.
    let dir = std::env::temp_dir().join(format!("platefield-arch-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(dir.join("low")).unwrap();
    std::fs::write(dir.join("lib.rs"), "pub mod low; pub mod high;").unwrap();
    std::fs::write(dir.join("low/mod.rs"), "use crate::{high::H, other};").unwrap();
    std::fs::write(dir.join("high.rs"), "fn f() { super::low::L; }").unwrap();
    let g = crate_graph(&dir);
    let _ = std::fs::remove_dir_all(&dir);
    let cycle = find_cycle(&g).expect("planted cycle");
    assert_eq!(cycle.first(), cycle.last());
    assert!(cycle.contains(&"low".to_string()) && cycle.contains(&"high".to_string()));
}
