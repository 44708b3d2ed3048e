//! The README and the user guide (docs/guide.md) are part of the interface:
//! the guide's "every key" scenario must run as written and name every key
//! the validator accepts, its `trajectory.csv` table must list every column,
//! and the example commands of both must run.

mod common;
use common::anchors;

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

/// The text of `rel`, a path from the repository's root.
fn doc(rel: &str) -> String {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../..")
        .join(rel);
    fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn readme() -> String {
    doc("README.md")
}

fn guide() -> String {
    doc("docs/guide.md")
}

/// The code blocks of `text` fenced with ```` ```LANG ````, in order.
fn blocks(text: &str, lang: &str) -> Vec<String> {
    let mut out = Vec::new();
    // (language of the open block, its text)
    let mut cur: Option<(String, String)> = None;
    for line in text.lines() {
        let l = line.trim_end();
        match &mut cur {
            None => {
                if let Some(tag) = l.strip_prefix("```") {
                    cur = Some((tag.trim().to_string(), String::new()));
                }
            }
            Some((tag, b)) => {
                if l == "```" {
                    if tag == lang {
                        out.push(std::mem::take(b));
                    }
                    cur = None;
                } else {
                    b.push_str(line);
                    b.push('\n');
                }
            }
        }
    }
    out
}

/// The scenario block of the guide (the one with `[solver]` and `[top]`).
fn every_key_block() -> String {
    let all = blocks(&guide(), "toml");
    let found: Vec<_> = all
        .into_iter()
        .filter(|b| b.contains("[solver]") && b.contains("[top]"))
        .collect();
    assert_eq!(
        found.len(),
        1,
        "expected one full scenario block in docs/guide.md"
    );
    found[0].clone()
}

/// The list the validator prints after `marker` in its error for `--set
/// SET` (an independent source: the docs are not consulted).
fn validator_list(set: &str, marker: &str) -> Vec<String> {
    let out = tippetop()
        .args(["run", "--preset", "nano", "--set", set, "--out"])
        .arg(std::env::temp_dir().join("tippetop-readme-never-written"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    let list = err
        .split(marker)
        .nth(1)
        .unwrap_or_else(|| panic!("no {marker:?} in {err:?}"));
    list.trim_end()
        .trim_end_matches(')')
        .split(", ")
        .map(str::to_string)
        .collect()
}

/// The valid keys of `table`, from the validator's unknown-key error.
fn valid_keys(table: &str) -> Vec<String> {
    let set = if table == "force" || table == "well" {
        format!("{table}.0.no_such_key=1")
    } else {
        format!("{table}.no_such_key=1")
    };
    validator_list(&set, "valid keys: ")
}

/// The valid tables, from the validator's unknown-table error.
fn valid_tables() -> Vec<String> {
    validator_list("no_such_table.x=1", "valid tables: ")
}

/// `(table, key)` for every `key = ...` line of the block, also commented
/// ones (`# key = ...`: keys that the example cannot set together with the
/// others, such as `friction_eps` with the default friction law).
fn keys_in_block(block: &str) -> BTreeSet<(String, String)> {
    let mut table = String::new();
    let mut keys = BTreeSet::new();
    for line in block.lines() {
        let l = line.split('#').next().unwrap().trim();
        if let Some(t) = l.strip_prefix("[[").and_then(|t| t.strip_suffix("]]")) {
            table = t.to_string();
        } else if let Some(t) = l.strip_prefix('[').and_then(|t| t.strip_suffix(']')) {
            table = t.to_string();
        } else {
            let l = line.trim().trim_start_matches('#').trim_start();
            if let Some((k, _)) = l.split_once('=') {
                let k = k.trim();
                if !k.is_empty() && k.chars().all(|c| c.is_ascii_alphanumeric() || c == '_') {
                    keys.insert((table.clone(), k.to_string()));
                }
            }
        }
    }
    keys
}

fn tmp(name: &str) -> PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("tippetop-readme-{name}-"))
        .tempdir()
        .unwrap()
        .keep()
}

#[test]
fn every_key_scenario_runs_as_written() {
    let dir = tmp("every-key");
    let file = dir.join("every-key.toml");
    fs::write(&file, every_key_block()).unwrap();
    let out = dir.join("out");
    let o = tippetop()
        .args(["run", "--no-plot", "--quiet", "--out"])
        .arg(&out)
        .arg(&file)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "docs/guide.md scenario failed: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    let summary = fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("\"status\": \"ok\""), "{summary}");
    let _ = fs::remove_dir_all(&dir);
}

#[test]
fn every_key_scenario_names_every_valid_key() {
    let documented = keys_in_block(&every_key_block());
    assert!(documented.contains(&(String::new(), "preset".to_string())));
    for table in valid_tables() {
        for key in valid_keys(&table) {
            assert!(
                documented.contains(&(table.clone(), key.clone())),
                "docs/guide.md's scenario block does not explain {table}.{key}"
            );
        }
    }
}

#[test]
fn guide_lists_every_trajectory_column_with_a_unit() {
    let text = guide();
    let heading = "The columns of `trajectory.csv`";
    let text = &text[text
        .find(heading)
        .expect("docs/guide.md lacks the column table")..];
    for col in tippetop::trajectory::COLUMNS {
        // A row of the column table: "| `col` | unit | meaning |", or a
        // row shared by several columns ("| `ux`, `uy` | m/s | ...").
        let row = text.lines().find(|l| {
            l.starts_with("| `")
                && l.split('|')
                    .nth(1)
                    .is_some_and(|c| c.split(',').any(|n| n.trim() == format!("`{col}`")))
        });
        let row = row.unwrap_or_else(|| panic!("docs/guide.md has no table row for column {col}"));
        let cells: Vec<&str> = row.split('|').map(str::trim).collect();
        assert!(cells.len() >= 4, "{row}");
        assert!(!cells[2].is_empty(), "no unit for {col}: {row}");
        assert!(cells[3].len() > 3, "no meaning for {col}: {row}");
    }
}

/// Every `cargo run --release -- ARGS` line of the shell blocks of the
/// README, then of the guide, runs with the built binary (exit 0), `--out`
/// redirected to a temporary directory (a command both give runs once).
#[test]
fn readme_commands_run() {
    let text = readme() + &guide();
    let mut commands: Vec<Vec<String>> = Vec::new();
    for b in blocks(&text, "") {
        let joined = b.replace("\\\n", " ");
        for line in joined.lines() {
            if let Some(rest) = line.trim().strip_prefix("cargo run --release -- ") {
                let args: Vec<String> = rest
                    .split('#')
                    .next()
                    .unwrap()
                    .split_whitespace()
                    .map(|a| a.replace('"', ""))
                    .collect();
                if !commands.contains(&args) {
                    commands.push(args);
                }
            }
        }
    }
    assert!(commands.len() >= 6, "found only {commands:?}");
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let base = tmp("commands");
    // The README's --out directories, redirected (for `animate DIR`).
    let mut outs: std::collections::HashMap<String, PathBuf> = std::collections::HashMap::new();
    for (i, args) in commands.iter().enumerate() {
        let mut args = args.clone();
        let out = base.join(format!("c{i}"));
        if args[0] == "animate" {
            let dir = outs
                .get(&args[1])
                .unwrap_or_else(|| panic!("README: animate {} before a run into it", args[1]));
            args[1] = dir.display().to_string();
        }
        match args.iter().position(|a| a == "--out") {
            Some(p) => {
                outs.insert(args[p + 1].clone(), out.clone());
                args[p + 1] = out.display().to_string()
            }
            None if ["run", "sweep", "reproduce"].contains(&args[0].as_str()) => {
                args.push("--out".into());
                args.push(out.display().to_string());
            }
            None => {}
        }
        // Plots are exercised elsewhere; here they would only cost time.
        if args[0] == "run" && !args.iter().any(|a| a == "--no-plot") {
            args.push("--no-plot".into());
        }
        let o = tippetop()
            .current_dir(&root)
            .args(&args)
            .arg("--quiet")
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "README command `tippetop {}` failed ({:?}): {}",
            args.join(" "),
            o.status.code(),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    let _ = fs::remove_dir_all(&base);
}

/// Every relative link of README.md and docs/*.md (`[text](target)`, outside
/// code blocks) names a file that exists, and its `#anchor`, if any, is a
/// heading or an `<a id>` of that file (of the same file for `(#anchor)`).
#[test]
fn doc_links_resolve() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut files = vec![root.join("README.md")];
    for e in fs::read_dir(root.join("docs")).unwrap() {
        let p = e.unwrap().path();
        if p.extension().is_some_and(|x| x == "md") {
            files.push(p);
        }
    }
    let mut checked = 0;
    let mut bad = Vec::new();
    for file in &files {
        let text = fs::read_to_string(file).unwrap();
        let mut fenced = false;
        for (n, line) in text.lines().enumerate() {
            if line.trim_start().starts_with("```") {
                fenced = !fenced;
                continue;
            }
            if fenced {
                continue;
            }
            // Inline code is not a link: keep the text between code spans.
            let prose: String = line.split('`').step_by(2).collect::<Vec<_>>().join(" ");
            let mut rest = prose.as_str();
            while let Some(i) = rest.find("](") {
                rest = &rest[i + 2..];
                let Some(j) = rest.find(')') else { break };
                let target = &rest[..j];
                rest = &rest[j..];
                if target.contains("://") || target.starts_with("mailto:") {
                    continue;
                }
                let (path, anchor) = match target.split_once('#') {
                    Some((p, a)) => (p, Some(a)),
                    None => (target, None),
                };
                let dest = if path.is_empty() {
                    file.clone()
                } else {
                    file.parent().unwrap().join(path)
                };
                checked += 1;
                let at = format!("{}:{}: ({target})", file.display(), n + 1);
                if !dest.exists() {
                    bad.push(format!("{at}: no such file"));
                } else if let Some(a) = anchor {
                    let t = fs::read_to_string(&dest).unwrap_or_default();
                    if !anchors(&t).contains(a) {
                        bad.push(format!("{at}: no anchor #{a}"));
                    }
                }
            }
        }
    }
    assert!(checked >= 20, "only {checked} links found");
    assert!(bad.is_empty(), "broken links:\n{}", bad.join("\n"));
}
