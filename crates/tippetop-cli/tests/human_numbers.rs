//! One number format in every human-facing output: the consoles of `run`,
//! `sweep`, `ensemble`, `bit`, `rare`, `device`, `animate`, `stability`,
//! `regime` and `adhesion`, and report.md, bit.md, device.md and rare.md,
//! hold no number with 7 or more significant digits (command lines
//! included), no power of ten beyond 10^100 written as a time (a time
//! beyond any time scale says so in words), and no `1e300`/`inf`/`NaN`
//! stand-ins. Small budgets throughout: the point is the format, not the
//! numbers. Machine-readable files (CSV, JSON) keep full precision and
//! are not scanned.

mod common;
use common::{HOT, bin, huge_times, many_digits, ok, repo, sentinels};
use std::path::Path;

/// The eccentric nano top in the Brownian mode at 300 K with a 2 kT well
/// at π/2: `rare`'s small exact-compatible case.
const BROWNIAN: &str = r#"preset = "nano"
[top]
offset = 1.775e-10
[surface]
gravity = 0.0
friction = 0.0
[[well]]
theta = 1.5707963267948966
depth = 8.283e-21
width = 0.3
[initial]
theta = 1.5707963267948966
spin = 0.0
[solver]
method = "brownian"
dt = 2e-15
t_end = 1e-12
samples = 2
[thermal]
temperature = 300.0
damping_translational = 2.2e12
damping_rotational = 2.2e12
seed = 5
"#;

/// Fails with every number of `text` that is not for people.
fn check(name: &str, text: &str) {
    let long = many_digits(text, 7);
    assert!(
        long.is_empty(),
        "numbers of 7 or more figures in {name}: {long:?}\n{text}"
    );
    let huge = huge_times(text);
    assert!(
        huge.is_empty(),
        "times beyond 10^100 in {name}: {huge:?}\n{text}"
    );
    let sent = sentinels(text);
    assert!(sent.is_empty(), "sentinels in {name}: {sent:?}\n{text}");
}

/// stdout and stderr of a successful `tippetop ARGS`, the scratch
/// directory `d` written as `DIR` (its name holds the process id).
fn console(d: &Path, args: &[&str]) -> String {
    let o = bin().args(args).output().unwrap();
    ok(&o);
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
    .replace(d.to_str().unwrap(), "DIR")
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap()
}

#[test]
fn the_scanners_find_what_they_should() {
    assert_eq!(
        many_digits("theta_final 1.394259e0 rad (CI 1.268116e0 ..)", 7),
        ["1.394259", "1.268116"]
    );
    assert_eq!(
        many_digits("`--set top.inertia_axial=2.0096786666666668e-44`", 7),
        ["2.0096786666666668"]
    );
    assert_eq!(many_digits("eps = 5.898304841223451e-8 m/s", 7).len(), 1);
    assert!(
        many_digits(
            "a frame every 50.25 ms, 991508 steps, budget 1000000, 0.1.0, run-12 2026-11-28",
            7
        )
        .is_empty()
    );
    assert_eq!(many_digits("1.500000 s", 7), ["1.500000"]);
    assert_eq!(
        huge_times("3.131 × 10^775 years (95 %: 8.198 × 10^1019 years)").len(),
        2
    );
    assert_eq!(huge_times("= 4.137e+1035 s (exact)"), ["4.137e+1035 s"]);
    assert!(
        huge_times("8.447 × 10^15 years, 10^664 kT, beyond any time scale (over 10^100 years)")
            .is_empty()
    );
}

#[test]
fn consoles_and_reports_read_as_numbers_for_people() {
    let d = common::scratch("human", "numbers");
    let out = |n: &str| d.join(n).to_str().unwrap().to_string();
    let run = out("run");
    check(
        "run",
        &console(
            &d,
            &[
                "run",
                "--preset",
                "classical",
                "--set",
                "solver.t_end=2",
                "--no-plot",
                "--out",
                &run,
            ],
        ),
    );
    check(
        "animate",
        &console(
            &d,
            &[
                "animate",
                &run,
                "--fps",
                "10",
                "--duration",
                "2",
                "--size",
                "160x120",
            ],
        ),
    );
    check(
        "sweep",
        &console(
            &d,
            &[
                "sweep",
                "--preset",
                "classical",
                "--set",
                "solver.t_end=0.2",
                "--set",
                "solver.samples=11",
                "--vary",
                "top.offset=0.001:0.015:3",
                "--out",
                &out("sweep"),
            ],
        ),
    );
    check(
        "ensemble",
        &console(
            &d,
            &[
                "ensemble",
                "--preset",
                "nano-physical",
                "--runs",
                "4",
                "--out",
                &out("ensemble"),
            ],
        ),
    );
    check(
        "stability",
        &console(&d, &["stability", "--preset", "classical"]),
    );
    check(
        "regime",
        &console(&d, &["regime", "--preset", "nano-physical"]),
    );
    check("adhesion", &console(&d, &["adhesion"]));
    let nano = repo("scenarios/bit/nano.toml");
    check(
        "bit",
        &console(&d, &["bit", nano.to_str().unwrap(), "--out", &out("bit")]),
    );
    check("bit.md", &read(&d.join("bit/bit.md")));
    // A bit ensemble with its step check (the check's lines and bit.md
    // section, a warning when not converged).
    let hot = d.join("hot.toml");
    std::fs::write(&hot, HOT).unwrap();
    let c = console(
        &d,
        &[
            "bit",
            hot.to_str().unwrap(),
            "--runs",
            "12",
            "--out",
            &out("bit_hot"),
        ],
    );
    assert!(c.contains("step check write: "), "{c}");
    check("bit_hot", &c);
    check("bit_hot/bit.md", &read(&d.join("bit_hot/bit.md")));
    let b = d.join("b.toml");
    std::fs::write(&b, BROWNIAN).unwrap();
    let b = b.to_str().unwrap();
    for (name, args) in [
        (
            "rare_direct",
            &[
                "--target",
                "theta>1.75",
                "--reset",
                "theta<1.3",
                "--method",
                "direct",
                "--replicas",
                "50",
            ][..],
        ),
        (
            "rare_ams",
            &[
                "--target",
                "theta>1.75",
                "--reset",
                "theta<1.3",
                "--method",
                "ams",
                "--replicas",
                "4",
                "--particles",
                "20",
            ][..],
        ),
        // A mean first-passage time far beyond f64: the exact answer
        // out of a well of 1e-17 J, about 2400 kT at 300 K.
        (
            "rare_exact_deep",
            &[
                "--target",
                "theta>2.9,theta<0.3",
                "--method",
                "exact",
                "--set",
                "well.0.depth=1e-17",
                "--set",
                "solver.dt=1e-19",
            ][..],
        ),
    ] {
        let mut a = vec!["rare", b];
        a.extend_from_slice(args);
        let o = out(name);
        a.extend(["--out", &o]);
        check(name, &console(&d, &a));
        check(
            &format!("{name}/rare.md"),
            &read(&d.join(name).join("rare.md")),
        );
    }
    let rep = out("reproduce");
    check(
        "reproduce",
        &console(&d, &["reproduce", "--quick", "--out", &rep]),
    );
    check("report.md", &read(&d.join("reproduce/report.md")));
}

/// `device --quick` at its smallest sizes: the 4 K retention (beyond f64)
/// and the extrapolated ones (10^1000 years and more) in words.
#[test]
fn device_reads_as_numbers_for_people() {
    let d = common::scratch("human", "device");
    let dev = d.join("dev");
    let c = console(
        &d,
        &[
            "device",
            "--quick",
            "--runs",
            "2",
            "--budget",
            "5",
            "--retention-runs",
            "2",
            "--threads",
            "2",
            "--out",
            dev.to_str().unwrap(),
        ],
    );
    check("device", &c);
    let md = read(&dev.join("device.md"));
    check("device.md", &md);
    // The console gives the answer's verdict and table, as device.md.
    let table = md
        .split("## Answer\n\n")
        .nth(1)
        .unwrap()
        .split("\n\n")
        .nth(1)
        .unwrap();
    assert!(table.starts_with("| |") && c.contains(table), "{c}");
}

/// A top that slipped for the first 47 ms of 200 s does not roll "100 %"
/// of the time: the share is not rounded up to all of it.
#[test]
fn a_top_that_slipped_does_not_roll_all_the_time() {
    let d = common::scratch("human", "rolling");
    let c = console(
        &d,
        &[
            "run",
            repo("scenarios/fig07_classical.toml").to_str().unwrap(),
            "--set",
            "solver.t_end=200",
            "--no-plot",
            "--out",
            d.join("run").to_str().unwrap(),
        ],
    );
    let line = c
        .lines()
        .find(|l| l.contains("rolls without slipping"))
        .unwrap_or_else(|| panic!("no rolling line:\n{c}"));
    assert!(!line.contains("100%") && !line.contains("100 %"), "{line}");
    assert!(line.contains("all but 47.1 ms"), "{line}");
}
