//! The library's top-level modules import each other without a cycle
//! (issue #13: "no cycle in the import graph"; docs/architecture.md).
//!
//! The graph is read from the source: every `crate::X` path and every item
//! of a `use crate::{...}` group, where a name the crate root re-exports
//! (`Scenario`, `Error`, ...) counts as the module that defines it. A
//! parent's `mod`/`pub use` of its children does not count. `input/`
//! groups the scenario's tables (issue #28, 3), which were top-level
//! modules of their own before: its children count as units here
//! (`input/scenario`, `input/top`, ...), so this check is as strict as it
//! was; the file-level check below covers every file.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

fn src() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("src")
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The unit a module path names: its first segment (`model::rigid` ->
/// `model`), or within `input` the child (`input::scenario::limits` ->
/// `input/scenario`; `input::Key` -> `input`).
fn unit(path: &str) -> String {
    let mut segs = path.split("::").map(str::trim);
    let first = segs.next().unwrap_or("").to_string();
    if first == "input" {
        if let Some(child) = segs.next() {
            if child.starts_with(|c: char| c.is_ascii_lowercase()) {
                return format!("input/{child}");
            }
        }
    }
    first
}

/// The unit a file belongs to (`model/rigid.rs` -> `model`,
/// `input/scenario/limits.rs` -> `input/scenario`, `input/mod.rs` ->
/// `input`).
fn top_module(file: &Path) -> String {
    let rel = file.strip_prefix(src()).unwrap();
    let segs: Vec<String> = rel
        .components()
        .map(|c| {
            c.as_os_str()
                .to_string_lossy()
                .trim_end_matches(".rs")
                .to_string()
        })
        .collect();
    let path = segs.join("::");
    unit(path.strip_suffix("::mod").unwrap_or(&path))
}

/// Names the crate root re-exports, and the module each comes from
/// (`pub use contact::{ContactMode, FrictionLaw}` in lib.rs).
fn root_reexports(lib: &str) -> BTreeMap<String, String> {
    let mut map = BTreeMap::new();
    for stmt in lib.split(';') {
        let stmt = stmt.trim();
        let Some(rest) = stmt.strip_prefix("pub use ") else {
            continue;
        };
        let (module, items) = rest.rsplit_once("::").unwrap();
        let module = unit(module);
        let items = items.trim_start_matches('{').trim_end_matches('}');
        for item in items.split(',') {
            let item = item.trim();
            if !item.is_empty() {
                map.insert(item.to_string(), module.trim().to_string());
            }
        }
    }
    map
}

/// Strip `//` comments (doc comments mention paths that are not imports).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|l| match l.find("//") {
            Some(i) => &l[..i],
            None => l,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The first path segment of every item of a `{...}` use group at top level.
fn group_heads(group: &str) -> Vec<String> {
    let mut heads = Vec::new();
    let (mut depth, mut item) = (0, String::new());
    for ch in group.chars() {
        match ch {
            '{' => {
                depth += 1;
                item.push(ch);
            }
            '}' => {
                depth -= 1;
                item.push(ch);
            }
            ',' if depth == 0 => {
                heads.push(std::mem::take(&mut item));
            }
            _ => item.push(ch),
        }
    }
    heads.push(item);
    heads
        .iter()
        .map(|i| unit(i.trim()))
        .filter(|h| !h.is_empty())
        .collect()
}

/// The top-level modules (or root re-exported names) a file refers to.
fn references(code: &str) -> BTreeSet<String> {
    let mut refs = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        if let Some(group) = after.strip_prefix('{') {
            // Balanced braces of the group.
            let mut depth = 1;
            let mut end = 0;
            for (k, ch) in group.char_indices() {
                match ch {
                    '{' => depth += 1,
                    '}' => {
                        depth -= 1;
                        if depth == 0 {
                            end = k;
                            break;
                        }
                    }
                    _ => {}
                }
            }
            refs.extend(group_heads(&group[..end]));
        } else {
            let name: String = after
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_' || *c == ':')
                .collect();
            refs.insert(unit(&name));
        }
        rest = after;
    }
    refs
}

fn graph() -> BTreeMap<String, BTreeSet<String>> {
    let lib = fs::read_to_string(src().join("lib.rs")).unwrap();
    let reexports = root_reexports(&code_of(&lib));
    let mut files = Vec::new();
    rust_files(&src(), &mut files);
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    for f in files {
        let from = top_module(&f);
        if from == "lib" {
            continue;
        }
        let text = fs::read_to_string(&f).unwrap();
        // Tests are excluded (as in the file-level check below): a file's
        // `#[cfg(test)] mod` is its last item.
        let text = text.split("#[cfg(test)]\nmod ").next().unwrap_or("");
        let code = code_of(text);
        for r in references(&code) {
            let to = reexports.get(&r).cloned().unwrap_or(r);
            if to != from {
                g.entry(from.clone()).or_default().insert(to);
            }
        }
    }
    g
}

/// A cycle through `start`, if any (depth-first search).
fn cycle(g: &BTreeMap<String, BTreeSet<String>>) -> Option<Vec<String>> {
    fn visit(
        g: &BTreeMap<String, BTreeSet<String>>,
        node: &str,
        path: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = path.iter().position(|p| p == node) {
            let mut c = path[i..].to_vec();
            c.push(node.to_string());
            return Some(c);
        }
        if done.contains(node) {
            return None;
        }
        path.push(node.to_string());
        for next in g.get(node).into_iter().flatten() {
            if let Some(c) = visit(g, next, path, done) {
                return Some(c);
            }
        }
        path.pop();
        done.insert(node.to_string());
        None
    }
    let mut done = BTreeSet::new();
    for start in g.keys() {
        if let Some(c) = visit(g, start, &mut Vec::new(), &mut done) {
            return Some(c);
        }
    }
    None
}

#[test]
fn top_level_modules_have_no_import_cycle() {
    let g = graph();
    // The reader sees the edges it must: the drivers use the models.
    assert!(g["simulate"].contains("model"), "{g:?}");
    assert!(g["model"].contains("integrate"), "{g:?}");
    if let Some(c) = cycle(&g) {
        panic!("import cycle: {}", c.join(" -> "));
    }
}

/// The detector finds a cycle when there is one (so the test above can fail).
#[test]
fn cycle_detector_finds_a_cycle() {
    let mut g: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    g.entry("a".into()).or_default().insert("b".into());
    g.entry("b".into()).or_default().insert("c".into());
    assert!(cycle(&g).is_none());
    g.entry("c".into()).or_default().insert("a".into());
    assert_eq!(cycle(&g).unwrap(), ["a", "b", "c", "a"]);
    // And the parser reads groups and root re-exports.
    let refs = references("use crate::{Error, model::{self, reduced::DIM}, sim::record::Track};");
    assert_eq!(
        refs.into_iter().collect::<Vec<_>>(),
        ["Error", "model", "sim"]
    );
}

// ---------------------------------------------------------------------------
// File level, every crate (issue #28, 4): no two files depend on each other,
// directly or around a loop. See support/source_graph.rs for what counts.

#[path = "support/source_graph.rs"]
mod source_graph;

use source_graph::{Crate, Graph};

/// The repository's root (this crate is `crates/tippetop`).
fn workspace() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .ancestors()
        .nth(2)
        .unwrap()
        .to_path_buf()
}

/// Every crate under `crates/`, the workspace's members and `tippetop-py`
/// (outside the workspace, its source read all the same).
fn crate_dirs() -> Vec<PathBuf> {
    let mut dirs: Vec<PathBuf> = fs::read_dir(workspace().join("crates"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("Cargo.toml").exists() && p.join("src").is_dir())
        .collect();
    dirs.sort();
    dirs
}

fn rel(p: &Path) -> String {
    p.strip_prefix(workspace())
        .unwrap_or(p)
        .display()
        .to_string()
}

/// The file graph of the crate rooted at `root`.
fn file_graph(root: &Path) -> Graph {
    let mut g = Graph::new();
    Crate::read(root).edges(&mut g);
    g
}

/// Each knot of files that depend on each other, with one cycle and the
/// edges inside it (each with a path that makes it).
fn knot_report(g: &Graph) -> String {
    let mut out = String::new();
    for knot in source_graph::knots(g) {
        let cycle = source_graph::cycle_in(g, &knot);
        out += &format!(
            "import cycle among {} files: {}\n",
            knot.len(),
            cycle
                .iter()
                .map(|f| rel(f))
                .collect::<Vec<_>>()
                .join(" -> ")
        );
        for a in &knot {
            for (b, why) in &g[a] {
                if knot.contains(b) {
                    out += &format!("    {} -> {}  ({why})\n", rel(a), rel(b));
                }
            }
        }
    }
    out
}

#[test]
fn no_file_depends_on_itself_around_a_loop_in_any_crate() {
    let mut report = String::new();
    let mut crates = 0;
    for dir in crate_dirs() {
        for root in source_graph::crate_roots(&dir) {
            crates += 1;
            let r = knot_report(&file_graph(&root));
            if !r.is_empty() {
                report += &format!("crate {}:\n{r}", rel(&root));
            }
        }
    }
    // tippetop, tippetop-cli (lib and bin), tippetop-paper, tippetop-py.
    assert!(crates >= 5, "{crates} crate roots found");
    assert!(report.is_empty(), "\n{report}");
}

/// The reader sees the edges it must, each kind of path once.
#[test]
fn file_graph_reader_sees_uses_paths_macros_and_reexports() {
    let dir = std::env::temp_dir().join(format!("tippetop-arch-{}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(dir.join("a")).unwrap();
    let files = [
        // The parent's `mod`, re-export and use of its children do not
        // count.
        (
            "lib.rs",
            "mod a; mod b; mod c; mod d; pub use a::{A, inner::I};\n\
             pub use d::D; fn uses_d() -> D { todo!() }",
        ),
        ("a.rs", "pub mod inner; pub struct A; pub use crate::b::B;"),
        ("a/inner.rs", "pub struct I; fn f() { super::A; }"),
        // A path in a macro call, through the root's re-export.
        (
            "b.rs",
            "pub struct B; fn g() { println!(\"{}\", crate::I); }",
        ),
        // A name imported through a re-export chain counts as its home;
        // a test module does not count.
        (
            "c.rs",
            "use crate::a::B as Bee; fn h(_: Bee) {}\n\
             #[cfg(test)] mod tests { use crate::d::D; }",
        ),
        (
            "d.rs",
            "pub struct D; #[arg(value_parser = crate::c::h)] struct X;",
        ),
    ];
    for (f, text) in files {
        fs::write(dir.join(f), text).unwrap();
    }
    let g = file_graph(&dir.join("lib.rs"));
    let dir = &dir;
    let mut edges: Vec<String> = g
        .iter()
        .flat_map(|(a, to)| {
            to.keys().map(move |b| {
                format!(
                    "{} -> {}",
                    a.strip_prefix(dir).unwrap().display(),
                    b.strip_prefix(dir).unwrap().display()
                )
            })
        })
        .collect();
    edges.sort();
    assert_eq!(
        edges,
        [
            "a.rs -> b.rs",
            "a/inner.rs -> a.rs",
            "b.rs -> a/inner.rs",
            "c.rs -> b.rs",
            "d.rs -> c.rs",
        ]
    );
    // No knot: b -> inner -> a -> b is one.
    let knots = source_graph::knots(&g);
    assert_eq!(knots.len(), 1, "{knots:?}");
    assert_eq!(knots[0].len(), 3);
    let report = knot_report(&g);
    assert!(report.contains("import cycle among 3 files"), "{report}");
    fs::remove_dir_all(dir).unwrap();
}

// ---------------------------------------------------------------------------
// Function length (issue #28, 4): at most 5 functions over 150 lines in
// crates/*/src, each a numerical kernel with its reason in a comment.

/// Longest a function may be before it counts as long [lines, from its
/// `fn` line to its closing brace].
const LONG: usize = 150;

/// The long functions allowed, by file and name: numerical kernels, each
/// with its reason in a comment above it.
const KERNELS: &[(&str, &str)] = &[
    ("crates/tippetop/src/numeric/eigen.rs", "hqr"),
    ("crates/tippetop/src/integrate/rosenbrock.rs", "step"),
];

/// Every function and method (test code excluded) of `crates/*/src` longer
/// than [`LONG`] lines: (file, name, lines).
fn long_functions() -> Vec<(String, String, usize)> {
    struct Finder<'a> {
        file: &'a str,
        out: &'a mut Vec<(String, String, usize)>,
    }
    impl Finder<'_> {
        fn check(&mut self, sig: &syn::Signature, end: proc_macro2::Span) {
            let lines = end.end().line + 1 - sig.fn_token.span.start().line;
            if lines > LONG {
                self.out
                    .push((self.file.to_string(), sig.ident.to_string(), lines));
            }
        }
    }
    fn is_test(attrs: &[syn::Attribute]) -> bool {
        attrs.iter().any(|a| {
            a.path().is_ident("test")
                || (a.path().is_ident("cfg")
                    && matches!(&a.meta, syn::Meta::List(l) if l.tokens.to_string() == "test"))
        })
    }
    impl<'ast> syn::visit::Visit<'ast> for Finder<'_> {
        fn visit_item_mod(&mut self, m: &'ast syn::ItemMod) {
            if !is_test(&m.attrs) {
                syn::visit::visit_item_mod(self, m);
            }
        }
        fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
            if !is_test(&f.attrs) {
                self.check(&f.sig, f.block.brace_token.span.close());
                syn::visit::visit_item_fn(self, f);
            }
        }
        fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
            if !is_test(&f.attrs) {
                self.check(&f.sig, f.block.brace_token.span.close());
                syn::visit::visit_impl_item_fn(self, f);
            }
        }
        fn visit_trait_item_fn(&mut self, f: &'ast syn::TraitItemFn) {
            if let Some(b) = &f.default {
                self.check(&f.sig, b.brace_token.span.close());
            }
            syn::visit::visit_trait_item_fn(self, f);
        }
    }
    let mut out = Vec::new();
    for dir in crate_dirs() {
        let mut files = Vec::new();
        rust_files(&dir.join("src"), &mut files);
        files.sort();
        for f in files {
            let text = fs::read_to_string(&f).unwrap();
            let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", f.display()));
            let name = rel(&f);
            syn::visit::Visit::visit_file(
                &mut Finder {
                    file: &name,
                    out: &mut out,
                },
                &ast,
            );
        }
    }
    out
}

#[test]
fn at_most_five_long_functions_all_kernels() {
    let long = long_functions();
    let listed =
        |list: &[(&str, &str)], f: &str, n: &str| list.iter().any(|&(lf, ln)| lf == f && ln == n);
    let report: Vec<String> = long
        .iter()
        .map(|(f, n, l)| format!("{f}: {n} ({l} lines)"))
        .collect();
    let kernels: Vec<&String> = long
        .iter()
        .zip(&report)
        .filter(|((f, n, _), _)| listed(KERNELS, f, n))
        .map(|(_, r)| r)
        .collect();
    let unlisted: Vec<&String> = long
        .iter()
        .zip(&report)
        .filter(|((f, n, _), _)| !listed(KERNELS, f, n))
        .map(|(_, r)| r)
        .collect();
    assert!(
        unlisted.is_empty(),
        "{} functions over {LONG} lines that are not listed kernels (split them):\n  {}",
        unlisted.len(),
        unlisted
            .iter()
            .map(|s| s.as_str())
            .collect::<Vec<_>>()
            .join("\n  ")
    );
    assert!(kernels.len() <= 5, "more than 5 long kernels: {kernels:#?}");
    // Each list names only functions that are long today: a function split
    // or shortened leaves its list.
    for (f, n) in KERNELS {
        assert!(
            long.iter().any(|(lf, ln, _)| lf == f && ln == n),
            "{f}: {n} is no longer over {LONG} lines: take it off the list"
        );
    }
}
