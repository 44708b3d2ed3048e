//! `tippetop sweep` and `tippetop merge`: parameter sweeps on all cores, cut
//! into shards that run anywhere (e.g. a Slurm array job, see
//! `docs/cluster.md`) and merge back into the very bytes of a one-shot run.
//!
//! Output directory of both commands:
//! - `sweep.csv`: one row per case in grid order (the first `--vary` slowest);
//!   columns: the varied keys, then `theta_final, theta_max, omega_final,
//!   Omega_final, first_time_theta_above_half_pi, contact_lost_at,
//!   negative_normal_fraction, rolling_fraction, J_max_rel_drift,
//!   energy_final, steps, rhs_evaluations, status` (see
//!   [`tippetop::analysis::sweep`]);
//! - `shard.json`: which cases the CSV holds and of which sweep (a one-shot
//!   run and a merge write `k = n = 1`), so `merge` can check a set of shards;
//! - `sweep.png`/`sweep.svg`: plots of a whole sweep of 1 or 2 axes and at
//!   most [`MAX_PLOT_CASES`] cases.
//!
//! A sweep streams its rows into `sweep.csv.partial` (beside
//! `shard.json.partial` and the checkpoints `sweep.csv.partial.sum`,
//! [`crate::partial`]) as the cases finish, in grid order, renames it at
//! the end and writes `shard.json` with its checksum; `--resume` continues
//! an interrupted sweep from the verified rows. The directory is locked and
//! updated as a unit ([`crate::output::OutDir`]).
//!
//! Exit codes: 0 done (cases that failed are reported in `status`, they do
//! not fail the sweep); 2 bad input (one line `error: KEY: WHAT (RANGE)` on
//! stderr, nothing written under `--out`); errors returned as `Err` (I/O,
//! an `--out` in use by another process) are for the caller to report
//! (exit 1).

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};

use crate::common::args::MergeArgs;
use crate::common::grid::{
    GridInput, PARTIAL_INFO, Streamed, read_shard_of, stream_rows, write_info,
};
use crate::output::{OutDir, read_plain, write_bytes_atomic};
use crate::partial::checksum_text;
use clap::{ArgGroup, Args};
use tippetop::analysis::sweep::{self, Shard, ShardInfo, Sweep, Table};

/// Long help of `tippetop sweep`.
pub const SWEEP_LONG_ABOUT: &str = "Run a grid of scenarios on all cores and write into --out:
  sweep.csv    one row per case: the varied keys, then theta_final, theta_max,
               omega_final, Omega_final, first_time_theta_above_half_pi,
               contact_lost_at, negative_normal_fraction, rolling_fraction,
               J_max_rel_drift, energy_final, steps, rhs_evaluations, status
  shard.json   what the CSV covers, for tippetop merge
  sweep.png, sweep.svg   plots, for a whole sweep (no --shard) of 1 or 2 --vary and at
               most 100 000 cases: with 1 --vary, theta final and max, omega final and
               the first time theta > pi/2 against the varied key; with 2, a heat map of
               theta final over the two keys (grey: failed case). No plots for 3 or more
               --vary, for a shard (tippetop merge draws them for the whole sweep), or
               above 100 000 cases (a note says so; sweep.csv has every row).

Each --vary KEY=FROM:TO:N takes N values FROM + (TO - FROM) i/(N - 1), i = 0..N-1
(KEY=FROM:TO:N:log: geometric spacing, FROM, TO > 0). The cases form a grid, rows in grid
order with the first --vary varying slowest. Each case is the scenario (preset, then file,
then each --set) with KEY=VALUE set for every --vary. A case whose scenario is invalid or
whose run fails gets the error in its status column (\"ok\" otherwise) and the sweep goes
on. The CSV is byte for byte the same whatever --threads and however the sweep is cut with
--shard.

--shard K/N runs only the K-th of N contiguous blocks of cases (sizes differ by at most
one; N at most the number of cases); join the shards' directories with tippetop merge.
Bad input exits with code 2 and writes nothing.

--threads T: 1 to 1024 (default: one per core, or RAYON_NUM_THREADS); the cases are
CPU-bound, so more threads than cores only add overhead.

Streaming and --resume: the rows are written in grid order as the cases finish, into
DIR/sweep.csv.partial (beside DIR/shard.json.partial, which identifies the sweep, and
DIR/sweep.csv.partial.sum, its checkpoints: the hash of the rows on disk, about once a
second); memory stays flat however many cases (at most 8 T + 16 finished rows wait for a
slower case before them). At the end sweep.csv.partial is renamed to sweep.csv, and
shard.json records its checksum (tippetop merge checks it). If the sweep is interrupted, run
the same command with --resume: it keeps the rows of sweep.csv.partial up to its last
checkpoint (later rows run again, with a note), runs the remaining cases, and ends with the
same sweep.csv as an uninterrupted run. A partial file that was edited or damaged (rows that
do not match their checkpoint, or are not rows of this sweep) or that is a symbolic link
exits with code 2 (one line naming the file and its line) and is left alone; so are another
sweep's partial files (other scenario, --set, --vary or --shard). With nothing to resume it
starts from the first case. Without --resume a sweep always starts over.

The output directory: created, checked and locked before the first case (an unwritable
--out fails at once with code 1). While the sweep runs, any other tippetop command writing
into the same directory exits at once with code 1 (\"DIR is in use by another tippetop
process (pid N)\"); it does not wait (the lock, DIR/.tippetop.lock, uses flock(2), on
Unix; on a file system without locks the sweep goes on with a warning). At the end, the files of the previous command into DIR (listed in
DIR/.tippetop-manifest) that this one did not write are removed, e.g. an old heat map when
the new sweep has 3 --vary; files the tool did not write are never touched.

Speed: the default model (vector) is 1.3-3.6x faster than the paper's Euler-angle equations
(--set solver.model=reduced); fewer --set solver.samples (output rows per case, which also
cap the step size) make each case cheaper (docs/performance.md).";

/// Run a parameter sweep (a grid of scenarios) on all cores.
#[derive(Debug, Args)]
#[command(long_about = SWEEP_LONG_ABOUT)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop sweep --preset classical --vary top.offset=0.0005:0.005:10 --out out/offset\n  \
                  tippetop sweep scenarios/nano.toml --vary top.inertia_axial=1e-44:1e-42:5:log \\\n      \
                  --vary surface.gravity=0:100:3 --out out/nano-map\n  \
                  tippetop sweep --preset classical --set solver.t_end=20 \\\n      \
                  --vary top.offset=0.0005:0.01:40 --vary top.inertia_axial=6e-7:2.7e-6:40 \\\n      \
                  --shard 3/8 --threads 4 --out shards/3 --quiet\n  \
                  tippetop merge shards/* --out result"
)]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML); optional with --preset")),
    mut_arg("sets", |a| a.help("Override one scenario value for every case, e.g. `--set solver.t_end=2`; repeatable, applied in order after the file (a --vary of the same key wins)")),
)]
pub struct SweepArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,

    /// Vary one key (as in --set) over N values from FROM to TO, both
    /// included; `:log` for geometric spacing. Repeatable: the cases form a
    /// grid, the first --vary varying slowest.
    #[arg(long = "vary", value_name = "KEY=FROM:TO:N[:log]", required = true)]
    pub vary: Vec<String>,

    /// Output directory (created if missing; locked while the sweep runs;
    /// the previous command's files in it are replaced or removed).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// `--threads`.
    #[command(flatten)]
    pub cores: crate::common::args::ThreadsArg,

    /// Run only the K-th of N contiguous blocks of cases (1 <= K <= N);
    /// join the outputs with `tippetop merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,

    /// Continue an interrupted run of the same sweep (same scenario, --set,
    /// --vary, --shard) from the rows in DIR/sweep.csv.partial; without a
    /// partial sweep, start from the first case.
    #[arg(long)]
    pub resume: bool,
}

use crate::scenario_load::input_error;

/// Run `tippetop sweep`. Bad input: one line on stderr and exit code 2
/// (returned as `Ok`); `Err` for I/O failures.
pub fn sweep(args: &SweepArgs, quiet: bool) -> Result<ExitCode> {
    let GridInput {
        toml_text,
        axes,
        shard,
        threads,
    } = match GridInput::parse(
        args.source.scenario.as_deref(),
        &args.vary,
        args.shard.as_deref(),
        args.cores.threads,
    ) {
        Ok(g) => g,
        Err(code) => return Ok(code),
    };
    let sw = Sweep {
        preset: args.source.preset.clone(),
        toml_text,
        sets: args.source.sets.clone(),
        axes,
    };
    if let Err(e) = sw.validate() {
        return Ok(input_error(e));
    }
    let threads = match sw.threads_within_memory(threads) {
        Ok(t) => crate::scenario_load::note_threads(quiet, threads, t),
        Err(e) => return Ok(input_error(e)),
    };
    let info = match sw.shard_info(shard) {
        Ok(i) => i,
        Err(e) => return Ok(input_error(e)),
    };
    let mut info_json = serde_json::to_string_pretty(&info)?;
    info_json.push('\n');

    // Created, locked and checked before computing anything.
    let mut out = OutDir::open(&args.out)?;
    let dir = args.out.clone();
    let range = info.first_index..info.end_index;
    let csv_partial = dir.join(PARTIAL_CSV);
    let start = std::time::Instant::now();
    let spec = Streamed {
        partial_csv: PARTIAL_CSV,
        partial_info: PARTIAL_INFO,
        header: sweep::csv_header(&sw.axes),
        what: "sweep",
        unit: "case",
        resume: args.resume,
        quiet,
    };
    let done = match stream_rows(
        &mut out,
        &spec,
        &info,
        &info_json,
        &|text| sw.complete_prefix(info.first_index, text),
        &mut |todo, sink| {
            sw.run_streaming(todo, Some(threads), &mut |row| {
                sink(sweep::csv_row(&row), row.status != "ok")
            })
        },
    )? {
        Ok(d) => d,
        Err(code) => {
            out.abandon();
            return Ok(code);
        }
    };
    let failed = done.failed;

    out.adopt(PARTIAL_CSV, "sweep.csv");
    write_info(
        out.stage(),
        &info,
        &[("sweep.csv", checksum_text(done.hash))],
    )?;
    if shard == Shard::ALL {
        if info.total_cases <= MAX_PLOT_CASES {
            let text = String::from_utf8(read_plain(&csv_partial)?)
                .with_context(|| format!("reading {}", csv_partial.display()))?;
            let table = Table::parse_csv(&text).map_err(anyhow::Error::new)?;
            drop(text);
            write_plots(out.stage(), &table)?;
        } else if !quiet {
            eprintln!(
                "note: no plots: {} cases (plots are drawn for at most {MAX_PLOT_CASES})",
                info.total_cases
            );
        }
    }
    out.commit(&["shard.json"])?;
    if !quiet {
        let n = range.len();
        let what = if shard == Shard::ALL {
            format!("{n} cases")
        } else {
            format!(
                "shard {}/{}: cases {}..{} of {}",
                shard.k, shard.n, range.start, range.end, info.total_cases
            )
        };
        println!(
            "{what} ({} ok, {failed} failed) in {} -> {}",
            n - failed,
            crate::output::fmt_duration(start.elapsed().as_secs_f64()),
            dir.join("sweep.csv").display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The file a sweep streams its rows into, in grid order, while it runs;
/// renamed to `sweep.csv` when the last case is done.
pub const PARTIAL_CSV: &str = "sweep.csv.partial";

/// Largest sweep that gets plots: the plots are drawn from the whole table,
/// read back from `sweep.csv` (about 300 bytes a case in memory); larger
/// sweeps get a note instead, and the data stay complete in `sweep.csv`.
pub const MAX_PLOT_CASES: usize = 100_000;

/// Merge the shards of a sweep (`tippetop merge`, after
/// [`crate::merge_cmd::run`] has checked --out and told the shards'
/// kind). Bad input (a missing or foreign shard, a gap, an overlap): one
/// line on stderr and exit code 2 (returned as `Ok`), nothing written;
/// `Err` for I/O failures while writing.
pub fn merge(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    let mut shards: Vec<(ShardInfo, String)> = Vec::new();
    for dir in &args.dirs {
        // Not while a sweep writes into it (e.g. a task still running):
        // exit code 1, as for a busy --out.
        let _reading = crate::output::read_lock(dir)?;
        match read_shard(dir) {
            Ok(s) => shards.push(s),
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    let csv = match sweep::merge(&shards) {
        Ok(c) => c,
        Err(e) => return Ok(input_error(e)),
    };
    let first = &shards[0].0;
    let info = ShardInfo {
        fingerprint: first.fingerprint.clone(),
        k: 1,
        n: 1,
        total_cases: first.total_cases,
        first_index: 0,
        end_index: first.total_cases,
        axes: first.axes.clone(),
        checksums: Default::default(),
    };
    let table = Table::parse_csv(&csv).map_err(anyhow::Error::new)?;
    let out = OutDir::open(&args.out)?;
    write_bytes_atomic(&out.stage().join("sweep.csv"), csv.as_bytes())?;
    write_info(
        out.stage(),
        &info,
        &[("sweep.csv", crate::partial::checksum(csv.as_bytes()))],
    )?;
    if info.total_cases <= MAX_PLOT_CASES {
        write_plots(out.stage(), &table)?;
    } else if !quiet {
        eprintln!(
            "note: no plots: {} cases (plots are drawn for at most {MAX_PLOT_CASES})",
            info.total_cases
        );
    }
    out.commit(&["shard.json"])?;
    if !quiet {
        let failed = table.status.iter().filter(|s| *s != "ok").count();
        println!(
            "merged {} shards: {} cases ({} ok, {failed} failed) -> {}",
            shards.len(),
            info.total_cases,
            info.total_cases - failed,
            args.out.join("sweep.csv").display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// A shard directory's `shard.json` and `sweep.csv`; `Err` is the one-line
/// message for bad input.
fn read_shard(dir: &Path) -> std::result::Result<(ShardInfo, String), String> {
    read_shard_of(
        dir,
        "sweep.csv",
        "a directory written by tippetop sweep, with shard.json and sweep.csv",
    )
}

/// Plots of a complete sweep into `dir`: for one axis, curves of the
/// columns against it (`table.column(key)`, `table.column("theta_final")`,
/// ...); for two axes, a heat map (`table.grid2("theta_final")` gives the
/// axes' values and the matrix). NaN marks a failed case.
fn write_plots(dir: &Path, table: &Table) -> Result<()> {
    use crate::plot::{HeatmapOpts, Panel, PlotOpts, RefLine, Series, heatmap, multi_panel};
    match table.keys.len() {
        1 => {
            let key = &table.keys[0];
            let x = table.column(key).unwrap_or_default();
            let col = |name: &str| table.column(name).unwrap_or_default();
            let mut theta = Panel::new(
                "θ [rad]",
                vec![
                    Series::new("θ final", x.clone(), col("theta_final")),
                    Series::new("θ max", x.clone(), col("theta_max")).dashed(),
                ],
            );
            theta.opts.hlines = vec![
                RefLine::new(std::f64::consts::FRAC_PI_2, "π/2"),
                RefLine::new(std::f64::consts::PI, "π"),
            ];
            let spin = Panel::new(
                "ω final [rad/s]",
                vec![Series::new("ω final", x.clone(), col("omega_final"))],
            );
            let first = Panel::new(
                "first θ > π/2 [s]",
                vec![Series::new(
                    "first time θ > π/2",
                    x.clone(),
                    col("first_time_theta_above_half_pi"),
                )],
            );
            multi_panel(
                &dir.join("sweep"),
                &format!("Sweep over {key}"),
                &axis_label(key),
                &[theta, spin, first],
                &PlotOpts {
                    size: (1000, 900),
                    ..Default::default()
                },
            )
        }
        2 => {
            let Some((xs, ys, z)) = table.grid2("theta_final") else {
                return Ok(());
            };
            // grid2 gives z[i][j] at (xs[i], ys[j]); heatmap wants rows per y.
            let zt: Vec<Vec<f64>> = (0..ys.len())
                .map(|j| (0..xs.len()).map(|i| z[i][j]).collect())
                .collect();
            heatmap(
                &dir.join("sweep"),
                "θ at the end of each run (grey: failed case)",
                &axis_label(&table.keys[0]),
                &axis_label(&table.keys[1]),
                "θ final [rad]",
                &xs,
                &ys,
                &zt,
                &HeatmapOpts {
                    z_range: Some((0.0, std::f64::consts::PI)),
                    ..Default::default()
                },
            )
        }
        _ => Ok(()),
    }
}

/// An axis label for a swept key: the key with its unit (`top.offset [m]`),
/// `[1]` for a dimensionless scenario key.
fn axis_label(key: &str) -> String {
    match tippetop::input::scenario::key_unit(key) {
        Some(u) => format!("{key} [{u}]"),
        None => format!("{key} [1]"),
    }
}
