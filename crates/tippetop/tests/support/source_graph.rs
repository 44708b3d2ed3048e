//! The file-level dependency graph of a crate, read from its source with
//! `syn` (shared by the architecture tests; included with `#[path]`).
//!
//! File A depends on file B when A names an item defined in B: through a
//! `use`, a path (`crate::x::y::Item`, `super::Item`, `sibling::Item`), or a
//! path inside a macro call or an attribute (`value_parser = x::parse`).
//! A name imported through re-exports counts as the file that defines it.
//! Not counted:
//! - a module naming its own descendants: its `mod child;` declarations,
//!   its re-exports of its children, and its calls into them (a parent is
//!   the sum of its children: `forces/mod.rs` lists the force terms, which
//!   name `super::Applied`). A child naming its parent does count;
//! - naming a module alone (`use crate::output;`): only its items count;
//! - test code (`#[cfg(test)]` items and modules; `tests/` is not read);
//! - other crates (`std`, `tippetop` from the CLI: crates cannot form cycles).
//!
//! Approximations (none matters for the cycle check): namespaces are not
//! told apart (a path with more segments prefers a module, a last segment
//! an item); an `impl` block's methods count as the file of their type
//! when called as `Type::method`, and not at all as `x.method()`.

#![allow(dead_code)]

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

use proc_macro2::{TokenStream, TokenTree};
use syn::visit::Visit;

/// A `use` item flattened: `use a::b::{c as d, e::*}` gives `d = a::b::c`
/// and the glob `a::b::e::*`.
#[derive(Clone, Debug)]
struct Use {
    alias: String,
    path: Vec<String>,
    glob: bool,
    public: bool,
}

/// A module: a file, or an inline `mod x { ... }` inside one.
#[derive(Default)]
struct Module {
    file: PathBuf,
    /// Where `mod child;` of this module looks for files.
    dir: PathBuf,
    parent: Option<usize>,
    children: BTreeMap<String, usize>,
    items: BTreeSet<String>,
    uses: Vec<Use>,
    /// Paths named in the module's own (non-test) items.
    refs: Vec<Vec<String>>,
}

#[derive(Clone, Copy, Debug)]
enum Target {
    Module(usize),
    /// An item defined in a module.
    Item(usize),
}

/// One crate's modules.
pub struct Crate {
    modules: Vec<Module>,
}

/// An edge A -> B with one path that makes it (for the report).
pub type Graph = BTreeMap<PathBuf, BTreeMap<PathBuf, String>>;

fn is_test_cfg(attrs: &[syn::Attribute]) -> bool {
    attrs.iter().any(|a| {
        a.path().is_ident("cfg")
            && matches!(&a.meta, syn::Meta::List(l) if l.tokens.to_string() == "test")
    })
}

fn path_attr(attrs: &[syn::Attribute]) -> Option<String> {
    attrs.iter().find_map(|a| match &a.meta {
        syn::Meta::NameValue(nv) if nv.path.is_ident("path") => match &nv.value {
            syn::Expr::Lit(syn::ExprLit {
                lit: syn::Lit::Str(s),
                ..
            }) => Some(s.value()),
            _ => None,
        },
        _ => None,
    })
}

fn flatten_use(tree: &syn::UseTree, prefix: &mut Vec<String>, public: bool, out: &mut Vec<Use>) {
    match tree {
        syn::UseTree::Path(p) => {
            prefix.push(p.ident.to_string());
            flatten_use(&p.tree, prefix, public, out);
            prefix.pop();
        }
        syn::UseTree::Name(n) => {
            let name = n.ident.to_string();
            if name == "self" {
                if let Some(last) = prefix.last() {
                    out.push(Use {
                        alias: last.clone(),
                        path: prefix.clone(),
                        glob: false,
                        public,
                    });
                }
            } else {
                let mut path = prefix.clone();
                path.push(name.clone());
                out.push(Use {
                    alias: name,
                    path,
                    glob: false,
                    public,
                });
            }
        }
        syn::UseTree::Rename(r) => {
            let mut path = prefix.clone();
            let name = r.ident.to_string();
            if name != "self" {
                path.push(name);
            }
            out.push(Use {
                alias: r.rename.to_string(),
                path,
                glob: false,
                public,
            });
        }
        syn::UseTree::Glob(_) => out.push(Use {
            alias: "*".into(),
            path: prefix.clone(),
            glob: true,
            public,
        }),
        syn::UseTree::Group(g) => {
            for t in &g.items {
                flatten_use(t, prefix, public, out);
            }
        }
    }
}

/// Every `a::b::c` (and lone `a`) in a token stream.
fn token_paths(tokens: TokenStream, out: &mut Vec<Vec<String>>) {
    let trees: Vec<TokenTree> = tokens.into_iter().collect();
    let mut i = 0;
    while i < trees.len() {
        match &trees[i] {
            TokenTree::Group(g) => {
                token_paths(g.stream(), out);
                i += 1;
            }
            TokenTree::Ident(id) => {
                // `$crate` and a lone `$x` are macro variables, not paths.
                let after_dollar =
                    i > 0 && matches!(&trees[i - 1], TokenTree::Punct(p) if p.as_char() == '$');
                let mut path = vec![id.to_string()];
                let mut j = i + 1;
                while j + 2 < trees.len()
                    && matches!(&trees[j], TokenTree::Punct(p) if p.as_char() == ':')
                    && matches!(&trees[j + 1], TokenTree::Punct(p) if p.as_char() == ':')
                {
                    if let TokenTree::Ident(next) = &trees[j + 2] {
                        path.push(next.to_string());
                        j += 3;
                    } else {
                        break;
                    }
                }
                if !after_dollar {
                    out.push(path);
                }
                i = j;
            }
            _ => i += 1,
        }
    }
}

/// Collects the paths of one module's items (not of nested modules).
struct Refs<'a> {
    out: &'a mut Vec<Vec<String>>,
}

impl<'ast> Visit<'ast> for Refs<'_> {
    fn visit_path(&mut self, p: &'ast syn::Path) {
        self.out
            .push(p.segments.iter().map(|s| s.ident.to_string()).collect());
        syn::visit::visit_path(self, p);
    }
    fn visit_attribute(&mut self, a: &'ast syn::Attribute) {
        // The arguments of `#[arg(value_parser = x::parse)]`, not the
        // attribute's own name nor doc text.
        if let syn::Meta::List(l) = &a.meta {
            token_paths(l.tokens.clone(), self.out);
        }
    }
    fn visit_macro(&mut self, m: &'ast syn::Macro) {
        self.visit_path(&m.path);
        token_paths(m.tokens.clone(), self.out);
    }
    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {}
    fn visit_item_use(&mut self, _: &'ast syn::ItemUse) {}
    fn visit_item_fn(&mut self, f: &'ast syn::ItemFn) {
        if !is_test_cfg(&f.attrs) {
            syn::visit::visit_item_fn(self, f);
        }
    }
    fn visit_impl_item_fn(&mut self, f: &'ast syn::ImplItemFn) {
        if !is_test_cfg(&f.attrs) {
            syn::visit::visit_impl_item_fn(self, f);
        }
    }
}

/// Function-local `use` items count as the module's own.
struct LocalUses<'a> {
    out: &'a mut Vec<Use>,
}

impl<'ast> Visit<'ast> for LocalUses<'_> {
    fn visit_item_use(&mut self, u: &'ast syn::ItemUse) {
        flatten_use(&u.tree, &mut Vec::new(), false, self.out);
    }
    fn visit_item_mod(&mut self, _: &'ast syn::ItemMod) {}
}

fn item_name(item: &syn::Item) -> Option<String> {
    Some(
        match item {
            syn::Item::Const(i) => &i.ident,
            syn::Item::Enum(i) => &i.ident,
            syn::Item::Fn(i) => &i.sig.ident,
            syn::Item::Macro(i) => i.ident.as_ref()?,
            syn::Item::Static(i) => &i.ident,
            syn::Item::Struct(i) => &i.ident,
            syn::Item::Trait(i) => &i.ident,
            syn::Item::TraitAlias(i) => &i.ident,
            syn::Item::Type(i) => &i.ident,
            syn::Item::Union(i) => &i.ident,
            _ => return None,
        }
        .to_string(),
    )
}

fn item_attrs(item: &syn::Item) -> &[syn::Attribute] {
    match item {
        syn::Item::Const(i) => &i.attrs,
        syn::Item::Enum(i) => &i.attrs,
        syn::Item::Fn(i) => &i.attrs,
        syn::Item::Impl(i) => &i.attrs,
        syn::Item::Macro(i) => &i.attrs,
        syn::Item::Mod(i) => &i.attrs,
        syn::Item::Static(i) => &i.attrs,
        syn::Item::Struct(i) => &i.attrs,
        syn::Item::Trait(i) => &i.attrs,
        syn::Item::Type(i) => &i.attrs,
        syn::Item::Union(i) => &i.attrs,
        syn::Item::Use(i) => &i.attrs,
        _ => &[],
    }
}

impl Crate {
    /// Reads the crate whose root file is `root` (`src/lib.rs`, `src/main.rs`).
    pub fn read(root: &Path) -> Crate {
        let mut c = Crate {
            modules: Vec::new(),
        };
        let dir = root.parent().unwrap().to_path_buf();
        c.load_file(root, dir, None, "crate");
        c
    }

    fn load_file(&mut self, file: &Path, dir: PathBuf, parent: Option<usize>, name: &str) {
        let text = fs::read_to_string(file).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        let ast = syn::parse_file(&text).unwrap_or_else(|e| panic!("{}: {e}", file.display()));
        self.load_items(&ast.items, file, dir, parent, name);
    }

    fn load_items(
        &mut self,
        items: &[syn::Item],
        file: &Path,
        dir: PathBuf,
        parent: Option<usize>,
        name: &str,
    ) -> usize {
        let id = self.modules.len();
        self.modules.push(Module {
            file: file.to_path_buf(),
            dir: dir.clone(),
            parent,
            ..Default::default()
        });
        if let Some(p) = parent {
            self.modules[p].children.insert(name.to_string(), id);
        }
        let mut refs = Vec::new();
        let mut uses = Vec::new();
        for item in items {
            if is_test_cfg(item_attrs(item)) {
                continue;
            }
            match item {
                syn::Item::Mod(m) => {
                    let child = m.ident.to_string();
                    match &m.content {
                        Some((_, inner)) => {
                            let d = dir.join(&child);
                            self.load_items(inner, file, d, Some(id), &child);
                        }
                        None => {
                            let path = match path_attr(&m.attrs) {
                                Some(p) => dir.join(p),
                                None => {
                                    let a = dir.join(format!("{child}.rs"));
                                    if a.exists() {
                                        a
                                    } else {
                                        dir.join(&child).join("mod.rs")
                                    }
                                }
                            };
                            let d = dir.join(&child);
                            self.load_file(&path, d, Some(id), &child);
                        }
                    }
                }
                syn::Item::Use(u) => {
                    let public = !matches!(u.vis, syn::Visibility::Inherited);
                    flatten_use(&u.tree, &mut Vec::new(), public, &mut uses);
                }
                _ => {
                    if let Some(n) = item_name(item) {
                        self.modules[id].items.insert(n);
                    }
                    Refs { out: &mut refs }.visit_item(item);
                    LocalUses { out: &mut uses }.visit_item(item);
                }
            }
        }
        self.modules[id].refs = refs;
        self.modules[id].uses = uses;
        id
    }

    fn lookup(&self, m: usize, name: &str, more: bool, depth: usize) -> Option<Target> {
        if depth > 40 {
            return None;
        }
        let module = &self.modules[m];
        match name {
            "self" => return Some(Target::Module(m)),
            "super" => return module.parent.map(Target::Module),
            "crate" => return Some(Target::Module(0)),
            _ => {}
        }
        let child = module.children.get(name).map(|&c| Target::Module(c));
        let item = module.items.contains(name).then_some(Target::Item(m));
        let alias = || {
            module
                .uses
                .iter()
                .filter(|u| !u.glob && u.alias == name)
                .find_map(|u| self.resolve(m, &u.path, depth + 1))
        };
        let found = if more {
            child.or_else(alias).or(item)
        } else {
            item.or_else(alias).or(child)
        };
        found.or_else(|| {
            module.uses.iter().filter(|u| u.glob).find_map(|u| {
                match self.resolve(m, &u.path, depth + 1)? {
                    Target::Module(g) if g != m => self.lookup(g, name, more, depth + 1),
                    _ => None,
                }
            })
        })
    }

    /// What `path`, named in module `m`, refers to; `None` outside the crate.
    fn resolve(&self, m: usize, path: &[String], depth: usize) -> Option<Target> {
        let (first, rest) = path.split_first()?;
        let mut t = self.lookup(m, first, !rest.is_empty(), depth)?;
        for (k, seg) in rest.iter().enumerate() {
            match t {
                Target::Module(c) => {
                    t = self.lookup(c, seg, k + 1 < rest.len(), depth)?;
                }
                Target::Item(_) => break,
            }
        }
        Some(t)
    }

    fn is_descendant(&self, mut m: usize, of: usize) -> bool {
        while let Some(p) = self.modules[m].parent {
            if p == of {
                return true;
            }
            m = p;
        }
        false
    }

    /// The file-level edges of this crate, added to `g`.
    pub fn edges(&self, g: &mut Graph) {
        for (m, module) in self.modules.iter().enumerate() {
            g.entry(module.file.clone()).or_default();
            let add = |target: Option<Target>, path: &[String], g: &mut Graph| {
                if let Some(Target::Item(d)) = target {
                    let to = &self.modules[d].file;
                    if *to != module.file && !self.is_descendant(d, m) {
                        g.entry(module.file.clone())
                            .or_default()
                            .entry(to.clone())
                            .or_insert_with(|| path.join("::"));
                    }
                }
            };
            for u in &module.uses {
                let t = self.resolve(m, &u.path, 0);
                let target_module = match t {
                    Some(Target::Item(d)) | Some(Target::Module(d)) => d,
                    None => continue,
                };
                if self.is_descendant(target_module, m) {
                    continue; // a parent's use or re-export of its children
                }
                if u.glob {
                    if let Some(Target::Module(d)) = t {
                        if self.modules[d].file != module.file {
                            add(Some(Target::Item(d)), &u.path, g);
                        }
                    }
                } else {
                    add(t, &u.path, g);
                }
            }
            for r in &module.refs {
                add(self.resolve(m, r, 0), r, g);
            }
        }
    }

    /// Every file of the crate.
    pub fn files(&self) -> BTreeSet<PathBuf> {
        self.modules.iter().map(|m| m.file.clone()).collect()
    }
}

/// The roots of the crates under `crate_dir/src`: `lib.rs`, `main.rs`,
/// `bin/*.rs`.
pub fn crate_roots(crate_dir: &Path) -> Vec<PathBuf> {
    let src = crate_dir.join("src");
    let mut roots: Vec<PathBuf> = ["lib.rs", "main.rs"]
        .iter()
        .map(|f| src.join(f))
        .filter(|p| p.exists())
        .collect();
    if let Ok(dir) = fs::read_dir(src.join("bin")) {
        let mut bins: Vec<PathBuf> = dir
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|x| x == "rs"))
            .collect();
        bins.sort();
        roots.extend(bins);
    }
    roots
}

/// The strongly connected components of more than one file (Tarjan).
pub fn knots(g: &Graph) -> Vec<Vec<PathBuf>> {
    struct St<'a> {
        g: &'a Graph,
        index: BTreeMap<&'a PathBuf, usize>,
        low: BTreeMap<&'a PathBuf, usize>,
        stack: Vec<&'a PathBuf>,
        on: BTreeSet<&'a PathBuf>,
        out: Vec<Vec<PathBuf>>,
    }
    fn visit<'a>(s: &mut St<'a>, v: &'a PathBuf) {
        let i = s.index.len();
        s.index.insert(v, i);
        s.low.insert(v, i);
        s.stack.push(v);
        s.on.insert(v);
        for w in s.g.get(v).into_iter().flat_map(|e| e.keys()) {
            if !s.index.contains_key(w) {
                visit(s, w);
                let lw = s.low[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(lw);
            } else if s.on.contains(w) {
                let iw = s.index[w];
                let lv = s.low.get_mut(v).unwrap();
                *lv = (*lv).min(iw);
            }
        }
        if s.low[v] == s.index[v] {
            let mut comp = Vec::new();
            loop {
                let w = s.stack.pop().unwrap();
                s.on.remove(w);
                comp.push(w.clone());
                if w == v {
                    break;
                }
            }
            if comp.len() > 1 {
                comp.sort();
                s.out.push(comp);
            }
        }
    }
    let mut s = St {
        g,
        index: BTreeMap::new(),
        low: BTreeMap::new(),
        stack: Vec::new(),
        on: BTreeSet::new(),
        out: Vec::new(),
    };
    for v in g.keys() {
        if !s.index.contains_key(v) {
            visit(&mut s, v);
        }
    }
    s.out.sort();
    s.out
}

/// A shortest cycle through the first file of a knot (breadth-first).
pub fn cycle_in(g: &Graph, knot: &[PathBuf]) -> Vec<PathBuf> {
    let start = &knot[0];
    let inside: BTreeSet<&PathBuf> = knot.iter().collect();
    let mut prev: BTreeMap<&PathBuf, &PathBuf> = BTreeMap::new();
    let mut queue = std::collections::VecDeque::from([start]);
    while let Some(v) = queue.pop_front() {
        for w in g[v].keys().filter(|w| inside.contains(w)) {
            if w == start {
                let mut c = vec![v.clone()];
                let mut x = v;
                while x != start {
                    x = prev[x];
                    c.push(x.clone());
                }
                c.reverse();
                c.push(start.clone());
                return c;
            }
            if !prev.contains_key(w) {
                prev.insert(w, v);
                queue.push_back(w);
            }
        }
    }
    unreachable!("a knot has a cycle")
}
