//! Issue 26 ("Trust under attack"), end to end: input files have a size
//! limit, `retention` checks what it reads, usage errors and durations are
//! printed as everything else, numbers are decimal, a scale overflow names
//! the key that caused it, and every documented limit is either within its
//! memory bound or refused up front.

mod common;

use std::io::Write as _;
use std::path::Path;
use std::process::{Command, Output, Stdio};

use common::{bin, ok, scratch};

/// Exit 2, exactly one stderr line starting with `error: {prefix}`,
/// nothing on stdout.
fn one_line_error(o: &Output, prefix: &str) -> String {
    let stderr = String::from_utf8_lossy(&o.stderr).into_owned();
    assert_eq!(o.status.code(), Some(2), "{stderr}");
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "{stderr:?}");
    assert!(
        lines[0].starts_with(&format!("error: {prefix}")),
        "{stderr:?} does not start with error: {prefix}"
    );
    assert!(
        o.stdout.is_empty(),
        "{}",
        String::from_utf8_lossy(&o.stdout)
    );
    lines[0].to_string()
}

fn run(args: &[&str]) -> Output {
    bin().args(args).output().unwrap()
}

// ---------------------------------------------------------------------------
// Input files: at most 16 MiB.

/// `run /dev/zero` used to read until memory ran out: it is refused after
/// 16 MiB + 1 byte, naming the file and the limit; nothing is written.
#[test]
fn a_device_as_scenario_is_refused_at_the_limit() {
    let d = scratch("trust", "devzero");
    let out = d.join("o");
    let o = bin()
        .args(["run", "/dev/zero", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let line = one_line_error(&o, "/dev/zero: ");
    assert!(line.contains("16 MiB"), "{line}");
    assert!(!out.exists());
    let _ = std::fs::remove_dir_all(&d);
}

/// A file one byte over 16 MiB is refused by every command that reads a
/// scenario file; exactly 16 MiB of TOML (a comment) is read (and then
/// fails for what it lacks, not for its size).
#[test]
fn scenario_files_over_16_mib_are_refused() {
    let d = scratch("trust", "bigfile");
    let limit = 16usize << 20;
    let big = d.join("big.toml");
    let mut text = String::from("preset = \"classical\"\n#");
    text.push_str(&"x".repeat(limit + 1 - text.len()));
    std::fs::write(&big, &text).unwrap();
    assert_eq!(std::fs::metadata(&big).unwrap().len(), limit as u64 + 1);
    let b = big.to_str().unwrap();
    let o = d.join("o");
    let o = o.to_str().unwrap();
    for args in [
        vec!["run", b, "--out", o],
        vec!["sweep", b, "--vary", "top.offset=1e-3:2e-3:2", "--out", o],
        vec!["ensemble", b, "--runs", "2", "--out", o],
        vec!["stability", b],
        vec!["regime", b],
        vec!["bit", b, "--out", o],
    ] {
        let line = one_line_error(&run(&args), &format!("{b}: "));
        assert!(line.contains("16 MiB"), "{args:?}: {line}");
        assert!(!Path::new(o).exists(), "{args:?}");
    }
    // Exactly at the limit: read, and the run goes on (classical preset,
    // shortened), so the size itself is fine.
    text.truncate(limit - 1);
    text.push('\n');
    std::fs::write(&big, &text).unwrap();
    assert_eq!(std::fs::metadata(&big).unwrap().len(), limit as u64);
    ok(&run(&[
        "run",
        b,
        "--set",
        "solver.t_end=0.01",
        "--no-plot",
        "--quiet",
        "--out",
        o,
    ]));
    let _ = std::fs::remove_dir_all(&d);
}

/// A pipe that never ends (`yes`) is caught at the limit too.
#[test]
fn an_endless_pipe_is_refused() {
    let d = scratch("trust", "pipe");
    let mut yes = Command::new("yes")
        .arg("# a comment line")
        .stdout(Stdio::piped())
        .spawn()
        .unwrap();
    let stdin = yes.stdout.take().unwrap();
    let o = bin()
        .args(["run", "/dev/stdin", "--out"])
        .arg(d.join("o"))
        .stdin(stdin)
        .output()
        .unwrap();
    let _ = yes.kill();
    let _ = yes.wait();
    let line = one_line_error(&o, "/dev/stdin: ");
    assert!(line.contains("16 MiB"), "{line}");
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------
// retention: what it reads is checked.

/// An ensemble's summary.json with the three values retention reads.
fn summary(dir: &Path, temperature: &str, rate: &str, se: &str) {
    std::fs::create_dir_all(dir).unwrap();
    let mut f = std::fs::File::create(dir.join("summary.json")).unwrap();
    write!(
        f,
        "{{\"temperature\": {temperature}, \"first_passage\": {{\"escape_rate\": {{\"rate\": {rate}, \"ln_rate_se\": {se}}}}}}}"
    )
    .unwrap();
}

/// A temperature of 1e308 K used to give exit 0 and a retention of
/// "inf s"; values out of range, of the wrong type, missing or
/// unparseable are now one line naming the file and the field, exit 2,
/// and nothing is written. Two valid points still give the closed form
/// (two temperatures: the fit is exact, `ln k = ln k1 − E (1/kT − 1/kT1)`).
#[test]
fn retention_checks_its_inputs() {
    let d = scratch("trust", "retention");
    let (a, b) = (d.join("a"), d.join("b"));
    summary(&b, "2000", "1e5", "0.1");
    let out = d.join("out");
    let go = |extra: &[&str]| {
        bin()
            .arg("retention")
            .arg(&a)
            .arg(&b)
            .args(["--out"])
            .arg(&out)
            .args(extra)
            .output()
            .unwrap()
    };
    let file = a.join("summary.json").display().to_string();
    for (t, k, se, field) in [
        ("1e308", "1e3", "0.1", "temperature"),
        ("-5", "1e3", "0.1", "temperature"),
        ("0", "1e3", "0.1", "temperature"),
        ("1000", "0", "0.1", "first_passage.escape_rate.rate"),
        ("1000", "1e308", "0.1", "first_passage.escape_rate.rate"),
        ("1000", "1e3", "0", "first_passage.escape_rate.ln_rate_se"),
        ("1000", "1e3", "7", "first_passage.escape_rate.ln_rate_se"),
        ("\"hot\"", "1e3", "0.1", "temperature"),
        ("1000", "[1]", "0.1", "first_passage.escape_rate.rate"),
    ] {
        summary(&a, t, k, se);
        let line = one_line_error(
            &go(&["--temperature", "300"]),
            &format!("{file}: {field}: "),
        );
        assert!(!line.contains("RatePoint"), "{line}");
        assert!(!line.contains("--rates"), "{line}");
        assert!(!out.exists());
    }
    // Not JSON, and no escape rate at all.
    std::fs::write(a.join("summary.json"), "{").unwrap();
    one_line_error(&go(&["--temperature", "300"]), &format!("{file}: "));
    std::fs::write(a.join("summary.json"), "{\"temperature\": 1000}").unwrap();
    one_line_error(
        &go(&["--temperature", "300"]),
        &format!("{file}: first_passage.escape_rate: "),
    );
    // One temperature twice: the directories are named, not an option.
    summary(&a, "2000", "1e5", "0.1");
    one_line_error(&go(&["--temperature", "300"]), "DIR: ");
    // The target: in range, and an extrapolation that f64 can hold.
    summary(&a, "1000", "1e3", "0.1");
    for t in ["1e308", "0", "-1", "nan"] {
        one_line_error(&go(&["--temperature", t]), "--temperature: ");
    }
    one_line_error(&go(&["--temperature", "0.001"]), "--temperature: ");
    assert!(!out.exists());
    // Valid: the closed form of the two-point fit.
    ok(&go(&["--temperature", "300", "--quiet"]));
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("retention.json")).unwrap())
            .unwrap();
    let kb = 1.380649e-23;
    let (x1, x2, x) = (1.0 / (kb * 1000.0), 1.0 / (kb * 2000.0), 1.0 / (kb * 300.0));
    let e = (1e5f64 / 1e3).ln() / (x1 - x2);
    let want = 1e3 * (-e * (x - x1)).exp();
    let got = r["target"]["rate"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------
// Messages.

/// clap's usage errors took five lines (error, tip, usage, help pointer);
/// now one, `error: ... (see tippetop SUB --help)`, exit 2, for every
/// subcommand; `--help` and `--version` still print to stdout with exit 0.
#[test]
fn usage_errors_are_one_line() {
    for (args, sub) in [
        (vec!["run", "--preset", "classical", "--ou", "x"], "run"),
        (vec!["sweep", "--vary"], "sweep"),
        (
            vec!["ensemble", "scenarios/thermal.toml", "--out", "x"],
            "ensemble",
        ),
        (vec!["ensemble", "--runs", "-3", "--out", "x"], "ensemble"),
        (vec!["retention", "a", "--temperature", "warm"], "retention"),
        (vec!["bit", "--threads", "many"], "bit"),
        (vec!["animate"], "animate"),
        (vec!["run", "--preset", "nano", "--set"], "run"),
    ] {
        let o = run(&args);
        let line = one_line_error(&o, "");
        assert!(
            line.ends_with(&format!("(see tippetop {sub} --help)")),
            "{args:?}: {line}"
        );
        assert!(!line.contains("Usage"), "{line}");
    }
    let line = one_line_error(&run(&["frobnicate"]), "unrecognized subcommand");
    assert!(line.ends_with("(see tippetop --help)"), "{line}");
    // A tip clap has is kept, on the same line.
    let line = one_line_error(&run(&["run", "--preset", "classical", "--ou", "x"]), "");
    assert!(
        line.contains("tip: a similar argument exists: '--out'"),
        "{line}"
    );
    for args in [vec!["--help"], vec!["run", "--help"], vec!["--version"]] {
        let o = run(&args);
        assert_eq!(o.status.code(), Some(0), "{args:?}");
        assert!(!o.stdout.is_empty() && o.stderr.is_empty(), "{args:?}");
    }
}

/// A one-case sweep printed "in 0.0 s": durations now have three
/// significant figures (in ms below a second), wherever they are printed.
#[test]
fn short_durations_are_not_zero() {
    let d = scratch("trust", "duration");
    let dur = |stdout: &[u8], before: &str| -> String {
        let text = String::from_utf8_lossy(stdout).into_owned();
        let at = text
            .find(before)
            .unwrap_or_else(|| panic!("{before:?} not in {text}"));
        text[at + before.len()..]
            .split_whitespace()
            .take(2)
            .collect::<Vec<_>>()
            .join(" ")
    };
    let check = |d: &str| {
        let (num, unit) = d.split_once(' ').unwrap();
        let x: f64 = num.parse().unwrap_or_else(|_| panic!("{d}"));
        assert!(x > 0.0, "{d}");
        assert!(unit == "ms" || unit == "s", "{d}");
        let digits = num.chars().filter(char::is_ascii_digit).collect::<String>();
        assert_eq!(
            digits.trim_start_matches('0').len(),
            3,
            "{d}: three significant figures"
        );
    };
    let o = bin()
        .args([
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.01",
            "--vary",
            "top.offset=1e-3:2e-3:1",
            "--out",
        ])
        .arg(d.join("s"))
        .output()
        .unwrap();
    ok(&o);
    check(&dur(&o.stdout, "1 cases (1 ok, 0 failed) in "));
    let o = bin()
        .args([
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=0.01",
            "--no-plot",
            "--out",
        ])
        .arg(d.join("r"))
        .output()
        .unwrap();
    ok(&o);
    check(&dur(&o.stdout, "wall time:"));
    let o = bin()
        .args([
            "ensemble",
            "--preset",
            "nano-physical",
            "--set",
            "solver.t_end=1e-13",
            "--set",
            "solver.samples=2",
            "--runs",
            "1",
            "--out",
        ])
        .arg(d.join("e"))
        .output()
        .unwrap();
    ok(&o);
    check(&dur(&o.stdout, "1 runs (1 ok, 0 failed) in "));
    let _ = std::fs::remove_dir_all(&d);
}

/// `0x10` was accepted as 16 m: numbers are decimal, in files and in
/// `--set`, and the error names the key (force windows by index).
#[test]
fn non_decimal_numbers_are_refused() {
    let d = scratch("trust", "hex");
    let out = d.join("o");
    let o = out.to_str().unwrap();
    for (set, key) in [
        ("top.radius=0x10", "top.radius"),
        ("top.radius=0o20", "top.radius"),
        ("surface.friction=0b1", "surface.friction"),
        ("solver.samples=0x3e9", "solver.samples"),
        ("force.0.hx=0x1", "force.0.hx"),
        ("initial.axis=[0, 0x1, 1]", "initial.axis"),
    ] {
        let line = one_line_error(
            &run(&["run", "--preset", "classical", "--set", set, "--out", o]),
            &format!("{key}: "),
        );
        assert!(line.contains("decimal"), "{line}");
        assert!(!out.exists());
    }
    let file = d.join("hex.toml");
    for (text, key) in [
        (
            "preset = \"classical\"\n[top]\nradius = 0x10\n",
            "top.radius",
        ),
        (
            "preset = \"nano\"\n[[force]]\nhx = 0\n[[force]]\nhy = 0o7\n",
            "force.1.hy",
        ),
        (
            "preset = \"classical\"\n[solver]\nsamples = 0b1111101001\n",
            "solver.samples",
        ),
    ] {
        std::fs::write(&file, text).unwrap();
        let line = one_line_error(
            &run(&["run", file.to_str().unwrap(), "--out", o]),
            &format!("{key}: "),
        );
        assert!(line.contains("decimal"), "{line}");
    }
    // Decimal digits with TOML's separators, and a string that looks like
    // hex, are fine.
    std::fs::write(
        &file,
        "preset = \"classical\"\n[solver]\nsamples = 1_001\nt_end = 0.01\nmethod = \"adaptive\" # 0x10\n",
    )
    .unwrap();
    ok(&run(&[
        "run",
        file.to_str().unwrap(),
        "--no-plot",
        "--quiet",
        "--out",
        o,
    ]));
    let _ = std::fs::remove_dir_all(&d);
}

// ---------------------------------------------------------------------------
// Limits: within the memory bound, or refused up front with the figure.

fn repo_file(path: &str) -> String {
    common::repo(path).to_str().unwrap().to_string()
}

/// The reproducer: an ensemble of runs of 5 000 000 samples aborted (exit
/// 134) allocating 8 GB for its histograms. Refused up front, exit 2, one
/// line with the figure: 3 quantities × (64 bins + 3) counts × 8 bytes +
/// the time (16) = 1624 bytes per sample, 8.12 GB; at the ensemble's limit
/// (100 000 samples) it runs, and writes the histograms of every sample.
#[test]
fn ensemble_limits_are_refused_up_front() {
    let d = scratch("trust", "ensemble-limits");
    let out = d.join("e");
    let o = out.to_str().unwrap();
    let thermal = repo_file("scenarios/thermal.toml");
    let line = one_line_error(
        &run(&[
            "ensemble",
            &thermal,
            "--set",
            "solver.t_end=1e-11",
            "--set",
            "solver.dt=2e-18",
            "--set",
            "solver.samples=5000000",
            "--runs",
            "1",
            "--out",
            o,
        ]),
        "solver.samples: ",
    );
    let per_sample = 3 * (64 + 3) * 8 + 16;
    assert_eq!(per_sample, 1624);
    assert!(
        line.contains(&format!("({per_sample} bytes per sample)")),
        "{line}"
    );
    assert!(line.contains("8.120 GB"), "{line}");
    assert!(line.contains("samples <= 100000"), "{line}");
    assert!(!out.exists());
    // More runs than an ensemble keeps statistics for.
    let line = one_line_error(
        &run(&["ensemble", &thermal, "--runs", "1000001", "--out", o]),
        "--runs: ",
    );
    assert!(line.contains("1000000"), "{line}");
    let bit = repo_file("scenarios/bit/nano_300K.toml");
    one_line_error(
        &run(&["bit", &bit, "--runs", "1000001", "--out", o]),
        "--runs: ",
    );
    let args = vec![
        "bit".to_string(),
        bit.clone(),
        "--vary".into(),
        "thermal.temperature=300:400:2".into(),
        "--runs".into(),
        "1000001".into(),
        "--out".into(),
        o.into(),
    ];
    one_line_error(&bin().args(&args).output().unwrap(), "--runs: ");
    assert!(!out.exists());
    // At the limit: one run of 100 000 samples, every one histogrammed.
    ok(&run(&[
        "ensemble",
        &thermal,
        "--set",
        "solver.t_end=1e-12",
        "--set",
        "solver.dt=1e-17",
        "--set",
        "solver.samples=100000",
        "--runs",
        "1",
        "--quiet",
        "--out",
        o,
    ]));
    let hist = std::fs::read_to_string(out.join("histograms.csv")).unwrap();
    assert_eq!(hist.lines().count(), 1 + 3 * 100_000);
    let _ = std::fs::remove_dir_all(&d);
}

/// More threads than fit in the memory bound run fewer at once, with a
/// note, and the same output: a sweep of runs of 5e6 samples (1.12 GB
/// each) runs two at once within 3 GiB whatever --threads says (here the
/// runs stop after one step, so only the plan is exercised).
#[test]
fn threads_beyond_the_memory_bound_are_noted() {
    let d = scratch("trust", "threads");
    let o = bin()
        .args([
            "sweep",
            "--preset",
            "classical",
            "--set",
            "solver.samples=5000000",
            // Every run stops at its step limit, after one step.
            "--set",
            "solver.max_steps=1",
            "--vary",
            "top.offset=1e-3:2e-3:4",
            "--threads",
            "16",
            "--out",
        ])
        .arg(d.join("s"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains("note: running 2 at once, not 16"),
        "{err}{}",
        String::from_utf8_lossy(&o.stdout)
    );
    let _ = std::fs::remove_dir_all(&d);
}
