//! Adaptive multilevel splitting (AMS) on the full stochastic dynamics:
//! probabilities far below what brute force reaches and mean escape times
//! far beyond a simulation's span, with 95 % intervals from independent
//! replicas (docs/physics.md#ams: the algorithm, why it is unbiased, the
//! intervals).
//!
//! # What it estimates
//!
//! - [`Quantity::Probability`] (a [`Problem`] with a `reset`):
//!   `p = P(target before reset)` from the scenario's initial state, or
//!   `P(target before reset and before T)` with a horizon `T`.
//! - [`Quantity::MeanFirstPassageTime`] (no `reset`): the mean time to the
//!   target from the initial state, by the flux relation
//!   `τ = T₁ + C (1/p − 1) + S`: `T₁` the mean time to the first crossing of
//!   an interface `ξ > z_Σ` near the state, `C` the mean time between
//!   crossings whose excursion fell back into the basin `ξ <= z_A`, `p` the
//!   probability that an excursion from the interface reaches the target
//!   before the basin (by AMS from the crossing states a direct run
//!   visited), `S` the mean duration of a successful excursion (from the
//!   same AMS). The escape rate is `1/τ`.
//!
//! The target and the reset are conditions over trajectory.csv columns in
//! the `--first-passage` grammar ([`Exit`]); the reaction coordinate ξ is
//! a column, a column negated, `|column − c|` or the tilt's energy
//! ([`Coordinate`]; by default θ, oriented towards the target, or in the
//! Langevin mode for a state's escape the tilt energy:
//! [`Coordinate::default_for`]).
//!
//! # The algorithm (generalised AMS, Bréhier, Gazeau, Goudenège, Lelièvre
//! & Rousset, Ann. Appl. Probab. 26, 3559 (2016))
//!
//! `n` particles (`particles`) start at the initial state (or, for the
//! flux relation, at crossing states drawn uniformly from the direct
//! run's), each run until it meets the target, the reset, the horizon or
//! its step budget, watched at **every** step. A particle's score is the
//! largest ξ over its steps, `+∞` if it met the target (the step that meets
//! the reset does not count: ξ̃ = −∞ there). Each iteration: `Z` = the
//! `k`-th smallest score (`kill` = k); if `Z = +∞`, stop; every particle
//! with score `<= Z` is killed (ties included: `K >= k` of them); if all
//! are, the replica is extinct (estimate 0); else the weight is multiplied
//! by `1 − K/n` and each killed particle is replaced by a copy of a
//! survivor (score `> Z`, drawn uniformly) up to that survivor's first step
//! with `ξ > Z`, continued with fresh noise. At the end
//! `p̂ = Π_j (1 − K_j/n) × (particles at the target)/n`, unbiased for any
//! `n`, `k` and ξ (the reference above, Theorem 4.1; sketch in
//! docs/physics.md#ams).
//!
//! # Paths, noise and reproducibility
//!
//! A path is a [`crate::Simulation`] of the scenario with `solver.t_end`
//! set to the horizon (or far beyond the step budget) and two output rows:
//! `solver.t_end` and `solver.samples` of the scenario do **not** cut a
//! path short; it runs until the target or the reset, bounded only by the
//! budget `max_steps` (counted from the path's root: the initial state or
//! its crossing state). A path cut by the budget counts as not reaching the
//! target (the estimate is then of `P(target before reset and within the
//! budget)`, reported as `truncated`). Replica `r` draws its noise from the
//! stream `(thermal.seed, thermal.run + r)`; the particle created `b`-th in
//! the replica (roots first) draws step `k`'s noise at the stream's counter
//! `b · 2⁴⁰ + k`: a pure function of (seed, replica, branch, step). The
//! survivors are drawn from the same stream's counters of a reserved
//! branch. Replicas run in parallel ([`crate::analysis::sweep::run_ordered`])
//! and are combined in replica order: the same inputs give the same bits
//! whatever the thread count, and the replicas of a shard (a range of
//! [`Ams::run`]) combine ([`Ams::combine`]) into the same bits as one run.
//!
//! # Intervals
//!
//! Probability: the mean of the replicas' estimates with Student's t
//! interval on `M − 1` degrees of freedom (`ci95`, lower end clipped at 0):
//! each replica is an unbiased estimate, so the mean is, and the interval
//! needs only the replicas' finite variance (their law is skewed, close to
//! log-normal for small `p`: the t interval is the distribution-free
//! choice; Cox's log-normal interval is given beside it,
//! `ci95_lognormal`). Every replica extinct: estimate 0 and the upper end
//! `1 − 0.05^{1/(nM)}` (no root of any replica met the target: `nM`
//! independent runs). Mean first-passage time: the flux relation's value
//! at the replica means, its standard error by the delta method over the
//! replicas (`(p, p S, T₁ sums and counts, C sums and counts)` per
//! replica), and the log-normal interval `τ exp(± t SE/τ)`.
//!
//! # Sizes and cost
//!
//! For `k = 1` a replica's relative variance is about `−ln p / n` with a
//! coordinate that follows the committor (Cérou & Guyader 2007; the
//! Brownian tests), a few times more with a rougher one (the tilt energy
//! of a Langevin escape: 0.9 at `n` = 100, `p` ~ 5e-9). The defaults
//! (`M` = 20 replicas of `n` = 100) give a 95 % interval within a factor 2
//! for the Brownian mode down to `p` ~ 1e-40 (relative half-width
//! `t₁₉ sqrt(−ln p/2000)`) and for `nano-physical`'s escape at 300 K
//! (factor 1.45). A replica takes about `n (1 − ln p / k)` paths. Each
//! iteration's replacements are sequential; the replicas are the
//! parallelism.

mod coordinate;
mod path;
mod results;
mod stats;

use std::ops::Range;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::AtomicBool;

pub(crate) use self::coordinate::TiltEnergy;
pub use self::coordinate::{COORDINATE_RANGE, Coordinate};
use self::path::{Cancelled, End, Path, Reset, Runner, Watch};
pub use self::results::{DirectPhase, Estimate, Flux, Level, Quantity, Replica};
pub use self::stats::t975;
use crate::analysis::ensemble::{Exit, check_scenario};
use crate::analysis::sweep::run_ordered;
use crate::input::thermal::MAX_RUNS;
use crate::random::Stream;
use crate::simulate::{Snapshot, noise_counter};
use crate::{Error, Failure, Scenario, Simulation};

/// Largest step count of a path's run (the simulation's own limit,
/// [`crate::limits::MAX_STEPS`]).
const RUN_STEPS: u64 = crate::limits::MAX_STEPS;

/// Largest `max_steps` (a path's budget) and `direct_steps`: together
/// within the run's limit.
pub const MAX_PATH_STEPS: u64 = RUN_STEPS / 2;

/// Branch indices a replica may use for its particles (the stream's
/// counter holds 24 bits of branch; the top ones are reserved).
pub const MAX_TRAJECTORIES: u64 = (1 << 24) - 16;

/// The reserved branch of a replica's survivor draws.
const SELECT_BRANCH: u64 = (1 << 24) - 1;
/// The reserved branch of the direct runs ([`Ams::direct`]).
const DIRECT_BRANCH: u64 = (1 << 24) - 2;
/// The reserved branches of the pilot run (downwards from here).
const PILOT_BRANCH: u64 = (1 << 24) - 3;
/// Most restarts of the pilot run after it met the target.
const PILOT_RESTARTS: u64 = 8;

/// Largest number of particles: a replica's particles ([`PARTICLE_BYTES`]
/// each) fit in [`crate::limits::MEMORY_BUDGET`] beside the default
/// records.
pub const MAX_PARTICLES: usize = 30_000;

/// Most levels a replica's record keeps ([`Replica::levels`]): beyond it
/// every other one is dropped, so that a record stays within about 64 kB.
pub const MAX_STORED_LEVELS: usize = 4096;

/// Largest number of replicas (`--replicas`): their records are kept
/// until the estimate is combined, and their memory must fit in
/// [`crate::limits::MEMORY_BUDGET`] too ([`Ams::threads_within_memory`]).
pub const MAX_REPLICAS: usize = 100_000;

/// The memory one particle of a running replica holds, an estimate
/// \[bytes\]: its path's checkpoints (at most about 18 snapshots of the
/// simulation, some shared with the path it branched from) and its running
/// maxima. Measured: 68 kB per particle (peak resident memory over 2000
/// particles, the nano-physical preset in the Brownian mode at dt = 2e-16
/// s); 96 KiB allows for the larger rigid model.
pub const PARTICLE_BYTES: u64 = 96 << 10;

/// What to estimate ([`Ams::new`] checks it).
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The scenario: a stochastic run (`solver.method = "langevin"` or
    /// `"brownian"` at `thermal.temperature > 0`); its `t_end` and
    /// `samples` are not used (see the module doc).
    pub scenario: Scenario,
    /// The target (`--target`).
    pub target: Exit,
    /// The reset (`--reset`): `Some` for [`Quantity::Probability`], `None`
    /// for [`Quantity::MeanFirstPassageTime`].
    pub reset: Option<Exit>,
    /// The reaction coordinate (`--coordinate`; by default
    /// [`Coordinate::default_for`] the scenario and the target).
    pub coordinate: Coordinate,
    /// The horizon `T` \[s\] (`--horizon`, probability only):
    /// `p = P(target before reset and before T)`.
    pub horizon: Option<f64>,
}

impl Problem {
    /// A problem with the default coordinate ([`Coordinate::default_for`])
    /// and no horizon.
    pub fn new(scenario: Scenario, target: Exit, reset: Option<Exit>) -> Problem {
        let coordinate = Coordinate::default_for(&scenario, &target);
        Problem {
            scenario,
            target,
            reset,
            coordinate,
            horizon: None,
        }
    }
}

/// Deliberately wrong variants of the algorithm, for the test that shows
/// the unbiasedness test has the power to see a bias. Not for use.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Variant {
    /// The algorithm of the module doc.
    #[default]
    Unbiased,
    /// Kill every particle at or below the level but weigh the iteration
    /// by `1 − k/n` (the continuous-time formula, which assumes no ties):
    /// biased upwards when ties occur, as in discrete time.
    TieBlindWeight,
}

/// Sizes and budgets ([`Settings::default`] gives the defaults; each is
/// checked by [`Ams::new`], the error naming the CLI option).
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// Independent replicas `M` (`--replicas`, 2 ..= [`MAX_REPLICAS`],
    /// their records within the memory bound; default 20).
    pub replicas: usize,
    /// Particles per replica `n` (`--particles`, 2 ..= [`MAX_PARTICLES`];
    /// default 100).
    pub particles: usize,
    /// Particles killed per iteration at least `k` (`--kill`, 1 ..= n − 1;
    /// default 1: the smallest variance).
    pub kill: usize,
    /// Most paths a replica may run, roots included (`--max-trajectories`,
    /// n ..= [`MAX_TRAJECTORIES`]; default 100 000, enough for `p` down to
    /// `e^{−1000}` with `n` = 100). A replica that needs more is incomplete:
    /// no estimate (an error naming the level reached).
    pub max_trajectories: u64,
    /// Step budget of a path, counted from its root (`--max-steps`,
    /// 1 ..= [`MAX_PATH_STEPS`]; default 10 000 000).
    pub max_steps: u64,
    /// Mean first-passage time: crossing states a replica's direct run
    /// collects (`--crossings`, 1 ..= 100 000; default 100).
    pub crossings: usize,
    /// Mean first-passage time: step budget of a replica's direct run
    /// (`--direct-steps`, 1 ..= [`MAX_PATH_STEPS`]; default 10 000 000).
    pub direct_steps: u64,
    /// Mean first-passage time: steps of the pilot run that places the
    /// basin and the interface (`--pilot-steps`, 1 000 ..= 10 000 000;
    /// default 100 000).
    pub pilot_steps: u64,
    /// Mean first-passage time: the basin `ξ <= z_A` (`--basin`); default
    /// the median of ξ over the pilot run's second half.
    pub basin: Option<f64>,
    /// Mean first-passage time: the interface `ξ > z_Σ` (`--interface`);
    /// default the 90 % quantile of ξ over the pilot run's second half.
    pub interface: Option<f64>,
    /// The algorithm (tests only).
    #[doc(hidden)]
    pub variant: Variant,
}

impl Default for Settings {
    fn default() -> Self {
        Settings {
            replicas: 20,
            particles: 100,
            kill: 1,
            max_trajectories: 100_000,
            max_steps: 10_000_000,
            crossings: 100,
            direct_steps: 10_000_000,
            pilot_steps: 100_000,
            basin: None,
            interface: None,
            variant: Variant::Unbiased,
        }
    }
}

/// Progress and cancellation.
#[derive(Clone, Copy, Default)]
pub struct Hooks<'a> {
    /// Called on the calling thread with the fraction of replicas (or
    /// direct runs) done, in `[0, 1]`.
    pub progress: Option<&'a (dyn Fn(f64) + Sync)>,
    /// Set it (from a Ctrl-C handler, say) to stop: the replicas running
    /// stop within a few thousand steps and are dropped; the call returns
    /// what was complete (`Ok(false)` / `Ok(None)`).
    pub cancel: Option<&'a AtomicBool>,
    /// Steps run so far over all replicas (added to as paths run, every
    /// few hundred steps), to show progress within long replicas.
    pub steps: Option<&'a std::sync::atomic::AtomicU64>,
}

/// A checked problem, ready to run ([`Ams::new`]).
#[derive(Debug, Clone)]
pub struct Ams {
    problem: Problem,
    settings: Settings,
    /// The scenario of the paths (t_end, samples and the step limit set).
    paths: Scenario,
    watch: Watch,
    /// `(z_A, z_Σ)` (mean first-passage time).
    levels: Option<(f64, f64)>,
}

/// A crossing of the interface by a direct run: where an AMS root starts.
struct Crossing {
    start: Snapshot,
}

impl Ams {
    /// Check `problem` and `settings`: a stochastic scenario, budgets in
    /// range, a target (and reset) that does not hold at the initial state,
    /// a finite ξ there, a horizon within the step limit; for the mean
    /// first-passage time, the basin and interface (from the pilot run if
    /// not given). Errors: [`Error::Invalid`] naming the CLI option (or
    /// the scenario key), one line; a pilot run that fails: its run-time
    /// error.
    pub fn new(problem: Problem, settings: Settings) -> Result<Ams, Error> {
        check_scenario(&problem.scenario)?;
        check_settings(&settings, problem.scenario.thermal.run)?;
        let sc = &problem.scenario;
        let dt = sc.solver.dt.unwrap_or(f64::NAN);
        let mut paths = sc.clone();
        paths.solver.samples = 2;
        paths.solver.max_steps = Some(RUN_STEPS);
        paths.solver.t_end = (RUN_STEPS - 2) as f64 * dt;
        if let Some(t) = problem.horizon {
            if problem.reset.is_none() {
                return Err(Error::invalid(
                    "--horizon",
                    "a horizon without --reset".into(),
                    "a horizon T > 0 [s] with --reset (a probability within T)".into(),
                ));
            }
            let limit = MAX_PATH_STEPS as f64 * dt;
            if !(t.is_finite() && t > 0.0 && t <= limit) {
                return Err(Error::invalid(
                    "--horizon",
                    format!("{t} s"),
                    format!("0 < T <= {limit:e} s ({MAX_PATH_STEPS} steps of solver.dt)"),
                ));
            }
            paths.solver.t_end = t;
        }
        // The scenario's own rules, with the paths' t_end.
        let sim = Simulation::new(&paths)?;
        let row = sim.state().values();
        let get = |i: usize| row[i];
        let reset = match &problem.reset {
            Some(r) => Reset::Cond(r.clone()),
            None => Reset::Never,
        };
        let watch = Watch::new(problem.coordinate, problem.target.clone(), reset, sc);
        let (xi0, target0, reset0) = watch.eval_values(&get);
        let state = format!(
            "theta = {:.6} rad, t = 0 (initial.theta {})",
            row[1], sc.initial.theta
        );
        if target0 {
            return Err(Error::invalid(
                "--target",
                format!("{} holds at the initial state ({state})", problem.target),
                "a condition that does not hold at the start".into(),
            ));
        }
        if reset0 {
            return Err(Error::invalid(
                "--reset",
                format!(
                    "{} holds at the initial state ({state})",
                    problem
                        .reset
                        .as_ref()
                        .map(|r| r.to_string())
                        .unwrap_or_default()
                ),
                "a condition that does not hold at the start".into(),
            ));
        }
        if !xi0.is_finite() {
            return Err(Error::invalid(
                "--coordinate",
                format!("{} is {xi0} at the initial state", problem.coordinate),
                COORDINATE_RANGE.into(),
            ));
        }
        let mut ams = Ams {
            problem,
            settings,
            paths,
            watch,
            levels: None,
        };
        if ams.problem.reset.is_none() {
            let levels = ams.place_levels(xi0)?;
            ams.watch.reset = Reset::Basin(levels.0);
            ams.levels = Some(levels);
        }
        Ok(ams)
    }

    /// The problem.
    pub fn problem(&self) -> &Problem {
        &self.problem
    }

    /// The settings.
    pub fn settings(&self) -> &Settings {
        &self.settings
    }

    /// The memory the replicas' records may take once run, at most
    /// \[bytes\]: each record and its levels (one per iteration, at most
    /// one per path beyond the first `n`, and at most
    /// [`MAX_STORED_LEVELS`] + 1), twice (the records are copied
    /// once to be combined).
    pub fn records_bytes(&self) -> u64 {
        records_bytes(&self.settings)
    }

    /// How many replicas may run at once within
    /// [`crate::limits::MEMORY_BUDGET`]: at most `threads`, each holding
    /// its `n` particles ([`PARTICLE_BYTES`] each) beside the replicas'
    /// records ([`Ams::records_bytes`]). Err (naming `--particles`) if not
    /// even one fits.
    pub fn threads_within_memory(&self, threads: usize) -> Result<usize, Error> {
        let per_replica = (self.settings.particles as u64).saturating_mul(PARTICLE_BYTES);
        crate::limits::fit_threads("--particles", threads, per_replica, self.records_bytes())
            .map(|t| t.min(self.settings.replicas.max(1)))
    }

    /// What is estimated.
    pub fn quantity(&self) -> Quantity {
        if self.problem.reset.is_some() {
            Quantity::Probability
        } else {
            Quantity::MeanFirstPassageTime
        }
    }

    /// The basin and interface levels `(z_A, z_Σ)` of the flux relation
    /// (mean first-passage time only).
    pub fn levels(&self) -> Option<(f64, f64)> {
        self.levels
    }

    fn seed(&self) -> u64 {
        self.paths.thermal.seed.unwrap_or(0)
    }

    fn first_run(&self) -> u64 {
        self.paths.thermal.run
    }

    /// A fresh path simulation of stream run `run`, at the initial state.
    fn simulation(&self, run: u64) -> Simulation {
        let mut sc = self.paths.clone();
        sc.thermal.run = run;
        Simulation::new(&sc)
            .expect("the scenario was checked by Ams::new")
            .for_paths()
    }

    /// The basin and interface: given, or the median and 90 % quantile of
    /// ξ over the second half of a pilot run from the initial state
    /// (stream run `thermal.run`, a reserved branch; restarted from the
    /// initial state when it meets the target).
    fn place_levels(&self, xi0: f64) -> Result<(f64, f64), Error> {
        let s = &self.settings;
        let (basin, interface) = match (s.basin, s.interface) {
            (Some(a), Some(b)) => (a, b),
            (a, b) => {
                let xs = self.pilot()?;
                let q = |f: f64| xs[((xs.len() - 1) as f64 * f).round() as usize];
                (a.unwrap_or(q(0.5)), b.unwrap_or(q(0.9)))
            }
        };
        if !(basin.is_finite() && interface.is_finite() && basin < interface) {
            return Err(Error::invalid(
                "--interface",
                format!("basin z_A = {basin}, interface z_Sigma = {interface}"),
                "finite levels of the coordinate with --basin < --interface (the defaults are the pilot run's 50 % and 90 % quantiles of the coordinate: give both where these coincide)".into(),
            ));
        }
        if xi0 >= interface {
            return Err(Error::invalid(
                "--interface",
                format!(
                    "{} = {xi0} at the initial state is not below the interface {interface}",
                    self.problem.coordinate
                ),
                "an interface above the coordinate's initial value (the state's basin)".into(),
            ));
        }
        Ok((basin, interface))
    }

    /// ξ at every step of the pilot run's second half, sorted.
    fn pilot(&self) -> Result<Vec<f64>, Error> {
        let total = self.settings.pilot_steps;
        let mut sim = self.simulation(self.first_run());
        let start = sim.snapshot();
        sim.set_noise_branch(PILOT_BRANCH);
        let mut xs = Vec::with_capacity((total / 2) as usize + 1);
        let mut used = 0u64;
        let mut restarts = 0;
        let watch = &self.watch;
        loop {
            let mut hit = false;
            let stopped = sim.advance_until(&mut |p| {
                used += 1;
                let (xi, target, _) = watch.eval(p);
                if target {
                    hit = true;
                    return true;
                }
                if used > total / 2 && xi.is_finite() {
                    xs.push(xi);
                }
                used >= total
            });
            if !stopped {
                if let Some(e) = sim.error() {
                    return Err(e.clone());
                }
                break;
            }
            if !hit || used >= total || restarts >= PILOT_RESTARTS {
                break;
            }
            restarts += 1;
            sim.restore(&start);
            sim.set_noise_branch(PILOT_BRANCH - restarts);
        }
        if xs.len() < 10 {
            return Err(Error::invalid(
                "--basin",
                format!(
                    "the pilot run met the target {restarts} times and left {} values of the coordinate to place the basin and the interface",
                    xs.len()
                ),
                "a target that a direct run does not reach at once (the state must be metastable), or --basin and --interface given".into(),
            ));
        }
        xs.sort_by(f64::total_cmp);
        Ok(xs)
    }

    /// Run replicas `range` (0-based positions) on `threads` threads and
    /// hand each [`Replica`] to `sink` in replica order (`sink` returns
    /// `false` to stop). `Ok(false)` if stopped (by `sink` or the cancel
    /// flag; the replicas running are dropped). Errors: a range past the
    /// replicas, a bad thread count.
    pub fn run(
        &self,
        range: Range<usize>,
        threads: Option<usize>,
        hooks: Hooks<'_>,
        sink: &mut dyn FnMut(Replica) -> bool,
    ) -> Result<bool, Error> {
        let m = self.settings.replicas;
        if range.end > m || range.start > range.end {
            return Err(Error::invalid(
                "--replicas",
                format!("replicas {range:?} requested"),
                format!("within 0..{m}"),
            ));
        }
        // No more replicas at once than their particles fit in memory.
        let threads = Some(self.threads_within_memory(crate::analysis::sweep::threads(threads)?)?);
        let total = range.len().max(1);
        let mut done = 0;
        let job = |i: usize| -> Option<Replica> {
            match catch_unwind(AssertUnwindSafe(|| self.replica(i, hooks))) {
                Ok(Ok(r)) => Some(r),
                Ok(Err(Cancelled)) => None,
                Err(panic) => {
                    let msg = panic
                        .downcast_ref::<&str>()
                        .map(|s| s.to_string())
                        .or_else(|| panic.downcast_ref::<String>().cloned())
                        .unwrap_or_else(|| "unknown panic".into());
                    let mut r = self.empty_replica(i);
                    r.status = format!("panicked: {msg}");
                    Some(r)
                }
            }
        };
        run_ordered(range, threads, &job, &mut |r| match r {
            Some(r) => {
                done += 1;
                let go = sink(r);
                if let Some(p) = hooks.progress {
                    p(done as f64 / total as f64);
                }
                go
            }
            None => false,
        })
    }

    /// Run every replica and combine them ([`Ams::combine`]); `Ok(None)`
    /// if cancelled.
    pub fn estimate(
        &self,
        threads: Option<usize>,
        hooks: Hooks<'_>,
    ) -> Result<Option<Estimate>, Error> {
        let mut reps = Vec::with_capacity(self.settings.replicas);
        let complete = self.run(0..self.settings.replicas, threads, hooks, &mut |r| {
            reps.push(r);
            true
        })?;
        if !complete {
            return Ok(None);
        }
        self.combine(&reps).map(Some)
    }

    fn empty_replica(&self, index: usize) -> Replica {
        Replica {
            index,
            run: self.first_run() + index as u64,
            status: "ok".into(),
            particles: self.settings.particles,
            estimate: 0.0,
            weighted_duration: 0.0,
            hits: 0,
            extinct: false,
            iterations: 0,
            trajectories: 0,
            steps: 0,
            truncated: 0,
            failed: 0,
            first_failure: None,
            levels: Vec::new(),
            direct: None,
        }
    }

    /// Replica `index` (see the module doc). `Err` only when cancelled.
    fn replica(&self, index: usize, hooks: Hooks<'_>) -> Result<Replica, Cancelled> {
        let cancel = hooks.cancel;
        let s = &self.settings;
        let n = s.particles;
        let mut rep = self.empty_replica(index);
        let stream = Stream::new(self.seed(), rep.run);
        let sim = self.simulation(rep.run);
        let start = sim.snapshot();
        let mut runner = Runner {
            sim,
            watch: &self.watch,
            max_steps: s.max_steps,
            horizon: self.problem.horizon.is_some(),
            cancel,
            steps: 0,
            all_steps: hooks.steps,
            failed: 0,
            first_failure: None,
        };
        let mut next_branch = 0u64;
        let mut paths: Vec<Path> = Vec::with_capacity(n);
        match self.levels {
            None => {
                for _ in 0..n {
                    paths.push(runner.root(&start, next_branch)?);
                    next_branch += 1;
                }
            }
            Some(levels) => {
                let (direct, crossings) =
                    self.direct_phase(&mut runner, &start, levels, &mut next_branch)?;
                rep.direct = Some(direct);
                if crossings.is_empty() {
                    rep.status = format!(
                        "the direct run did not cross the interface {} > {} within --direct-steps {} steps",
                        self.problem.coordinate, levels.1, s.direct_steps
                    );
                    rep.steps = runner.steps;
                    return Ok(rep);
                }
                let draw = noise_counter(SELECT_BRANCH, 0);
                for i in 0..n {
                    let u = stream.uniform(draw, i as u64);
                    let c = ((u * crossings.len() as f64) as usize).min(crossings.len() - 1);
                    paths.push(runner.root(&crossings[c].start, next_branch)?);
                    next_branch += 1;
                }
            }
        }
        let mut trajectories = n as u64;
        let count_end = |p: &Path, rep: &mut Replica| {
            if p.end == End::Budget {
                rep.truncated += 1;
            }
        };
        for p in &paths {
            count_end(p, &mut rep);
        }
        let k = s.kill;
        let mut ln_weight = 0.0f64;
        let mut iteration = 0u64;
        let mut sorted = vec![0.0; n];
        loop {
            if cancel.is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed)) {
                return Err(Cancelled);
            }
            for (x, p) in sorted.iter_mut().zip(&paths) {
                *x = p.score;
            }
            sorted.sort_by(f64::total_cmp);
            let z = sorted[k - 1];
            if z == f64::INFINITY {
                break;
            }
            let killed: Vec<usize> = (0..n).filter(|&i| paths[i].score <= z).collect();
            let survivors: Vec<usize> = (0..n).filter(|&i| paths[i].score > z).collect();
            if survivors.is_empty() {
                rep.extinct = true;
                break;
            }
            let big_k = killed.len();
            if trajectories + big_k as u64 > s.max_trajectories
                || next_branch + big_k as u64 > MAX_TRAJECTORIES
            {
                rep.status = format!(
                    "--max-trajectories {} reached at level {} = {z} (P(above) ~ {:.3e}) before the target",
                    s.max_trajectories,
                    self.problem.coordinate,
                    ln_weight.exp()
                );
                break;
            }
            let kill_frac = match s.variant {
                Variant::Unbiased => big_k as f64 / n as f64,
                Variant::TieBlindWeight => k as f64 / n as f64,
            };
            ln_weight += (1.0 - kill_frac).ln();
            iteration += 1;
            rep.levels.push([z, ln_weight / std::f64::consts::LN_10]);
            if rep.levels.len() > MAX_STORED_LEVELS {
                let last = rep.levels[rep.levels.len() - 1];
                let mut k = 0;
                rep.levels.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                if rep.levels.last() != Some(&last) {
                    rep.levels.push(last);
                }
            }
            let draw = noise_counter(SELECT_BRANCH, iteration);
            let mut fresh = Vec::with_capacity(big_k);
            for (m, _) in killed.iter().enumerate() {
                let u = stream.uniform(draw, m as u64);
                let j = survivors[((u * survivors.len() as f64) as usize).min(survivors.len() - 1)];
                let p = runner.branch(&paths[j], z, next_branch)?;
                next_branch += 1;
                count_end(&p, &mut rep);
                fresh.push(p);
            }
            for (&i, p) in killed.iter().zip(fresh) {
                paths[i] = p;
            }
            trajectories += big_k as u64;
        }
        rep.iterations = iteration;
        rep.trajectories = trajectories;
        rep.steps = runner.steps;
        rep.failed = runner.failed;
        rep.first_failure = runner.first_failure.take();
        if rep.status == "ok" && !rep.extinct {
            let hits: Vec<&Path> = paths.iter().filter(|p| p.end == End::Target).collect();
            rep.hits = hits.len() as u64;
            let w = ln_weight.exp() / n as f64;
            rep.estimate = w * hits.len() as f64;
            rep.weighted_duration = w * hits.iter().map(|p| p.end_time - p.root_time).sum::<f64>();
        }
        Ok(rep)
    }

    /// The direct run of a replica (mean first-passage time): from the
    /// initial state until `crossings` crossings of the interface (or the
    /// budget), restarting from the initial state (a new branch) when it
    /// meets the target.
    fn direct_phase(
        &self,
        runner: &mut Runner<'_>,
        start: &Snapshot,
        (basin, interface): (f64, f64),
        next_branch: &mut u64,
    ) -> Result<(DirectPhase, Vec<Crossing>), Cancelled> {
        let s = &self.settings;
        let watch = &self.watch;
        let cancel = runner.cancel;
        let sim = &mut runner.sim;
        sim.restore(start);
        sim.set_noise_branch(*next_branch);
        *next_branch += 1;
        let mut d = DirectPhase::default();
        let mut crossings = Vec::new();
        let mut armed = true;
        let mut last: Option<f64> = None;
        let mut used = 0u64;
        #[derive(PartialEq)]
        enum Why {
            None,
            Target,
            Crossing,
            Budget,
            Cancel,
        }
        while crossings.len() < s.crossings {
            let mut why = Why::None;
            let stopped = sim.advance_until(&mut |p| {
                used += 1;
                let (xi, target, _) = watch.eval(p);
                if target {
                    why = Why::Target;
                    return true;
                }
                if armed {
                    if xi > interface {
                        why = Why::Crossing;
                        return true;
                    }
                } else if xi <= basin {
                    armed = true;
                }
                if used >= s.direct_steps {
                    why = Why::Budget;
                    return true;
                }
                if used % 1024 == 0
                    && cancel.is_some_and(|c| c.load(std::sync::atomic::Ordering::Relaxed))
                {
                    why = Why::Cancel;
                    return true;
                }
                false
            });
            if !stopped {
                if let Some(e) = sim.error() {
                    runner.failed += 1;
                    runner.first_failure.get_or_insert_with(|| e.to_string());
                }
                break;
            }
            let t = sim.time();
            let crossing = why == Why::Crossing || (why == Why::Target && armed);
            if crossing {
                match last {
                    None => {
                        d.first_crossing_sum += t;
                        d.first_crossing_count += 1;
                    }
                    Some(tp) => {
                        d.cycle_sum += t - tp;
                        d.cycle_count += 1;
                    }
                }
                crossings.push(Crossing {
                    start: sim.snapshot(),
                });
                last = Some(t);
                armed = false;
            }
            match why {
                Why::Target if *next_branch >= MAX_TRAJECTORIES / 2 => {
                    // No branch left for a restart (the direct run met the
                    // target millions of times: the state is not metastable).
                    d.hits += 1;
                    break;
                }
                Why::Target => {
                    d.hits += 1;
                    sim.restore(start);
                    sim.set_noise_branch(*next_branch);
                    *next_branch += 1;
                    armed = true;
                    last = None;
                }
                Why::Budget => break,
                Why::Cancel => return Err(Cancelled),
                _ => {}
            }
            if used >= s.direct_steps {
                break;
            }
        }
        runner.count(used);
        d.steps = used;
        d.crossings = crossings.len() as u64;
        Ok((d, crossings))
    }

    /// Combine replicas (all of them, in any order of delivery but given
    /// in replica order) into the estimate and its interval (see the
    /// module doc). Errors: a replica without an estimate (its status: the
    /// budget or a failure; [`Error::Runtime`]), fewer than 2 replicas,
    /// replicas of another number of particles ([`Error::Invalid`]).
    pub fn combine(&self, replicas: &[Replica]) -> Result<Estimate, Error> {
        let n = self.settings.particles;
        let m = replicas.len();
        if m < 2 {
            return Err(Error::invalid(
                "--replicas",
                format!("{m} replicas to combine"),
                "2 or more".into(),
            ));
        }
        if let Some(r) = replicas.iter().find(|r| r.particles != n) {
            return Err(Error::invalid(
                "merge",
                format!("replica {} has {} particles, not {n}", r.index, r.particles),
                "replicas of one problem and one set of sizes".into(),
            ));
        }
        if let Some(r) = replicas.iter().find(|r| r.status != "ok") {
            return Err(Error::runtime(
                0.0,
                Failure::StepLimit,
                format!("replica {} has no estimate: {}", r.index, r.status),
            ));
        }
        let sum = |f: &dyn Fn(&Replica) -> u64| replicas.iter().map(f).sum::<u64>();
        let first_failure = replicas.iter().find_map(|r| r.first_failure.clone());
        let ps: Vec<f64> = replicas.iter().map(|r| r.estimate).collect();
        let (p, sd) = stats::mean_sd(&ps).expect("two or more replicas");
        let se = sd / (m as f64).sqrt();
        let t = t975(m as u64 - 1);
        let extinct = ps.iter().all(|&x| x == 0.0);
        let mut est = Estimate {
            quantity: self.quantity(),
            method: "ams",
            estimate: p,
            ci95: [(p - t * se).max(0.0), p + t * se],
            standard_error: se,
            interval: "student_t",
            ci95_lognormal: stats::lognormal_mean_ci(&ps).map(|x| x.1),
            extinct,
            replicas: m,
            particles: n,
            iterations: sum(&|r| r.iterations),
            trajectories: sum(&|r| r.trajectories),
            steps: sum(&|r| r.steps),
            truncated: sum(&|r| r.truncated),
            failed: sum(&|r| r.failed),
            first_failure,
            flux: None,
        };
        let rule_of_three = 1.0 - 0.05f64.powf(1.0 / (n * m) as f64);
        if extinct {
            est.ci95 = [0.0, rule_of_three];
            est.interval = "rule_of_three";
        }
        let Some((basin, interface)) = self.levels else {
            return Ok(est);
        };
        // The flux relation τ = T1 + C (1/p − 1) + S at the replica means.
        let direct = |r: &Replica| r.direct.clone().unwrap_or_default();
        let rows: Vec<Vec<f64>> = replicas
            .iter()
            .map(|r| {
                let d = direct(r);
                vec![
                    r.estimate,
                    r.weighted_duration,
                    d.first_crossing_sum,
                    d.first_crossing_count as f64,
                    d.cycle_sum,
                    d.cycle_count as f64,
                ]
            })
            .collect();
        let mean: Vec<f64> = (0..6)
            .map(|j| rows.iter().map(|r| r[j]).sum::<f64>() / m as f64)
            .collect();
        let [pm, qm, t1s, t1c, cs, cc] = [mean[0], mean[1], mean[2], mean[3], mean[4], mean[5]];
        if t1c == 0.0 || cc == 0.0 {
            return Err(Error::runtime(
                0.0,
                Failure::StepLimit,
                format!(
                    "the direct runs measured {} first crossings and {} cycles of the interface: raise --crossings or --direct-steps",
                    sum(&|r| direct(r).first_crossing_count),
                    sum(&|r| direct(r).cycle_count)
                ),
            ));
        }
        let t1 = t1s / t1c;
        let c = cs / cc;
        let mut flux = Flux {
            basin,
            interface,
            probability: pm,
            probability_se: se,
            first_crossing_time: t1,
            cycle_time: c,
            transit_time: (pm > 0.0).then(|| qm / pm),
            cycles: sum(&|r| direct(r).cycle_count),
            direct_hits: sum(&|r| direct(r).hits),
            rate: 0.0,
        };
        if extinct {
            // p <= the rule of three's bound: τ >= T1 + C (1/p_ub − 1).
            let lower = t1 + c * (1.0 / rule_of_three - 1.0);
            est.estimate = lower;
            est.ci95 = [lower, f64::INFINITY];
            est.standard_error = f64::INFINITY;
            est.interval = "bound";
            est.ci95_lognormal = None;
            flux.rate = 1.0 / lower;
            est.flux = Some(flux);
            return Ok(est);
        }
        let tau = t1 + c * (1.0 / pm - 1.0) + qm / pm;
        let grad = [
            -(c + qm) / (pm * pm),
            1.0 / pm,
            1.0 / t1c,
            -t1s / (t1c * t1c),
            (1.0 / pm - 1.0) / cc,
            -(1.0 / pm - 1.0) * cs / (cc * cc),
        ];
        let se_tau = stats::delta_variance(&rows, &grad).sqrt();
        let f = (t * se_tau / tau).exp();
        est.estimate = tau;
        est.ci95 = [tau / f, tau * f];
        est.standard_error = se_tau;
        est.interval = "lognormal_delta";
        est.ci95_lognormal = None;
        flux.rate = 1.0 / tau;
        est.flux = Some(flux);
        Ok(est)
    }

    /// Direct simulation, for cross-checks: `runs` plain paths from the
    /// initial state (run `i` on the stream run `thermal.run + i`, a
    /// reserved branch: independent of every replica), each until the
    /// target or the reset (or the horizon, or the budget), watched at
    /// every step. Probability: `hits/runs` with Wilson's interval; mean
    /// first-passage time: the mean over the runs with Student's t interval
    /// (a run cut by the budget is `truncated`, its time left out: the mean
    /// is then biased low). `Ok(None)` if cancelled. Errors: `runs` out of
    /// `1 ..` (key `--runs`), a bad thread count.
    pub fn direct(
        &self,
        runs: usize,
        threads: Option<usize>,
        hooks: Hooks<'_>,
    ) -> Result<Option<Estimate>, Error> {
        if runs == 0 || (runs as u64) > MAX_RUNS - self.first_run() {
            return Err(Error::invalid(
                "--runs",
                format!("{runs} runs from thermal.run = {}", self.first_run()),
                "N >= 1 with thermal.run + N <= 4294967296".into(),
            ));
        }
        let watch = match self.problem.reset {
            Some(_) => self.watch.clone(),
            None => {
                let mut w = self.watch.clone();
                w.reset = Reset::Never;
                w
            }
        };
        let job = |i: usize| -> Option<(End, f64, u64, Option<String>)> {
            let sim = self.simulation(self.first_run() + i as u64);
            let start = sim.snapshot();
            let mut runner = Runner {
                sim,
                watch: &watch,
                max_steps: self.settings.max_steps,
                horizon: self.problem.horizon.is_some(),
                cancel: hooks.cancel,
                steps: 0,
                all_steps: hooks.steps,
                failed: 0,
                first_failure: None,
            };
            let p = runner.root(&start, DIRECT_BRANCH).ok()?;
            Some((
                p.end,
                p.end_time - p.root_time,
                runner.steps,
                runner.first_failure,
            ))
        };
        let mut out = Vec::with_capacity(runs);
        let every = (runs / 100).max(1);
        let complete = run_ordered(0..runs, threads, &job, &mut |r| match r {
            Some(r) => {
                out.push(r);
                if let Some(p) = hooks.progress {
                    if out.len() % every == 0 || out.len() == runs {
                        p(out.len() as f64 / runs as f64);
                    }
                }
                true
            }
            None => false,
        })?;
        if !complete {
            return Ok(None);
        }
        let hits = out.iter().filter(|r| r.0 == End::Target).count();
        let truncated = out.iter().filter(|r| r.0 == End::Budget).count() as u64;
        let failed = out.iter().filter(|r| r.0 == End::Failed).count() as u64;
        let mut est = Estimate {
            quantity: self.quantity(),
            method: "direct",
            estimate: 0.0,
            ci95: [0.0, 0.0],
            standard_error: 0.0,
            interval: "wilson",
            ci95_lognormal: None,
            extinct: hits == 0,
            replicas: runs,
            particles: 1,
            iterations: 0,
            trajectories: runs as u64,
            steps: out.iter().map(|r| r.2).sum(),
            truncated,
            failed,
            first_failure: out.iter().find_map(|r| r.3.clone()),
            flux: None,
        };
        match self.quantity() {
            Quantity::Probability => {
                let p = hits as f64 / runs as f64;
                est.estimate = p;
                est.standard_error = (p * (1.0 - p) / runs as f64).sqrt();
                est.ci95 = crate::analysis::bit::wilson(hits, runs, 1.959_963_984_540_054)
                    .unwrap_or([0.0, 1.0]);
            }
            Quantity::MeanFirstPassageTime => {
                let times: Vec<f64> = out
                    .iter()
                    .filter(|r| r.0 == End::Target)
                    .map(|r| r.1)
                    .collect();
                est.interval = "student_t";
                if let Some((mean, sd)) = stats::mean_sd(&times) {
                    let se = sd / (times.len() as f64).sqrt();
                    let t = t975(times.len() as u64 - 1);
                    est.estimate = mean;
                    est.standard_error = se;
                    est.ci95 = [(mean - t * se).max(0.0), mean + t * se];
                } else {
                    let longest = out.iter().map(|r| r.1).fold(0.0, f64::max);
                    est.estimate = times.first().copied().unwrap_or(longest);
                    est.ci95 = [est.estimate, f64::INFINITY];
                    est.standard_error = f64::INFINITY;
                    est.interval = "bound";
                }
            }
        }
        Ok(Some(est))
    }
}

/// What the records of the replicas of `s` may take at most \[bytes\]
/// (see [`Ams::records_bytes`]).
fn records_bytes(s: &Settings) -> u64 {
    let levels = s
        .max_trajectories
        .saturating_sub(s.particles as u64)
        .saturating_add(1)
        .min(MAX_STORED_LEVELS as u64 + 1);
    let one = (std::mem::size_of::<Replica>() as u64)
        .saturating_add(levels.saturating_mul(std::mem::size_of::<[f64; 2]>() as u64));
    (s.replicas as u64).saturating_mul(one).saturating_mul(2)
}

/// Check the sizes and budgets (keys: the CLI options).
fn check_settings(s: &Settings, first_run: u64) -> Result<(), Error> {
    let bad = |key: &str, what: String, range: String| Err(Error::invalid(key, what, range));
    if s.replicas < 2 || s.replicas as u64 > MAX_RUNS - first_run.min(MAX_RUNS) {
        return bad(
            "--replicas",
            format!("{} replicas from thermal.run = {first_run}", s.replicas),
            "M >= 2, with the runs thermal.run .. thermal.run + M - 1 below 4294967296".into(),
        );
    }
    if s.replicas > MAX_REPLICAS {
        return bad(
            "--replicas",
            format!("{} replicas", s.replicas),
            format!("2 <= M <= {MAX_REPLICAS}"),
        );
    }
    if !(2..=MAX_PARTICLES).contains(&s.particles) {
        return bad(
            "--particles",
            format!("{}", s.particles),
            format!("2 <= n <= {MAX_PARTICLES}"),
        );
    }
    if !(1..s.particles).contains(&s.kill) {
        return bad(
            "--kill",
            format!("{} of {} particles", s.kill, s.particles),
            "1 <= k < n (--particles)".into(),
        );
    }
    if !(s.particles as u64..=MAX_TRAJECTORIES).contains(&s.max_trajectories) {
        return bad(
            "--max-trajectories",
            format!("{}", s.max_trajectories),
            format!("n (--particles) <= N <= {MAX_TRAJECTORIES} per replica"),
        );
    }
    if !(1..=MAX_PATH_STEPS).contains(&s.max_steps) {
        return bad(
            "--max-steps",
            format!("{}", s.max_steps),
            format!("1 <= steps <= {MAX_PATH_STEPS} per path"),
        );
    }
    if !(1..=100_000).contains(&s.crossings) {
        return bad(
            "--crossings",
            format!("{}", s.crossings),
            "1 <= crossings <= 100000 per replica".into(),
        );
    }
    if !(1..=MAX_PATH_STEPS).contains(&s.direct_steps) {
        return bad(
            "--direct-steps",
            format!("{}", s.direct_steps),
            format!("1 <= steps <= {MAX_PATH_STEPS} per replica"),
        );
    }
    if !(1000..=10_000_000).contains(&s.pilot_steps) {
        return bad(
            "--pilot-steps",
            format!("{}", s.pilot_steps),
            "1000 <= steps <= 10000000".into(),
        );
    }
    let records = records_bytes(s);
    if records > crate::limits::MEMORY_BUDGET {
        return bad(
            "--replicas",
            format!(
                "{} replicas of up to --max-trajectories {} paths could keep {} of records",
                s.replicas,
                s.max_trajectories,
                crate::limits::fmt_bytes(records)
            ),
            format!(
                "at most {} per command: fewer --replicas or a lower --max-trajectories",
                crate::limits::fmt_bytes(crate::limits::MEMORY_BUDGET)
            ),
        );
    }
    for (key, v) in [("--basin", s.basin), ("--interface", s.interface)] {
        if let Some(v) = v {
            if !v.is_finite() {
                return bad(
                    key,
                    format!("{v}"),
                    "a finite level of the coordinate".into(),
                );
            }
        }
    }
    Ok(())
}
