//! Issue 12 ("Done when"): a seeded mutation fuzz of the scenarios. Starting
//! from the presets and every `scenarios/*.toml`, each case overrides one to
//! three keys (any key of the file format) with extreme or ordinary values
//! (0, -0, ±1e-320, ±1e308, ±inf, nan, huge integers, negatives, wrong
//! types, every enum name), then loads, validates and simulates in process.
//! Asserted for every case:
//!
//! - no panic (and so no abort: nothing allocates beyond the sample bound);
//! - a rejected case is an input error ([`Error::Invalid`]) of one line;
//! - an accepted case runs to an end within its step limit (a small
//!   `solver.max_steps` keeps the fuzz fast), keeps at most `samples` rows
//!   and `MAX_EVENTS + 1` events, and needs at most `MAX_RUN_BYTES`;
//! - a run that fails is a run-time error of one line; a run that does not
//!   fail has finite rows only.
//!
//! The exit-code side (exit 2 writes nothing and prints one line) is checked
//! on the binary by `tippetop-cli/tests/hardening_cli.rs`.

use std::panic::{AssertUnwindSafe, catch_unwind};

use tippetop::{
    Error, Scenario,
    analysis::stability::{self, SmoothLaw},
    limits, simulate,
};

/// SplitMix64: a small, seeded, portable generator (the same cases on every
/// machine).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
    fn pick<'a>(&mut self, xs: &[&'a str]) -> &'a str {
        xs[self.below(xs.len())]
    }
}

const KEYS: &[&str] = &[
    "top.radius",
    "top.offset",
    "top.mass",
    "top.inertia_transverse",
    "top.inertia_axial",
    "surface.gravity",
    "surface.friction",
    "surface.friction_law",
    "surface.friction_eps",
    "surface.contact",
    "surface.restitution",
    "force.0.hx",
    "force.0.hy",
    "force.0.start",
    "force.0.stop",
    "force.1.hx",
    "force.1.start",
    "force.1.stop",
    "initial.theta",
    "initial.theta_dot",
    "initial.precession",
    "initial.spin",
    "initial.ux",
    "initial.uy",
    "solver.method",
    "solver.t_end",
    "solver.steps",
    "solver.rtol",
    "solver.samples",
    "solver.model",
    "solver.max_steps",
];

const EXTREME: &[&str] = &[
    "0",
    "-0.0",
    "1e-320",
    "-1e-320",
    "1e308",
    "-1e308",
    "1.7976931348623157e308",
    "5e-324",
    "inf",
    "-inf",
    "nan",
    "9223372036854775807",
    "-9223372036854775808",
    "4611686018427387904",
    "-1",
    "1e9",
    "1e-9",
    "1e15",
    "1e-15",
    "\"x\"",
    "true",
    "[1]",
];

const ORDINARY: &[&str] = &[
    "0.5",
    "2",
    "3",
    "10",
    "1e-3",
    "1e-6",
    "1e3",
    "0.13",
    "3.0",
    "1.5707963267948966",
    "3.141592653589793",
    "1e-22",
    "1e-12",
    "3.55e-10",
    "1e-4",
    "101",
];

const NAMES: &[&str] = &[
    "coulomb",
    "coulomb_sliding",
    "regularized",
    "viscous",
    "bilateral",
    "paper",
    "unilateral",
    "adaptive",
    "rk4",
    "stiff",
    "reduced",
    "vector",
    "rigid",
];

/// The step limit and row count every fuzz case starts from (a case may
/// override them).
const BASE_SETS: &[&str] = &["solver.max_steps=2000", "solver.samples=21"];

fn bases() -> Vec<(String, Option<&'static str>, Option<String>)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenarios");
    let mut v: Vec<(String, Option<&'static str>, Option<String>)> = vec![
        ("preset nano".into(), Some("nano"), None),
        ("preset classical".into(), Some("classical"), None),
    ];
    let mut files: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 5, "{files:?}");
    for p in files {
        let text = std::fs::read_to_string(&p).unwrap();
        v.push((p.display().to_string(), None, Some(text)));
    }
    v
}

/// One case: the sets applied on top of `BASE_SETS`.
fn mutations(rng: &mut Rng) -> Vec<String> {
    let n = 1 + rng.below(3);
    (0..n)
        .map(|_| {
            let key = rng.pick(KEYS);
            let value = match rng.below(10) {
                0..=3 => rng.pick(EXTREME),
                4..=7 => rng.pick(ORDINARY),
                _ => {
                    let s = rng.pick(NAMES);
                    // Half of them as TOML strings, half bare (both accepted).
                    if rng.below(2) == 0 {
                        return format!("{key}=\"{s}\"");
                    }
                    s
                }
            };
            format!("{key}={value}")
        })
        .collect()
}

/// How a case ended.
enum Outcome {
    Rejected,
    Ok,
    Failed,
}

/// Check one case; `Err` describes what went wrong.
fn check(preset: Option<&str>, text: Option<&str>, sets: &[String]) -> Result<Outcome, String> {
    let loaded = catch_unwind(AssertUnwindSafe(|| Scenario::load(preset, text, sets)))
        .map_err(|_| "panic in Scenario::load".to_string())?;
    let sc = match loaded {
        Err(e @ Error::Invalid { .. }) => {
            let msg = e.to_string();
            if msg.contains('\n') || msg.is_empty() {
                return Err(format!("input error not one line: {msg:?}"));
            }
            return Ok(Outcome::Rejected);
        }
        Err(e) => return Err(format!("load gave a non-input error: {e}")),
        Ok(sc) => sc,
    };
    if limits::run_memory_bytes(&sc.solver) > limits::MAX_RUN_BYTES {
        return Err("accepted a run beyond MAX_RUN_BYTES".into());
    }
    let tr = catch_unwind(AssertUnwindSafe(|| simulate(&sc)))
        .map_err(|_| "panic in simulate".to_string())?
        .map_err(|e| format!("simulate rejected what load accepted: {e}"))?;
    let limit = sc.solver.step_limit();
    if tr.summary.steps > limit {
        return Err(format!("{} steps > limit {limit}", tr.summary.steps));
    }
    if tr.samples.len() > sc.solver.samples {
        return Err(format!("{} rows > samples", tr.samples.len()));
    }
    if tr.events.len() > limits::MAX_EVENTS + 1 {
        return Err(format!("{} events", tr.events.len()));
    }
    match &tr.error {
        Some(e @ Error::Runtime { .. }) => {
            if e.to_string().contains('\n') {
                return Err(format!("run-time error not one line: {e}"));
            }
        }
        Some(e) => return Err(format!("run failed with an input error: {e}")),
        None => {
            if let Some(s) = tr.samples.iter().find(|s| !s.is_finite()) {
                return Err(format!("status ok with a non-finite row: {s:?}"));
            }
            if tr.samples.len() != sc.solver.samples {
                return Err(format!("status ok with {} rows", tr.samples.len()));
            }
            return Ok(Outcome::Ok);
        }
    }
    Ok(Outcome::Failed)
}

/// Number of fuzz cases (a few thousand; a few seconds on one core).
const CASES: usize = 20_000;

#[test]
fn fuzz_scenarios() {
    let bases = bases();
    let mut rng = Rng(0x7170_7e70_2026_0012);
    let mut failures = Vec::new();
    let (mut rejected, mut ok, mut failed) = (0usize, 0usize, 0usize);
    // Keep the output readable: a caught panic is reported below, with its
    // case, not as a backtrace per case.
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    for case in 0..CASES {
        let (name, preset, text) = &bases[rng.below(bases.len())];
        let mut sets: Vec<String> = BASE_SETS.iter().map(|s| s.to_string()).collect();
        sets.extend(mutations(&mut rng));
        match check(*preset, text.as_deref(), &sets) {
            Err(why) => failures.push(format!("case {case} ({name}, {sets:?}): {why}")),
            Ok(Outcome::Rejected) => rejected += 1,
            Ok(Outcome::Ok) => ok += 1,
            Ok(Outcome::Failed) => failed += 1,
        }
    }
    std::panic::set_hook(hook);
    eprintln!(
        "fuzz: {CASES} cases: {rejected} rejected, {ok} ran to the end, {failed} failed part-way"
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    // The mix exercises all three outcomes.
    assert!(
        rejected > CASES / 10 && ok > CASES / 20 && failed > CASES / 50,
        "{rejected} {ok} {failed}"
    );
}

/// The stability analysis (`tippetop stability`) on fuzzed scenarios with
/// fuzzed options: no panic; options out of range, a scenario the analysis
/// does not model and a law asked for with another law's ε are input
/// errors; the rest give a report or a one-line run-time error.
#[test]
fn fuzz_stability() {
    let bases = bases();
    let mut rng = Rng(0x57ab_1e00_2026_0012);
    let opt_values = [
        None,
        Some(f64::NAN),
        Some(f64::INFINITY),
        Some(-1e308),
        Some(1e308),
        Some(1e-320),
        Some(0.0),
        Some(-1.0),
        Some(1e-3),
        Some(2.0),
        Some(150.0),
        Some(1e100),
        Some(1e-100),
    ];
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let mut failures = Vec::new();
    let (mut reports, mut cases) = (0, 0);
    while cases < 600 {
        let (name, preset, text) = &bases[rng.below(bases.len())];
        let mut sets: Vec<String> = BASE_SETS.iter().map(|s| s.to_string()).collect();
        sets.extend(mutations(&mut rng));
        let Ok(sc) = Scenario::load(*preset, text.as_deref(), &sets) else {
            continue;
        };
        cases += 1;
        let opts = stability::Options {
            law: [None, Some(SmoothLaw::Regularized), Some(SmoothLaw::Viscous)][rng.below(3)],
            eps: opt_values[rng.below(opt_values.len())],
            spin: opt_values[rng.below(opt_values.len())],
            tol_rel: opt_values[rng.below(opt_values.len())].unwrap_or(1e-10),
            run: rng.below(4) == 0,
            ..Default::default()
        };
        // Bad input: options out of range, a scenario the analysis does not
        // model, or a law asked for with another law's ε.
        let valid_opts = opts.validate().is_ok()
            && stability::supports(&sc).is_ok()
            && stability::law_and_eps(&sc, &opts).is_ok();
        match catch_unwind(AssertUnwindSafe(|| stability::analyse(&sc, &opts))) {
            Err(_) => failures.push(format!("{name} {sets:?} {opts:?}: panic")),
            Ok(Ok(_)) if valid_opts => reports += 1,
            Ok(Ok(_)) => failures.push(format!("{name} {sets:?} {opts:?}: accepted")),
            Ok(Err(e)) => {
                if e.to_string().contains('\n') || (e.is_input() == valid_opts) {
                    failures.push(format!("{name} {sets:?} {opts:?}: {e}"));
                }
            }
        }
    }
    std::panic::set_hook(hook);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    assert!(reports > 50, "{reports}");
}
