//! `tippetop rare`: a rare-event question about a scenario (issue 27):
//! the probability of reaching a target before a reset, or the mean
//! first-passage time to a target, by the exact one-dimensional answer or
//! a plain ensemble ([`tippetop::analysis::rare`]); writes rare.json and
//! rare.md.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::{ArgGroup, Args};
use tippetop::analysis::rare::exact::{Edge, Exact, Positive, Quantity};
use tippetop::analysis::rare::problem::{self, DEFAULT_REPLICAS, Problem, RareMethod, Report};

use crate::output::{OutDir, write_bytes_atomic};
use crate::scenario_load::input_error;

/// Long help of `tippetop rare`.
pub const RARE_LONG_ABOUT: &str =
    "A rare-event question about a stochastic scenario (solver.method = \
\"langevin\" or \"brownian\" at thermal.temperature > 0), from its initial state:
  with --reset (or --horizon): p = P(target before reset [and before the horizon T]);
  without: the mean first-passage time to the target [s].
COND is the grammar of `ensemble --first-passage`: COLUMN>VALUE or COLUMN<VALUE over trajectory.csv
columns (SI units), several joined by ',' (any of them), e.g. 'theta<1.07,theta>2.07'.

Methods:
  exact   the exact answer where theta is a one-dimensional diffusion: the Brownian mode on the
          plane (wells, gravity, adhesion, contact damping, a constant H_x; conditions on theta
          only; no horizon). Mean first-passage time and splitting probability by quadrature in
          log space (barriers of hundreds of kT; a value past 1e308 is given by its logarithm).
          Anywhere else it refuses with the reason (exit 2). docs/physics.md §22.1.
  direct  a plain ensemble of --replicas runs (run K is the scenario with thermal.run = r0 + K),
          each until the target or the reset holds at the end of a step (a tie goes to the
          target), or the horizon, or --max-steps steps (censored): solver.t_end and
          solver.samples do not cut a run short. p with the Wilson 95 % interval (censored or
          failed runs widen it upwards); the mean time with mean +- t(0.975, n-1) s/sqrt(n) (with
          censored runs: a lower bound, the interval open above).
  ams     adaptive multilevel splitting (not available yet).

Writes into --out:
  rare.json  quantity (\"probability\" or \"mean_first_passage_time\"), estimate, ci95 [lo, hi]
             (null where unknown or past f64), ln_estimate, method, replicas, trajectories, steps,
             wall_seconds, exact (the exact answer where it applies: value and its log for the
             continuous path, watched: the same for a path watched every solver.dt, the theta
             window; else exact_unavailable, the reason), the conditions, the budgets, the
             tallies of a direct ensemble, the scenario
  rare.md    the answer in words, 4 significant figures
The files are the same bytes for any --threads, apart from wall_seconds. Bad input (a condition
that holds at the start, --method exact where it is not exact, budgets out of range) exits with
code 2 and writes nothing; runs that fail part-way are counted, the files written, and the
command exits with code 3.";

/// `tippetop rare`.
#[derive(Debug, Args)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop rare --preset nano-physical --set solver.method=brownian --set solver.dt=2e-15 \\\n    \
                  --target 'theta<1.22,theta>1.92' --method exact --out out/rare\n  \
                  tippetop rare scenarios/thermal.toml --target 'theta>1.9' --reset 'theta<1.2' \\\n    \
                  --method direct --replicas 2000 --out out/rare"
)]
pub struct RareArgs {
    /// Scenario file (TOML): a Langevin or Brownian run at temperature > 0.
    #[arg(value_name = "SCENARIO.toml")]
    pub scenario: Option<PathBuf>,

    /// Start from a built-in scenario ("nano", "nano-physical", "classical").
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,

    /// Override one scenario value, e.g. `--set thermal.temperature=77`;
    /// repeatable, applied in order after the file.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub sets: Vec<String>,

    /// The target condition (the `--first-passage` grammar), e.g.
    /// `theta<1.22,theta>1.92`.
    #[arg(long, value_name = "COND")]
    pub target: String,

    /// The reset condition: with it, the probability of the target before
    /// the reset.
    #[arg(long, value_name = "COND")]
    pub reset: Option<String>,

    /// exact, direct or ams (default direct).
    #[arg(long, value_name = "METHOD", default_value = "direct")]
    pub method: String,

    /// Independent runs of the direct method (>= 1; default 1000).
    #[arg(long, value_name = "N")]
    pub replicas: Option<usize>,

    /// Horizon T [s]: p = P(target before reset and before T).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub horizon: Option<f64>,

    /// Step budget of one trajectory, 1 to 20000000 (default 1000000).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,

    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// Number of threads, 1 to 1024 (default: one per core).
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}

/// A positive value with 4 significant figures from its logarithm (so
/// values past f64 print too: `3.162e+431`).
pub fn fmt_positive(p: Positive) -> String {
    if p.value.is_finite() && p.value > 0.0 && p.value >= 1e-300 {
        return format!("{:.4}", Sig(p.value));
    }
    if p.ln == f64::NEG_INFINITY {
        return "0".into();
    }
    let l10 = p.ln / std::f64::consts::LN_10;
    let mut e = l10.floor();
    let mut m = 10f64.powf(l10 - e);
    if format!("{m:.3}") == "10.000" {
        m = 1.0;
        e += 1.0;
    }
    format!("{m:.3}e{}{}", if e >= 0.0 { "+" } else { "" }, e as i64)
}

/// 4 significant figures: fixed for 1e-3 <= |v| < 1e4, scientific beyond.
struct Sig(f64);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if !v.is_finite() {
            return write!(f, "{v}");
        }
        let a = v.abs();
        if v == 0.0 {
            write!(f, "0")
        } else if (1e-3..1e4).contains(&a) {
            let digits = (3 - a.log10().floor() as i32).max(0) as usize;
            write!(f, "{v:.digits$}")
        } else {
            write!(f, "{v:.3e}")
        }
    }
}

fn s4(v: f64) -> String {
    format!("{}", Sig(v))
}

/// What is estimated, in words.
fn question(p: &Problem) -> String {
    match p.quantity() {
        Quantity::Probability => {
            let mut s = format!("P({}", p.target);
            if let Some(r) = &p.reset {
                let _ = write!(s, " before {r}");
            }
            if let Some(t) = p.horizon {
                let _ = write!(s, " within {} s", s4(t));
            }
            s.push(')');
            s
        }
        Quantity::MeanFirstPassageTime => format!("mean first-passage time to {}", p.target),
    }
}

fn with_unit(v: f64, q: Quantity) -> String {
    match q {
        Quantity::Probability => s4(v),
        Quantity::MeanFirstPassageTime => format!("{} s", s4(v)),
    }
}

fn interval(ci: [f64; 2], q: Quantity) -> String {
    let hi = if ci[1].is_finite() {
        with_unit(ci[1], q)
    } else {
        "unknown (censored runs)".into()
    };
    format!("{} .. {hi}", with_unit(ci[0], q))
}

fn exact_words(e: &Exact, q: Quantity) -> String {
    let unit = if q == Quantity::MeanFirstPassageTime {
        " s"
    } else {
        ""
    };
    let mut s = format!("{}{unit}", fmt_positive(e.value));
    if let Some(w) = e.watched {
        let _ = write!(
            s,
            " (watched at every step of solver.dt: {}{unit})",
            fmt_positive(w)
        );
    }
    s
}

/// The console's summary lines.
fn summary_lines(p: &Problem, r: &Report, wall: f64) -> Vec<String> {
    let q = r.quantity;
    let mut lines = Vec::new();
    match r.method {
        RareMethod::Exact => {
            let e = r.exact.as_ref().expect("the exact method has its answer");
            lines.push(format!(
                "{} = {} (exact, 1D)",
                question(p),
                exact_words(e, q)
            ));
        }
        _ => {
            let bound = r
                .tally
                .as_ref()
                .is_some_and(|t| q == Quantity::MeanFirstPassageTime && t.censored > 0);
            lines.push(format!(
                "{} = {}{} (95 % CI {}), {}: {} trajectories, {} steps, {:.1} s",
                question(p),
                if bound { ">= " } else { "" },
                with_unit(r.estimate, q),
                interval(r.ci95, q),
                r.method.name(),
                r.trajectories,
                r.steps,
                wall
            ));
            match &r.exact {
                Some(e) => lines.push(format!("exact (1D): {}", exact_words(e, q))),
                None => lines.push(format!(
                    "exact (1D): not applicable ({})",
                    r.exact_unavailable.clone().unwrap_or_default()
                )),
            }
        }
    }
    lines
}

fn markdown(p: &Problem, r: &Report, wall: f64) -> String {
    let q = r.quantity;
    let mut s = String::new();
    let _ = writeln!(s, "# Rare event: {}\n", question(p));
    let _ = writeln!(
        s,
        "From the scenario's initial state (theta = {} rad), T = {} K, seed {}.\n",
        s4(p.scenario.initial.theta),
        s4(p.scenario.thermal.temperature),
        p.scenario.thermal.seed.unwrap_or(0)
    );
    match r.method {
        RareMethod::Exact => {
            let e = r.exact.as_ref().expect("exact");
            let _ = writeln!(
                s,
                "**Exact (one-dimensional θ diffusion): {}**\n",
                exact_words(e, q)
            );
        }
        _ => {
            let t = r.tally.clone().unwrap_or_default();
            let _ = writeln!(
                s,
                "**{}: {} (95 % interval {})**\n",
                r.method.name(),
                with_unit(r.estimate, q),
                interval(r.ci95, q)
            );
            let _ = writeln!(
                s,
                "{} trajectories, {} steps in {:.1} s: {} met the target, {} the reset, {} reached the horizon, {} used their whole budget of {} steps, {} failed.\n",
                r.trajectories,
                r.steps,
                wall,
                t.target,
                t.reset,
                t.horizon,
                t.censored,
                p.max_steps,
                t.failed
            );
            match &r.exact {
                Some(e) => {
                    let _ = writeln!(
                        s,
                        "Exact (one-dimensional θ diffusion): {}.\n",
                        exact_words(e, q)
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "No exact answer here: {}.\n",
                        r.exact_unavailable.clone().unwrap_or_default()
                    );
                }
            }
        }
    }
    if let Some(e) = &r.exact {
        let edge = |e: Option<Edge>, pole: &str| match e {
            Some(e) => format!(
                "{} rad ({})",
                s4(e.theta),
                if e.target { "target" } else { "reset" }
            ),
            None => format!("none (the pole {pole}, reflecting)"),
        };
        let _ = writeln!(
            s,
            "θ window: lower edge {}, upper edge {}.",
            edge(e.lower, "0"),
            edge(e.upper, "π")
        );
    }
    s
}

/// Run `tippetop rare`. Bad input: one line and exit code 2 (returned as
/// `Ok`), nothing written; `Err` for I/O failures.
pub fn run(args: &RareArgs, quiet: bool) -> Result<ExitCode> {
    let started = std::time::Instant::now();
    let toml_text = match crate::scenario_load::read_text(args.scenario.as_deref()) {
        Ok(t) => t,
        Err(code) => return Ok(code),
    };
    let method = match RareMethod::parse(&args.method) {
        Ok(m) => m,
        Err(e) => return Ok(input_error(e)),
    };
    if let Err(e) = tippetop::analysis::sweep::threads(args.threads) {
        return Ok(input_error(e));
    }
    let scenario =
        match tippetop::Scenario::load(args.preset.as_deref(), toml_text.as_deref(), &args.sets) {
            Ok(s) => s,
            Err(e) => return Ok(input_error(e)),
        };
    let prob = match Problem::new(
        scenario,
        &args.target,
        args.reset.as_deref(),
        args.horizon,
        args.max_steps,
    ) {
        Ok(p) => p,
        Err(e) => return Ok(input_error(e)),
    };
    let replicas = args.replicas.unwrap_or(DEFAULT_REPLICAS);
    let report = match method {
        RareMethod::Ams => {
            return Ok(input_error("--method ams is not available yet"));
        }
        RareMethod::Exact => {
            if args.replicas.is_some() {
                return Ok(input_error(
                    "--replicas: given with --method exact (which runs no trajectory)",
                ));
            }
            match problem::by_exact(&prob) {
                Ok(r) => r,
                Err(e) if e.is_input() => return Ok(input_error(e)),
                Err(e) => return Err(e.into()),
            }
        }
        RareMethod::Direct => {
            if replicas == 0 || replicas as u64 > tippetop::thermal::MAX_RUNS {
                return Ok(input_error(format!(
                    "--replicas: {replicas} is not allowed (N >= 1, the run indices below 4294967296)"
                )));
            }
            let out = OutDir::open(&args.out)?;
            let pb = crate::progress::bar(quiet, replicas as u64, "rare (direct)");
            let r = problem::by_direct(&prob, replicas, args.threads, &mut |done| {
                pb.set_position(done as u64);
                true
            });
            pb.finish_and_clear();
            match r {
                Ok(r) => return finish(args, &prob, &r, out, started, quiet),
                Err(e) => {
                    out.abandon();
                    if e.is_input() {
                        return Ok(input_error(e));
                    }
                    return Err(e.into());
                }
            }
        }
    };
    let out = OutDir::open(&args.out)?;
    finish(args, &prob, &report, out, started, quiet)
}

/// Write rare.json and rare.md, print the summary; exit code 3 if runs
/// failed.
fn finish(
    args: &RareArgs,
    prob: &Problem,
    report: &Report,
    out: OutDir,
    started: std::time::Instant,
    quiet: bool,
) -> Result<ExitCode> {
    let wall = started.elapsed().as_secs_f64();
    let stage = out.stage().to_path_buf();
    let mut text = serde_json::to_string_pretty(&report.document(prob, wall))?;
    text.push('\n');
    write_bytes_atomic(&stage.join("rare.json"), text.as_bytes())?;
    write_bytes_atomic(
        &stage.join("rare.md"),
        markdown(prob, report, wall).as_bytes(),
    )?;
    out.commit(&["rare.json"])?;
    if !quiet {
        for l in summary_lines(prob, report, wall) {
            println!("{l}");
        }
        println!("wrote {}", args.out.display());
    }
    if let Some(t) = &report.tally {
        if t.failed > 0 {
            eprintln!(
                "error: {} of {} runs failed (first: {})",
                t.failed,
                t.runs(),
                t.first_error.clone().unwrap_or_default()
            );
            return Ok(ExitCode::from(3));
        }
    }
    Ok(ExitCode::SUCCESS)
}
