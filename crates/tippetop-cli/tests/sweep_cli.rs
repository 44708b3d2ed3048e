//! `tippetop sweep` and `tippetop merge` end to end: files written, shards
//! merged byte for byte, bad input (exit code 2, one line, nothing written).

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

mod common;
use common::{checkpoints, fnv1a64, names, refused, with_checksum};

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
            ".tippetop-stage",
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
/// at once. (A path that is a file or under one is bad input, exit code 2:
/// `out_that_is_a_file_is_bad_input`.)
#[test]
fn unwritable_out_fails_before_computing() {
    let d = scratch("unwritable");
    let file = d.join("file");
    std::fs::write(&file, "not a directory").unwrap();
    let mut outs = vec![];
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
    // merge writes the plots again (into a directory that held a shard).
    let s2 = d.join("s2");
    assert!(sweep(&s2, &["--shard", "2/2"]).status.success());
    let m = d.join("m");
    assert!(sweep(&m, &["--shard", "1/2"]).status.success());
    assert_eq!(visible(&m), ["shard.json", "sweep.csv"]);
    let o = bin()
        .arg("merge")
        .arg(&out)
        .arg(&s2)
        .arg("--out")
        .arg(&m)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let out = m;
    assert_eq!(
        visible(&out),
        ["shard.json", "sweep.csv", "sweep.png", "sweep.svg"]
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
            std::fs::write(
                part.join("sweep.csv.partial.sum"),
                checkpoints(&json, &csv[..ends[rows_kept]]),
            )
            .unwrap();
            let mut args = extra.clone();
            args.extend(["--resume", "--threads", "2"]);
            let o = sweep(&part, &args);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            assert_eq!(read(&part.join("sweep.csv")), csv, "{shard:?} {rows_kept}");
            assert_eq!(read(&part.join("shard.json")), json);
            assert!(!part.join("sweep.csv.partial").exists());
            assert!(!part.join("shard.json.partial").exists());
            assert!(!part.join("sweep.csv.partial.sum").exists());
        }
        let _ = std::fs::remove_dir_all(&whole);
    }
    // A partial file with more rows than the shard has (cases 3..9 for
    // shard 2/3, cases 3..6): without checkpoints nothing of it is trusted
    // and the sweep starts over; with checkpoints over all its rows it is
    // not a file of this shard: bad input.
    let whole = d.join("whole");
    assert!(sweep(&whole, &[]).status.success());
    let full = read(&whole.join("sweep.csv"));
    let part = d.join("too-long");
    assert!(sweep(&part, &["--shard", "2/3"]).status.success());
    let want = read(&part.join("sweep.csv"));
    let ends: Vec<usize> = full.match_indices('\n').map(|(i, _)| i + 1).collect();
    let text = format!("{}{}", &full[..ends[0]], &full[ends[3]..]);
    std::fs::write(part.join("sweep.csv.partial"), &text).unwrap();
    std::fs::copy(part.join("shard.json"), part.join("shard.json.partial")).unwrap();
    let o = sweep(&part, &["--shard", "2/3", "--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&part.join("sweep.csv")), want);
    std::fs::write(part.join("sweep.csv.partial"), &text).unwrap();
    std::fs::copy(part.join("shard.json"), part.join("shard.json.partial")).unwrap();
    std::fs::write(
        part.join("sweep.csv.partial.sum"),
        checkpoints(&read(&part.join("shard.json")), &text),
    )
    .unwrap();
    let o = sweep(&part, &["--shard", "2/3", "--resume"]);
    refused(&o, &["sweep.csv.partial: 6 rows, more than the 3 cases"]);
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
    // kill -9 leaves the lock file and the staging directory: the next
    // command takes them over (issue 26: not a permanent block).
    assert!(out.join(".tippetop.lock").exists());
    assert!(names(&out).iter().any(|n| n == ".tippetop-stage"));
    let o = bin()
        .args(args)
        .args(["--resume", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&out.join("sweep.csv")), want);
    // The staging directory is left, emptied of what the killed sweep had
    // staged.
    assert!(names(&out.join(".tippetop-stage")).is_empty());
    assert_eq!(
        names(&out),
        [
            ".tippetop-manifest",
            ".tippetop-stage",
            "shard.json",
            "sweep.csv",
            "sweep.png",
            "sweep.svg"
        ]
    );
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

/// Issue 26 (A): writes followed symbolic links. A link planted where the
/// lock file or a partial file goes (`o/.tippetop.lock -> ../v`,
/// `o/sweep.csv.partial -> ../v`, ...) made `run` and `sweep` write into
/// the link's target, even without `--resume`. Now each is refused with
/// one line naming the file (exit code 2), the target untouched; a link
/// where the final `sweep.csv` goes is replaced, its target untouched.
#[cfg(unix)]
#[test]
fn links_in_the_output_directory_are_refused() {
    let d = scratch("links");
    let victim = d.join("v");
    let plant = |out: &Path, name: &str| {
        let _ = std::fs::remove_dir_all(out);
        std::fs::create_dir_all(out).unwrap();
        std::fs::write(&victim, "keep").unwrap();
        std::os::unix::fs::symlink(&victim, out.join(name)).unwrap();
    };
    let out = d.join("o");
    // The lock, for run and sweep.
    plant(&out, ".tippetop.lock");
    let o = bin()
        .args(["run", "--preset", "classical", "--set", "solver.t_end=0.01"])
        .args(["--no-plot", "--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    refused(&o, &["o/.tippetop.lock: is a symbolic link"]);
    assert_eq!(read(&victim), "keep");
    assert_eq!(names(&out), [".tippetop.lock"]);
    let o = sweep(&out, &[]);
    refused(&o, &["o/.tippetop.lock: is a symbolic link"]);
    assert_eq!(read(&victim), "keep");
    // The partial files, with and without --resume.
    for name in [
        "sweep.csv.partial",
        "shard.json.partial",
        "sweep.csv.partial.sum",
    ] {
        for resume in [false, true] {
            plant(&out, name);
            let o = sweep(&out, if resume { &["--resume"] } else { &[] });
            refused(&o, &[&format!("o/{name}: is a symbolic link")]);
            assert_eq!(read(&victim), "keep", "{name}");
            assert_eq!(names(&out), [name], "{name}: nothing else written");
        }
    }
    // The final file: replaced, not followed.
    plant(&out, "sweep.csv");
    let o = sweep(&out, &[]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&victim), "keep");
    let meta = std::fs::symlink_metadata(out.join("sweep.csv")).unwrap();
    assert!(meta.is_file());
    assert_eq!(read(&out.join("sweep.csv")).lines().count(), 10);
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (C): `--resume` kept edited values, NaN, edited statuses and
/// fabricated rows, and rows with an extra field (a malformed sweep.csv).
/// Now the rows it keeps are checked against the checkpoints beside the
/// partial file (`sweep.csv.partial.sum`, hashes of the rows on disk) and
/// row by row: each corruption is refused with one line naming the file
/// and line (exit code 2), the partial files left as they were. Rows after
/// the last checkpoint (a fabricated row appended, a torn line) are cut
/// and run again: the same bytes as an uninterrupted run.
#[test]
fn resume_refuses_corrupted_partials() {
    let d = scratch("corrupt");
    let whole = d.join("whole");
    assert!(sweep(&whole, &[]).status.success());
    let csv = read(&whole.join("sweep.csv"));
    let mut info: serde_json::Value =
        serde_json::from_str(&read(&whole.join("shard.json"))).unwrap();
    info.as_object_mut().unwrap().remove("checksums");
    let json = serde_json::to_string_pretty(&info).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    let ends: Vec<usize> = csv.match_indices('\n').map(|(i, _)| i + 1).collect();
    // An interrupted sweep: the header and 5 rows, all checkpointed.
    let kept = &csv[..ends[5]];
    let sums = checkpoints(&json, kept);
    let part = d.join("part");
    let setup = |partial: &str, sum: &str| {
        let _ = std::fs::remove_dir_all(&part);
        std::fs::create_dir_all(&part).unwrap();
        std::fs::write(part.join("sweep.csv.partial"), partial).unwrap();
        std::fs::write(part.join("shard.json.partial"), &json).unwrap();
        std::fs::write(part.join("sweep.csv.partial.sum"), sum).unwrap();
    };
    // Line 3 (case 1) edited in each way.
    let edit = |f: &dyn Fn(&str) -> String| -> String {
        let mut v: Vec<String> = lines[..6].iter().map(|l| l.to_string()).collect();
        v[2] = f(&v[2]);
        v.join("\n") + "\n"
    };
    let field = |l: &str, i: usize, x: &str| -> String {
        let mut f: Vec<&str> = l.split(',').collect();
        f[i] = x;
        f.join(",")
    };
    let theta_final = 2; // after the two varied keys
    let status = lines[0].split(',').count() - 1;
    let cases: Vec<(&str, String, String)> = vec![
        (
            "edited value",
            edit(&|l| {
                let v: f64 = l.split(',').nth(theta_final).unwrap().parse().unwrap();
                field(l, theta_final, &format!("{:?}", v * 1.001))
            }),
            "sweep.csv.partial:3: does not match its checksum".into(),
        ),
        (
            "NaN",
            edit(&|l| field(l, theta_final, "NaN")),
            "sweep.csv.partial:3: does not match its checksum".into(),
        ),
        (
            "edited status",
            edit(&|l| field(l, status, "failed")),
            "sweep.csv.partial:3: does not match its checksum".into(),
        ),
        (
            "extra field",
            edit(&|l| format!("{l},1")),
            "sweep.csv.partial:3: not a row of this sweep (more fields than the header)".into(),
        ),
        (
            "fabricated row",
            edit(&|_| lines[2].replace("0.001,", "0.0015,")),
            "sweep.csv.partial:3: not a row of this sweep (not the case's grid values)".into(),
        ),
        (
            "a row removed",
            format!("{}{}", &csv[..ends[1]], &csv[ends[2]..ends[5]]),
            "sweep.csv.partial:3: not a row of this sweep (not the case's grid values)".into(),
        ),
        (
            "truncated line",
            csv[..ends[4] - 7].to_string(),
            "shorter than the".into(),
        ),
    ];
    for (what, text, words) in &cases {
        assert_ne!(text, kept, "{what}");
        setup(text, &sums);
        let before = names(&part);
        let o = sweep(&part, &["--resume"]);
        refused(&o, &["error: --resume: ", "part/sweep.csv.partial", words]);
        assert_eq!(names(&part), before, "{what}");
        assert_eq!(&read(&part.join("sweep.csv.partial")), text, "{what}");
    }
    // An edited checkpoint file, and a checkpoint line that is not one.
    // The last checkpoint's hash, its last digit changed.
    let bad_sum = {
        let body = sums.strip_suffix('\n').unwrap();
        let last = body.chars().last().unwrap();
        let other = if last == '0' { '1' } else { '0' };
        format!("{}{other}\n", &body[..body.len() - 1])
    };
    // The comment and the fingerprint line, then a line that is not a
    // checkpoint.
    let not_one = sums.lines().take(2).collect::<Vec<_>>().join("\n") + "\n0 12 zz\n";
    for (sum, words) in [
        (bad_sum.as_str(), "does not match its checksum in "),
        (
            not_one.as_str(),
            "sweep.csv.partial.sum:3: not a checkpoint",
        ),
    ] {
        setup(kept, sum);
        refused(&sweep(&part, &["--resume"]), &[words]);
    }
    // Past the last checkpoint: a fabricated row appended, a torn line.
    // Cut (with a note) and run again: the uninterrupted bytes.
    for tail in [
        lines[6].replace(",ok", ",failed") + "\n",
        lines[6][..9].to_string(),
    ] {
        setup(&format!("{kept}{tail}"), &sums);
        let o = bin()
            .args(&BASE[..BASE.len() - 1])
            .args(["--resume", "--out"])
            .arg(&part)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(
            err.contains("1 line after line 6 (after the last checkpoint) not verified"),
            "{err}"
        );
        assert!(err.contains("resuming: 5 of 9 cases kept"), "{err}");
        assert_eq!(read(&part.join("sweep.csv")), csv);
    }
    // No checkpoint file: nothing trusted, the sweep starts over.
    setup(kept, &sums);
    std::fs::remove_file(part.join("sweep.csv.partial.sum")).unwrap();
    std::fs::write(
        part.join("sweep.csv.partial"),
        edit(&|l| field(l, theta_final, "NaN")),
    )
    .unwrap();
    let o = sweep(&part, &["--resume"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(read(&part.join("sweep.csv")), csv);
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (B): a signal left the staging directory (with a partial
/// result file of up to 512 MB) and the lock file in `--out` until the
/// next command. Now SIGINT and SIGTERM remove both (the process still
/// dies of the signal), the partial files stay, and `--resume` ends with
/// the bytes of an uninterrupted run.
#[cfg(unix)]
#[test]
fn a_signal_removes_the_stage_and_the_lock() {
    use std::os::unix::process::ExitStatusExt;
    let d = scratch("signal");
    let args = [
        "sweep",
        "--preset",
        "classical",
        "--set",
        "solver.t_end=0.2",
        "--set",
        "solver.samples=11",
        "--vary",
        "top.offset=0.001:0.004:1000",
        "--quiet",
    ];
    let whole = d.join("whole");
    let o = bin().args(args).arg("--out").arg(&whole).output().unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let want = read(&whole.join("sweep.csv"));
    for sig in [libc::SIGINT, libc::SIGTERM] {
        let out = d.join(format!("out{sig}"));
        let mut cmd = bin();
        cmd.args(args).args(["--threads", "1", "--out"]).arg(&out);
        // A test run started in the background by a non-interactive shell
        // inherits SIGINT ignored (and tippetop keeps an ignored SIGINT
        // ignored): give the child the default action.
        // SAFETY: signal(2) is async-signal-safe; nothing else runs in the
        // forked child before exec.
        unsafe {
            std::os::unix::process::CommandExt::pre_exec(&mut cmd, || {
                libc::signal(libc::SIGINT, libc::SIG_DFL);
                Ok(())
            });
        }
        // A checkpoint at every row: at the default of one a second, a
        // fast machine finishes before the third checkpoint line.
        cmd.env("TIPPETOP_CHECKPOINT_SECONDS", "0");
        let mut child = cmd.spawn().unwrap();
        // Until rows are checkpointed.
        let sum = out.join("sweep.csv.partial.sum");
        let t0 = std::time::Instant::now();
        // The comment, the fingerprint and two checkpoints.
        while std::fs::read_to_string(&sum).map_or(0, |t| t.lines().count()) < 4 {
            assert!(child.try_wait().unwrap().is_none(), "the sweep ended early");
            assert!(t0.elapsed().as_secs() < 60, "no checkpoint after 60 s");
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
        assert!(out.join(".tippetop.lock").exists());
        assert!(names(&out).iter().any(|n| n == ".tippetop-stage"));
        // SAFETY: kill(2) of our own child.
        assert_eq!(unsafe { libc::kill(child.id() as libc::pid_t, sig) }, 0);
        let status = child.wait().unwrap();
        assert_eq!(status.signal(), Some(sig), "{status:?}");
        assert_eq!(
            names(&out),
            [
                ".tippetop-manifest",
                "shard.json.partial",
                "sweep.csv.partial",
                "sweep.csv.partial.sum"
            ],
            "signal {sig}"
        );
        let o = bin()
            .args(args)
            .args(["--resume", "--out"])
            .arg(&out)
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(read(&out.join("sweep.csv")), want);
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A signal during a commit waits for it: the files are all moved in and
/// listed, then the stage and the lock are removed and the process dies
/// of the signal. (The handler does the cleanup itself; without the wait
/// it would remove the stage with the files not yet moved.)
#[cfg(unix)]
#[test]
fn a_signal_during_the_commit_waits_for_its_end() {
    use std::os::unix::process::ExitStatusExt;
    let d = scratch("signal-commit");
    for sig in [libc::SIGTERM, libc::SIGHUP] {
        let out = d.join(format!("out{sig}"));
        let status = bin()
            .args(["run", "--preset", "classical", "--set", "solver.t_end=0.5"])
            .args(["--no-plot", "--quiet", "--out"])
            .arg(&out)
            .env("TIPPETOP_TEST_SIGNAL_IN_COMMIT", sig.to_string())
            .status()
            .unwrap();
        assert_eq!(status.signal(), Some(sig), "{status:?}");
        assert_eq!(
            names(&out),
            [
                ".tippetop-manifest",
                "scenario.toml",
                "summary.json",
                "trajectory.csv"
            ],
            "signal {sig}"
        );
        let manifest = read(&out.join(".tippetop-manifest"));
        for f in ["scenario.toml", "summary.json", "trajectory.csv"] {
            assert!(
                manifest.lines().any(|l| l.split('\t').next() == Some(f)),
                "{manifest}"
            );
        }
        let summary: serde_json::Value =
            serde_json::from_str(&read(&out.join("summary.json"))).unwrap();
        assert_eq!(summary["t_end"], 0.5);
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (D): an `--out` that is a file exited 2 for run and reproduce
/// but 1 for sweep, ensemble and bit. Now bad input (exit code 2, one line
/// naming it, nothing written) in every command, as is a path under a
/// file.
#[test]
fn out_that_is_a_file_is_bad_input() {
    let d = scratch("out-file");
    let file = d.join("file");
    std::fs::write(&file, "mine").unwrap();
    let hot = common::repo("scenarios/thermal.toml");
    let cmds: Vec<Vec<String>> = vec![
        BASE.iter().map(|s| s.to_string()).collect(),
        vec![
            "ensemble".into(),
            hot.display().to_string(),
            "--runs".into(),
            "2".into(),
        ],
        vec![
            "bit".into(),
            common::repo("scenarios/bit/nano.toml")
                .display()
                .to_string(),
        ],
        vec!["run".into(), "--preset".into(), "classical".into()],
        vec!["merge".into(), d.display().to_string()],
    ];
    for out in [file.clone(), file.join("sub")] {
        for args in &cmds {
            let o = bin().args(args).arg("--out").arg(&out).output().unwrap();
            // Every command names the option `--out` (`run` said `out`).
            refused(&o, &["--out: ", "file"]);
            assert_eq!(read(&file), "mine");
            assert_eq!(names(&d), ["file"], "{args:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// Issue 26 (C, D): `merge` accepted corrupted shard sets, said "sweep.csv
/// has 10 rows, not 10" for a file cut at its last line end, and could
/// write over one of its inputs. Now each shard's files must match the
/// checksums its shard.json records (written by the shard run), every row
/// must be a row of its case (also when someone recomputed the checksum),
/// the messages say what is wrong, and an --out that is an input is bad
/// input; exit code 2, nothing written.
#[test]
fn merge_checks_what_it_joins() {
    let d = scratch("merge-checks");
    let shards: Vec<PathBuf> = (1..=2)
        .map(|k| {
            let s = d.join(format!("s{k}"));
            assert!(sweep(&s, &["--shard", &format!("{k}/2")]).status.success());
            s
        })
        .collect();
    let whole = d.join("whole");
    assert!(sweep(&whole, &[]).status.success());
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
    // The shards as written merge into the bytes of a one-shot run, and
    // shard.json carries the same checksum.
    let good = d.join("good");
    let o = merge(&good);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        read(&good.join("sweep.csv")),
        read(&whole.join("sweep.csv"))
    );
    assert_eq!(
        read(&good.join("shard.json")),
        read(&whole.join("shard.json"))
    );
    let sum = format!(
        "{:016x}",
        fnv1a64(read(&whole.join("sweep.csv")).as_bytes())
    );
    assert!(read(&whole.join("shard.json")).contains(&sum));

    let csv_path = shards[1].join("sweep.csv");
    let json_path = shards[1].join("shard.json");
    let (csv, json) = (read(&csv_path), read(&json_path));
    let row = csv.lines().nth(2).unwrap();
    let nan = {
        let mut f: Vec<&str> = row.split(',').collect();
        f[2] = "NaN";
        f.join(",")
    };
    let mut no_sum: serde_json::Value = serde_json::from_str(&json).unwrap();
    no_sum.as_object_mut().unwrap().remove("checksums");
    let no_sum = serde_json::to_string(&no_sum).unwrap();
    let cut = csv.strip_suffix('\n').unwrap().to_string();
    let extra = csv.replace(row, &format!("{row},1"));
    let cases: Vec<(String, String, &str)> = vec![
        (
            csv.replace(row, &nan),
            json.clone(),
            "s2/sweep.csv: does not match its checksum in ",
        ),
        (
            csv.clone(),
            no_sum,
            "s2/shard.json: no checksum of sweep.csv",
        ),
        (
            extra.clone(),
            with_checksum(&json, "sweep.csv", extra.as_bytes()),
            "line 3 of sweep.csv is not case 6 (more fields than the header)",
        ),
        (
            cut.clone(),
            with_checksum(&json, "sweep.csv", cut.as_bytes()),
            "sweep.csv ends in the middle of its last row (line 5, no line end)",
        ),
    ];
    for (text, info, words) in &cases {
        std::fs::write(&csv_path, text).unwrap();
        std::fs::write(&json_path, info).unwrap();
        let out = d.join("out");
        refused(&merge(&out), &[words]);
        assert!(!out.exists(), "{words}");
    }
    std::fs::write(&csv_path, &csv).unwrap();
    std::fs::write(&json_path, &json).unwrap();
    // --out is one of the inputs: refused, the input untouched.
    refused(
        &merge(&shards[0]),
        &["--out: ", "one of the shard directories"],
    );
    assert_eq!(
        names(&shards[0]),
        [
            ".tippetop-manifest",
            ".tippetop-stage",
            "shard.json",
            "sweep.csv"
        ]
    );
    let _ = std::fs::remove_dir_all(&d);
}
