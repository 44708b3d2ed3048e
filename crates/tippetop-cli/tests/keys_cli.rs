//! `tippetop keys`: the listing against the validator's own key lists and
//! units (an independent source: its error messages), docs/keys.md kept
//! current, and a force plug-in's bad input through the CLI.

use std::fs;
use std::path::Path;

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

fn stdout(args: &[&str]) -> String {
    let out = tippetop().args(args).output().unwrap();
    assert!(out.status.success(), "{args:?}: {out:?}");
    String::from_utf8(out.stdout).unwrap()
}

/// `(code, one line of stderr)` of `tippetop run --preset classical --set SET`.
fn run_error(set: &str, dir: &Path) -> (Option<i32>, String) {
    let out = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--no-plot",
            "--set",
            set,
            "--out",
        ])
        .arg(dir)
        .output()
        .unwrap();
    (out.status.code(), String::from_utf8(out.stderr).unwrap())
}

/// docs/keys.md is what `tippetop keys --markdown` prints.
#[test]
fn docs_keys_md_is_current() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../docs/keys.md");
    let committed = fs::read_to_string(&path).unwrap_or_default();
    let now = stdout(&["keys", "--markdown"]);
    assert!(
        committed == now,
        "docs/keys.md is stale: regenerate it with `cargo run -p tippetop-cli -- keys --markdown > docs/keys.md`"
    );
}

/// `tippetop keys surface` lists exactly the keys the validator accepts in
/// `[surface]` (from its unknown-key error), each with the unit its range
/// message states; an unknown table is one line and exit code 2.
#[test]
fn keys_lists_the_validators_keys_with_their_units() {
    let dir = std::env::temp_dir().join("tippetop-keys-never-written");
    for table in ["surface", "wind", "solver"] {
        let (code, err) = run_error(&format!("{table}.no_such_key=1"), &dir);
        assert_eq!(code, Some(2), "{err}");
        let valid: Vec<String> = err
            .split("valid keys: ")
            .nth(1)
            .unwrap()
            .trim_end()
            .trim_end_matches(')')
            .split(", ")
            .map(str::to_string)
            .collect();
        let listing = stdout(&["keys", table]);
        let lines: Vec<&str> = listing.lines().skip(1).collect();
        let listed: Vec<String> = lines
            .iter()
            .map(|l| l.split_whitespace().next().unwrap().to_string())
            .collect();
        assert_eq!(listed, valid, "{table}");
        for l in lines {
            let mut words = l.split_whitespace();
            let (key, unit) = (words.next().unwrap(), words.next().unwrap());
            // The range in parentheses states the unit as `[unit]`.
            let range = &l[l.rfind("  (").unwrap()..];
            if !matches!(unit, "1" | "-") {
                assert!(range.contains(&format!("[{unit}]")), "{table}.{key}: {l}");
            } else {
                assert!(
                    !range.contains(" [m") && !range.contains(" [N]"),
                    "{table}.{key}: {l}"
                );
            }
        }
    }
    assert!(stdout(&["keys", "surface"]).starts_with("[surface]"));
    let out = tippetop().args(["keys", "nope"]).output().unwrap();
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: keys: unknown table \"nope\""),
        "{err}"
    );
    assert!(err.contains("wind"), "{err}");
}

/// A force plug-in's bad input (NaN, out of range, unknown key in
/// `[wind]`, a model that cannot apply it) is one line naming the key and
/// the range, exit code 2, nothing written.
#[test]
fn bad_wind_is_one_line_exit_2_nothing_written() {
    let root = tempfile::tempdir().unwrap();
    for (set, want) in [
        (
            "wind.fx=nan",
            "error: wind.fx: NaN is not allowed (-1000 <= f <= 1000 [N], lab frame)",
        ),
        (
            "wind.fx=1e4",
            "error: wind.fx: 10000 is not allowed (-1000 <= f <= 1000 [N], lab frame)",
        ),
        (
            "wind.gust=1",
            "error: wind.gust: unknown key (valid keys: fx, fy)",
        ),
    ] {
        let dir = root.path().join("out");
        let (code, err) = run_error(set, &dir);
        assert_eq!(code, Some(2), "{set}: {err}");
        assert_eq!(err.trim_end(), want, "{set}");
        assert!(!dir.exists(), "{set}: wrote {}", dir.display());
    }
    let dir = root.path().join("out");
    let out = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--no-plot",
            "--set",
            "wind.fx=1e-3",
        ])
        .args(["--set", "solver.model=\"reduced\"", "--out"])
        .arg(&dir)
        .output()
        .unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(
        err.trim_end(),
        "error: wind: [wind] is not available in model = \"reduced\" ([wind] needs model = \"vector\" (the default) or \"rigid\")"
    );
    assert!(!dir.exists());
}
