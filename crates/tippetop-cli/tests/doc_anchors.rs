//! The docs' anchors that the code and the docs point at exist.
//!
//! `readme.rs` checks the Markdown links of README.md and docs/*.md. This
//! checks the references that are not links: `docs/physics.md#NAME` (or any
//! other doc of the repository, `guide.md#NAME`, `performance.md#NAME`, ...)
//! and `§NAME` (a section of docs/physics.md) in source comments, messages,
//! scripts, scenario files and the docs' own inline code; that
//! docs/physics.md's stable anchors (`<a id="NAME">`) are unique; and that
//! its list of sections at the top names every one of them.
//!
//! Only the standard library: the repository's files are read as text.

mod common;
use common::anchors;

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `<a id="...">` anchors of a Markdown text, in order, repeats kept.
fn ids(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for line in text.lines() {
        let mut rest = line;
        while let Some(i) = rest.find("<a id=\"") {
            rest = &rest[i + 7..];
            if let Some(j) = rest.find('"') {
                out.push(rest[..j].to_string());
            }
        }
    }
    out
}

/// The text files under `dir` that may point at the docs: sources, scripts,
/// scenarios, notebooks and the docs themselves (not `target/`, not hidden
/// directories other than `.ci`).
fn files(dir: &Path, out: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(dir) else {
        return;
    };
    for e in entries.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        if p.is_dir() {
            if name == "target" || (name.starts_with('.') && name != ".ci") {
                continue;
            }
            files(&p, out);
        } else {
            let text_ext = [
                "rs", "md", "py", "pyi", "toml", "sh", "ipynb", "js", "html", "txt",
            ];
            let ext = p.extension().map(|x| x.to_string_lossy().into_owned());
            if ext.is_some_and(|x| text_ext.contains(&x.as_str()))
                || dir.file_name().is_some_and(|n| n == ".ci")
            {
                out.push(p);
            }
        }
    }
}

/// `(doc, anchor)` for every `NAME.md#ANCHOR` in `text` (the name without
/// its directories; an anchor with a capital letter is a placeholder, as
/// GitHub's anchors are lower case, and is skipped).
fn md_refs(text: &str) -> Vec<(String, String)> {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    let mut out = Vec::new();
    let mut from = 0;
    while let Some(i) = text[from..].find(".md#") {
        let at = from + i;
        let name_start = text[..at]
            .char_indices()
            .rev()
            .take_while(|&(_, c)| word(c))
            .last()
            .map_or(at, |(k, _)| k);
        let rest = &text[at + 4..];
        let end = rest.find(|c: char| !word(c)).unwrap_or(rest.len());
        let anchor = rest[..end].trim_end_matches('-');
        if name_start < at && !anchor.is_empty() && !anchor.contains(|c: char| c.is_uppercase()) {
            out.push((text[name_start..at].to_string(), anchor.to_string()));
        }
        from = at + 4;
    }
    out
}

/// Every `§NAME` of `text` that names a section by anchor (lower case, as
/// `§contensou`; not a numbered citation such as Gardiner's `§5.2.7`).
fn section_refs(text: &str) -> Vec<String> {
    let mut out = Vec::new();
    for (i, _) in text.match_indices('§') {
        let rest = &text[i + '§'.len_utf8()..];
        let end = rest
            .find(|c: char| !(c.is_ascii_lowercase() || c.is_ascii_digit() || c == '-'))
            .unwrap_or(rest.len());
        let name = rest[..end].trim_end_matches('-');
        if name.starts_with(|c: char| c.is_ascii_lowercase()) {
            out.push(name.to_string());
        }
    }
    out
}

/// The doc a reference names: README.md at the root, the others in docs/.
fn doc_path(name: &str) -> Option<PathBuf> {
    let p = if name == "README" {
        root().join("README.md")
    } else {
        root().join("docs").join(format!("{name}.md"))
    };
    p.exists().then_some(p)
}

/// Every `NAME.md#ANCHOR` and `§NAME` in the repository's text files
/// resolves: to an anchor of that doc, or of docs/physics.md for `§`.
/// (A `NAME.md` that is not a doc of the repository, such as the research
/// notes outside it, is not checked.)
#[test]
fn doc_references_resolve() {
    // The repository's own directories only: not what a user keeps in the
    // checkout (`out/`, a virtual environment's packages).
    let mut paths = vec![root().join("README.md")];
    for dir in ["crates", "benches", "examples", "scenarios", "docs", ".ci"] {
        files(&root().join(dir), &mut paths);
    }
    assert!(paths.len() > 100, "only {} files found", paths.len());
    let physics = fs::read_to_string(root().join("docs/physics.md")).unwrap();
    let physics_ids: BTreeSet<String> = ids(&physics).into_iter().collect();
    let mut docs: BTreeMap<String, Option<BTreeSet<String>>> = BTreeMap::new();
    let (mut checked, mut bad) = (0, Vec::new());
    for p in &paths {
        let Ok(text) = fs::read_to_string(p) else {
            continue;
        };
        let rel = p.strip_prefix(root()).unwrap_or(p).display().to_string();
        for (n, line) in text.lines().enumerate() {
            for (name, anchor) in md_refs(line) {
                let known = docs.entry(name.clone()).or_insert_with(|| {
                    doc_path(&name).map(|d| anchors(&fs::read_to_string(d).unwrap()))
                });
                if let Some(known) = known {
                    checked += 1;
                    if !known.contains(&anchor) {
                        bad.push(format!("{rel}:{}: {name}.md#{anchor}", n + 1));
                    }
                }
            }
            for name in section_refs(line) {
                checked += 1;
                if !physics_ids.contains(&name) {
                    bad.push(format!(
                        "{rel}:{}: §{name} (no <a id=\"{name}\"> in docs/physics.md)",
                        n + 1
                    ));
                }
            }
        }
    }
    assert!(checked >= 200, "only {checked} references found");
    assert!(bad.is_empty(), "unresolved references:\n{}", bad.join("\n"));
}

/// docs/physics.md's stable anchors are unique, and its list of sections
/// (the text before its first `## ` heading) links every one of them.
#[test]
fn physics_anchors_unique_and_listed() {
    let text = fs::read_to_string(root().join("docs/physics.md")).unwrap();
    let all = ids(&text);
    assert!(all.len() >= 30, "only {} anchors", all.len());
    let mut seen = BTreeSet::new();
    let repeated: Vec<_> = all.iter().filter(|a| !seen.insert(*a)).collect();
    assert!(repeated.is_empty(), "anchors given twice: {repeated:?}");
    let body = text.split_once("\n## ").map_or("", |(head, _)| head);
    let unlisted: Vec<_> = all
        .iter()
        .filter(|a| !body.contains(&format!("(#{a})")))
        .collect();
    assert!(
        unlisted.is_empty(),
        "anchors missing from physics.md's list of sections: {unlisted:?}"
    );
}
