//! The arguments of `tippetop bit`, shared by its three modes: a bit or
//! its ensemble ([`crate::bit_cmd`]), a design map with `--vary`
//! ([`crate::bitmap_cmd`]) and a protocol search with `--search`
//! ([`crate::search_cmd`]).

use std::path::PathBuf;

use clap::{ArgGroup, Args};

/// Long help of `tippetop bit`.
pub const BIT_LONG_ABOUT: &str = "Run a memory bit: write (phase 1, target bit.one), then erase
(phase 2, target bit.zero), and write into --out:
  bit.json       for write, erase (all runs), erase_given_write (runs whose write succeeded)
                 and cycle (both succeeded): runs, successes, probability, ci95 (Wilson 95 %
                 at T > 0; [p, p] with deterministic = true for the single run at T = 0),
                 time_median, time_q25, time_q75 (switching time: the start of the final stay
                 in the target window, from the phase start; cycle: from the write's start)
                 [s], energy_median (net work of the applied force on the top over the phase)
                 [J], max_applied_force (largest total of the windows acting at once) [N],
                 failures per mode (never_entered, left, too_late, run_failed, lifted_off);
                 pull_off_margin_min over the runs that completed [N] (with adhesion; null
                 if none did); the bit and protocols
  bit.md         the same in words, with theta.png
  theta.png, theta.svg   theta(t) of a typical run (the first with the most frequent outcome)
  theta_PHASE_MODE.png, .svg   ensembles: theta(t) of the first run whose write or erase
                 failed as MODE, one per failure mode seen (linked from bit.md)
  runs.csv       one row per run: run (thermal.run), status, then for write and erase:
                 outcome (ok or the failure mode), time [s], energy [J]; pull_off_margin_min
  bit.toml       the resolved bit scenario, every key explicit: `tippetop bit bit.toml`
                 runs it again
  scenario.toml  the run's scenario (run 0): `tippetop run scenario.toml --set thermal.run=R`
                 replays run R alone

The scenario file has a [bit] table (zero = [lo, hi], one = [lo, hi] [rad], defaults [0, 0.5]
and [pi/2 - 0.35, pi/2 + 0.35], disjoint; hold [s] > 0; phase [s] > hold) and [[write]],
[[erase]] windows (kind = \"contact\", the default: hx, hy, optional hz [N], the paper's force
at the contact point in the precessing frame; kind = \"tip\": point [m] in the body frame and
force [N] in the lab frame; kind = \"magnetic\": moment [A m^2] along the axis, field [T] and
gradient [T/m] in the lab frame, docs/physics.md#actuators; start, stop [s] from the start of the
phase, start < stop <= phase, stop default phase). The run lasts 2 x phase
(solver.t_end is replaced), the scenario's own [[force]] list must be empty (a preset's is
replaced by the protocols), the initial theta must lie in zero. A phase succeeds iff theta stays in
its target window during its last hold seconds on the continuous solution (events at the
window's edges; an excursion within one integration step is not seen, and the step is at most
the row spacing: at least 10 rows per hold); its switching time is the crossing into the window.
--set reaches bit.KEY, write.K.KEY and erase.K.KEY. At T > 0
(solver.method = \"langevin\" or \"brownian\") --runs N runs (default 100, at most 1000000), run K with
thermal.run = r0 + K, independent of --threads; --shard K/M runs only the K-th of M blocks of
the runs and writes runs.csv (those runs), shard.json and bit.toml: tippetop merge of the
shards' directories writes the outputs of the unsharded run, byte for byte (--shard at T = 0
is bad input: one run). A run that fails part-way is a result (its
phases from the failure on are run_failed or lifted_off; exit code 0). Bad input exits with
code 2 and writes nothing.

The step check (at T > 0 with --runs 2 or more; on by default, --no-step-check skips it): after
the ensemble, the same runs again on the scenario at solver.dt/2 (the step limit doubled, an
independent seed: thermal.seed + 0x9E3779B97F4A7C15, wrapping): twice the steps, about twice
the ensemble's own time, so the command takes about three times as long as with --no-step-check
(scenarios/bit/nano_300K.toml, 100 runs: 74 s against 21 s). Each probability with a 95 %
interval (write, erase, erase_given_write, cycle) is compared with its value at dt/2: converged
in the step when |P(dt/2) - P(dt)| is below the change's own 95 % half-width (the two answers'
half-widths in quadrature, widened by the Bonferroni factor of the number of probabilities
judged together; docs/physics.md#step-check). The answer written stays the one at solver.dt;
bit.json gains dt_converged (true: every checked probability converged; false: one or more did
not, and the console and bit.md warn \"NOT converged in the step\": use a smaller solver.dt;
null: not checked), step_check (per probability: scale, at_dt and at_half_dt, each {dt,
estimate, ci95}, step_error, statistical, family, converged; null if not checked) and
step_unchecked (why not, or null); bit.md has a step-check section; runs_half_dt.csv holds the
runs at dt/2 (the columns of runs.csv). With no step error, noise alone flags a bit at most
about 5 % of the time; a step error shows again at a smaller solver.dt, noise does not. --shard K/M runs
the check's runs of its block too (runs_half_dt.csv, checksummed in shard.json): tippetop merge
writes the checked outputs. --resume keeps the check's runs on disk as it keeps the ensemble's
(DIR/runs_half_dt.csv.partial). No check (dt_converged null, the console and bit.md say why):
with --no-step-check, at T = 0 (one deterministic run: no interval), with --runs 1 (no interval
worth comparing), in a design map (below). A scenario whose dt/2 version is invalid exits with
code 2 naming the key.

Design maps: --vary KEY=FROM:TO:N[:log] (repeatable, the grammar of tippetop sweep; any key
--set reaches: write.0.hy, write.0.stop, erase.1.hx, bit.hold, thermal.temperature, ...) runs
the bit at every point of the grid and writes into --out:
  bitmap.csv   one row per point in grid order (first --vary slowest): the varied keys; for
               each of write, erase, erase_given_write, cycle: BLOCK_runs, _successes,
               _probability, _ci_lo, _ci_hi, _time_median, _time_q25, _time_q75 [s],
               _energy_median [J], _max_applied_force [N], _never_entered, _left, _too_late,
               _run_failed, _lifted_off; then runs, deterministic, pull_off_margin_min [N],
               status (ok; or how many runs failed and the first one's error, the figures
               kept; or why the point's scenario is invalid: empty figures)
  shard.json   what the CSV covers, for tippetop merge
  bitmap.png, bitmap.svg   one --vary: write probability (with its 95 % interval) and median
               write time against the key
  write_probability.png/.svg, write_time.png/.svg   two or more --vary: heat maps over the
               first two keys (the others at their first value; at most 250 values per axis)
Each row is the single `tippetop bit --set KEY=VALUE ...` run of its point. At T > 0 a point is
--runs N runs (default 100, at most 1000000; a point at T = 0 runs once), run K with thermal.run = r0 + K at
every point (common random numbers). The points run in parallel (--threads), the rows stream
into bitmap.csv.partial in grid order (memory flat in the number of points); the bytes do not
depend on --threads. --shard K/N runs the K-th of N blocks of points (join them with tippetop
merge: the bytes of an unsharded run); --resume continues an interrupted map. Keep
solver.samples at 1 + 10 x 2 phase / hold, the least the hold check takes: the rows also cap
the step size. A key no point accepts, or a bad range: one line naming it, exit code 2. A map
runs no step check (its cost would double; the console says \"step unchecked: a map\"): check
the point you choose with tippetop bit --set KEY=VALUE, without --vary.";

/// A memory bit: write and erase protocols, success probabilities, switching times.
#[derive(Debug, Args)]
#[command(long_about = BIT_LONG_ABOUT)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop bit scenarios/bit/nano.toml --out out/bit\n  \
                  tippetop bit scenarios/bit/nano.toml --set write.0.hy=2e-22 --out out/bit2\n  \
                  tippetop bit scenarios/bit/nano.toml --vary write.0.hy=0:1e-21:50 \\\n      \
                  --vary write.0.stop=1e-5:1e-4:50 --out out/bitmap"
)]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML) with [bit], [[write]] and [[erase]]")),
    mut_arg("sets", |a| a.help("Override one value, e.g. `--set write.0.hy=2e-22` or `--set bit.hold=1e-5`; repeatable, applied in order after the file")),
)]
pub struct BitArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,

    /// Number of runs at T > 0 (default 100; with --vary, per grid point); at
    /// T = 0 only 1.
    #[arg(long, value_name = "N")]
    pub runs: Option<usize>,

    /// Output directory (created if missing; locked while the command runs).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// `--threads`.
    #[command(flatten)]
    pub cores: crate::common::args::ThreadsArg,

    /// A design map: vary one key (as in --set: a scenario key, bit.KEY,
    /// write.K.KEY, erase.K.KEY) over N values from FROM to TO, both
    /// included (`:log` for geometric spacing). Repeatable: the points form
    /// a grid, the first --vary varying slowest; writes bitmap.csv.
    #[arg(long = "vary", value_name = "KEY=FROM:TO:N[:log]")]
    pub vary: Vec<String>,

    /// Run only the K-th of N contiguous blocks of the grid points (with
    /// --vary) or of the runs (an ensemble at T > 0); join the outputs
    /// with `tippetop merge`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,

    /// Continue an interrupted map (--vary; from DIR/bitmap.csv.partial) or
    /// ensemble (T > 0; from DIR/runs.csv.partial) with the same scenario,
    /// --set, --vary, --runs and --shard: the runs on disk are kept and
    /// the outputs are those of an uninterrupted run, byte for byte.
    #[arg(long)]
    pub resume: bool,

    /// Search the protocol of one phase instead (T = 0; the file's
    /// [search] table: phase, windows, actuator ("contact", "tip" with
    /// point [m], "magnetic" with moment [A m^2]), bounds of magnitude
    /// ([N]; |B| [T] for a magnet), angle, start and duration, weight,
    /// margin, seed, budget, perturbations; docs/physics.md#search). Writes
    /// search.json, search.md, best.toml, evaluations.csv.
    #[arg(long, conflicts_with_all = ["vary", "shard", "resume"])]
    pub search: bool,

    /// Skip the step check (the runs again at solver.dt/2, about twice as
    /// long as the ensemble itself): bit.json's dt_converged and step_check are
    /// then null and the console and bit.md say the step is unchecked.
    #[arg(long)]
    pub no_step_check: bool,
}
