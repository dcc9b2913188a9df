//! The library's public API, listed in `docs/dev/api.md`.
//!
//! The list is read from the source with `syn`: from `src/lib.rs`, every
//! module declared `pub` whose parents are all `pub` is reachable, and in
//! each reachable module every item declared `pub` (not `pub(crate)`,
//! `pub(super)` or `pub(in …)`) is public: functions, structs, enums,
//! traits, constants, statics, type aliases and re-exports (`pub use`).
//! The `pub` functions and constants of an inherent `impl` are public
//! when its type is (the type found in the impl's module, else the one
//! public type of that name). A `pub` item of a module that is not
//! reachable is public when a reachable `pub use` re-exports it (matched
//! by its module's name and its own; a glob re-exports all of them): it
//! is listed, with its methods, under the module that re-exports it.
//! `#[cfg(test)]` and `#[doc(hidden)]` items are left out. The test fails when `docs/dev/api.md` differs from the
//! list; `PLATEFIELD_WRITE_API=1 cargo test --release --test api`
//! rewrites it.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write;
use std::path::{Path, PathBuf};
use syn::{Attribute, ImplItem, Item, Type, Visibility};

/// One public item: its kind (`fn`, `struct`, …) and name; a method's
/// name is `Type::name`.
type Entry = (String, String);

/// The public items by module path (`platefield::design::method`).
#[derive(Default)]
struct Api {
    items: BTreeMap<String, BTreeSet<Entry>>,
    /// Inherent impls seen anywhere: (module path, type name, its `pub`
    /// functions and constants, as (kind, name)).
    impls: Vec<(String, String, Vec<Entry>)>,
    /// Impls with public items whose type is neither in their module nor
    /// the one public type of its name: (module path, type name).
    unresolved: Vec<(String, String)>,
    /// `pub` items of modules that are not reachable: (module path, kind,
    /// name).
    hidden: Vec<(String, String, String)>,
    /// What reachable `pub use`s re-export: (re-exporting module path,
    /// the source module's path as written, resolved against the
    /// re-exporting module, the item's name or `*`).
    reexports: Vec<(String, String, String)>,
}

fn has_attr(attrs: &[Attribute], name: &str, arg: &str) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident(name)
            && a.meta
                .require_list()
                .is_ok_and(|l| l.tokens.to_string().split(',').any(|t| t.trim() == arg))
    })
}

/// Left out of the API: test-only or hidden.
fn skipped(attrs: &[Attribute]) -> bool {
    has_attr(attrs, "cfg", "test") || has_attr(attrs, "doc", "hidden")
}

fn public(vis: &Visibility) -> bool {
    matches!(vis, Visibility::Public(_))
}

/// The file of module `name` declared in `file` (Rust 2018 layout).
fn module_file(file: &Path, name: &str) -> PathBuf {
    let stem = file.file_stem().and_then(|s| s.to_str()).unwrap_or("");
    let dir = file.parent().unwrap_or(Path::new("."));
    let dir = if stem == "lib" || stem == "mod" {
        dir.to_path_buf()
    } else {
        dir.join(stem)
    };
    let flat = dir.join(format!("{name}.rs"));
    if flat.exists() {
        flat
    } else {
        dir.join(name).join("mod.rs")
    }
}

/// The last identifier of an impl's self type (`Foo<T>` → `Foo`).
fn type_name(ty: &Type) -> Option<String> {
    match ty {
        Type::Path(p) => p.path.segments.last().map(|s| s.ident.to_string()),
        _ => None,
    }
}

fn impl_entries(items: &[ImplItem]) -> Vec<Entry> {
    items
        .iter()
        .filter_map(|i| match i {
            ImplItem::Fn(f) if public(&f.vis) && !skipped(&f.attrs) => {
                Some(("fn".into(), f.sig.ident.to_string()))
            }
            ImplItem::Const(c) if public(&c.vis) && !skipped(&c.attrs) => {
                Some(("const".into(), c.ident.to_string()))
            }
            _ => None,
        })
        .collect()
}

impl Api {
    /// Reads the items of module `path` (reachable from outside when
    /// `reachable`) and of the modules it declares.
    fn read(&mut self, path: &str, items: &[Item], file: &Path, reachable: bool) {
        for item in items {
            self.item(path, item, file, reachable);
        }
    }

    fn add(&mut self, path: &str, kind: &str, name: String) {
        self.items
            .entry(path.to_string())
            .or_default()
            .insert((kind.to_string(), name));
    }

    fn item(&mut self, path: &str, item: &Item, file: &Path, reachable: bool) {
        let (attrs, vis, named): (&[Attribute], Option<&Visibility>, Option<(&str, String)>) =
            match item {
                Item::Fn(i) => (
                    &i.attrs,
                    Some(&i.vis),
                    Some(("fn", i.sig.ident.to_string())),
                ),
                Item::Struct(i) => (
                    &i.attrs,
                    Some(&i.vis),
                    Some(("struct", i.ident.to_string())),
                ),
                Item::Enum(i) => (&i.attrs, Some(&i.vis), Some(("enum", i.ident.to_string()))),
                Item::Trait(i) => (&i.attrs, Some(&i.vis), Some(("trait", i.ident.to_string()))),
                Item::Const(i) => (&i.attrs, Some(&i.vis), Some(("const", i.ident.to_string()))),
                Item::Static(i) => (
                    &i.attrs,
                    Some(&i.vis),
                    Some(("static", i.ident.to_string())),
                ),
                Item::Type(i) => (&i.attrs, Some(&i.vis), Some(("type", i.ident.to_string()))),
                Item::Use(i) => {
                    let text = quote_use(&i.tree);
                    (&i.attrs, Some(&i.vis), Some(("use", text)))
                }
                Item::Impl(i) => {
                    if i.trait_.is_none() && !skipped(&i.attrs) {
                        if let Some(t) = type_name(&i.self_ty) {
                            self.impls
                                .push((path.to_string(), t, impl_entries(&i.items)));
                        }
                    }
                    return;
                }
                Item::Mod(m) => {
                    if skipped(&m.attrs) {
                        return;
                    }
                    let child = format!("{path}::{}", m.ident);
                    let open = reachable && public(&m.vis);
                    if open {
                        self.items.entry(child.clone()).or_default();
                    }
                    match &m.content {
                        Some((_, inner)) => self.read(&child, inner, file, open),
                        None => {
                            let f = module_file(file, &m.ident.to_string());
                            let text = std::fs::read_to_string(&f)
                                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                            let parsed = syn::parse_file(&text)
                                .unwrap_or_else(|e| panic!("{}: {e}", f.display()));
                            self.read(&child, &parsed.items, &f, open);
                        }
                    }
                    return;
                }
                _ => (&[], None, None),
            };
        if let (Some(vis), Some((kind, name))) = (vis, named) {
            if public(vis) && !skipped(attrs) {
                if let (true, Item::Use(u)) = (reachable, item) {
                    let mut leaves = Vec::new();
                    use_leaves(&u.tree, &mut Vec::new(), &mut leaves);
                    for (from, leaf) in leaves {
                        self.reexports
                            .push((path.to_string(), resolve(path, &from), leaf));
                    }
                }
                if reachable {
                    self.add(path, kind, name);
                } else if kind != "use" {
                    self.hidden.push((path.to_string(), kind.to_string(), name));
                }
            }
        }
    }

    /// Lists the hidden items that a reachable `pub use` re-exports under
    /// the module that re-exports them.
    fn resolve_reexports(&mut self) {
        let hidden = std::mem::take(&mut self.hidden);
        let mut reexports = std::mem::take(&mut self.reexports);
        // The shortest path first: an item re-exported twice is listed once.
        reexports.sort_by_key(|(at, _, _)| (at.matches("::").count(), at.clone()));
        let mut listed = BTreeSet::new();
        for (at, from, leaf) in reexports {
            for (i, (path, kind, name)) in hidden.iter().enumerate() {
                if *path == from && (leaf == "*" || *name == leaf) && listed.insert(i) {
                    self.add(&at, kind, name.clone());
                }
            }
        }
    }

    /// Adds the inherent impls' public functions to their types.
    fn resolve_impls(&mut self) {
        let types: Vec<(String, String)> = self
            .items
            .iter()
            .flat_map(|(p, set)| {
                set.iter()
                    .filter(|(k, _)| k == "struct" || k == "enum")
                    .map(move |(_, n)| (p.clone(), n.clone()))
            })
            .collect();
        for (path, ty, entries) in std::mem::take(&mut self.impls) {
            let here = types.iter().find(|(p, n)| *p == path && *n == ty);
            let named: Vec<_> = types.iter().filter(|(_, n)| *n == ty).collect();
            let owner = here.or(if named.len() == 1 {
                Some(named[0])
            } else {
                None
            });
            match owner.cloned() {
                Some((p, n)) => {
                    for (kind, name) in entries {
                        self.add(&p, kind.as_str(), format!("{n}::{name}"));
                    }
                }
                None if named.len() > 1 && !entries.is_empty() => self.unresolved.push((path, ty)),
                None => {}
            }
        }
    }

    fn count(&self, kind: &str, method: Option<bool>) -> usize {
        self.items
            .values()
            .flatten()
            .filter(|(k, n)| k == kind && method.is_none_or(|m| n.contains("::") == m))
            .count()
    }

    /// `docs/dev/api.md`'s text.
    fn markdown(&self) -> String {
        let mut s = String::from(
            "# The library's public API\n\n\
             Generated by `PLATEFIELD_WRITE_API=1 cargo test --release --test api` and checked by \
             that test (`tests/api.rs` says what counts as public). A module is listed when it \
             and its parents are `pub`; under it, its `pub` items, and the `pub` functions and \
             constants of its types' inherent impls (`Type::name`).\n\n",
        );
        let funcs = self.count("fn", None);
        let _ = writeln!(
            s,
            "| kind | count |\n|---|---|\n| modules | {} |\n| `pub fn` | {funcs} ({} free, {} methods) |",
            self.items.len(),
            self.count("fn", Some(false)),
            self.count("fn", Some(true)),
        );
        for kind in ["struct", "enum", "trait", "const", "static", "type", "use"] {
            let label = if kind == "use" {
                "`pub use` (re-exports)".to_string()
            } else {
                format!("`pub {kind}`")
            };
            let _ = writeln!(s, "| {label} | {} |", self.count(kind, None));
        }
        for (path, set) in &self.items {
            let _ = write!(s, "\n## `{path}`\n\n");
            if set.is_empty() {
                s.push_str("(modules only)\n");
            }
            for (kind, name) in set {
                let _ = writeln!(s, "- {kind} `{name}`");
            }
        }
        s
    }
}

/// A `use` tree as text (`super::rule::{Rule, better_within}`).
fn quote_use(tree: &syn::UseTree) -> String {
    use syn::UseTree::*;
    match tree {
        Path(p) => format!("{}::{}", p.ident, quote_use(&p.tree)),
        Name(n) => n.ident.to_string(),
        Rename(r) => format!("{} as {}", r.ident, r.rename),
        Glob(_) => "*".into(),
        Group(g) => format!(
            "{{{}}}",
            g.items.iter().map(quote_use).collect::<Vec<_>>().join(", ")
        ),
    }
}

/// Every (module path as written, item name) a `use` tree names; `*` for
/// a glob, the original name for a rename.
fn use_leaves(tree: &syn::UseTree, prefix: &mut Vec<String>, out: &mut Vec<(Vec<String>, String)>) {
    use syn::UseTree::*;
    match tree {
        Path(p) => {
            prefix.push(p.ident.to_string());
            use_leaves(&p.tree, prefix, out);
            prefix.pop();
        }
        Name(n) => out.push((prefix.clone(), n.ident.to_string())),
        Rename(r) => out.push((prefix.clone(), r.ident.to_string())),
        Glob(_) => out.push((prefix.clone(), "*".into())),
        Group(g) => g.items.iter().for_each(|t| use_leaves(t, prefix, out)),
    }
}

/// A `use` path's module (`self`, `super`, `crate` or a child's name
/// first) as a path from the crate root, seen from module `at`.
fn resolve(at: &str, from: &[String]) -> String {
    let mut path: Vec<&str> = at.split("::").collect();
    for (i, seg) in from.iter().enumerate() {
        match seg.as_str() {
            "self" => {}
            "super" => {
                path.pop();
            }
            "crate" if i == 0 => path.truncate(1),
            s => path.push(s),
        }
    }
    path.join("::")
}

fn library_api() -> Api {
    let lib = Path::new(env!("CARGO_MANIFEST_DIR")).join("src/lib.rs");
    let text = std::fs::read_to_string(&lib).unwrap();
    let parsed = syn::parse_file(&text).unwrap();
    let mut api = Api::default();
    api.items.entry("platefield".into()).or_default();
    api.read("platefield", &parsed.items, &lib, true);
    api.resolve_reexports();
    api.resolve_impls();
    api
}

/// `docs/dev/api.md` lists the library's public items as they are.
#[test]
fn the_api_list_is_the_librarys() {
    let api = library_api();
    assert!(
        api.unresolved.is_empty(),
        "impls whose public type is ambiguous by name: {:?}",
        api.unresolved
    );
    let text = api.markdown();
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/dev/api.md");
    if std::env::var_os("PLATEFIELD_WRITE_API").is_some() {
        std::fs::write(&path, &text).unwrap();
    }
    let committed = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        committed == text,
        "docs/dev/api.md is stale: PLATEFIELD_WRITE_API=1 cargo test --release --test api"
    );
}

/// The reader finds what a hand-made crate declares: a public item in a
/// public module, none in a private one or behind `pub(crate)` unless a
/// reachable `pub use` re-exports it, a
/// method on its type, nothing from tests.
#[test]
fn the_reader_tells_public_from_private() {
    let dir = std::env::temp_dir().join(format!("platefield-api-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("a")).unwrap();
    std::fs::write(
        dir.join("lib.rs"),
        "pub mod a; mod b; pub(crate) mod c;\npub use c::Shown;\n#[cfg(test)] mod tests { pub fn t() {} }\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("a/mod.rs"),
        "pub struct S; impl S { pub fn m(&self) {} fn p(&self) {} }\n\
         pub(crate) fn hidden() {}\npub fn shown() {}\npub use self::S as T;\npub mod inner { pub const K: u8 = 1; }\n",
    )
    .unwrap();
    std::fs::write(dir.join("b.rs"), "pub fn private_module() {}\n").unwrap();
    std::fs::write(
        dir.join("c.rs"),
        "pub fn crate_module() {}\npub struct Shown; impl Shown { pub fn n(&self) {} }\n",
    )
    .unwrap();
    let lib = dir.join("lib.rs");
    let parsed = syn::parse_file(&std::fs::read_to_string(&lib).unwrap()).unwrap();
    let mut api = Api::default();
    api.read("k", &parsed.items, &lib, true);
    api.resolve_reexports();
    api.resolve_impls();
    let listed: Vec<String> = api
        .items
        .iter()
        .flat_map(|(p, s)| s.iter().map(move |(k, n)| format!("{k} {p}::{n}")))
        .collect();
    assert_eq!(
        listed,
        [
            "fn k::Shown::n",
            "struct k::Shown",
            "use k::c::Shown",
            "fn k::a::S::m",
            "fn k::a::shown",
            "struct k::a::S",
            "use k::a::self::S as T",
            "const k::a::inner::K",
        ]
    );
    let _ = std::fs::remove_dir_all(&dir);
}
