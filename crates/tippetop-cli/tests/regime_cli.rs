//! `tippetop regime` and the `regime` object of summary.json.

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

#[test]
fn regime_json_matches_the_library() {
    let out = tippetop()
        .args([
            "regime",
            "--preset",
            "nano",
            "--temperature",
            "300",
            "--json",
        ])
        .output()
        .unwrap();
    assert!(out.status.success());
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let lib = tippetop::analysis::regime::regime(&tippetop::Scenario::nano(), Some(300.0)).unwrap();
    assert_eq!(v["applied_over_weight"].as_f64(), lib.applied_over_weight);
    assert_eq!(
        v["rotational_energy_over_kT"].as_f64(),
        lib.rotational_energy_over_kt
    );
    assert!(v["adhesion_over_weight"].is_null());
    let text = tippetop()
        .args(["regime", "--preset", "nano"])
        .output()
        .unwrap();
    let text = String::from_utf8(text.stdout).unwrap();
    assert!(text.contains("angular_momentum_over_hbar"), "{text}");
    assert!(text.contains("questionable"), "{text}");
}

#[test]
fn bad_input_is_one_line_exit_2() {
    for args in [
        vec!["regime", "--preset", "nano", "--temperature", "-1"],
        vec!["regime", "--preset", "nano", "--temperature", "nan"],
        vec!["regime", "--preset", "nano", "--set", "top.mass=-1"],
        vec!["regime"],
    ] {
        let out = tippetop().args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(out.stdout.is_empty());
    }
}

/// Every run's summary.json carries the regime (no temperature: the
/// thermal entries are null).
#[test]
fn summary_json_has_the_regime() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    tippetop()
        .args(["run", "--preset", "nano", "--no-plot", "--quiet", "--out"])
        .arg(&out)
        .assert()
        .success();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let r = &v["regime"];
    assert!(r["applied_over_weight"].as_f64().unwrap() > 12.0);
    assert!(r["rotational_energy_over_kT"].is_null());
    assert!(r["temperature"].is_null());
}

/// Issue 26: summary.json's regime is the run's, at the run's own
/// temperature: `--preset nano-physical` (C60 on graphene at 300 K) carries
/// the thermal ratios at 300 K (they were null), by hand from the preset's
/// C = 5.0242e-44 kg m² and ω0 = 100 rad/s (as `tests/regime.rs`):
/// ½ C ω0²/kT = 6.065018e-20, ω0/√(kT/C) = 3.482820e-10, and
/// t_end/τ = 1e-12 s / 9.1 ps.
#[test]
fn summary_json_regime_is_at_the_runs_temperature() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("o");
    tippetop()
        .args([
            "run",
            "--preset",
            "nano-physical",
            "--set",
            "solver.t_end=1e-12",
            "--set",
            "solver.samples=11",
            "--no-plot",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .assert()
        .success();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap()).unwrap();
    let r = &v["regime"];
    let close = |key: &str, want: f64| {
        let got = r[key]
            .as_f64()
            .unwrap_or_else(|| panic!("{key}: {}", r[key]));
        assert!((got - want).abs() <= 1e-4 * want, "{key}: {got} vs {want}");
    };
    assert_eq!(r["temperature"].as_f64(), Some(300.0));
    close("rotational_energy_over_kT", 6.065018e-20);
    close("spin_over_thermal_spin", 3.482820e-10);
    close("window_over_orientation_correlation_time", 1e-12 / 9.1e-12);
}
