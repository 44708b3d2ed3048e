//! `tippetop bit FILE --search`: the protocol search of
//! [`tippetop::analysis::search`] (issue #16 item 5). Writes into `--out`:
//! `search.json` (the spec, the best protocol, its evaluation and
//! robustness, or that none was found and how close the best came),
//! `search.md` (the same in words), `best.toml` (the best protocol as a
//! ready-to-run bit scenario: `tippetop bit best.toml` runs it again, bit
//! for bit) and `evaluations.csv` (every evaluation in order).

use std::fmt::Write as _;
use std::process::ExitCode;

use anyhow::Result;
use tippetop::analysis::bit::{Z95, wilson};
use tippetop::analysis::search::{Evaluation, ProtocolSearch, SearchResult};
use tippetop::input::scenario::search::{SearchActuator, SearchSpec};

use crate::bit_args::BitArgs;
use crate::output::{OutDir, fmt_f64, write_bytes_atomic};
use crate::scenario_load::input_error;

fn opt(v: Option<f64>) -> String {
    v.map(fmt_f64).unwrap_or_else(|| "-".into())
}

fn eval_json(e: &Evaluation) -> serde_json::Value {
    serde_json::json!({
        "merit": e.merit,
        "success": e.success,
        "success_with_margin": e.success_with_margin,
        "failure": e.failure.map(|m| m.as_str()),
        "time": e.time,
        "energy": e.energy,
        "distance": e.distance,
    })
}

/// Run the search for `tippetop bit --search`. Bad input: one line, exit 2,
/// nothing written.
pub fn run(args: &BitArgs, toml_text: Option<&str>, quiet: bool) -> Result<ExitCode> {
    if args.runs.is_some_and(|n| n != 1) {
        return Ok(input_error(
            "--runs: the search runs deterministic runs (T = 0): omit --runs".to_string(),
        ));
    }
    let search =
        match ProtocolSearch::new(toml_text, args.source.preset.as_deref(), &args.source.sets) {
            Ok(s) => s,
            Err(e) => return Ok(input_error(e)),
        };
    let spec = search.spec.clone();
    let (kind, point, moment) = match spec.actuator {
        SearchActuator::Contact => ("contact", None, None),
        SearchActuator::Tip { point } => ("tip", Some(point), None),
        SearchActuator::Magnetic { moment } => ("magnetic", None, Some(moment)),
    };
    let out = OutDir::open(&args.out)?;
    let stage = out.stage().to_path_buf();
    let names: Vec<String> = (0..spec.windows)
        .flat_map(|k| {
            ["magnitude", "angle", "start", "duration"]
                .map(|p| format!("{}.{k}.{p}", spec.phase.name()))
        })
        .collect();
    let mut csv = format!(
        "evaluation,{},merit,success,success_with_margin,failure,time,energy,distance\n",
        names.join(",")
    );
    let pb = crate::progress::bar(quiet, spec.budget as u64, "search");
    let result = search.run(&mut |k, x, e| {
        let xs: Vec<String> = x.iter().map(|v| fmt_f64(*v)).collect();
        let _ = writeln!(
            csv,
            "{k},{},{},{},{},{},{},{},{}",
            xs.join(","),
            fmt_f64(e.merit),
            e.success,
            e.success_with_margin,
            e.failure.map(|m| m.as_str()).unwrap_or("ok"),
            opt(e.time),
            opt(e.energy),
            fmt_f64(e.distance)
        );
        pb.inc(1);
    });
    pb.finish_and_clear();
    let Some(r) = result else {
        out.abandon();
        anyhow::bail!("the search made no evaluation");
    };
    let found = r.best.success_with_margin;
    let (ok, n) = r.robustness;
    let json = report_json(&spec, (kind, point, moment), &r);
    let mut text = serde_json::to_string_pretty(&json)?;
    text.push('\n');
    write_bytes_atomic(&stage.join("search.json"), text.as_bytes())?;
    write_bytes_atomic(&stage.join("evaluations.csv"), csv.as_bytes())?;
    let best_toml = format!(
        "# The best {} protocol found by `tippetop bit --search` ({} evaluations, seed {}):\n\
         # run it with `tippetop bit best.toml --out DIR`.\n{}",
        spec.phase.name(),
        r.evaluations,
        spec.seed,
        search.text(&r.best_x)
    );
    write_bytes_atomic(&stage.join("best.toml"), best_toml.as_bytes())?;
    let md = markdown(&spec, &r);
    write_bytes_atomic(&stage.join("search.md"), md.as_bytes())?;
    out.commit(&["search.json"])?;
    if !quiet {
        if found {
            println!(
                "found: switching time {} s, energy {} J, merit {}; robustness {ok}/{n}",
                opt(r.best.time),
                opt(r.best.energy),
                fmt_f64(r.best.merit)
            );
        } else {
            println!(
                "none found in {} evaluations: the closest stayed {} rad outside the target window",
                r.evaluations,
                fmt_f64(r.best.distance)
            );
        }
        println!("wrote {}", args.out.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The components written for the actuator, the quantity's symbol and
/// unit: the paper's H (precessing frame), the tip's horizontal lab-frame
/// force, or the field in the lab X-Z plane.
#[allow(clippy::type_complexity)]
fn components(spec: &SearchSpec) -> ((&'static str, &'static str), &'static str, &'static str) {
    match spec.actuator {
        SearchActuator::Contact => (("hx", "hy"), "H", "N"),
        SearchActuator::Tip { .. } => (("fx", "fy"), "F", "N"),
        SearchActuator::Magnetic { .. } => (("bx", "bz"), "B", "T"),
    }
}

/// (component 0, component 1) of magnitude `m` at angle `a` [rad].
fn parts(spec: &SearchSpec, m: f64, a: f64) -> (f64, f64) {
    match spec.actuator {
        SearchActuator::Magnetic { .. } => (m * a.sin(), m * a.cos()),
        _ => (m * a.cos(), m * a.sin()),
    }
}

/// `search.json`: the spec, the best protocol, its evaluation and
/// robustness. `actuator`: its kind, tip point and magnetic moment.
#[allow(clippy::type_complexity)]
fn report_json(
    spec: &SearchSpec,
    actuator: (&str, Option<[f64; 3]>, Option<f64>),
    r: &SearchResult,
) -> serde_json::Value {
    let (kind, point, moment) = actuator;
    let (comp, _, _) = components(spec);
    let parts = |m: f64, a: f64| parts(spec, m, a);
    let found = r.best.success_with_margin;
    let (ok, n) = r.robustness;
    let ci = wilson(ok, n, Z95);
    let protocol: Vec<serde_json::Value> = r
        .best_x
        .chunks(4)
        .map(|w| {
            serde_json::json!({
                "magnitude": w[0], "angle": w[1], "start": w[2], "duration": w[3],
                comp.0: parts(w[0], w[1]).0, comp.1: parts(w[0], w[1]).1,
            })
        })
        .collect();
    serde_json::json!({
        "search": {
            "phase": spec.phase.name(),
            "windows": spec.windows,
            "actuator": kind,
            "point": point,
            "moment": moment,
            "magnitude": spec.magnitude,
            "angle": spec.angle,
            "start": spec.start,
            "duration": spec.duration,
            "weight": spec.weight,
            "margin": spec.margin,
            "seed": spec.seed,
            "budget": spec.budget,
            "perturbations": spec.perturbations,
        },
        "found": found,
        "evaluations": r.evaluations,
        "starts": r.starts,
        "best": {
            "protocol": protocol,
            "evaluation": eval_json(&r.best),
        },
        "robustness": {
            "perturbation": "every parameter x (1 + 0.05 (2u - 1)), u uniform (Philox seed, 1)",
            "runs": n,
            "successes": ok,
            "fraction": (n > 0).then(|| ok as f64 / n as f64),
            "ci95": ci,
        },
    })
}

/// `search.md`: what `search.json` says, in words.
fn markdown(spec: &SearchSpec, r: &SearchResult) -> String {
    let (comp, symbol, unit) = components(spec);
    let parts = |m: f64, a: f64| parts(spec, m, a);
    let found = r.best.success_with_margin;
    let (ok, n) = r.robustness;
    let ci = wilson(ok, n, Z95);
    let mut md = String::new();
    let _ = writeln!(md, "# Protocol search ({} phase)\n", spec.phase.name());
    if found {
        let _ = writeln!(
            md,
            "Found: a {}-window protocol that switches in {} s with net actuator work {} J \
             (merit {}), succeeding with a margin of {} rad; {} evaluations in {} starts.\n",
            spec.windows,
            opt(r.best.time),
            opt(r.best.energy),
            fmt_f64(r.best.merit),
            spec.margin,
            r.evaluations,
            r.starts
        );
    } else {
        let _ = writeln!(
            md,
            "No protocol within the bounds succeeded with the margin in {} evaluations ({} starts). \
             The closest came within {} rad of the target window (shrunk by the margin) over the \
             hold{}.\n",
            r.evaluations,
            r.starts,
            fmt_f64(r.best.distance),
            r.best
                .failure
                .map(|m| format!("; its failure: {}", m.as_str()))
                .unwrap_or_default()
        );
    }
    for (k, w) in r.best_x.chunks(4).enumerate() {
        let _ = writeln!(
            md,
            "- window {k}: |{symbol}| = {} {unit} at {} rad ({} = {}, {} = {}), from {} s for {} s",
            fmt_f64(w[0]),
            fmt_f64(w[1]),
            comp.0,
            fmt_f64(parts(w[0], w[1]).0),
            comp.1,
            fmt_f64(parts(w[0], w[1]).1),
            fmt_f64(w[2]),
            fmt_f64(w[3])
        );
    }
    if n > 0 {
        let _ = writeln!(
            md,
            "\nRobustness: {ok} of {n} runs with every parameter perturbed by up to ±5 % succeed{}.",
            ci.map(|[lo, hi]| format!(" (Wilson 95 %: [{}, {}])", fmt_f64(lo), fmt_f64(hi)))
                .unwrap_or_default()
        );
    }
    let _ = writeln!(
        md,
        "\nbest.toml runs it again: `tippetop bit best.toml --out DIR`."
    );
    md
}
