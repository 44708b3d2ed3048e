//! `tippetop ensemble` (and `tippetop merge` of its shards): a Langevin
//! scenario run N times with independent noise, on all cores, cut into
//! shards that merge back byte for byte. The library part is
//! [`tippetop::analysis::ensemble`]; the streaming, the shards, `--resume`
//! and the output directory work as for `tippetop sweep`
//! ([`crate::sweep_cmd`]).

use std::io::BufRead;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::{ArgGroup, Args};
use serde::{Deserialize, Serialize};
use tippetop::analysis::ensemble::step_check::{self as ens_step, Outcome, Plan, Refined};
use tippetop::analysis::ensemble::{
    self, BINS, Ensemble, EnsembleShard, EnsembleStats, Histograms, QUANTILES, SPREAD, StatsAcc,
};
use tippetop::analysis::sweep::{self, Shard};

use crate::output::{OutDir, check_plain, open_plain, read_plain, write_bytes_atomic};
use crate::partial::{FNV_OFFSET, PartialWriter, check_checksum, checksum, checksum_text, fnv1a};

/// Long help of `tippetop ensemble`.
pub const ENSEMBLE_LONG_ABOUT: &str =
    "Run a Langevin scenario N times with independent noise (run K is the scenario with
thermal.run = r0 + K, r0 its own thermal.run, default 0) on all cores and write into --out:
  ensemble.csv    one row per run, in run order:
                  run, seed        thermal.run and thermal.seed of the run: `tippetop run
                                   FILE --set thermal.run=RUN` replays it alone
                  status           ok, or the error of a run that failed part-way
                  <col>_final      every trajectory.csv column (see tippetop run --help) at
                                   the last output row, in its units (t_final, theta_final,
                                   ..., yp_final)
                  theta_max        largest theta over every step [rad]
                  theta_min, N_min smallest theta [rad] and normal force [N] over the output rows
                  negative_normal_fraction   fraction of the time with N < 0
                  first_passage_time         first time theta > pi/2 [s] (or the
                                   --first-passage criterion holds); empty if never
                  censored         1: no passage up to t_reached; 0: it passed
                  t_reached        time the run reached [s] (t_end unless it failed)
  histograms.csv  per sample time t and quantity (theta, omega, Omega): the range lower,
                  upper, then integer counts: underflow, bin0..bin63 (64 equal bins),
                  overflow, missing (runs that ended before t). Ranges: theta [0, pi];
                  omega [min(omega0, 0) - 6 sqrt(kT/C), max(omega0, 0) + 6 sqrt(kT/C)],
                  Omega likewise with the initial precession and sqrt(kT/A)
  quantiles.csv   per sample time and quantity: n (values counted), q05 q25 q50 q75 q95
                  from the histograms (linear within a bin; empty outside the range)
  summary.json    runs, ok and failed runs; mean, standard deviation and 95 % confidence
                  interval (mean +- 1.96 s/sqrt(n), over the ok runs) of the final theta,
                  omega, Omega and energy; first passages (theta > pi/2 or --first-passage):
                  observed, censored, censored fraction, Kaplan-Meier median, the escape
                  rate (passages / time at risk, 95 % CI); temperature; the histogram ranges;
                  dt_converged, step_check, step_unchecked: the step check (below)
  fan.png, fan.svg   theta(t): median and the 25-75 % and 5-95 % quantile bands
  shard.json      which runs the files hold, for tippetop merge

The scenario must be a Langevin or Brownian run at a temperature > 0 (solver.method =
\"langevin\" or \"brownian\",
solver.dt, surface.friction = 0, a [thermal] table with temperature, damping_translational,
damping_rotational and seed); anything else exits with code 2. --runs N: 1 <= N <= 1000000, the
run indices below 2^32; solver.samples at most 100000 (the histograms keep 1624 bytes per
sample). Runs run at once on --threads threads, fewer (with a note) if more would need more
than the memory bound of 3 GiB. The files are byte for byte the same whatever --threads and however the
runs are cut with --shard K/N (the K-th of N contiguous blocks of runs; join the shards'
directories with tippetop merge: counts add, rows concatenate; summary.json's step-check keys
aside, below). A run that fails part-way is a
row with its error in status; the ensemble goes on. Bad input exits with code 2 and writes
nothing.

Streaming and --resume as for tippetop sweep: rows are written in run order into
DIR/ensemble.csv.partial as the runs finish, memory stays flat in N (the histograms are
counts; summary.json's Kaplan-Meier estimate keeps 16 bytes per run); a killed ensemble
continues with the same command plus --resume and ends with the same bytes. The output
directory is locked while the command runs.

The step check (on by default; --no-step-check skips it): after the ensemble, the same N runs
again on the scenario at solver.dt/2 (the step limit doubled, an independent seed:
thermal.seed + 0x9E3779B97F4A7C15, wrapping), whose files are not written. Each statistic with
a 95 % interval is compared with its value at dt/2: the means of the final theta, omega, Omega
and energy and of the observed passage times (by their difference), the censored fraction (its
Wilson 95 % interval) and the escape rate (by the ratio, on a log scale). A statistic is
converged in the step when its change is below the change's own 95 % half-width (the two
answers' half-widths added in quadrature, widened by the Bonferroni factor of the number of
statistics checked together): the step's effect is not resolved at the ensemble's precision.
summary.json gains \"dt_converged\" (true: every checked statistic converged; false: one or
more did not, and the console warns \"NOT converged in the step\": use a smaller solver.dt) and
\"step_check\" (per statistic: both estimates with their intervals and steps, the change, the
half-width); the answer written stays the one at dt. The second pass has twice the steps: it
costs about twice the ensemble, so the command takes about three times as long. With no step
error, noise alone flags an ensemble about 5 % of the time (docs/physics.md#step-check); a step error shows again at a
smaller solver.dt, noise does not. No check (\"dt_converged\": null, \"step_check\": null and
\"step_unchecked\" saying why): with --no-step-check; with --shard (the check compares the
whole ensemble's statistics: run the ensemble without --shard, or at --set solver.dt=DT/2 and
compare), and so in tippetop merge's summary.json, which therefore differs from a one-shot
run's in these keys only; with --runs 1 (no interval). --resume resumes the ensemble; the
check's pass keeps no partial file and runs again whole (the same bytes). A scenario whose
dt/2 version is invalid (e.g. beyond the step limit) exits with code 2 naming the key.";

/// Run a Langevin scenario N times (an ensemble) and write statistics.
#[derive(Debug, Args)]
#[command(long_about = ENSEMBLE_LONG_ABOUT)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop ensemble scenarios/thermal.toml --runs 1000 --out out/ens\n  \
                  tippetop ensemble scenarios/thermal.toml --runs 100000 --shard 3/8 --out shards/3 --quiet\n  \
                  tippetop merge shards/* --out result\n  \
                  tippetop run scenarios/thermal.toml --set thermal.run=17 --out out/run17   (replay run 17)"
)]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML): a Langevin run at temperature > 0")),
    mut_arg("sets", |a| a.help("Override one scenario value for every run, e.g. `--set thermal.temperature=77`; repeatable, applied in order after the file")),
)]
pub struct EnsembleArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,

    /// Number of runs N (1 to 1000000; run K uses thermal.run = r0 + K).
    #[arg(long, value_name = "N")]
    pub runs: usize,

    /// Output directory (created if missing; locked while the ensemble
    /// runs; the previous command's files in it are replaced or removed).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// `--threads`.
    #[command(flatten)]
    pub cores: crate::common::args::ThreadsArg,

    /// Run only the K-th of N contiguous blocks of runs (1 <= K <= N);
    /// join the outputs with `tippetop merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,

    /// Continue an interrupted run of the same ensemble (same scenario,
    /// --set, --runs, --shard) from DIR/ensemble.csv.partial; without one,
    /// start from the first run.
    #[arg(long)]
    pub resume: bool,

    /// First-passage criterion over trajectory.csv columns (SI units):
    /// `COLUMN>VALUE` or `COLUMN<VALUE`, several joined by ',' (any of
    /// them), e.g. `theta<1.07,theta>2.07` (leaving a lying well). Each run
    /// stops at its first output row where it holds (resolution: the
    /// sample spacing); first_passage_time and censored refer to it, and
    /// summary.json gains the escape rate (passages / time at risk, for
    /// `tippetop retention`). Default: theta > pi/2, runs to t_end.
    #[arg(long, value_name = "SPEC")]
    pub first_passage: Option<String>,

    /// Skip the step check (the N runs again at solver.dt/2, about twice
    /// the ensemble's cost): summary.json's dt_converged and step_check are
    /// then null and the console says the step is unchecked.
    #[arg(long)]
    pub no_step_check: bool,
}

/// The file the rows stream into while the ensemble runs.
pub const PARTIAL_CSV: &str = "ensemble.csv.partial";
/// The running ensemble's `shard.json`.
pub const PARTIAL_INFO: &str = "shard.json.partial";
/// The histograms of the rows flushed so far (a checkpoint for `--resume`,
/// written at each checkpoint of the CSV, which records its hash).
pub const PARTIAL_HIST: &str = "histograms.json.partial";

/// The checkpoint of the histograms: the counts of the first `rows` runs
/// of the shard.
#[derive(Debug, Serialize, Deserialize)]
struct Checkpoint {
    fingerprint: String,
    first_index: usize,
    rows: usize,
    hist: Histograms,
}

/// [`Checkpoint`] as written: the same JSON, from borrowed histograms.
#[derive(Serialize)]
struct CheckpointRef<'a> {
    fingerprint: &'a str,
    first_index: usize,
    rows: usize,
    hist: &'a Histograms,
}

use crate::scenario_load::input_error;

/// Run `tippetop ensemble`. Bad input: one line on stderr and exit code 2
/// (returned as `Ok`), nothing written; `Err` for I/O failures.
pub fn ensemble(args: &EnsembleArgs, quiet: bool) -> Result<ExitCode> {
    let (ens, shard, threads, info, info_json, plan) = match inputs(args, quiet)? {
        Ok(i) => i,
        Err(code) => return Ok(code),
    };

    let mut out = OutDir::open(&args.out)?;
    let dir = args.out.clone();
    let csv_partial = dir.join(PARTIAL_CSV);
    let info_partial = dir.join(PARTIAL_INFO);
    let hist_partial = dir.join(PARTIAL_HIST);
    let sum = crate::partial::sum_name(PARTIAL_CSV);
    let range = info.first_index..info.end_index;

    let (kept, checkpoint) = match kept_rows(args, quiet, &ens, &info, &info_json)? {
        Ok(k) => k,
        Err(code) => {
            out.abandon();
            return Ok(code);
        }
    };

    out.claim(&[PARTIAL_CSV, PARTIAL_INFO, PARTIAL_HIST, sum.as_str()])?;
    write_bytes_atomic(&info_partial, info_json.as_bytes())?;
    let pb = crate::progress::bar(quiet, range.len() as u64, "ensemble");
    // The histograms of the kept rows: the checkpoint's, and the rows it
    // does not cover run again (their counts only; the rows stay as kept).
    let (mut hist, covered) = match checkpoint {
        Some(c) => (c.hist, c.rows),
        None => (ens.histograms(), 0),
    };
    if kept.rows > covered {
        let again = range.start + covered..range.start + kept.rows;
        let run = ens.run_streaming(again, Some(threads), &mut |row| {
            hist.add(&row);
            true
        });
        if let Err(e) = run {
            anyhow::bail!("{e}");
        }
    }

    let mut w = PartialWriter::open(
        &dir,
        PARTIAL_CSV,
        &ensemble::csv_header(),
        &info.fingerprint,
        &kept,
    )?;
    if !quiet && kept.rows > 0 {
        eprintln!(
            "resuming: {} of {} runs kept from {} (verified against its checkpoints)",
            kept.rows,
            range.len(),
            csv_partial.display()
        );
    }
    pb.inc(kept.rows as u64);
    let start = std::time::Instant::now();
    let mut write_error: Option<anyhow::Error> = None;
    let todo = range.start + kept.rows..range.end;
    let run = ens.run_streaming(todo, Some(threads), &mut |row| {
        hist.add(&row);
        w.push(&ensemble::csv_row(&row));
        // About once a second: the rows on disk, then the histograms of
        // exactly those rows (what --resume starts from).
        let result = if w.due() {
            save_checkpoint(&mut w, &hist_partial, &info, &hist)
        } else {
            Ok(())
        };
        pb.inc(1);
        match result {
            Ok(()) => true,
            Err(e) => {
                write_error = Some(e);
                false
            }
        }
    });
    pb.finish_and_clear();
    if let Err(e) = run {
        anyhow::bail!("{e}");
    }
    if let Some(e) = write_error {
        return Err(e);
    }
    save_checkpoint(&mut w, &hist_partial, &info, &hist)?;
    let hash = w.finish()?;

    let stats = read_stats(&csv_partial)?;
    // The step check runs after the ensemble's rows are all on disk: a
    // kill during it leaves a complete partial file, and --resume goes
    // straight to the check again.
    let begun = std::time::Instant::now();
    let step = match &plan {
        Plan::Off(why) => Outcome::Off(why.clone()),
        Plan::Run(fine) => {
            let fine_stats = refined_stats(fine, threads, quiet)?;
            Outcome::Done(Refined::new(&ens, &stats, fine, &fine_stats))
        }
    };
    let check_seconds = begun.elapsed().as_secs_f64();
    out.adopt(PARTIAL_CSV, "ensemble.csv");
    write_results(out.stage(), &info, &hist, &stats, &step)?;
    write_info(out.stage(), &info, checksum_text(hash), &hist)?;
    out.commit(&["summary.json"])?;
    if !quiet {
        let what = if shard == Shard::ALL {
            format!("{} runs", range.len())
        } else {
            format!(
                "shard {}/{}: runs {}..{} of {}",
                shard.k, shard.n, range.start, range.end, info.total_runs
            )
        };
        println!(
            "{what} ({} ok, {} failed) in {} -> {}",
            stats.ok,
            stats.failed,
            crate::output::fmt_duration(start.elapsed().as_secs_f64() - check_seconds),
            dir.join("ensemble.csv").display()
        );
        print_stats(&stats);
        print_step(&step, check_seconds);
    }
    Ok(ExitCode::SUCCESS)
}

/// The step check's plan: off with `--no-step-check`, else
/// [`ens_step::plan`]. Error: the refined scenario is invalid (the key
/// named, the check said).
fn step_plan(no_check: bool, ens: &Ensemble, shard: Shard) -> Result<Plan, tippetop::Error> {
    if no_check {
        return Ok(Plan::Off("--no-step-check".into()));
    }
    ens_step::plan(ens, shard, "--no-step-check")
}

/// The statistics of the refined ensemble `fine`, all its runs on
/// `threads` threads (a progress bar "step check (dt/2)"; nothing is
/// written).
fn refined_stats(fine: &Ensemble, threads: usize, quiet: bool) -> Result<EnsembleStats> {
    let pb = crate::progress::bar(quiet, fine.runs as u64, "step check (dt/2)");
    let stats = ens_step::refined_stats(fine, Some(threads), &mut || {
        pb.inc(1);
        true
    });
    pb.finish_and_clear();
    match stats {
        Ok(Some(s)) => Ok(s),
        Ok(None) => anyhow::bail!("step check: stopped before its end"),
        Err(e) => anyhow::bail!("step check: {e}"),
    }
}

/// The step check for people: the refined ensemble's runs, a line per
/// statistic, then whether the ensemble is converged in the step (a
/// warning on stderr if not).
fn print_step(step: &Outcome, seconds: f64) {
    let (Outcome::Done(r), Some(converged)) = (step, step.converged()) else {
        if let Some(why) = step.unchecked() {
            println!("step unchecked ({why})");
        }
        return;
    };
    let g = |x: f64| tippetop::human::sig(x, 4);
    let (dt, dt2) = (r.checks[0].2.at_dt.dt, r.checks[0].2.at_half_dt.dt);
    println!(
        "step check: the {} runs again at dt/2 = {} s (independent noise; {} failed) in {}",
        r.runs,
        g(dt2),
        r.failed,
        crate::output::fmt_duration(seconds)
    );
    for (name, unit, c) in &r.checks {
        let fmt = |x: f64| {
            if unit.is_empty() {
                g(x)
            } else {
                format!("{} {unit}", g(x))
            }
        };
        let words = c.words(&fmt);
        let words = words.strip_prefix("step check: ").unwrap_or(&words);
        println!("step check {name}: {words}");
    }
    if converged {
        println!(
            "step check: converged in the step: each of the {} statistics changed by less than the \
             95 % half-width of its change from dt = {} s to dt/2 = {} s (dt_converged: true)",
            r.checks.len(),
            g(dt),
            g(dt2)
        );
    } else {
        let off: Vec<&str> = r
            .checks
            .iter()
            .filter(|c| !c.2.converged)
            .map(|c| c.0)
            .collect();
        eprintln!(
            "warning: NOT converged in the step: {} of {} statistics ({}) changed by more than \
             the 95 % half-width of the change from dt = {} s to dt/2 = {} s: a step error in \
             the answer at dt, or noise (an ensemble without step error is flagged about 5 % of \
             the time); a smaller solver.dt tells them apart (dt_converged: false)",
            off.len(),
            r.checks.len(),
            off.join(", "),
            g(dt),
            g(dt2)
        );
    }
}

/// The ensemble, its shard, the threads, the shard's description (and
/// its JSON) and the step check's plan from the arguments. Bad input: one
/// line on stderr, `Ok(Err(exit code 2))`.
#[allow(clippy::type_complexity)]
fn inputs(
    args: &EnsembleArgs,
    quiet: bool,
) -> Result<std::result::Result<(Ensemble, Shard, usize, EnsembleShard, String, Plan), ExitCode>> {
    let toml_text = match crate::scenario_load::read_text(args.source.scenario.as_deref()) {
        Ok(t) => t,
        Err(code) => return Ok(Err(code)),
    };
    let shard = match args.shard.as_deref().map(Shard::parse).transpose() {
        Ok(s) => s.unwrap_or(Shard::ALL),
        Err(e) => return Ok(Err(input_error(e))),
    };
    let threads = match sweep::threads(args.cores.threads) {
        Ok(t) => t,
        Err(e) => return Ok(Err(input_error(e))),
    };
    let exit = match args
        .first_passage
        .as_deref()
        .map(ensemble::Exit::parse)
        .transpose()
    {
        Ok(e) => e,
        Err(e) => return Ok(Err(input_error(e))),
    };
    let ens = match Ensemble::new(
        args.source.preset.clone(),
        toml_text,
        args.source.sets.clone(),
        args.runs,
    ) {
        Ok(e) => e.with_exit(exit),
        Err(e) => return Ok(Err(input_error(e))),
    };
    let threads = match ens.threads_within_memory(threads) {
        Ok(t) => crate::scenario_load::note_threads(quiet, threads, t),
        Err(e) => return Ok(Err(input_error(e))),
    };
    let info = match ens.shard_info(shard) {
        Ok(i) => i,
        Err(e) => return Ok(Err(input_error(e))),
    };
    let plan = match step_plan(args.no_step_check, &ens, shard) {
        Ok(p) => p,
        Err(e) => return Ok(Err(input_error(e))),
    };
    let mut info_json = serde_json::to_string_pretty(&info)?;
    info_json.push('\n');
    Ok(Ok((ens, shard, threads, info, info_json, plan)))
}

/// What an interrupted run of this ensemble left in `--out` that
/// `--resume` keeps: the verified rows, and the histogram checkpoint if
/// one matches them. Bad input (partial files that are links, another
/// ensemble's, damaged): one line on stderr, `Ok(Err(exit code 2))` (the
/// caller abandons `--out`).
#[allow(clippy::type_complexity)]
fn kept_rows(
    args: &EnsembleArgs,
    quiet: bool,
    ens: &Ensemble,
    info: &EnsembleShard,
    info_json: &str,
) -> Result<std::result::Result<(crate::partial::Kept, Option<Checkpoint>), ExitCode>> {
    let dir = args.out.clone();
    let csv_partial = dir.join(PARTIAL_CSV);
    let hist_partial = dir.join(PARTIAL_HIST);
    let sum = crate::partial::sum_name(PARTIAL_CSV);
    let range = info.first_index..info.end_index;

    // Never through a link (planted, it would make the command overwrite
    // its target).
    for name in [PARTIAL_CSV, PARTIAL_INFO, PARTIAL_HIST, sum.as_str()] {
        if let Err(e) = check_plain(&dir.join(name)) {
            return Ok(Err(input_error(e)));
        }
    }
    if !args.resume {
        return Ok(Ok((crate::partial::Kept::default(), None)));
    }
    let resume = crate::common::grid::Resume {
        dir: &dir,
        partial_csv: PARTIAL_CSV,
        partial_info: PARTIAL_INFO,
        what: "ensemble",
        unit: "run",
        keys: "--set, --runs and --shard",
        quiet,
        range_len: range.len(),
        fingerprint: &info.fingerprint,
    };
    let described = |o: &EnsembleShard| {
        format!(
            "fingerprint {}, runs {}..{} of {}",
            o.fingerprint, o.first_index, o.end_index, o.total_runs
        )
    };
    let kept = match crate::common::grid::resume_kept(
        &resume,
        info_json,
        info,
        &|o: &mut EnsembleShard| o.checksums.clear(),
        &described,
        &|text| ens.complete_prefix(info.first_index, text),
    )? {
        Ok(k) => k,
        Err(code) => return Ok(Err(code)),
    };
    // The histogram checkpoint, trusted only if a verified
    // checkpoint of the CSV records its hash (it then holds the
    // counts of that checkpoint's rows).
    let mut checkpoint: Option<Checkpoint> = None;
    if kept.rows > 0 && hist_partial.exists() {
        let bytes = read_plain(&hist_partial)?;
        let h = fnv1a(FNV_OFFSET, &bytes);
        checkpoint = kept
            .checkpoints
            .iter()
            .rev()
            .find(|c| c.extra == Some(h))
            .and_then(|at| {
                serde_json::from_slice::<Checkpoint>(&bytes)
                    .ok()
                    .filter(|c| c.rows == at.rows)
            })
            .filter(|c| {
                c.fingerprint == info.fingerprint
                    && c.first_index == info.first_index
                    && c.rows <= kept.rows
                    && c.hist.bins == BINS
                    && c.hist.ranges == ens.ranges()
                    && c.hist.times.len() == ens.scenario.solver.samples
            });
        if checkpoint.is_none() && !quiet {
            eprintln!(
                "note: {} does not match a checkpoint of {}: the kept runs run again \
                 for their histogram counts",
                hist_partial.display(),
                csv_partial.display()
            );
        }
    }
    Ok(Ok((kept, checkpoint)))
}

/// The statistics of the ensemble, from its CSV as written (kept rows
/// included), line by line.
fn read_stats(csv_partial: &Path) -> Result<EnsembleStats> {
    let mut acc = StatsAcc::default();
    let f = open_plain(csv_partial, std::fs::OpenOptions::new().read(true))?;
    for (j, line) in std::io::BufReader::new(f).lines().enumerate().skip(1) {
        let line = line.with_context(|| format!("reading {}", csv_partial.display()))?;
        acc.push_line(j + 1, &line).map_err(anyhow::Error::new)?;
    }
    Ok(acc.finish())
}

/// The ensemble's statistics for people: 4 significant figures with units
/// (summary.json has them at full precision).
fn print_stats(stats: &EnsembleStats) {
    let g = |x: f64| tippetop::human::sig(x, 4);
    let show = |name: &str, m: &ensemble::MeanCi, unit: &str| match (m.mean, m.ci95) {
        (Some(mean), Some([lo, hi])) => {
            println!(
                "{name:<14} {} {unit} (95 % CI {} .. {}, n = {})",
                g(mean),
                g(lo),
                g(hi),
                m.n
            )
        }
        (Some(mean), None) => println!("{name:<14} {} {unit} (n = {})", g(mean), m.n),
        _ => {}
    };
    show("theta_final", &stats.theta_final, "rad");
    show("omega_final", &stats.omega_final, "rad/s");
    show("Omega_final", &stats.precession_final, "rad/s");
    show("energy_final", &stats.energy_final, "J");
    let fp = &stats.first_passage;
    if let Some(r) = &fp.escape_rate {
        println!(
            "passage rate   {} 1/s (95 % CI {} .. {}; {} passages in {} s at risk; an escape rate if passages are Poisson)",
            g(r.rate),
            g(r.ci95[0]),
            g(r.ci95[1]),
            r.passages,
            g(r.exposure)
        );
    }
    println!(
        "first passage  {} passed, {} censored; Kaplan-Meier median {}",
        fp.observed,
        fp.censored,
        fp.kaplan_meier_median
            .map_or("not reached (over half censored)".to_string(), |t| {
                format!("{} s", g(t))
            })
    );
}

/// Write `histograms.csv`, `quantiles.csv`, `summary.json` (with the step
/// check's keys) and the fan chart into `dir`.
fn write_results(
    dir: &Path,
    info: &EnsembleShard,
    hist: &Histograms,
    stats: &EnsembleStats,
    step: &Outcome,
) -> Result<()> {
    write_bytes_atomic(&dir.join("histograms.csv"), hist.csv().as_bytes())?;
    write_bytes_atomic(&dir.join("quantiles.csv"), hist.quantiles_csv().as_bytes())?;
    let names = ensemble::QUANTITIES;
    let ranges: serde_json::Map<String, serde_json::Value> = names
        .iter()
        .zip(hist.ranges)
        .map(|(n, r)| (n.to_string(), serde_json::json!(r)))
        .collect();
    let mut summary = serde_json::to_value(stats)?;
    if let serde_json::Value::Object(m) = &mut summary {
        m.insert("fingerprint".into(), info.fingerprint.clone().into());
        m.insert("first_run".into(), info.first_run.into());
        m.insert(
            "first_passage_criterion".into(),
            info.exit
                .clone()
                .unwrap_or_else(|| "theta>pi/2 (the run's event; runs go to t_end)".into())
                .into(),
        );
        if let Some(t) = info.temperature {
            m.insert("temperature".into(), t.into());
        }
        m.insert("seed".into(), info.seed.into());
        m.insert(
            "shard".into(),
            serde_json::json!({
                "k": info.k, "n": info.n, "total_runs": info.total_runs,
                "first_index": info.first_index, "end_index": info.end_index,
            }),
        );
        m.insert(
            "histograms".into(),
            serde_json::json!({
                "bins": hist.bins,
                "spread_thermal_widths": SPREAD,
                "ranges": ranges,
                "quantiles": QUANTILES,
            }),
        );
        if let serde_json::Value::Object(fields) = serde_json::to_value(step.fields())? {
            m.extend(fields);
        }
    }
    let mut json = serde_json::to_string_pretty(&summary)?;
    json.push('\n');
    write_bytes_atomic(&dir.join("summary.json"), json.as_bytes())?;
    write_fan(dir, hist, stats.runs, info.temperature)
}

/// The fan chart of θ(t): the median over shaded 25–75 % and 5–95 %
/// bands, from the histograms; the title names the run count and the
/// temperature \[K\].
fn write_fan(dir: &Path, hist: &Histograms, runs: u64, temperature: Option<f64>) -> Result<()> {
    use crate::plot::{PlotOpts, RefLine, Series, line_plot};
    let idx: Vec<usize> = (0..hist.times.len())
        .filter(|&i| hist.times[i].is_some())
        .collect();
    if idx.len() < 2 {
        return Ok(());
    }
    let t_end = idx
        .iter()
        .filter_map(|&i| hist.times[i])
        .fold(0.0, f64::max);
    let (scale, unit) = crate::common::time_unit(t_end);
    let xs: Vec<f64> = idx
        .iter()
        .map(|&i| hist.times[i].unwrap_or(f64::NAN) * scale)
        .collect();
    let q = |p: f64| -> Vec<f64> {
        idx.iter()
            .map(|&i| hist.quantile(i, 0, p).unwrap_or(f64::NAN))
            .collect()
    };
    // Bands only (their line is NaN, so not drawn), then the median.
    let gap = vec![f64::NAN; xs.len()];
    let mut outer =
        Series::new("5–95 % of the runs", xs.clone(), gap.clone()).color((110, 150, 210));
    outer.band = Some((q(0.05), q(0.95)));
    let mut inner = Series::new("25–75 %", xs.clone(), gap).color((40, 90, 170));
    inner.band = Some((q(0.25), q(0.75)));
    let series = vec![
        outer,
        inner,
        Series::new("median", xs.clone(), q(0.5))
            .color((200, 30, 30))
            .width(3),
    ];
    let at = temperature.map_or(String::new(), |t| {
        format!(" at {} K", tippetop::human::sig(t, 3))
    });
    line_plot(
        &dir.join("fan"),
        &format!("θ(t) of {runs} runs{at}: median and quantile bands"),
        &format!("t [{unit}]"),
        "θ [rad]",
        &series,
        &PlotOpts {
            hlines: vec![
                RefLine::new(std::f64::consts::FRAC_PI_2, "π/2"),
                RefLine::new(std::f64::consts::PI, "π"),
            ],
            y_range: Some((0.0, std::f64::consts::PI * 1.05)),
            ..Default::default()
        },
    )
}

/// Whether `dir` holds an ensemble's output (rather than a sweep's), for
/// `tippetop merge`.
pub fn is_ensemble_dir(dir: &Path) -> bool {
    tippetop::limits::read_file(&dir.join("shard.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok())
        .is_some_and(|v| v["kind"] == "ensemble")
}

/// `tippetop merge` of an ensemble's shards: `ensemble.csv` concatenated,
/// `histograms.csv` added, the rest recomputed from them: byte for byte the
/// files of a one-shot run (the plots aside). Bad input: one line, exit
/// code 2, nothing written.
pub fn merge(args: &crate::common::args::MergeArgs, quiet: bool) -> Result<ExitCode> {
    let mut shards: Vec<(EnsembleShard, String)> = Vec::new();
    let mut hists: Vec<(usize, Histograms)> = Vec::new();
    for dir in &args.dirs {
        let _reading = crate::output::read_lock(dir)?;
        match read_shard(dir) {
            Ok((info, csv, h)) => {
                hists.push((info.first_index, h));
                shards.push((info, csv));
            }
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    let csv = match ensemble::merge_csv(&shards) {
        Ok(c) => c,
        Err(e) => return Ok(input_error(e)),
    };
    hists.sort_by_key(|(i, _)| *i);
    let mut hist = hists[0].1.clone();
    for (_, h) in &hists[1..] {
        if let Err(e) = hist.merge(h) {
            return Ok(input_error(e));
        }
    }
    let stats = match EnsembleStats::from_csv(&csv) {
        Ok(s) => s,
        Err(e) => return Ok(input_error(e)),
    };
    let first = &shards[0].0;
    let info = EnsembleShard {
        k: 1,
        n: 1,
        first_index: 0,
        end_index: first.total_runs,
        checksums: Default::default(),
        ..first.clone()
    };
    let step = Outcome::Off(
        "a merge of shards: the check compares the whole ensemble's statistics; run the \
         ensemble without --shard, or at --set solver.dt=DT/2 and compare"
            .into(),
    );
    let out = OutDir::open(&args.out)?;
    write_bytes_atomic(&out.stage().join("ensemble.csv"), csv.as_bytes())?;
    write_info(out.stage(), &info, checksum(csv.as_bytes()), &hist)?;
    write_results(out.stage(), &info, &hist, &stats, &step)?;
    out.commit(&["summary.json"])?;
    if !quiet {
        println!(
            "merged {} shards: {} runs ({} ok, {} failed) -> {}",
            shards.len(),
            stats.runs,
            stats.ok,
            stats.failed,
            args.out.join("ensemble.csv").display()
        );
        print_stats(&stats);
        print_step(&step, 0.0);
    }
    Ok(ExitCode::SUCCESS)
}

/// A shard directory's `shard.json`, `ensemble.csv` and `histograms.csv`;
/// `Err` is the one-line message for bad input.
fn read_shard(dir: &Path) -> std::result::Result<(EnsembleShard, String, Histograms), String> {
    let what = "a directory written by tippetop ensemble, with shard.json, ensemble.csv and \
                histograms.csv";
    let read = |name: &str| {
        let path = dir.join(name);
        std::fs::read_to_string(&path)
            .map_err(|e| format!("{}: cannot read it: {e} ({what})", path.display()))
    };
    let json = crate::scenario_load::read_small(&dir.join("shard.json"), what)?;
    let info: EnsembleShard = serde_json::from_str(&json).map_err(|e| {
        format!(
            "{}: not an ensemble's shard description: {e} ({what})",
            dir.join("shard.json").display()
        )
    })?;
    let (csv, hist_csv) = (read("ensemble.csv")?, read("histograms.csv")?);
    check_checksum(&info.checksums, dir, "ensemble.csv", csv.as_bytes())?;
    check_checksum(&info.checksums, dir, "histograms.csv", hist_csv.as_bytes())?;
    let hist = Histograms::parse_csv(&hist_csv).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok((info, csv, hist))
}

/// Write `shard.json` into `dir`: `info` with the checksums of
/// `ensemble.csv` (`csv`, its [`checksum_text`]) and `histograms.csv` (of
/// `hist`).
fn write_info(dir: &Path, info: &EnsembleShard, csv: String, hist: &Histograms) -> Result<()> {
    let mut info = info.clone();
    info.checksums = [
        ("ensemble.csv".to_string(), csv),
        (
            "histograms.csv".to_string(),
            checksum(hist.csv().as_bytes()),
        ),
    ]
    .into();
    let mut json = serde_json::to_string_pretty(&info)?;
    json.push('\n');
    write_bytes_atomic(&dir.join("shard.json"), json.as_bytes())
}

/// A checkpoint of a running ensemble: the rows waiting in `w` written,
/// then the histograms of all rows so far written to `hist_partial`, their
/// hash recorded with the rows' checkpoint (written first: a kill between
/// the two leaves the previous histogram file, matching the previous
/// checkpoint).
fn save_checkpoint(
    w: &mut PartialWriter,
    hist_partial: &Path,
    info: &EnsembleShard,
    hist: &Histograms,
) -> Result<()> {
    // Streamed from the histograms themselves, twice (once to hash, once
    // to the file): no copy of them and no JSON text in memory (an
    // ensemble's histograms reach 1624 bytes per sample).
    let c = CheckpointRef {
        fingerprint: &info.fingerprint,
        first_index: info.first_index,
        rows: w.rows(),
        hist,
    };
    let mut hasher = HashSink(FNV_OFFSET);
    serde_json::to_writer(&mut hasher, &c)?;
    w.checkpoint(Some(hasher.0))?;
    crate::output::write_atomic(hist_partial, |f| {
        serde_json::to_writer(f, &c).map_err(std::io::Error::other)
    })
}

/// A writer that only hashes what it is given (FNV-1a 64, as `fnv1a`).
struct HashSink(u64);

impl std::io::Write for HashSink {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        self.0 = fnv1a(self.0, buf);
        Ok(buf.len())
    }
    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}
