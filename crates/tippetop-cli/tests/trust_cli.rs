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
    let (x1, x2, x) = (
        1.0 / (kb * 1000.0),
        1.0 / (kb * 2000.0),
        1.0 / (kb * 300.0),
    );
    let e = (1e5f64 / 1e3).ln() / (x1 - x2);
    let want = 1e3 * (-e * (x - x1)).exp();
    let got = r["target"]["rate"].as_f64().unwrap();
    assert!((got / want - 1.0).abs() < 1e-12, "{got} vs {want}");
    let _ = std::fs::remove_dir_all(&d);
}
