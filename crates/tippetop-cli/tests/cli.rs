//! End-to-end tests of the `tippetop` binary: help texts, exit codes, the
//! one-line error contract, and (once `simulate` lands) the files a run
//! writes.

use std::fs;
use std::path::Path;

use assert_cmd::Command;
use predicates::prelude::*;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

/// Run with `args`, expect exit `code`, exactly one stderr line starting
/// `error: ` (and containing `needle`), and `out` not created.
fn expect_input_error(args: &[&str], out: &Path, needle: &str) {
    let assert = tippetop().args(args).assert().code(2);
    let stderr = String::from_utf8(assert.get_output().stderr.clone()).unwrap();
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "stderr: {stderr:?}");
    assert!(lines[0].starts_with("error: "), "{stderr:?}");
    assert!(lines[0].contains(needle), "{stderr:?} lacks {needle:?}");
    assert!(!out.exists(), "{} was created", out.display());
}

#[test]
fn help_has_description_and_example() {
    for args in [
        vec!["--help"],
        vec!["run", "--help"],
        vec!["reproduce", "--help"],
        vec!["help", "run"],
    ] {
        tippetop()
            .args(&args)
            .assert()
            .success()
            .stdout(predicate::str::contains("Example"))
            .stdout(predicate::str::contains("tippetop "));
    }
    tippetop()
        .args(["run", "--help"])
        .assert()
        .stdout(predicate::str::contains("trajectory.csv"))
        .stdout(predicate::str::contains("--set"))
        .stdout(predicate::str::contains("--no-plot"))
        .stdout(predicate::str::contains("--quiet"));
    tippetop()
        .args(["reproduce", "--help"])
        .assert()
        .stdout(predicate::str::contains("--extended"))
        .stdout(predicate::str::contains("--out"));
    // The long help of sweep and merge (their variants' one-line doc
    // comments used to hide it): what the files hold, and the models.
    tippetop()
        .args(["sweep", "--help"])
        .assert()
        .stdout(predicate::str::contains("rhs_evaluations, status"))
        .stdout(predicate::str::contains("solver.model=reduced"));
    tippetop()
        .args(["merge", "--help"])
        .assert()
        .stdout(predicate::str::contains("byte for byte"));
    tippetop()
        .args(["run", "--help"])
        .assert()
        .stdout(predicate::str::contains("Models (solver.model)"));
}

#[test]
fn usage_errors_exit_2() {
    tippetop().assert().code(2);
    tippetop().args(["run"]).assert().code(2);
    tippetop().args(["run", "--bogus"]).assert().code(2);
    tippetop().args(["frobnicate"]).assert().code(2);
}

#[test]
fn unknown_preset_is_one_line_exit_2_and_touches_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    expect_input_error(
        &["run", "--preset", "bogus", "--out", o],
        &out,
        "error: preset: ",
    );
    // --quiet (anywhere) silences everything but the error.
    expect_input_error(
        &["--quiet", "run", "--preset", "bogus", "--out", o],
        &out,
        "preset",
    );
    expect_input_error(
        &["run", "-q", "--preset", "bogus", "--out", o],
        &out,
        "preset",
    );
}

#[test]
fn unreadable_scenario_file_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let missing = dir.path().join("missing.toml");
    expect_input_error(
        &[
            "run",
            missing.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        // Every command names the file (issue 26: one reader for all).
        &format!("error: {}: cannot read it", missing.display()),
    );
}

#[test]
fn malformed_set_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    expect_input_error(
        &[
            "run",
            "--preset",
            "nano",
            "--set",
            "top.radius",
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        "error: set: ",
    );
}

#[test]
fn out_that_is_a_file_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    fs::write(&out, "not a directory").unwrap();
    let assert = tippetop()
        .args(["run", "--preset", "nano", "--out", out.to_str().unwrap()])
        .assert()
        .code(2);
    let stderr = String::from_utf8(assert.get_output().stderr.clone()).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(stderr.starts_with("error: --out: "), "{stderr:?}");
    assert_eq!(fs::read_to_string(&out).unwrap(), "not a directory");
}

#[test]
fn out_of_range_set_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    expect_input_error(
        &[
            "run",
            "--preset",
            "nano",
            "--set",
            "top.radius=-1",
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        "error: top.radius: ",
    );
    expect_input_error(
        &[
            "run",
            "--preset",
            "classical",
            "--set",
            "top.no_such_key=1",
            "--out",
            out.to_str().unwrap(),
        ],
        &out,
        "no_such_key",
    );
}

#[test]
fn bad_scenario_file_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let bad = dir.path().join("bad.toml");
    fs::write(&bad, "preset = \"classical\"\n[top]\nradius = -0.01\n").unwrap();
    expect_input_error(
        &["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()],
        &out,
        "error: top.radius: ",
    );
    fs::write(&bad, "[top\nradius = \n").unwrap();
    expect_input_error(
        &["run", bad.to_str().unwrap(), "--out", out.to_str().unwrap()],
        &out,
        "error: ",
    );
}

#[test]
fn written_scenario_reproduces_the_run() {
    let dir = tempfile::tempdir().unwrap();
    let a = dir.path().join("a");
    let b = dir.path().join("b");
    tippetop()
        .args(["-q", "run", "--preset", "classical", "--no-plot"])
        .args(["--set", "solver.t_end=0.5", "--set", "solver.samples=51"])
        .args(["--out", a.to_str().unwrap()])
        .assert()
        .success();
    tippetop()
        .args(["-q", "run", "--no-plot"])
        .arg(a.join("scenario.toml"))
        .args(["--out", b.to_str().unwrap()])
        .assert()
        .success();
    assert_eq!(
        fs::read_to_string(a.join("trajectory.csv")).unwrap(),
        fs::read_to_string(b.join("trajectory.csv")).unwrap()
    );
}

#[test]
fn reproduce_out_is_a_file_is_input_error() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    fs::write(&out, "not a directory").unwrap();
    tippetop()
        .args(["reproduce", "--quiet", "--out", out.to_str().unwrap()])
        .assert()
        .code(2)
        .stderr(predicate::str::starts_with("error: --out: "));
    assert_eq!(fs::read_to_string(&out).unwrap(), "not a directory");
}

/// A short classical run: every file, the CSV header and round-trip floats,
/// the summary's fields, the human summary on stdout.
#[test]
fn run_classical_writes_everything() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let assert = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--out",
            out.to_str().unwrap(),
        ])
        .assert()
        .success();
    let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
    for word in ["theta", "J", "energy", "status", "wall time", "wrote"] {
        assert!(stdout.contains(word), "stdout lacks {word}: {stdout}");
    }
    for f in [
        "trajectory.csv",
        "summary.json",
        "scenario.toml",
        "theta.png",
        "theta.svg",
        "spin.png",
        "spin.svg",
        "diagnostics.png",
        "diagnostics.svg",
    ] {
        assert!(out.join(f).is_file(), "missing {f}");
    }
    // No temporary files left.
    for e in fs::read_dir(&out).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.ends_with(".tmp"), "{name}");
    }
    let csv = fs::read_to_string(out.join("trajectory.csv")).unwrap();
    let mut lines = csv.lines();
    assert_eq!(
        lines.next().unwrap(),
        tippetop::trajectory::COLUMNS.join(",")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|f| f.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 1001);
    assert_eq!(rows[0][0], 0.0);
    assert_eq!(rows[0][1], 0.1);
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["status"], "ok");
    assert_eq!(json["t_end"], 10.0);
    assert!(json["wall_seconds"].as_f64().unwrap() >= 0.0);
    assert!(json["scenario"].as_str().unwrap().contains("radius"));
    assert!(json["events"].is_array());
    assert_eq!(
        json["theta_final"].as_f64().unwrap(),
        *rows.last().unwrap().get(1).unwrap()
    );
}

#[test]
fn quiet_and_no_plot() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    tippetop()
        .args(["run", "--quiet", "--no-plot", "--preset", "classical"])
        .args(["--out", out.to_str().unwrap()])
        .assert()
        .success()
        .stdout(predicate::str::is_empty())
        .stderr(predicate::str::is_empty());
    assert!(out.join("trajectory.csv").is_file());
    assert!(!out.join("theta.png").exists());
}

#[test]
fn runtime_failure_exits_3_and_writes_partial_results() {
    // An RK4 run with far too few steps for a fast top blows up part-way;
    // the lead may swap in a scenario that fails more reliably.
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let assert = tippetop()
        .args(["run", "--preset", "classical", "--no-plot"])
        .args([
            "--set",
            "solver.method=\"rk4\"",
            "--set",
            "solver.steps=1000",
        ])
        .args(["--set", "initial.spin=1e6"])
        .args(["--out", out.to_str().unwrap()])
        .assert()
        .code(3);
    let stderr = String::from_utf8(assert.get_output().stderr.clone()).unwrap();
    assert_eq!(stderr.lines().count(), 1, "{stderr:?}");
    assert!(stderr.starts_with("error: "), "{stderr:?}");
    let json: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_ne!(json["status"], "ok");
    assert!(out.join("trajectory.csv").is_file());
}

/// `reproduce` on short windows writes every figure (PNG, SVG, CSV), the
/// report and claims.json.
#[test]
fn reproduce_quick_writes_every_figure_and_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("repro");
    tippetop()
        .args([
            "reproduce",
            "--quick",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ])
        .assert()
        .success();
    for n in [
        "02", "03", "04", "05", "06", "07", "08", "09", "10", "11", "12", "13", "14", "15",
    ] {
        for ext in ["png", "svg", "csv"] {
            let p = out.join(format!("fig{n}.{ext}"));
            assert!(p.is_file(), "missing {}", p.display());
            assert!(fs::metadata(&p).unwrap().len() > 100);
        }
        let csv = fs::read_to_string(out.join(format!("fig{n}.csv"))).unwrap();
        assert!(
            csv.starts_with("t,"),
            "fig{n}.csv header: {}",
            csv.lines().next().unwrap()
        );
    }
    let claims: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("claims.json")).unwrap()).unwrap();
    let claims = claims.as_array().unwrap();
    assert!(claims.len() >= 14);
    for c in claims {
        for key in [
            "id",
            "claim",
            "paper_value",
            "measured",
            "settings",
            "verdict",
            "why",
        ] {
            assert!(c.get(key).is_some(), "claim lacks {key}: {c}");
        }
        let v = c["verdict"].as_str().unwrap();
        assert!(["reproduced", "partly", "not reproduced"].contains(&v));
    }
    let report = fs::read_to_string(out.join("report.md")).unwrap();
    assert!(report.contains("Quick mode"));
    // No temporary files left behind.
    assert!(
        fs::read_dir(&out).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .ends_with(".tmp"))
    );
}

/// Every bad-input class, end to end: exit 2, one line naming the key, and
/// nothing written under --out.
#[test]
fn every_bad_input_class_is_one_line_exit_2_nothing_written() {
    let cases: &[(&[&str], &str)] = &[
        (&["--set", "top.radiuss=1"], "top.radiuss: unknown key"),
        (&["--set", "topp.radius=1"], "topp"),
        (&["--set", "surface.friction=\"abc\""], "surface.friction: "),
        (&["--set", "surface.friction=nan"], "surface.friction: "),
        (&["--set", "surface.gravity=inf"], "surface.gravity: "),
        (&["--set", "top.radius=0"], "top.radius: "),
        (&["--set", "top.mass=-1"], "top.mass: "),
        (&["--set", "top.offset=-0.001"], "top.offset: "),
        (&["--set", "top.offset=0.015"], "top.offset: "),
        (
            &["--set", "top.inertia_transverse=0"],
            "top.inertia_transverse: ",
        ),
        (&["--set", "top.inertia_axial=-1e-6"], "top.inertia_axial: "),
        (&["--set", "top.inertia_axial=3e-6"], "top.inertia_axial: "),
        (&["--set", "surface.friction=-0.1"], "surface.friction: "),
        (&["--set", "solver.t_end=0"], "solver.t_end: "),
        (&["--set", "solver.samples=1"], "solver.samples: "),
        (
            &[
                "--set",
                "force.0.hx=1",
                "--set",
                "force.0.start=1",
                "--set",
                "force.0.stop=0.5",
            ],
            "force.0.stop: ",
        ),
        (
            &["--set", "force.0.hx=1", "--set", "force.0.start=-1"],
            "force.0.start: ",
        ),
        (
            &["--set", "solver.model=reduced", "--set", "initial.theta=0"],
            "initial.theta: ",
        ),
        (&["--set", "initial.theta=3.2"], "initial.theta: "),
        (
            &["--set", "surface.friction_law=bogus"],
            "surface.friction_law: ",
        ),
        (&["--set", "surface.contact=bogus"], "surface.contact: "),
        (&["--set", "solver.method=bogus"], "solver.method: "),
        (&["--set", "solver.model=bogus"], "solver.model: "),
        (
            &["--set", "surface.friction_law=regularized"],
            "surface.friction_eps: ",
        ),
        (
            &["--set", "solver.method=rk4", "--set", "solver.steps=333"],
            "solver.steps: ",
        ),
    ];
    for (sets, needle) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("out");
        let mut args = vec![
            "run",
            "--preset",
            "classical",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(sets);
        expect_input_error(&args, &out, needle);
    }
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    expect_input_error(
        &["run", "--preset", "bogus", "--out", out.to_str().unwrap()],
        &out,
        "preset: ",
    );
}

/// `solver.model = "vector"` from the command line: the run writes its
/// outputs, starts from an upright top (θ = 0, which the Euler angles
/// refuse) and records the model in the echoed scenario; a bad model name
/// lists the three valid ones.
#[test]
fn vector_model_runs_from_upright_and_bad_model_lists_the_choices() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.model=vector",
            "--set",
            "initial.theta=0",
            "--set",
            "initial.theta_dot=10",
            "--set",
            "solver.t_end=0.2",
            "--no-plot",
            "--quiet",
            "--out",
            o,
        ])
        .assert()
        .code(0);
    let scen = std::fs::read_to_string(out.join("scenario.toml")).unwrap();
    assert!(scen.contains("model = \"vector\""), "{scen}");
    let csv = std::fs::read_to_string(out.join("trajectory.csv")).unwrap();
    assert_eq!(csv.lines().count(), 1002, "header + 1001 rows");
    let bad = dir.path().join("bad");
    expect_input_error(
        &[
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.model=euler",
            "--out",
            bad.to_str().unwrap(),
        ],
        &bad,
        "solver.model: unknown value \"euler\" (valid: \"reduced\", \"vector\" or \"rigid\")",
    );
}

/// Visible names in `dir` (not the tool's hidden lock and manifest), sorted.
fn visible(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    v.sort();
    v
}

/// Defect 5 of issue 12: `--no-plot` after a plotted run left the old plots
/// beside the new data. Now the previous run's files that the new one does
/// not write are removed, and only those (a file of the user's stays).
#[test]
fn no_plot_after_a_plotted_run_removes_the_old_plots() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    let o = out.to_str().unwrap();
    let short = ["--preset", "classical", "--set", "solver.t_end=0.5"];
    tippetop()
        .args(["run", "--quiet", "--out", o])
        .args(short)
        .assert()
        .success();
    assert!(out.join("theta.png").is_file());
    fs::write(out.join("notes.txt"), "mine").unwrap();
    tippetop()
        .args(["run", "--quiet", "--no-plot", "--out", o])
        .args(short)
        .assert()
        .success();
    assert_eq!(
        visible(&out),
        [
            "notes.txt",
            "scenario.toml",
            "summary.json",
            "trajectory.csv"
        ]
    );
    assert_eq!(fs::read_to_string(out.join("notes.txt")).unwrap(), "mine");
}

/// Defect 5 of issue 12: `reproduce` after `reproduce --extended` left the
/// ε-study figures and maps, which the new report does not list. Now every
/// figure in the directory is one the report names.
#[test]
fn reproduce_after_extended_leaves_only_figures_of_the_report() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rep");
    let o = out.to_str().unwrap();
    tippetop()
        .args(["reproduce", "--quick", "--extended", "--quiet", "--out", o])
        .assert()
        .success();
    assert!(out.join("figeps_10s.png").is_file());
    // The adhesion study (#14 item 4): its section and figures.
    let ext = fs::read_to_string(out.join("report.md")).unwrap();
    assert!(ext.contains("## Adhesion: what van der Waals binding does to the paper's story"));
    assert!(ext.contains("**The paper's claims under adhesion**"));
    for f in ["constant", "reversal", "pulse8us", "pulse1us", "zoom"] {
        assert!(out.join(format!("figadhesion_{f}.png")).is_file(), "{f}");
        assert!(ext.contains(&format!("(figadhesion_{f}.png)")), "{f}");
    }
    // The nanotube study (#30 item 3): with --quick, the narrowest tube and
    // the hot study's (tube::QUICK_TUBES), the table's two rows.
    assert!(ext.contains("## Inside a nanotube"));
    assert!(out.join("figtube_energy.png").is_file());
    assert!(ext.contains("| (10,10)") && ext.contains("| (15,15)"));
    assert!(!ext.contains("| (12,12)") && !ext.contains("| (20,20)"));
    tippetop()
        .args(["reproduce", "--quick", "--quiet", "--out", o])
        .assert()
        .success();
    let report = fs::read_to_string(out.join("report.md")).unwrap();
    let names = visible(&out);
    assert!(!names.iter().any(|n| n.starts_with("figeps")), "{names:?}");
    assert!(
        !names.iter().any(|n| n.starts_with("figadhesion")),
        "{names:?}"
    );
    assert!(!report.contains("Adhesion"));
    for n in names.iter().filter(|n| n.ends_with(".png")) {
        assert!(report.contains(n.as_str()), "{n} is not in report.md");
    }
    for n in &names {
        let stem = n.rsplit_once('.').map_or(n.as_str(), |(s, _)| s);
        assert!(
            ["report", "claims"].contains(&stem) || report.contains(&format!("{stem}.png")),
            "{n} does not belong to the report"
        );
    }
}

/// Defect 6 of issue 12: an `--out` that cannot be created was found only
/// after the simulation. Now `run` and `reproduce` fail (one line) before
/// computing: the failing run takes a small part of the time the same run
/// takes into a writable directory. (A path under a file: bad input, exit
/// code 2 since issue 26, as for every command.)
#[test]
fn unwritable_out_fails_before_simulating() {
    let dir = tempfile::tempdir().unwrap();
    let file = dir.path().join("file");
    fs::write(&file, "x").unwrap();
    let bad = file.join("sub");
    let good = dir.path().join("good");
    let args = [
        "run",
        "--preset",
        "classical",
        "--set",
        "solver.t_end=20000",
        "--no-plot",
        "--quiet",
        "--out",
    ];
    let t0 = std::time::Instant::now();
    tippetop().args(args).arg(&good).assert().success();
    let t_good = t0.elapsed().as_secs_f64();
    let t0 = std::time::Instant::now();
    let a = tippetop().args(args).arg(&bad).assert().code(2);
    let t_bad = t0.elapsed().as_secs_f64();
    let err = String::from_utf8(a.get_output().stderr.clone()).unwrap();
    assert!(err.starts_with("error: --out: "), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        t_bad < 0.5 * t_good,
        "the failing run took {t_bad} s, the whole run {t_good} s"
    );
    let a = tippetop()
        .args(["reproduce", "--quick", "--quiet", "--out"])
        .arg(&bad)
        .assert()
        .code(2);
    let err = String::from_utf8(a.get_output().stderr.clone()).unwrap();
    assert!(err.starts_with("error: --out: "), "{err}");
}

/// Defect 10 of issue 12 (the CLI part): `run --help` documents every
/// trajectory.csv column, each with its unit in brackets (or, for the 0/1
/// flag `rolling`, its values).
#[test]
fn run_help_documents_every_trajectory_column_with_its_unit() {
    let a = tippetop().args(["run", "--help"]).assert().success();
    let help = String::from_utf8(a.get_output().stdout.clone()).unwrap();
    let section = help
        .split_once("trajectory.csv columns")
        .expect("a trajectory.csv columns section")
        .1
        .split("\n\n")
        .next()
        .unwrap();
    // Entries: "  NAME[, NAME]   description" with continuation lines
    // indented further.
    let mut entries: Vec<(Vec<String>, String)> = Vec::new();
    for line in section.lines().skip(1) {
        let indent = line.len() - line.trim_start().len();
        if indent == 2 {
            let (names, text) = line.trim_start().split_once("  ").unwrap();
            let names = names.split(", ").map(|n| n.trim().to_string()).collect();
            entries.push((names, text.trim().to_string()));
        } else {
            entries.last_mut().unwrap().1.push_str(line.trim());
        }
    }
    let documented: Vec<&String> = entries.iter().flat_map(|(n, _)| n).collect();
    assert_eq!(
        documented,
        tippetop::trajectory::COLUMNS.iter().collect::<Vec<_>>(),
        "every column, in order"
    );
    for (names, text) in &entries {
        let has_unit = text.contains(" [") && text.contains(']');
        assert!(
            has_unit || (names == &["rolling"] && text.contains("1 while")),
            "{names:?}: {text}"
        );
    }
    for word in [
        "[s]",
        "[rad]",
        "[rad/s]",
        "[m/s]",
        "[N]",
        "[kg m³/s]",
        "[J]",
    ] {
        assert!(section.contains(word), "{word}");
    }
    // The output directory's behaviour.
    for word in [
        ".tippetop.lock",
        "exits at once with code 1",
        ".tippetop-manifest",
    ] {
        assert!(help.contains(word), "{word}");
    }
}

/// `sweep --help` says which sweeps get plots and which none, the lock, the
/// thread bound and --resume.
#[test]
fn sweep_help_documents_plots_lock_threads_and_resume() {
    let a = tippetop().args(["sweep", "--help"]).assert().success();
    let help = String::from_utf8(a.get_output().stdout.clone()).unwrap();
    for word in [
        "sweep.png, sweep.svg",
        "heat map",
        "No plots for 3 or more",
        "for a shard",
        "above 100 000 cases",
        "1 to 1024",
        "--resume",
        "sweep.csv.partial",
        "in use by another tippetop",
        "it does not wait",
        "never touched",
    ] {
        assert!(help.contains(word), "sweep --help lacks {word:?}");
    }
}

/// The summary's contact line names what `contact_lost_at` is: the first
/// N < 0 for a top held on the plane, the first lift-off for the rigid model
/// with unilateral contact (whose fraction is then the time in flight). Both
/// at the paper's 3.08 µs (README), the printed time that of summary.json.
#[test]
fn contact_line_says_lift_off_for_a_top_that_flies() {
    let dir = tempfile::tempdir().unwrap();
    for (sets, words) in [
        (&[][..], "contact:     N < 0 first at t = "),
        (
            &["solver.model=\"rigid\"", "surface.contact=\"unilateral\""][..],
            "contact:     lifts off first at t = ",
        ),
    ] {
        let out = dir.path().join(format!("r{}", sets.len()));
        let mut cmd = tippetop();
        cmd.args([
            "run",
            "--no-plot",
            "--preset",
            "nano",
            "--set",
            "solver.t_end=1e-5",
        ]);
        for s in sets {
            cmd.args(["--set", s]);
        }
        let assert = cmd
            .args(["--out", out.to_str().unwrap()])
            .assert()
            .success();
        let stdout = String::from_utf8(assert.get_output().stdout.clone()).unwrap();
        let line = stdout
            .lines()
            .find(|l| l.starts_with(words))
            .unwrap_or_else(|| panic!("no {words:?} in {stdout}"));
        let json: serde_json::Value =
            serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
        let t = json["contact_lost_at"].as_f64().unwrap();
        assert!((t - 3.08e-6).abs() < 0.005e-6, "{t}");
        assert!(line.contains("t = 3.08e-6 s"), "{line}");
    }
}

/// Issue 29 (1): `reproduce` wrote 46 files into `out/`, then `run` without
/// `--out` replaced them all without a word. Now `run` writes into its own
/// `out/run/`, and a subcommand that would replace another's output in an
/// `--out` refuses (exit 2, one line naming the directory and the other
/// subcommand), touching nothing, unless `--force`; an adding one
/// (`animate`) is not refused, and no lock file is left behind.
#[test]
fn no_command_silently_replaces_another_commands_output() {
    let dir = tempfile::tempdir().unwrap();
    let listing = |p: &std::path::Path| -> Vec<String> {
        let mut v: Vec<String> = fs::read_dir(p)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    let cmd = || {
        let mut c = tippetop();
        c.current_dir(dir.path());
        c
    };
    cmd().args(["-q", "reproduce"]).assert().success();
    let out = dir.path().join("out");
    let reproduced = listing(&out);
    assert!(
        reproduced.contains(&"report.md".to_string()),
        "{reproduced:?}"
    );
    assert!(reproduced.len() > 40, "{reproduced:?}");
    let report = fs::read(out.join("report.md")).unwrap();

    // `run` without --out: its own directory, reproduce's files untouched.
    let short = ["--preset", "classical", "--set", "solver.t_end=0.2"];
    cmd().args(["-q", "run"]).args(short).assert().success();
    assert!(out.join("run/summary.json").exists());
    let mut with_run = reproduced.clone();
    with_run.push("run".into());
    with_run.sort();
    assert_eq!(listing(&out), with_run);

    // `run --out out`: refused, naming the directory and `reproduce`.
    let o = cmd()
        .args(["run", "--out", "out"])
        .args(short)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: --out: out holds the output of `tippetop reproduce`"));
    assert!(err.contains("--force"), "{err}");
    assert_eq!(listing(&out), with_run);
    assert_eq!(fs::read(out.join("report.md")).unwrap(), report);

    // `animate` adds to a run's directory; the run may replace its own.
    cmd()
        .args(["-q", "animate", "out/run", "--fps", "2", "--duration", "1"])
        .args(["--size", "160x120"])
        .assert()
        .success();
    assert!(out.join("run/viewer.html").exists());
    cmd().args(["-q", "run"]).args(short).assert().success();

    // --force replaces reproduce's output (its files removed, run's there).
    cmd()
        .args(["-q", "run", "--force", "--out", "out"])
        .args(short)
        .assert()
        .success();
    let after = listing(&out);
    assert!(!after.contains(&"report.md".to_string()), "{after:?}");
    assert!(after.contains(&"trajectory.csv".to_string()), "{after:?}");
    for d in [&out, &out.join("run")] {
        assert!(!d.join(".tippetop.lock").exists(), "{}", d.display());
    }
}

/// Issue 29 (3): `run --preset classical --set surface.friction=0.2`
/// printed only "never above π/2"; the reason (it sticks at once and rolls,
/// and a rolling contact does no work) was in summary.json alone. The
/// console now tells it, with summary.json's figures.
#[test]
fn console_says_why_a_rolling_top_does_not_rise() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            "surface.friction=0.2",
        ])
        .args(["--set", "solver.t_end=2", "--no-plot", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    let summary: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let rolling = summary["rolling_fraction"].as_f64().unwrap();
    assert!(rolling > 0.9, "{rolling}");
    let line = text
        .lines()
        .find(|l| l.starts_with("friction:"))
        .unwrap_or_else(|| panic!("{text}"));
    let pct: f64 = line
        .split("slipping ")
        .nth(1)
        .and_then(|r| r.split('%').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((pct - 100.0 * rolling).abs() < 0.05, "{line} vs {rolling}");
    let stick = summary["events"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["kind"] == "stick")
        .unwrap()["t"]
        .as_f64()
        .unwrap();
    assert!(
        line.contains(&format!("{:.3}", stick)[..5]),
        "{line} {stick}"
    );
    assert!(text.contains("a rolling contact does no work"), "{text}");
    assert!(
        text.contains("--set surface.friction_law=contensou --set surface.contact_radius="),
        "{text}"
    );
}

/// Issue 29 (6, 7): `stability --preset classical` printed `4.0415e1 rad/s`
/// and `0.0000e0`, called upright "unstable", then "Late-time state of the
/// run: upright" without saying why. Now its numbers have 4 significant
/// figures (no exponent 0 to 3) and it names each part's friction law and
/// reconciles the two verdicts.
#[test]
fn stability_reads_and_reconciles_its_verdicts() {
    let o = tippetop()
        .args(["stability", "--preset", "classical", "-q"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("= 40.41"), "{text}");
    assert!(text.contains(
        "Friction laws: the linearisation uses the regularized law (ε = 0.001500 m/s); the run uses the scenario's coulomb law."
    ), "{text}");
    assert!(text.contains("They disagree about the upright state only through that law"));
    // Every number: its digits (mantissa) and its exponent.
    let b = text.as_bytes();
    let mut k = 0;
    while k < b.len() {
        if !b[k].is_ascii_digit() {
            k += 1;
            continue;
        }
        let start = k;
        while k < b.len() && (b[k].is_ascii_digit() || b[k] == b'.') {
            k += 1;
        }
        let digits = b[start..k].iter().filter(|c| c.is_ascii_digit()).count();
        let number = &text[start..k];
        assert!(digits < 10, "{number} in {text}");
        if k + 1 < b.len() && b[k] == b'e' && (b[k + 1].is_ascii_digit() || b[k + 1] == b'-') {
            let e0 = k + 1;
            k += 2;
            while k < b.len() && b[k].is_ascii_digit() {
                k += 1;
            }
            let e: i32 = text[e0..k].parse().unwrap();
            assert!(!(0..4).contains(&e), "{number}e{e} in {text}");
        }
    }
}

/// Issue 29 (8): `--help` pages of 60-111 lines put Usage last. Every
/// subcommand's page (short and long) now starts with its usage line.
#[test]
fn every_help_page_starts_with_usage() {
    let top = tippetop().arg("--help").output().unwrap();
    let text = String::from_utf8(top.stdout).unwrap();
    assert!(text.starts_with("Usage: tippetop "), "{text}");
    let subs: Vec<String> = text
        .lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .filter(|s| s != "help")
        .collect();
    assert!(subs.len() >= 12, "{subs:?}");
    for sub in &subs {
        for flag in ["-h", "--help"] {
            let o = tippetop().args([sub.as_str(), flag]).output().unwrap();
            let page = String::from_utf8(o.stdout).unwrap();
            assert!(
                page.starts_with(&format!("Usage: tippetop {sub} ")),
                "{sub} {flag}: {}",
                &page[..page.len().min(200)]
            );
        }
    }
}

/// Issue 29 (8): no command showed a preset's values. `tippetop show`
/// prints the resolved scenario; run from that text, it is the same run
/// (the same scenario.toml as the preset's own run writes).
#[test]
fn show_prints_the_resolved_scenario() {
    let dir = tempfile::tempdir().unwrap();
    let o = tippetop()
        .args(["show", "--preset", "nano", "--set", "solver.t_end=1e-6"])
        .output()
        .unwrap();
    assert!(o.status.success());
    let file = dir.path().join("shown.toml");
    fs::write(&file, &o.stdout).unwrap();
    let (a, b) = (dir.path().join("a"), dir.path().join("b"));
    tippetop()
        .args([
            "-q",
            "run",
            "--preset",
            "nano",
            "--set",
            "solver.t_end=1e-6",
        ])
        .args(["--no-plot", "--out"])
        .arg(&a)
        .assert()
        .success();
    tippetop()
        .args(["-q", "run"])
        .arg(&file)
        .args(["--no-plot", "--out"])
        .arg(&b)
        .assert()
        .success();
    let read = |d: &Path, f: &str| fs::read_to_string(d.join(f)).unwrap();
    // `show` adds comments (units, what each key is): without them, the
    // text is scenario.toml's.
    let shown: String = String::from_utf8(o.stdout)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with("# SI units"))
        .map(|l| {
            format!(
                "{}\n",
                l.split_once("  # ").map_or(l, |(a, _)| a.trim_end())
            )
        })
        .collect();
    assert_eq!(read(&a, "scenario.toml"), shown);
    assert_eq!(read(&a, "trajectory.csv"), read(&b, "trajectory.csv"));
    expect_input_error(
        &["show", "--preset", "bogus"],
        &dir.path().join("none"),
        "preset",
    );
}
