//! `tippetop run --no-pose` (issue #28 item 7): trajectory.csv without the
//! pose's nine columns, every other byte as the default run's; the default
//! output unchanged; `animate` refuses a run without the pose.

use std::fs;
use std::path::Path;

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

/// The fields of `trajectory.csv`, line by line.
fn fields(dir: &Path) -> Vec<Vec<String>> {
    fs::read_to_string(dir.join("trajectory.csv"))
        .unwrap()
        .lines()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

/// summary.json without the wall time (which differs between any two runs).
fn summary(dir: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
    v.as_object_mut().unwrap().remove("wall_seconds");
    v
}

/// For each model, with the exact law's stick/slip (classical, 3 s) and
/// the nano top: the `--no-pose` file is the default file less its last
/// nine columns (`tippetop::trajectory::POSE_COLUMNS`), byte for byte, and
/// the summaries agree.
#[test]
fn no_pose_writes_the_default_file_less_the_pose_columns() {
    let dir = tempfile::tempdir().unwrap();
    let pose = tippetop::trajectory::POSE_COLUMNS;
    let cases: [&[&str]; 4] = [
        &["--preset", "classical", "--set", "solver.t_end=3"],
        &["--preset", "nano", "--set", "solver.t_end=2e-5"],
        &[
            "--preset",
            "nano",
            "--set",
            "solver.t_end=2e-5",
            "--set",
            "solver.model=\"reduced\"",
        ],
        &[
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.3",
            "--set",
            "solver.model=\"rigid\"",
        ],
    ];
    for (i, args) in cases.iter().enumerate() {
        let (a, b) = (
            dir.path().join(format!("a{i}")),
            dir.path().join(format!("b{i}")),
        );
        for (out, extra) in [(&a, None), (&b, Some("--no-pose"))] {
            let mut c = tippetop();
            c.arg("run")
                .args(*args)
                .args(["--no-plot", "--quiet", "--out"]);
            c.arg(out);
            if let Some(x) = extra {
                c.arg(x);
            }
            c.assert().success();
        }
        let (fa, fb) = (fields(&a), fields(&b));
        assert_eq!(fa.len(), fb.len(), "{args:?}");
        assert!(fa.len() > 100, "{args:?}");
        let n = tippetop::trajectory::COLUMNS.len();
        assert_eq!(fa[0].len(), n);
        assert_eq!(fa[0][n - pose.len()..], pose.map(String::from)[..]);
        for (ra, rb) in fa.iter().zip(&fb) {
            assert_eq!(&ra[..n - pose.len()], &rb[..], "{args:?}");
        }
        assert_eq!(summary(&a), summary(&b), "{args:?}");
    }
}

/// `run --help` says what `--no-pose` leaves out and saves; `animate`
/// refuses a run written without the pose (one line, exit 2).
#[test]
fn no_pose_is_documented_and_animate_refuses_it() {
    let help = tippetop().args(["run", "--help"]).output().unwrap();
    let help = String::from_utf8(help.stdout).unwrap();
    assert!(help.contains("--no-pose"), "{help}");
    assert!(help.contains("10 state components instead of 17"), "{help}");
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("run");
    tippetop()
        .args(["run", "--preset", "classical", "--set", "solver.t_end=1"])
        .args(["--no-plot", "--quiet", "--no-pose", "--out"])
        .arg(&out)
        .assert()
        .success();
    let o = tippetop()
        .args([
            "animate",
            "--fps",
            "2",
            "--duration",
            "1",
            "--size",
            "64x64",
        ])
        .arg(&out)
        .output()
        .unwrap();
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(
        err.starts_with("error: ") && err.contains("--no-pose"),
        "{err}"
    );
    assert!(!out.join("animation.gif").exists());
}
