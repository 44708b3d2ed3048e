//! Trust, round 3, end to end: a bit whose runs blew up is reported as a
//! blow-up, with no minimum over its failed runs and no `ok` row
//! (bitmap.csv, bit.json and bit.md alike); a Wilson bound of 0 successes
//! is 0; `tippetop stability` refuses a friction law it does not linearise
//! and names the plug-in key that was set.

mod common;
use common::{bin, json, ok, refused, repo};

use std::path::Path;

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("trust3-bit", name)
}

/// The room-temperature bit under a write force 1e16 times the paper's:
/// every run's state blows up within 60 ps (the unit axis reached
/// |k| = 1.3e45, the spin 5.8e118 rad/s, where the run used to end as a
/// "Painleve paradox").
const BLOWN: [&str; 4] = ["--set", "thermal.seed=0", "--set", "write.0.hx=1e-6"];

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

/// A field that is a number but not a finite one, or spelled like one.
fn non_finite(f: &str) -> bool {
    f.parse::<f64>().is_ok_and(|v| !v.is_finite())
        || ["inf", "-inf", "nan", "infinity"].contains(&f.to_ascii_lowercase().as_str())
}

/// The design map of the audit: both points' runs blew up. No row is
/// `ok`, no field is a non-finite number, the smallest pull-off margin (a
/// minimum over failed runs) is empty, and the status says what happened:
/// the state blew up, when, and not a Painlevé case.
#[test]
fn a_blown_up_map_has_no_ok_row_and_no_minimum() {
    let d = scratch("map");
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_300K.toml"))
        .args(&BLOWN[..2])
        .args(["--vary", "write.0.hx=1e-6:2e-5:2", "--out"])
        .arg(d.join("o"))
        .output()
        .unwrap();
    ok(&o);
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(stdout.contains("2 points (0 ok"), "{stdout}");
    let (header, rows) = csv(&d.join("o/bitmap.csv"));
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    assert_eq!(rows.len(), 2);
    for r in &rows {
        assert_eq!(r.len(), header.len());
        for (h, v) in header.iter().zip(r) {
            assert!(!non_finite(v), "{h} = {v}");
        }
        assert_eq!(r[col("pull_off_margin_min")], "", "{r:?}");
        assert_eq!(r[col("write_run_failed")], "100", "{r:?}");
        let status = &r[col("status")];
        assert_ne!(status, "ok");
        assert!(
            status.starts_with("100 of 100 runs failed") && status.contains("blew up"),
            "{status}"
        );
        assert!(!status.contains("Painleve"), "{status}");
        assert!(!status.contains('\n'), "{status}");
    }
}

/// The single bit of the map's first point: every run's status in runs.csv
/// names the blow-up (the unit axis's |k|, the time), none a Painlevé
/// case; bit.json's margin is null and bit.md says the same in words (no
/// `-inf N`); runs.csv holds no non-finite number.
#[test]
fn a_blown_up_bit_says_so_alike_in_every_output() {
    let d = scratch("one");
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_300K.toml"))
        .args(BLOWN)
        .arg("--out")
        .arg(d.join("o"))
        .output()
        .unwrap();
    ok(&o);
    let j = json(&d.join("o/bit.json"));
    assert!(
        j["pull_off_margin_min"].is_null(),
        "{}",
        j["pull_off_margin_min"]
    );
    assert_eq!(j["write"]["failures"]["run_failed"], 100);
    let md = std::fs::read_to_string(d.join("o/bit.md")).unwrap();
    assert!(!md.contains("inf"), "{md}");
    assert!(
        md.contains("Smallest pull-off margin over the runs: none (no run completed)."),
        "{md}"
    );
    let (header, rows) = csv(&d.join("o/runs.csv"));
    let status = header.iter().position(|h| h == "status").unwrap();
    assert_eq!(rows.len(), 100);
    for r in &rows {
        for (h, v) in header.iter().zip(r) {
            assert!(!non_finite(v), "run {}: {h} = {v}", r[0]);
        }
        let s = &r[status];
        assert!(s.starts_with("at t = "), "{s}");
        assert!(s.contains("the state blew up: the symmetry axis k"), "{s}");
        assert!(s.contains("|k| = "), "{s}");
        assert!(!s.contains("Painleve"), "{s}");
    }
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
        // The interval is the question here, not the step.
        .args(["--runs", "7", "--no-step-check", "--out"])
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

/// A scenario under Coulomb–Contensou friction over a disc (a drilling
/// torque the linearised model does not have): refused naming the law,
/// exit 2, one line, nothing printed on stdout.
#[test]
fn stability_refuses_a_law_it_does_not_linearise() {
    for args in [
        vec![
            "--preset",
            "classical",
            "--set",
            "surface.friction_law=\"contensou\"",
            "--set",
            "surface.contact_radius=1e-4",
        ],
        vec![
            "--preset",
            "classical",
            "--set",
            "surface.friction_law=\"contensou_pade\"",
            "--set",
            "surface.contact_radius=1e-4",
        ],
    ] {
        let o = bin()
            .arg("stability")
            .args(&args)
            .arg("--no-run")
            .output()
            .unwrap();
        refused(&o, &["surface.friction_law", "contensou", "drilling"]);
        assert!(o.stdout.is_empty(), "{args:?}");
    }
    let o = bin()
        .arg("stability")
        .arg(repo("scenarios/toy_with_stem.toml"))
        .arg("--no-run")
        .output()
        .unwrap();
    refused(&o, &["surface.friction_law", "\"contensou\""]);
    // The disc of radius 0 is the point law, exact Coulomb bit for bit:
    // analysed as Coulomb is.
    let o = bin()
        .args(["stability", "--preset", "classical", "--no-run", "--set"])
        .arg("surface.friction_law=\"contensou\"")
        .args(["--set", "surface.contact_radius=0"])
        .output()
        .unwrap();
    ok(&o);
}

/// A scenario under the viscous law: analysed with that law and its ε,
/// never the regularised law with the viscous law's ε; asking for the
/// other smooth law without an ε of its own is refused naming both.
#[test]
fn stability_never_takes_one_laws_eps_for_another() {
    let viscous = [
        "--preset",
        "classical",
        "--no-run",
        "--set",
        "surface.friction_law=\"viscous\"",
        "--set",
        "surface.friction_eps=1e-2",
    ];
    let o = bin().arg("stability").args(viscous).output().unwrap();
    ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    let first = out.lines().next().unwrap();
    assert!(
        first.contains("linearised with the viscous friction law (ε = 0.01000 m/s"),
        "{first}"
    );
    let o = bin()
        .arg("stability")
        .args(viscous)
        .args(["--law", "regularized"])
        .output()
        .unwrap();
    refused(&o, &["law: regularized", "\"viscous\"", "--eps"]);
    // With an ε of its own, the other law is what was asked.
    let o = bin()
        .arg("stability")
        .args(viscous)
        .args(["--law", "regularized", "--eps", "2e-3"])
        .output()
        .unwrap();
    ok(&o);
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(
        out.lines()
            .next()
            .unwrap()
            .contains("linearised with the regularized friction law (ε = 0.002000 m/s"),
        "{out}"
    );
}

/// A plug-in table the analysis does not model is refused naming the key
/// that was set, not the table's first key.
#[test]
fn stability_names_the_plugin_key_that_was_set() {
    for (set, named, not) in [
        ("wind.fy=1", "wind.fy", "wind.fx"),
        ("wind.fx=1", "wind.fx", "wind.fy"),
    ] {
        let o = bin()
            .args([
                "stability",
                "--preset",
                "classical",
                "--no-run",
                "--set",
                set,
            ])
            .output()
            .unwrap();
        refused(&o, &[named]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!err.contains(not), "{err}");
        assert!(o.stdout.is_empty());
    }
}
