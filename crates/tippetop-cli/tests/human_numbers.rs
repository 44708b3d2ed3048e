//! One number format in every human-facing output (issue #29, 5): the
//! console of `run`, `stability`, `regime`, `adhesion` and `bit`, and
//! bit.md, hold no machine-precision numbers (10 or more significant
//! digits) and no `1e300`/`inf`/`NaN` stand-ins. (report.md: report_md.rs;
//! device.md and its console: device_cli.rs.)

mod common;
use common::{bin, long_numbers, ok, repo, sentinels};

fn check(name: &str, text: &str) {
    let long = long_numbers(text, 10);
    assert!(long.is_empty(), "long numbers in {name}: {long:?}\n{text}");
    let sent = sentinels(text);
    assert!(sent.is_empty(), "sentinels in {name}: {sent:?}\n{text}");
}

fn console(args: &[&str]) -> String {
    let o = bin().args(args).output().unwrap();
    ok(&o);
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn consoles_and_bit_md_read_as_numbers_for_people() {
    let d = common::scratch("human", "numbers");
    let out = |n: &str| d.join(n).to_str().unwrap().to_string();
    let run = out("run");
    check(
        "run",
        &console(&[
            "run",
            "--preset",
            "classical",
            "--set",
            "solver.t_end=2",
            "--no-plot",
            "--out",
            &run,
        ]),
    );
    check(
        "stability",
        &console(&["stability", "--preset", "classical"]),
    );
    check("regime", &console(&["regime", "--preset", "nano-physical"]));
    check("adhesion", &console(&["adhesion"]));
    let bit = out("bit");
    let nano = repo("scenarios/bit/nano.toml");
    check(
        "bit",
        &console(&["bit", nano.to_str().unwrap(), "--out", &bit]),
    );
    check(
        "bit.md",
        &std::fs::read_to_string(d.join("bit/bit.md")).unwrap(),
    );
}
