//! report.md is for a referee: it opens with an abstract of the decisive
//! findings, defines its verdicts' words once, its table cells hold at most
//! 80 characters, each row's numbers are those of the runs its verdict
//! rests on, and its prose holds no machine-precision numbers (10 or more
//! significant digits) and no `1e300`-style sentinels. Failure messages are
//! footnotes. Checked on `reproduce --quick --extended` (the adhesion study
//! included) and, for the verdicts, on the full reproduction.

use std::fs;

use assert_cmd::Command;

mod common;
use common::{long_numbers, sentinels};

#[test]
fn long_numbers_finds_what_it_should() {
    assert_eq!(
        long_numbers("t = 2.0000000000000002e-7 s", 10),
        vec!["2.0000000000000002"]
    );
    assert_eq!(
        long_numbers("0.00004061824921529044 s", 10),
        vec!["0.00004061824921529044"]
    );
    assert!(long_numbers("3.081 µs, 47.9 %, run 12345", 10).is_empty());
    assert!(long_numbers("`--set x=1.3499999999999998e-6`", 10).is_empty());
}

#[test]
fn report_opens_with_an_abstract_and_keeps_cells_short() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rep");
    Command::cargo_bin("tippetop")
        .unwrap()
        .args([
            "reproduce",
            "--quick",
            "--extended",
            "--quiet",
            "--out",
            out.to_str().unwrap(),
        ])
        .assert()
        .success();
    let report = fs::read_to_string(out.join("report.md")).unwrap();
    // The adhesion study's tables are checked too.
    assert!(report.contains("**The paper's claims under adhesion**"));
    // The abstract comes before any table, with the verdict counts and the
    // decisive findings' numbers.
    let abs = report.find("## Abstract").expect("no abstract");
    let first_table = report.find("\n|").unwrap();
    assert!(abs < first_table, "the abstract is not first");
    // The abstract: the paragraph under its heading.
    let abstract_text = report[abs..]
        .trim_start_matches("## Abstract")
        .trim_start()
        .split("\n\n")
        .next()
        .unwrap();
    for needle in ["reproduces", "RK4", "N < 0", "θ"] {
        assert!(
            abstract_text.contains(needle),
            "the abstract lacks {needle:?}: {abstract_text}"
        );
    }
    // One sentence of counts, then one per finding, each led by a bold name.
    let sentences = abstract_text.matches(" **").count() + 1;
    assert!(
        (5..=10).contains(&sentences),
        "{sentences} sentences: {abstract_text}"
    );
    // Every table cell at most 80 characters.
    for line in report.lines().filter(|l| l.starts_with('|')) {
        for c in line.split(" | ") {
            let c = c.trim_matches(|ch| ch == '|' || ch == ' ');
            assert!(
                c.chars().count() <= 80,
                "a cell of {} characters: {c}",
                c.chars().count()
            );
        }
    }
    // Failure messages live in footnotes, referenced from the runs table.
    assert!(
        report.contains("[^1]: at t = "),
        "no footnote for a failed run"
    );
    assert!(!report.contains("the analysis issue"), "internal jargon");
    // Human numbers: no 10+ significant digits outside code spans, no e300.
    let long = long_numbers(&report, 10);
    assert!(
        long.is_empty(),
        "machine-precision numbers in report.md: {long:?}"
    );
    let sent = sentinels(&report);
    assert!(sent.is_empty(), "sentinels in report.md: {sent:?}");
}

#[test]
fn sentinels_finds_what_it_should() {
    assert_eq!(
        sentinels("beyond 1e300 s (95 %: > 1e300–> 1e300 s)").len(),
        3
    );
    assert_eq!(sentinels("= inf yr, ratio NaN"), vec!["inf", "NaN"]);
    assert!(sentinels("infinite, 1e30 s, `x = 1e300`, 3.740 × 10^664 years").is_empty());
}

/// Every verdict's word is defined once, at the top; a claim called
/// "partly" says why: its criterion's weaker level ("partly if ..."), or
/// the computations disagree and its table line gives each one's own
/// verdict and numbers (c1_fit: the paper-contact run reproduces the fit,
/// the bilateral run does not; the line showed the bilateral numbers
/// alone). On the full reproduction: these are its verdicts.
#[test]
fn verdict_words_are_defined_and_rows_show_the_runs_they_judge() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("rep");
    Command::cargo_bin("tippetop")
        .unwrap()
        .args(["reproduce", "--quiet", "--out", out.to_str().unwrap()])
        .assert()
        .success();
    let report = fs::read_to_string(out.join("report.md")).unwrap();
    let claims_at = report.find("## The claims").unwrap();
    for word in ["reproduced", "partly", "not reproduced"] {
        let def = format!("- **{word}**: ");
        assert_eq!(report.matches(&def).count(), 1, "{def:?} defined once");
        assert!(
            report.find(&def).unwrap() < claims_at,
            "{def:?} after the table"
        );
    }
    let claims: serde_json::Value =
        serde_json::from_str(&fs::read_to_string(out.join("claims.json")).unwrap()).unwrap();
    for c in claims.as_array().unwrap() {
        let (id, why, summary) = (
            &c["id"],
            c["why"].as_str().unwrap(),
            c["summary"].as_str().unwrap(),
        );
        if c["verdict"] == "partly" {
            assert!(
                why.contains("partly if")
                    || why.contains("else partly")
                    || summary.starts_with("bilateral "),
                "{id}: partly without a definition: {why} | {summary}"
            );
        }
    }
    let row = report
        .lines()
        .find(|l| l.starts_with("| [c1_fit]"))
        .unwrap();
    assert!(row.contains("**partly**"), "{row}");
    assert!(
        row.contains("bilateral no (") && row.contains("paper contact yes ("),
        "{row}"
    );
}
