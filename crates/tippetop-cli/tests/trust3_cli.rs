//! Trust under attack, third round: what an adversary or a careless user
//! can do to the output directory and the budgets.
//!
//! - `--resume` never keeps the rows of another run whose partial CSV and
//!   checkpoint file were copied in beside this run's description (sweep,
//!   `bit --vary`, `bit --runs`, ensemble): the checkpoints name the run's
//!   fingerprint.
//! - A forged `.tippetop-manifest` cannot make a command remove a file it
//!   did not write.
//! - Every budget of `rare` is bounded before anything is allocated.
//!
//! `TIPPETOP_TEST_BIN=PATH` runs them against another build of `tippetop`.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

mod common;
use common::{HOT, NANO20, RARE, ok, refused};

/// The binary under test, or the one `TIPPETOP_TEST_BIN` names (to see
/// these tests fail on a build from before the fixes).
fn bin() -> Command {
    Command::new(
        std::env::var_os("TIPPETOP_TEST_BIN")
            .unwrap_or_else(|| env!("CARGO_BIN_EXE_tippetop").into()),
    )
}

fn scratch(name: &str) -> PathBuf {
    common::scratch("trust3", name)
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

/// Run `args` into `out`, checkpointing at every row, and kill it (SIGKILL)
/// once its checkpoint file `partial.sum` holds `rows` checkpoints or more:
/// the partial files a killed run leaves.
fn killed(args: &[&str], out: &Path, partial: &str, rows: usize) {
    let mut child = bin()
        .args(args)
        .args(["--threads", "1", "--quiet", "--out"])
        .arg(out)
        .env("TIPPETOP_CHECKPOINT_SECONDS", "0")
        .spawn()
        .unwrap();
    let sum = out.join(format!("{partial}.sum"));
    let t0 = Instant::now();
    loop {
        let n = std::fs::read_to_string(&sum).map_or(0, |t| {
            t.lines()
                .filter(|l| l.split(' ').count() >= 3 && !l.starts_with('#'))
                .count()
        });
        if n > rows {
            break;
        }
        assert!(
            child.try_wait().unwrap().is_none(),
            "{args:?} ended before {rows} checkpoints"
        );
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "no rows after 120 s"
        );
        std::thread::sleep(Duration::from_millis(2));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(out.join(partial).exists());
}

/// Two runs that differ in one key (`a`, `b`), each killed part-way; B's
/// partial CSV and its checkpoints copied into A's directory: `--resume` of
/// A refuses them (exit code 2, one line naming the checkpoint file and
/// the other run), and leaves every file as it was. (That a run's own
/// partial files resume is the kill-and-resume tests' part.)
fn foreign_partial_is_refused(tag: &str, base: &[&str], a: &str, b: &str, partial: &str) {
    let d = scratch(tag);
    let (da, db) = (d.join("a"), d.join("b"));
    let with = |set: &str| -> Vec<String> {
        let mut v: Vec<String> = base.iter().map(|s| s.to_string()).collect();
        v.extend(["--set".into(), set.into()]);
        v
    };
    let (args_a, args_b) = (with(a), with(b));
    let sa: Vec<&str> = args_a.iter().map(String::as_str).collect();
    let sb: Vec<&str> = args_b.iter().map(String::as_str).collect();
    killed(&sa, &da, partial, 3);
    killed(&sb, &db, partial, 3);
    let sum = format!("{partial}.sum");
    for name in [partial, sum.as_str()] {
        std::fs::copy(db.join(name), da.join(name)).unwrap();
    }
    let before: Vec<(String, String)> = [partial, sum.as_str()]
        .iter()
        .map(|n| (n.to_string(), read(&da.join(n))))
        .collect();
    let o = bin()
        .args(&sa)
        .args(["--resume", "--quiet", "--out"])
        .arg(&da)
        .output()
        .unwrap();
    refused(
        &o,
        &[
            "--resume: ",
            &format!("{sum}:2: the checkpoints of another"),
            "fingerprint",
        ],
    );
    for (n, text) in before {
        assert_eq!(read(&da.join(&n)), text, "{n} changed");
    }
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn another_sweeps_partial_rows_are_refused() {
    foreign_partial_is_refused(
        "sweep",
        &[
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.2",
            "--vary",
            "top.offset=0.001:0.004:1000",
        ],
        "solver.samples=51",
        "solver.samples=52",
        "sweep.csv.partial",
    );
}

#[test]
fn another_maps_partial_rows_are_refused() {
    let d = scratch("map-files");
    let f = d.join("nano20.toml");
    std::fs::write(&f, NANO20).unwrap();
    let f = f.to_string_lossy().into_owned();
    foreign_partial_is_refused(
        "map",
        &["bit", &f, "--vary", "write.0.hy=0:1e-21:2000"],
        "solver.samples=81",
        "solver.samples=82",
        "bitmap.csv.partial",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn another_bit_ensembles_partial_rows_are_refused() {
    let d = scratch("runs-files");
    let f = d.join("hot.toml");
    std::fs::write(&f, HOT).unwrap();
    let f = f.to_string_lossy().into_owned();
    foreign_partial_is_refused(
        "runs",
        &["bit", &f, "--runs", "20000"],
        "solver.samples=201",
        "solver.samples=202",
        "runs.csv.partial",
    );
    let _ = std::fs::remove_dir_all(&d);
}

#[test]
fn another_ensembles_partial_rows_are_refused() {
    foreign_partial_is_refused(
        "ensemble",
        &[
            "ensemble",
            "--preset",
            "nano-physical",
            "--set",
            "solver.t_end=2e-12",
            "--runs",
            "100000",
        ],
        "solver.samples=51",
        "solver.samples=52",
        "ensemble.csv.partial",
    );
}

/// A forged `.tippetop-manifest` naming a file of the user's: no
/// subcommand removes it (it was not written by tippetop: no size and
/// hash recorded), each says so in one note, and the new manifest no
/// longer lists it.
#[test]
fn a_forged_manifest_removes_nothing() {
    let d = scratch("forged");
    let cases: &[&[&str]] = &[
        &[
            "run",
            "--preset",
            "nano",
            "--set",
            "solver.t_end=1e-7",
            "--no-plot",
        ],
        &[
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.01",
            "--vary",
            "initial.spin=60:150:2",
        ],
        &[
            "ensemble",
            "--preset",
            "nano-physical",
            "--set",
            "solver.t_end=2e-13",
            "--runs",
            "2",
        ],
        &["adhesion"],
        &["regime", "--preset", "nano"],
        &["reproduce"],
    ];
    for (k, args) in cases.iter().enumerate() {
        let out = d.join(format!("out{k}"));
        std::fs::create_dir_all(&out).unwrap();
        std::fs::write(out.join("user_file.txt"), "mine\n").unwrap();
        // A forged line with a record, too: the size is right, the hash
        // is not the file's.
        std::fs::write(out.join("notes.md"), "my notes\n").unwrap();
        std::fs::write(
            out.join(".tippetop-manifest"),
            format!(
                "# tippetop: x\n# command: {}\nuser_file.txt\nnotes.md\t9\t0123456789abcdef\n",
                args[0]
            ),
        )
        .unwrap();
        let o = bin().args(*args).arg("--out").arg(&out).output().unwrap();
        if !o.status.success() {
            // A command that writes no directory (regime prints): skip.
            assert_eq!(o.status.code(), Some(2), "{args:?}");
            continue;
        }
        assert_eq!(read(&out.join("user_file.txt")), "mine\n", "{args:?}");
        assert_eq!(read(&out.join("notes.md")), "my notes\n", "{args:?}");
        let err = String::from_utf8_lossy(&o.stderr);
        for f in ["user_file.txt", "notes.md"] {
            assert_eq!(
                err.lines()
                    .filter(|l| l.starts_with("note: ")
                        && l.contains(f)
                        && l.ends_with("left alone"))
                    .count(),
                1,
                "{args:?}: {err}"
            );
        }
        let manifest = read(&out.join(".tippetop-manifest"));
        assert!(!manifest.contains("user_file.txt"), "{manifest}");
        assert!(!manifest.contains("notes.md"), "{manifest}");
    }
    let _ = std::fs::remove_dir_all(&d);
}

/// A file tippetop wrote is removed by the next command that does not
/// write it when it is as it was written; once the user has changed it
/// (here: appended a line), it is theirs and stays, with a note.
#[test]
fn a_changed_output_is_left_and_an_unchanged_one_removed() {
    let d = scratch("changed");
    let out = d.join("out");
    let run = |extra: &[&str]| {
        bin()
            .args(["run", "--preset", "nano", "--set", "solver.t_end=1e-7"])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap()
    };
    ok(&run(&[]));
    assert!(out.join("theta.svg").exists() && out.join("spin.svg").exists());
    let mut svg = read(&out.join("theta.svg"));
    svg.push_str("<!-- my annotation -->\n");
    std::fs::write(out.join("theta.svg"), &svg).unwrap();
    let o = run(&["--no-plot"]);
    ok(&o);
    assert!(
        !out.join("spin.svg").exists(),
        "an unchanged stale output stays"
    );
    assert_eq!(read(&out.join("theta.svg")), svg);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("theta.svg: listed in")
            && err.contains("its size or bytes are not those recorded"),
        "{err}"
    );
    let _ = std::fs::remove_dir_all(&d);
}

/// Every budget of `rare --method ams` is checked before anything is
/// allocated or written: a count past its bound, or sizes whose memory
/// (the particles of the replicas running at once, the records of all)
/// would pass the command's memory bound, exits 2 with one line naming
/// the flag and its range, and `--out` is not created. (One billion
/// replicas aborted with a failed 232 GB allocation, exit 134, a lock and
/// a stage left behind.)
#[test]
fn rare_budgets_are_bounded_before_allocating() {
    let d = scratch("rare-budgets");
    for (k, (extra, words)) in [
        (
            &["--replicas", "1000000000"][..],
            &["--replicas", "2 <= M <= 100000"][..],
        ),
        (
            &["--replicas", "50000"],
            &["--replicas", "of records", "at most 3.221 GB"],
        ),
        (&["--max-trajectories", "16777201"], &["--max-trajectories"]),
        (
            &["--particles", "100000"],
            &["--particles", "2 <= n <= 30000"],
        ),
        (&["--particles", "30000", "--kill", "30000"], &["--kill"]),
        (&["--max-steps", "1000000000000"], &["--max-steps"]),
    ]
    .into_iter()
    .enumerate()
    {
        let out = d.join(format!("out{k}"));
        let o = bin()
            .args(RARE)
            .args(["--method", "ams"])
            .args(extra)
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        refused(&o, words);
        assert!(!out.exists(), "{extra:?}: --out written");
    }
    let _ = std::fs::remove_dir_all(&d);
}
