//! What a newcomer meets first: the hint for a toy that never rises and
//! that the fix it names works, console lines that are not errors said to
//! be none (Jellett's J under Contensou friction, the step limit of a run
//! that advances), `show`'s commented TOML, `--force` where nothing is
//! written, help pages, and the docs' `--set` spelling.

mod common;
use common::{bin, json, ok, repo, scratch};

use std::process::Output;

/// The `--set`s that make the classical preset a user's own toy: R = 20 mm,
/// a = 4 mm, m = 20 g, C = 2/5 m R², A/C = 0.94, spin 150 rad/s.
const TOY: [&str; 6] = [
    "top.radius=0.02",
    "top.offset=0.004",
    "top.mass=0.02",
    "top.inertia_axial=3.2e-6",
    "top.inertia_transverse=3.008e-6",
    "initial.spin=150",
];

/// `tippetop run --preset classical` with the toy's `--set`s, then `extra`.
fn run_toy(extra: &[&str], out: &std::path::Path) -> Output {
    let mut c = bin();
    c.args(["run", "--preset", "classical", "--no-plot"]);
    for s in TOY.iter().chain(extra) {
        c.args(["--set", s]);
    }
    c.arg("--out").arg(out).output().unwrap()
}

fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// The `--set KEY=VALUE` arguments a line names, in order.
fn sets_in(line: &str) -> Vec<String> {
    let words: Vec<&str> = line.split_whitespace().collect();
    words
        .windows(2)
        .filter(|w| w[0] == "--set")
        .map(|w| w[1].trim_end_matches([',', ')', '`', ';']).to_string())
        .collect()
}

/// A toy that rolls under exact Coulomb friction is told the README's cause
/// (its contact patch: Coulomb-Contensou friction with a contact radius),
/// and the `--set`s the hint gives make that toy invert within 10 s. A nano
/// top that rolls keeps the paper's slip law as its hint.
#[test]
fn a_rolling_toy_is_pointed_to_its_contact_patch_and_the_fix_inverts_it() {
    let dir = scratch("newcomer", "hint");
    let o = run_toy(&["solver.t_end=2"], &dir.join("rolls"));
    ok(&o);
    let text = stdout(&o);
    assert!(text.contains("never above π/2"), "{text}");
    assert!(text.contains("a rolling contact does no work"), "{text}");
    let line = text
        .lines()
        .find(|l| l.contains("surface.friction_law=contensou"))
        .unwrap_or_else(|| panic!("the hint does not name Contensou friction: {text}"));
    let fix = sets_in(line);
    assert_eq!(
        fix,
        [
            "surface.friction_law=contensou",
            "surface.contact_radius=3e-4"
        ],
        "{line}"
    );

    let fixed = dir.join("fixed");
    let extra: Vec<&str> = fix.iter().map(String::as_str).collect();
    let o = run_toy(&extra, &fixed);
    ok(&o);
    let s = json(&fixed.join("summary.json"));
    let above = s["first_time_theta_above_half_pi"].as_f64();
    let theta = s["theta_final"].as_f64().unwrap();
    assert!(above.is_some_and(|t| t < 5.0), "{above:?}");
    assert!(theta > std::f64::consts::PI - 0.3, "theta(10 s) = {theta}");

    let o = bin()
        .args([
            "run",
            "--preset",
            "nano-adhesive",
            "--set",
            "solver.t_end=1e-9",
        ])
        .args(["--no-plot", "--out"])
        .arg(dir.join("nano"))
        .output()
        .unwrap();
    ok(&o);
    let text = stdout(&o);
    assert!(text.contains("a rolling contact does no work"), "{text}");
    assert!(!text.contains("contensou"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Under Contensou friction the patch's drilling torque changes Jellett's
/// J: its drift is said to be physics, not integration error; under
/// Coulomb friction it is a plain accuracy figure.
#[test]
fn jellett_drift_under_contensou_is_said_to_be_physics() {
    let dir = scratch("newcomer", "jellett");
    let jellett = |o: &Output| {
        ok(o);
        let text = stdout(o);
        text.lines()
            .find(|l| l.starts_with("Jellett J:"))
            .unwrap_or_else(|| panic!("{text}"))
            .to_string()
    };
    let patch = [
        "surface.friction_law=contensou",
        "surface.contact_radius=3e-4",
        "solver.t_end=3",
    ];
    let line = jellett(&run_toy(&patch, &dir.join("c")));
    assert!(
        line.contains("not conserved") && line.contains("drilling torque"),
        "{line}"
    );
    assert!(line.contains("not an integration error"), "{line}");
    let line = jellett(&run_toy(&["solver.t_end=1"], &dir.join("r")));
    assert!(!line.contains('('), "{line}");
    let help = stdout(&bin().args(["run", "--help"]).output().unwrap());
    let help = help.split_whitespace().collect::<Vec<_>>().join(" ");
    assert!(
        help.contains("not conserved by the physics under friction_law = \"contensou\""),
        "{help}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run that advances steadily but needs more steps than its limit is
/// told that the step limit (`solver.max_steps`) stopped it, not that it
/// cannot make progress, with the value that lets it finish; that value
/// does. The limit can be raised above its default, up to 1e9.
#[test]
fn the_step_limit_is_named_with_the_key_that_raises_it() {
    let dir = scratch("newcomer", "steps");
    let o = run_toy(&["solver.max_steps=500"], &dir.join("a"));
    assert_eq!(o.status.code(), Some(3), "{}", stderr(&o));
    let err = stderr(&o);
    let line = err
        .lines()
        .find(|l| l.starts_with("error: "))
        .unwrap_or_else(|| panic!("{err}"));
    assert!(
        line.contains("step limit 500 reached (solver.max_steps): the run was advancing"),
        "{line}"
    );
    assert!(!line.contains("cannot make progress"), "{line}");
    let raise = sets_in(line);
    assert_eq!(raise.len(), 1, "{line}");
    assert!(raise[0].starts_with("solver.max_steps="), "{line}");
    let o = run_toy(&[raise[0].as_str()], &dir.join("b"));
    ok(&o);

    for (v, code) in [("30000000", 0), ("1000000000", 0), ("1000000001", 2)] {
        let o = bin()
            .args(["show", "--preset", "classical", "--set"])
            .arg(format!("solver.max_steps={v}"))
            .output()
            .unwrap();
        assert_eq!(o.status.code(), Some(code), "{v}: {}", stderr(&o));
        if code == 2 {
            let e = stderr(&o);
            assert_eq!(e.lines().count(), 1, "{e}");
            assert!(
                e.starts_with("error: solver.max_steps: ") && e.contains("<= 1000000000"),
                "{e}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `show` writes each key with its unit and meaning as a TOML comment; the
/// text is still the scenario (the library reads it back to the same
/// scenario), and `show` of the saved text prints the same text.
#[test]
fn show_comments_its_keys_and_round_trips() {
    let dir = scratch("newcomer", "show");
    for preset in ["classical", "nano-physical"] {
        let o = bin().args(["show", "--preset", preset]).output().unwrap();
        ok(&o);
        let text = stdout(&o);
        for line in text.lines() {
            if line.contains(" = ") {
                assert!(line.contains("  # "), "{preset}: no comment: {line}");
            }
            if line.starts_with('[') {
                assert!(line.contains("]  # "), "{preset}: no comment: {line}");
            }
        }
        let has = |start: &str, comment: &str| {
            text.lines()
                .any(|l| l.starts_with(start) && l.contains(comment))
        };
        assert!(has("radius = ", "# m, "), "{text}");
        assert!(has("mass = ", "# kg, "), "{text}");
        assert!(has("spin = ", "# rad/s, "), "{text}");
        assert!(has("friction_law = ", "\"contensou\""), "{text}");

        // The library reads the text to the scenario the preset is.
        let read = tippetop::Scenario::load(None, Some(&text), &[]).unwrap();
        let own = tippetop::Scenario::load(Some(preset), None, &[]).unwrap();
        assert_eq!(read.to_toml_string(), own.to_toml_string(), "{preset}");

        let file = dir.join(format!("{preset}.toml"));
        std::fs::write(&file, &text).unwrap();
        let again = bin().arg("show").arg(&file).output().unwrap();
        ok(&again);
        assert_eq!(stdout(&again), text, "{preset}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--force` lets a command replace another's output in --out; a command
/// that writes no files refuses it (one line naming it, exit 2).
#[test]
fn force_is_refused_where_nothing_is_written() {
    for args in [
        &["show", "--preset", "classical", "--force"][..],
        &["--force", "keys"],
        &["keys", "solver", "--force"],
        &["regime", "--preset", "nano", "--force"],
        &["adhesion", "--force"],
        &["stability", "--preset", "classical", "--force"],
    ] {
        let o = bin().args(args).output().unwrap();
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let e = stderr(&o);
        assert_eq!(e.lines().count(), 1, "{args:?}: {e}");
        assert!(
            e.starts_with("error: --force: ") && e.contains("writes no files"),
            "{args:?}: {e}"
        );
        assert!(o.stdout.is_empty(), "{args:?}");
    }
}

/// Help pages are for users: no issue numbers.
#[test]
fn help_pages_cite_no_issue_numbers() {
    let top = stdout(&bin().arg("--help").output().unwrap());
    let mut pages = vec![("tippetop".to_string(), top)];
    for sub in [
        "run",
        "reproduce",
        "sweep",
        "ensemble",
        "merge",
        "stability",
        "adhesion",
        "regime",
        "retention",
        "bit",
        "device",
        "rare",
        "animate",
        "show",
        "keys",
    ] {
        let o = bin().args([sub, "--help"]).output().unwrap();
        ok(&o);
        pages.push((sub.to_string(), stdout(&o)));
    }
    for (name, page) in pages {
        let lower = page.to_lowercase();
        for (i, _) in lower.match_indices("issue") {
            let after = lower[i + 5..].trim_start_matches([' ', '#']);
            assert!(
                !after.starts_with(|c: char| c.is_ascii_digit()),
                "{name} --help cites an issue: {}",
                &page[i..(i + 20).min(page.len())]
            );
        }
    }
}

/// The `--set KEY=VALUE` values of `text` that are quoted (`="x"`, `='"x"'`,
/// `=\"x\"`), with their line numbers.
fn quoted_sets(text: &str) -> Vec<(usize, String)> {
    let mut found = Vec::new();
    for (at, _) in text.match_indices("--set") {
        let arg: String = text[at + "--set".len()..]
            .trim_start_matches([' ', '\n', '='])
            .chars()
            .take_while(|c| !c.is_whitespace() && *c != '`')
            .collect();
        if let Some((key, value)) = arg.split_once('=')
            && key.contains('.')
            && value.starts_with(['"', '\'', '\\'])
        {
            found.push((text[..at].lines().count(), arg));
        }
    }
    found
}

/// The docs spell a `--set` of a name one way, bare
/// (`--set surface.friction_law=contensou`), and the CLI takes a bare word
/// for every key whose value is a name.
#[test]
fn docs_spell_set_values_bare_and_bare_words_are_read() {
    let mut files = vec![repo("README.md"), repo("benches/compare/README.md")];
    let mut docs: Vec<_> = std::fs::read_dir(repo("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    files.extend(docs);
    let mut bad = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        for (line, arg) in quoted_sets(&text) {
            bad.push(format!("{}:{line}: --set {arg}", f.display()));
        }
    }
    assert!(bad.is_empty(), "quoted --set values:\n{}", bad.join("\n"));

    for (sets, expect) in [
        (
            &[
                "surface.friction_law=contensou",
                "surface.contact_radius=3e-4",
            ][..],
            "friction_law = \"contensou\"",
        ),
        (
            &["solver.model=rigid", "surface.contact=unilateral"],
            "contact = \"unilateral\"",
        ),
        (&["solver.method=stiff"], "method = \"stiff\""),
        (
            &[
                "surface.contact_pressure=uniform",
                "surface.friction_law=contensou",
                "surface.contact_radius=1e-4",
            ],
            "contact_pressure = \"uniform\"",
        ),
    ] {
        let mut c = bin();
        c.args(["show", "--preset", "classical"]);
        for s in sets {
            c.args(["--set", s]);
        }
        let o = c.output().unwrap();
        ok(&o);
        assert!(stdout(&o).contains(expect), "{sets:?}");
    }
}

/// The README's "the same top" commands differ from each other in the
/// friction law alone (the law and its own parameters).
#[test]
fn the_readmes_same_top_changes_only_the_friction_law() {
    let readme = std::fs::read_to_string(repo("README.md")).unwrap();
    let at = readme
        .find("the same top under exact Coulomb friction")
        .expect("the README's same-top example");
    let block = &readme[at..];
    let block = &block[block.find("```\n").unwrap() + 4..];
    let block = &block[..block.find("```").unwrap()];
    let law_keys = [
        "surface.friction_law",
        "surface.friction_eps",
        "surface.contact_radius",
        "surface.contact_pressure",
    ];
    let mut others = Vec::new();
    for line in block.lines().filter(|l| l.contains(" run ")) {
        assert!(line.contains("--preset classical"), "{line}");
        let rest: Vec<String> = sets_in(line)
            .into_iter()
            .filter(|s| !law_keys.iter().any(|k| s.starts_with(&format!("{k}="))))
            .collect();
        others.push(rest);
    }
    assert!(others.len() >= 2, "{block}");
    assert!(
        others.iter().all(|o| o.is_empty()),
        "the same top's commands change more than the law: {others:?}"
    );
}
