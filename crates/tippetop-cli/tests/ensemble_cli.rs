//! `tippetop ensemble` (and `tippetop merge` of its shards) end to end:
//! the same bytes whatever the threads, shards or interruptions, run K
//! replayed alone, histogram counts, bad input (exit code 2, one line,
//! nothing written).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::{checkpoints, names, refused, with_checksum};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tippetop"))
}

/// A fresh directory for one test, with the scenario in it.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tippetop-ens-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    std::fs::write(d.join("lang.toml"), SCENARIO).unwrap();
    d
}

/// A Langevin run of 1000 steps (milliseconds).
const SCENARIO: &str = r#"preset = "nano"
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

const FILES: [&str; 5] = [
    "ensemble.csv",
    "histograms.csv",
    "quantiles.csv",
    "summary.json",
    "shard.json",
];

fn ensemble(d: &Path, out: &str, extra: &[&str]) -> Output {
    bin()
        .arg("ensemble")
        .arg(d.join("lang.toml"))
        .args(extra)
        .arg("--quiet")
        .arg("--out")
        .arg(d.join(out))
        .output()
        .unwrap()
}

/// A file's text without summary.json's `step_unchecked` line, which says
/// why the step is unchecked (--no-step-check, a merge of shards).
fn but_the_reason(t: String) -> String {
    t.lines()
        .filter(|l| !l.starts_with("  \"step_unchecked\": "))
        .collect::<Vec<_>>()
        .join("\n")
}

fn ok(o: &Output) {
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// Exit code 2, one line `error: ...` on stderr starting with `start`.
fn assert_input_error(o: &Output, start: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(err.lines().count() == 1, "{err}");
    assert!(err.starts_with(start), "{err}");
}

/// Without the step check (sharded runs and merges run none), so that the
/// one-shot summary.json is the merge's but for the reason it gives.
#[test]
fn threads_and_shards_give_the_same_bytes() {
    let d = scratch("bytes");
    let unchecked = "--no-step-check";
    ok(&ensemble(
        &d,
        "t1",
        &["--runs", "9", "--threads", "1", unchecked],
    ));
    ok(&ensemble(
        &d,
        "t2",
        &["--runs", "9", "--threads", "2", unchecked],
    ));
    for f in FILES {
        assert_eq!(
            read(&d.join("t1").join(f)),
            read(&d.join("t2").join(f)),
            "{f}"
        );
    }
    let csv = read(&d.join("t1/ensemble.csv"));
    assert_eq!(csv.lines().count(), 10);
    assert!(csv.starts_with("run,seed,status,t_final,theta_final,"));
    assert!(d.join("t1/fan.png").exists() && d.join("t1/fan.svg").exists());
    // Shards of uneven sizes (5 + 4 and 3 + 3 + 3), merged in any order.
    ok(&ensemble(&d, "s1", &["--runs", "9", "--shard", "1/2"]));
    ok(&ensemble(
        &d,
        "s2",
        &["--runs", "9", "--shard", "2/2", "--threads", "2"],
    ));
    assert_eq!(read(&d.join("s1/ensemble.csv")).lines().count(), 6);
    let o = bin()
        .args(["merge", "--quiet", "--out"])
        .arg(d.join("m"))
        .arg(d.join("s2"))
        .arg(d.join("s1"))
        .output()
        .unwrap();
    ok(&o);
    for f in FILES {
        assert_eq!(
            but_the_reason(read(&d.join("t1").join(f))),
            but_the_reason(read(&d.join("m").join(f))),
            "{f}"
        );
    }
    // Merging a shard twice (a gap and an overlap): bad input, nothing written.
    let o = bin()
        .args(["merge", "--quiet", "--out"])
        .arg(d.join("bad"))
        .arg(d.join("s1"))
        .arg(d.join("s1"))
        .output()
        .unwrap();
    assert_input_error(&o, "error: merge: ");
    assert!(!d.join("bad").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// Every run is counted once per sample time and quantity; at t = 0 every
/// run is at the initial θ = 0.1, which lies in bin floor(0.1 / (π/64)) = 2.
#[test]
fn histogram_counts_add_up_to_the_runs() {
    let d = scratch("hist");
    ok(&ensemble(&d, "e", &["--runs", "7"]));
    let text = read(&d.join("e/histograms.csv"));
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(
        header[..5],
        ["t", "quantity", "lower", "upper", "underflow"]
    );
    assert_eq!(header.len(), 5 + 64 + 2);
    let mut rows = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        let counts: Vec<u64> = f[4..].iter().map(|c| c.parse().unwrap()).collect();
        assert_eq!(counts.iter().sum::<u64>(), 7, "{line}");
        if f[1] == "theta" {
            assert_eq!((f[2], f[3]), ("0.0", "3.141592653589793"));
            if f[0] == "0.0" {
                assert_eq!(counts[1 + 2], 7, "{line}");
            }
        }
        rows += 1;
    }
    assert_eq!(rows, 11 * 3);
    let q = read(&d.join("e/quantiles.csv"));
    assert!(q.starts_with("t,quantity,n,q05,q25,q50,q75,q95\n0.0,theta,7,"));
    let _ = std::fs::remove_dir_all(&d);
}

/// An interrupted ensemble (the header, some rows and a torn row in the
/// partial file, as a kill leaves it) ends with `--resume` with the bytes
/// of an uninterrupted run, the histograms of the kept rows included.
#[test]
fn resumed_ensemble_is_byte_identical() {
    let d = scratch("resume");
    ok(&ensemble(&d, "whole", &["--runs", "6"]));
    let csv = read(&d.join("whole/ensemble.csv"));
    let ends: Vec<usize> = csv.match_indices('\n').map(|(i, _)| i + 1).collect();
    for kept in [0, 2, 5] {
        let part = d.join(format!("part{kept}"));
        std::fs::create_dir_all(&part).unwrap();
        let cut = ends[kept] + (ends[kept + 1] - ends[kept]) / 2;
        std::fs::write(part.join("ensemble.csv.partial"), &csv[..cut]).unwrap();
        std::fs::copy(d.join("whole/shard.json"), part.join("shard.json.partial")).unwrap();
        std::fs::write(
            part.join("ensemble.csv.partial.sum"),
            checkpoints(&read(&d.join("whole/shard.json")), &csv[..ends[kept]]),
        )
        .unwrap();
        let name = format!("part{kept}");
        ok(&ensemble(
            &d,
            &name,
            &["--runs", "6", "--resume", "--threads", "2"],
        ));
        for f in FILES {
            assert_eq!(
                read(&d.join("whole").join(f)),
                read(&part.join(f)),
                "{f} {kept}"
            );
        }
        assert!(!part.join("ensemble.csv.partial").exists());
    }
    // Another ensemble's partial files: bad input, left alone.
    let other = d.join("other");
    std::fs::create_dir_all(&other).unwrap();
    std::fs::write(other.join("ensemble.csv.partial"), &csv[..ends[2]]).unwrap();
    std::fs::copy(d.join("whole/shard.json"), other.join("shard.json.partial")).unwrap();
    let o = ensemble(&d, "other", &["--runs", "7", "--resume"]);
    assert_input_error(&o, "error: --resume: the partial ensemble in ");
    assert_eq!(read(&other.join("ensemble.csv.partial")), &csv[..ends[2]]);
    let _ = std::fs::remove_dir_all(&d);
}

fn parse(s: &str) -> f64 {
    if s.is_empty() {
        f64::NAN
    } else {
        s.parse().unwrap()
    }
}

/// Same value, NaN equal to NaN.
fn same(a: f64, b: f64) -> bool {
    a == b || (a.is_nan() && b.is_nan())
}

/// Run K of the ensemble is `tippetop run` with `--set thermal.run=K`: its
/// `_final` values are the last row of that run's trajectory.csv, exactly,
/// and its first passage that run's summary.
#[test]
fn run_k_replays_alone() {
    let d = scratch("replay");
    ok(&ensemble(&d, "e", &["--runs", "5"]));
    let csv = read(&d.join("e/ensemble.csv"));
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    for k in [0usize, 3] {
        let row: Vec<&str> = csv.lines().nth(1 + k).unwrap().split(',').collect();
        assert_eq!(
            (row[0], row[1], row[2]),
            (k.to_string().as_str(), "1", "ok")
        );
        let out = d.join(format!("run{k}"));
        let o = bin()
            .arg("run")
            .arg(d.join("lang.toml"))
            .args([
                "--set",
                &format!("thermal.run={k}"),
                "--no-plot",
                "--quiet",
                "--out",
            ])
            .arg(&out)
            .output()
            .unwrap();
        ok(&o);
        let traj = read(&out.join("trajectory.csv"));
        let cols: Vec<&str> = traj.lines().next().unwrap().split(',').collect();
        let last: Vec<f64> = traj.lines().last().unwrap().split(',').map(parse).collect();
        for (c, v) in cols.iter().zip(&last) {
            let i = header
                .iter()
                .position(|h| *h == format!("{c}_final"))
                .unwrap();
            assert!(same(parse(row[i]), *v), "run {k} {c}: {} vs {v}", row[i]);
        }
        let summary: serde_json::Value =
            serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
        let col = |name: &str| parse(row[header.iter().position(|h| *h == name).unwrap()]);
        let fp = summary["first_time_theta_above_half_pi"]
            .as_f64()
            .unwrap_or(f64::NAN);
        assert!(same(col("first_passage_time"), fp));
        assert_eq!(col("censored"), if fp.is_nan() { 1.0 } else { 0.0 });
        assert_eq!(col("theta_max"), summary["theta_max"].as_f64().unwrap());
        assert_eq!(col("t_reached"), 1e-11);
    }
    // Runs differ from each other (independent noise).
    let finals: Vec<&str> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').nth(4).unwrap())
        .collect();
    assert!(finals.windows(2).all(|w| w[0] != w[1]), "{finals:?}");
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_input_is_one_line_and_writes_nothing() {
    let d = scratch("bad");
    let cases: &[(&[&str], &str)] = &[
        (
            &["--runs", "3", "--set", "thermal.temperature=0"],
            "error: thermal.temperature: ",
        ),
        (&["--runs", "0"], "error: --runs: "),
        (
            &["--runs", "2", "--set", "thermal.run=4294967295"],
            "error: --runs: 2 runs from thermal.run = 4294967295",
        ),
        (&["--runs", "3", "--shard", "4/4"], "error: --shard: "),
        (&["--runs", "3", "--shard", "0/2"], "error: --shard: "),
        (&["--runs", "3", "--threads", "0"], "error: --threads: "),
        (
            &["--runs", "3", "--set", "thermal.seed=-1"],
            "error: thermal.seed: ",
        ),
    ];
    for (args, want) in cases {
        let o = ensemble(&d, "out", args);
        assert_input_error(&o, want);
        assert!(!d.join("out").exists(), "{args:?}");
    }
    // A deterministic preset.
    let o = bin()
        .args(["ensemble", "--preset", "nano", "--runs", "3", "--out"])
        .arg(d.join("out"))
        .output()
        .unwrap();
    assert_input_error(&o, "error: solver.method: \"adaptive\" is deterministic");
    assert!(!d.join("out").exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// `--first-passage`: each run stops at its first output row where the
/// criterion holds. Replayed alone with `tippetop run`, the run's
/// trajectory.csv reaches the criterion first at exactly that row's time,
/// and its rows up to there are the ensemble run's (the same stream):
/// `t_reached` equals the passage time, the `_final` values are that row.
/// Bad specs are input errors naming `--first-passage`.
#[test]
fn first_passage_stops_each_run_at_its_exit() {
    let d = scratch("exit");
    // |spin| above 1e11 rad/s: thermal spin sqrt(kT/C) = 2.9e11, so most
    // runs pass within the 10 ps, at different rows.
    let spec = "omega>1e11,omega<-1e11";
    ok(&ensemble(
        &d,
        "e",
        &["--runs", "6", "--first-passage", spec],
    ));
    let csv = read(&d.join("e/ensemble.csv"));
    let header: Vec<&str> = csv.lines().next().unwrap().split(',').collect();
    let at = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let mut passed = 0;
    for (k, line) in csv.lines().skip(1).enumerate() {
        let row: Vec<&str> = line.split(',').collect();
        let out = d.join(format!("run{k}"));
        ok(&bin()
            .arg("run")
            .arg(d.join("lang.toml"))
            .args([
                "--set",
                &format!("thermal.run={k}"),
                "--no-plot",
                "--quiet",
                "--out",
            ])
            .arg(&out)
            .output()
            .unwrap());
        let traj = read(&out.join("trajectory.csv"));
        let cols: Vec<&str> = traj.lines().next().unwrap().split(',').collect();
        let iw = cols.iter().position(|c| *c == "omega").unwrap();
        let first = traj.lines().skip(1).find(|l| {
            let w = parse(l.split(',').nth(iw).unwrap());
            !(-1e11..=1e11).contains(&w)
        });
        match first {
            Some(l) => {
                passed += 1;
                let t = parse(l.split(',').next().unwrap());
                assert_eq!(parse(row[at("first_passage_time")]), t, "run {k}");
                assert_eq!(parse(row[at("t_reached")]), t, "run {k}");
                assert_eq!(parse(row[at("censored")]), 0.0);
                assert_eq!(
                    parse(row[at("omega_final")]),
                    parse(l.split(',').nth(iw).unwrap())
                );
            }
            None => {
                assert!(parse(row[at("first_passage_time")]).is_nan());
                assert_eq!(parse(row[at("censored")]), 1.0);
                assert_eq!(parse(row[at("t_reached")]), 1e-11);
            }
        }
    }
    assert!(
        passed >= 2,
        "only {passed} runs passed: the test needs passages"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&read(&d.join("e/summary.json"))).unwrap();
    assert_eq!(
        summary["first_passage_criterion"],
        "omega>100000000000.0,omega<-100000000000.0"
    );
    assert_eq!(summary["temperature"], 300.0);
    for bad in ["omega", "bogus>1", "theta>x", "theta>inf"] {
        let out = d.join("bad");
        let o = bin()
            .arg("ensemble")
            .arg(d.join("lang.toml"))
            .args(["--runs", "2", "--first-passage", bad, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert_input_error(&o, "error: --first-passage: ");
        assert!(!out.exists());
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// `tippetop retention` on two ensembles: with two temperatures the fit is
/// exact, `E = ln(k2/k1) / (1/(k_B T1) − 1/(k_B T2))`, and the rate at the
/// target follows from either point; checked against that closed form from
/// the two summary.json files. Bad input: one directory, a bad
/// temperature.
#[test]
fn retention_extrapolates_two_ensembles() {
    let d = scratch("retention");
    let spec = "omega>1e11,omega<-1e11";
    for t in ["300", "600"] {
        ok(&ensemble(
            &d,
            &format!("e{t}"),
            &[
                "--runs",
                "8",
                "--first-passage",
                spec,
                "--set",
                &format!("thermal.temperature={t}"),
            ],
        ));
    }
    let rate = |t: &str| {
        let s: serde_json::Value =
            serde_json::from_str(&read(&d.join(format!("e{t}/summary.json")))).unwrap();
        s["first_passage"]["escape_rate"]["rate"]
            .as_f64()
            .expect("passages")
    };
    let (k1, k2) = (rate("300"), rate("600"));
    let kb = 1.380649e-23;
    let (b1, b2) = (1.0 / (kb * 300.0), 1.0 / (kb * 600.0));
    let e = (k2 / k1).ln() / (b1 - b2);
    let b = 1.0 / (kb * 450.0);
    let want = k1 * (-e * (b - b1)).exp();
    let o = bin()
        .arg("retention")
        .arg(d.join("e300"))
        .arg(d.join("e600"))
        .args(["--temperature", "450", "--quiet", "--out"])
        .arg(d.join("r"))
        .output()
        .unwrap();
    ok(&o);
    let r: serde_json::Value = serde_json::from_str(&read(&d.join("r/retention.json"))).unwrap();
    let got = r["target"]["rate"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    let eb = r["fit"]["barrier"].as_f64().unwrap();
    assert!((eb - e).abs() <= 1e-12 * e.abs().max(1e-30), "{eb} vs {e}");
    let o = bin()
        .arg("retention")
        .arg(d.join("e300"))
        .args(["--temperature", "450"])
        .output()
        .unwrap();
    assert_input_error(&o, "error: DIR: ");
    let o = bin()
        .arg("retention")
        .arg(d.join("e300"))
        .arg(d.join("e600"))
        .args(["--temperature", "-1"])
        .output()
        .unwrap();
    assert_input_error(&o, "error: --temperature: ");
    let _ = std::fs::remove_dir_all(&d);
}

/// A Langevin run of 10 000 steps (tens of milliseconds in a debug build):
/// an ensemble long enough to be killed part-way.
fn long_scenario(d: &Path) -> PathBuf {
    let p = d.join("long.toml");
    std::fs::write(&p, SCENARIO.replace("t_end = 1e-11", "t_end = 1e-10")).unwrap();
    p
}

/// Issue 26 (E): an ensemble killed part-way (SIGKILL: nothing cleaned
/// up; SIGTERM: the staging directory and the lock removed) continues with
/// `--resume` from its checkpoints (the rows and the histograms of exactly
/// those rows) and ends with the bytes of an uninterrupted run.
#[cfg(unix)]
#[test]
fn killed_ensemble_resumes_byte_identical() {
    let d = scratch("kill");
    let scenario = long_scenario(&d);
    // The step check is not what is tested: off (it would triple the
    // time; resumed_ensemble_is_byte_identical resumes with it).
    let run = |out: &Path, extra: &[&str]| {
        bin()
            .arg("ensemble")
            .arg(&scenario)
            .args(["--runs", "300", "--no-step-check"])
            .args(extra)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    let whole = d.join("whole");
    ok(&run(&whole, &["--quiet"]));
    for sig in [libc::SIGKILL, libc::SIGTERM] {
        let out = d.join(format!("out{sig}"));
        let mut child = bin()
            .arg("ensemble")
            .arg(&scenario)
            .args(["--runs", "300", "--no-step-check", "--threads", "1"])
            .args(["--quiet", "--out"])
            .arg(&out)
            // A checkpoint at every row: at the default of one a second, a
            // fast machine finishes before the third checkpoint line.
            .env("TIPPETOP_CHECKPOINT_SECONDS", "0")
            .spawn()
            .unwrap();
        let sum = out.join("ensemble.csv.partial.sum");
        let t0 = std::time::Instant::now();
        // The comment, the fingerprint and two checkpoints.
        while std::fs::read_to_string(&sum).map_or(0, |t| t.lines().count()) < 4 {
            assert!(
                child.try_wait().unwrap().is_none(),
                "the ensemble ended early"
            );
            assert!(t0.elapsed().as_secs() < 60, "no checkpoint after 60 s");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        // SAFETY: kill(2) of our own child.
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
        child.wait().unwrap();
        let left = names(&out);
        let stage = left.iter().any(|n| n.starts_with(".tippetop-stage"));
        assert_eq!(stage, sig == libc::SIGKILL, "{left:?}");
        assert_eq!(
            left.contains(&".tippetop.lock".to_string()),
            sig == libc::SIGKILL
        );
        assert!(
            left.contains(&"histograms.json.partial".to_string()),
            "{left:?}"
        );
        let o = run(&out, &["--resume"]);
        ok(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(err.contains("resuming: "), "{err}");
        assert!(!err.contains("does not match a checkpoint"), "{err}");
        for f in FILES {
            assert_eq!(read(&whole.join(f)), read(&out.join(f)), "{f}");
        }
        // No lock file; the staging directory left empty.
        assert!(!names(&out).iter().any(|n| n.starts_with(".tippetop")
            && n != ".tippetop-manifest"
            && n != ".tippetop-stage"));
        assert!(names(&out.join(".tippetop-stage")).is_empty());
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (A, C): a link planted where a partial file goes is refused
/// (exit code 2, its target untouched), with or without `--resume`; a
/// corrupted `ensemble.csv.partial` is refused with its file and line; an
/// edited histogram checkpoint is not used (the kept runs run again for
/// their counts) and the result is still the uninterrupted run's.
#[test]
fn resume_refuses_links_and_corrupted_partials() {
    let d = scratch("corrupt");
    ok(&ensemble(&d, "whole", &["--runs", "6"]));
    let csv = read(&d.join("whole/ensemble.csv"));
    let lines: Vec<&str> = csv.lines().collect();
    let ends: Vec<usize> = csv.match_indices('\n').map(|(i, _)| i + 1).collect();
    let kept = &csv[..ends[4]];
    let part = d.join("part");
    let setup = |text: &str| {
        let _ = std::fs::remove_dir_all(&part);
        std::fs::create_dir_all(&part).unwrap();
        std::fs::write(part.join("ensemble.csv.partial"), text).unwrap();
        std::fs::copy(d.join("whole/shard.json"), part.join("shard.json.partial")).unwrap();
        std::fs::write(
            part.join("ensemble.csv.partial.sum"),
            checkpoints(&read(&d.join("whole/shard.json")), kept),
        )
        .unwrap();
    };
    let edit = |f: &dyn Fn(&str) -> String| -> String {
        let mut v: Vec<String> = lines[..5].iter().map(|l| l.to_string()).collect();
        v[2] = f(&v[2]);
        v.join("\n") + "\n"
    };
    let field = |l: &str, i: usize, x: &str| -> String {
        let mut f: Vec<&str> = l.split(',').collect();
        f[i] = x;
        f.join(",")
    };
    let cases: Vec<(String, &str)> = vec![
        (
            edit(&|l| field(l, 4, "3.0")),
            "ensemble.csv.partial:3: does not match its checksum",
        ),
        (
            edit(&|l| field(l, 4, "NaN")),
            "ensemble.csv.partial:3: does not match its checksum",
        ),
        (
            edit(&|l| field(l, 2, "failed")),
            "ensemble.csv.partial:3: does not match its checksum",
        ),
        (
            edit(&|l| format!("{l},1")),
            "ensemble.csv.partial:3: not a row of this ensemble (more fields than the header)",
        ),
        (
            edit(&|_| lines[1].to_string()),
            "ensemble.csv.partial:3: not a row of this ensemble (not the run's run and seed)",
        ),
        (csv[..ends[3] - 5].to_string(), "shorter than the"),
    ];
    for (text, words) in &cases {
        setup(text);
        let before = names(&part);
        let o = ensemble(&d, "part", &["--runs", "6", "--resume"]);
        refused(&o, &["error: --resume: ", words]);
        assert_eq!(names(&part), before);
        assert_eq!(&read(&part.join("ensemble.csv.partial")), text);
    }
    // Links, with and without --resume.
    #[cfg(unix)]
    for name in [
        "ensemble.csv.partial",
        "shard.json.partial",
        "histograms.json.partial",
        "ensemble.csv.partial.sum",
    ] {
        for resume in [false, true] {
            let victim = d.join("v");
            std::fs::write(&victim, "keep").unwrap();
            let _ = std::fs::remove_dir_all(&part);
            std::fs::create_dir_all(&part).unwrap();
            std::os::unix::fs::symlink(&victim, part.join(name)).unwrap();
            let extra: &[&str] = if resume {
                &["--runs", "6", "--resume"]
            } else {
                &["--runs", "6"]
            };
            let o = ensemble(&d, "part", extra);
            refused(&o, &[&format!("part/{name}: is a symbolic link")]);
            assert_eq!(read(&victim), "keep");
            assert_eq!(names(&part), [name]);
        }
    }
    // An edited histogram checkpoint (counts of 4 runs made 40): not used.
    setup(kept);
    let hist = d.join("h");
    ok(&ensemble(&d, "h", &["--runs", "4"]));
    let counts = read(&hist.join("histograms.csv")).replace(",4,", ",40,");
    let fake =
        format!("{{\"fingerprint\":\"x\",\"first_index\":0,\"rows\":4,\"hist\":{counts:?}}}");
    std::fs::write(part.join("histograms.json.partial"), fake).unwrap();
    let o = bin()
        .arg("ensemble")
        .arg(d.join("lang.toml"))
        .args(["--runs", "6", "--resume", "--out"])
        .arg(&part)
        .output()
        .unwrap();
    ok(&o);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("does not match a checkpoint"), "{err}");
    for f in FILES {
        assert_eq!(read(&d.join("whole").join(f)), read(&part.join(f)), "{f}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (C): `merge` of ensemble shards checks the checksums their
/// shard.json records for ensemble.csv and histograms.csv (an edited count
/// was merged before), and the rows (also when the checksum was
/// recomputed).
#[test]
fn merge_checks_ensemble_shards() {
    let d = scratch("merge-checks");
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let name = format!("s{k}");
            ok(&ensemble(
                &d,
                &name,
                &["--runs", "6", "--shard", &format!("{k}/2")],
            ));
            d.join(name)
        })
        .collect();
    let merge = |out: &Path| {
        bin()
            .arg("merge")
            .args(&shards)
            .arg("--out")
            .arg(out)
            .arg("--quiet")
            .output()
            .unwrap()
    };
    // Unchecked, as a merge is.
    ok(&ensemble(&d, "whole", &["--runs", "6", "--no-step-check"]));
    let good = d.join("good");
    ok(&merge(&good));
    for f in FILES {
        assert_eq!(
            but_the_reason(read(&d.join("whole").join(f))),
            but_the_reason(read(&good.join(f))),
            "{f}"
        );
    }
    let json_path = shards[1].join("shard.json");
    let json = read(&json_path);
    let hist_path = shards[1].join("histograms.csv");
    let hist = read(&hist_path);
    let csv_path = shards[1].join("ensemble.csv");
    let csv = read(&csv_path);
    let row = csv.lines().nth(1).unwrap();
    let extra = csv.replace(row, &format!("{row},1"));
    let cases: Vec<(&Path, String, String, &str)> = vec![
        (
            &hist_path,
            hist.replacen(",3,", ",30,", 1),
            json.clone(),
            "s2/histograms.csv: does not match its checksum in ",
        ),
        (
            &csv_path,
            csv.replace(row, &row.replace(",ok,", ",failed,")),
            json.clone(),
            "s2/ensemble.csv: does not match its checksum in ",
        ),
        (
            &csv_path,
            extra.clone(),
            with_checksum(&json, "ensemble.csv", extra.as_bytes()),
            "line 2 of ensemble.csv is not run 3 (more fields than the header)",
        ),
    ];
    for (path, text, info, words) in &cases {
        let original = read(path);
        assert_ne!(&original, text, "{words}");
        std::fs::write(path, text).unwrap();
        std::fs::write(&json_path, info).unwrap();
        let out = d.join("out");
        refused(&merge(&out), &[words]);
        assert!(!out.exists());
        std::fs::write(path, original).unwrap();
        std::fs::write(&json_path, &json).unwrap();
    }
    let _ = std::fs::remove_dir_all(&d);
}
