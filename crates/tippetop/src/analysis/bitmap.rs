//! Design maps of a memory bit (issue #16 item 4): the bit of
//! [`crate::analysis::bit`] on a grid of scenario or protocol keys, one
//! `bitmap.csv` row per grid point with every `bit.json` figure.
//!
//! The grid is a [`Sweep`]'s (the same `--vary KEY=FROM:TO:N[:log]` axes,
//! grid order, [`Shard`]s, resume and merge): each grid point is the bit
//! scenario ([`BitScenario::load`]) with `KEY=VALUE` appended to the `--set`
//! list for every axis, so any key `--set` reaches can vary: scenario keys
//! (`top.offset`, `thermal.temperature`) and the bit's (`bit.hold`,
//! `write.0.hy`, `erase.1.stop`). A point whose scenario is invalid gets
//! the error in `status` and empty figures; one with runs that failed gets
//! their count and the first failure in `status` and keeps its figures (a
//! minimum over runs, the pull-off margin's, over those that completed);
//! the map goes on.
//!
//! At a point at T = 0 (or with a deterministic method) the bit is one run;
//! at T > 0 it is an ensemble of `runs` runs, run `k` with
//! `thermal.run = r0 + k` at every point: the same random streams at every
//! grid point (common random numbers), so differences between neighbouring
//! points are not noise of different draws. The runs of a point run one
//! after the other on one thread; the points run in parallel
//! ([`crate::analysis::sweep::run_ordered`]), and the rows come back in
//! grid order whatever the thread count.
//!
//! # `bitmap.csv`
//!
//! Header: the varied keys in axis order; for each block `write`, `erase`,
//! `erase_given_write`, `cycle` of `bit.json` the [`BLOCK_FIELDS`] prefixed
//! with the block's name (`write_probability`, `cycle_time_median`, ...);
//! then [`TAIL_FIELDS`] and `status`. Floats in the shortest round-trip
//! form, an empty field for a missing value, `\n` line endings.

use std::ops::Range;

use crate::Error;
use crate::analysis::bit::{self, Block, Mode, Protocol, Report, RunResult};
use crate::analysis::sweep::{
    self, Case, Prefix, Shard, ShardInfo, Sweep, fmt_f64, run_ordered, status_field,
};
use crate::input::scenario::bit::BitScenario;
use crate::input::thermal::{MAX_ENSEMBLE_RUNS, MAX_RUNS};

/// The figures of each block, after its name and `_` (units: times \[s\],
/// energy \[J\], force \[N\]; the rest are counts or fractions).
/// `ci_lo`, `ci_hi` are `ci95`; the last five are the failures per
/// [`Mode`].
pub const BLOCK_FIELDS: [&str; 15] = [
    "runs",
    "successes",
    "probability",
    "ci_lo",
    "ci_hi",
    "time_median",
    "time_q25",
    "time_q75",
    "energy_median",
    "max_applied_force",
    "never_entered",
    "left",
    "too_late",
    "run_failed",
    "lifted_off",
];

/// The blocks of `bit.json`, in column order.
pub const BLOCKS: [&str; 4] = ["write", "erase", "erase_given_write", "cycle"];

/// The columns after the blocks and before `status`: the runs of the point,
/// `deterministic` (`true`: one run at T = 0), the smallest pull-off
/// margin over the runs \[N\] (empty without adhesion).
pub const TAIL_FIELDS: [&str; 3] = ["runs", "deterministic", "pull_off_margin_min"];

/// Runs per point at T > 0 when not given.
pub const DEFAULT_RUNS: usize = 100;

/// The name of the map's CSV.
pub const CSV_NAME: &str = "bitmap.csv";

/// Fields of a `bitmap.csv` line of a map over `nkeys` keys.
pub fn ncols(nkeys: usize) -> usize {
    nkeys + BLOCKS.len() * BLOCK_FIELDS.len() + TAIL_FIELDS.len() + 1
}

/// A design map: the grid (base bit scenario and axes) and the runs per
/// point at T > 0.
#[derive(Debug, Clone, PartialEq)]
pub struct BitMap {
    /// The base bit scenario (`preset`, `toml_text`, `sets`, as for
    /// [`BitScenario::load`]) and the varied keys (the first slowest).
    pub grid: Sweep,
    /// Runs of each point at T > 0 (a point at T = 0 runs once), >= 1.
    pub runs: usize,
}

/// One grid point's result.
#[derive(Debug, Clone, PartialEq)]
pub struct MapRow {
    /// Position in grid order (0-based).
    pub index: usize,
    /// One value per axis (the keys' units).
    pub values: Vec<f64>,
    /// The point's `bit.json` statistics; `None` if its scenario is invalid.
    pub report: Option<Report>,
    /// `"ok"` if every run of the point completed; else how many failed
    /// and the first failure (`3 of 100 runs failed; the first, run 7: at
    /// t = ...`), the figures kept; or why the point's scenario is invalid.
    pub status: String,
}

impl BitMap {
    /// The bit scenario of grid point `case`.
    pub fn load_case(&self, case: &Case) -> Result<BitScenario, Error> {
        BitScenario::load(
            self.grid.preset.as_deref(),
            self.grid.toml_text.as_deref(),
            &self.grid.case_sets(case),
        )
    }

    /// Number of grid points.
    pub fn total(&self) -> usize {
        self.grid.total()
    }

    /// Check the map before running anything: `runs` in `1..=`
    /// [`MAX_ENSEMBLE_RUNS`], the
    /// axes and the grid as [`Sweep::validate`] with bit scenarios (a key
    /// that no point accepts is named in the error).
    pub fn validate(&self) -> Result<(), Error> {
        if self.runs == 0 || self.runs > MAX_ENSEMBLE_RUNS {
            return Err(Error::invalid(
                "--runs",
                format!("{} runs per point", self.runs),
                format!("1 to {MAX_ENSEMBLE_RUNS}"),
            ));
        }
        self.grid
            .validate_with(&|case| self.load_case(case).map(|_| ()))
    }

    /// A 16-hex-digit hash of what defines the map's output (as
    /// [`Sweep::fingerprint`], with the runs per point).
    pub fn fingerprint(&self) -> String {
        self.grid
            .fingerprint_of("tippetop bitmap 1", &[("runs", self.runs.to_string())])
    }

    /// What `shard` of the map covers, for `shard.json`.
    pub fn shard_info(&self, shard: Shard) -> Result<ShardInfo, Error> {
        let mut info = self.grid.shard_info(shard)?;
        info.fingerprint = self.fingerprint();
        Ok(info)
    }

    /// Run grid point `index`: load its bit scenario, run it (once at
    /// T = 0, `runs` times at T > 0) and gather the statistics. Never
    /// fails: an invalid scenario goes into `status`, a failed run is a
    /// result ([`bit::run_one`]) that the status counts.
    pub fn run_point(&self, index: usize) -> MapRow {
        let case = self.grid.case(index);
        let (report, status) = match self.load_case(&case) {
            Ok(bs) => match self.point(&bs) {
                Ok((r, status)) => (Some(r), status),
                Err(e) => (None, e.to_string()),
            },
            Err(e) => (None, e.to_string()),
        };
        MapRow {
            index,
            values: case.values,
            report,
            status,
        }
    }

    /// The statistics of the point `bs` and its status ([`MapRow::status`]).
    fn point(&self, bs: &BitScenario) -> Result<(Report, String), Error> {
        let stochastic = bit::is_stochastic(bs);
        let runs = if stochastic { self.runs } else { 1 };
        let r0 = bs.scenario.thermal.run;
        if runs as u64 > MAX_RUNS - r0.min(MAX_RUNS) {
            return Err(Error::invalid(
                "--runs",
                format!("{runs} runs from thermal.run = {r0}"),
                format!("run indices thermal.run .. thermal.run + runs - 1 below {MAX_RUNS}"),
            ));
        }
        let results: Vec<RunResult> = (0..runs).map(|k| bit::run_one(bs, k as u64)).collect();
        let mut failed = results.iter().filter(|r| r.status != "ok");
        let status = match failed.next() {
            None => "ok".to_string(),
            Some(first) => format!(
                "{} of {runs} runs failed; the first, run {}: {}",
                1 + failed.count(),
                first.run,
                first.status
            ),
        };
        Ok((
            bit::report_of(&Protocol::of(bs), &results, !stochastic),
            status,
        ))
    }

    /// How many points the map may run at once within
    /// [`crate::limits::MEMORY_BUDGET`]: at most `threads`, each keeping a
    /// run of the grid's largest `solver.samples` and the results of its
    /// `runs` runs. Error (key `solver.samples`) if not even one fits.
    pub fn threads_within_memory(&self, threads: usize) -> Result<usize, Error> {
        let samples = self
            .grid
            .max_samples_with(&|case| self.load_case(case).ok().map(|b| b.scenario.solver.samples));
        let result = (std::mem::size_of::<RunResult>() + 64) as u64;
        let row = (std::mem::size_of::<MapRow>() + std::mem::size_of::<Report>() + 1024) as u64;
        let per_point =
            crate::limits::run_memory_bytes_for(samples) + self.runs as u64 * result + 9 * row;
        crate::limits::fit_threads("solver.samples", threads, per_point, 16 * row)
    }

    /// Run the points `range` on `threads` threads (`None`: see
    /// [`sweep::threads`]) and hand each row to `sink` in grid order, with
    /// the memory and ordering guarantees of [`Sweep::run_streaming`]
    /// (`Ok(false)`: `sink` stopped it). Errors as for
    /// [`Sweep::run_streaming`].
    pub fn run_streaming(
        &self,
        range: Range<usize>,
        threads: Option<usize>,
        sink: &mut dyn FnMut(MapRow) -> bool,
    ) -> Result<bool, Error> {
        self.grid.check_range(&range, "bitmap")?;
        run_ordered(range, threads, &|i| self.run_point(i), sink)
    }

    /// How much of an interrupted `bitmap.csv` of the points from
    /// `first_index` on can be kept (see [`Sweep::complete_prefix`]).
    pub fn complete_prefix(&self, first_index: usize, text: &str) -> Prefix {
        self.grid.complete_prefix_of(
            first_index,
            text,
            &csv_header(&self.grid.axes),
            ncols(self.grid.axes.len()),
        )
    }
}

/// The header line of `bitmap.csv` (with its `\n`).
pub fn csv_header(axes: &[sweep::Axis]) -> String {
    let mut cols: Vec<String> = axes.iter().map(|a| a.key.clone()).collect();
    for b in BLOCKS {
        cols.extend(BLOCK_FIELDS.iter().map(|f| format!("{b}_{f}")));
    }
    cols.extend(TAIL_FIELDS.iter().map(|f| f.to_string()));
    cols.push("status".into());
    let mut s = cols.join(",");
    s.push('\n');
    s
}

fn opt(x: Option<f64>) -> String {
    x.map(fmt_f64).unwrap_or_default()
}

fn block_fields(b: &Block, out: &mut Vec<String>) {
    out.push(b.runs.to_string());
    out.push(b.successes.to_string());
    out.push(opt(b.probability));
    out.push(opt(b.ci95.map(|c| c[0])));
    out.push(opt(b.ci95.map(|c| c[1])));
    out.push(opt(b.time_median));
    out.push(opt(b.time_q25));
    out.push(opt(b.time_q75));
    out.push(opt(b.energy_median));
    out.push(fmt_f64(b.max_applied_force));
    for m in Mode::ALL {
        out.push(b.failures.get(m.as_str()).copied().unwrap_or(0).to_string());
    }
}

/// One line of `bitmap.csv` (with its `\n`).
pub fn csv_row(row: &MapRow) -> String {
    let mut fields: Vec<String> = row.values.iter().map(|&v| fmt_f64(v)).collect();
    match &row.report {
        Some(r) => {
            for b in [&r.write, &r.erase, &r.erase_given_write, &r.cycle] {
                block_fields(b, &mut fields);
            }
            fields.push(r.runs.to_string());
            fields.push(r.deterministic.to_string());
            fields.push(opt(r.pull_off_margin_min));
        }
        None => fields.extend(std::iter::repeat_n(
            String::new(),
            BLOCKS.len() * BLOCK_FIELDS.len() + TAIL_FIELDS.len(),
        )),
    }
    fields.push(status_field(&row.status));
    let mut s = fields.join(",");
    s.push('\n');
    s
}

/// Join the shards of one map (each its `shard.json` and `bitmap.csv`, in
/// any order) into the `bitmap.csv` of the whole map, byte for byte what
/// an unsharded run writes (checks as [`sweep::merge`]).
pub fn merge(shards: &[(ShardInfo, String)]) -> Result<String, Error> {
    let Some((first, _)) = shards.first() else {
        return Err(Error::invalid(
            "merge",
            "no shards given".into(),
            "one or more shard outputs".into(),
        ));
    };
    sweep::merge_of(
        shards,
        &csv_header(&first.axes),
        ncols(first.axes.len()),
        CSV_NAME,
        "bit",
    )
}

/// The position of column `name` in a `bitmap.csv` header line.
pub fn column_index(header: &str, name: &str) -> Option<usize> {
    header.trim_end().split(',').position(|c| c == name)
}
