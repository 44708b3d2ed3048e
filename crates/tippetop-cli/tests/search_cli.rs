//! `tippetop bit --search` end to end (issue #16 item 5): a search on the
//! paper's nano top finds a write that works, its best.toml run by
//! `tippetop bit` gives the same figures bit for bit, the files are
//! consistent, and bad input exits 2 with one line naming the key and
//! nothing written.

mod common;
use common::{bin, json, repo};

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("search-cli", name)
}

use std::path::Path;

#[test]
fn search_finds_a_write_and_best_toml_reproduces_it() {
    let d = scratch("found");
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_search.toml"))
        .args([
            "--search",
            "--set",
            "search.budget=12",
            "--set",
            "search.perturbations=3",
            "--quiet",
            "--out",
        ])
        .arg(d.join("s"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = json(&d.join("s/search.json"));
    assert_eq!(s["found"], true, "{s}");
    assert_eq!(s["evaluations"], 12);
    let ev = &s["best"]["evaluation"];
    assert_eq!(ev["success_with_margin"], true);
    // evaluations.csv: a header and one row per evaluation.
    let csv = std::fs::read_to_string(d.join("s/evaluations.csv")).unwrap();
    assert_eq!(csv.lines().count(), 13);
    // The merit is the switching time over the phase (weight 0).
    let merit = ev["merit"].as_f64().unwrap();
    let best_rows: Vec<&str> = csv
        .lines()
        .skip(1)
        .filter(|l| l.contains(&format!(",{merit},")))
        .collect();
    assert!(
        !best_rows.is_empty(),
        "best merit {merit} not among the evaluations"
    );
    // Rerun best.toml with plain `tippetop bit`: the same write, bit for bit.
    let o = bin()
        .arg("bit")
        .arg(d.join("s/best.toml"))
        .args(["--quiet", "--out"])
        .arg(d.join("b"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = json(&d.join("b/bit.json"));
    assert_eq!(b["write"]["successes"], 1);
    assert_eq!(b["write"]["time_median"], ev["time"], "{b}");
    assert_eq!(b["write"]["energy_median"], ev["energy"], "{b}");
    // The protocol in best.toml is the reported one.
    let p = &s["best"]["protocol"][0];
    assert_eq!(
        b["write"]["max_applied_force"].as_f64().unwrap().to_bits(),
        {
            let (hx, hy) = (p["hx"].as_f64().unwrap(), p["hy"].as_f64().unwrap());
            hx.hypot(hy).to_bits()
        }
    );
    // Same input, same bytes.
    let o = bin()
        .arg("bit")
        .arg(repo("scenarios/bit/nano_search.toml"))
        .args([
            "--search",
            "--set",
            "search.budget=12",
            "--set",
            "search.perturbations=3",
            "--quiet",
            "--out",
        ])
        .arg(d.join("s2"))
        .output()
        .unwrap();
    assert!(o.status.success());
    for f in ["search.json", "evaluations.csv", "best.toml"] {
        assert_eq!(
            std::fs::read(d.join("s").join(f)).unwrap(),
            std::fs::read(d.join("s2").join(f)).unwrap(),
            "{f}"
        );
    }
}

/// Search `file` with `sets` into `d/s`, check it found a protocol of
/// `kind` whose best.toml holds a `kind` window with `key` (`"force"`,
/// `"field"`), rerun best.toml into `d/b`, and check the rerun's `phase`
/// figures are the search's best evaluation bit for bit. Returns
/// search.json.
fn search_and_rerun(
    d: &Path,
    file: &str,
    sets: &[&str],
    kind: &str,
    key: &str,
    phase: &str,
) -> serde_json::Value {
    let mut args = vec!["--search"];
    for s in sets {
        args.extend(["--set", s]);
    }
    let o = bin()
        .arg("bit")
        .arg(repo(file))
        .args(&args)
        .args(["--quiet", "--out"])
        .arg(d.join("s"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let s = json(&d.join("s/search.json"));
    assert_eq!(s["found"], true, "{s}");
    assert_eq!(s["search"]["actuator"], kind);
    let best = std::fs::read_to_string(d.join("s/best.toml")).unwrap();
    assert!(
        best.contains(&format!("kind = \"{kind}\"")) && best.contains(&format!("{key} = [")),
        "{best}"
    );
    let o = bin()
        .arg("bit")
        .arg(d.join("s/best.toml"))
        .args(["--quiet", "--out"])
        .arg(d.join("b"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let b = json(&d.join("b/bit.json"));
    let ev = &s["best"]["evaluation"];
    assert_eq!(b["write"]["successes"], 1);
    assert_eq!(b[phase]["successes"], 1);
    assert_eq!(b[phase]["time_median"], ev["time"]);
    assert_eq!(b[phase]["energy_median"], ev["energy"]);
    s
}

/// A search over a physical actuator: a tip at the top of the nano top
/// (scenarios/bit/nano_tip_search.toml). It finds a write; the best.toml
/// it writes has a tip window and reruns it bit for bit.
#[test]
fn tip_search_finds_a_push_and_best_toml_reproduces_it() {
    let d = scratch("tip");
    search_and_rerun(
        &d,
        "scenarios/bit/nano_tip_search.toml",
        &["search.perturbations=2"],
        "tip",
        "force",
        "write",
    );
}

/// A uniform field on a moment along the axis erases where the paper's
/// reversed force does not (physics.md#search); the best protocol reruns
/// bit for bit from best.toml, as a `kind = "magnetic"` window whose field
/// lies in the lab X-Z plane at the found polar angle.
#[test]
fn magnetic_search_finds_an_erase_and_best_toml_reproduces_it() {
    let d = scratch("magnetic");
    let s = search_and_rerun(
        &d,
        "scenarios/bit/nano_magnetic_search.toml",
        &["search.budget=40", "search.perturbations=2"],
        "magnetic",
        "field",
        "erase",
    );
    assert_eq!(s["search"]["moment"], 2.78220302349e-23);
    let w = &s["best"]["protocol"][0];
    let (m, a) = (
        w["magnitude"].as_f64().unwrap(),
        w["angle"].as_f64().unwrap(),
    );
    let (bx, bz) = (w["bx"].as_f64().unwrap(), w["bz"].as_f64().unwrap());
    assert!((bx - m * a.sin()).abs() <= 1e-15 * m && (bz - m * a.cos()).abs() <= 1e-15 * m);
}

fn expect_input_error(d: &Path, text: &str, extra: &[&str], key: &str) {
    std::fs::write(d.join("bad.toml"), text).unwrap();
    let out = d.join("out");
    let o = bin()
        .arg("bit")
        .arg(d.join("bad.toml"))
        .arg("--search")
        .args(extra)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{key}: {err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with(&format!("error: {key}")), "{key}: {err}");
    assert!(!out.exists(), "{key}: wrote {}", out.display());
}

const BASE: &str = "preset = \"nano\"\n[solver]\nsamples = 201\n[bit]\nhold = 2e-5\nphase = 1e-4\n";
const SEARCH: &str = "[search]\nmagnitude = [0.0, 4e-22]\nangle = [-3.0, 3.0]\nstart = [0.0, 5e-5]\nduration = [1e-6, 1e-4]\nbudget = 5\n";

#[test]
fn bad_search_input_names_the_key() {
    let d = scratch("bad");
    // --search without [search].
    expect_input_error(&d, BASE, &[], "search");
    // A missing bound.
    let no_mag = SEARCH.replace("magnitude = [0.0, 4e-22]\n", "");
    expect_input_error(&d, &format!("{BASE}{no_mag}"), &[], "search.magnitude");
    // Bounds reversed, a start past the phase, a zero duration.
    expect_input_error(
        &d,
        &format!("{BASE}{}", SEARCH.replace("[-3.0, 3.0]", "[3.0, -3.0]")),
        &[],
        "search.angle",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{}", SEARCH.replace("[0.0, 5e-5]", "[0.0, 2e-4]")),
        &[],
        "search.start",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{}", SEARCH.replace("[1e-6, 1e-4]", "[0.0, 1e-4]")),
        &[],
        "search.duration",
    );
    // Unknown key, unknown actuator, a margin wider than the window.
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}speed = 1\n"),
        &[],
        "search.speed",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}actuator = \"laser\"\n"),
        &[],
        "search.actuator",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}margin = 0.4\n"),
        &[],
        "search.margin",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{}", SEARCH.replace("budget = 5", "budget = 0")),
        &[],
        "search.budget",
    );
    // A tip needs its point; a contact window takes none.
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}actuator = \"tip\"\n"),
        &[],
        "search.point",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}point = [0.0, 0.0, 1e-10]\n"),
        &[],
        "search.point",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}actuator = \"tip\"\npoint = [0.0, 1e-10]\n"),
        &[],
        "search.point",
    );
    // A magnet needs a non-zero moment; other actuators take none.
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}actuator = \"magnetic\"\n"),
        &[],
        "search.moment",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}actuator = \"magnetic\"\nmoment = 0.0\n"),
        &[],
        "search.moment",
    );
    expect_input_error(
        &d,
        &format!("{BASE}{SEARCH}moment = 1e-23\n"),
        &[],
        "search.moment",
    );
}
