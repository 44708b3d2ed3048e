//! The step check of `tippetop bit` end to end: a bit ensemble at T > 0 is
//! run again at solver.dt/2 with an independent seed, and each probability
//! with a 95 % interval is compared with its value there. The check's runs
//! are those of a plain bit at dt/2 (replayed here with the seed the check
//! documents), bit.json holds both answers and the verdict, the bytes do
//! not depend on --threads, `--no-step-check` and a deterministic bit say
//! why the step is unchecked, an invalid dt/2 scenario is bad input, a
//! kill during the check's pass resumes to the same bytes, and shards
//! merge to the checked output.

mod common;
use common::{HOT, NANO20, bin, json, names, ok, refused};

use std::path::Path;
use std::process::Output;

fn scratch(name: &str) -> std::path::PathBuf {
    common::scratch("step-check-bit", name)
}

/// `tippetop bit DIR/hot.toml ARGS --out DIR/OUT` (not quiet: the console
/// is read).
fn bit(d: &Path, file: &str, out: &str, extra: &[&str]) -> Output {
    bin()
        .arg("bit")
        .arg(d.join(file))
        .args(extra)
        .arg("--out")
        .arg(d.join(out))
        .output()
        .unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// The blocks of bit.json, in its order.
const BLOCKS: [&str; 4] = ["write", "erase", "erase_given_write", "cycle"];

/// The Wilson 95 % score interval of `k` successes in `n`, from its
/// textbook formula (z = 1.959964: the 97.5 % normal quantile), to check
/// the interval of the answer at dt/2 independently of the library's.
fn wilson(k: usize, n: usize) -> [f64; 2] {
    let (z, nf) = (1.959_963_984_540_054_f64, n as f64);
    let p = k as f64 / nf;
    let c = (p + z * z / (2.0 * nf)) / (1.0 + z * z / nf);
    let h = z / (1.0 + z * z / nf) * (p * (1.0 - p) / nf + z * z / (4.0 * nf * nf)).sqrt();
    [(c - h).max(0.0), (c + h).min(1.0)]
}

/// Successes per block counted from a runs.csv (the write and erase
/// outcome columns; erase_given_write over the runs whose write is `ok`;
/// cycle: both `ok`): (successes, runs) in [`BLOCKS`] order.
fn counts(csv: &str) -> [(usize, usize); 4] {
    let mut lines = csv.lines();
    let head: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = |n: &str| head.iter().position(|h| *h == n).unwrap();
    let (w, e) = (col("write"), col("erase"));
    let mut c = [(0, 0); 4];
    for l in lines {
        let f: Vec<&str> = l.split(',').collect();
        let (wo, eo) = (f[w] == "ok", f[e] == "ok");
        c[0] = (c[0].0 + usize::from(wo), c[0].1 + 1);
        c[1] = (c[1].0 + usize::from(eo), c[1].1 + 1);
        if wo {
            c[2] = (c[2].0 + usize::from(eo), c[2].1 + 1);
        }
        c[3] = (c[3].0 + usize::from(wo && eo), c[3].1 + 1);
    }
    c
}

/// The default run of a bit ensemble checks the step: bit.json has
/// `dt_converged` and, per probability with an interval, the answer at
/// dt (the one bit.json reports) and at dt/2, whose step is exactly half
/// (halving a binary float is exact); the answer at dt/2 is the count in
/// runs_half_dt.csv with its Wilson interval; the verdict follows from the
/// numbers; and the bytes do not depend on --threads.
#[test]
fn default_run_checks_the_step_whatever_the_threads() {
    let d = scratch("default");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    let o1 = bit(&d, "hot.toml", "t1", &["--runs", "12", "--threads", "1"]);
    ok(&o1);
    ok(&bit(
        &d,
        "hot.toml",
        "t2",
        &["--runs", "12", "--threads", "2"],
    ));
    for f in ["bit.json", "bit.md", "runs.csv", "runs_half_dt.csv"] {
        assert_eq!(
            std::fs::read(d.join("t1").join(f)).unwrap(),
            std::fs::read(d.join("t2").join(f)).unwrap(),
            "{f}"
        );
    }
    let b = json(&d.join("t1/bit.json"));
    let half = read(&d.join("t1/runs_half_dt.csv"));
    let fine = counts(&half);
    let checks = b["step_check"].as_object().expect("step_check object");
    let mut all = true;
    for (k, blk) in BLOCKS.iter().enumerate() {
        let x = &b[*blk];
        // Every block with an interval is checked (erase_given_write has
        // none when no write succeeded).
        assert_eq!(checks.contains_key(*blk), !x["ci95"].is_null(), "{blk}");
        let Some(c) = checks.get(*blk) else { continue };
        let (a, h) = (&c["at_dt"], &c["at_half_dt"]);
        assert_eq!(a["dt"].as_f64(), Some(1e-14), "{blk}");
        assert_eq!(h["dt"].as_f64(), Some(1e-14 / 2.0), "{blk}");
        assert_eq!(a["estimate"], x["probability"], "{blk}");
        assert_eq!(a["ci95"], x["ci95"], "{blk}");
        let (s, n) = fine[k];
        let p = s as f64 / n as f64;
        assert_eq!(h["estimate"].as_f64(), Some(p), "{blk}: {s} of {n}");
        let ci = wilson(s, n);
        for i in 0..2 {
            let got = h["ci95"][i].as_f64().unwrap();
            assert!((got - ci[i]).abs() < 1e-12, "{blk}: {got} vs {ci:?}");
        }
        let pa = a["estimate"].as_f64().unwrap();
        let (lo, hi) = (
            a["ci95"][0].as_f64().unwrap(),
            a["ci95"][1].as_f64().unwrap(),
        );
        let (err, stat) = (
            c["step_error"].as_f64().unwrap(),
            c["statistical"].as_f64().unwrap(),
        );
        assert_eq!(err, (p - pa).abs(), "{blk}");
        // The change's own half-width: the two answers' in quadrature
        // (independent answers: their variances add), widened by the
        // Bonferroni factor z(1 - 0.025/m)/1.96 of the m probabilities
        // judged together (normal tables: z = 2.3940 for m = 3, 2.4977
        // for m = 4).
        let m = checks.len();
        assert_eq!(c["family"].as_u64(), Some(m as u64), "{blk}");
        assert!(m == 3 || m == 4, "{m}");
        let z = if m == 4 { 2.4977 } else { 2.3940 };
        let want = z / 1.96 * (0.5 * (hi - lo)).hypot(0.5 * (ci[1] - ci[0]));
        assert!((stat / want - 1.0).abs() < 1e-3, "{blk}: {stat} vs {want}");
        assert_eq!(c["converged"].as_bool(), Some(err < stat), "{blk}");
        assert_eq!(c["scale"], "linear");
        all &= err < stat;
    }
    assert_eq!(
        b["dt_converged"].as_bool(),
        Some(all),
        "{}",
        b["dt_converged"]
    );
    assert!(b["step_unchecked"].is_null());
    // The console and bit.md give a line per probability and the verdict
    // (a warning on stderr when not converged).
    let out = stdout(&o1);
    let md = read(&d.join("t1/bit.md"));
    for blk in checks.keys() {
        assert!(
            out.contains(&format!("step check {blk}: at dt/2 = ")),
            "{out}"
        );
        assert!(md.contains(&format!("- {blk}: at dt/2 = ")), "{md}");
    }
    let err = String::from_utf8_lossy(&o1.stderr);
    assert_eq!(out.contains("(dt_converged: true)"), all, "{out}");
    assert_eq!(
        err.contains("warning: NOT converged in the step"),
        !all,
        "{err}"
    );
    assert_eq!(
        md.contains("**Warning: NOT converged in the step"),
        !all,
        "{md}"
    );

    // The check's runs are a plain bit at dt/2 with the seed moved by
    // 0x9E3779B97F4A7C15 (wrapping) and the step limit doubled (20000000
    // for Langevin): with thermal.seed = 2^64 - 0x9E3779B97F4A7C15 + 7 the
    // check's seed is 7, and its runs are HOT's at dt = 5e-15.
    let seed = (7u64).wrapping_sub(0x9E37_79B9_7F4A_7C15);
    let seed_set = format!("thermal.seed={seed}");
    ok(&bit(
        &d,
        "hot.toml",
        "moved",
        &["--runs", "12", "--quiet", "--set", &seed_set],
    ));
    ok(&bit(
        &d,
        "hot.toml",
        "half",
        &[
            "--runs",
            "12",
            "--quiet",
            "--no-step-check",
            "--set",
            "solver.dt=5e-15",
            "--set",
            "solver.max_steps=40000000",
        ],
    ));
    assert_eq!(
        read(&d.join("moved/runs_half_dt.csv")),
        read(&d.join("half/runs.csv"))
    );
    // And independent of the runs at dt: not the same rows.
    assert_ne!(half, read(&d.join("t1/runs.csv")));
    let _ = std::fs::remove_dir_all(&d);
}

/// `--no-step-check`: no second pass (no runs_half_dt.csv), bit.json's
/// `dt_converged` and `step_check` null with the reason, the console and
/// bit.md say the step is unchecked; the answer itself is the checked
/// run's (the check only adds).
#[test]
fn no_step_check_writes_null_and_says_unchecked() {
    let d = scratch("off");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    ok(&bit(&d, "hot.toml", "on", &["--runs", "8", "--quiet"]));
    let o = bit(&d, "hot.toml", "off", &["--runs", "8", "--no-step-check"]);
    ok(&o);
    let b = json(&d.join("off/bit.json"));
    assert!(
        b["dt_converged"].is_null() && b["step_check"].is_null(),
        "{b}"
    );
    assert_eq!(b["step_unchecked"], "--no-step-check");
    assert!(stdout(&o).contains("step unchecked (--no-step-check)"));
    assert!(read(&d.join("off/bit.md")).contains("Step unchecked (--no-step-check)."));
    assert!(!d.join("off/runs_half_dt.csv").exists());
    assert_eq!(read(&d.join("on/runs.csv")), read(&d.join("off/runs.csv")));
    let mut on = json(&d.join("on/bit.json"));
    let mut off = b.clone();
    for v in [&mut on, &mut off] {
        for k in ["dt_converged", "step_check", "step_unchecked"] {
            v.as_object_mut().unwrap().remove(k);
        }
    }
    assert_eq!(on, off);
    let _ = std::fs::remove_dir_all(&d);
}

/// A deterministic bit (T = 0: one run without noise) and a single run at
/// T > 0 have no interval to compare a change of the step with: no check,
/// and bit.json, bit.md and the console say why in one line. A design map
/// runs no check and says so.
#[test]
fn a_deterministic_bit_says_why_there_is_no_check() {
    let d = scratch("cold");
    std::fs::write(d.join("nano20.toml"), NANO20).unwrap();
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    for (file, out, extra, why) in [
        ("nano20.toml", "cold", &[][..], "one deterministic run"),
        (
            "hot.toml",
            "one",
            &["--runs", "1"][..],
            "one run (--runs 1)",
        ),
    ] {
        let o = bit(&d, file, out, extra);
        ok(&o);
        let b = json(&d.join(out).join("bit.json"));
        assert!(
            b["dt_converged"].is_null() && b["step_check"].is_null(),
            "{b}"
        );
        let reason = b["step_unchecked"].as_str().unwrap();
        assert!(reason.starts_with(why), "{reason}");
        let line: Vec<String> = stdout(&o)
            .lines()
            .filter(|l| l.starts_with("step unchecked ("))
            .map(String::from)
            .collect();
        assert_eq!(line, [format!("step unchecked ({reason})")]);
        assert!(read(&d.join(out).join("bit.md")).contains(&format!("Step unchecked ({reason}).")));
    }
    let o = bit(
        &d,
        "nano20.toml",
        "map",
        &["--vary", "write.0.hy=1e-22:2e-22:2"],
    );
    ok(&o);
    assert!(
        stdout(&o).contains("step unchecked: a map"),
        "{}",
        stdout(&o)
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// A scenario valid at dt whose dt/2 version is not (2 × 6.7e8 steps
/// beyond the largest step limit, 1e9): one line naming solver.dt and the
/// check, exit code 2, nothing written.
#[test]
fn an_invalid_half_step_is_bad_input() {
    let d = scratch("bad");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    let o = bit(
        &d,
        "hot.toml",
        "out",
        &[
            "--set",
            "solver.max_steps=1000000000",
            "--set",
            "solver.dt=3e-20",
        ],
    );
    refused(&o, &["error: solver.dt", "step check", "--no-step-check"]);
    assert!(!d.join("out").exists());
}

/// A bit killed (SIGKILL) during its ensemble's pass, and during the
/// check's pass (its ensemble complete on disk): `--resume` keeps the
/// verified rows of each pass and ends with the bytes of an
/// uninterrupted run.
#[cfg(unix)]
#[test]
fn killed_in_either_pass_resumes_byte_identical() {
    let d = scratch("kill");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    let args = ["--runs", "150", "--threads", "1", "--quiet"];
    ok(&bit(&d, "hot.toml", "whole", &args));
    for (partial, resumed_passes) in [("runs.csv.partial", 1), ("runs_half_dt.csv.partial", 2)] {
        let sum = d.join(format!("out/{partial}.sum"));
        // Up to 3 tries: a try counts if the kill caught the pass.
        let caught = (0..3).any(|_| {
            let _ = std::fs::remove_dir_all(d.join("out"));
            let mut child = bin()
                .arg("bit")
                .arg(d.join("hot.toml"))
                .args(args)
                .arg("--out")
                .arg(d.join("out"))
                // A checkpoint at every row.
                .env("TIPPETOP_CHECKPOINT_SECONDS", "0")
                .spawn()
                .unwrap();
            let t0 = std::time::Instant::now();
            // The comment, the fingerprint and two checkpoints.
            while std::fs::read_to_string(&sum).map_or(0, |t| t.lines().count()) < 4 {
                if child.try_wait().unwrap().is_some() {
                    break;
                }
                assert!(t0.elapsed().as_secs() < 60, "no checkpoint after 60 s");
                std::thread::sleep(std::time::Duration::from_millis(2));
            }
            let _ = child.kill();
            let status = child.wait().unwrap();
            let finished = d.join(format!("out/{}", partial.trim_end_matches(".partial")));
            !status.success() && !finished.exists()
        });
        assert!(
            caught,
            "{partial}: the child finished before the kill in 3 tries"
        );
        let left = names(&d.join("out"));
        assert!(left.contains(&partial.to_string()), "{left:?}");
        let mut resumed = args.to_vec();
        resumed.retain(|a| *a != "--quiet");
        resumed.push("--resume");
        let o = bit(&d, "hot.toml", "out", &resumed);
        ok(&o);
        let err = String::from_utf8_lossy(&o.stderr);
        // The rows kept of each pass that had any; no note for a check's
        // pass that had not started.
        assert_eq!(err.matches("resuming: ").count(), resumed_passes, "{err}");
        assert!(
            err.contains(&format!(
                "runs kept from {}",
                d.join("out").join(partial).display()
            )),
            "{err}"
        );
        assert!(!err.contains("no partial"), "{err}");
        for f in ["bit.json", "bit.md", "runs.csv", "runs_half_dt.csv"] {
            assert_eq!(
                std::fs::read(d.join("whole").join(f)).unwrap(),
                std::fs::read(d.join("out").join(f)).unwrap(),
                "{partial}: {f}"
            );
        }
        let left = names(&d.join("out"));
        assert!(!left.iter().any(|n| n.contains(".partial")), "{left:?}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Shards run the check's runs of their block: `tippetop merge` writes the
/// checked outputs of the unsharded run byte for byte; shards with and
/// without the check do not merge (exit 2, nothing written).
#[test]
fn shards_merge_to_the_checked_bytes() {
    let d = scratch("shards");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    let q = ["--runs", "10", "--quiet"];
    ok(&bit(&d, "hot.toml", "all", &q));
    for (k, extra) in [(1, None), (2, None), (2, Some("--no-step-check"))] {
        let sh = format!("{k}/2");
        let mut a = q.to_vec();
        a.extend(["--shard", &sh]);
        a.extend(extra);
        let out = format!("s{k}{}", if extra.is_some() { "off" } else { "" });
        ok(&bit(&d, "hot.toml", &out, &a));
    }
    let merge = |dirs: &[&str], out: &str| {
        bin()
            .arg("merge")
            .args(dirs.iter().map(|s| d.join(s)))
            .arg("--quiet")
            .arg("--out")
            .arg(d.join(out))
            .output()
            .unwrap()
    };
    ok(&merge(&["s2", "s1"], "merged"));
    for f in ["bit.json", "bit.md", "runs.csv", "runs_half_dt.csv"] {
        assert_eq!(
            std::fs::read(d.join("all").join(f)).unwrap(),
            std::fs::read(d.join("merged").join(f)).unwrap(),
            "{f}"
        );
    }
    let o = merge(&["s1", "s2off"], "mixed");
    refused(&o, &["runs_half_dt.csv", "--no-step-check"]);
    assert!(!d.join("mixed").exists());
    let _ = std::fs::remove_dir_all(&d);
}
