//! `tippetop bit`: a memory bit's write and erase protocols, run once at
//! T = 0 or as an ensemble of Langevin runs at T > 0, with success
//! probabilities, switching times and energies. The library part is
//! [`tippetop::input::scenario::bit`] (the tables) and [`tippetop::analysis::bit`]
//! (the evaluation and statistics); the runs go through the sweep's
//! ordered parallel runner ([`sweep::run_ordered`]).

use std::fmt::Write as _;
use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;
use tippetop::analysis::bit::{self, Block, Mode, Report, RunResult};
use tippetop::analysis::step_check::{self, AtStep, Scale, StepCheck};
use tippetop::analysis::sweep::{self, Shard, ShardInfo, Sweep};
use tippetop::input::scenario::bit::BitScenario;
use tippetop::input::thermal::{MAX_ENSEMBLE_RUNS, MAX_RUNS};

use crate::output::{OutDir, write_bytes_atomic};
use crate::partial::{check_checksum, checksum};

pub use crate::bit_args::{BIT_LONG_ABOUT, BitArgs};

/// Runs of an ensemble when `--runs` is not given (T > 0).
pub const DEFAULT_RUNS: usize = 100;

use crate::scenario_load::input_error;

/// Run `tippetop bit`. Bad input: one line on stderr and exit code 2
/// (returned as `Ok`), nothing written; `Err` for I/O failures.
pub fn run(args: &BitArgs, quiet: bool) -> Result<ExitCode> {
    if !args.vary.is_empty() {
        return run_map(args, quiet);
    }
    let toml_text = match crate::scenario_load::read_text(args.source.scenario.as_deref()) {
        Ok(t) => t,
        Err(code) => return Ok(code),
    };
    if args.search {
        return crate::search_cmd::run(args, toml_text.as_deref(), quiet);
    }
    let threads = match sweep::threads(args.cores.threads) {
        Ok(t) => t,
        Err(e) => return Ok(input_error(e)),
    };
    let bs = match BitScenario::load(
        args.source.preset.as_deref(),
        toml_text.as_deref(),
        &args.source.sets,
    ) {
        Ok(b) => b,
        Err(e) => return Ok(input_error(e)),
    };
    let stochastic = bit::is_stochastic(&bs);
    let runs = match run_count(args, &bs, stochastic) {
        Ok(n) => n,
        Err(code) => return Ok(code),
    };
    let plan = match step_plan(args.no_step_check, &bs, stochastic, runs) {
        Ok(p) => p,
        Err(e) => return Ok(input_error(e)),
    };
    // With the check the command keeps the results of both passes.
    let kept_runs = match plan {
        StepPlan::Run(_) => 2 * runs,
        StepPlan::Off(_) => runs,
    };
    let threads = match bit::threads_within_memory(&bs, kept_runs, threads) {
        Ok(t) => crate::scenario_load::note_threads(quiet, threads, t),
        Err(e) => return Ok(input_error(e)),
    };

    let shard = match args.shard.as_deref().map(Shard::parse).transpose() {
        Ok(s) => s,
        Err(e) => return Ok(input_error(e)),
    };
    let range = match shard {
        None => 0..runs,
        Some(_) if !stochastic => {
            return Ok(input_error(
                "--shard: a bit at T = 0 is one run (--shard K/N splits the runs of an \
                 ensemble at T > 0, or with --vary the points of a map)",
            ));
        }
        Some(sh) => match sweep::shard_range(runs, sh) {
            Ok(r) => r,
            Err(e) => return Ok(input_error(e)),
        },
    };

    if args.resume && !stochastic {
        return Ok(input_error(
            "--resume: a bit at T = 0 is one run, there is nothing to resume (--resume \
             continues an ensemble at T > 0, or a map with --vary)",
        ));
    }
    let mut out = OutDir::open(&args.out)?;
    let mut results: Vec<RunResult> = Vec::with_capacity(range.len());
    // The deterministic run is kept for the figure; an ensemble's typical
    // run is run again.
    let mut kept: Option<tippetop::Trajectory> = None;
    // The step check's runs: the second pass, after the first is on disk
    // whole, so that a kill during it leaves the first complete and
    // --resume goes on with the second.
    let mut fine_results: Vec<RunResult> = Vec::new();
    if stochastic {
        let mut passes = vec![(Pass::MAIN, &bs)];
        if let StepPlan::Run(fine) = &plan {
            passes.push((Pass::HALF_DT, fine.as_ref()));
        }
        for (k, (pass, pass_bs)) in passes.into_iter().enumerate() {
            let got = match stream_ensemble(
                &mut out,
                args,
                (pass, pass_bs),
                toml_text.clone(),
                runs,
                (shard, range.clone()),
                threads,
                quiet,
            )? {
                Ok(r) => r,
                Err(code) => {
                    out.abandon();
                    return Ok(code);
                }
            };
            if k == 0 {
                results = got;
            } else {
                fine_results = got;
            }
        }
    } else {
        match deterministic_run(&bs, quiet) {
            Ok((result, traj)) => {
                results.push(result);
                kept = Some(traj);
            }
            Err(e) => {
                out.abandon();
                return Ok(input_error(e));
            }
        }
    }
    let step = match &plan {
        StepPlan::Run(fine) => StepRuns::Done(fine, &fine_results),
        StepPlan::Off(why) => StepRuns::Off(why.clone()),
    };
    if let Some(sh) = shard {
        let fingerprint = ensemble_grid(args, toml_text)
            .fingerprint_of("tippetop bit 1", &[("runs", runs.to_string())]);
        return write_shard(
            out,
            args,
            &bs,
            (sh, fingerprint),
            runs,
            range,
            (&results, &step),
            quiet,
        );
    }
    write_bit(
        out,
        &args.out,
        &bs,
        &results,
        !stochastic,
        kept,
        &step,
        quiet,
    )
}

/// `tippetop bit --vary`: the design map, which runs no step check (each
/// point's check would double its cost, and the point worth checking is
/// the one the map picks).
fn run_map(args: &BitArgs, quiet: bool) -> Result<ExitCode> {
    let code = crate::bitmap_cmd::run(args, quiet)?;
    if code == ExitCode::SUCCESS && !quiet {
        if args.no_step_check {
            println!("step unchecked (--no-step-check)");
        } else {
            println!("{MAP_UNCHECKED}");
        }
    }
    Ok(code)
}

/// The one run of a bit at T = 0, with a progress bar: its result and
/// its trajectory (the θ figure; neither reads the pose).
fn deterministic_run(
    bs: &BitScenario,
    quiet: bool,
) -> std::result::Result<(RunResult, tippetop::Trajectory), tippetop::Error> {
    let sc = bs.run_scenario(0);
    let mut progress = crate::progress::RunProgress::new(quiet, sc.solver.t_end);
    let traj = tippetop::simulate_watching_with_pose(&sc, &bit::watches(bs), false, &mut |p| {
        progress.update(p)
    });
    progress.finish();
    let (traj, stays) = traj?;
    Ok((bit::evaluate_run(bs, sc.thermal.run, &traj, &stays), traj))
}

/// What `tippetop bit --vary` prints: a map runs no step check.
const MAP_UNCHECKED: &str = "step unchecked: a map (each point's check would double its cost); \
                             check the chosen point with tippetop bit --set KEY=VALUE, without --vary";

/// The CSV of the step check's runs at `solver.dt / 2` (the columns of
/// runs.csv), beside runs.csv in a bit's and a shard's output.
const HALF_DT_CSV: &str = "runs_half_dt.csv";

/// What the step check of a bit does.
enum StepPlan {
    /// Run the ensemble again on this bit scenario: the scenario at
    /// `solver.dt / 2` ([`step_check::refined`]), the same runs.
    Run(Box<BitScenario>),
    /// No check, and why (bit.json's `step_unchecked`).
    Off(String),
}

/// Why a bit has no step check (`None`: it has one): `--no-step-check`;
/// one deterministic run (no interval); a single run (an interval that
/// spans most of [0, 1] and a probability of 0 or 1: nothing to compare).
fn unchecked_reason(no_check: bool, stochastic: bool, runs: usize) -> Option<String> {
    if no_check {
        return Some("--no-step-check".into());
    }
    if !stochastic {
        return Some(
            "one deterministic run (T = 0 or a deterministic solver.method): no 95 % interval \
             to compare a change of the step with"
                .into(),
        );
    }
    if runs < 2 {
        return Some(
            "one run (--runs 1): its probabilities are 0 or 1, with no interval worth \
             comparing; --runs 2 or more"
                .into(),
        );
    }
    None
}

/// The step check's plan ([`unchecked_reason`]; else the bit at dt/2).
/// Error: the refined scenario is invalid (the key named, the check said).
fn step_plan(
    no_check: bool,
    bs: &BitScenario,
    stochastic: bool,
    runs: usize,
) -> std::result::Result<StepPlan, tippetop::Error> {
    if let Some(why) = unchecked_reason(no_check, stochastic, runs) {
        return Ok(StepPlan::Off(why));
    }
    Ok(StepPlan::Run(Box::new(refined_bit(bs)?)))
}

/// The bit scenario of the step check: the run's scenario at `solver.dt /
/// 2` ([`step_check::refined`]), the states and protocols unchanged.
/// Error: the refined scenario is invalid (the message says it is the
/// check's, and how to skip it).
fn refined_bit(bs: &BitScenario) -> std::result::Result<BitScenario, tippetop::Error> {
    let scenario = step_check::refined(&bs.scenario).map_err(|e| match e {
        tippetop::Error::Invalid { key, what, range } => tippetop::Error::Invalid {
            key,
            what: format!("{what} in the step check's scenario at solver.dt/2"),
            range: format!("{range}; --no-step-check skips the check"),
        },
        other => other,
    })?;
    Ok(BitScenario {
        scenario,
        ..bs.clone()
    })
}

/// The step check's runs, for the outputs.
enum StepRuns<'a> {
    /// The runs at dt/2 of this bit scenario, in run order (those of the
    /// shard, in a shard).
    Done(&'a BitScenario, &'a [RunResult]),
    /// No check, and why.
    Off(String),
}

/// The step check's result: each checked probability, or why none is.
enum StepOutcome {
    /// The runs at dt/2 ran.
    Done {
        /// Each probability with a 95 % interval at dt: its block's name
        /// in bit.json and the comparison, in bit.json's order.
        checks: Vec<(&'static str, StepCheck)>,
        /// The runs at dt/2, and how many failed.
        runs: usize,
        failed: usize,
    },
    /// No check, and why.
    Off(String),
}

impl StepOutcome {
    /// Compare the report at dt (`a`, of `bs`) with the runs at dt/2.
    fn of(bs: &BitScenario, a: &Report, step: &StepRuns) -> StepOutcome {
        let (fine, fine_results) = match step {
            StepRuns::Done(f, r) => (f, r),
            StepRuns::Off(why) => return StepOutcome::Off(why.clone()),
        };
        let b = bit::report(fine, fine_results, false);
        let dt = bs.scenario.solver.dt.unwrap_or(f64::NAN);
        let dt2 = fine.scenario.solver.dt.unwrap_or(f64::NAN);
        let mut checks = Vec::new();
        for (name, x, y) in [
            ("write", &a.write, &b.write),
            ("erase", &a.erase, &b.erase),
            (
                "erase_given_write",
                &a.erase_given_write,
                &b.erase_given_write,
            ),
            ("cycle", &a.cycle, &b.cycle),
        ] {
            let Some((estimate, ci95)) = x.probability.zip(x.ci95) else {
                continue;
            };
            let at = AtStep { dt, estimate, ci95 };
            // Without its runs at dt/2 (no write succeeded there, for
            // erase_given_write) the answer is NaN (null in bit.json), and
            // the check is not converged.
            let half = y.probability.zip(y.ci95).map_or(
                AtStep {
                    dt: dt2,
                    estimate: f64::NAN,
                    ci95: [f64::NAN; 2],
                },
                |(estimate, ci95)| AtStep {
                    dt: dt2,
                    estimate,
                    ci95,
                },
            );
            checks.push((name, at, half));
        }
        // Judged together: each half-width gets the family's Bonferroni
        // factor, so a bit with no step error is flagged about 5 % of the
        // time in all.
        let m = checks.len();
        let checks = checks
            .into_iter()
            .map(|(name, at, half)| (name, StepCheck::in_family(at, half, Scale::Linear, m)))
            .collect();
        StepOutcome::Done {
            checks,
            runs: fine_results.len(),
            failed: fine_results.iter().filter(|r| r.status != "ok").count(),
        }
    }

    /// `dt_converged`: whether every checked probability converged; `None`
    /// without a check.
    fn converged(&self) -> Option<bool> {
        match self {
            StepOutcome::Done { checks, .. } if !checks.is_empty() => {
                Some(checks.iter().all(|c| c.1.converged))
            }
            _ => None,
        }
    }

    /// Why the step is unchecked (`None`: checked).
    fn unchecked(&self) -> Option<&str> {
        match self {
            StepOutcome::Off(why) => Some(why),
            StepOutcome::Done { checks, .. } if checks.is_empty() => {
                Some("no probability has a 95 % interval")
            }
            StepOutcome::Done { .. } => None,
        }
    }

    /// The checked probabilities that did not converge.
    fn unconverged(&self) -> Vec<&'static str> {
        match self {
            StepOutcome::Done { checks, .. } => checks
                .iter()
                .filter(|c| !c.1.converged)
                .map(|c| c.0)
                .collect(),
            StepOutcome::Off(_) => Vec::new(),
        }
    }

    /// The steps compared: (dt, dt/2) \[s\].
    fn steps(&self) -> Option<(f64, f64)> {
        match self {
            StepOutcome::Done { checks, .. } => {
                checks.first().map(|c| (c.1.at_dt.dt, c.1.at_half_dt.dt))
            }
            StepOutcome::Off(_) => None,
        }
    }
}

/// One probability's check in words, without the leading "step check: ".
fn check_words(c: &StepCheck) -> String {
    let w = c.words(&prob);
    w.strip_prefix("step check: ").unwrap_or(&w).to_string()
}

/// The verdict line of a check that did not converge (`off`: the
/// probabilities that did not), for the console's warning and bit.md.
fn unconverged_words(off: &[&str], of: usize, (dt, dt2): (f64, f64)) -> String {
    format!(
        "NOT converged in the step: {} ({} of {of} probabilities) changed by more than the 95 % \
         half-width of the change from dt = {} s to dt/2 = {} s: a step error in the answer at \
         dt, or noise (a bit without step error is flagged at most about 5 % of the time); a \
         smaller \
         solver.dt tells them apart (dt_converged: false)",
        off.join(", "),
        off.len(),
        human(dt),
        human(dt2)
    )
}

/// The verdict line of a converged check.
fn converged_words(of: usize, (dt, dt2): (f64, f64)) -> String {
    format!(
        "converged in the step: each of the {of} probabilities changed by less than the 95 % \
         half-width of its change from dt = {} s to dt/2 = {} s (dt_converged: true)",
        human(dt),
        human(dt2)
    )
}

/// The number of runs: 1 at T = 0, `--runs` (default [`DEFAULT_RUNS`]) at
/// T > 0. Bad input: one line on stderr, `Err(exit code 2)`.
fn run_count(
    args: &BitArgs,
    bs: &BitScenario,
    stochastic: bool,
) -> std::result::Result<usize, ExitCode> {
    let sc = &bs.scenario;
    match (stochastic, args.runs) {
        (false, None | Some(1)) => Ok(1),
        (false, Some(n)) => Err(input_error(format!(
            "--runs: {n} runs of a deterministic scenario would all be the same \
             (1, or omit it, at T = 0; N >= 1 with solver.method = \"langevin\" at T > 0)"
        ))),
        (true, n) => {
            let n = n.unwrap_or(DEFAULT_RUNS);
            let room = MAX_RUNS - sc.thermal.run.min(MAX_RUNS);
            if n == 0 || n > MAX_ENSEMBLE_RUNS || n as u64 > room {
                return Err(input_error(format!(
                    "--runs: {n} runs from thermal.run = {} (1 <= N <= {MAX_ENSEMBLE_RUNS}, \
                     with the run indices thermal.run .. thermal.run + N - 1 below 4294967296)",
                    sc.thermal.run
                )));
            }
            Ok(n)
        }
    }
}

/// One pass of a bit ensemble's runs: the ensemble at the scenario's
/// step, or the step check's at half of it. Each streams into its own
/// partial files, so --resume keeps either.
#[derive(Debug, Clone, Copy)]
struct Pass {
    /// The partial CSV it streams into.
    partial_csv: &'static str,
    /// The partial description beside it.
    partial_info: &'static str,
    /// Its noun in the progress bar and the notes.
    what: &'static str,
    /// What its fingerprint adds to the ensemble's (the scenario, --set,
    /// --runs): nothing for the ensemble itself.
    extra: Option<(&'static str, &'static str)>,
}

impl Pass {
    /// The ensemble at the scenario's step.
    const MAIN: Pass = Pass {
        partial_csv: PARTIAL_RUNS,
        partial_info: crate::common::grid::PARTIAL_INFO,
        what: "bit ensemble",
        extra: None,
    };
    /// The step check's runs at `solver.dt / 2`.
    const HALF_DT: Pass = Pass {
        partial_csv: "runs_half_dt.csv.partial",
        partial_info: "shard_half_dt.json.partial",
        what: "step check (dt/2)",
        extra: Some(("step check", "solver.dt/2")),
    };
}

/// The runs `range` of a bit ensemble of `runs` (its shard `shard`) on
/// the bit scenario `bs` of the pass `pass`, streamed into the pass's
/// partial CSV in run order (beside the partial description that
/// identifies the ensemble), so --resume can keep them; then read back
/// for the statistics (the rows round-trip exactly). Bad input: one line
/// on stderr, `Ok(Err(exit code 2))` (the caller abandons `out`).
#[allow(clippy::too_many_arguments)]
fn stream_ensemble(
    out: &mut OutDir,
    args: &BitArgs,
    (pass, bs): (Pass, &BitScenario),
    toml_text: Option<String>,
    runs: usize,
    (shard, range): (Option<Shard>, std::ops::Range<usize>),
    threads: usize,
    quiet: bool,
) -> Result<std::result::Result<Vec<RunResult>, ExitCode>> {
    let sc = &bs.scenario;
    let sh = shard.unwrap_or(Shard::ALL);
    let mut extra = vec![("runs", runs.to_string())];
    extra.extend(pass.extra.map(|(k, v)| (k, v.to_string())));
    let info = ShardInfo {
        fingerprint: ensemble_grid(args, toml_text).fingerprint_of("tippetop bit 1", &extra),
        k: sh.k,
        n: sh.n,
        total_cases: runs,
        first_index: range.start,
        end_index: range.end,
        axes: Vec::new(),
        checksums: Default::default(),
    };
    let mut info_json = serde_json::to_string_pretty(&info)?;
    info_json.push('\n');
    // The check's pass resumes only what an interrupted check left: after
    // a kill during the ensemble's own pass there is none, and no note.
    let resume =
        args.resume && (pass.extra.is_none() || out.dir().join(pass.partial_info).exists());
    let spec = crate::common::grid::Streamed {
        partial_csv: pass.partial_csv,
        partial_info: pass.partial_info,
        header: format!("{}\n", bit::CSV_HEADER),
        what: pass.what,
        unit: "run",
        resume,
        quiet,
    };
    let r0 = sc.thermal.run;
    let streamed = crate::common::grid::stream_rows(
        out,
        &spec,
        &info,
        &info_json,
        &|text| runs_prefix(text, r0 + range.start as u64, range.len()),
        &mut |todo, sink| {
            sweep::run_ordered(
                todo,
                Some(threads),
                &|k| bit::run_one(bs, k as u64),
                &mut |r| sink(bit::csv_row(&r), r.status != "ok"),
            )
        },
    )?;
    if let Err(code) = streamed {
        return Ok(Err(code));
    }
    let name = pass.partial_csv;
    let text = String::from_utf8(crate::output::read_plain(&args.out.join(name))?)?;
    let results: Vec<RunResult> = text
        .lines()
        .skip(1)
        .map(|l| {
            bit::parse_csv_row(l).ok_or_else(|| anyhow::anyhow!("{name}: unreadable row {l:?}"))
        })
        .collect::<Result<_>>()?;
    anyhow::ensure!(
        results.len() == range.len(),
        "{name}: {} rows for {} runs",
        results.len(),
        range.len()
    );
    Ok(Ok(results))
}

/// Write the outputs of a whole bit (`results` of every run, in run
/// order; `kept`: the deterministic run's trajectory, for the figure;
/// `step`: the step check's runs) into `out` and commit it.
#[allow(clippy::too_many_arguments)]
fn write_bit(
    out: OutDir,
    dir: &Path,
    bs: &BitScenario,
    results: &[RunResult],
    deterministic: bool,
    kept: Option<tippetop::Trajectory>,
    step: &StepRuns,
    quiet: bool,
) -> Result<ExitCode> {
    let bs = bs.clone();
    let report = bit::report(&bs, results, deterministic);
    let check = StepOutcome::of(&bs, &report, step);

    let stage = out.stage().to_path_buf();
    let json = bit_json(&bs, &report, &check);
    let mut text = serde_json::to_string_pretty(&json)?;
    text.push('\n');
    write_bytes_atomic(&stage.join("bit.json"), text.as_bytes())?;
    write_bytes_atomic(&stage.join("runs.csv"), runs_csv(results).as_bytes())?;
    if let StepRuns::Done(_, fine) = step {
        write_bytes_atomic(&stage.join(HALF_DT_CSV), runs_csv(fine).as_bytes())?;
    }
    write_bytes_atomic(&stage.join("bit.toml"), bs.to_toml_string().as_bytes())?;
    write_bytes_atomic(
        &stage.join("scenario.toml"),
        bs.scenario.to_toml_string().as_bytes(),
    )?;
    let typical = typical_run(results);
    let traj = match kept {
        Some(t) => Ok(t),
        // θ's figure: no pose.
        None => tippetop::simulate_with_pose(&bs.run_scenario(typical as u64), false, &mut |_| {}),
    };
    let figure = match traj
        .map_err(anyhow::Error::from)
        .and_then(|t| theta_figure(&stage, &bs, results[typical].run, &t))
    {
        Ok(()) => Some(typical),
        Err(e) => {
            if !quiet {
                eprintln!("warning: no theta figure: {e:#}");
            }
            None
        }
    };
    let modes = failure_figures(&stage, &bs, results, quiet);
    let mut md = bit_md(&bs, &report, &check, figure.map(|k| &results[k]));
    if !modes.is_empty() {
        let _ = writeln!(md, "## Failure modes\n");
        for (file, phase, mode, run) in &modes {
            let _ = writeln!(
                md,
                "![{phase} {mode}]({file}.png)\n\nθ(t) of run {run}, the first whose {phase} failed \
                 as `{mode}`.\n"
            );
        }
    }
    write_bytes_atomic(&stage.join("bit.md"), md.as_bytes())?;
    out.commit(&["bit.json"])?;
    if !quiet {
        for (name, b) in [
            ("write", &report.write),
            ("erase", &report.erase),
            ("erase_given_write", &report.erase_given_write),
            ("cycle", &report.cycle),
        ] {
            println!("{name}: {}", one_line(b));
        }
        print_step(&check);
        println!("wrote {}", dir.display());
    }
    Ok(ExitCode::SUCCESS)
}

/// The step check for people: a line per probability, then whether the
/// bit is converged in the step (a warning on stderr if not), or why the
/// step is unchecked.
fn print_step(check: &StepOutcome) {
    let (
        StepOutcome::Done {
            checks,
            runs,
            failed,
        },
        Some(converged),
        Some(steps),
    ) = (check, check.converged(), check.steps())
    else {
        if let Some(why) = check.unchecked() {
            println!("step unchecked ({why})");
        }
        return;
    };
    println!(
        "step check: the {runs} runs again at dt/2 = {} s (independent noise; {failed} failed), \
         each probability's change against its own 95 % half-width",
        human(steps.1)
    );
    for (name, c) in checks {
        println!("step check {name}: {}", check_words(c));
    }
    if converged {
        println!("step check: {}", converged_words(checks.len(), steps));
    } else {
        eprintln!(
            "warning: {}",
            unconverged_words(&check.unconverged(), checks.len(), steps)
        );
    }
}

/// The CSV a bit ensemble's shard writes (one row per run of the shard).
const RUNS_CSV: &str = "runs.csv";

/// The file an ensemble streams its runs into while it runs (removed at
/// the end, when `runs.csv` is written).
const PARTIAL_RUNS: &str = "runs.csv.partial";

/// The complete rows an interrupted ensemble left in `runs.csv.partial`
/// (`text`): the header, then rows of runs `r0, r0 + 1, ...` (at most
/// `max`), each a line [`bit::csv_row`] writes ([`check_run_line`]); a torn
/// last line is dropped; `problem` says why a complete line was refused.
fn runs_prefix(text: &str, r0: u64, max: usize) -> sweep::Prefix {
    let header = format!("{}\n", bit::CSV_HEADER);
    let mut p = sweep::Prefix::default();
    if !text.starts_with(&header) {
        p.problem = Some("not the header");
        return p;
    }
    p.bytes = header.len();
    for line in text[header.len()..].split_inclusive('\n') {
        let Some(body) = line.strip_suffix('\n') else {
            break;
        };
        let checked = if p.rows < max {
            check_run_line(body, r0 + p.rows as u64)
        } else {
            Err("past the last run")
        };
        match checked {
            Ok(failed) => p.failed += usize::from(failed),
            Err(why) => {
                p.problem = Some(why);
                break;
            }
        }
        p.rows += 1;
        p.bytes += line.len();
    }
    p
}

/// Check a line of `runs.csv` (without its `\n`) as the row of run
/// `run` (`thermal.run`): exactly what [`bit::csv_row`] writes for the
/// result it parses to. `Ok(true)`: its status is not `ok`.
fn check_run_line(body: &str, run: u64) -> std::result::Result<bool, &'static str> {
    let r = bit::parse_csv_row(body).ok_or("not a run's row")?;
    if r.run != run {
        return Err("not the run's index");
    }
    if bit::csv_row(&r).strip_suffix('\n') != Some(body) {
        return Err("not a row as tippetop writes it");
    }
    Ok(r.status != "ok")
}

/// What defines a bit ensemble's output, for its shards: the scenario
/// (preset, file, `--set`s) and the number of runs.
fn ensemble_grid(args: &BitArgs, toml_text: Option<String>) -> Sweep {
    Sweep {
        preset: args.source.preset.clone(),
        toml_text,
        sets: args.source.sets.clone(),
        axes: Vec::new(),
    }
}

/// A shard of a bit ensemble: `runs.csv` of its runs, `shard.json`
/// (`total_cases` = the runs of the whole ensemble; the fingerprint of
/// [`ensemble_grid`] and the runs), `bit.toml`; with the step check,
/// `runs_half_dt.csv`, the check's runs of the same block (its checksum in
/// shard.json says the shard has it).
#[allow(clippy::too_many_arguments)]
fn write_shard(
    out: OutDir,
    args: &BitArgs,
    bs: &BitScenario,
    (shard, fingerprint): (Shard, String),
    runs: usize,
    range: std::ops::Range<usize>,
    (results, step): (&[RunResult], &StepRuns),
    quiet: bool,
) -> Result<ExitCode> {
    let info = ShardInfo {
        fingerprint,
        k: shard.k,
        n: shard.n,
        total_cases: runs,
        first_index: range.start,
        end_index: range.end,
        axes: Vec::new(),
        checksums: Default::default(),
    };
    let stage = out.stage().to_path_buf();
    let (csv, toml) = (runs_csv(results), bs.to_toml_string());
    write_bytes_atomic(&stage.join(RUNS_CSV), csv.as_bytes())?;
    write_bytes_atomic(&stage.join("bit.toml"), toml.as_bytes())?;
    let mut sums = vec![
        (RUNS_CSV, checksum(csv.as_bytes())),
        ("bit.toml", checksum(toml.as_bytes())),
    ];
    if let StepRuns::Done(_, fine) = step {
        let fine = runs_csv(fine);
        write_bytes_atomic(&stage.join(HALF_DT_CSV), fine.as_bytes())?;
        sums.push((HALF_DT_CSV, checksum(fine.as_bytes())));
    }
    crate::common::grid::write_info(&stage, &info, &sums)?;
    out.commit(&["shard.json"])?;
    if !quiet {
        println!(
            "shard {}/{}: runs {}..{} of {} -> {}{}",
            shard.k,
            shard.n,
            range.start,
            range.end,
            runs,
            args.out.join(RUNS_CSV).display(),
            match step {
                StepRuns::Done(..) => format!(" (the step check's at dt/2: {HALF_DT_CSV})"),
                StepRuns::Off(why) => format!(" (step unchecked: {why})"),
            }
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Whether `dir` holds a shard of a bit ensemble (`runs.csv` beside
/// `shard.json`), for `tippetop merge`.
pub fn is_bit_shard_dir(dir: &Path) -> bool {
    dir.join(RUNS_CSV).is_file() && dir.join("shard.json").is_file()
}

/// `tippetop merge` of the shards of one bit ensemble: the outputs of an
/// unsharded run (bit.json, bit.md, runs.csv, bit.toml, scenario.toml, the
/// figure), byte for byte.
pub fn merge(args: &crate::common::args::MergeArgs, quiet: bool) -> Result<ExitCode> {
    let mut shards: Vec<(ShardInfo, String)> = Vec::new();
    // The step check's runs of each shard (`None`: run with
    // --no-step-check, or a check that does not apply).
    let mut halves: Vec<Option<String>> = Vec::new();
    let mut tomls: Vec<String> = Vec::new();
    let what = "a directory written by tippetop bit --shard, with shard.json, runs.csv, bit.toml";
    for dir in &args.dirs {
        let _reading = crate::output::read_lock(dir)?;
        let read = |name: &str| {
            let path = dir.join(name);
            std::fs::read_to_string(&path)
                .map_err(|e| format!("{}: cannot read it: {e} ({what})", path.display()))
        };
        let got = (|| {
            let small = |name: &str| crate::scenario_load::read_small(&dir.join(name), what);
            let info: ShardInfo = serde_json::from_str(&small("shard.json")?)
                .map_err(|e| format!("{}: {e} ({what})", dir.join("shard.json").display()))?;
            let (csv, toml) = (read(RUNS_CSV)?, small("bit.toml")?);
            check_checksum(&info.checksums, dir, RUNS_CSV, csv.as_bytes())?;
            check_checksum(&info.checksums, dir, "bit.toml", toml.as_bytes())?;
            // A shard has the check's runs iff its shard.json has their
            // checksum.
            let half = if info.checksums.contains_key(HALF_DT_CSV) {
                let h = read(HALF_DT_CSV)?;
                check_checksum(&info.checksums, dir, HALF_DT_CSV, h.as_bytes())?;
                Some(h)
            } else {
                None
            };
            Ok::<_, String>((info, csv, toml, half))
        })();
        match got {
            Ok((info, csv, toml, half)) => {
                shards.push((info, csv));
                tomls.push(toml);
                halves.push(half);
            }
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    if let Some(i) = halves
        .iter()
        .position(|h| h.is_some() != halves[0].is_some())
    {
        let (with, without) = if halves[0].is_some() { (0, i) } else { (i, 0) };
        return Ok(input_error(format!(
            "merge: {} has the step check's runs ({HALF_DT_CSV}) and {} has not (all shards \
             with the step check, or all with --no-step-check)",
            args.dirs[with].display(),
            args.dirs[without].display()
        )));
    }
    if let Some(i) = tomls.iter().position(|t| *t != tomls[0]) {
        return Ok(input_error(format!(
            "merge: {} has another bit.toml than {} (all shards from one bit ensemble)",
            args.dirs[i].display(),
            args.dirs[0].display()
        )));
    }
    let bs = match BitScenario::load(None, Some(&tomls[0]), &[]) {
        Ok(b) => b,
        Err(e) => return Ok(input_error(e)),
    };
    let r0 = bs.scenario.thermal.run;
    let header = format!("{}\n", bit::CSV_HEADER);
    let csv = match sweep::merge_rows(&shards, &header, RUNS_CSV, "bit", &|_, index, line| {
        check_run_line(line, r0 + index as u64).map(|_| ())
    }) {
        Ok(c) => c,
        Err(e) => return Ok(input_error(e)),
    };
    let results: Option<Vec<RunResult>> = csv.lines().skip(1).map(bit::parse_csv_row).collect();
    let Some(results) = results else {
        return Ok(input_error(format!(
            "merge: a line of {RUNS_CSV} is not a run's row ({what})"
        )));
    };
    // The step check's runs, joined as the ensemble's are.
    let mut fine_results: Vec<RunResult> = Vec::new();
    let fine = if halves[0].is_some() {
        let fine = match refined_bit(&bs) {
            Ok(f) => f,
            Err(e) => return Ok(input_error(e)),
        };
        let half_shards: Vec<(ShardInfo, String)> = shards
            .iter()
            .zip(halves)
            .map(|((info, _), h)| (info.clone(), h.unwrap_or_default()))
            .collect();
        let csv = match sweep::merge_rows(
            &half_shards,
            &header,
            HALF_DT_CSV,
            "bit",
            &|_, index, line| check_run_line(line, r0 + index as u64).map(|_| ()),
        ) {
            Ok(c) => c,
            Err(e) => return Ok(input_error(e)),
        };
        let got: Option<Vec<RunResult>> = csv.lines().skip(1).map(bit::parse_csv_row).collect();
        let Some(got) = got else {
            return Ok(input_error(format!(
                "merge: a line of {HALF_DT_CSV} is not a run's row ({what})"
            )));
        };
        fine_results = got;
        Some(fine)
    } else {
        None
    };
    let step = match &fine {
        Some(f) => StepRuns::Done(f, &fine_results),
        // Shards without the check's runs: what the unsharded ensemble
        // would say (shards exist only at T > 0).
        None => StepRuns::Off(
            unchecked_reason(results.len() >= 2, true, results.len())
                .unwrap_or_else(|| "--no-step-check".into()),
        ),
    };
    let out = OutDir::open(&args.out)?;
    write_bit(out, &args.out, &bs, &results, false, None, &step, quiet)
}

/// bit.md's step-check section: what was compared, a line per
/// probability and the verdict (a warning when not converged), or why the
/// step is unchecked.
fn step_md(s: &mut String, check: &StepOutcome) {
    let _ = writeln!(s, "## Step check\n");
    let (
        StepOutcome::Done {
            checks,
            runs,
            failed,
        },
        Some(converged),
        Some(steps),
    ) = (check, check.converged(), check.steps())
    else {
        if let Some(why) = check.unchecked() {
            let _ = writeln!(s, "Step unchecked ({why}).\n");
        }
        return;
    };
    let _ = writeln!(
        s,
        "The {runs} runs again at dt/2 = {} s (solver.dt = {} s halved, the step limit doubled, \
         an independent seed; {failed} failed; their rows: `{HALF_DT_CSV}`). Each probability \
         with a 95 % interval is compared with its value at dt/2: converged in the step when \
         the change is below its own 95 % half-width (the two answers' half-widths in \
         quadrature, widened for the {} probabilities judged together). The figures above are \
         those at dt.\n",
        human(steps.1),
        human(steps.0),
        checks.len(),
    );
    for (name, c) in checks {
        let _ = writeln!(s, "- {name}: {}", check_words(c));
    }
    if converged {
        let _ = writeln!(s, "\nConverged in the step: {}.\n", {
            let w = converged_words(checks.len(), steps);
            w.strip_prefix("converged in the step: ")
                .unwrap_or(&w)
                .to_string()
        });
    } else {
        let _ = writeln!(
            s,
            "\n**Warning: {}.**\n",
            unconverged_words(&check.unconverged(), checks.len(), steps)
        );
    }
}

/// A number in bit.md and on the console: 4 significant figures
/// (`tippetop::human`); bit.json and runs.csv keep full precision.
fn human(x: f64) -> String {
    tippetop::human::sig(x, 4)
}

/// A probability for people: `0` and `1` exactly, else 3 significant
/// figures.
fn prob(p: f64) -> String {
    if p == 0.0 || p == 1.0 {
        format!("{p}")
    } else {
        tippetop::human::sig(p, 3)
    }
}

/// `v` with its unit, or `–` (no unit) when there is none.
fn opt_unit(v: Option<f64>, unit: &str) -> String {
    v.map(|x| format!("{} {unit}", human(x)))
        .unwrap_or_else(|| "–".into())
}

/// A block in one line: `P = 0.96 [0.90, 0.98] (96 of 100 runs), time
/// median 4.1e-5 s`; a single deterministic run has no interval and no
/// median: `P = 1 (one deterministic run), time 4.062e-5 s`.
fn one_line(b: &Block) -> String {
    let fails: Vec<String> = b
        .failures
        .iter()
        .filter(|(_, n)| **n > 0)
        .map(|(m, n)| format!("{m} {n}"))
        .collect();
    if b.deterministic && b.runs == 1 {
        let modes: Vec<&str> = b
            .failures
            .iter()
            .filter(|(_, n)| **n > 0)
            .map(|(m, _)| *m)
            .collect();
        return format!(
            "P = {} (one deterministic run){}, energy {}{}",
            b.probability.map_or_else(|| "-".into(), prob),
            b.time_median
                .map(|t| format!(", time {} s", human(t)))
                .unwrap_or_default(),
            opt_unit(b.energy_median, "J"),
            if modes.is_empty() {
                String::new()
            } else {
                format!("; failure: {}", modes.join(", "))
            }
        );
    }
    let ci = b
        .ci95
        .map(|[lo, hi]| format!(" [{}, {}]", prob(lo), prob(hi)))
        .unwrap_or_default();
    format!(
        "P = {}{ci} ({} of {} runs){}, time median {}, energy median {}{}",
        b.probability.map_or_else(|| "-".into(), prob),
        b.successes,
        b.runs,
        if b.deterministic {
            ", deterministic"
        } else {
            ""
        },
        opt_unit(b.time_median, "s"),
        opt_unit(b.energy_median, "J"),
        if fails.is_empty() {
            String::new()
        } else {
            format!("; failures: {}", fails.join(", "))
        }
    )
}

/// bit.json: the report, the bit and its protocols, and the step check
/// (`dt_converged`, `step_check`: each checked probability's comparison,
/// `step_unchecked`: why there is none; null where they do not apply).
fn bit_json(bs: &BitScenario, report: &Report, check: &StepOutcome) -> serde_json::Value {
    let windows = |list: &[tippetop::input::scenario::bit::Actuator]| -> serde_json::Value {
        list.iter()
            .map(|a| match a.kind {
                tippetop::input::scenario::bit::ActuatorKind::Body(
                    tippetop::BodyActuator::Tip { point, force },
                ) => serde_json::json!({
                    "kind": a.kind.name(), "point": point, "force": force,
                    "start": a.start, "stop": a.stop,
                }),
                tippetop::input::scenario::bit::ActuatorKind::Body(
                    tippetop::BodyActuator::Magnetic {
                        moment,
                        field,
                        gradient,
                    },
                ) => serde_json::json!({
                    "kind": a.kind.name(), "moment": moment, "field": field,
                    "gradient": gradient, "start": a.start, "stop": a.stop,
                }),
                tippetop::input::scenario::bit::ActuatorKind::Contact => serde_json::json!({
                    "kind": a.kind.name(), "hx": a.hx, "hy": a.hy, "hz": a.hz,
                    "start": a.start, "stop": a.stop,
                }),
            })
            .collect()
    };
    let b = &bs.bit;
    let mut v = serde_json::to_value(report).unwrap_or_default();
    if let Some(m) = v.as_object_mut() {
        m.insert(
            "bit".into(),
            serde_json::json!({
                "zero": b.zero, "one": b.one, "hold": b.hold, "phase": b.phase,
                "temperature": bs.scenario.thermal.temperature,
                "first_run": bs.scenario.thermal.run,
                "seed": bs.scenario.thermal.seed,
                "sample_spacing": 2.0 * b.phase / (bs.scenario.solver.samples - 1) as f64,
            }),
        );
        m.insert("write_protocol".into(), windows(&bs.write));
        m.insert("erase_protocol".into(), windows(&bs.erase));
        m.insert(
            "dt_converged".into(),
            check
                .converged()
                .map_or(serde_json::Value::Null, Into::into),
        );
        let checks = match check {
            StepOutcome::Done { checks, .. } if check.unchecked().is_none() => {
                let mut o = serde_json::Map::new();
                for (name, c) in checks {
                    o.insert((*name).into(), serde_json::to_value(c).unwrap_or_default());
                }
                serde_json::Value::Object(o)
            }
            _ => serde_json::Value::Null,
        };
        m.insert("step_check".into(), checks);
        m.insert(
            "step_unchecked".into(),
            check
                .unchecked()
                .map_or(serde_json::Value::Null, Into::into),
        );
    }
    v
}

fn outcome(p: &bit::PhaseResult) -> &'static str {
    p.failure.map(Mode::as_str).unwrap_or("ok")
}

fn runs_csv(results: &[RunResult]) -> String {
    let mut s = format!("{}\n", bit::CSV_HEADER);
    for r in results {
        s.push_str(&bit::csv_row(r));
    }
    s
}

/// For an ensemble (more than one run): `theta_PHASE_MODE.png/.svg` in
/// `dir`, θ(t) of the first run whose PHASE (write or erase) failed as
/// MODE, one per (phase, mode) seen (a run that failed to start has no
/// figure). Returns (file stem, phase, mode, thermal.run) per figure.
fn failure_figures(
    dir: &Path,
    bs: &BitScenario,
    results: &[RunResult],
    quiet: bool,
) -> Vec<(String, &'static str, &'static str, u64)> {
    let mut out = Vec::new();
    if results.len() < 2 {
        return out;
    }
    for phase in ["write", "erase"] {
        let mut seen: Vec<&'static str> = Vec::new();
        for (k, r) in results.iter().enumerate() {
            let p = if phase == "write" { &r.write } else { &r.erase };
            let Some(mode) = p.failure.map(Mode::as_str) else {
                continue;
            };
            if seen.contains(&mode) {
                continue;
            }
            seen.push(mode);
            let file = format!("theta_{phase}_{mode}");
            let made = tippetop::simulate_with_pose(&bs.run_scenario(k as u64), false, &mut |_| {})
                .map_err(anyhow::Error::from)
                .and_then(|t| {
                    theta_figure_named(dir, &file, &format!("{phase} {mode}: "), bs, r.run, &t)
                });
            match made {
                Ok(()) => out.push((file, phase, mode, r.run)),
                Err(e) => {
                    if !quiet {
                        eprintln!("warning: no figure for {phase} {mode}: {e:#}");
                    }
                }
            }
        }
    }
    out
}

/// The index of a typical run: the first whose (write, erase) outcome is
/// the most frequent one (ties: the outcome seen first).
pub fn typical_run(results: &[RunResult]) -> usize {
    let key = |r: &RunResult| (outcome(&r.write), outcome(&r.erase));
    let mut best = (0, 0);
    for (i, r) in results.iter().enumerate() {
        if results[..i].iter().any(|q| key(q) == key(r)) {
            continue;
        }
        let n = results.iter().filter(|q| key(q) == key(r)).count();
        if n > best.1 {
            best = (i, n);
        }
    }
    best.0
}

/// `theta.png`/`theta.svg` in `dir`: θ(t) of `traj` (`thermal.run` =
/// `run`), with the edges of the two states marked.
fn theta_figure(
    dir: &std::path::Path,
    bs: &BitScenario,
    run: u64,
    traj: &tippetop::Trajectory,
) -> Result<()> {
    theta_figure_named(dir, "theta", "", bs, run, traj)
}

/// `NAME.png`/`NAME.svg` in `dir`: as [`theta_figure`], the title prefixed
/// by `what`.
fn theta_figure_named(
    dir: &std::path::Path,
    name: &str,
    what: &str,
    bs: &BitScenario,
    run: u64,
    traj: &tippetop::Trajectory,
) -> Result<()> {
    use crate::plot::{self, Legend, PlotOpts, RefLine, Series};
    let t_end = 2.0 * bs.bit.phase;
    let (scale, unit) = crate::common::time_unit(t_end);
    let t: Vec<f64> = traj.samples.iter().map(|x| x.t * scale).collect();
    let th: Vec<f64> = traj.samples.iter().map(|x| x.theta).collect();
    let b = &bs.bit;
    plot::line_plot(
        &dir.join(name),
        &format!(
            "{what}θ(t) of run {run}: write to {} {unit}, then erase",
            human(b.phase * scale)
        ),
        &format!("t [{unit}]"),
        "θ [rad]",
        &[Series::new("θ", t, th)],
        &PlotOpts {
            hlines: vec![
                RefLine::new(b.zero[0], "zero"),
                RefLine::new(b.zero[1], "zero"),
                RefLine::new(b.one[0], "one"),
                RefLine::new(b.one[1], "one"),
            ],
            x_range: Some((0.0, t_end * scale)),
            y_range: Some((0.0, std::f64::consts::PI)),
            legend: Legend::None,
            // The phase boundary, and each phase's hold window (its last
            // `hold` seconds, where success is judged) shaded.
            vlines: vec![plot::VLine::new(b.phase * scale, "erase starts")],
            spans: vec![
                plot::Span {
                    x0: (b.phase - b.hold) * scale,
                    x1: b.phase * scale,
                    label: "write hold".into(),
                },
                plot::Span {
                    x0: (2.0 * b.phase - b.hold) * scale,
                    x1: 2.0 * b.phase * scale,
                    label: "erase hold".into(),
                },
            ],
            ..PlotOpts::default()
        },
    )
}

fn bit_md(
    bs: &BitScenario,
    r: &Report,
    check: &StepOutcome,
    typical: Option<&RunResult>,
) -> String {
    let b = &bs.bit;
    let mut s = String::from("# Memory bit\n\n");
    let _ = writeln!(
        s,
        "States: zero = θ in [{}, {}] rad, one = θ in [{}, {}] rad. Each phase lasts {} s; a \
         phase succeeds iff θ stays in its target window during its last {} s, on the \
         continuous solution (events at the window's edges; steps at most the row spacing, {} \
         s). The switching time is the crossing into the window.\n",
        human(b.zero[0]),
        human(b.zero[1]),
        human(b.one[0]),
        human(b.one[1]),
        human(b.phase),
        human(b.hold),
        human(2.0 * b.phase / (bs.scenario.solver.samples - 1) as f64),
    );
    if r.deterministic {
        let _ = writeln!(
            s,
            "One deterministic run (T = 0): probabilities are 0 or 1.\n"
        );
    } else {
        let _ = writeln!(
            s,
            "{} Langevin runs at T = {} K (seed {}, thermal.run {} to {}); intervals are \
             Wilson 95 %.\n",
            r.runs,
            human(bs.scenario.thermal.temperature),
            bs.scenario.thermal.seed.unwrap_or(0),
            bs.scenario.thermal.run,
            bs.scenario.thermal.run + r.runs as u64 - 1,
        );
    }
    for (name, what, blk) in [
        ("Write", "standing to lying (target one)", &r.write),
        (
            "Erase",
            "back to standing (target zero), all runs",
            &r.erase,
        ),
        (
            "Erase after a successful write",
            "runs whose write succeeded",
            &r.erase_given_write,
        ),
        ("Cycle", "write and erase both succeeded", &r.cycle),
    ] {
        let _ = writeln!(s, "## {name}: {what}\n");
        let _ = writeln!(s, "- {}", one_line(blk));
        // One run has a switching time, not quartiles.
        if blk.runs > 1 {
            let _ = writeln!(
                s,
                "- switching time quartiles: {}, {}, {}",
                opt_unit(blk.time_q25, "s"),
                opt_unit(blk.time_median, "s"),
                opt_unit(blk.time_q75, "s")
            );
        }
        let _ = writeln!(
            s,
            "- largest total applied force: {} N\n",
            human(blk.max_applied_force)
        );
    }
    step_md(&mut s, check);
    if let Some(t) = typical {
        let _ = writeln!(
            s,
            "![theta(t)](theta.png)\n\nθ(t) of run {} (a typical run: the first with the most \
             frequent outcome, write {}, erase {}); the horizontal lines are the edges of the \
             two states.\n",
            t.run,
            outcome(&t.write),
            outcome(&t.erase)
        );
    }
    // A minimum over the runs that completed: none if every run failed
    // (as bit.json's null says).
    match r.pull_off_margin_min {
        Some(m) => {
            let _ = writeln!(s, "Smallest pull-off margin over the runs: {} N.", human(m));
        }
        None if bs.scenario.adhesion().is_on() => {
            let _ = writeln!(
                s,
                "Smallest pull-off margin over the runs: none (no run completed)."
            );
        }
        None => {
            let _ = writeln!(s, "No adhesion: no pull-off margin.");
        }
    }
    s
}
