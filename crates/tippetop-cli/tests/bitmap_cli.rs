//! `tippetop bit --vary` end to end (issue #16 item 4, design maps): every
//! row equals a single `tippetop bit --set` run of its grid point (at T = 0
//! and at T > 0, where every point uses the same (seed, run) streams),
//! threads and shards do not change the bytes, `--resume` ends with the
//! bytes of an uninterrupted run, and bad `--vary` input exits with code 2,
//! one line naming the key, nothing written.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_tippetop"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("tippetop-bitmap-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn ok(o: &Output) {
    assert!(
        o.status.success(),
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    );
}

/// The nano top's bit with 20 µs phases (the issue's map preset): the
/// paper's force, its reversal as the erase.
const NANO20: &str = r#"preset = "nano"
[solver]
samples = 81
[bit]
hold = 5e-6
phase = 2e-5
[[write]]
hx = 1e-22
hy = 1e-22
[[erase]]
hx = -1e-22
hy = -1e-22
"#;

/// A Langevin bit of 2000 steps per run (as in bit_cli.rs).
const HOT: &str = r#"preset = "nano"
[surface]
friction = 0.0
[solver]
method = "langevin"
dt = 1e-14
samples = 201
[thermal]
temperature = 300.0
damping_translational = 1e11
damping_rotational = 1e11
seed = 7
[bit]
hold = 2e-12
phase = 1e-11
[[write]]
hx = 3e-11
hy = 3e-11
stop = 5e-12
[[erase]]
hx = -3e-11
hy = -3e-11
stop = 5e-12
"#;

fn bit(d: &Path, file: &str, out: &str, extra: &[&str]) -> Output {
    bin()
        .arg("bit")
        .arg(d.join(file))
        .args(extra)
        .arg("--quiet")
        .arg("--out")
        .arg(d.join(out))
        .output()
        .unwrap()
}

/// `bitmap.csv` as (header, rows of fields).
fn table(p: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(p).unwrap();
    let mut lines = text.lines();
    let head = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_string)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    (head, rows)
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// Every figure of `bit.json` equals the map row's field, bit for bit
/// (floats parsed from both files; counts as integers; missing = empty).
fn same_as_bit_json(head: &[String], row: &[String], b: &serde_json::Value) {
    let field = |name: &str| {
        let i = head.iter().position(|h| h == name).unwrap();
        row[i].as_str()
    };
    let num = |s: &str| (!s.is_empty()).then(|| s.parse::<f64>().unwrap().to_bits());
    let js = |v: &serde_json::Value| v.as_f64().map(f64::to_bits);
    for blk in ["write", "erase", "erase_given_write", "cycle"] {
        let x = &b[blk];
        for f in [
            "probability",
            "time_median",
            "time_q25",
            "time_q75",
            "energy_median",
            "max_applied_force",
        ] {
            assert_eq!(num(field(&format!("{blk}_{f}"))), js(&x[f]), "{blk}_{f}");
        }
        for f in ["runs", "successes"] {
            assert_eq!(field(&format!("{blk}_{f}")), x[f].to_string(), "{blk}_{f}");
        }
        for (k, f) in ["ci_lo", "ci_hi"].into_iter().enumerate() {
            assert_eq!(num(field(&format!("{blk}_{f}"))), js(&x["ci95"][k]), "{f}");
        }
        for (mode, n) in x["failures"].as_object().unwrap() {
            assert_eq!(field(&format!("{blk}_{mode}")), n.to_string(), "{mode}");
        }
    }
    assert_eq!(field("runs"), b["runs"].to_string());
    assert_eq!(field("deterministic"), b["deterministic"].to_string());
    assert_eq!(
        num(field("pull_off_margin_min")),
        js(&b["pull_off_margin_min"])
    );
    assert_eq!(field("status"), "ok");
}

/// A 3 x 2 map over the write force and the hold at T = 0: each row is
/// the single deterministic `tippetop bit --set` run of its point. Not
/// vacuous: H_y = 0 (only H_x = 0.1 zN) never writes within 20 µs and
/// H_y = 1 zN does (probabilities 0 and 1 both occur).
#[test]
fn map_rows_are_the_single_runs_of_their_points() {
    let d = scratch("t0");
    std::fs::write(d.join("nano20.toml"), NANO20).unwrap();
    let o = bit(
        &d,
        "nano20.toml",
        "map",
        &[
            "--vary",
            "write.0.hy=0:1e-21:3",
            "--vary",
            "bit.hold=5e-6:6e-6:2",
        ],
    );
    ok(&o);
    let (head, rows) = table(&d.join("map/bitmap.csv"));
    assert_eq!(rows.len(), 6);
    assert_eq!(&head[..2], ["write.0.hy", "bit.hold"]);
    let mut seen = std::collections::BTreeSet::new();
    for row in &rows {
        let sets = [
            "--set".to_string(),
            format!("write.0.hy={}", row[0]),
            "--set".to_string(),
            format!("bit.hold={}", row[1]),
        ];
        let sets: Vec<&str> = sets.iter().map(String::as_str).collect();
        ok(&bit(&d, "nano20.toml", "one", &sets));
        same_as_bit_json(&head, row, &json(&d.join("one/bit.json")));
        let p = head.iter().position(|h| h == "write_probability").unwrap();
        seen.insert(row[p].clone());
    }
    assert!(seen.contains("0.0") && seen.contains("1.0"), "{seen:?}");
    for f in ["write_probability.png", "write_time.svg", "shard.json"] {
        assert!(d.join("map").join(f).is_file(), "{f}");
    }
    // A point whose scenario is invalid (hold 4 us: 8 rows per hold) gets
    // the error in status and empty figures; the map goes on.
    ok(&bit(
        &d,
        "nano20.toml",
        "part",
        &["--vary", "bit.hold=4e-6:5e-6:2"],
    ));
    let (head, rows) = table(&d.join("part/bitmap.csv"));
    assert!(
        rows[0].last().unwrap().starts_with("solver.samples"),
        "{rows:?}"
    );
    assert_eq!(rows[0][1], "");
    assert_eq!(rows[1].last().unwrap(), "ok");
    assert_eq!(rows[0].len(), head.len());
    assert!(d.join("part/bitmap.png").is_file());
}

/// At T > 0 each point is an ensemble whose run K uses thermal.run = K at
/// every point (common random numbers): a point's row equals `tippetop
/// bit --runs N --set ...` of that point. Threads (1, 2) and shards (1/3,
/// 2/3, 3/3 merged in any order) give the same bitmap.csv and shard.json
/// bytes; a point at T = 0 is one deterministic run.
#[test]
fn ensembles_per_point_threads_shards_and_merge() {
    let d = scratch("hot");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    let map = |out: &str, extra: &[&str]| {
        let mut args = vec![
            "--runs",
            "6",
            "--vary",
            "write.0.hx=1e-11:5e-11:3",
            "--vary",
            "thermal.temperature=0:300:2",
        ];
        args.extend_from_slice(extra);
        bit(&d, "hot.toml", out, &args)
    };
    ok(&map("t1", &["--threads", "1"]));
    ok(&map("t2", &["--threads", "2"]));
    for k in 1..=3 {
        ok(&map(&format!("s{k}"), &["--shard", &format!("{k}/3")]));
    }
    let o = bin()
        .arg("merge")
        .args([d.join("s3"), d.join("s1"), d.join("s2")])
        .arg("--quiet")
        .arg("--out")
        .arg(d.join("merged"))
        .output()
        .unwrap();
    ok(&o);
    for f in ["bitmap.csv", "shard.json"] {
        let one = std::fs::read(d.join("t1").join(f)).unwrap();
        assert_eq!(one, std::fs::read(d.join("t2").join(f)).unwrap(), "{f}");
        assert_eq!(one, std::fs::read(d.join("merged").join(f)).unwrap(), "{f}");
    }
    // A shard holds its block only: 6 points in 3 shards of 2.
    assert_eq!(table(&d.join("s2/bitmap.csv")).1.len(), 2);
    let (head, rows) = table(&d.join("t1/bitmap.csv"));
    let det = head.iter().position(|h| h == "deterministic").unwrap();
    let runs = head.iter().position(|h| h == "runs").unwrap();
    for row in &rows {
        let cold = row[1] == "0.0";
        assert_eq!(row[det], cold.to_string(), "{row:?}");
        assert_eq!(row[runs], if cold { "1" } else { "6" }, "{row:?}");
    }
    // The hot points are the single ensembles of their points.
    for row in rows.iter().filter(|r| r[1] != "0.0") {
        let hx = format!("write.0.hx={}", row[0]);
        ok(&bit(
            &d,
            "hot.toml",
            "one",
            &[
                "--runs",
                "6",
                "--set",
                &hx,
                "--set",
                "thermal.temperature=300.0",
            ],
        ));
        same_as_bit_json(&head, row, &json(&d.join("one/bit.json")));
    }
}

/// `--resume` keeps the complete rows of bitmap.csv.partial (a torn last
/// line is cut) and ends with the bytes of an uninterrupted run; on
/// another map's partial files it exits with code 2.
#[test]
fn resume_ends_with_the_same_bytes() {
    let d = scratch("resume");
    std::fs::write(d.join("nano20.toml"), NANO20).unwrap();
    let args = ["--vary", "write.0.hy=0:1e-21:4", "--threads", "1"];
    ok(&bit(&d, "nano20.toml", "full", &args));
    let full = std::fs::read_to_string(d.join("full/bitmap.csv")).unwrap();
    let info = std::fs::read_to_string(d.join("full/shard.json")).unwrap();
    // An interrupted run: the header, two rows and half of the third.
    let cut: usize = full
        .split_inclusive('\n')
        .take(3)
        .map(str::len)
        .sum::<usize>()
        + 10;
    let part = d.join("part");
    std::fs::create_dir_all(&part).unwrap();
    std::fs::write(part.join("bitmap.csv.partial"), &full[..cut]).unwrap();
    std::fs::write(part.join("shard.json.partial"), &info).unwrap();
    let mut resumed = args.to_vec();
    resumed.push("--resume");
    ok(&bit(&d, "nano20.toml", "part", &resumed));
    assert_eq!(
        std::fs::read_to_string(part.join("bitmap.csv")).unwrap(),
        full
    );
    // Another map's partial files: exit 2.
    std::fs::write(part.join("bitmap.csv.partial"), &full[..cut]).unwrap();
    std::fs::write(part.join("shard.json.partial"), &info).unwrap();
    let other = ["--vary", "write.0.hy=0:1e-21:5", "--resume"];
    let o = bit(&d, "nano20.toml", "part", &other);
    assert_eq!(o.status.code(), Some(2), "{o:?}");
    assert!(String::from_utf8_lossy(&o.stderr).contains("another map"));
}

/// Exit 2, one stderr line starting with `error: KEY`, nothing written.
#[test]
fn bad_vary_names_the_key() {
    let d = scratch("bad");
    std::fs::write(d.join("nano20.toml"), NANO20).unwrap();
    for (vary, key) in [
        ("write.0.hw=0:1:2", "write.0.hw"),
        ("bit.foo=0:1:2", "bit.foo"),
        ("top.nosuch=0:1:2", "top.nosuch"),
        ("write.3.hy=0:1e-22:2", "write.3.hy"),
        ("force.0.hx=0:1e-22:2", "force.0.hx"),
        ("write.0.hy=0:1e-22:0", "write.0.hy"),
        ("write.0.hy=0:x:3", "write.0.hy"),
        // Every stop beyond the 20 us phase: no point is valid.
        ("write.0.stop=3e-5:4e-5:3", "write.0.stop"),
        ("bit.hold=-1:0:2", "bit.hold"),
        ("thermal.temperature=-5:-1:2", "thermal.temperature"),
    ] {
        let out = d.join("out");
        let o = bin()
            .arg("bit")
            .arg(d.join("nano20.toml"))
            .args(["--vary", vary, "--out"])
            .arg(&out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{vary}: {err}");
        assert_eq!(err.lines().count(), 1, "{vary}: {err}");
        assert!(err.starts_with(&format!("error: {key}")), "{vary}: {err}");
        assert!(!out.exists(), "{vary}: wrote {}", out.display());
    }
    // --resume belongs to a map.
    let o = bin()
        .arg("bit")
        .arg(d.join("nano20.toml"))
        .arg("--resume")
        .arg("--out")
        .arg(d.join("out"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(!d.join("out").exists());
}

/// A single bit ensemble at T > 0 cut into shards of its runs (`--runs N
/// --shard K/M`): `tippetop merge` of the shards (any order) writes the
/// bytes of the unsharded run (bit.json, bit.md, runs.csv, bit.toml,
/// scenario.toml, the figure). Shards of another ensemble (other --runs)
/// do not merge; --shard of a bit at T = 0 is bad input.
#[test]
fn bit_ensemble_shards_merge_to_the_unsharded_bytes() {
    let d = scratch("eshards");
    std::fs::write(d.join("hot.toml"), HOT).unwrap();
    ok(&bit(&d, "hot.toml", "all", &["--runs", "10"]));
    for k in 1..=3 {
        let sh = format!("{k}/3");
        ok(&bit(
            &d,
            "hot.toml",
            &format!("s{k}"),
            &["--runs", "10", "--shard", &sh],
        ));
    }
    assert_eq!(
        std::fs::read_to_string(d.join("s2/runs.csv"))
            .unwrap()
            .lines()
            .count(),
        4
    );
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
    ok(&merge(&["s3", "s1", "s2"], "merged"));
    for f in [
        "bit.json",
        "bit.md",
        "runs.csv",
        "bit.toml",
        "scenario.toml",
        "theta.svg",
    ] {
        assert_eq!(
            std::fs::read(d.join("all").join(f)).unwrap(),
            std::fs::read(d.join("merged").join(f)).unwrap(),
            "{f}"
        );
    }
    // A gap, and a shard of another ensemble: exit 2, nothing written.
    let o = merge(&["s1", "s3"], "gap");
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("missing"));
    ok(&bit(
        &d,
        "hot.toml",
        "other",
        &["--runs", "9", "--shard", "2/3"],
    ));
    let o = merge(&["s1", "other", "s3"], "mixed");
    assert_eq!(o.status.code(), Some(2));
    assert!(!d.join("mixed").exists() && !d.join("gap").exists());
    // At T = 0 a bit is one run.
    std::fs::write(d.join("nano20.toml"), NANO20).unwrap();
    let o = bit(&d, "nano20.toml", "cold", &["--shard", "1/2"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).starts_with("error: --shard"));
    assert!(!d.join("cold").exists());
}
