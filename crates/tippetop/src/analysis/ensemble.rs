//! Ensembles of Langevin runs: the same scenario run `N` times with
//! independent noise, one CSV row per run, fixed-bin histograms of θ, ω and
//! Ω at every sample time, quantiles from them, means with 95 % confidence
//! intervals and Kaplan–Meier medians of first-passage times. No I/O: the
//! CLI (`tippetop ensemble`) streams the rows to disk.
//!
//! # Runs
//!
//! Run `k` of an ensemble (`0 <= k < N`) is the scenario with
//! `thermal.run = r0 + k`, `r0` the scenario's own `thermal.run` (default
//! 0). The noise of a Langevin run is a pure function of `(thermal.seed,
//! thermal.run, step)`, so run `k` can be replayed alone (`tippetop run
//! ... --set thermal.run=R` with `R` the row's `run` column) and the rows do
//! not depend on threads, shards or order. The parallel machinery is the
//! sweep's ([`sweep::run_ordered`], [`sweep::shard_range`]).
//!
//! # `ensemble.csv`
//!
//! Header [`csv_header`]: `run,seed,status`, then `<col>_final` for every
//! `trajectory.csv` column ([`COLUMNS`], the last output row's values, in
//! its units), then [`EXTRA_FIELDS`]:
//! - `theta_max` \[rad\]: largest θ over every step (the run's summary);
//! - `theta_min` \[rad\], `N_min` \[N\]: smallest θ and normal force over the
//!   output rows;
//! - `negative_normal_fraction`: fraction of the time with N < 0;
//! - `first_passage_time` \[s\]: first time θ > π/2, empty if it never
//!   happened (the run is then censored);
//! - `censored`: 1 if θ never exceeded π/2 in the time the run reached, 0
//!   if it did;
//! - `t_reached` \[s\]: the time the run reached (`solver.t_end` unless it
//!   failed), the censoring time of a censored run.
//!
//! A run that fails part-way keeps its row: `status` is the error, the
//! `_final` values are those of its last output row. Floats are written in
//! Rust's shortest round-trip form, an empty field is a missing value.
//!
//! # Histograms
//!
//! At every sample time, θ, ω and Ω are counted in [`BINS`] equal bins over
//! fixed ranges ([`ranges`]), plus an underflow, an overflow and a
//! `missing` count (runs that ended before that sample, or a NaN). Counts
//! are integers, so histograms of shards add up exactly to the histogram of
//! the whole ensemble. The ranges depend only on the scenario: θ on
//! `[0, π]`; ω on `[min(ω0, 0) − 6 σ_ω, max(ω0, 0) + 6 σ_ω]` with
//! `σ_ω = sqrt(kT/C)` (the equilibrium spread of the spin: the spin relaxes
//! from its initial value ω0 towards 0) and Ω likewise with the initial
//! precession Ω0 and `σ_Ω = sqrt(kT/A)` ([`SPREAD`] = 6 widths). Values
//! outside the range go to the under/overflow bins (Ω, a rate of the tilt's
//! direction, is large near θ = 0 and π, where the direction is ill
//! defined).

use std::collections::BTreeMap;
use std::ops::Range;
use std::panic::{AssertUnwindSafe, catch_unwind};

use serde::{Deserialize, Serialize};

use crate::analysis::sweep::{self, Shard, fmt_f64, fnv1a, status_field};
use crate::input::thermal::{MAX_ENSEMBLE_RUNS, MAX_RUNS};
use crate::trajectory::COLUMNS;
use crate::{Error, Method, Scenario};

pub mod step_check;

/// Number of equal bins of each histogram (plus underflow, overflow and
/// missing).
pub const BINS: usize = 64;

/// Half-width of the ω and Ω histogram ranges beyond the initial value and
/// 0, in thermal widths `sqrt(kT/C)` and `sqrt(kT/A)`.
pub const SPREAD: f64 = 6.0;

/// The quantiles of `quantiles.csv` (as fractions).
pub const QUANTILES: [f64; 5] = [0.05, 0.25, 0.5, 0.75, 0.95];

/// The histogrammed quantities, in the order of `histograms.csv`: θ
/// \[rad\], ω \[rad/s\], Ω \[rad/s\].
pub const QUANTITIES: [&str; 3] = ["theta", "omega", "Omega"];

/// The columns of `ensemble.csv` after the `_final` ones (see the module
/// documentation for their meaning and units).
pub const EXTRA_FIELDS: [&str; 7] = [
    "theta_max",
    "theta_min",
    "N_min",
    "negative_normal_fraction",
    "first_passage_time",
    "censored",
    "t_reached",
];

/// z of the two-sided 95 % normal confidence interval.
pub const Z95: f64 = 1.96;

/// Valid range of `--runs`.
const RUNS_RANGE: &str =
    "1 <= N <= 1000000, with the run indices thermal.run .. thermal.run + N - 1 below 4294967296";

/// Largest `solver.samples` of an ensemble's runs: 100 000. The histograms
/// keep [`HIST_BYTES_PER_SAMPLE`] bytes at every sample time (162 MB at
/// 100 000 samples, twice that while `histograms.csv` and the `--resume`
/// checkpoint are written); at the run's own limit
/// ([`crate::limits::MAX_SAMPLES`], 5 000 000) they would need 8.1 GB.
pub const MAX_SAMPLES: usize = 100_000;

/// Memory of the histograms at one sample time \[bytes\]: three quantities
/// of [`BINS`] + 3 counts (8 bytes each) and the sample time (16).
pub const HIST_BYTES_PER_SAMPLE: u64 = (3 * (BINS + 3) * 8 + 16) as u64;

/// An ensemble: a base scenario (as for [`Scenario::load`]) run `runs`
/// times with independent noise.
#[derive(Debug, Clone, PartialEq)]
pub struct Ensemble {
    /// Preset name (`--preset`), if any.
    pub preset: Option<String>,
    /// Scenario file contents (TOML), if any.
    pub toml_text: Option<String>,
    /// `--set TABLE.KEY=VALUE` overrides.
    pub sets: Vec<String>,
    /// Number of runs `N`.
    pub runs: usize,
    /// The loaded base scenario (its `thermal.run` is the first run's).
    pub scenario: Scenario,
    /// The first-passage criterion (`--first-passage`): each run stops at
    /// the first output row where it holds. `None`: the runs go to
    /// `t_end`, and the passage is θ > π/2 (the run's event).
    pub exit: Option<Exit>,
}

/// Valid form of `--first-passage`.
pub const EXIT_RANGE: &str = "COLUMN>VALUE or COLUMN<VALUE over trajectory.csv columns (SI units), several joined by ',' (any of them), e.g. theta<1.07,theta>2.07";

/// A first-passage criterion over the output rows: any of its terms
/// `column > value` or `column < value` (trajectory.csv columns, SI).
/// Checked at the output rows only: the passage time is the first row's
/// time where it holds (resolution: the sample spacing).
#[derive(Debug, Clone, PartialEq)]
pub struct Exit {
    terms: Vec<(usize, bool, f64)>,
}

impl Exit {
    /// Parse `theta>1.2`, `theta<1.07,theta>2.07` (error key
    /// `--first-passage`).
    pub fn parse(spec: &str) -> Result<Exit, Error> {
        let bad = |what: String| Error::invalid("--first-passage", what, EXIT_RANGE.into());
        let mut terms = Vec::new();
        for term in spec.split(',') {
            let term = term.trim();
            let (col, above, val) = if let Some((c, v)) = term.split_once('>') {
                (c, true, v)
            } else if let Some((c, v)) = term.split_once('<') {
                (c, false, v)
            } else {
                return Err(bad(format!("{term:?} has no > or <")));
            };
            let col = col.trim();
            let Some(i) = COLUMNS.iter().position(|c| *c == col) else {
                return Err(bad(format!("{col:?} is not a trajectory.csv column")));
            };
            let v: f64 = val
                .trim()
                .parse()
                .map_err(|_| bad(format!("{:?} is not a number", val.trim())))?;
            if !v.is_finite() {
                return Err(bad(format!("{v} is not a finite threshold")));
            }
            terms.push((i, above, v));
        }
        Ok(Exit { terms })
    }

    /// The columns the criterion reads (indices into [`COLUMNS`], in the
    /// order of its terms).
    pub fn columns(&self) -> impl Iterator<Item = usize> + '_ {
        self.terms.iter().map(|t| t.0)
    }

    /// Its terms `(column, above, threshold)`: `column > threshold` if
    /// `above`, else `column < threshold` (column an index into
    /// [`COLUMNS`], the threshold in its SI unit).
    pub fn terms(&self) -> &[(usize, bool, f64)] {
        &self.terms
    }

    /// Whether it holds for the values `value(column)` (SI).
    pub fn hit_by(&self, value: &dyn Fn(usize) -> f64) -> bool {
        self.terms.iter().any(|&(i, above, v)| {
            let x = value(i);
            if above { x > v } else { x < v }
        })
    }

    /// Whether an output row (values in [`COLUMNS`] order) has passed.
    pub fn hit(&self, values: &[f64; 26]) -> bool {
        self.terms.iter().any(
            |&(i, above, v)| {
                if above { values[i] > v } else { values[i] < v }
            },
        )
    }
}

impl std::fmt::Display for Exit {
    /// The canonical spec (`theta>1.2,theta<0.5`, shortest round-trip
    /// floats).
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let parts: Vec<String> = self
            .terms
            .iter()
            .map(|&(i, above, v)| format!("{}{}{v:?}", COLUMNS[i], if above { '>' } else { '<' }))
            .collect();
        f.write_str(&parts.join(","))
    }
}

/// Check that `sc` is a stochastic run: `solver.method = "langevin"` or
/// `"brownian"` at `thermal.temperature > 0` (anything else gives `N`
/// identical runs).
pub fn check_scenario(sc: &Scenario) -> Result<(), Error> {
    if !sc.solver.method.is_stochastic() {
        let name = match sc.solver.method {
            Method::Adaptive => "adaptive",
            Method::Rk4 => "rk4",
            Method::Stiff => "stiff",
            Method::Langevin => "langevin",
            Method::Brownian => "brownian",
        };
        return Err(Error::invalid(
            "solver.method",
            format!("\"{name}\" is deterministic: every run of an ensemble would be the same"),
            "\"langevin\" or \"brownian\" with thermal.temperature > 0 for an ensemble".into(),
        ));
    }
    if !sc.thermal.is_hot() {
        return Err(Error::invalid(
            "thermal.temperature",
            format!(
                "{} K gives no noise: every run of an ensemble would be the same",
                sc.thermal.temperature
            ),
            "> 0 [K] for an ensemble".into(),
        ));
    }
    Ok(())
}

/// The fixed histogram ranges `[lower, upper]` of θ \[rad\], ω \[rad/s\] and
/// Ω \[rad/s\] for a scenario (see the module documentation).
pub fn ranges(sc: &Scenario) -> [[f64; 2]; 3] {
    let kt = sc.thermal.kt();
    let s_spin = (kt / sc.top.inertia_axial).sqrt();
    let s_prec = (kt / sc.top.inertia_transverse).sqrt();
    let around = |x0: f64, s: f64| [x0.min(0.0) - SPREAD * s, x0.max(0.0) + SPREAD * s];
    [
        [0.0, std::f64::consts::PI],
        around(sc.initial.spin, s_spin),
        around(sc.initial.precession, s_prec),
    ]
}

/// The result of one run: its row of `ensemble.csv` and its output rows'
/// θ, ω, Ω for the histograms.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Position in the ensemble (0-based).
    pub index: usize,
    /// `thermal.run` of the run (replay it with `--set thermal.run=R`).
    pub run: u64,
    /// `thermal.seed`.
    pub seed: u64,
    /// `"ok"` or the error.
    pub status: String,
    /// The last output row's values in [`COLUMNS`] order (its units);
    /// `None` without any output row.
    pub finals: Option<[f64; 26]>,
    /// Largest θ over every step \[rad\].
    pub theta_max: Option<f64>,
    /// Smallest θ over the output rows \[rad\].
    pub theta_min: Option<f64>,
    /// Smallest normal force over the output rows \[N\].
    pub normal_min: Option<f64>,
    /// Fraction of the time with N < 0.
    pub negative_normal_fraction: Option<f64>,
    /// First time θ > π/2 \[s\], if it happened.
    pub first_passage: Option<f64>,
    /// Time the run reached \[s\]; `None` if it did not run.
    pub t_reached: Option<f64>,
    /// Per output row: `[t, θ, ω, Ω]` (s, rad, rad/s, rad/s).
    pub samples: Vec<[f64; 4]>,
}

impl RunRow {
    /// Whether the first passage was not observed (`None` if the run did
    /// not run at all).
    pub fn censored(&self) -> Option<bool> {
        self.t_reached.map(|_| self.first_passage.is_none())
    }
}

/// Run `sc` sample by sample until the first output row where `exit`
/// holds (or `t_end`, or a failure): the trajectory up to there.
/// The per-step record is the lean one ([`crate::Simulation::lean`]): the row
/// reads no J or energy.
fn run_to_exit(sc: &Scenario, exit: &Exit) -> Result<crate::Trajectory, Error> {
    let mut sim = crate::Simulation::new(sc)?.lean();
    let (n, t_end) = (sc.solver.samples, sc.solver.t_end);
    let mut seen = 0;
    'run: for i in 0..n {
        let t = if i + 1 == n {
            t_end
        } else {
            t_end * i as f64 / (n - 1) as f64
        };
        sim.integrate_to(t)?;
        let rows = sim.samples();
        for r in &rows[seen..] {
            if exit.hit(&r.values()) {
                break 'run;
            }
        }
        seen = rows.len();
        if sim.is_finished() {
            break;
        }
    }
    Ok(sim.into_trajectory())
}

/// What [`Ensemble::complete_prefix`] keeps of an interrupted
/// `ensemble.csv` (the sweep's [`crate::analysis::sweep::Prefix`]: rows,
/// bytes, failed rows, and why the first complete line not kept was
/// refused).
pub use crate::analysis::sweep::Prefix;

/// What a shard of an ensemble covers, written beside its CSV as
/// `shard.json`; [`merge_csv`] checks a set of them against each other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct EnsembleShard {
    /// Always `"ensemble"` (tells an ensemble's shard from a sweep's).
    pub kind: String,
    /// [`Ensemble::fingerprint`].
    pub fingerprint: String,
    /// Which shard, 1-based.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
    /// Number of runs of the whole ensemble.
    pub total_runs: usize,
    /// First run of the shard (0-based position).
    pub first_index: usize,
    /// One past the last run of the shard.
    pub end_index: usize,
    /// `thermal.run` of the ensemble's first run.
    pub first_run: u64,
    /// `thermal.seed`.
    pub seed: u64,
    /// The first-passage criterion (`--first-passage`), if any.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub exit: Option<String>,
    /// `thermal.temperature` \[K\] (for `tippetop retention`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub temperature: Option<f64>,
    /// The checksums of the files the shard's output holds (`ensemble.csv`,
    /// `histograms.csv`): file name to `fnv1a64:` and the 16 hex digits of
    /// the FNV-1a 64 hash of its bytes; `tippetop merge` checks them. Empty
    /// (and not written) in the partial `shard.json` of a running
    /// ensemble.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub checksums: BTreeMap<String, String>,
}

impl Ensemble {
    /// Load and check an ensemble: the scenario must load and be a
    /// stochastic run ([`check_scenario`]); `1 <= runs` and the last run's
    /// `thermal.run` below 2^32 (key `--runs`).
    pub fn new(
        preset: Option<String>,
        toml_text: Option<String>,
        sets: Vec<String>,
        runs: usize,
    ) -> Result<Ensemble, Error> {
        let scenario = Scenario::load(preset.as_deref(), toml_text.as_deref(), &sets)?;
        check_scenario(&scenario)?;
        let samples = scenario.solver.samples;
        if samples > MAX_SAMPLES {
            return Err(Error::invalid(
                "solver.samples",
                format!(
                    "{samples} samples for an ensemble: its histograms would need {} ({HIST_BYTES_PER_SAMPLE} bytes per sample)",
                    crate::limits::fmt_bytes(HIST_BYTES_PER_SAMPLE.saturating_mul(samples as u64))
                ),
                format!("2 <= samples <= {MAX_SAMPLES} for an ensemble"),
            ));
        }
        let room = MAX_RUNS - scenario.thermal.run.min(MAX_RUNS);
        if runs == 0 || runs > MAX_ENSEMBLE_RUNS || runs as u64 > room {
            return Err(Error::invalid(
                "--runs",
                format!("{runs} runs from thermal.run = {}", scenario.thermal.run),
                RUNS_RANGE.into(),
            ));
        }
        Ok(Ensemble {
            preset,
            toml_text,
            sets,
            runs,
            scenario,
            exit: None,
        })
    }

    /// The same ensemble with a first-passage criterion: each run stops
    /// at its first output row where `exit` holds ([`Ensemble::exit`]).
    pub fn with_exit(mut self, exit: Option<Exit>) -> Ensemble {
        self.exit = exit;
        self
    }

    /// `thermal.run` of the first run.
    pub fn first_run(&self) -> u64 {
        self.scenario.thermal.run
    }

    /// `thermal.seed` (required by the scenario's validation at T > 0).
    pub fn seed(&self) -> u64 {
        self.scenario.thermal.seed.unwrap_or(0)
    }

    /// The scenario of run `index`: the base with `thermal.run = r0 + index`.
    pub fn scenario_of(&self, index: usize) -> Scenario {
        let mut sc = self.scenario.clone();
        sc.thermal.run = self.first_run() + index as u64;
        sc
    }

    /// Run `index`. Never fails: errors (and panics) go into the row's
    /// `status`. The trajectory is reduced to the row and dropped.
    pub fn run(&self, index: usize) -> RunRow {
        let sc = self.scenario_of(index);
        let mut row = RunRow {
            index,
            run: sc.thermal.run,
            seed: self.seed(),
            status: String::new(),
            finals: None,
            theta_max: None,
            theta_min: None,
            normal_min: None,
            negative_normal_fraction: None,
            first_passage: None,
            t_reached: None,
            samples: Vec::new(),
        };
        let outcome = catch_unwind(AssertUnwindSafe(|| match &self.exit {
            // The same row as `simulate` (which replays it), without the
            // per-step J and energy the row does not read.
            None => crate::simulate::simulate_for_row(&sc),
            Some(exit) => run_to_exit(&sc, exit),
        }));
        match outcome {
            Ok(Ok(traj)) => {
                let s = &traj.summary;
                row.status = s.status.clone();
                row.finals = traj.samples.last().map(|x| x.values());
                row.theta_max = Some(s.theta_max);
                let min =
                    |f: fn(&crate::Sample) -> f64| traj.samples.iter().map(f).reduce(f64::min);
                row.theta_min = min(|x| x.theta);
                row.normal_min = min(|x| x.normal);
                row.negative_normal_fraction = Some(s.negative_normal_fraction);
                row.first_passage = match &self.exit {
                    None => s.first_time_theta_above_half_pi,
                    Some(exit) => traj
                        .samples
                        .iter()
                        .find(|x| exit.hit(&x.values()))
                        .map(|x| x.t),
                };
                row.t_reached = Some(s.t_end);
                row.samples = traj
                    .samples
                    .iter()
                    .map(|x| [x.t, x.theta, x.spin, x.precession])
                    .collect();
            }
            Ok(Err(e)) => row.status = e.to_string(),
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                row.status = format!("panicked: {msg}");
            }
        }
        row
    }

    /// Run the runs `range` (0-based positions) on `threads` threads and
    /// hand each row to `sink` in run order (see [`sweep::run_ordered`]:
    /// memory flat in the number of runs, rows independent of the thread
    /// count). Errors: a range past [`Ensemble::runs`], a bad thread count.
    pub fn run_streaming(
        &self,
        range: Range<usize>,
        threads: Option<usize>,
        sink: &mut dyn FnMut(RunRow) -> bool,
    ) -> Result<bool, Error> {
        if range.end > self.runs || range.start > range.end {
            return Err(Error::invalid(
                "ensemble",
                format!("runs {range:?} requested"),
                format!("within 0..{}", self.runs),
            ));
        }
        sweep::run_ordered(range, threads, &|i| self.run(i), sink)
    }

    /// How many runs the ensemble may run at once within
    /// [`crate::limits::MEMORY_BUDGET`]: at most `threads`. A run keeps
    /// its trajectory ([`crate::limits::run_memory_bytes`]) and its row
    /// (32 bytes per sample for the histograms); up to
    /// [`sweep::window`]`(threads)` rows wait to be written in order; the
    /// command keeps the histograms (twice, while they are written) and 32
    /// bytes per run for the Kaplan–Meier estimate. Error (key
    /// `solver.samples`) if not even one run fits.
    pub fn threads_within_memory(&self, threads: usize) -> Result<usize, Error> {
        let samples = self.scenario.solver.samples as u64;
        let row = std::mem::size_of::<RunRow>() as u64 + 32 * samples;
        let hist = HIST_BYTES_PER_SAMPLE * samples;
        let per_run = crate::limits::run_memory_bytes(&self.scenario.solver) + 9 * row;
        let fixed = 2 * hist + 16 * row + 32 * self.runs as u64;
        crate::limits::fit_threads("solver.samples", threads, per_run, fixed)
    }

    /// The histogram ranges of this ensemble ([`ranges`]).
    pub fn ranges(&self) -> [[f64; 2]; 3] {
        ranges(&self.scenario)
    }

    /// Empty histograms for this ensemble: [`BINS`] bins over [`ranges`] at
    /// each of `solver.samples` sample times.
    pub fn histograms(&self) -> Histograms {
        Histograms::new(self.scenario.solver.samples, self.ranges())
    }

    /// The run positions of `shard` (see [`sweep::shard_range`]).
    pub fn shard_range(&self, shard: Shard) -> Result<Range<usize>, Error> {
        sweep::shard_range(self.runs, shard).map_err(|e| match e {
            Error::Invalid { key, what, range } => Error::Invalid {
                key,
                what: what.replace("sweep", "ensemble").replace("case", "run"),
                range: range.replace("cases", "runs"),
            },
            other => other,
        })
    }

    /// What `shard` of this ensemble covers, for `shard.json`.
    pub fn shard_info(&self, shard: Shard) -> Result<EnsembleShard, Error> {
        let r = self.shard_range(shard)?;
        Ok(EnsembleShard {
            kind: "ensemble".into(),
            fingerprint: self.fingerprint(),
            k: shard.k,
            n: shard.n,
            total_runs: self.runs,
            first_index: r.start,
            end_index: r.end,
            first_run: self.first_run(),
            seed: self.seed(),
            exit: self.exit.as_ref().map(|e| e.to_string()),
            temperature: Some(self.scenario.thermal.temperature),
            checksums: BTreeMap::new(),
        })
    }

    /// A 16-hex-digit hash (FNV-1a) of what defines the output: the
    /// tippetop version, the preset, the scenario text, the `--set`s and
    /// the number of runs.
    pub fn fingerprint(&self) -> String {
        let mut text = String::from("tippetop ensemble 1\n");
        let mut field = |name: &str, value: &str| {
            text.push_str(&format!("{name} {} {value}\n", value.len()));
        };
        field("version", env!("CARGO_PKG_VERSION"));
        field("preset", self.preset.as_deref().unwrap_or("-"));
        match &self.toml_text {
            Some(t) => field("file", t),
            None => field("nofile", ""),
        }
        for s in &self.sets {
            field("set", s);
        }
        field("runs", &self.runs.to_string());
        if let Some(e) = &self.exit {
            field("exit", &e.to_string());
        }
        format!("{:016x}", fnv1a(text.as_bytes()))
    }

    /// How much of an interrupted `ensemble.csv` of the runs from
    /// `first_index` on can be kept: the header (else nothing) and every
    /// complete line that [`check_row`] accepts as the next run (its `run`
    /// and `seed`), up to the first that it does not (a torn last line;
    /// `problem` says why a complete line was refused).
    pub fn complete_prefix(&self, first_index: usize, text: &str) -> Prefix {
        let header = csv_header();
        let mut p = Prefix::default();
        if !text.starts_with(&header) {
            p.problem = Some("not the header");
            return p;
        }
        p.bytes = header.len();
        for line in text[header.len()..].split_inclusive('\n') {
            let index = first_index + p.rows;
            let Some(body) = line.strip_suffix('\n') else {
                break;
            };
            let checked = if index < self.runs {
                check_row(body, self.first_run() + index as u64, self.seed())
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
}

// ---------------------------------------------------------------------------
// ensemble.csv

/// Number of fields of an `ensemble.csv` line.
pub const NCOLS: usize = 3 + COLUMNS.len() + EXTRA_FIELDS.len();

/// The header line of `ensemble.csv` (with its `\n`).
pub fn csv_header() -> String {
    let mut cols: Vec<String> = vec!["run".into(), "seed".into(), "status".into()];
    cols.extend(COLUMNS.iter().map(|c| format!("{c}_final")));
    cols.extend(EXTRA_FIELDS.iter().map(|c| c.to_string()));
    let mut s = cols.join(",");
    s.push('\n');
    s
}

fn opt(x: Option<f64>) -> String {
    x.map(fmt_f64).unwrap_or_default()
}

/// One line of `ensemble.csv` (with its `\n`).
pub fn csv_row(row: &RunRow) -> String {
    let mut f: Vec<String> = vec![
        row.run.to_string(),
        row.seed.to_string(),
        status_field(&row.status),
    ];
    match &row.finals {
        Some(v) => f.extend(v.iter().map(|&x| fmt_f64(x))),
        None => f.extend(std::iter::repeat_n(String::new(), COLUMNS.len())),
    }
    f.extend([
        opt(row.theta_max),
        opt(row.theta_min),
        opt(row.normal_min),
        opt(row.negative_normal_fraction),
        opt(row.first_passage),
        row.censored()
            .map(|c| if c { "1" } else { "0" }.to_string())
            .unwrap_or_default(),
        opt(row.t_reached),
    ]);
    let mut s = f.join(",");
    s.push('\n');
    s
}

/// A line of `ensemble.csv` parsed back.
#[derive(Debug, Clone, PartialEq)]
pub struct ParsedRow {
    /// `thermal.run`.
    pub run: u64,
    /// `thermal.seed`.
    pub seed: u64,
    /// `ok` or the error.
    pub status: String,
    /// The numeric fields after `status` (NaN where empty), in header order.
    pub fields: Vec<f64>,
}

impl ParsedRow {
    /// A numeric column by header name (NaN where empty).
    pub fn get(&self, name: &str) -> Option<f64> {
        let i = COLUMNS
            .iter()
            .map(|c| format!("{c}_final"))
            .chain(EXTRA_FIELDS.iter().map(|c| c.to_string()))
            .position(|c| c == name)?;
        self.fields.get(i).copied()
    }
}

/// Split a CSV line into fields (RFC 4180 quotes allowed).
fn split_fields(line: &str) -> Option<Vec<String>> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut chars = line.chars().peekable();
    let mut quoted = false;
    let mut at_start = true;
    while let Some(c) = chars.next() {
        if quoted {
            if c == '"' {
                if chars.peek() == Some(&'"') {
                    chars.next();
                    cur.push('"');
                } else {
                    quoted = false;
                }
            } else {
                cur.push(c);
            }
        } else if c == '"' && at_start {
            quoted = true;
            at_start = false;
        } else if c == ',' {
            out.push(std::mem::take(&mut cur));
            at_start = true;
        } else {
            cur.push(c);
            at_start = false;
        }
    }
    if quoted {
        return None;
    }
    out.push(cur);
    Some(out)
}

/// Check a data line of `ensemble.csv` (without its `\n`) as the row of
/// the run with `thermal.run = run` and `thermal.seed = seed`: [`NCOLS`]
/// fields, that `run` and `seed`, a status as [`csv_row`] writes it (`ok`
/// only with the run's final values), numbers (or empty) after it, and
/// `censored` empty, 0 or 1. `Ok(true)`: a row whose status is not `ok`;
/// `Err`: why not.
pub fn check_row(line: &str, run: u64, seed: u64) -> Result<bool, &'static str> {
    let f = split_fields(line).ok_or("an unterminated quote")?;
    match f.len().cmp(&NCOLS) {
        std::cmp::Ordering::Less => return Err("too few fields"),
        std::cmp::Ordering::Greater => return Err("more fields than the header"),
        std::cmp::Ordering::Equal => {}
    }
    if f[0].parse::<u64>().ok() != Some(run) || f[1].parse::<u64>().ok() != Some(seed) {
        return Err("not the run's run and seed");
    }
    // The raw field as written: quoted iff it holds a comma or a quote.
    let raw = field_at(line, 2);
    if f[2].is_empty() || raw != Some(status_field(&f[2])) {
        return Err("a malformed status");
    }
    let censored = 3 + COLUMNS.len() + 5;
    for (i, v) in f.iter().enumerate().skip(3) {
        let ok = if i == censored {
            matches!(v.as_str(), "" | "0" | "1")
        } else {
            v.is_empty() || v.parse::<f64>().is_ok()
        };
        if !ok {
            return Err("a field that is not a number");
        }
    }
    if f[2] == "ok" && (f[3].is_empty() || f[NCOLS - 1].is_empty()) {
        return Err("status ok without results");
    }
    Ok(f[2] != "ok")
}

/// The raw text of field `i` of a CSV line whose fields before `i` are
/// unquoted (the run and the seed, before the status): up to the closing
/// quote of a quoted field, else up to the next comma.
fn field_at(line: &str, i: usize) -> Option<String> {
    let mut rest = line;
    for _ in 0..i {
        rest = rest.split_once(',')?.1;
    }
    if let Some(inner) = rest.strip_prefix('"') {
        let mut end = None;
        let mut chars = inner.char_indices().peekable();
        while let Some((k, c)) = chars.next() {
            if c == '"' {
                if chars.peek().is_some_and(|&(_, d)| d == '"') {
                    chars.next();
                } else {
                    end = Some(k + 2);
                    break;
                }
            }
        }
        Some(rest[..end?].to_string())
    } else {
        Some(rest.split(',').next().unwrap_or("").to_string())
    }
}

/// Parse a data line of `ensemble.csv` (without its `\n`); `None` if it
/// does not have the layout of [`csv_row`].
pub fn parse_row(line: &str) -> Option<ParsedRow> {
    let f = split_fields(line)?;
    if f.len() != NCOLS {
        return None;
    }
    let run = f[0].parse().ok()?;
    let seed = f[1].parse().ok()?;
    let mut fields = Vec::with_capacity(NCOLS - 3);
    for s in &f[3..] {
        fields.push(if s.is_empty() {
            f64::NAN
        } else {
            s.parse::<f64>().ok()?
        });
    }
    Some(ParsedRow {
        run,
        seed,
        status: f[2].clone(),
        fields,
    })
}

/// Join shard outputs (each an [`EnsembleShard`] and its `ensemble.csv`
/// text, in any order) into the `ensemble.csv` of the whole ensemble, byte
/// for byte what a one-shot run writes. Checks that the shards are of one
/// ensemble, that each CSV has the header and the runs it should, and that
/// the shards tile the runs with no gap and no overlap. Errors:
/// [`Error::Invalid`] with key `merge`.
pub fn merge_csv(shards: &[(EnsembleShard, String)]) -> Result<String, Error> {
    let err = |what: String, range: &str| Error::invalid("merge", what, range.into());
    let Some((first, _)) = shards.first() else {
        return Err(err("no shards given".into(), "one or more shard outputs"));
    };
    let as_written = "ensemble.csv as written by tippetop ensemble";
    let header = csv_header();
    for (info, text) in shards {
        let name = format!(
            "shard {}/{} (runs {}..{})",
            info.k, info.n, info.first_index, info.end_index
        );
        if info.fingerprint != first.fingerprint
            || info.total_runs != first.total_runs
            || info.first_run != first.first_run
            || info.seed != first.seed
        {
            return Err(err(
                format!(
                    "{name} is of another ensemble (fingerprint {} with {} runs, not {} with {})",
                    info.fingerprint, info.total_runs, first.fingerprint, first.total_runs
                ),
                "all shards from one ensemble: same scenario, --set, --runs, same tippetop",
            ));
        }
        if info.first_index > info.end_index || info.end_index > info.total_runs {
            return Err(err(
                format!(
                    "{name} does not fit an ensemble of {} runs",
                    info.total_runs
                ),
                "shard.json as written by tippetop ensemble",
            ));
        }
        let Some(body) = text.strip_prefix(header.as_str()) else {
            return Err(err(
                format!("{name}: ensemble.csv does not start with the ensemble header"),
                as_written,
            ));
        };
        let want = info.end_index - info.first_index;
        let lines: Vec<&str> = body.split_inclusive('\n').collect();
        if lines.len() != want {
            return Err(err(
                format!("{name}: ensemble.csv has {} rows, not {want}", lines.len()),
                as_written,
            ));
        }
        for (j, line) in lines.iter().enumerate() {
            let run = info.first_run + (info.first_index + j) as u64;
            let Some(line) = line.strip_suffix('\n') else {
                return Err(err(
                    format!(
                        "{name}: ensemble.csv ends in the middle of its last row (line {}, no \
                         line end)",
                        j + 2
                    ),
                    as_written,
                ));
            };
            if let Err(why) = check_row(line, run, info.seed) {
                return Err(err(
                    format!(
                        "{name}: line {} of ensemble.csv is not run {run} ({why})",
                        j + 2
                    ),
                    as_written,
                ));
            }
        }
    }
    let mut order: Vec<&(EnsembleShard, String)> = shards.iter().collect();
    order.sort_by_key(|(i, _)| (i.first_index, i.end_index));
    let total = first.total_runs;
    let complete = "shards that cover every run exactly once";
    let mut cursor = 0;
    let mut out = header.clone();
    for (info, text) in order {
        if info.first_index != cursor {
            return Err(err(
                if info.first_index > cursor {
                    format!("runs {cursor}..{} of {total} are missing", info.first_index)
                } else {
                    format!(
                        "shard {}/{} (runs {}..{}) overlaps runs before {cursor}",
                        info.k, info.n, info.first_index, info.end_index
                    )
                },
                complete,
            ));
        }
        out.push_str(&text[header.len()..]);
        cursor = info.end_index;
    }
    if cursor != total {
        return Err(err(
            format!("runs {cursor}..{total} of {total} are missing"),
            complete,
        ));
    }
    Ok(out)
}

// ---------------------------------------------------------------------------
// Histograms and quantiles.

/// Fixed-bin histograms of θ, ω and Ω at every sample time, in integer
/// counts. For sample `i` and quantity `q` the slots are
/// `[underflow, bin 0, ..., bin B-1, overflow, missing]`, bin `j` covering
/// `[lower + j w, lower + (j + 1) w)` with `w = (upper - lower) / B` (the
/// last bin includes `upper`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Histograms {
    /// Number of bins `B` between the range's ends.
    pub bins: usize,
    /// `[lower, upper]` per quantity ([`QUANTITIES`] order, their units).
    pub ranges: [[f64; 2]; 3],
    /// The sample times \[s\] (`None` until a run has reached that sample).
    pub times: Vec<Option<f64>>,
    /// The counts, `times.len() * 3 * (B + 3)` of them.
    pub counts: Vec<u64>,
}

impl Histograms {
    /// Empty histograms with [`BINS`] bins at `samples` sample times.
    pub fn new(samples: usize, ranges: [[f64; 2]; 3]) -> Histograms {
        Histograms {
            bins: BINS,
            ranges,
            times: vec![None; samples],
            counts: vec![0; samples * 3 * (BINS + 3)],
        }
    }

    fn width(&self) -> usize {
        self.bins + 3
    }

    /// The slots of sample `i`, quantity `q`.
    pub fn slots(&self, i: usize, q: usize) -> &[u64] {
        let w = self.width();
        let at = (i * 3 + q) * w;
        &self.counts[at..at + w]
    }

    /// The slot (0 underflow, `1..=B` the bins, `B + 1` overflow, `B + 2`
    /// missing) of the value `x` of quantity `q`.
    pub fn slot(&self, q: usize, x: f64) -> usize {
        let [lo, hi] = self.ranges[q];
        let b = self.bins;
        if x.is_nan() {
            b + 2
        } else if x < lo {
            0
        } else if x > hi {
            b + 1
        } else {
            let j = ((x - lo) / (hi - lo) * b as f64).floor();
            1 + (j.max(0.0) as usize).min(b - 1)
        }
    }

    /// Count one run: its output rows' θ, ω, Ω; samples it did not reach
    /// count as missing.
    pub fn add(&mut self, row: &RunRow) {
        let w = self.width();
        for i in 0..self.times.len() {
            for q in 0..3 {
                let s = match row.samples.get(i) {
                    Some(v) => self.slot(q, v[q + 1]),
                    None => self.bins + 2,
                };
                self.counts[(i * 3 + q) * w + s] += 1;
            }
            if let Some(v) = row.samples.get(i) {
                self.times[i].get_or_insert(v[0]);
            }
        }
    }

    /// Add the counts of `other` (another shard of the same ensemble).
    /// Error (key `merge`) if the shapes or the ranges differ.
    pub fn merge(&mut self, other: &Histograms) -> Result<(), Error> {
        if self.bins != other.bins
            || self.ranges != other.ranges
            || self.times.len() != other.times.len()
            || self.counts.len() != other.counts.len()
        {
            return Err(Error::invalid(
                "merge",
                "histograms.csv of the shards have different bins, ranges or sample times".into(),
                "all shards from one ensemble".into(),
            ));
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        for (a, b) in self.times.iter_mut().zip(&other.times) {
            if a.is_none() {
                *a = *b;
            }
        }
        Ok(())
    }

    /// The CSV header of `histograms.csv` (with its `\n`).
    pub fn csv_header(&self) -> String {
        let mut cols: Vec<String> = ["t", "quantity", "lower", "upper", "underflow"]
            .iter()
            .map(|s| s.to_string())
            .collect();
        cols.extend((0..self.bins).map(|j| format!("bin{j}")));
        cols.extend(["overflow".to_string(), "missing".to_string()]);
        let mut s = cols.join(",");
        s.push('\n');
        s
    }

    /// `histograms.csv`: one line per sample time and quantity: `t`
    /// \[s\], the quantity, its range `lower, upper`, then the counts.
    pub fn csv(&self) -> String {
        let mut s = self.csv_header();
        for (i, t) in self.times.iter().enumerate() {
            for (q, name) in QUANTITIES.iter().enumerate() {
                let mut f = vec![
                    opt(*t),
                    name.to_string(),
                    fmt_f64(self.ranges[q][0]),
                    fmt_f64(self.ranges[q][1]),
                ];
                f.extend(self.slots(i, q).iter().map(|c| c.to_string()));
                s.push_str(&f.join(","));
                s.push('\n');
            }
        }
        s
    }

    /// Parse a `histograms.csv` written by [`Histograms::csv`].
    pub fn parse_csv(text: &str) -> Result<Histograms, Error> {
        let bad = |what: String| {
            Error::invalid(
                "histograms.csv",
                what,
                "a file written by tippetop ensemble or merge".into(),
            )
        };
        let mut lines = text.lines();
        let header = lines.next().unwrap_or("");
        let ncols = header.split(',').count();
        if ncols < 8 {
            return Err(bad("unexpected header".into()));
        }
        let bins = ncols - 7;
        let mut h = Histograms {
            bins,
            ranges: [[0.0; 2]; 3],
            times: Vec::new(),
            counts: Vec::new(),
        };
        if format!("{header}\n") != h.csv_header() {
            return Err(bad("unexpected header".into()));
        }
        let num = |s: &str, j: usize| {
            s.parse::<f64>()
                .map_err(|_| bad(format!("line {}: {s:?} is not a number", j + 2)))
        };
        for (j, line) in lines.enumerate() {
            let f: Vec<&str> = line.split(',').collect();
            let q = j % 3;
            if f.len() != ncols || f[1] != QUANTITIES[q] {
                return Err(bad(format!(
                    "line {} is not a {} row",
                    j + 2,
                    QUANTITIES[q]
                )));
            }
            let range = [num(f[2], j)?, num(f[3], j)?];
            if j < 3 {
                h.ranges[q] = range;
            } else if h.ranges[q] != range {
                return Err(bad(format!("line {}: the range changes", j + 2)));
            }
            if q == 0 {
                h.times.push(if f[0].is_empty() {
                    None
                } else {
                    Some(num(f[0], j)?)
                });
            }
            for c in &f[4..] {
                h.counts.push(
                    c.parse::<u64>()
                        .map_err(|_| bad(format!("line {}: {c:?} is not a count", j + 2)))?,
                );
            }
        }
        if h.counts.len() != h.times.len() * 3 * h.width() {
            return Err(bad("the last sample time is incomplete".into()));
        }
        Ok(h)
    }

    /// Quantile `p` (a fraction in `[0, 1]`) of quantity `q` at sample `i`
    /// (see [`quantile`]), with the number of values counted.
    pub fn quantile(&self, i: usize, q: usize, p: f64) -> Option<f64> {
        let [lo, hi] = self.ranges[q];
        quantile(self.slots(i, q), lo, hi, p)
    }

    /// `quantiles.csv`: per sample time and quantity, `t` \[s\], the
    /// quantity, `n` (values counted, missing ones excluded), then the
    /// [`QUANTILES`] (the quantity's units; empty when it lies in the under-
    /// or overflow, i.e. outside the histogram's range, or `n = 0`).
    pub fn quantiles_csv(&self) -> String {
        let mut s = String::from("t,quantity,n,q05,q25,q50,q75,q95\n");
        for (i, t) in self.times.iter().enumerate() {
            for (q, name) in QUANTITIES.iter().enumerate() {
                let sl = self.slots(i, q);
                let n: u64 = sl[..sl.len() - 1].iter().sum();
                let mut f = vec![opt(*t), name.to_string(), n.to_string()];
                f.extend(QUANTILES.iter().map(|&p| opt(self.quantile(i, q, p))));
                s.push_str(&f.join(","));
                s.push('\n');
            }
        }
        s
    }
}

/// Quantile `p` of a histogram given as slots `[underflow, bin 0, ..., bin
/// B-1, overflow, missing]` over `[lower, upper]` (missing values left
/// out): with `n` counted values, the value of rank `r = p n`, the values
/// of a bin taken as spread evenly over it (linear interpolation of the
/// cumulative count). `None` if `n = 0`, or if the rank falls in the
/// underflow or the overflow (the quantile is then outside the range and
/// unknown).
pub fn quantile(slots: &[u64], lower: f64, upper: f64, p: f64) -> Option<f64> {
    if slots.len() < 4 || !(0.0..=1.0).contains(&p) {
        return None;
    }
    let b = slots.len() - 3;
    let under = slots[0];
    let n: u64 = slots[..b + 2].iter().sum();
    if n == 0 {
        return None;
    }
    let r = p * n as f64;
    if under > 0 && r <= under as f64 {
        return None;
    }
    let w = (upper - lower) / b as f64;
    let mut before = under as f64;
    for (j, &c) in slots[1..=b].iter().enumerate() {
        let c = c as f64;
        if c > 0.0 && before + c >= r {
            let frac = ((r - before) / c).clamp(0.0, 1.0);
            return Some(lower + w * (j as f64 + frac));
        }
        before += c;
    }
    None
}

// ---------------------------------------------------------------------------
// Statistics.

/// Running mean and variance (Welford), fed in run order.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct MeanAcc {
    /// Values added.
    pub n: u64,
    mean: f64,
    m2: f64,
}

impl MeanAcc {
    /// Add a value (NaN is skipped).
    pub fn push(&mut self, x: f64) {
        if x.is_nan() {
            return;
        }
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    /// The mean with its 95 % confidence interval.
    pub fn result(&self) -> MeanCi {
        let n = self.n;
        let mean = (n > 0).then_some(self.mean);
        let std = (n > 1).then(|| (self.m2 / (n - 1) as f64).sqrt());
        let half = std.map(|s| Z95 * s / (n as f64).sqrt());
        MeanCi {
            n,
            mean,
            std,
            ci95: half.and_then(|h| mean.map(|m| [m - h, m + h])),
        }
    }
}

/// A mean with its 95 % confidence interval `mean ± 1.96 s / sqrt(n)`, `s`
/// the sample standard deviation (normal approximation: good for `n` of a
/// few tens and more).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct MeanCi {
    /// Number of values.
    pub n: u64,
    /// The mean (`None` for `n = 0`), in the values' units.
    pub mean: Option<f64>,
    /// Sample standard deviation (`n − 1` in the denominator; `None` for
    /// `n < 2`).
    pub std: Option<f64>,
    /// `[mean − 1.96 s/sqrt(n), mean + 1.96 s/sqrt(n)]` (`None` for `n < 2`).
    pub ci95: Option<[f64; 2]>,
}

/// The Kaplan–Meier median of first-passage times with right censoring:
/// each entry is `(time, observed)`, `time` \[s\] the passage time if
/// `observed`, else the censoring time (the run ended without a passage).
/// The survival estimate `S(t) = Π (1 − d_i / n_i)` over the distinct
/// passage times `t_i <= t` (`d_i` passages at `t_i`, `n_i` runs still at
/// risk just before: a run censored at `t_i` counts as at risk at `t_i`).
/// The median is the smallest passage time with `S <= 1/2`; `None` if `S`
/// stays above 1/2 (more than half the runs censored before passing).
pub fn kaplan_meier_median(entries: &[(f64, bool)]) -> Option<f64> {
    let mut v: Vec<(f64, bool)> = entries.iter().copied().filter(|e| !e.0.is_nan()).collect();
    // Time order; at equal times passages before censorings.
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(b.1.cmp(&a.1)));
    let mut at_risk = v.len();
    let mut s = 1.0;
    let mut i = 0;
    while i < v.len() {
        let t = v[i].0;
        let mut d = 0;
        let mut gone = 0;
        while i < v.len() && v[i].0 == t {
            d += usize::from(v[i].1);
            gone += 1;
            i += 1;
        }
        if d > 0 {
            s *= (at_risk - d) as f64 / at_risk as f64;
            if s <= 0.5 {
                return Some(t);
            }
        }
        at_risk -= gone;
    }
    None
}

/// First passages θ > π/2 over an ensemble.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FirstPassage {
    /// Runs with a passage.
    pub observed: u64,
    /// Runs without a passage in the time they reached.
    pub censored: u64,
    /// `censored / (observed + censored)` (`None` without runs).
    pub censored_fraction: Option<f64>,
    /// Kaplan–Meier median of the passage time \[s\]
    /// ([`kaplan_meier_median`]).
    pub kaplan_meier_median: Option<f64>,
    /// Mean passage time of the observed passages only \[s\] (biased low
    /// when runs are censored).
    pub mean_observed: MeanCi,
    /// The escape rate if passages are a Poisson process (escape over a
    /// barrier of many kT after the top has settled in its well, Kramers):
    /// the maximum-likelihood estimate with right censoring,
    /// `k = passages / exposure` (exposure: the sum of the passage times
    /// and of the censoring times) \[1/s\]. `None` without a passage.
    pub escape_rate: Option<EscapeRate>,
}

/// An escape rate with its 95 % confidence interval ([`escape_rate`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EscapeRate {
    /// Passages observed.
    pub passages: u64,
    /// Total time at risk \[s\].
    pub exposure: f64,
    /// `passages / exposure` \[1/s\].
    pub rate: f64,
    /// Standard error of `ln rate`: `1/sqrt(passages)`.
    pub ln_rate_se: f64,
    /// `rate · exp(∓1.96/sqrt(passages))` \[1/s\] (normal on the log scale).
    pub ci95: [f64; 2],
    /// The mean residence time `1/rate` \[s\].
    pub mean_time: f64,
}

/// The maximum-likelihood escape rate of an exponential law from `entries`
/// `(time, observed)` (as for [`kaplan_meier_median`]): `d / Σ time`, with
/// `ln` rate's standard error `1/sqrt(d)` (Fisher information). `None` for
/// `d = 0` or no exposure.
pub fn escape_rate(entries: &[(f64, bool)]) -> Option<EscapeRate> {
    let d = entries.iter().filter(|e| e.1 && !e.0.is_nan()).count() as u64;
    let exposure: f64 = entries.iter().filter(|e| !e.0.is_nan()).map(|e| e.0).sum();
    if d == 0 || exposure <= 0.0 {
        return None;
    }
    let rate = d as f64 / exposure;
    let se = 1.0 / (d as f64).sqrt();
    Some(EscapeRate {
        passages: d,
        exposure,
        rate,
        ln_rate_se: se,
        ci95: [rate * (-Z95 * se).exp(), rate * (Z95 * se).exp()],
        mean_time: 1.0 / rate,
    })
}

/// The ensemble's statistics (the core of `summary.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnsembleStats {
    /// Rows in `ensemble.csv`.
    pub runs: u64,
    /// Rows with status `ok`.
    pub ok: u64,
    /// Rows with another status (failed runs).
    pub failed: u64,
    /// θ at the end \[rad\], over the `ok` runs.
    pub theta_final: MeanCi,
    /// ω at the end \[rad/s\], over the `ok` runs.
    pub omega_final: MeanCi,
    /// Ω at the end \[rad/s\], over the `ok` runs.
    #[serde(rename = "Omega_final")]
    pub precession_final: MeanCi,
    /// Energy at the end \[J\], over the `ok` runs.
    pub energy_final: MeanCi,
    /// First time θ > π/2, over every run that ran (a failed run is
    /// censored at the time it reached).
    pub first_passage: FirstPassage,
}

impl EnsembleStats {
    /// From an `ensemble.csv`, in its row order (so the same file gives
    /// the same bits). Error: a line that is not an ensemble row.
    pub fn from_csv(text: &str) -> Result<EnsembleStats, Error> {
        let mut lines = text.lines();
        if lines.next().map(|h| format!("{h}\n")) != Some(csv_header()) {
            return Err(bad_csv("unexpected header".into()));
        }
        let mut acc = StatsAcc::default();
        for (j, line) in lines.enumerate() {
            acc.push_line(j + 2, line)?;
        }
        Ok(acc.finish())
    }
}

fn bad_csv(what: String) -> Error {
    Error::invalid(
        "ensemble.csv",
        what,
        "a file written by tippetop ensemble or merge".into(),
    )
}

/// [`EnsembleStats`] accumulated row by row (in run order), for an
/// `ensemble.csv` read line by line. Holds 16 bytes per run (the passage
/// or censoring times, for the Kaplan–Meier estimate), nothing else per run.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StatsAcc {
    runs: u64,
    ok: u64,
    acc: [MeanAcc; 4],
    passage: MeanAcc,
    entries: Vec<(f64, bool)>,
}

impl StatsAcc {
    /// Add data line `line` (number `lineno` in the file, for the error)
    /// of `ensemble.csv`. Error: not an ensemble row.
    pub fn push_line(&mut self, lineno: usize, line: &str) -> Result<(), Error> {
        let r = parse_row(line).ok_or_else(|| bad_csv(format!("line {lineno} is not a row")))?;
        self.push(&r);
        Ok(())
    }

    /// Add a parsed row.
    pub fn push(&mut self, r: &ParsedRow) {
        self.runs += 1;
        let get = |n: &str| r.get(n).unwrap_or(f64::NAN);
        if r.status == "ok" {
            self.ok += 1;
            for (a, n) in self.acc.iter_mut().zip([
                "theta_final",
                "omega_final",
                "Omega_final",
                "energy_final",
            ]) {
                a.push(get(n));
            }
        }
        let (fp, reached) = (get("first_passage_time"), get("t_reached"));
        if !fp.is_nan() {
            self.entries.push((fp, true));
            self.passage.push(fp);
        } else if !reached.is_nan() {
            self.entries.push((reached, false));
        }
    }

    /// The statistics of the rows added.
    pub fn finish(&self) -> EnsembleStats {
        let observed = self.passage.n;
        let n = self.entries.len() as u64;
        let censored = n - observed;
        EnsembleStats {
            runs: self.runs,
            ok: self.ok,
            failed: self.runs - self.ok,
            theta_final: self.acc[0].result(),
            omega_final: self.acc[1].result(),
            precession_final: self.acc[2].result(),
            energy_final: self.acc[3].result(),
            first_passage: FirstPassage {
                observed,
                censored,
                censored_fraction: (n > 0).then(|| censored as f64 / n as f64),
                kaplan_meier_median: kaplan_meier_median(&self.entries),
                mean_observed: self.passage.result(),
                escape_rate: escape_rate(&self.entries),
            },
        }
    }
}
