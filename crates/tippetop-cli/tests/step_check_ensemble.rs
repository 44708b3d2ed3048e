//! `tippetop ensemble`'s step check end to end: the ensemble again at
//! solver.dt/2 (independent noise), each statistic with a 95 % interval
//! compared, `dt_converged` and `step_check` in summary.json; off with
//! `--no-step-check`, with `--shard` and in a merge; the same bytes
//! whatever the threads; a Brownian ensemble near its step rule's limit
//! that is not converged and a Langevin one that is.

mod common;

use std::path::Path;
use std::process::Output;

use common::{bin, checkpoints, json, ok, scratch};

/// The Langevin scenario of ensemble_cli.rs (scenarios/thermal.toml): the
/// nano top at 300 K, 1000 steps of 1e-14 s. Its fastest rate is the
/// thermal spin sqrt(kT/C) = 2.87e11 1/s: dt * rate = 0.0029 (the rule's
/// limit is 0.02).
const LANGEVIN: &str = r#"preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
t_end = 1e-11
samples = 11
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 1
"#;

/// The eccentric nano top (a = R/2) in the Brownian mode at 300 K, no
/// gravity, started at theta = 1.5, 10 steps of 5e-14 s: 94 % of the step
/// rule's limit (the spin's diffusion kT/(gamma_r C) = 3.75e10 1/s gives
/// dt * rate = 0.00187 against 0.002). A passage is theta > pi/2, 0.071 rad
/// away.
const BROWNIAN: &str = r#"preset = "nano"
[top]
offset = 1.775e-10
[surface]
gravity = 0.0
friction = 0.0
[initial]
theta = 1.5
spin = 0.0
[solver]
method = "brownian"
dt = 5e-14
t_end = 5e-13
samples = 2
[thermal]
temperature = 300.0
damping_translational = 2.2e12
damping_rotational = 2.2e12
seed = 5
"#;

/// The files of an ensemble's output directory.
const FILES: [&str; 5] = [
    "ensemble.csv",
    "histograms.csv",
    "quantiles.csv",
    "summary.json",
    "shard.json",
];

fn setup(name: &str) -> std::path::PathBuf {
    let d = scratch("step-check-ens", name);
    std::fs::write(d.join("lang.toml"), LANGEVIN).unwrap();
    std::fs::write(d.join("brown.toml"), BROWNIAN).unwrap();
    d
}

/// `tippetop ensemble DIR/FILE ARGS --out DIR/OUT`.
fn ensemble(d: &Path, file: &str, out: &str, args: &[&str]) -> Output {
    bin()
        .arg("ensemble")
        .arg(d.join(file))
        .args(args)
        .arg("--out")
        .arg(d.join(out))
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The file names in `dir`, sorted.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// summary.json without the step check's keys.
fn answer(summary: &serde_json::Value) -> serde_json::Value {
    let mut s = summary.clone();
    let m = s.as_object_mut().unwrap();
    for k in ["dt_converged", "step_check", "step_unchecked"] {
        m.remove(k);
    }
    s
}

/// |change| over the 95 % half-width of one statistic's check.
fn ratio(c: &serde_json::Value) -> f64 {
    c["step_error"].as_f64().unwrap() / c["statistical"].as_f64().unwrap()
}

/// (a) By default the ensemble runs again at dt/2 = 5e-15 s exactly, and
/// summary.json holds dt_converged (every statistic's `converged`) and,
/// per statistic, both answers: at dt the statistic as summary.json gives
/// it, at dt/2 another (independent noise). The answer is the unchecked
/// run's, its files are unchanged, and the refined runs write no file.
#[test]
fn default_run_checks_the_step_at_half_dt() {
    let d = setup("default");
    let o = ensemble(&d, "lang.toml", "e", &["--runs", "20"]);
    ok(&o);
    let s = json(&d.join("e/summary.json"));
    let checks = s["step_check"].as_object().expect("a step_check object");
    for name in [
        "theta_final",
        "omega_final",
        "Omega_final",
        "energy_final",
        "first_passage.censored_fraction",
    ] {
        assert!(checks.contains_key(name), "{name}: {checks:?}");
    }
    let mut all = true;
    for (name, c) in checks {
        assert_eq!(c["at_dt"]["dt"], 1e-14, "{name}");
        assert_eq!(c["at_half_dt"]["dt"].as_f64(), Some(1e-14 / 2.0), "{name}");
        let scale = if name == "first_passage.escape_rate" {
            "log"
        } else {
            "linear"
        };
        assert_eq!(c["scale"], scale, "{name}");
        let converged = c["converged"].as_bool().unwrap();
        assert_eq!(converged, ratio(c) < 1.0, "{name}");
        all &= converged;
    }
    assert_eq!(s["dt_converged"].as_bool(), Some(all));
    assert!(s.get("step_unchecked").is_none());
    let theta = &checks["theta_final"];
    assert_eq!(theta["at_dt"]["estimate"], s["theta_final"]["mean"]);
    assert_eq!(theta["at_dt"]["ci95"], s["theta_final"]["ci95"]);
    let (x, y) = (
        theta["at_dt"]["estimate"].as_f64().unwrap(),
        theta["at_half_dt"]["estimate"].as_f64().unwrap(),
    );
    assert_ne!(x, y, "independent noise at dt/2");
    assert_eq!(theta["step_error"].as_f64(), Some((y - x).abs()));
    let rate = &checks["first_passage.escape_rate"];
    assert_eq!(
        rate["at_dt"]["estimate"],
        s["first_passage"]["escape_rate"]["rate"]
    );
    let out = stdout(&o);
    assert!(
        out.contains("step check: the 20 runs again at dt/2 = 5.000e-15 s"),
        "{out}"
    );
    assert!(
        out.contains("step check theta_final: at dt/2 = 5.000e-15 s "),
        "{out}"
    );
    let verdict = if all {
        "converged in the step: each of the"
    } else {
        "NOT converged in the step: "
    };
    assert!(
        out.contains(verdict) || stderr(&o).contains(verdict),
        "{out}{}",
        stderr(&o)
    );
    // The same answer and files without the check.
    let u = ensemble(&d, "lang.toml", "u", &["--runs", "20", "--no-step-check"]);
    ok(&u);
    assert_eq!(names(&d.join("e")), names(&d.join("u")));
    for f in FILES {
        if f != "summary.json" {
            assert_eq!(
                std::fs::read(d.join("e").join(f)).unwrap(),
                std::fs::read(d.join("u").join(f)).unwrap(),
                "{f}"
            );
        }
    }
    assert_eq!(answer(&s), answer(&json(&d.join("u/summary.json"))));
    let _ = std::fs::remove_dir_all(&d);
}

/// (b) `--no-step-check`: dt_converged and step_check null, the reason in
/// step_unchecked and on the console. A shard, a merge and one run have
/// no check either, each with its reason; a scenario whose dt/2 version
/// is invalid is bad input naming the key (nothing written).
#[test]
fn unchecked_runs_say_why() {
    let d = setup("unchecked");
    let o = ensemble(&d, "lang.toml", "n", &["--runs", "4", "--no-step-check"]);
    ok(&o);
    let s = json(&d.join("n/summary.json"));
    assert!(s["dt_converged"].is_null() && s["step_check"].is_null());
    assert_eq!(s["step_unchecked"], "--no-step-check");
    assert!(
        stdout(&o).contains("step unchecked (--no-step-check)"),
        "{}",
        stdout(&o)
    );
    assert!(!stderr(&o).contains("NOT converged"));
    let reason = |out: &str| {
        let s = json(&d.join(out).join("summary.json"));
        assert!(s["dt_converged"].is_null() && s["step_check"].is_null());
        s["step_unchecked"].as_str().unwrap().to_string()
    };
    for k in ["1/2", "2/2"] {
        let out = format!("s{}", &k[..1]);
        ok(&ensemble(
            &d,
            "lang.toml",
            &out,
            &["--runs", "4", "--shard", k, "--quiet"],
        ));
        assert!(
            reason(&out).starts_with(&format!("sharded (--shard {k}): ")),
            "{}",
            reason(&out)
        );
    }
    let m = bin()
        .args(["merge", "--out"])
        .arg(d.join("m"))
        .arg(d.join("s1"))
        .arg(d.join("s2"))
        .output()
        .unwrap();
    ok(&m);
    assert!(
        reason("m").starts_with("a merge of shards: "),
        "{}",
        reason("m")
    );
    assert!(stdout(&m).contains("step unchecked (a merge of shards: "));
    ok(&ensemble(
        &d,
        "lang.toml",
        "one",
        &["--runs", "1", "--quiet"],
    ));
    assert!(reason("one").starts_with("one run: "), "{}", reason("one"));
    // 6e8 steps at dt need 1.2e9 at dt/2, beyond the largest step limit
    // (1e9): refused before anything runs.
    let o = ensemble(
        &d,
        "lang.toml",
        "bad",
        &[
            "--runs",
            "2",
            "--set",
            "solver.max_steps=1000000000",
            "--set",
            "solver.t_end=6e-6",
        ],
    );
    let err = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: solver.dt: "), "{err}");
    assert!(
        err.contains("in the step check's scenario at solver.dt/2"),
        "{err}"
    );
    assert!(!d.join("bad").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// (c) Not converged: the Brownian ensemble near its step rule's limit.
/// Its step error is the passages missed between step ends (a diffusion
/// watched every dt crosses a level later, as if the level were 0.58
/// rms steps further: the error falls like sqrt(dt)). Measured apart
/// (seed 11, 40 000 runs per step, --no-step-check), the censored fraction
/// is 0.5615, 0.5353, 0.5117, 0.4996, 0.4864 at dt, dt/2, ..., dt/16 and
/// the escape rate 1.161e12, 1.269e12, ... 1/s: from dt to dt/2 the
/// fraction changes by 0.026 (± 0.0035) and ln(rate) by 0.088. With 20 000
/// runs the fraction's 95 % half-width is 1.96 sqrt(0.56 0.44 / 20000) =
/// 0.0069, a quarter of the change (noise would have to hide 3.9 standard
/// deviations of the difference), and the rate's is 1.96 / sqrt(8 800
/// passages) = 0.021 on the log scale, a quarter of its change.
#[test]
fn brownian_near_its_step_limit_is_not_converged() {
    let d = setup("not-converged");
    let o = ensemble(&d, "brown.toml", "e", &["--runs", "20000"]);
    ok(&o);
    let s = json(&d.join("e/summary.json"));
    assert_eq!(s["dt_converged"], false);
    for name in [
        "first_passage.censored_fraction",
        "first_passage.escape_rate",
    ] {
        let c = &s["step_check"][name];
        assert_eq!(c["converged"], false, "{name}: {c}");
        assert!(ratio(c) > 2.0, "{name}: {c}");
    }
    let err = stderr(&o);
    assert!(
        err.contains("warning: NOT converged in the step: "),
        "{err}"
    );
    assert!(err.contains("first_passage.censored_fraction"), "{err}");
    let _ = std::fs::remove_dir_all(&d);
}

/// (c) Converged: the Langevin ensemble, 200 runs. Its step error is below
/// what the check can see: measured apart (seed 101, 4 000 runs at dt and
/// at dt/4, --no-step-check) no statistic moved by more than 1.22
/// standard errors of the difference (theta_final -0.31, omega_final
/// 1.06, Omega_final 1.22, energy_final -0.22, censored fraction 0.69,
/// escape rate -0.64, mean passage time 0.66; each such standard error is
/// 0.16 of the statistic's 95 % half-width at 200 runs), so from dt to
/// dt/2 each moves by less than about 0.4 of that half-width (3/4 of
/// 1.22 + 1.96 of them: the splitting is of weak order 2, and dt * rate =
/// 0.0029). What the check
/// compares is then the noise of two independent answers: a statistic
/// passes with probability 83 % (P(|Z| < 1.96/sqrt 2)), all seven
/// together with about one half (19 of 40 seeds of this scenario); the
/// seed is fixed, so the outcome is, and each change is also checked
/// against three half-widths, which noise alone passes but with
/// probability 3e-5.
#[test]
fn langevin_well_below_its_step_limit_is_converged() {
    let d = setup("converged");
    let o = ensemble(&d, "lang.toml", "e", &["--runs", "200"]);
    ok(&o);
    let s = json(&d.join("e/summary.json"));
    let checks = s["step_check"].as_object().unwrap();
    assert_eq!(checks.len(), 7, "{checks:?}");
    for (name, c) in checks {
        assert!(ratio(c) < 3.0, "{name}: {c}");
    }
    assert_eq!(s["dt_converged"], true, "{checks:?}");
    let out = stdout(&o);
    assert!(
        out.contains("step check: converged in the step: each of the 7 statistics"),
        "{out}"
    );
    assert!(!stderr(&o).contains("NOT converged"));
    let _ = std::fs::remove_dir_all(&d);
}

/// (d) The check's figures, like the ensemble's, do not depend on the
/// threads: every file byte for byte the same with 1 and 2.
#[test]
fn threads_give_the_same_bytes_with_the_check() {
    let d = setup("threads");
    for t in ["1", "2"] {
        ok(&ensemble(
            &d,
            "lang.toml",
            &format!("t{t}"),
            &["--runs", "12", "--threads", t, "--quiet"],
        ));
    }
    assert!(json(&d.join("t1/summary.json"))["step_check"].is_object());
    for f in FILES {
        assert_eq!(
            std::fs::read(d.join("t1").join(f)).unwrap(),
            std::fs::read(d.join("t2").join(f)).unwrap(),
            "{f}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A kill during the check leaves the ensemble's rows complete in
/// ensemble.csv.partial: `--resume` keeps them all, runs the check again
/// whole and ends with the bytes of an uninterrupted run.
#[test]
fn resumed_during_the_check_is_byte_identical() {
    let d = setup("resume");
    ok(&ensemble(
        &d,
        "lang.toml",
        "whole",
        &["--runs", "6", "--quiet"],
    ));
    let csv = std::fs::read_to_string(d.join("whole/ensemble.csv")).unwrap();
    let info = std::fs::read_to_string(d.join("whole/shard.json")).unwrap();
    let part = d.join("part");
    std::fs::create_dir_all(&part).unwrap();
    std::fs::write(part.join("ensemble.csv.partial"), &csv).unwrap();
    std::fs::copy(d.join("whole/shard.json"), part.join("shard.json.partial")).unwrap();
    std::fs::write(
        part.join("ensemble.csv.partial.sum"),
        checkpoints(&info, &csv),
    )
    .unwrap();
    let o = ensemble(&d, "lang.toml", "part", &["--runs", "6", "--resume"]);
    ok(&o);
    assert!(
        stderr(&o).contains("resuming: 6 of 6 runs kept"),
        "{}",
        stderr(&o)
    );
    for f in FILES {
        assert_eq!(
            std::fs::read(d.join("whole").join(f)).unwrap(),
            std::fs::read(part.join(f)).unwrap(),
            "{f}"
        );
    }
    let _ = std::fs::remove_dir_all(&d);
}
