//! Issue 12 (hardening), end to end: extreme input is exit 2 with one line
//! and nothing written, never a panic; runs that cannot make progress stop
//! with exit 3; `stability` checks its own arguments first.

use std::path::Path;

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

/// Exit 2, exactly one stderr line `error: KEY...`, nothing on stdout,
/// `out` (if given) not created.
fn expect_input_error(args: &[&str], out: Option<&Path>, key: &str) {
    let a = tippetop().args(args).assert();
    let o = a.get_output();
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{args:?}: {stderr:?}");
    assert!(
        lines[0].starts_with(&format!("error: {key}: ")),
        "{args:?}: {stderr:?}"
    );
    assert!(o.stdout.is_empty(), "{args:?}");
    if let Some(out) = out {
        assert!(!out.exists(), "{args:?}: {} was created", out.display());
    }
}

/// Defect 1: values that used to panic in the solver are input errors, for
/// every model and method.
#[test]
fn run_rejects_extreme_values_without_panic() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    for (preset, set, key) in [
        ("classical", "solver.t_end=1e308", "solver.t_end"),
        ("nano", "solver.t_end=1e-320", "solver.t_end"),
        ("classical", "surface.gravity=1e308", "surface.gravity"),
        ("nano", "top.mass=1e-320", "force.0.hx"),
        ("classical", "initial.spin=-1e308", "solver.t_end"),
        ("nano", "initial.spin=1e308", "solver.t_end"),
        ("classical", "solver.samples=1000000000", "solver.samples"),
        (
            "nano",
            "solver.samples=4611686018427387904",
            "solver.samples",
        ),
    ] {
        for model in ["vector", "reduced", "rigid"] {
            for method in ["adaptive", "rk4", "stiff"] {
                let m = format!("solver.model={model}");
                let me = format!("solver.method={method}");
                expect_input_error(
                    &[
                        "run",
                        "--preset",
                        preset,
                        "--set",
                        set,
                        "--set",
                        &m,
                        "--set",
                        &me,
                        "--no-plot",
                        "--out",
                        o,
                    ],
                    Some(&out),
                    key,
                );
            }
        }
    }
}

/// Defect 3: a run that reaches its step limit stops with exit 3, says so,
/// and writes what it computed.
#[test]
fn step_limit_is_exit_3_with_results() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let a = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.max_steps=200",
        ])
        .args([
            "--set",
            "solver.method=stiff",
            "--no-plot",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .assert()
        .code(3);
    let stderr = String::from_utf8_lossy(&a.get_output().stderr).to_string();
    assert!(
        stderr.contains("step limit 200 reached (the run cannot make progress"),
        "{stderr}"
    );
    assert!(out.join("summary.json").exists());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("step limit 200"), "{summary}");
}

/// Defect 10: rk4 alone runs on both presets.
#[test]
fn rk4_runs_on_both_presets() {
    let dir = tempfile::tempdir().unwrap();
    for p in ["nano", "classical"] {
        tippetop()
            .args(["run", "--preset", p, "--set", "solver.method=rk4"])
            .args(["--no-plot", "--quiet", "--out"])
            .arg(dir.path().join(p))
            .assert()
            .success();
    }
}

/// Defect 8: `stability` rejects bad --spin, --eps, --tol (exit 2, one
/// line, before "running the scenario ..."), and bad scenario values.
#[test]
fn stability_checks_its_arguments_first() {
    for (args, key) in [
        (vec!["--spin", "nan"], "spin"),
        (vec!["--spin", "inf"], "spin"),
        (vec!["--spin", "1e308"], "spin"),
        (vec!["--spin=-1e200"], "spin"),
        (vec!["--eps", "0"], "eps"),
        (vec!["--eps", "-1"], "eps"),
        (vec!["--eps", "1e308"], "eps"),
        (vec!["--tol=-1"], "tol"),
        (vec!["--tol", "2"], "tol"),
        (vec!["--tol", "nan"], "tol"),
        (vec!["--set", "solver.t_end=1e308"], "solver.t_end"),
        (vec!["--set", "top.mass=1e-320"], "top.mass"),
    ] {
        let mut all = vec!["stability", "--preset", "classical"];
        all.extend(args);
        expect_input_error(&all, None, key);
    }
}

/// Defect 8 / 10: `stability --help` has examples, the output and the exit
/// codes.
#[test]
fn stability_help_is_complete() {
    let a = tippetop().args(["stability", "--help"]).assert().success();
    let help = String::from_utf8_lossy(&a.get_output().stdout).to_string();
    for needle in [
        "Examples:",
        "tippetop stability --preset classical",
        "Output (stdout",
        "Exit codes: 0",
        "2 bad input",
        "3 the analysis",
        "|spin| <= 1e100",
        "0 <= TOL < 1",
    ] {
        assert!(help.contains(needle), "{needle:?} missing:\n{help}");
    }
}
