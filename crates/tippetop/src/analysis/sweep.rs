//! Parameter sweeps: a grid of scenarios run in parallel, one CSV row per
//! case, split into shards that run anywhere and merge back byte for byte.
//!
//! A [`Sweep`] is a base scenario (preset, TOML text and `--set` overrides, as
//! for [`Scenario::load`]) and one or more [`Axis`]es, each varying one
//! scenario key over evenly spaced (or log-spaced) values. The cases form a
//! grid in row-major order: the first axis varies slowest. Each case is the
//! base scenario with `KEY=VALUE` appended to the `--set` list for every
//! axis (so an axis overrides a `--set` of the same key), with the value
//! written in Rust's shortest round-trip form, so the scenario gets exactly
//! the grid value.
//!
//! A case whose scenario is invalid (e.g. a swept offset reaching the radius)
//! or whose run fails part-way does not stop the sweep: its row carries the
//! error text in `status` (the summary fields are empty for an invalid
//! scenario, and those of the run up to the failure for a failed run).
//!
//! # Determinism
//!
//! The output bytes depend only on the sweep (and the binary that ran it):
//! the rows come back in grid order whatever the thread count
//! ([`Sweep::run_streaming`] delivers each row once all rows before it are
//! done, through a reorder buffer of bounded size), floats are written in the
//! shortest form that parses back to the same `f64`, and there are no timing
//! columns. A sweep cut into [`Shard`]s, run on different machines and
//! joined with [`merge`] gives the same `sweep.csv` as a one-shot run.
//!
//! # CSV layout
//!
//! Header: the varied keys in axis order, then [`FIELDS`], then `status`.
//! One line per case, `\n` line endings, an empty field for a missing value
//! (no summary, or an event that never happened), `status` is `ok` or the
//! error (one line; quoted per RFC 4180 when it contains a comma or a quote).
//!
//! ```no_run
//! use tippetop::analysis::sweep::{Axis, Sweep, csv};
//! let sweep = Sweep {
//!     preset: Some("classical".into()),
//!     toml_text: None,
//!     sets: vec!["solver.t_end=1".into()],
//!     axes: vec![Axis::parse("top.offset=0.001:0.004:4").unwrap()],
//! };
//! sweep.validate().unwrap();
//! let rows = sweep.run(0..sweep.total(), None, &|| {}).unwrap();
//! print!("{}", csv(&sweep.axes, &rows));
//! ```

use std::collections::BTreeMap;
use std::ops::Range;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Condvar, Mutex, mpsc};

use serde::{Deserialize, Serialize};

use crate::{Error, Scenario, Summary};

/// The summary columns of `sweep.csv`, after the varied keys and before
/// `status`. Units: angles \[rad\], rates \[rad/s\], times \[s\], energy \[J\];
/// the drift and the fractions are dimensionless; `steps` (accepted steps)
/// and `rhs_evaluations` are counts.
pub const FIELDS: [&str; 12] = [
    "theta_final",
    "theta_max",
    "omega_final",
    "Omega_final",
    "first_time_theta_above_half_pi",
    "contact_lost_at",
    "negative_normal_fraction",
    "rolling_fraction",
    "J_max_rel_drift",
    "energy_final",
    "steps",
    "rhs_evaluations",
];

/// Largest number of cases in one sweep.
pub const MAX_CASES: usize = 1_000_000_000;

/// Largest thread count of a sweep. The work is CPU-bound, so threads beyond
/// the cores only add start-up time and memory (each holds a case in
/// flight, and [`window`] grows with the count); 20 000 threads took
/// minutes just to start.
pub const MAX_THREADS: usize = 1024;

/// The thread count a sweep runs on: `requested`, or without it
/// `RAYON_NUM_THREADS` if set to a positive number, else one per core (as
/// reported by the OS), at most [`MAX_THREADS`]. Error: a requested count of
/// 0 or above [`MAX_THREADS`] (key `--threads`).
pub fn threads(requested: Option<usize>) -> Result<usize, Error> {
    match requested {
        Some(t) if (1..=MAX_THREADS).contains(&t) => Ok(t),
        Some(t) => Err(Error::invalid(
            "--threads",
            format!("{t} threads"),
            format!("1 to {MAX_THREADS}; more threads than cores only add overhead"),
        )),
        None => {
            let env = std::env::var("RAYON_NUM_THREADS")
                .ok()
                .and_then(|v| v.trim().parse::<usize>().ok())
                .filter(|&t| t > 0);
            let t =
                env.unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
            Ok(t.clamp(1, MAX_THREADS))
        }
    }
}

/// How far past the next row to deliver [`Sweep::run_streaming`] may start
/// a case on `threads` threads: `8 * threads + 16` cases, so the rows held
/// at once stay a few times the thread count however large the sweep.
pub fn window(threads: usize) -> usize {
    8 * threads + 16
}

/// How many cases [`Sweep::validate`] tries to load, at most, when looking
/// for one valid case.
const VALIDATE_PROBES: usize = 4096;

const VARY_SYNTAX: &str = "KEY=FROM:TO:N or KEY=FROM:TO:N:log, e.g. top.offset=0.001:0.004:4";

// ---------------------------------------------------------------------------
// Axes.

/// One varied scenario key: `n` values from `from` to `to` (both included),
/// evenly spaced, or geometrically spaced with `log`; or, with `given`
/// (made by [`Axis::of_values`]), exactly the values listed. The values have the
/// key's units (e.g. \[m\] for `top.offset`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Axis {
    /// Scenario key as in `--set`, e.g. `top.inertia_axial` or `force.0.hx`.
    pub key: String,
    /// First value (in the key's units).
    pub from: f64,
    /// Last value (in the key's units).
    pub to: f64,
    /// Number of values, >= 1.
    pub n: usize,
    /// Geometric spacing (`from` and `to` must then be > 0).
    pub log: bool,
    /// The values as given (`None` for the CLI's `--vary`, whose values
    /// `from`, `to`, `n`, `log` define); with them, `from` and `to` are the
    /// first and last, `n` their number and `log` false. Not written to
    /// `shard.json` when `None`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub given: Option<Vec<f64>>,
}

impl Axis {
    /// Parse `KEY=FROM:TO:N` or `KEY=FROM:TO:N:log` (the CLI's `--vary`).
    /// The key is checked against the scenario later, by [`Sweep::validate`];
    /// here only the syntax and the ranges of FROM, TO and N.
    pub fn parse(spec: &str) -> Result<Axis, Error> {
        let bad = |what: String| Error::invalid("--vary", what, VARY_SYNTAX.into());
        let Some((key, range)) = spec.split_once('=') else {
            return Err(bad(format!("{spec:?} has no '='")));
        };
        let key = key.trim();
        if key.is_empty() {
            return Err(bad(format!("{spec:?} has no key")));
        }
        let parts: Vec<&str> = range.split(':').map(str::trim).collect();
        let log = match parts.as_slice() {
            [_, _, _] => false,
            [_, _, _, "log"] => true,
            [_, _, _, other] => {
                return Err(Error::invalid(
                    key,
                    format!("unknown spacing {other:?} in --vary"),
                    "nothing for even spacing, or :log".into(),
                ));
            }
            _ => {
                return Err(Error::invalid(
                    key,
                    format!("{range:?} is not FROM:TO:N[:log]"),
                    VARY_SYNTAX.into(),
                ));
            }
        };
        let num = |s: &str, what: &str| {
            s.parse::<f64>().map_err(|_| {
                Error::invalid(
                    key,
                    format!("{what} {s:?} is not a number in --vary"),
                    "a finite number, e.g. 0.5 or 1e-44".into(),
                )
            })
        };
        let from = num(parts[0], "FROM")?;
        let to = num(parts[1], "TO")?;
        let n = parts[2].parse::<usize>().map_err(|_| {
            Error::invalid(
                key,
                format!("N {:?} is not a whole number in --vary", parts[2]),
                "N >= 1".into(),
            )
        })?;
        let axis = Axis {
            key: key.to_string(),
            from,
            to,
            n,
            log,
            given: None,
        };
        axis.check()?;
        Ok(axis)
    }

    /// An axis of exactly `values`, in the order given (the key's units),
    /// e.g. from a list in Python. Error (naming `key`): no values, or one
    /// that is not finite. The scenario checks each value when a case loads.
    pub fn of_values(key: &str, values: Vec<f64>) -> Result<Axis, Error> {
        let axis = Axis {
            key: key.trim().to_string(),
            from: values.first().copied().unwrap_or(f64::NAN),
            to: values.last().copied().unwrap_or(f64::NAN),
            n: values.len(),
            log: false,
            given: Some(values),
        };
        axis.check()?;
        Ok(axis)
    }

    /// Check the ranges: finite bounds, `n >= 1`, positive bounds with `log`;
    /// for given values, at least one, all finite, and `from`, `to`, `n`
    /// agreeing with them.
    pub fn check(&self) -> Result<(), Error> {
        let key = self.key.as_str();
        if let Some(values) = &self.given {
            if values.is_empty() {
                return Err(Error::invalid(
                    key,
                    "no values given".into(),
                    "one or more finite numbers".into(),
                ));
            }
            if let Some((i, v)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(Error::invalid(
                    key,
                    format!("value {i} = {v} is not allowed"),
                    "finite numbers".into(),
                ));
            }
            let (first, last) = (values[0], values[values.len() - 1]);
            if self.n != values.len()
                || self.log
                || first.to_bits() != self.from.to_bits()
                || last.to_bits() != self.to.to_bits()
            {
                return Err(Error::invalid(
                    key,
                    "from, to, n or log do not match the given values".into(),
                    "an axis made by Axis::of_values".into(),
                ));
            }
            return Ok(());
        }
        for (name, v) in [("FROM", self.from), ("TO", self.to)] {
            if !v.is_finite() {
                return Err(Error::invalid(
                    key,
                    format!("{name} = {v} is not allowed in --vary"),
                    "a finite number".into(),
                ));
            }
        }
        if self.n == 0 {
            return Err(Error::invalid(
                key,
                "N = 0 in --vary".into(),
                "N >= 1".into(),
            ));
        }
        if self.log && !(self.from > 0.0 && self.to > 0.0) {
            return Err(Error::invalid(
                key,
                format!(
                    "log spacing from {:?} to {:?} in --vary",
                    self.from, self.to
                ),
                "FROM > 0 and TO > 0 with :log".into(),
            ));
        }
        Ok(())
    }

    /// Value `i` (0-based, `i < n`): `from + (to - from) i / (n - 1)`, or
    /// `from (to / from)^(i / (n - 1))` with `log`; `from` for `n = 1`. The
    /// first and last values are exactly `from` and `to`. With given values,
    /// the `i`-th of them.
    pub fn value(&self, i: usize) -> f64 {
        if let Some(values) = &self.given {
            return values[i];
        }
        if i == 0 || self.n <= 1 {
            return self.from;
        }
        if i + 1 == self.n {
            return self.to;
        }
        let d = (self.n - 1) as f64;
        if self.log {
            self.from * (self.to / self.from).powf(i as f64 / d)
        } else {
            self.from + (self.to - self.from) * i as f64 / d
        }
    }

    /// All `n` values in order.
    pub fn values(&self) -> Vec<f64> {
        (0..self.n).map(|i| self.value(i)).collect()
    }

    /// The axis as `--vary` text (`KEY=FROM:TO:N[:log]`, floats in shortest
    /// round-trip form); `Axis::parse(&a.spec())` gives `a` back. With given
    /// values, `KEY=[v0, v1, ...]` (which `--vary` does not take).
    pub fn spec(&self) -> String {
        if let Some(values) = &self.given {
            let vs: Vec<String> = values.iter().map(|v| format!("{v:?}")).collect();
            return format!("{}=[{}]", self.key, vs.join(", "));
        }
        format!(
            "{}={:?}:{:?}:{}{}",
            self.key,
            self.from,
            self.to,
            self.n,
            if self.log { ":log" } else { "" }
        )
    }
}

// ---------------------------------------------------------------------------
// Shards.

/// The `k`-th of `n` contiguous blocks of a sweep's cases (`1 <= k <= n`),
/// as in `--shard K/N`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which block, 1-based.
    pub k: usize,
    /// Number of blocks.
    pub n: usize,
}

impl Shard {
    /// The whole sweep as one shard (`1/1`).
    pub const ALL: Shard = Shard { k: 1, n: 1 };

    /// Parse `K/N` (1-based: `1 <= K <= N`).
    pub fn parse(spec: &str) -> Result<Shard, Error> {
        let bad = |what: String| {
            Error::invalid(
                "--shard",
                what,
                "K/N with 1 <= K <= N, e.g. --shard 3/8".into(),
            )
        };
        let Some((k, n)) = spec.split_once('/') else {
            return Err(bad(format!("{spec:?} is not K/N")));
        };
        let (Ok(k), Ok(n)) = (k.trim().parse::<usize>(), n.trim().parse::<usize>()) else {
            return Err(bad(format!("{spec:?} is not K/N with whole numbers")));
        };
        if n == 0 || k == 0 || k > n {
            return Err(bad(format!("{spec:?} is out of range")));
        }
        Ok(Shard { k, n })
    }
}

/// The case indices (0-based, end exclusive) of `shard` in a sweep of `total`
/// cases: `n` contiguous blocks tiling `0..total` in order, whose sizes
/// differ by at most one (the first `total % n` blocks are one longer).
/// Error if `shard.n > total`: every shard has at least one case.
pub fn shard_range(total: usize, shard: Shard) -> Result<Range<usize>, Error> {
    if shard.n == 0 || shard.k == 0 || shard.k > shard.n {
        return Err(Error::invalid(
            "--shard",
            format!("{}/{} is out of range", shard.k, shard.n),
            "K/N with 1 <= K <= N".into(),
        ));
    }
    if shard.n > total {
        return Err(Error::invalid(
            "--shard",
            format!(
                "{} shards for a sweep of {total} case{}",
                shard.n,
                if total == 1 { "" } else { "s" }
            ),
            format!("N <= {total}, the number of cases"),
        ));
    }
    let base = total / shard.n;
    let rem = total % shard.n;
    let i = shard.k - 1;
    let start = i * base + i.min(rem);
    let len = base + usize::from(i < rem);
    Ok(start..start + len)
}

/// What a shard covers, written beside its CSV as `shard.json`; [`merge`]
/// checks a set of them against each other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardInfo {
    /// [`Sweep::fingerprint`] of the sweep the shard belongs to.
    pub fingerprint: String,
    /// Which shard, 1-based.
    pub k: usize,
    /// Number of shards the sweep was cut into.
    pub n: usize,
    /// Number of cases of the whole sweep.
    pub total_cases: usize,
    /// First case of the shard (0-based, grid order).
    pub first_index: usize,
    /// One past the last case of the shard.
    pub end_index: usize,
    /// The sweep's axes.
    pub axes: Vec<Axis>,
    /// The checksums of the files the shard's output holds (e.g.
    /// `sweep.csv`): file name to `fnv1a64:` and the 16 hex digits of the
    /// FNV-1a 64 hash of its bytes; `tippetop merge` checks them. Empty
    /// (and not written) in the partial `shard.json` of a running sweep.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub checksums: BTreeMap<String, String>,
}

// ---------------------------------------------------------------------------
// The sweep.

/// A grid of scenarios: a base (as for [`Scenario::load`]) and the axes.
#[derive(Debug, Clone, PartialEq)]
pub struct Sweep {
    /// Preset name (`--preset`), if any.
    pub preset: Option<String>,
    /// Scenario file contents (TOML), if any.
    pub toml_text: Option<String>,
    /// `--set TABLE.KEY=VALUE` overrides, applied before the axes' values.
    pub sets: Vec<String>,
    /// The varied keys; the first varies slowest.
    pub axes: Vec<Axis>,
}

/// One grid point.
#[derive(Debug, Clone, PartialEq)]
pub struct Case {
    /// Position in grid order (0-based).
    pub index: usize,
    /// One value per axis, in axis order (the keys' units).
    pub values: Vec<f64>,
}

/// What [`Sweep::complete_prefix`] keeps of an interrupted `sweep.csv`.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Prefix {
    /// Complete data rows kept (cases `first_index..first_index + rows`).
    pub rows: usize,
    /// Bytes kept: the header and those rows (0: not even the header).
    pub bytes: usize,
    /// How many of the kept rows have a status other than `ok`.
    pub failed: usize,
    /// Why the first line not kept was refused, if it was a complete line
    /// (`None`: the text ended, or with a torn last line).
    pub problem: Option<&'static str>,
}

/// The result of one case.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// Position in grid order (0-based).
    pub index: usize,
    /// One value per axis, in axis order (the keys' units).
    pub values: Vec<f64>,
    /// The run's summary; `None` if the case's scenario was invalid.
    pub summary: Option<Summary>,
    /// `"ok"`, or the error (invalid scenario, or the run's failure).
    pub status: String,
}

impl Sweep {
    /// Number of cases: the product of the axes' `n` (1 without axes);
    /// saturates at `usize::MAX` ([`Sweep::validate`] rejects more than
    /// [`MAX_CASES`]).
    pub fn total(&self) -> usize {
        self.axes
            .iter()
            .try_fold(1usize, |acc, a| acc.checked_mul(a.n))
            .unwrap_or(usize::MAX)
    }

    /// Case `index` (grid order, the first axis slowest; `index < total()`).
    pub fn case(&self, index: usize) -> Case {
        let mut values = vec![0.0; self.axes.len()];
        let mut rest = index;
        for (slot, axis) in values.iter_mut().zip(&self.axes).rev() {
            let n = axis.n.max(1);
            *slot = axis.value(rest % n);
            rest /= n;
        }
        Case { index, values }
    }

    /// Every case in grid order.
    pub fn cases(&self) -> Vec<Case> {
        (0..self.total()).map(|i| self.case(i)).collect()
    }

    /// The `--set` list of a case: the sweep's own, then `KEY=VALUE` per axis
    /// (values in shortest round-trip form, so the scenario gets them exactly).
    pub fn case_sets(&self, case: &Case) -> Vec<String> {
        let mut sets = self.sets.clone();
        for (axis, v) in self.axes.iter().zip(&case.values) {
            sets.push(format!("{}={v:?}", axis.key));
        }
        sets
    }

    /// The scenario of a case.
    pub fn load_case(&self, case: &Case) -> Result<Scenario, Error> {
        Scenario::load(
            self.preset.as_deref(),
            self.toml_text.as_deref(),
            &self.case_sets(case),
        )
    }

    /// Check the sweep before running anything: each axis's ranges, no key
    /// varied twice, at most [`MAX_CASES`] cases, and at least one case
    /// whose scenario loads (so the base scenario, the `--set`s and every
    /// varied key are valid). The cases tried are the first, the last and up
    /// to 4096 spread over the grid; if none loads, the first case's error is
    /// returned (e.g. `top.foo: unknown key (...)`). Cases that do not load
    /// in a sweep that passes are reported per row by [`Sweep::run`].
    pub fn validate(&self) -> Result<(), Error> {
        self.validate_with(&|case| self.load_case(case).map(|_| ()))
    }

    /// [`Sweep::validate`] with another loader of a case (`load(case)`:
    /// `Ok` iff the case's input is valid), e.g. a bit scenario's
    /// ([`crate::analysis::bitmap`]).
    pub fn validate_with(&self, load: &dyn Fn(&Case) -> Result<(), Error>) -> Result<(), Error> {
        for (i, a) in self.axes.iter().enumerate() {
            a.check()?;
            if self.axes[..i].iter().any(|b| b.key == a.key) {
                return Err(Error::invalid(
                    &a.key,
                    "varied twice".into(),
                    "each key in at most one --vary".into(),
                ));
            }
        }
        let total = self
            .axes
            .iter()
            .try_fold(1usize, |acc, a| acc.checked_mul(a.n))
            .filter(|&t| t <= MAX_CASES);
        let Some(total) = total else {
            let ns: Vec<String> = self.axes.iter().map(|a| a.n.to_string()).collect();
            return Err(Error::invalid(
                "--vary",
                format!("{} cases is too many", ns.join(" x ")),
                format!("at most {MAX_CASES} cases"),
            ));
        };
        let first = match load(&self.case(0)) {
            Ok(()) => return Ok(()),
            Err(e) => e,
        };
        let probes: Vec<usize> = if total <= VALIDATE_PROBES {
            (1..total).collect()
        } else {
            std::iter::once(total - 1)
                .chain((1..VALIDATE_PROBES).map(|j| j * (total / VALIDATE_PROBES)))
                .collect()
        };
        if probes.into_iter().any(|i| load(&self.case(i)).is_ok()) {
            Ok(())
        } else {
            Err(first)
        }
    }

    /// The case indices of `shard` (see [`shard_range`]).
    pub fn shard_range(&self, shard: Shard) -> Result<Range<usize>, Error> {
        shard_range(self.total(), shard)
    }

    /// What `shard` of this sweep covers, for `shard.json`.
    pub fn shard_info(&self, shard: Shard) -> Result<ShardInfo, Error> {
        let r = self.shard_range(shard)?;
        Ok(ShardInfo {
            fingerprint: self.fingerprint(),
            k: shard.k,
            n: shard.n,
            total_cases: self.total(),
            first_index: r.start,
            end_index: r.end,
            axes: self.axes.clone(),
            checksums: BTreeMap::new(),
        })
    }

    /// The largest `solver.samples` of any case: the axis's largest value
    /// if `solver.samples` is varied, else the first loadable case's (the
    /// run limit [`crate::limits::MAX_SAMPLES`] if none loads).
    pub fn max_samples(&self) -> usize {
        self.max_samples_with(&|case| self.load_case(case).ok().map(|sc| sc.solver.samples))
    }

    /// [`Sweep::max_samples`] for any kind of case: `samples_of` loads a
    /// case and gives its `solver.samples` (`None` if it does not load).
    pub fn max_samples_with(&self, samples_of: &dyn Fn(&Case) -> Option<usize>) -> usize {
        if let Some(a) = self.axes.iter().rev().find(|a| a.key == "solver.samples") {
            let top = match &a.given {
                Some(v) => v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
                None => a.from.max(a.to),
            };
            // Out of range values fail as their cases; the limit bounds
            // what a valid case needs.
            return top.clamp(2.0, crate::limits::MAX_SAMPLES as f64) as usize;
        }
        (0..self.total().min(VALIDATE_PROBES))
            .find_map(|i| samples_of(&self.case(i)))
            .unwrap_or(crate::limits::MAX_SAMPLES)
    }

    /// How many cases the sweep may run at once within
    /// [`crate::limits::MEMORY_BUDGET`]: at most `threads`, each keeping a
    /// run of [`Sweep::max_samples`] ([`crate::limits::run_memory_bytes`])
    /// and up to 8 rows waiting to be written in order
    /// ([`window`]). Error (key `solver.samples`) if not even one fits.
    pub fn threads_within_memory(&self, threads: usize) -> Result<usize, Error> {
        let row = (std::mem::size_of::<Row>()
            + std::mem::size_of::<Summary>()
            + 8 * self.axes.len()
            + 256) as u64;
        let per_case = crate::limits::run_memory_bytes_for(self.max_samples()) + 9 * row;
        crate::limits::fit_threads("solver.samples", threads, per_case, 16 * row)
    }

    /// Run one case: load its scenario and simulate it. Never fails: errors
    /// (and panics) go into the row's `status`.
    pub fn run_case(&self, index: usize) -> Row {
        let case = self.case(index);
        let outcome = catch_unwind(AssertUnwindSafe(|| {
            let sc = self.load_case(&case)?;
            // The row reads the summary alone: no pose (the same bits).
            crate::simulate_with_pose(&sc, false, &mut |_| {}).map(|traj| traj.summary)
        }));
        let (summary, status) = match outcome {
            Ok(Ok(summary)) => {
                let status = summary.status.clone();
                (Some(summary), status)
            }
            Ok(Err(e)) => (None, e.to_string()),
            Err(panic) => {
                let msg = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                (None, format!("panicked: {msg}"))
            }
        };
        Row {
            index,
            values: case.values,
            summary,
            status,
        }
    }

    /// Run the cases `range` (0-based grid indices) on `threads` threads
    /// (`None`: see [`threads`]), calling `progress` after each case. The
    /// rows come back in index order, identical for any thread count. Errors:
    /// a thread count out of `1..=`[`MAX_THREADS`], a range past
    /// [`Sweep::total`], or a thread pool that cannot be built. Keeps every
    /// row in memory: for large sweeps use [`Sweep::run_streaming`].
    pub fn run(
        &self,
        range: Range<usize>,
        threads: Option<usize>,
        progress: &(dyn Fn() + Sync),
    ) -> Result<Vec<Row>, Error> {
        let mut rows = Vec::with_capacity(range.len().min(1 << 20));
        self.run_streaming(range, threads, &mut |row| {
            progress();
            rows.push(row);
            true
        })?;
        Ok(rows)
    }

    /// Run the cases `range` on `threads` threads (`None`: see [`threads`])
    /// and hand each row to `sink`, in index order, as soon as it and all
    /// rows before it are done. `sink` runs on the calling thread; when it
    /// returns `false` no further case is started and the call returns
    /// `Ok(false)` (`Ok(true)`: every row was delivered).
    ///
    /// Memory is flat in the number of cases: a case starts only when it is
    /// less than [`window`]`(threads)` cases past the next row to deliver,
    /// so at most that many rows wait (a slow case holds the others back
    /// rather than letting finished rows pile up). Each thread takes the
    /// next case when it is free (one case at a time: case costs vary a lot
    /// across a grid, and fixed blocks left threads idle). The rows, and so
    /// the order and bytes of a CSV written from them, do not depend on the
    /// thread count. Errors as for [`Sweep::run`].
    pub fn run_streaming(
        &self,
        range: Range<usize>,
        threads: Option<usize>,
        sink: &mut dyn FnMut(Row) -> bool,
    ) -> Result<bool, Error> {
        self.check_range(&range, "sweep")?;
        run_ordered(range, threads, &|i| self.run_case(i), sink)
    }

    /// `Ok` iff `range` lies within `0..total()` (else an error with key
    /// `key`).
    pub fn check_range(&self, range: &Range<usize>, key: &str) -> Result<(), Error> {
        if range.end > self.total() || range.start > range.end {
            return Err(Error::invalid(
                key,
                format!("cases {range:?} requested"),
                format!("within 0..{}", self.total()),
            ));
        }
        Ok(())
    }

    /// How much of an interrupted `sweep.csv` of the cases from
    /// `first_index` on can be kept: the header (it must be this sweep's,
    /// else nothing is kept) and then every complete line (ending in `\n`)
    /// that [`Sweep::check_line`] accepts as the next case, up to the first
    /// that it does not (a torn last line, say; `problem` says why a
    /// complete line was refused).
    pub fn complete_prefix(&self, first_index: usize, text: &str) -> Prefix {
        let ncols = self.axes.len() + FIELDS.len() + 1;
        self.complete_prefix_of(first_index, text, &csv_header(&self.axes), ncols)
    }

    /// [`Sweep::complete_prefix`] of any CSV of this grid whose lines hold
    /// the case's values first and `status` last: `header` (with its `\n`)
    /// and `ncols` fields a line (e.g. a bit map's `bitmap.csv`).
    pub fn complete_prefix_of(
        &self,
        first_index: usize,
        text: &str,
        header: &str,
        ncols: usize,
    ) -> Prefix {
        let mut p = Prefix::default();
        if !text.starts_with(header) {
            p.problem = Some("not the header");
            return p;
        }
        p.bytes = header.len();
        for line in text[header.len()..].split_inclusive('\n') {
            let index = first_index + p.rows;
            let Some(body) = line.strip_suffix('\n') else {
                break;
            };
            match self.check_line(index, body, ncols) {
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

    /// Check a data line (without its `\n`) of a CSV of this grid as case
    /// `index` (see [`Sweep::complete_prefix_of`]): `ncols` fields, the
    /// case's grid values first (as [`csv_row`] writes them), then fields
    /// that are empty, numbers or `true`/`false`, then a status as
    /// [`csv_row`] writes it (`ok` only with results: not every field
    /// empty). `Ok(true)`: a row whose status is not `ok`; `Err`: why not.
    pub fn check_line(&self, index: usize, body: &str, ncols: usize) -> Result<bool, &'static str> {
        if index >= self.total() {
            return Err("past the last case");
        }
        let (head, status) = split_line(body, ncols)?;
        let case = self.case(index);
        let nkeys = case.values.len();
        if !case
            .values
            .iter()
            .zip(&head)
            .all(|(v, f)| fmt_f64(*v) == *f)
        {
            return Err("not the case's grid values");
        }
        let rest = &head[nkeys.min(head.len())..];
        if !rest
            .iter()
            .all(|f| f.is_empty() || *f == "true" || *f == "false" || f.parse::<f64>().is_ok())
        {
            return Err("a field that is not a number");
        }
        let empty = rest.iter().all(|f| f.is_empty());
        if status == "ok" && empty && !rest.is_empty() {
            return Err("status ok without results");
        }
        Ok(status != "ok")
    }

    /// A 16-hex-digit hash (FNV-1a, 64 bit) of everything that defines the
    /// sweep's output: the tippetop version, the preset, the scenario text,
    /// the `--set`s and the axes. Shards with the same fingerprint belong to
    /// the same sweep. Stable across runs, machines and thread counts.
    pub fn fingerprint(&self) -> String {
        self.fingerprint_of("tippetop sweep 1", &[])
    }

    /// [`Sweep::fingerprint`] of another kind of grid (`tag`, e.g.
    /// `"tippetop bitmap 1"`) with `extra` `(name, value)` fields that also
    /// define its output (e.g. the runs per point).
    pub fn fingerprint_of(&self, tag: &str, extra: &[(&str, String)]) -> String {
        let mut text = format!("{tag}\n");
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
        for a in &self.axes {
            field("vary", &a.spec());
        }
        for (name, value) in extra {
            field(name, value);
        }
        format!("{:016x}", fnv1a(text.as_bytes()))
    }
}

pub(crate) fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// Run `job(i)` for every index in `range` on `threads` threads (`None`:
/// see [`threads`]) and hand each result to `sink`, in index order, as soon
/// as it and all results before it are done: the machinery of
/// [`Sweep::run_streaming`] for any kind of job (an ensemble's runs, say).
/// `sink` runs on the calling thread; when it returns `false` no further
/// index is started and the call returns `Ok(false)` (`Ok(true)`: every
/// result was delivered).
///
/// Memory is flat in the number of indices: an index starts only when it is
/// less than [`window`]`(threads)` past the next result to deliver. Each
/// thread takes the next index when it is free. The sequence of results
/// handed to `sink` does not depend on the thread count (as long as `job`
/// is a function of its index). Errors: a thread count out of
/// `1..=`[`MAX_THREADS`], or a thread pool that cannot be built.
pub fn run_ordered<T: Send>(
    range: Range<usize>,
    threads: Option<usize>,
    job: &(dyn Fn(usize) -> T + Sync),
    sink: &mut dyn FnMut(T) -> bool,
) -> Result<bool, Error> {
    let t = self::threads(threads)?;
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(t)
        .build()
        .map_err(|e| {
            Error::invalid(
                "--threads",
                format!("cannot start the thread pool: {e}"),
                "fewer threads".into(),
            )
        })?;
    let window = window(t);
    let next = AtomicUsize::new(range.start);
    let stop = AtomicBool::new(false);
    // The next index to deliver; workers wait on it for the window.
    let delivered = Mutex::new(range.start);
    let moved = Condvar::new();
    let (tx, rx) = mpsc::channel::<(usize, T)>();
    let mut complete = true;
    // The caller's stop flag (`simulate::stoppable`) holds in the workers.
    let outer_stop = crate::simulate::stop_flag();
    pool.in_place_scope(|scope| {
        for _ in 0..t {
            let tx = tx.clone();
            let (next, stop, delivered, moved) = (&next, &stop, &delivered, &moved);
            let end = range.end;
            let outer_stop = outer_stop.clone();
            scope.spawn(move |_| {
                crate::simulate::with_stop_flag(outer_stop, || {
                    loop {
                        if stop.load(Ordering::Relaxed) {
                            break;
                        }
                        let i = next.fetch_add(1, Ordering::Relaxed);
                        if i >= end {
                            break;
                        }
                        {
                            let mut d = delivered.lock().unwrap_or_else(|e| e.into_inner());
                            while i >= *d + window && !stop.load(Ordering::Relaxed) {
                                d = moved.wait(d).unwrap_or_else(|e| e.into_inner());
                            }
                        }
                        if stop.load(Ordering::Relaxed) || tx.send((i, job(i))).is_err() {
                            break;
                        }
                    }
                })
            });
        }
        drop(tx);
        let mut pending: BTreeMap<usize, T> = BTreeMap::new();
        let mut expect = range.start;
        'rows: for (i, item) in &rx {
            pending.insert(i, item);
            while let Some(r) = pending.remove(&expect) {
                expect += 1;
                if !sink(r) {
                    complete = false;
                    break 'rows;
                }
                *delivered.lock().unwrap_or_else(|e| e.into_inner()) = expect;
                moved.notify_all();
            }
        }
        if !complete {
            stop.store(true, Ordering::Relaxed);
            // Take the lock so no worker misses the wake-up between its
            // check of `stop` and its wait.
            drop(delivered.lock().unwrap_or_else(|e| e.into_inner()));
            moved.notify_all();
        }
    });
    Ok(complete)
}

// ---------------------------------------------------------------------------
// CSV.

/// The header line (with its `\n`): the axes' keys, [`FIELDS`], `status`.
pub fn csv_header(axes: &[Axis]) -> String {
    let mut cols: Vec<&str> = axes.iter().map(|a| a.key.as_str()).collect();
    cols.extend(FIELDS);
    cols.push("status");
    let mut s = cols.join(",");
    s.push('\n');
    s
}

/// A float in Rust's shortest round-trip form (`0.1`, `1e-24`, `NaN`, `inf`).
pub fn fmt_f64(x: f64) -> String {
    format!("{x:?}")
}

fn opt(x: Option<f64>) -> String {
    x.map(fmt_f64).unwrap_or_default()
}

/// The status as one CSV field: line breaks become spaces, and the field
/// is quoted (quotes doubled) when it contains a comma or a quote.
pub(crate) fn status_field(status: &str) -> String {
    let one_line: String = status
        .chars()
        .map(|c| if c == '\n' || c == '\r' { ' ' } else { c })
        .collect();
    if one_line.contains([',', '"']) {
        format!("\"{}\"", one_line.replace('"', "\"\""))
    } else {
        one_line
    }
}

/// One data line (with its `\n`): the case's values, the summary fields
/// (empty without a summary, or for an event that never happened), status.
pub fn csv_row(row: &Row) -> String {
    let mut fields: Vec<String> = row.values.iter().map(|&v| fmt_f64(v)).collect();
    match &row.summary {
        Some(s) => fields.extend([
            fmt_f64(s.theta_final),
            fmt_f64(s.theta_max),
            fmt_f64(s.omega_final),
            fmt_f64(s.precession_final),
            opt(s.first_time_theta_above_half_pi),
            opt(s.contact_lost_at),
            fmt_f64(s.negative_normal_fraction),
            fmt_f64(s.rolling_fraction),
            fmt_f64(s.jellett_max_rel_drift),
            fmt_f64(s.energy_final),
            s.steps.to_string(),
            s.rhs_evaluations.to_string(),
        ]),
        None => fields.extend(std::iter::repeat_n(String::new(), FIELDS.len())),
    }
    fields.push(status_field(&row.status));
    let mut s = fields.join(",");
    s.push('\n');
    s
}

/// The whole CSV: header and one line per row, in the order given.
pub fn csv(axes: &[Axis], rows: &[Row]) -> String {
    let mut s = csv_header(axes);
    for r in rows {
        s.push_str(&csv_row(r));
    }
    s
}

/// Split a data line into its `ncols` fields: the first `ncols - 1`
/// (unquoted), and the status, the last, as [`status_field`] writes it
/// (quoted iff it holds a comma or a quote). `Err`: too few fields, or a
/// last field that is not such a status (e.g. an extra field after it).
fn split_line(line: &str, ncols: usize) -> Result<(Vec<&str>, String), &'static str> {
    let mut parts = line.splitn(ncols, ',');
    let head: Vec<&str> = parts.by_ref().take(ncols - 1).collect();
    let raw = parts.next().ok_or("too few fields")?;
    if head.len() != ncols - 1 {
        return Err("too few fields");
    }
    let status = match raw.strip_prefix('"') {
        Some(inner) => inner
            .strip_suffix('"')
            .ok_or("a malformed status")?
            .replace("\"\"", "\""),
        None => raw.to_string(),
    };
    if status.is_empty() || status_field(&status) != raw {
        return Err(if raw.contains(',') {
            "more fields than the header"
        } else {
            "a malformed status"
        });
    }
    Ok((head, status))
}

// ---------------------------------------------------------------------------
// Merge.

/// Join shard outputs (each a [`ShardInfo`] and its `sweep.csv` text, in any
/// order) into the CSV of the whole sweep, byte for byte what a one-shot run
/// writes. Checks that all shards belong to the same sweep (fingerprint,
/// total, axes), that each CSV has the right header, row count and grid
/// values, and that the shards tile `0..total` with no gap and no overlap.
/// Errors are [`Error::Invalid`] with key `merge`.
pub fn merge(shards: &[(ShardInfo, String)]) -> Result<String, Error> {
    let Some((first, _)) = shards.first() else {
        return Err(Error::invalid(
            "merge",
            "no shards given".into(),
            "one or more shard outputs".into(),
        ));
    };
    let ncols = first.axes.len() + FIELDS.len() + 1;
    merge_of(
        shards,
        &csv_header(&first.axes),
        ncols,
        "sweep.csv",
        "sweep",
    )
}

/// [`merge`] for any CSV of a grid whose lines hold the case's values first
/// and `status` last (see [`Sweep::complete_prefix_of`]): `header` (with its
/// `\n`) and `ncols` fields a line, in files named `file` written by
/// `tippetop COMMAND` (for the messages).
pub fn merge_of(
    shards: &[(ShardInfo, String)],
    header: &str,
    ncols: usize,
    file: &str,
    command: &str,
) -> Result<String, Error> {
    let Some((first, _)) = shards.first() else {
        return Err(Error::invalid(
            "merge",
            "no shards given".into(),
            "one or more shard outputs".into(),
        ));
    };
    let sweep = Sweep {
        preset: None,
        toml_text: None,
        sets: Vec::new(),
        axes: first.axes.clone(),
    };
    let total = sweep.total();
    if let Some((info, _)) = shards.iter().find(|(i, _)| i.total_cases != total) {
        return Err(Error::invalid(
            "merge",
            format!(
                "shard {}/{} (cases {}..{}) does not fit a {command} of {total} cases",
                info.k, info.n, info.first_index, info.end_index
            ),
            format!("shard.json as written by tippetop {command}"),
        ));
    }
    merge_rows(shards, header, file, command, &|_, index, line| {
        sweep.check_line(index, line, ncols).map(|_| ())
    })
}

/// Join the CSV texts of shards (each after its [`ShardInfo`], in any
/// order) whose lines are the items `first_index..end_index` of
/// `total_cases`, one line each after `header`: checks that the shards
/// belong together (fingerprint, total, axes), that each text has the
/// header, its number of lines, and lines that `row_ok(info, index, line)`
/// accepts as item `index` (`Err`: why not), and that the shards tile
/// `0..total_cases`.
/// `file` and `command` name the CSV and the command that wrote it in the
/// messages ([`Error::Invalid`] with key `merge`).
pub fn merge_rows(
    shards: &[(ShardInfo, String)],
    header: &str,
    file: &str,
    command: &str,
    row_ok: &dyn Fn(&ShardInfo, usize, &str) -> Result<(), &'static str>,
) -> Result<String, Error> {
    let err = |what: String, range: &str| Error::invalid("merge", what, range.into());
    let Some((first, _)) = shards.first() else {
        return Err(err("no shards given".into(), "one or more shard outputs"));
    };
    let same =
        format!("all shards from one {command}: same scenario, --set and --vary, same tippetop");
    let same = same.as_str();
    let written = format!("{file} as written by tippetop {command}");
    let written = written.as_str();
    let header = header.to_string();
    for (info, text) in shards {
        let name = format!(
            "shard {}/{} (cases {}..{})",
            info.k, info.n, info.first_index, info.end_index
        );
        if info.fingerprint != first.fingerprint
            || info.total_cases != first.total_cases
            || info.axes != first.axes
        {
            return Err(err(
                format!(
                    "{name} is of another {command} (fingerprint {} with {} cases, not {} with {})",
                    info.fingerprint, info.total_cases, first.fingerprint, first.total_cases
                ),
                same,
            ));
        }
        if info.first_index > info.end_index || info.end_index > info.total_cases {
            return Err(err(
                format!(
                    "{name} does not fit a {command} of {} cases",
                    info.total_cases
                ),
                format!("shard.json as written by tippetop {command}").as_str(),
            ));
        }
        let Some(body) = text.strip_prefix(header.as_str()) else {
            return Err(err(
                format!("{name}: {file} does not start with the {command}'s header"),
                written,
            ));
        };
        let lines: Vec<&str> = body.split_inclusive('\n').collect();
        let want = info.end_index - info.first_index;
        if lines.len() != want {
            return Err(err(
                format!("{name}: {file} has {} rows, not {want}", lines.len()),
                written,
            ));
        }
        for (j, line) in lines.iter().enumerate() {
            let index = info.first_index + j;
            let Some(line) = line.strip_suffix('\n') else {
                return Err(err(
                    format!(
                        "{name}: {file} ends in the middle of its last row (line {}, no line end)",
                        j + 2
                    ),
                    written,
                ));
            };
            if let Err(why) = row_ok(info, index, line) {
                return Err(err(
                    format!(
                        "{name}: line {} of {file} is not case {index} ({why})",
                        j + 2
                    ),
                    written,
                ));
            }
        }
    }
    let mut order: Vec<&(ShardInfo, String)> = shards.iter().collect();
    order.sort_by_key(|(i, _)| (i.first_index, i.end_index));
    let total = first.total_cases;
    let mut cursor = 0;
    let mut out = header.clone();
    let complete = "shards that cover every case exactly once";
    for (info, text) in order {
        if info.first_index > cursor {
            return Err(err(
                format!(
                    "cases {cursor}..{} of {total} are missing",
                    info.first_index
                ),
                complete,
            ));
        }
        if info.first_index < cursor {
            return Err(err(
                format!(
                    "shard {}/{} (cases {}..{}) overlaps cases before {cursor}",
                    info.k, info.n, info.first_index, info.end_index
                ),
                complete,
            ));
        }
        out.push_str(&text[header.len()..]);
        cursor = info.end_index;
    }
    if cursor != total {
        return Err(err(
            format!("cases {cursor}..{total} of {total} are missing"),
            complete,
        ));
    }
    Ok(out)
}

// ---------------------------------------------------------------------------
// Columns, for plots and analyses.

/// A sweep's results as columns of numbers (from rows or parsed back from
/// `sweep.csv`), for plots: curves over the axis for a 1D sweep, a heat map
/// over the two axes for a 2D sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The varied keys, in axis order.
    pub keys: Vec<String>,
    /// Per case, one value per axis.
    pub values: Vec<Vec<f64>>,
    /// Per case, the [`FIELDS`] (NaN where the CSV field is empty).
    pub fields: Vec<[f64; FIELDS.len()]>,
    /// Per case, `ok` or the error.
    pub status: Vec<String>,
}

impl Table {
    /// From rows computed in this process.
    pub fn from_rows(axes: &[Axis], rows: &[Row]) -> Table {
        let opt = |x: Option<f64>| x.unwrap_or(f64::NAN);
        Table {
            keys: axes.iter().map(|a| a.key.clone()).collect(),
            values: rows.iter().map(|r| r.values.clone()).collect(),
            fields: rows
                .iter()
                .map(|r| match &r.summary {
                    Some(s) => [
                        s.theta_final,
                        s.theta_max,
                        s.omega_final,
                        s.precession_final,
                        opt(s.first_time_theta_above_half_pi),
                        opt(s.contact_lost_at),
                        s.negative_normal_fraction,
                        s.rolling_fraction,
                        s.jellett_max_rel_drift,
                        s.energy_final,
                        s.steps as f64,
                        s.rhs_evaluations as f64,
                    ],
                    None => [f64::NAN; FIELDS.len()],
                })
                .collect(),
            status: rows.iter().map(|r| r.status.clone()).collect(),
        }
    }

    /// Parse a `sweep.csv`.
    pub fn parse_csv(text: &str) -> Result<Table, Error> {
        let bad = |what: String| {
            Error::invalid(
                "sweep.csv",
                what,
                "a file written by tippetop sweep or merge".into(),
            )
        };
        let mut lines = text.lines();
        let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
        let nf = FIELDS.len();
        if header.len() < nf + 1
            || header[header.len() - nf - 1..header.len() - 1] != FIELDS
            || header.last() != Some(&"status")
        {
            return Err(bad("unexpected header".into()));
        }
        let nk = header.len() - nf - 1;
        let mut t = Table {
            keys: header[..nk].iter().map(|s| s.to_string()).collect(),
            values: Vec::new(),
            fields: Vec::new(),
            status: Vec::new(),
        };
        for (j, line) in lines.enumerate() {
            let (head, status) = split_line(line, header.len())
                .map_err(|why| bad(format!("line {}: {why}", j + 2)))?;
            let num = |s: &str| -> Result<f64, Error> {
                if s.is_empty() {
                    Ok(f64::NAN)
                } else {
                    s.parse::<f64>()
                        .map_err(|_| bad(format!("line {}: {s:?} is not a number", j + 2)))
                }
            };
            t.values.push(
                head[..nk]
                    .iter()
                    .map(|s| num(s))
                    .collect::<Result<_, _>>()?,
            );
            let mut f = [f64::NAN; FIELDS.len()];
            for (slot, s) in f.iter_mut().zip(&head[nk..]) {
                *slot = num(s)?;
            }
            t.fields.push(f);
            t.status.push(status);
        }
        Ok(t)
    }

    /// A column by header name (a varied key or one of [`FIELDS`]); NaN for
    /// empty fields.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        if let Some(i) = self.keys.iter().position(|k| k == name) {
            return Some(self.values.iter().map(|v| v[i]).collect());
        }
        let i = FIELDS.iter().position(|f| *f == name)?;
        Some(self.fields.iter().map(|f| f[i]).collect())
    }

    /// For a complete 2D sweep (two keys, every case present): the distinct
    /// values of the first key (rows of the map, `xs`), of the second
    /// (`ys`), and the named column as `z[i][j]` at `(xs[i], ys[j])`.
    #[allow(clippy::type_complexity)]
    pub fn grid2(&self, name: &str) -> Option<(Vec<f64>, Vec<f64>, Vec<Vec<f64>>)> {
        if self.keys.len() != 2 {
            return None;
        }
        let col = self.column(name)?;
        let ny = self
            .values
            .iter()
            .position(|v| v[0] != self.values[0][0])
            .unwrap_or(self.values.len());
        if ny == 0 || self.values.len() % ny != 0 {
            return None;
        }
        let nx = self.values.len() / ny;
        let xs: Vec<f64> = (0..nx).map(|i| self.values[i * ny][0]).collect();
        let ys: Vec<f64> = (0..ny).map(|j| self.values[j][1]).collect();
        let z = (0..nx)
            .map(|i| col[i * ny..(i + 1) * ny].to_vec())
            .collect();
        Some((xs, ys, z))
    }
}
