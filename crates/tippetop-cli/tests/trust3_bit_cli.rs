//! Trust, round 3, end to end: a Wilson bound of 0 successes is 0.

mod common;
use common::{bin, json, ok, repo};

use std::path::Path;

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("trust3-bit", name)
}

/// The fields of a CSV line (a quoted field may hold commas and `""`).
fn fields(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut chars = line.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '"' if quoted && chars.peek() == Some(&'"') => {
                cur.push('"');
                chars.next();
            }
            '"' => quoted = !quoted,
            ',' if !quoted => out.push(std::mem::take(&mut cur)),
            _ => cur.push(c),
        }
    }
    out.push(cur);
    out
}

/// The header and rows of a CSV file.
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = fields(lines.next().unwrap());
    (header, lines.map(fields).collect())
}

/// 0 successes of 7 runs (nothing erases at 300 K; 7 is a count where
/// `centre − half` left 2.78e-17): the Wilson lower bound is 0 exactly in
/// bit.json, bitmap.csv and bit.md, and 7 of 7 has the upper bound 1.
#[test]
fn the_wilson_bound_of_no_success_is_zero() {
    let d = scratch("wilson");
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_300K.toml"))
        .args(["--runs", "7", "--out"])
        .arg(d.join("one"))
        .output()
        .unwrap();
    ok(&o);
    let j = json(&d.join("one/bit.json"));
    assert_eq!(j["erase"]["successes"], 0);
    assert_eq!(j["erase"]["ci95"][0].as_f64(), Some(0.0), "{}", j["erase"]);
    assert_eq!(j["write"]["successes"], 7);
    assert_eq!(j["write"]["ci95"][1].as_f64(), Some(1.0), "{}", j["write"]);
    let md = std::fs::read_to_string(d.join("one/bit.md")).unwrap();
    assert!(md.contains("P = 0 [0, 0.354] (0 of 7 runs)"), "{md}");
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_300K.toml"))
        .args(["--runs", "7", "--vary", "write.0.hx=1e-22:2e-22:2", "--out"])
        .arg(d.join("map"))
        .output()
        .unwrap();
    ok(&o);
    let (header, rows) = csv(&d.join("map/bitmap.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    for r in &rows {
        assert_eq!(r[col("erase_successes")], "0");
        assert_eq!(r[col("erase_ci_lo")], "0.0", "{r:?}");
        assert_eq!(r[col("write_ci_hi")], "1.0", "{r:?}");
    }
}
