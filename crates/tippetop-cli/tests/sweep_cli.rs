//! `tippetop sweep` and `tippetop merge` end to end: files written, shards
//! merged byte for byte, bad input (exit code 2, one line, nothing written).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tippetop"))
}

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tippetop-sweep-cli-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const BASE: &[&str] = &[
    "sweep",
    "--preset",
    "classical",
    "--set",
    "solver.t_end=0.2",
    "--set",
    "solver.samples=11",
    "--vary",
    "top.offset=0.001:0.015:3",
    "--vary",
    "initial.spin=60:150:3",
    "--quiet",
];

fn sweep(out: &Path, extra: &[&str]) -> Output {
    bin()
        .args(BASE)
        .args(extra)
        .arg("--out")
        .arg(out)
        .output()
        .unwrap()
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// Exit code 2, one line `error: ...` on stderr containing `what`.
fn assert_input_error(o: &Output, what: &str) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "stderr: {err}");
    assert!(
        err.starts_with("error: ") && err.lines().count() == 1,
        "{err}"
    );
    assert!(err.contains(what), "{err}");
}

#[test]
fn one_shot_shards_and_merge() {
    let d = scratch("merge");
    let one = d.join("one");
    let o = sweep(&one, &["--threads", "1"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(
        o.stdout.is_empty() && o.stderr.is_empty(),
        "--quiet prints nothing"
    );
    let csv = read(&one.join("sweep.csv"));
    assert_eq!(csv.lines().count(), 10);
    assert!(csv.starts_with("top.offset,initial.spin,theta_final,"));
    assert_eq!(csv.matches(",ok\n").count(), 6, "{csv}");
    let json: serde_json::Value = serde_json::from_str(&read(&one.join("shard.json"))).unwrap();
    assert_eq!(json["k"], 1);
    assert_eq!(json["n"], 1);
    assert_eq!(json["total_cases"], 9);
    assert_eq!(json["end_index"], 9);
    assert_eq!(json["axes"][1]["key"], "initial.spin");

    // 2 threads: same bytes.
    let two = d.join("two");
    assert!(sweep(&two, &["--threads", "2"]).status.success());
    assert_eq!(read(&two.join("sweep.csv")), csv);

    // 4 shards, merged in a shuffled order: same sweep.csv and shard.json.
    let mut dirs = Vec::new();
    for k in 1..=4 {
        let s = d.join(format!("s{k}"));
        let o = sweep(&s, &["--shard", &format!("{k}/4")]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        dirs.push(s);
    }
    let merged = d.join("merged");
    let o = bin()
        .arg("merge")
        .args([&dirs[2], &dirs[0], &dirs[3], &dirs[1]])
        .arg("--out")
        .arg(&merged)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(String::from_utf8_lossy(&o.stdout).contains("merged 4 shards: 9 cases"));
    assert_eq!(read(&merged.join("sweep.csv")), csv);
    assert_eq!(
        read(&merged.join("shard.json")),
        read(&one.join("shard.json"))
    );

    // A missing shard: error, nothing written.
    let bad = d.join("bad");
    let o = bin()
        .arg("merge")
        .args([&dirs[0], &dirs[1], &dirs[3]])
        .arg("--out")
        .arg(&bad)
        .output()
        .unwrap();
    assert_input_error(&o, "are missing");
    assert!(!bad.exists());
    // A directory that is not a shard.
    let o = bin()
        .arg("merge")
        .arg(&dirs[0])
        .arg(d.join("nowhere"))
        .arg("--out")
        .arg(&bad)
        .output()
        .unwrap();
    assert_input_error(&o, "shard.json");
    assert!(!bad.exists());
    // A shard of another sweep.
    let other = d.join("other");
    assert!(
        sweep(&other, &["--set", "surface.friction=0.2", "--shard", "4/4"])
            .status
            .success()
    );
    let o = bin()
        .arg("merge")
        .args([&dirs[0], &dirs[1], &dirs[2], &other])
        .arg("--out")
        .arg(&bad)
        .output()
        .unwrap();
    assert_input_error(&o, "another sweep");
    assert!(!bad.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn bad_input_exits_2_and_writes_nothing() {
    let d = scratch("bad");
    let out = d.join("out");
    let cases: &[(&[&str], &str)] = &[
        (
            &["--vary", "top.colour=1:2:3"],
            "error: top.colour: unknown key",
        ),
        (&["--vary", "top.mass=1:2:0"], "error: top.mass: N = 0"),
        (
            &["--vary", "top.mass=0:2:3:log"],
            "error: top.mass: log spacing",
        ),
        (&["--vary", "top.mass=1:2"], "error: top.mass: "),
        (&["--vary", "top.mass"], "error: --vary: "),
        (&["--shard", "5/4"], "error: --shard: "),
        (
            &["--shard", "10/10"],
            "error: --shard: 10 shards for a sweep of 9 cases",
        ),
        (&["--threads", "0"], "error: --threads: "),
        (&["--set", "top.radius=-1"], "error: top.radius: "),
    ];
    for (extra, what) in cases {
        let o = sweep(&out, extra);
        assert_input_error(&o, what);
        assert!(!out.exists(), "{extra:?} wrote {}", out.display());
    }
    // A missing scenario file.
    let o = bin()
        .args([
            "sweep",
            "no-such-file.toml",
            "--vary",
            "top.mass=1:2:2",
            "--out",
        ])
        .arg(&out)
        .output()
        .unwrap();
    assert_input_error(&o, "no-such-file.toml");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn help_has_examples() {
    for cmd in ["sweep", "merge"] {
        let o = bin().args([cmd, "--help"]).output().unwrap();
        assert!(o.status.success());
        let help = String::from_utf8_lossy(&o.stdout);
        assert!(help.contains("Examples:"), "{help}");
        assert!(
            help.contains("tippetop merge shards/* --out result"),
            "{help}"
        );
    }
}

/// A sweep with `solver.model = "vector"`: the same bytes on 1 and 2
/// threads, the same status per case (6 valid of 9), θ_final and ω_final within 1e-6 of the
/// Euler-angle model's sweep of the same grid (the same physics; both at
/// the preset's rtol 1e-10), and fewer right-hand-side evaluations in all.
#[test]
fn vector_model_sweep_is_thread_invariant_and_agrees_with_euler_angles() {
    let d = scratch("vector");
    let runs: Vec<String> = [("reduced", "1"), ("vector", "1"), ("vector", "2")]
        .iter()
        .map(|(model, threads)| {
            let out = d.join(format!("{model}-{threads}"));
            let o = sweep(
                &out,
                &[
                    "--set",
                    &format!("solver.model={model}"),
                    "--threads",
                    threads,
                ],
            );
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            read(&out.join("sweep.csv"))
        })
        .collect();
    assert_eq!(runs[1], runs[2], "vector sweep depends on the thread count");
    let rows = |csv: &str| -> Vec<Vec<String>> {
        csv.lines()
            .skip(1)
            .map(|l| l.split(',').map(str::to_string).collect())
            .collect()
    };
    let header: Vec<&str> = runs[0].lines().next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (th, om, ev, st) = (
        col("theta_final"),
        col("omega_final"),
        col("rhs_evaluations"),
        col("status"),
    );
    let (red, vec) = (rows(&runs[0]), rows(&runs[1]));
    assert_eq!(red.len(), 9);
    let (mut e_red, mut e_vec, mut ok) = (0u64, 0u64, 0);
    for (r, v) in red.iter().zip(&vec) {
        // The grid has invalid cases (offset = R): the same error for both.
        assert_eq!(r[st], v[st]);
        if r[st] != "ok" {
            continue;
        }
        ok += 1;
        let f = |s: &str| s.parse::<f64>().unwrap();
        assert!(
            (f(&r[th]) - f(&v[th])).abs() <= 1e-6,
            "theta {} vs {}",
            r[th],
            v[th]
        );
        assert!(
            (f(&r[om]) - f(&v[om])).abs() <= 1e-6 * f(&r[om]).abs(),
            "omega {} vs {}",
            r[om],
            v[om]
        );
        e_red += r[ev].parse::<u64>().unwrap();
        e_vec += v[ev].parse::<u64>().unwrap();
    }
    assert!(
        e_vec < e_red,
        "evaluations: vector {e_vec}, Euler angles {e_red}"
    );
    assert_eq!(ok, 6, "valid cases");
    let _ = std::fs::remove_dir_all(&d);
}

/// Every name in `dir`, sorted.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// Defect 4 of issue 12: two processes writing into one `--out` corrupted
/// each other (every writer used `DIR/.NAME.tmp`). Now the first holds a lock
/// on the directory and any second `sweep`, `run`, `merge` or `reproduce`
/// exits at once with code 1 and one line naming the holder's pid, writing
/// nothing; the first finishes with consistent files.
#[test]
fn second_process_on_the_same_out_exits_1() {
    let d = scratch("lock");
    let out = d.join("out");
    let n = 20000;
    let mut first = bin()
        .args([
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.2",
            "--set",
            "solver.samples=11",
            "--vary",
            &format!("top.offset=0.001:0.004:{n}"),
            "--threads",
            "1",
            "--quiet",
            "--out",
        ])
        .arg(&out)
        .spawn()
        .unwrap();
    let pid = first.id().to_string();
    // Wait until the first holds the lock (its pid in the lock file).
    let lock = out.join(".tippetop.lock");
    let t0 = std::time::Instant::now();
    while !std::fs::read_to_string(&lock).is_ok_and(|s| s.trim() == pid) {
        assert!(
            t0.elapsed().as_secs() < 60,
            "the first sweep never took the lock"
        );
        assert!(
            first.try_wait().unwrap().is_none(),
            "the first sweep ended early"
        );
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
    let want = format!(
        "error: {} is in use by another tippetop process (pid {pid}); choose another --out or wait until it ends\n",
        out.display()
    );
    let seconds: Vec<Vec<String>> = vec![
        BASE.iter().map(|s| s.to_string()).collect(),
        ["run", "--preset", "classical", "--quiet"]
            .map(String::from)
            .to_vec(),
        ["reproduce", "--quick", "--quiet"]
            .map(String::from)
            .to_vec(),
    ];
    for args in &seconds {
        let o = bin().args(args).arg("--out").arg(&out).output().unwrap();
        assert_eq!(o.status.code(), Some(1), "{args:?}");
        assert_eq!(String::from_utf8_lossy(&o.stderr), want, "{args:?}");
    }
    assert!(
        first.try_wait().unwrap().is_none(),
        "the first sweep ended before the others tried: make it longer"
    );
    assert!(first.wait().unwrap().success());
    // The first sweep's files, complete; nothing of the others.
    assert_eq!(
        listing(&out),
        [
            ".tippetop-manifest",
            ".tippetop.lock",
            "shard.json",
            "sweep.csv",
            "sweep.png",
            "sweep.svg"
        ]
    );
    let csv = read(&out.join("sweep.csv"));
    assert_eq!(csv.lines().count(), n + 1);
    assert!(csv.ends_with('\n'));
    let _ = std::fs::remove_dir_all(&d);
}

/// Defect 6 of issue 12: an `--out` that exists but cannot be written (a
/// read-only directory; `/proc`, where even root cannot create files) was
/// found only after the whole sweep had run. Now it is an error (exit code 1)
/// before the first case: a sweep of a million cases (minutes of work) fails
/// at once. (A path under a regular file was already caught early.)
#[test]
fn unwritable_out_fails_before_computing() {
    let d = scratch("unwritable");
    let file = d.join("file");
    std::fs::write(&file, "not a directory").unwrap();
    let mut outs = vec![file.join("sub")];
    // An existing directory where even root cannot create files (procfs).
    #[cfg(target_os = "linux")]
    if Path::new("/proc/self").is_dir() {
        outs.push(PathBuf::from("/proc"));
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let ro = d.join("ro");
        std::fs::create_dir(&ro).unwrap();
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        // Root ignores permissions: only a non-root run can test this one.
        if std::fs::write(ro.join("probe"), "").is_err() {
            outs.push(ro.join("out"));
            outs.push(ro);
        }
    }
    for out in &outs {
        let mut child = bin()
            .args([
                "sweep",
                "--preset",
                "classical",
                "--set",
                "solver.t_end=0.2",
                "--set",
                "solver.samples=11",
                "--vary",
                "top.offset=0.001:0.004:1000000",
                "--quiet",
                "--out",
            ])
            .arg(out)
            .stderr(std::process::Stdio::piped())
            .spawn()
            .unwrap();
        let t0 = std::time::Instant::now();
        let status = loop {
            if let Some(s) = child.try_wait().unwrap() {
                break s;
            }
            if t0.elapsed().as_secs() > 20 {
                let _ = child.kill();
                let _ = child.wait();
                panic!("{}: still computing after 20 s", out.display());
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        };
        let mut err = String::new();
        std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
        assert_eq!(status.code(), Some(1), "{err}");
        assert!(err.starts_with("error: cannot "), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
    }
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(d.join("ro"), std::fs::Permissions::from_mode(0o755));
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Defect 5 of issue 12: a sweep with 3 axes or a shard, written where a
/// 2-axis sweep had been, left the old heat map beside the new sweep.csv.
/// Now the files of the previous command that the new one does not write
/// are removed (only those: a file of the user's stays).
#[test]
fn stale_plots_of_a_previous_sweep_are_removed() {
    let d = scratch("stale");
    let out = d.join("out");
    assert!(sweep(&out, &[]).status.success());
    assert!(out.join("sweep.png").is_file() && out.join("sweep.svg").is_file());
    std::fs::write(out.join("notes.txt"), "mine").unwrap();
    let three = ["--vary", "surface.friction=0.1:0.3:2"];
    assert!(sweep(&out, &three).status.success());
    let visible = |out: &Path| -> Vec<String> {
        listing(out)
            .into_iter()
            .filter(|n| !n.starts_with('.'))
            .collect()
    };
    assert_eq!(visible(&out), ["notes.txt", "shard.json", "sweep.csv"]);
    assert_eq!(read(&out.join("sweep.csv")).lines().count(), 19);
    assert!(sweep(&out, &[]).status.success());
    assert!(out.join("sweep.png").is_file());
    assert!(sweep(&out, &["--shard", "1/2"]).status.success());
    assert_eq!(visible(&out), ["notes.txt", "shard.json", "sweep.csv"]);
    // merge writes the plots again.
    let s2 = d.join("s2");
    assert!(sweep(&s2, &["--shard", "2/2"]).status.success());
    let o = bin()
        .arg("merge")
        .arg(&out)
        .arg(&s2)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        visible(&out),
        [
            "notes.txt",
            "shard.json",
            "sweep.csv",
            "sweep.png",
            "sweep.svg"
        ]
    );
    assert_eq!(read(&out.join("sweep.csv")).lines().count(), 10);
    let _ = std::fs::remove_dir_all(&d);
}

/// Run `cmd`, killing it (and failing) if it has not ended after `secs`.
fn output_within(mut cmd: Command, secs: u64) -> Output {
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = std::time::Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed().as_secs() >= secs {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{cmd:?} still running after {secs} s");
        }
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Defect 9 of issue 12: `--threads 20000` started 20 000 threads, for
/// minutes. Now above 1024 it is bad input: exit code 2 at once, one line
/// saying the bound, nothing written.
#[test]
fn thread_count_above_the_bound_is_bad_input() {
    let d = scratch("threads");
    let out = d.join("out");
    let mut cmd = bin();
    cmd.args(BASE)
        .args(["--threads", "20000", "--out"])
        .arg(&out);
    let o = output_within(cmd, 20);
    assert_input_error(&o, "error: --threads: 20000 threads (1 to 1024");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// Defect 9 of issue 12: an interrupted sweep (here: what a kill leaves, a
/// partial file with a torn last line) continues with `--resume` and ends
/// with the very bytes of an uninterrupted run, for a whole sweep and for a
/// shard, on another thread count.
#[test]
fn resumed_sweep_is_byte_identical() {
    let d = scratch("resume");
    for shard in [None, Some("2/3")] {
        let extra: Vec<&str> = shard.map_or(vec![], |s| vec!["--shard", s]);
        let whole = d.join("whole");
        assert!(sweep(&whole, &extra).status.success());
        let csv = read(&whole.join("sweep.csv"));
        let json = read(&whole.join("shard.json"));
        for rows_kept in [0, 1, 2] {
            let part = d.join(format!("part{rows_kept}"));
            let _ = std::fs::remove_dir_all(&part);
            std::fs::create_dir_all(&part).unwrap();
            // The header, `rows_kept` rows and half of the next row.
            let ends: Vec<usize> = csv.match_indices('\n').map(|(i, _)| i + 1).collect();
            let cut = ends[rows_kept] + (ends[rows_kept + 1] - ends[rows_kept]) / 2;
            std::fs::write(part.join("sweep.csv.partial"), &csv[..cut]).unwrap();
            std::fs::write(part.join("shard.json.partial"), &json).unwrap();
            let mut args = extra.clone();
            args.extend(["--resume", "--threads", "2"]);
            let o = sweep(&part, &args);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert_eq!(read(&part.join("sweep.csv")), csv, "{shard:?} {rows_kept}");
            assert_eq!(read(&part.join("shard.json")), json);
            assert!(!part.join("sweep.csv.partial").exists());
            assert!(!part.join("shard.json.partial").exists());
        }
        let _ = std::fs::remove_dir_all(&whole);
    }
    // A partial file with more rows than the shard has (cases 3..9 for
    // shard 2/3, cases 3..6): not this sweep's, so it starts over.
    let whole = d.join("whole");
    assert!(sweep(&whole, &[]).status.success());
    let full = read(&whole.join("sweep.csv"));
    let part = d.join("too-long");
    assert!(sweep(&part, &["--shard", "2/3"]).status.success());
    let want = read(&part.join("sweep.csv"));
    let ends: Vec<usize> = full.match_indices('\n').map(|(i, _)| i + 1).collect();
    let text = format!("{}{}", &full[..ends[0]], &full[ends[3]..]);
    std::fs::write(part.join("sweep.csv.partial"), text).unwrap();
    std::fs::copy(part.join("shard.json"), part.join("shard.json.partial")).unwrap();
    let o = sweep(&part, &["--shard", "2/3", "--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&part.join("sweep.csv")), want);
    let _ = std::fs::remove_dir_all(&d);
}

/// Defect 9 of issue 12: a sweep wrote nothing until its last case. Now its
/// rows stream to `sweep.csv.partial` as they are done: a sweep killed
/// part-way leaves complete rows on disk, and `--resume` finishes it with
/// the bytes of an uninterrupted run.
#[test]
fn killed_sweep_streams_rows_and_resumes() {
    let d = scratch("kill");
    let args = [
        "sweep",
        "--preset",
        "classical",
        "--set",
        "solver.t_end=0.2",
        "--set",
        "solver.samples=11",
        "--vary",
        "top.offset=0.001:0.004:4000",
        "--quiet",
    ];
    let whole = d.join("whole");
    let o = bin().args(args).arg("--out").arg(&whole).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let want = read(&whole.join("sweep.csv"));

    let out = d.join("out");
    let mut child = bin()
        .args(args)
        .args(["--threads", "1", "--out"])
        .arg(&out)
        .spawn()
        .unwrap();
    let partial = out.join("sweep.csv.partial");
    let t0 = std::time::Instant::now();
    loop {
        let rows = std::fs::read_to_string(&partial).map_or(0, |t| t.lines().count());
        if rows > 20 {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "the sweep ended without rows in sweep.csv.partial"
        );
        assert!(t0.elapsed().as_secs() < 60, "no rows on disk after 60 s");
        std::thread::sleep(std::time::Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.join("sweep.csv").exists());
    let o = bin()
        .args(args)
        .args(["--resume", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&out.join("sweep.csv")), want);
    let _ = std::fs::remove_dir_all(&d);
}

/// `--resume` continues only the same sweep: a partial sweep of another
/// one is bad input (exit code 2) and stays as it was; with nothing to
/// resume the sweep starts from the first case.
#[test]
fn resume_checks_the_sweep() {
    let d = scratch("resume-other");
    let other = d.join("other");
    assert!(
        sweep(&other, &["--set", "surface.friction=0.2"])
            .status
            .success()
    );
    let out = d.join("out");
    std::fs::create_dir_all(&out).unwrap();
    let partial = read(&other.join("sweep.csv"));
    let partial = &partial[..partial.len() / 2];
    std::fs::write(out.join("sweep.csv.partial"), partial).unwrap();
    std::fs::copy(other.join("shard.json"), out.join("shard.json.partial")).unwrap();
    let before = listing(&out);
    let o = sweep(&out, &["--resume"]);
    assert_input_error(&o, "error: --resume: the partial sweep in ");
    assert!(String::from_utf8_lossy(&o.stderr).contains("is another sweep"));
    assert_eq!(listing(&out), before);
    assert_eq!(read(&out.join("sweep.csv.partial")), partial);
    // Nothing to resume: a fresh sweep, the same bytes as without --resume.
    let fresh = d.join("fresh");
    let o = sweep(&fresh, &["--resume"]);
    assert!(o.status.success());
    let plain = d.join("plain");
    assert!(sweep(&plain, &[]).status.success());
    assert_eq!(
        read(&fresh.join("sweep.csv")),
        read(&plain.join("sweep.csv"))
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// `merge` does not read a shard directory that a sweep is still writing
/// into (a cluster task still running): exit code 1, one line, nothing
/// written; once the writer is gone the merge works.
#[test]
fn merge_refuses_a_shard_directory_being_written() {
    let d = scratch("merge-busy");
    let dirs: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let s = d.join(format!("s{k}"));
            assert!(sweep(&s, &["--shard", &format!("{k}/2")]).status.success());
            s
        })
        .collect();
    let out = d.join("merged");
    let writer = tippetop_cli::output::OutDir::open(&dirs[1]).unwrap();
    let o = bin()
        .arg("merge")
        .args(&dirs)
        .arg("--out")
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    assert_eq!(
        err,
        format!(
            "error: {} is in use by another tippetop process (pid {}); wait until it ends\n",
            dirs[1].display(),
            std::process::id()
        )
    );
    assert!(!out.exists());
    drop(writer);
    let o = bin()
        .arg("merge")
        .args(&dirs)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let _ = std::fs::remove_dir_all(&d);
}
