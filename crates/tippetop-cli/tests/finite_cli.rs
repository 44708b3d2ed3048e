//! Issue 26, "finite or failed", end to end: a run that exits 0 has no
//! value in its trajectory that is not a finite number; a run whose output
//! row is not finite exits 3 with `failure = "non_finite"` and the rows
//! before it. The reproducer of the issue (a fast spin whose attitude went
//! NaN while the run said ok), and a NaN planted in `qw` from a given time
//! (`TIPPETOP_TEST_NAN_ROW_AT`, `tippetop::testing`).

use std::path::Path;
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tippetop"))
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// The data rows of a trajectory.csv, parsed (`NaN` parses to NaN).
fn rows(p: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse::<f64>().unwrap()).collect())
        .collect();
    (header, rows)
}

/// The reproducer: `run --preset classical --set initial.spin=1e6
/// --set solver.t_end=2` exited 0 with `qw..qz` NaN in 236 of 1001 rows;
/// `animate` then refused the run. Now: exit 0, every value finite, the
/// quaternion unit to 4 ulp, and `animate` draws it.
#[test]
fn fast_spin_runs_finite_and_animates() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("q");
    let o = bin()
        .args(["run", "--preset", "classical", "--set", "initial.spin=1e6"])
        .args(["--set", "solver.t_end=2", "--no-plot", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(json(&out.join("summary.json"))["status"], "ok");
    let (header, rows) = rows(&out.join("trajectory.csv"));
    assert_eq!(rows.len(), 1001);
    let qw = header.iter().position(|c| c == "qw").unwrap();
    for (i, r) in rows.iter().enumerate() {
        assert!(r.iter().all(|v| v.is_finite()), "row {i}: {r:?}");
        let n = r[qw..qw + 4].iter().map(|v| v * v).sum::<f64>().sqrt();
        assert!((n - 1.0).abs() <= 4.0 * f64::EPSILON, "row {i}: |q| = {n}");
    }
    let o = bin()
        .args([
            "animate",
            "--fps",
            "2",
            "--duration",
            "1",
            "--size",
            "64x64",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(out.join("animation.gif").exists());
}

/// A NaN planted in `qw` from t = 0.5 s of a 1 s classical run (1001 rows):
/// exit 3, one line on stderr naming the failure, summary.json `status` not
/// ok with `failure = "non_finite"` at 0.5 s, and trajectory.csv the 500
/// rows before 0.5 s, all finite. The same run without the plant: exit 0.
#[test]
fn a_planted_nan_row_exits_3_with_the_rows_before_it() {
    let dir = tempfile::tempdir().unwrap();
    for model in ["vector", "reduced", "rigid"] {
        let out = dir.path().join(model);
        let model_set = format!("solver.model=\"{model}\"");
        let go = |plant: bool| {
            let mut c = bin();
            c.args(["run", "--preset", "classical", "--set", "solver.t_end=1"])
                .args(["--set", &model_set, "--no-plot", "--quiet", "--out"])
                .arg(&out);
            if plant {
                c.env("TIPPETOP_TEST_NAN_ROW_AT", "0.5");
            }
            c.output().unwrap()
        };
        let o = go(false);
        assert_eq!(o.status.code(), Some(0), "{model}");
        let o = go(true);
        let err = String::from_utf8(o.stderr).unwrap();
        assert_eq!(o.status.code(), Some(3), "{model}: {err}");
        assert_eq!(err.lines().count(), 1, "{model}: {err}");
        // The planted time, 0.5 s, with 4 significant figures (tippetop::human).
        assert!(
            err.starts_with("error: run failed at t = 0.5000 s"),
            "{err}"
        );
        assert!(err.contains("NaN in column qw"), "{err}");
        let s = json(&out.join("summary.json"));
        assert_eq!(s["failure"], "non_finite", "{model}");
        assert_ne!(s["status"], "ok");
        assert_eq!(s["t_end"].as_f64(), Some(0.5), "{model}");
        let (_, rows) = rows(&out.join("trajectory.csv"));
        assert_eq!(rows.len(), 500, "{model}");
        assert!(
            rows.iter()
                .all(|r| r[0] < 0.5 && r.iter().all(|v| v.is_finite()))
        );
    }
}

/// Sweep and ensemble rows obey the same rule: with the NaN planted every
/// case's and run's status is the failure (the commands go on: exit 0),
/// and no field of their rows is NaN.
#[test]
fn planted_nan_rows_fail_sweep_and_ensemble_rows() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("sweep");
    let o = bin()
        .env("TIPPETOP_TEST_NAN_ROW_AT", "0.01")
        .args([
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.02",
        ])
        .args([
            "--set",
            "solver.samples=11",
            "--vary",
            "surface.friction=0.1:0.2:3",
        ])
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(out.join("sweep.csv")).unwrap();
    assert_eq!(text.lines().count(), 4);
    for line in text.lines().skip(1) {
        // A sweep's runs compute no pose: the NaN is planted in `J`.
        assert!(line.contains("NaN in column J"), "{line}");
        assert!(!line.split(',').any(|f| f == "NaN"), "{line}");
    }
    let out = dir.path().join("ens");
    let o = bin()
        .env("TIPPETOP_TEST_NAN_ROW_AT", "5e-12")
        .args(["ensemble", "scenarios/thermal.toml", "--runs", "2"])
        .args(["--set", "solver.t_end=1e-11", "--set", "solver.samples=11"])
        .args(["--quiet", "--out"])
        .arg(&out)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(out.join("ensemble.csv")).unwrap();
    assert_eq!(text.lines().count(), 3);
    for line in text.lines().skip(1) {
        assert!(line.contains("NaN in column qw"), "{line}");
        assert!(!line.split(',').any(|f| f == "NaN"), "{line}");
    }
    assert_eq!(json(&out.join("summary.json"))["failed"], 2);
}
