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
    for (ups, rest) in super_paths(code) {
        if ups >= depth {
            add(rest);
        }
    }
    out.remove("self");
    out.remove("super");
    out
}

/// Every `super::super::…` path in `code`: how many levels it goes up,
/// and the code after the last `super::`.
fn super_paths(code: &str) -> Vec<(usize, &str)> {
    let mut out = Vec::new();
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
        out.push((ups, rest));
    }
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
            None | Some("lib") => continue,
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
        ("design", &["verify", "report", "pose", "inverse"]),
        ("pose", &["inverse"]),
        ("verify", &["report"]),
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

/// The comma-separated items of the `{…}` group at the start of `s`.
fn group_items(s: &str) -> Vec<&str> {
    let mut items = Vec::new();
    let mut depth = 0usize;
    let mut start = 0;
    for (j, ch) in s.char_indices() {
        match ch {
            '{' => {
                depth += 1;
                if depth == 1 {
                    start = j + 1;
                }
            }
            '}' => {
                depth -= 1;
                if depth == 0 {
                    items.push(&s[start..j]);
                    break;
                }
            }
            ',' if depth == 1 => {
                items.push(&s[start..j]);
                start = j + 1;
            }
            _ => {}
        }
    }
    items
}

/// The first `need` components of each path that `s` starts with (a path
/// `a::b::c`, or a group `{a::b, c::{d, e}}` of them); shorter where a
/// path ends sooner.
fn path_heads(s: &str, need: usize) -> Vec<Vec<String>> {
    let s = s.trim_start();
    if need == 0 {
        return vec![Vec::new()];
    }
    if s.starts_with('{') {
        return group_items(s)
            .into_iter()
            .flat_map(|item| path_heads(item, need))
            .collect();
    }
    let Some(id) = ident(s) else {
        return Vec::new();
    };
    let rest = s[id.len()..].trim_start();
    match rest.strip_prefix("::") {
        Some(more) if need > 1 => path_heads(more, need - 1)
            .into_iter()
            .map(|mut h| {
                h.insert(0, id.to_string());
                h
            })
            .collect(),
        _ => vec![vec![id.to_string()]],
    }
}

/// The files of its own top-level module that a file at module path
/// `path` (at least two components: `dynamics::radau`) uses: the second
/// component of every `crate::` path into its module and every `super::`
/// path that reaches the module's root, where that names another file.
fn used_files(code: &str, path: &[String]) -> BTreeSet<String> {
    let (top, own) = (&path[0], &path[1]);
    let mut out = BTreeSet::new();
    let mut add = |base: &[String], after: &str| {
        for h in path_heads(after, 2 - base.len()) {
            let full: Vec<&String> = base.iter().chain(h.iter()).collect();
            if full.len() == 2 && full[0] == top && full[1] != own {
                out.insert(full[1].clone());
            }
        }
    };
    for (k, _) in code.match_indices("crate::") {
        let before = code[..k].chars().next_back();
        if !before.is_some_and(|ch| ch.is_alphanumeric() || ch == '_' || ch == '$') {
            add(&[], &code[k + "crate::".len()..]);
        }
    }
    for (ups, rest) in super_paths(code) {
        // `super` reaches the module's root (or the crate's) from here.
        if let Some(keep) = path.len().checked_sub(ups).filter(|k| *k <= 1) {
            add(&path[..keep], rest);
        }
    }
    out
}

/// Per top-level module, the graph between its files: a file
/// `src/m/f.rs` (with the files under `src/m/f/`) is the node `f`; the
/// module's root `src/m/mod.rs` is no node (it declares and re-exports the
/// files, and its own items are shared by all of them), nor are test-only
/// files (`*_tests.rs`, `tests.rs`). Method calls between `impl` blocks in
/// different files are not seen: only paths.
fn file_graphs(src: &Path) -> BTreeMap<String, Graph> {
    let mut files = Vec::new();
    rust_files(src, &mut files);
    let mut graphs: BTreeMap<String, Graph> = BTreeMap::new();
    for f in files {
        let path = module_path(f.strip_prefix(src).expect("under src"));
        if path.len() < 2 || path[1] == "tests" || path[1].ends_with("_tests") {
            continue;
        }
        let text = std::fs::read_to_string(&f).expect("read file");
        let code = strip_cfg_test(&strip_comments_and_literals(&text));
        let graph = graphs.entry(path[0].clone()).or_default();
        let used = used_files(&code, &path);
        graph.entry(path[1].clone()).or_default().extend(used);
    }
    // Only edges to files that exist (not to the root's own items).
    for graph in graphs.values_mut() {
        let nodes: BTreeSet<String> = graph.keys().cloned().collect();
        for used in graph.values_mut() {
            used.retain(|u| nodes.contains(u));
        }
    }
    graphs
}

/// The strongly connected components of `graph` with more than one node
/// (its import circles), each sorted.
fn circles(graph: &Graph) -> Vec<Vec<String>> {
    // Two nodes are in one component when each reaches the other.
    let reach = |from: &str| -> BTreeSet<String> {
        let mut seen = BTreeSet::new();
        let mut todo = vec![from.to_string()];
        while let Some(m) = todo.pop() {
            for next in graph.get(&m).into_iter().flatten() {
                if seen.insert(next.clone()) {
                    todo.push(next.clone());
                }
            }
        }
        seen
    };
    let reaches: BTreeMap<&String, BTreeSet<String>> =
        graph.keys().map(|m| (m, reach(m))).collect();
    let mut out: Vec<Vec<String>> = Vec::new();
    for (m, r) in &reaches {
        let comp: Vec<String> = r
            .iter()
            .filter(|n| reaches.get(n).is_some_and(|back| back.contains(*m)))
            .cloned()
            .collect();
        if comp.len() > 1 && !out.contains(&comp) {
            out.push(comp);
        }
    }
    out
}

/// The import circles between files that remain, each `module: files`
/// (sorted): none. A circle that appears fails the test; one that must
/// stay for a while is listed here with its reason.
const REMAINING_CIRCLES: &[&str] = &[];

/// No import circle between the files of any top-level module but those
/// listed in [`REMAINING_CIRCLES`].
#[test]
fn files_of_a_module_import_one_way() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let graphs = file_graphs(&src);
    assert!(
        graphs.get("dynamics").is_some_and(|g| g.len() >= 7),
        "too few files found in dynamics: {:?}",
        graphs.get("dynamics")
    );
    let found: Vec<String> = graphs
        .iter()
        .flat_map(|(m, g)| {
            circles(g)
                .into_iter()
                .map(move |c| format!("{m}: {}", c.join(", ")))
        })
        .collect();
    let allowed: Vec<String> = REMAINING_CIRCLES.iter().map(|s| s.to_string()).collect();
    assert_eq!(
        found, allowed,
        "import circles between files (found, allowed)"
    );
}

/// The file-level scanner: `super::` and `crate::m::` paths (grouped,
/// nested) name sibling files; paths to the root's items, to other
/// modules and inside the file's own subtree do not; a planted circle is
/// found, a chain is not.
#[test]
fn file_scanner_finds_siblings_and_circles() {
    let code = strip_comments_and_literals(
        "use super::{a::X, b, c::{self, Y}};\nuse super::Root;\nuse crate::m::d::Z;\n\
         use crate::other::e::W;\nfn f() { super::super::m::g::h(); self::own::k(); }",
    );
    let path = ["m".to_string(), "f".to_string()];
    let expect: BTreeSet<String> = ["a", "b", "c", "d", "g", "Root"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    assert_eq!(used_files(&code, &path), expect);
    // From a file below `f` (src/m/f/sub.rs) one `super` stays inside f.
    let deep = ["m".to_string(), "f".to_string(), "sub".to_string()];
    assert_eq!(
        used_files(
            &strip_comments_and_literals("use super::x; use super::super::y;"),
            &deep
        ),
        ["y".to_string()].into_iter().collect()
    );
    let chain = graph_of(&[("a", "b"), ("b", "c"), ("a", "c")]);
    assert!(circles(&chain).is_empty());
    let circle = graph_of(&[("a", "b"), ("b", "c"), ("c", "a"), ("c", "d")]);
    assert_eq!(
        circles(&circle),
        vec![vec!["a".to_string(), "b".into(), "c".into()]]
    );
}

/// The simulator takes its arguments grouped (the step-state
/// `dynamics::state::Step`, one type per slip scheme): no function in
/// `src/dynamics` needs clippy's leave for many arguments.
#[test]
fn dynamics_has_no_long_argument_lists() {
    let mut files = Vec::new();
    rust_files(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("src/dynamics"),
        &mut files,
    );
    assert!(files.len() >= 8, "{files:?}");
    for f in files {
        let text = std::fs::read_to_string(&f).expect("read file");
        assert!(
            !text.contains("clippy::too_many_arguments"),
            "{} allows clippy::too_many_arguments",
            f.display()
        );
    }
}

/// The library names no clap type: clap is the command's (its argument
/// structs and value parsers are in the `platefield-cli` crate), so
/// `lib.rs` exports none.
#[test]
fn only_the_binary_names_clap() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut library = 0;
    for f in files {
        let rel = f.strip_prefix(&src).expect("under src");
        library += 1;
        let code = strip_comments_and_literals(&std::fs::read_to_string(&f).expect("read file"));
        let names = code.match_indices("clap").any(|(k, _)| {
            let before = code[..k].chars().next_back();
            let after = code[k + 4..].chars().next();
            let word = |c: Option<char>| c.is_some_and(|c| c.is_alphanumeric() || c == '_');
            !word(before) && !word(after)
        });
        assert!(!names, "{} names clap", rel.display());
    }
    assert!(library > 100, "too few library files: {library}");
    // The check sees a use of clap.
    let planted = strip_comments_and_literals("use clap::Args; // clap\nlet s = \"clap\";");
    assert_eq!(planted.matches("clap").count(), 1);
}

/// `line` with string literals emptied, a `//` comment cut and one-
/// character char literals removed (so their braces do not count), as
/// /work/tools/fnlen.py reads a line.
fn fn_line_code(line: &str) -> String {
    let c: Vec<char> = line.chars().collect();
    let mut out = String::new();
    let mut i = 0;
    while i < c.len() {
        if c[i] == '"' {
            // A closed literal on this line becomes "", an open one stays.
            let mut j = i + 1;
            while j < c.len() && c[j] != '"' {
                j += if c[j] == '\\' { 2 } else { 1 };
            }
            if j < c.len() {
                out.push_str("\"\"");
                i = j + 1;
                continue;
            }
        }
        out.push(c[i]);
        i += 1;
    }
    if let Some(k) = out.find("//") {
        out.truncate(k);
    }
    let c: Vec<char> = out.chars().collect();
    let mut code = String::new();
    let mut i = 0;
    while i < c.len() {
        if c[i] == '\'' && i + 2 < c.len() && c[i + 2] == '\'' {
            i += 3;
        } else {
            code.push(c[i]);
            i += 1;
        }
    }
    code
}

/// The function a line opens, if any: `[pub[(…)]] [const] [async]
/// [unsafe] fn name`, indented or not.
fn fn_name(line: &str) -> Option<&str> {
    let mut rest = line.trim_start();
    if let Some(r) = rest.strip_prefix("pub") {
        let r = match r.strip_prefix('(') {
            Some(inner) => &inner[inner.find(')')? + 1..],
            None => r,
        };
        if r.starts_with(char::is_whitespace) {
            rest = r.trim_start();
        }
    }
    for word in ["const", "async", "unsafe"] {
        if let Some(r) = rest.strip_prefix(word) {
            if r.starts_with(char::is_whitespace) {
                rest = r.trim_start();
            }
        }
    }
    let r = rest.strip_prefix("fn")?;
    if !r.starts_with(char::is_whitespace) {
        return None;
    }
    let r = r.trim_start();
    let end = r
        .find(|c: char| !(c.is_alphanumeric() || c == '_'))
        .unwrap_or(r.len());
    (end > 0).then(|| &r[..end])
}

/// Every function of `text` with a body, as (lines, name, first line),
/// up to its `#[cfg(test)] mod` (tests aside): from the line that opens it
/// to the line whose brace closes its body, braces matched line by line.
fn function_lengths(text: &str) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.split('\n').collect();
    let end = (0..lines.len())
        .find(|&i| {
            lines[i].trim() == "#[cfg(test)]"
                && lines
                    .get(i + 1)
                    .is_some_and(|l| l.trim_start().starts_with("mod "))
        })
        .unwrap_or(lines.len());
    let mut out = Vec::new();
    for i in 0..end {
        let Some(name) = fn_name(lines[i]) else {
            continue;
        };
        let (mut depth, mut started, mut j) = (0i64, false, i);
        while j < end {
            let code = fn_line_code(lines[j]);
            if code.contains(';') && !started && !code.contains('{') {
                break;
            }
            for ch in code.chars() {
                match ch {
                    '{' => {
                        depth += 1;
                        started = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if started && depth <= 0 {
                break;
            }
            j += 1;
        }
        if started {
            out.push((j - i + 1, name.to_string(), i + 1));
        }
    }
    out
}

/// Functions of at least this many lines are long.
const LONG_FUNCTION_LINES: usize = 80;
/// At most this share of the functions in `src/` may be long (the crates
/// platefield is built on: clarabel 0.9 %, argmin 2.2 %, serde_json 0.2 %).
const LONG_FUNCTION_SHARE: f64 = 0.015;

/// Functions of ≥ [`LONG_FUNCTION_LINES`] lines are at most
/// [`LONG_FUNCTION_SHARE`] of the functions in `src/` (tests aside);
/// the count matches /work/tools/fnlen.py's.
#[test]
fn long_functions_are_few() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut all = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).expect("read file");
        for (n, name, line) in function_lengths(&text) {
            all.push((n, format!("{}:{line} {name}", f.display())));
        }
    }
    let long: Vec<&(usize, String)> = all
        .iter()
        .filter(|(n, _)| *n >= LONG_FUNCTION_LINES)
        .collect();
    assert!(all.len() > 1000, "too few functions found: {}", all.len());
    let share = long.len() as f64 / all.len() as f64;
    println!(
        "{} of {} functions >= {LONG_FUNCTION_LINES} lines ({:.2} %)",
        long.len(),
        all.len(),
        100.0 * share
    );
    assert!(
        share <= LONG_FUNCTION_SHARE,
        "{} of {} functions are >= {LONG_FUNCTION_LINES} lines: {long:?}",
        long.len(),
        all.len()
    );
}

/// The counter on planted code: a body's braces matched (those in strings,
/// comments and char literals not counted), declarations without a body
/// and the test module skipped, signatures over several lines counted.
#[test]
fn function_counter_matches_braces() {
    let code = "fn a() {\n    let s = \"}}\"; // }\n    let c = '{';\n}\n\
                pub(crate) fn b(\n    x: u8,\n) -> u8 {\n    if x > 0 { x } else { 0 }\n}\n\
                trait T {\n    fn c(&self);\n}\n\
                pub const unsafe fn d() {}\n\
                #[cfg(test)]\nmod tests {\n    fn e() {\n    }\n}\n";
    let got = function_lengths(code);
    let want = vec![
        (4, "a".to_string(), 1),
        (5, "b".to_string(), 5),
        (1, "d".to_string(), 13),
    ];
    assert_eq!(got, want);
    assert_eq!(fn_name("    pub(in crate::x) async fn go<T>()"), Some("go"));
    assert_eq!(fn_name("let fnord = 1;"), None);
}

/// The names of the dependencies (normal, dev and build) a manifest
/// declares: every `name = …` or `name.workspace = …` line inside a
/// `[*dependencies]` table (not `[workspace.dependencies]`, which only
/// names versions for the members).
fn manifest_dependencies(manifest: &str) -> BTreeSet<String> {
    let mut names = BTreeSet::new();
    let mut in_dependencies = false;
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            let table = line.trim_matches(['[', ']']);
            in_dependencies = table.ends_with("dependencies") && !table.starts_with("workspace");
        } else if in_dependencies && !line.starts_with('#') {
            if let Some((key, _)) = line.split_once('=') {
                let name = key.trim().trim_end_matches(".workspace");
                names.insert(name.to_string());
            }
        }
    }
    names
}

/// The workspace's crates are layered: the library depends on none of the
/// others; the report writers on the library only; the studies on the
/// library and the report writers; the command on all three. So the
/// library never depends on the command or the laboratory.
#[test]
fn crates_are_layered() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let ours = [
        "platefield",
        "platefield-report",
        "platefield-studies",
        "platefield-cli",
    ];
    for (manifest, allowed) in [
        ("Cargo.toml", &[][..]),
        ("report/Cargo.toml", &["platefield"][..]),
        (
            "studies/Cargo.toml",
            &["platefield", "platefield-report"][..],
        ),
        (
            "cli/Cargo.toml",
            &["platefield", "platefield-report", "platefield-studies"][..],
        ),
    ] {
        let text = std::fs::read_to_string(root.join(manifest)).expect("read manifest");
        let deps = manifest_dependencies(&text);
        let ours_used: Vec<&String> = deps.iter().filter(|d| ours.contains(&d.as_str())).collect();
        for d in &ours_used {
            assert!(allowed.contains(&d.as_str()), "{manifest} depends on {d}");
        }
        assert_eq!(ours_used.len(), allowed.len(), "{manifest}: {ours_used:?}");
    }
    // The reader sees a workspace dependency and skips other tables.
    let planted = "[workspace.dependencies]\ny = \"1\"\n[package]\nname = \"x\"\n[dependencies]\nplatefield.workspace = true\n[dev-dependencies]\napprox = \"0.5\"\n";
    let names: Vec<String> = manifest_dependencies(planted).into_iter().collect();
    assert_eq!(names, ["approx", "platefield"]);
}

/// Numbered work-log references in `text`: an issue, session or round
/// named by its number ("issue 27", "Issue #13", "session 7", "round 2")
/// or a round by its ordinal ("the 7th round"), as (line, reference).
/// Words are runs of letters and digits, compared case-insensitively; the
/// two words of a reference may be separated only by spaces, `#` or the
/// markers of a comment continued on the next line (`//`, `//!`, `///`).
fn work_log_references(text: &str) -> Vec<(usize, String)> {
    // (line, start, end, lower-case word)
    let mut words: Vec<(usize, usize, usize, String)> = Vec::new();
    let mut line = 1;
    let mut start = None;
    for (k, c) in text
        .char_indices()
        .chain(std::iter::once((text.len(), ' ')))
    {
        if c.is_alphanumeric() {
            start.get_or_insert(k);
        } else if let Some(s) = start.take() {
            words.push((line, s, k, text[s..k].to_lowercase()));
        }
        if c == '\n' {
            line += 1;
        }
    }
    let is_number = |w: &str| !w.is_empty() && w.chars().all(|c| c.is_ascii_digit());
    let is_ordinal = |w: &str| {
        ["st", "nd", "rd", "th"]
            .iter()
            .any(|s| w.strip_suffix(s).is_some_and(is_number))
    };
    let named = ["issue", "issues", "session", "sessions", "round", "rounds"];
    let mut found = Vec::new();
    for pair in words.windows(2) {
        let ((l, _, end, first), (_, t, _, second)) = (&pair[0], &pair[1]);
        let gap = &text[*end..*t];
        if !gap
            .chars()
            .all(|c| c.is_whitespace() || c == '#' || c == '/' || c == '!')
        {
            continue;
        }
        let numbered = named.contains(&first.as_str()) && is_number(second);
        let ordinal = is_ordinal(first) && (second == "round" || second == "rounds");
        if numbered || ordinal {
            found.push((*l, format!("{first} {second}")));
        }
    }
    found
}

/// Comments and code say what the code does and why, not in which piece of
/// work it was written: no file of the library, the report writers or the
/// command (comments, doc comments and literals included) names an issue,
/// a session or a round by its number.
#[test]
fn no_work_log_references() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "report/src", "cli/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 150, "too few files: {}", files.len());
    let mut hits = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).expect("read file");
        for (line, reference) in work_log_references(&text) {
            let rel = f.strip_prefix(root).expect("under the workspace");
            hits.push(format!("{}:{line}: {reference}", rel.display()));
        }
    }
    assert!(hits.is_empty(), "work-log references:\n{}", hits.join("\n"));
    // The check sees every form, across a comment's line break too …
    let planted = "//! As in Issue #13 and issues 27,\n/// the session\n/// 7 and the\n\
                   // 2nd round (round 3) found.\nlet s = \"issue 30\";";
    let found: Vec<(usize, String)> = work_log_references(planted);
    let expected = [
        (1, "issue 13"),
        (1, "issues 27"),
        (2, "session 7"),
        (4, "2nd round"),
        (4, "round 3"),
        (5, "issue 30"),
    ];
    assert_eq!(
        found,
        expected.map(|(l, r)| (l, r.to_string())).to_vec(),
        "planted references"
    );
    // … and leaves numbers and words that only stand near each other alone.
    let clean = "// The issue. 5 points round the 3rd axis; tissue 4; 12 rounds of sessions;\n\
                 // rounding 2 places; the 1st and 2nd rounding; \"#2ca02c\"";
    assert_eq!(work_log_references(clean), Vec::new());
}

/// The printing macros and stream handles a file's code (comments,
/// literals and `#[cfg(test)]` items removed) names, each with its count.
fn printing(code: &str) -> BTreeMap<&'static str, usize> {
    const TOKENS: [&str; 7] = [
        "eprintln!",
        "eprint!",
        "println!",
        "print!",
        "dbg!",
        "stderr()",
        "stdout()",
    ];
    let mut found = BTreeMap::new();
    for token in TOKENS {
        let n = code
            .match_indices(token)
            .filter(|(k, _)| {
                // `println!` holds `print!`'s letters only as a suffix of
                // a longer name: count a token where no identifier
                // character precedes it.
                !code[..*k]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || c == '_')
            })
            .count();
        if n > 0 {
            found.insert(token, n);
        }
    }
    found
}

/// The library speaks to a person only through its one observer
/// (`platefield::progress::say`): the default observer's `eprintln!` and
/// the terminal check of the progress bar (`stderr()`) are its only
/// stream writes; no other file of the library prints, so an embedding
/// program that installs an observer hears every line. Test-only files
/// (`*tests.rs`, `testutil.rs`, declared under `#[cfg(test)]`) may print.
#[test]
fn the_library_prints_only_through_its_observer() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    let mut printed = Vec::new();
    for f in &files {
        let name = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
        if name.ends_with("tests.rs") || name == "testutil.rs" || name == "main.rs" {
            continue;
        }
        let text = std::fs::read_to_string(f).expect("read file");
        let found = printing(&strip_cfg_test(&strip_comments_and_literals(&text)));
        let rel = f.strip_prefix(&src).unwrap_or(f).display().to_string();
        let allowed: BTreeMap<&str, usize> = if rel == "progress.rs" {
            [("eprintln!", 1), ("stderr()", 1)].into_iter().collect()
        } else {
            BTreeMap::new()
        };
        if found != allowed {
            printed.push(format!("{rel}: {found:?}"));
        }
    }
    assert!(
        printed.is_empty(),
        "printing outside the observer: {printed:#?}"
    );
    // The scanner counts a planted print and skips one in a test module.
    let planted = "fn f() { eprintln!(\"x\"); let p = std::io::stdout(); }\n\
                   #[cfg(test)]\nmod tests { fn g() { println!(\"y\"); } }\n";
    let found = printing(&strip_cfg_test(&strip_comments_and_literals(planted)));
    assert_eq!(
        found,
        [("eprintln!", 1), ("stdout()", 1)].into_iter().collect()
    );
}

/// Units a reported measurement carries, longest first where one is the
/// start of another (`s⁻¹` before `s`, `mm/s` before `mm`).
const MEASURE_UNITS: [&str; 19] = [
    "s⁻¹", "1/s", "m/s²", "mm/s", "cm/s", "m/s", "kHz", "Hz", "MB", "GB", "ms", "µs", "min", "mm",
    "cm", "%", "°", "s", "h",
];

/// The units of a time.
const TIME_UNITS: [&str; 5] = ["ms", "µs", "min", "s", "h"];

/// The unit of `MEASURE_UNITS` (or of `units`) that `rest` starts with,
/// after at most one space, ending where a word would (no letter or digit
/// right after it). A number glued to `×` ("3× faster") counts as a
/// factor; `5 × 5 points` (a product, spaced) does not.
fn unit_after<'a>(rest: &str, units: &[&'a str]) -> Option<&'a str> {
    if rest.starts_with('×') {
        return Some("×");
    }
    let rest = rest.strip_prefix(' ').unwrap_or(rest);
    units.iter().copied().find(|u| {
        rest.strip_prefix(u)
            .is_some_and(|after| !after.starts_with(|c: char| c.is_alphanumeric()))
    })
}

/// Every number with a unit in `text`: (byte offset of the number, unit).
/// A number is a run of digits (with `.` inside) that no letter or digit
/// precedes, so `2ω`, `x2`, `10s³` (a polynomial) and `R10` are not.
fn numbers_with_units<'a>(text: &str, units: &[&'a str]) -> Vec<(usize, &'a str)> {
    let mut found = Vec::new();
    let mut chars = text.char_indices().peekable();
    let mut prev: Option<char> = None;
    while let Some((k, c)) = chars.next() {
        let starts = c.is_ascii_digit()
            && !prev.is_some_and(|p| p.is_alphanumeric() || p == '.' || p == '_');
        prev = Some(c);
        if !starts {
            continue;
        }
        let mut end = k + c.len_utf8();
        while let Some(&(j, d)) = chars.peek() {
            let dot_inside = d == '.' && text[j + 1..].starts_with(|x: char| x.is_ascii_digit());
            if d.is_ascii_digit() || dot_inside {
                end = j + d.len_utf8();
                prev = Some(d);
                chars.next();
            } else {
                break;
            }
        }
        if let Some(unit) = unit_after(&text[end..], units) {
            found.push((k, unit));
        }
    }
    found
}

/// Comment lines that report a measurement, as (line, what was found).
///
/// The comments of a file are read block by block: consecutive lines
/// that are comments (`//`, `///`, `//!`), their markers removed and the
/// lines joined, so a sentence broken across lines reads whole. A block
/// reports a measurement where
/// - the word `measured` (not `unmeasured`, any case) is followed, in the
///   same clause (before the next `;` or sentence end, within 120
///   characters), by a number with a unit of [`MEASURE_UNITS`] or a
///   factor glued to `×` ("measured: 1.9 mm/s", "(measured 3× faster)");
/// - the word `took` is followed in the same clause by a time ("took
///   100 s");
/// - a time is followed by `CPU` or `wall` ("404 s CPU", "4.9 s of CPU").
///
/// A clause that names where its number lives — `results/` or `docs/` —
/// is a link, and allowed. Derivations and stated choices carry no such
/// word and pass: "O(τ³)", "asin(1/Γ)", "the curvature of G is −N",
/// "within 1e-5 relative", "measured over the window", "5 × 5 points".
/// Each hit names the line its trigger word is on.
fn measurement_reports(text: &str) -> Vec<(usize, String)> {
    // (first line, joined text, byte offset in the text where each line starts)
    let mut blocks: Vec<(usize, String, Vec<usize>)> = Vec::new();
    let mut open = false;
    for (i, line) in text.lines().enumerate() {
        let t = line.trim_start();
        if let Some(rest) = t.strip_prefix("//") {
            let rest = rest.trim_start_matches(['/', '!']).trim();
            if !open {
                blocks.push((i + 1, String::new(), Vec::new()));
                open = true;
            }
            let block = blocks.last_mut().expect("opened");
            if !block.1.is_empty() {
                block.1.push(' ');
            }
            block.2.push(block.1.len());
            block.1.push_str(rest);
        } else {
            open = false;
        }
    }
    let mut found = Vec::new();
    for (first, joined, starts) in &blocks {
        let lower = joined.to_lowercase();
        // Lower-casing keeps these ASCII words' offsets; the clause is
        // cut on the original text.
        let line_of = |k: usize| first + starts.partition_point(|&s| s <= k) - 1;
        let clause = |from: usize| {
            let rest = &joined[from..];
            let mut end = rest.len().min(120);
            while !rest.is_char_boundary(end) {
                end -= 1;
            }
            for (j, c) in rest[..end].char_indices() {
                let sentence_end = c == '.' && rest[j + 1..].starts_with(' ');
                if c == ';' || sentence_end {
                    end = j;
                    break;
                }
            }
            &rest[..end]
        };
        let linked = |s: &str| s.contains("results/") || s.contains("docs/");
        for (word, units) in [("measured", &MEASURE_UNITS[..]), ("took", &TIME_UNITS[..])] {
            for (k, _) in lower.match_indices(word) {
                let before = lower[..k].chars().next_back();
                let after = lower[k + word.len()..].chars().next();
                if before.is_some_and(|c| c.is_alphanumeric())
                    || after.is_some_and(|c| c.is_alphanumeric())
                {
                    continue;
                }
                let from = k + word.len();
                let c = clause(from);
                if linked(c) {
                    continue;
                }
                if let Some((_, unit)) = numbers_with_units(c, units).first() {
                    found.push((line_of(k), format!("{word} … {unit}: {}", c.trim())));
                }
            }
        }
        for (k, unit) in numbers_with_units(joined, &TIME_UNITS) {
            let rest = &lower[k..];
            let tail = rest
                .find(|c: char| !(c.is_ascii_digit() || c == '.'))
                .map_or("", |e| &rest[e..]);
            let tail = tail
                .trim_start()
                .strip_prefix(unit)
                .unwrap_or(tail)
                .trim_start();
            let tail = tail.strip_prefix("of ").unwrap_or(tail);
            let tail = tail.strip_prefix("user ").unwrap_or(tail);
            if (tail.starts_with("cpu") || tail.starts_with("wall")) && !linked(clause(k)) {
                found.push((line_of(k), format!("{unit} of CPU: {}", clause(k).trim())));
            }
        }
    }
    found.sort();
    found
}

/// Comments say what the code does and why; measured numbers live in one
/// generated place (a study's file in `results/`, or the page of `docs/`
/// that states them) and are linked, not restated: no comment of the
/// library, the report writers, the studies or the command (whose doc
/// comments are its `--help`) reports a measurement by
/// [`measurement_reports`]'s pattern without naming `results/` or
/// `docs/`.
#[test]
fn no_measurements_in_comments() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut files = Vec::new();
    for dir in ["src", "report/src", "studies/src", "cli/src"] {
        rust_files(&root.join(dir), &mut files);
    }
    assert!(files.len() > 150, "too few files: {}", files.len());
    let mut hits = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).expect("read file");
        for (line, what) in measurement_reports(&text) {
            let rel = f.strip_prefix(root).expect("under the workspace");
            hits.push(format!("{}:{line}: {what}", rel.display()));
        }
    }
    assert!(
        hits.is_empty(),
        "comments reporting measurements (link the results/ or docs/ file instead):\n{}",
        hits.join("\n")
    );
}

/// The pattern on planted comments: each form of a reported measurement
/// is found on the line of its trigger word, across a comment's line
/// break too; links, derivations, stated tolerances and the verb in its
/// other senses are not.
#[test]
fn measurement_pattern_finds_planted_reports() {
    let planted = "\
/// The sink gains swirl (measured: 4.7 % shape error at μ 0.3).
//! Only the outer column moves (measured
//! on sort_friction: 1.9–2.7 mm/s for μ 0.2), and
/// which measured 3× faster than the other form.
// A 100 000-vertex outline took 100 s to check.
/// The bracket's design (404 s CPU) and the library's 4.9 s of CPU.
let x = 1; // not a comment line of its own: measured 5 s
";
    let found: Vec<usize> = measurement_reports(planted)
        .into_iter()
        .map(|(line, _)| line)
        .collect();
    assert_eq!(
        found,
        [1, 2, 4, 5, 6, 6],
        "{:?}",
        measurement_reports(planted)
    );
    let clean = "\
/// The error is O(τ³); the curvature of G is −N, so δ = asin(1/Γ).
/// Measured over the window: the mean of 5 × 5 points, 20 measured cycles.
/// Within 1e-5 relative (a stated tolerance, 2 % of the bound, 30 ms cycle).
/// The parts are measured on `results/probes.md`: 3.2 % against 0.14 %.
/// (measured: `docs/dev/forward-model.md`, 0.41 s → 0.34 s).
/// The unmeasured part took the rest; a draw not measured counts as the worst.
/// Measured. Then 5 s later the part stops; it took. 3 s
/// w = 10s³ − 15s⁴ + 6s⁵, harmonic 2ω, in 2 steps of 10 cycles.
";
    assert_eq!(measurement_reports(clean), Vec::new());
}
