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
        // The cause is named (issue 26): the mass overflows the applied
        // force's rate sqrt(|H| / (m R)), the radius the inertia unit m R^2.
        ("nano", "top.mass=1e-320", "top.mass"),
        ("nano", "top.radius=1e308", "top.radius"),
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

/// The vertical load `force.K.hz` (docs/physics.md#vertical-load) is checked like
/// `hx`, `hy`: it must be finite, and the time unit it sets,
/// `sqrt(|(H, hz)| / (m R))`, must be finite too (1e308 N overflows it on
/// both presets); exit 2, one line naming the key, nothing written, for
/// every model.
#[test]
fn run_rejects_a_bad_vertical_load() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    for preset in ["classical", "nano"] {
        for value in ["nan", "inf", "-inf", "1e308", "-1e308"] {
            for model in ["vector", "reduced", "rigid"] {
                let set = format!("force.0.hz={value}");
                let m = format!("solver.model={model}");
                expect_input_error(
                    &[
                        "run",
                        "--preset",
                        preset,
                        "--set",
                        &set,
                        "--set",
                        &m,
                        "--no-plot",
                        "--out",
                        o,
                    ],
                    Some(&out),
                    "force.0.hz",
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
        stderr.contains("step limit 200 reached (solver.max_steps"),
        "{stderr}"
    );
    assert!(out.join("summary.json").exists());
    let summary = std::fs::read_to_string(out.join("summary.json")).unwrap();
    assert!(summary.contains("step limit 200"), "{summary}");
}

/// Issue 29 (item 3): the nano preset's long run (`solver.t_end = 1`)
/// runs away (its spin grows linearly to ~2.4e9 rad/s, its step size falls)
/// and fails: a Painleve paradox after ~6.2 M steps. Scaled down (a step
/// limit of 1 500 000, the same run until then; the warning comes at
/// t = 4.3 ms, ~1.3 M steps in), the warning that the state
/// is running away appears on stderr before the failure: the spin has grown
/// tenfold since the first progress report (16 384 steps in), decided by
/// the state, not the wall clock. The step-limit message shows no 17-digit
/// number.
#[test]
fn a_runaway_is_announced_before_the_failure() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let a = tippetop()
        .args(["run", "--preset", "nano", "--set", "solver.t_end=1"])
        .args(["--set", "solver.max_steps=1500000", "--no-plot", "--out"])
        .arg(&out)
        .assert()
        .code(3);
    let stderr = String::from_utf8_lossy(&a.get_output().stderr).to_string();
    let lines: Vec<&str> = stderr.lines().collect();
    let warn = lines
        .iter()
        .position(|l| l.starts_with("warning: the state is running away: at t = "))
        .unwrap_or_else(|| panic!("no runaway warning: {stderr}"));
    let fail = lines
        .iter()
        .position(|l| l.starts_with("error: run failed at t = "))
        .unwrap_or_else(|| panic!("no failure: {stderr}"));
    assert!(warn < fail, "{stderr}");
    assert!(lines[warn].contains("has grown 10x since t = "), "{stderr}");
    assert!(
        lines[fail].contains("step limit 1500000 reached") && lines[fail].contains("= 666.7 ns;"),
        "{stderr}"
    );
    // The spin ran away: the step limit is not the cause, and the message
    // does not suggest raising it.
    assert!(
        lines[fail].contains("cannot make progress")
            && lines[fail].contains("the spin has grown to"),
        "{stderr}"
    );
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
        // The linearised model has no vertical load (docs/physics.md#vertical-load).
        (vec!["--set", "force.0.hz=1"], "force.0.hz"),
        // Nor a body actuator (docs/physics.md#actuators).
        (
            vec![
                "--set",
                "force.0.kind=tip",
                "--set",
                "force.0.point=[0.0, 0.0, 0.0]",
                "--set",
                "force.0.force=[0.0, 0.0, 0.01]",
            ],
            "force.0.kind",
        ),
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

/// The fuzz of `tippetop/tests/fuzz.rs` on the binary, fewer cases: every
/// invocation exits 0, 2 or 3 (never a panic, 101, or an abort); exit 2
/// prints one line and writes nothing; exit 0 and 3 write the summary.
#[test]
fn fuzz_cli() {
    let mut state: u64 = 0x7170_7e70_2026_0c11;
    let mut next = move |n: usize| {
        // SplitMix64.
        state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) % n as u64) as usize
    };
    let keys = [
        "top.radius",
        "top.offset",
        "top.mass",
        "top.inertia_transverse",
        "top.inertia_axial",
        "surface.gravity",
        "surface.friction",
        "surface.friction_law",
        "surface.contact",
        "surface.restitution",
        "force.0.hx",
        "force.0.hy",
        "force.0.hz",
        "force.0.stop",
        "initial.theta",
        "initial.theta_dot",
        "initial.precession",
        "initial.spin",
        "initial.ux",
        "solver.method",
        "solver.t_end",
        "solver.steps",
        "solver.rtol",
        "solver.samples",
        "solver.model",
        "solver.max_steps",
    ];
    let extreme = [
        "0",
        "-0.0",
        "1e-320",
        "-1e-320",
        "1e308",
        "-1e308",
        "inf",
        "-inf",
        "nan",
        "9223372036854775807",
        "-1",
        "1e9",
    ];
    let ordinary = [
        "0.5",
        "2",
        "1e-3",
        "3.0",
        "0.13",
        "1e-22",
        "rk4",
        "stiff",
        "reduced",
        "rigid",
        "viscous",
        "paper",
        "unilateral",
        "coulomb_sliding",
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut codes = [0usize; 4];
    for case in 0..150 {
        let out = dir.path().join(format!("c{case}"));
        let preset = ["nano", "classical"][next(2)];
        let mut args: Vec<String> = vec!["run".into(), "--preset".into(), preset.into()];
        for s in ["solver.max_steps=2000", "solver.samples=21"] {
            args.extend(["--set".into(), s.into()]);
        }
        for _ in 0..1 + next(2) {
            let value = if next(3) == 0 {
                extreme[next(extreme.len())]
            } else {
                ordinary[next(ordinary.len())]
            };
            let kv = format!("{}={value}", keys[next(keys.len())]);
            args.extend(["--set".into(), kv]);
        }
        args.extend(["--no-plot".into(), "--quiet".into(), "--out".into()]);
        args.push(out.to_str().unwrap().into());
        let o = tippetop().args(&args).output().unwrap();
        let stderr = String::from_utf8_lossy(&o.stderr).to_string();
        let code = o.status.code();
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
        match code {
            Some(2) => {
                assert_eq!(stderr.lines().count(), 1, "{args:?}: {stderr}");
                assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
                assert!(!out.exists(), "{args:?} wrote {}", out.display());
                codes[2] += 1;
            }
            Some(c @ (0 | 3)) => {
                assert!(out.join("summary.json").exists(), "{args:?}: {stderr}");
                if c == 3 {
                    assert!(stderr.starts_with("error: "), "{args:?}: {stderr}");
                }
                codes[c as usize] += 1;
            }
            other => panic!("{args:?}: exit {other:?}: {stderr}"),
        }
    }
    eprintln!(
        "fuzz_cli: exit codes 0, 2, 3: {}, {}, {}",
        codes[0], codes[2], codes[3]
    );
    assert!(codes[0] > 0 && codes[2] > 0 && codes[3] > 0, "{codes:?}");
}

/// The `[adhesion]` table (docs/physics.md#adhesion): `force` and `energy` must
/// be finite and `>= 0`, and both zero or both positive (a pull-off force
/// without a binding energy, or an energy without a force, is bad input);
/// exit 2, one line naming the key, nothing written.
#[test]
fn run_rejects_bad_adhesion() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    let cases: &[(&[&str], &str)] = &[
        (
            &["adhesion.force=-1e-10", "adhesion.energy=1e-19"],
            "adhesion.force",
        ),
        (
            &["adhesion.force=nan", "adhesion.energy=1e-19"],
            "adhesion.force",
        ),
        (
            &["adhesion.force=inf", "adhesion.energy=1e-19"],
            "adhesion.force",
        ),
        (
            &["adhesion.force=1e-10", "adhesion.energy=-1e-19"],
            "adhesion.energy",
        ),
        (
            &["adhesion.force=1e-10", "adhesion.energy=inf"],
            "adhesion.energy",
        ),
        (&["adhesion.force=1e-10"], "adhesion.energy"),
        (&["adhesion.energy=1e-19"], "adhesion.force"),
        (&["adhesion.pull=1"], "adhesion.pull"),
        // Stiff friction with adhesion, explicit methods: refused with advice.
        (
            &[
                "adhesion.force=5.9e-10",
                "adhesion.energy=1.17e-19",
                "surface.friction_law=regularized",
                "surface.friction_eps=1e-6",
            ],
            "surface.friction_law",
        ),
        (
            &[
                "adhesion.force=5.9e-10",
                "adhesion.energy=1.17e-19",
                "surface.friction_law=viscous",
                "surface.friction_eps=1e-6",
                "solver.method=rk4",
            ],
            "surface.friction_law",
        ),
    ];
    for (sets, key) in cases {
        for model in ["vector", "reduced", "rigid"] {
            let m = format!("solver.model={model}");
            let mut args = vec!["run", "--preset", "nano", "--no-plot", "--out", o];
            for s in sets.iter().copied().chain([m.as_str()]) {
                args.extend(["--set", s]);
            }
            expect_input_error(&args, Some(&out), key);
        }
    }
}

/// The `[[well]]` entries (docs/physics.md#wells): every key finite and in
/// range, every key required, no two wells overlapping (centres closer than
/// 3 (w_i + w_j)): one line naming the key, exit 2, nothing written.
#[test]
fn run_rejects_bad_wells() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    let ok = ["well.0.theta=1.5", "well.0.depth=1e-21", "well.0.width=0.1"];
    let with = |extra: &[&'static str], drop: &str| -> Vec<&'static str> {
        ok.iter()
            .copied()
            .filter(|s| !s.starts_with(drop))
            .chain(extra.iter().copied())
            .collect()
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (with(&["well.0.theta=-0.1"], "well.0.theta"), "well.0.theta"),
        (with(&["well.0.theta=3.2"], "well.0.theta"), "well.0.theta"),
        (with(&["well.0.theta=nan"], "well.0.theta"), "well.0.theta"),
        (with(&["well.0.depth=0"], "well.0.depth"), "well.0.depth"),
        (
            with(&["well.0.depth=-1e-21"], "well.0.depth"),
            "well.0.depth",
        ),
        (with(&["well.0.depth=inf"], "well.0.depth"), "well.0.depth"),
        (with(&["well.0.width=0"], "well.0.width"), "well.0.width"),
        (with(&["well.0.width=-0.1"], "well.0.width"), "well.0.width"),
        (with(&[], "well.0.width"), "well.0.width"),
        (with(&[], "well.0.depth"), "well.0.depth"),
        (
            with(
                &["well.1.theta=2.0", "well.1.depth=1e-21", "well.1.width=0.1"],
                "none",
            ),
            "well.1.theta",
        ),
        (with(&["well.0.radius=1"], "none"), "well.0.radius"),
        (with(&["well.2.theta=1"], "none"), "well.2.theta"),
    ];
    for (sets, key) in cases {
        for model in ["vector", "reduced", "rigid"] {
            let m = format!("solver.model={model}");
            let mut args = vec!["run", "--preset", "nano", "--no-plot", "--out", o];
            for s in sets.iter().copied().chain([m.as_str()]) {
                args.extend(["--set", s]);
            }
            expect_input_error(&args, Some(&out), key);
        }
    }
    // Centres 0.6 rad = 3 (0.1 + 0.1) apart: allowed (the bound itself).
    let mut args = vec![
        "run",
        "--preset",
        "classical",
        "--no-plot",
        "--quiet",
        "--out",
        o,
        "--set",
        "solver.t_end=0.1",
    ];
    for s in
        ok.iter()
            .copied()
            .chain(["well.1.theta=2.1", "well.1.depth=1e-21", "well.1.width=0.1"])
    {
        args.extend(["--set", s]);
    }
    tippetop().args(&args).assert().success();
}

/// Bad thermal input (issue #15): negative temperature, zero damping at
/// T > 0, Coulomb friction with mu > 0 at T > 0, a dt above the step rule,
/// a missing seed, temperature without the Langevin method, a Brownian
/// run's contact damping beyond its conditioning limit: one line naming
/// the key, exit 2, nothing written.
#[test]
fn run_rejects_bad_thermal_input() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("out");
    let o = out.to_str().unwrap();
    let ok = [
        "surface.friction=0",
        "solver.method=\"langevin\"",
        "solver.dt=1e-14",
        "solver.t_end=1e-11",
        "solver.samples=11",
        "thermal.temperature=300",
        "thermal.damping_translational=1e11",
        "thermal.damping_rotational=1e11",
        "thermal.seed=1",
    ];
    let with = |extra: &[&'static str], drop: &str| -> Vec<&'static str> {
        ok.iter()
            .copied()
            .filter(|s| drop.is_empty() || !s.starts_with(drop))
            .chain(extra.iter().copied())
            .collect()
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (with(&["thermal.temperature=-1"], ""), "thermal.temperature"),
        (
            with(&["thermal.damping_rotational=0"], ""),
            "thermal.damping_rotational",
        ),
        (
            with(&["thermal.damping_translational=0"], ""),
            "thermal.damping_translational",
        ),
        (with(&["surface.friction=0.1"], ""), "surface.friction"),
        (with(&["solver.dt=1e-12"], ""), "solver.dt"),
        (with(&[], "thermal.seed"), "thermal.seed"),
        (with(&[], "solver.dt"), "solver.dt"),
        (vec!["thermal.temperature=300"], "thermal.temperature"),
        // The Brownian method with a contact damping 1e13 times the bath's
        // (the mobility's conditioning limit is 1e8).
        (
            with(
                &[
                    "solver.method=\"brownian\"",
                    "solver.dt=1e-16",
                    "thermal.damping_contact=1",
                ],
                "solver.method",
            ),
            "thermal.damping_contact",
        ),
        // The rigid Brownian body above a wall (unilateral contact,
        // physics.md#brownian-wall) with graphene's adhesion: the wall's thermal
        // length kT/F_a = 7 pm binds the step (dt <= 2.8e-18 s here).
        (
            with(
                &[
                    "solver.method=\"brownian\"",
                    "solver.model=\"rigid\"",
                    "surface.contact=\"unilateral\"",
                    "solver.dt=1e-16",
                    "adhesion.force=5.9159e-10",
                    "adhesion.energy=1.1696e-19",
                ],
                "solver.dt",
            ),
            "solver.dt",
        ),
    ];
    for (sets, key) in cases {
        let mut args = vec!["run", "--preset", "nano", "--no-plot", "--out", o];
        for s in &sets {
            args.push("--set");
            args.push(s);
        }
        expect_input_error(&args, Some(&out), key);
    }
    // The valid run writes its files.
    let mut args = vec![
        "run",
        "--preset",
        "nano",
        "--no-plot",
        "--quiet",
        "--out",
        o,
    ];
    for s in ok {
        args.push("--set");
        args.push(s);
    }
    tippetop().args(&args).assert().success();
    assert!(out.join("trajectory.csv").exists());
}

/// Coulomb–Contensou friction (#18): a contact radius out of range
/// (negative, not finite, above 0.1 R), missing, or given to another law,
/// and an unknown pressure: exit 2, one line naming the key, nothing
/// written.
#[test]
fn run_rejects_a_bad_contact_radius() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    let law = "surface.friction_law=\"contensou\"";
    for (sets, key) in [
        (
            vec![law, "surface.contact_radius=-1e-4"],
            "surface.contact_radius",
        ),
        (
            vec![law, "surface.contact_radius=nan"],
            "surface.contact_radius",
        ),
        (
            vec![law, "surface.contact_radius=inf"],
            "surface.contact_radius",
        ),
        // classical R = 15 mm: 0.1 R = 1.5 mm.
        (
            vec![law, "surface.contact_radius=1.6e-3"],
            "surface.contact_radius",
        ),
        (vec![law], "surface.contact_radius"),
        (
            vec!["surface.contact_radius=1e-4"],
            "surface.contact_radius",
        ),
        (
            vec![
                law,
                "surface.contact_radius=1e-4",
                "surface.contact_pressure=\"flat\"",
            ],
            "surface.contact_pressure",
        ),
    ] {
        let mut args = vec!["run", "--preset", "classical"];
        for s in &sets {
            args.push("--set");
            args.push(s);
        }
        args.extend(["--no-plot", "--out", o]);
        expect_input_error(&args, Some(&out), key);
    }
}

/// The stem (docs/physics.md#stem): bad stem input is one line naming the
/// key and its range, exit 2, nothing written; the on-plane models stop at
/// the stem's touchdown with exit 3 (`not_modelled`), the rows so far and
/// `summary.json` (its stem entries) written.
#[test]
fn stem_input_errors_and_on_plane_stop() {
    let toy = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenarios/toy_with_stem.toml"
    );
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    for (set, key, range) in [
        (
            "top.stem_radius=0.02",
            "top.stem_radius",
            "0 < stem_radius < radius",
        ),
        (
            "top.stem_radius=0",
            "top.stem_radius",
            "0 < stem_radius < radius",
        ),
        (
            "top.stem_distance=0.01",
            "top.stem_distance",
            "stem_distance > offset + radius - stem_radius",
        ),
        (
            "surface.contact=bilateral",
            "surface.contact",
            "\"unilateral\" with a stem",
        ),
        ("initial.theta=3", "initial.theta", "theta < theta_td"),
    ] {
        let args = ["run", toy, "--set", set, "--no-plot", "--out", o];
        expect_input_error(&args, Some(&out), key);
        let e = tippetop().args(args).assert().get_output().stderr.clone();
        assert!(String::from_utf8_lossy(&e).contains(range), "{set}");
    }
    // One key without the other.
    expect_input_error(
        &[
            "run",
            "--preset",
            "classical",
            "--set",
            "top.stem_radius=0.0025",
            "--no-plot",
            "--out",
            o,
        ],
        Some(&out),
        "top.stem_distance",
    );
    // The vector model stops where the stem touches.
    let a = tippetop()
        .args([
            "run",
            toy,
            "--set",
            "solver.model=vector",
            "--set",
            "surface.contact=bilateral",
            "--no-plot",
            "--out",
            o,
        ])
        .assert();
    let outp = a.get_output();
    let stderr = String::from_utf8_lossy(&outp.stderr);
    assert_eq!(outp.status.code(), Some(3), "{stderr}");
    assert!(
        stderr.contains("the stem touches the plane at theta = theta_td"),
        "{stderr}"
    );
    assert_eq!(
        stderr.lines().filter(|l| l.starts_with("error:")).count(),
        1,
        "{stderr}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    assert_eq!(summary["failure"], "not_modelled");
    assert_eq!(summary["first_stem_contact_at"], summary["t_end"]);
    assert_eq!(summary["stem_contact_fraction"], 0.0);
    // Without a stem the entries are absent.
    let plain = dir.path().join("plain");
    tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.01",
            "--no-plot",
            "--out",
            plain.to_str().unwrap(),
        ])
        .assert()
        .success();
    let s = std::fs::read_to_string(plain.join("summary.json")).unwrap();
    assert!(!s.contains("stem"), "{s}");
}

/// The tube (docs/physics.md#tube-dynamics): each refusal is one line
/// naming its key, exit 2, nothing written: the radius missing, not larger
/// than the sphere, not a number; the angle out of range; the tube's keys
/// on the plane; the reduced and vector models; the plane-only inputs
/// (an actuator, a [[well]], Contensou); the Brownian method (its drift
/// correction is the plane's; Langevin is taken). A lift-off from the wall
/// (unilateral contact), deterministic or hot (Langevin), stops with exit 3
/// and says so, rows written.
#[test]
fn tube_input_errors_and_lift_off() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    let o = out.to_str().unwrap();
    let (rigid, tube, b) = (
        "solver.model=\"rigid\"",
        "surface.shape=\"tube\"",
        "surface.tube_radius=0.05",
    );
    for (preset, sets, key) in [
        ("classical", vec![rigid, tube], "surface.tube_radius"),
        (
            "classical",
            vec![rigid, tube, "surface.tube_radius=0.015"],
            "surface.tube_radius",
        ),
        (
            "classical",
            vec![rigid, tube, "surface.tube_radius=-1"],
            "surface.tube_radius",
        ),
        (
            "classical",
            vec![rigid, tube, b, "surface.tube_angle=2"],
            "surface.tube_angle",
        ),
        ("classical", vec![b], "surface.tube_radius"),
        (
            "classical",
            vec!["surface.tube_angle=0.1"],
            "surface.tube_angle",
        ),
        ("classical", vec![tube, b], "surface.shape"),
        (
            "classical",
            vec![tube, b, "solver.model=\"vector\""],
            "surface.shape",
        ),
        (
            "nano",
            vec![
                rigid,
                tube,
                "surface.tube_radius=1e-9",
                "force.1.kind=\"tip\"",
                "force.1.point=[0.0, 0.0, 0.0]",
                "force.1.force=[0.0, 0.0, 1e-25]",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                b,
                "well.0.theta=1.0",
                "well.0.depth=1e-3",
                "well.0.width=0.5",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                b,
                "surface.friction_law=\"contensou\"",
                "surface.contact_radius=1e-4",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![rigid, "surface.shape=\"cone\""],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                b,
                "solver.method=\"brownian\"",
                "solver.dt=1e-5",
                "surface.friction=0",
                "thermal.temperature=1e17",
                "thermal.damping_translational=20",
                "thermal.damping_rotational=20",
                "thermal.seed=1",
            ],
            "solver.method",
        ),
    ] {
        let mut args = vec!["run", "--preset", preset];
        for s in &sets {
            args.push("--set");
            args.push(s);
        }
        args.extend(["--no-plot", "--out", o]);
        expect_input_error(&args, Some(&out), key);
    }
    // A frictionless top thrown along the wall at 1.2 m/s in a 5 cm tube
    // (v² > 3 g (b − R)): N falls through 0 above the axis's height.
    let a = tippetop()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            rigid,
            "--set",
            tube,
            "--set",
            b,
            "--set",
            "surface.contact=\"unilateral\"",
            "--set",
            "surface.friction=0",
            "--set",
            "surface.friction_law=\"coulomb_sliding\"",
            "--set",
            "initial.spin=0",
            "--set",
            "initial.theta=0",
            "--set",
            "initial.uy=1.2",
            "--set",
            "solver.t_end=0.5",
            "--no-plot",
            "--out",
            o,
        ])
        .assert();
    let res = a.get_output();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert_eq!(res.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("lifts off the tube's wall"), "{stderr}");
    assert!(out.join("summary.json").exists());
    assert!(out.join("trajectory.csv").exists());
    // A hot nano top (Langevin, 300 K, no adhesion) in a 1 nm tube under
    // unilateral contact: the bath's kicks take N through 0 within ps, and
    // the run stops there the same way (docs/physics.md#tube-langevin).
    let mut args = vec!["run", "--preset", "nano"];
    for s in [
        rigid,
        tube,
        "surface.tube_radius=1e-9",
        "surface.contact=\"unilateral\"",
        "surface.friction=0",
        "solver.method=\"langevin\"",
        "solver.dt=5e-15",
        "solver.t_end=1e-11",
        "thermal.temperature=300",
        "thermal.damping_translational=2.2e12",
        "thermal.damping_rotational=2.2e12",
        "thermal.seed=1",
    ] {
        args.extend(["--set", s]);
    }
    args.extend(["--no-plot", "--out", o]);
    let a = tippetop().args(&args).assert();
    let res = a.get_output();
    let stderr = String::from_utf8_lossy(&res.stderr);
    assert_eq!(res.status.code(), Some(3), "{stderr}");
    assert!(stderr.contains("lifts off the tube's wall"), "{stderr}");
    assert!(out.join("trajectory.csv").exists());
}

/// A bad nano-scale value is quoted as given, in powers of ten
/// (`-1.196e-24`, `3e-10`), not as `-0.000000000000000000000001196`, and
/// the one line still names the key and the range (exit 2, nothing
/// written).
#[test]
fn bad_nano_values_are_quoted_readably() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    for (set, want) in [
        (
            "top.mass=-1.196e-24",
            "error: top.mass: -1.196e-24 is not allowed (a finite number > 0)",
        ),
        (
            "solver.rtol=1e-30",
            "error: solver.rtol: 1e-30 is not allowed (1e-14 <= rtol <= 1e-2)",
        ),
    ] {
        let a = tippetop()
            .args(["run", "--preset", "nano", "--set", set, "--out"])
            .arg(&out)
            .assert()
            .code(2);
        let stderr = String::from_utf8_lossy(&a.get_output().stderr).to_string();
        assert_eq!(stderr.trim_end(), want);
        assert!(!out.exists());
    }
}
