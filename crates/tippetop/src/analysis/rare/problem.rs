//! A rare-event question about a scenario and its answer by one method
//! (`tippetop rare`, Python's `tt.rare`; see the module [`super`]). No I/O.
//!
//! The question: from the scenario's initial state, with a `target`
//! condition and an optional `reset` condition (the grammar of `ensemble
//! --first-passage`, [`Exit`]) and an optional horizon `T`:
//!
//! - with a reset or a horizon, `p = P(target before reset and before T)`
//!   ([`Quantity::Probability`]);
//! - otherwise the mean first-passage time to the target
//!   ([`Quantity::MeanFirstPassageTime`]).
//!
//! A trajectory runs until it meets the target or the reset (checked at
//! the end of every step), bounded only by its step budget (`max_steps`)
//! or the horizon: `solver.t_end` and `solver.samples` do not cut it short.

use crate::analysis::ensemble::{self, Exit};
use crate::analysis::rare::ams::{self, Ams, Coordinate, Estimate, Flux, Replica, Settings};
use crate::analysis::rare::direct::{self, Tally};
use crate::analysis::rare::exact::{self, Exact, Quantity};
use crate::input::thermal::MAX_RUNS;
use crate::limits::MAX_STEPS;
use crate::{Error, Scenario, Simulation};

/// Default number of replicas of `direct`.
pub const DEFAULT_REPLICAS: usize = 1000;
/// Default step budget of one trajectory.
pub const DEFAULT_MAX_STEPS: u64 = 1_000_000;

/// The method that answers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RareMethod {
    /// The exact one-dimensional answer ([`exact`]).
    Exact,
    /// A plain ensemble ([`direct`]).
    Direct,
    /// Adaptive multilevel splitting ([`super::ams`]).
    Ams,
}

/// Valid values of `--method`.
pub const METHOD_RANGE: &str = "exact, direct or ams";

impl RareMethod {
    /// Parse `"exact"`, `"direct"` or `"ams"` (key `--method`).
    pub fn parse(s: &str) -> Result<RareMethod, Error> {
        match s {
            "exact" => Ok(RareMethod::Exact),
            "direct" => Ok(RareMethod::Direct),
            "ams" => Ok(RareMethod::Ams),
            other => Err(Error::invalid(
                "--method",
                format!("{other:?} is not a method"),
                METHOD_RANGE.into(),
            )),
        }
    }

    /// The name as parsed.
    pub fn name(self) -> &'static str {
        match self {
            RareMethod::Exact => "exact",
            RareMethod::Direct => "direct",
            RareMethod::Ams => "ams",
        }
    }
}

/// A rare-event question, checked.
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    /// The scenario (its initial state is the start).
    pub scenario: Scenario,
    /// The target condition.
    pub target: Exit,
    /// The reset condition, if any.
    pub reset: Option<Exit>,
    /// The horizon \[s\], if any.
    pub horizon: Option<f64>,
    /// The step budget of one trajectory.
    pub max_steps: u64,
}

/// `Exit::parse` with the error under `key` instead of `--first-passage`.
fn parse_cond(spec: &str, key: &str) -> Result<Exit, Error> {
    Exit::parse(spec).map_err(|e| match e {
        Error::Invalid { what, range, .. } => Error::invalid(key, what, range),
        other => other,
    })
}

impl Problem {
    /// Check a question: the scenario a stochastic run at `T > 0`
    /// ([`ensemble::check_scenario`]); `target` and `reset` in the
    /// `--first-passage` grammar (keys `--target`, `--reset`), neither
    /// holding at the start; `horizon` finite and `> 0`, within the step
    /// budget; `max_steps` in `1..=`[`MAX_STEPS`] (default
    /// [`DEFAULT_MAX_STEPS`]).
    pub fn new(
        scenario: Scenario,
        target: &str,
        reset: Option<&str>,
        horizon: Option<f64>,
        max_steps: Option<u64>,
    ) -> Result<Problem, Error> {
        ensemble::check_scenario(&scenario)?;
        let target = parse_cond(target, "--target")?;
        let reset = reset.map(|r| parse_cond(r, "--reset")).transpose()?;
        let max_steps = max_steps.unwrap_or(DEFAULT_MAX_STEPS);
        if !(1..=MAX_STEPS).contains(&max_steps) {
            return Err(Error::invalid(
                "--max-steps",
                format!("{max_steps}"),
                format!("1 to {MAX_STEPS} steps per trajectory"),
            ));
        }
        let dt = scenario.solver.dt.unwrap_or(f64::NAN);
        if let Some(t) = horizon {
            let steps = t / dt;
            let fits = t.is_finite() && t > 0.0 && steps <= max_steps as f64;
            if !fits {
                return Err(Error::invalid(
                    "--horizon",
                    format!("{t} s ({steps:.4e} steps of solver.dt = {dt} s)"),
                    format!(
                        "a finite time > 0 [s], at most --max-steps ({max_steps}) steps of solver.dt"
                    ),
                ));
            }
        }
        // The start: neither condition may already hold. The run's span
        // is the budget's (or the horizon), with two rows.
        let mut probe = scenario.clone();
        probe.solver.samples = 2;
        probe.solver.max_steps = Some(MAX_STEPS);
        probe.solver.t_end = horizon.unwrap_or(max_steps as f64 * dt);
        let start = Simulation::new(&probe)?.state();
        let v = start.values();
        for (key, cond) in [("--target", Some(&target)), ("--reset", reset.as_ref())] {
            if let Some(c) = cond {
                if c.hit(&v) {
                    return Err(Error::invalid(
                        key,
                        format!(
                            "{c} already holds at the start (theta = {} rad)",
                            start.theta
                        ),
                        "a condition the initial state does not meet".into(),
                    ));
                }
            }
        }
        Ok(Problem {
            scenario,
            target,
            reset,
            horizon,
            max_steps,
        })
    }

    /// [`Problem::new`] for the splitting: `max_steps` (a path's budget
    /// from its root) in `1..=`[`ams::MAX_PATH_STEPS`], default
    /// [`Settings::default`]'s (key `--max-steps`).
    pub fn for_ams(
        scenario: Scenario,
        target: &str,
        reset: Option<&str>,
        horizon: Option<f64>,
        max_steps: Option<u64>,
    ) -> Result<Problem, Error> {
        if let Some(m) = max_steps {
            if !(1..=ams::MAX_PATH_STEPS).contains(&m) {
                return Err(Error::invalid(
                    "--max-steps",
                    format!("{m}"),
                    format!(
                        "1 <= steps <= {} per path of --method ams",
                        ams::MAX_PATH_STEPS
                    ),
                ));
            }
        }
        let m = max_steps.unwrap_or(Settings::default().max_steps);
        Problem::new(scenario, target, reset, horizon, Some(m))
    }

    /// What the question asks.
    pub fn quantity(&self) -> Quantity {
        if self.reset.is_some() || self.horizon.is_some() {
            Quantity::Probability
        } else {
            Quantity::MeanFirstPassageTime
        }
    }

    /// The exact answer ([`exact::exact`]), `Err(Error::Invalid)` with the
    /// reason where it is not exact; a horizon is refused (the answer
    /// within a finite time needs the time-dependent solution).
    pub fn exact(&self) -> Result<Exact, Error> {
        if let Some(t) = self.horizon {
            return Err(Error::invalid(
                "--horizon",
                format!(
                    "no exact 1D answer within {t} s: that needs the time-dependent solution, not computed"
                ),
                "no --horizon with --method exact".into(),
            ));
        }
        exact::exact(&self.scenario, &self.target, self.reset.as_ref())
    }

    /// The time \[s\] a trajectory stops at: the horizon, or the end of its
    /// step budget.
    pub fn t_stop(&self) -> f64 {
        self.horizon
            .unwrap_or(self.max_steps as f64 * self.scenario.solver.dt.unwrap_or(0.0))
    }
}

/// The answer to a [`Problem`] by one method.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    /// What it is.
    pub quantity: Quantity,
    /// Which method.
    pub method: RareMethod,
    /// The estimate (\[1\] or \[s\]; a lower bound with censored runs).
    pub estimate: f64,
    /// Its 95 % interval (`[estimate, estimate]` for the exact method;
    /// the upper end `inf` when unknown).
    pub ci95: [f64; 2],
    /// Independent replicas (0 for the exact method).
    pub replicas: usize,
    /// Trajectories simulated.
    pub trajectories: u64,
    /// Steps simulated over all trajectories.
    pub steps: u64,
    /// The exact answer where it applies.
    pub exact: Option<Exact>,
    /// Why there is no exact answer (the refusal's message).
    pub exact_unavailable: Option<String>,
    /// The tallies of a direct ensemble.
    pub tally: Option<Tally>,
    /// The splitting's details (`--method ams`).
    pub ams: Option<AmsPart>,
}

/// What the splitting adds to a [`Report`].
#[derive(Debug, Clone, PartialEq)]
pub struct AmsPart {
    /// The reaction coordinate (canonical spec, [`Coordinate`]'s `Display`).
    pub coordinate: String,
    /// The sizes and budgets.
    pub settings: Settings,
    /// The combined estimate ([`Ams::combine`]).
    pub estimate: Estimate,
    /// The replicas, in replica order (their levels draw the picture).
    pub replicas: Vec<Replica>,
}

/// The exact answer beside a simulation: `(Some, None)` where it applies,
/// `(None, reason)` where not.
fn exact_beside(p: &Problem) -> (Option<Exact>, Option<String>) {
    match p.exact() {
        Ok(e) => (Some(e), None),
        Err(e) => (None, Some(e.to_string())),
    }
}

/// The exact method's report: `estimate` the exact value (`inf` beyond
/// f64: see [`Exact::value`]'s log), `ci95 = [estimate, estimate]`.
/// `Err(Error::Invalid)` where it is not exact (the reason).
pub fn by_exact(p: &Problem) -> Result<Report, Error> {
    let e = p.exact()?;
    let v = e.value.value;
    Ok(Report {
        quantity: e.quantity,
        method: RareMethod::Exact,
        estimate: v,
        ci95: [v, v],
        replicas: 0,
        trajectories: 0,
        steps: 0,
        exact: Some(e),
        exact_unavailable: None,
        tally: None,
        ams: None,
    })
}

/// The direct method's report: `replicas` runs (`1 <=` and the run
/// indices below 2^32, key `--replicas`) on `threads` threads, `progress`
/// called with the number of runs done after each (returning false stops
/// the ensemble: then `Err`, a run-time error "interrupted"). A probability with its
/// Wilson interval ([`Tally::probability`]), a mean time with its
/// t-interval ([`Tally::mean_time`]; NaN if every run failed).
/// The same bits for any thread count.
pub fn by_direct(
    p: &Problem,
    replicas: usize,
    threads: Option<usize>,
    progress: &mut dyn FnMut(usize) -> bool,
) -> Result<Report, Error> {
    let room = MAX_RUNS - p.scenario.thermal.run.min(MAX_RUNS);
    if replicas == 0 || replicas as u64 > room {
        return Err(Error::invalid(
            "--replicas",
            format!("{replicas} from thermal.run = {}", p.scenario.thermal.run),
            "N >= 1, with the run indices thermal.run .. thermal.run + N - 1 below 4294967296"
                .into(),
        ));
    }
    let mut tally = Tally::default();
    let mut done = 0;
    let complete = direct::run_replicas(
        &p.scenario,
        &p.target,
        p.reset.as_ref(),
        p.t_stop(),
        p.horizon.is_some(),
        replicas,
        threads,
        &mut |_, o| {
            tally.push(&o);
            done += 1;
            progress(done)
        },
    )?;
    if !complete {
        return Err(Error::runtime(
            0.0,
            crate::Failure::Numerics,
            format!("interrupted after {done} of {replicas} runs"),
        ));
    }
    let quantity = p.quantity();
    let (estimate, ci95) = match quantity {
        Quantity::Probability => tally.probability(),
        Quantity::MeanFirstPassageTime => tally
            .mean_time()
            .unwrap_or((f64::NAN, [0.0, f64::INFINITY])),
    };
    let (exact, exact_unavailable) = exact_beside(p);
    Ok(Report {
        quantity,
        method: RareMethod::Direct,
        estimate,
        ci95,
        replicas,
        trajectories: tally.runs(),
        steps: tally.steps,
        exact,
        exact_unavailable,
        tally: Some(tally),
        ams: None,
    })
}

/// The splitting of a question ([`Ams::new`]): the reaction coordinate
/// `coordinate` (`--coordinate`, [`Coordinate::parse`]; `None`: the
/// default, [`Coordinate::default_for`] the scenario and the target) and
/// `settings`, whose `max_steps` is replaced by the question's. Errors:
/// [`Error::Invalid`] naming the option (a coordinate that is not a
/// column, budgets out of range, a horizon without a reset, ...); a pilot
/// run that fails (mean first-passage time): its run-time error.
pub fn ams_for(p: &Problem, coordinate: Option<&str>, settings: Settings) -> Result<Ams, Error> {
    let coordinate = match coordinate {
        Some(c) => Coordinate::parse(c)?,
        None => Coordinate::default_for(&p.scenario, &p.target),
    };
    let settings = Settings {
        max_steps: p.max_steps,
        ..settings
    };
    Ams::new(
        ams::Problem {
            scenario: p.scenario.clone(),
            target: p.target.clone(),
            reset: p.reset.clone(),
            coordinate,
            horizon: p.horizon,
        },
        settings,
    )
}

/// The splitting's report from all the replicas of `ams` (made by
/// [`ams_for`] from `p`), in replica order: [`Ams::combine`] (its errors:
/// a replica without an estimate is a run-time error), the exact answer
/// beside it where it applies. The same bits for any thread count or
/// shard layout that delivers the same replicas.
pub fn by_ams(p: &Problem, ams: &Ams, replicas: Vec<Replica>) -> Result<Report, Error> {
    let est = ams.combine(&replicas)?;
    let (exact, exact_unavailable) = exact_beside(p);
    Ok(Report {
        quantity: p.quantity(),
        method: RareMethod::Ams,
        estimate: est.estimate,
        ci95: est.ci95,
        replicas: est.replicas,
        trajectories: est.trajectories,
        steps: est.steps,
        exact,
        exact_unavailable,
        tally: None,
        ams: Some(AmsPart {
            coordinate: ams.problem().coordinate.to_string(),
            settings: ams.settings().clone(),
            estimate: est,
            replicas,
        }),
    })
}

/// The splitting's part of [`Document`] (`--method ams`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AmsDoc {
    /// The reaction coordinate ξ (`--coordinate`, canonical).
    pub coordinate: String,
    /// Particles per replica `n`.
    pub particles: usize,
    /// Particles killed per iteration at least `k`.
    pub kill: usize,
    /// Most paths per replica.
    pub max_trajectories: u64,
    /// Mean first-passage time: crossing states per replica, the direct
    /// run's and the pilot run's step budgets.
    pub crossings: usize,
    /// The direct run's step budget (per replica).
    pub direct_steps: u64,
    /// The pilot run's steps.
    pub pilot_steps: u64,
    /// Standard error of `estimate` (\[1\] or \[s\]; null if unbounded).
    pub standard_error: f64,
    /// How `ci95` was made: `student_t`, `rule_of_three`,
    /// `lognormal_delta` or `bound`.
    pub interval: &'static str,
    /// Cox's log-normal interval of the replicas' mean (probability).
    pub ci95_lognormal: Option<[f64; 2]>,
    /// No particle of any replica met the target (estimate 0, or a lower
    /// bound for a time).
    pub extinct: bool,
    /// Splitting iterations (levels) over all replicas.
    pub iterations: u64,
    /// Paths cut by the step budget.
    pub truncated: u64,
    /// Paths that failed.
    pub failed: u64,
    /// The first failure's message.
    pub first_failure: Option<String>,
    /// Each replica's estimate (a probability; for a time, its `p`), in
    /// replica order.
    pub replica_estimates: Vec<f64>,
    /// The flux relation's parts (mean first-passage time).
    pub flux: Option<Flux>,
}

fn ams_doc(a: &AmsPart) -> AmsDoc {
    let (s, e) = (&a.settings, &a.estimate);
    AmsDoc {
        coordinate: a.coordinate.clone(),
        particles: s.particles,
        kill: s.kill,
        max_trajectories: s.max_trajectories,
        crossings: s.crossings,
        direct_steps: s.direct_steps,
        pilot_steps: s.pilot_steps,
        standard_error: e.standard_error,
        interval: e.interval,
        ci95_lognormal: e.ci95_lognormal,
        extinct: e.extinct,
        iterations: e.iterations,
        truncated: e.truncated,
        failed: e.failed,
        first_failure: e.first_failure.clone(),
        replica_estimates: a.replicas.iter().map(|r| r.estimate).collect(),
        flux: e.flux.clone(),
    }
}

/// An absorbing edge of the θ window in [`ExactDoc`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EdgeDoc {
    /// θ \[rad\].
    pub theta: f64,
    /// `"target"` or `"reset"`.
    pub role: &'static str,
}

/// The exact answer in [`Document`] (non-finite numbers are written as
/// null by JSON writers).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ExactDoc {
    /// The value for the continuous process (\[1\] or \[s\]; inf past f64).
    pub value: f64,
    /// Its natural log.
    pub ln_value: f64,
    /// The value for the path watched at every step of `solver.dt` (BGK).
    pub watched: Option<f64>,
    /// Its natural log.
    pub ln_watched: Option<f64>,
    /// `solver.dt` \[s\] of the watched value.
    pub watched_dt: Option<f64>,
    /// The start θ0 \[rad\].
    pub theta0: f64,
    /// The lower absorbing edge (null: the pole θ = 0, reflecting).
    pub lower: Option<EdgeDoc>,
    /// The upper absorbing edge (null: θ = π, reflecting).
    pub upper: Option<EdgeDoc>,
}

/// The tallies of a direct ensemble in [`Document`].
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TallyDoc {
    /// Runs that met the target.
    pub target: u64,
    /// Runs that met the reset.
    pub reset: u64,
    /// Runs that reached the horizon.
    pub horizon: u64,
    /// Runs that used their whole step budget.
    pub censored: u64,
    /// Runs that failed.
    pub failed: u64,
    /// The first failure's message.
    pub first_error: Option<String>,
}

/// `rare.json` (and Python's `tt.rare` dict): the report as a document.
/// Non-finite numbers (an upper bound that is unknown, an exact value past
/// f64) are written as null; `ln_estimate` stays finite.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Document {
    /// `"probability"` or `"mean_first_passage_time"`.
    pub quantity: &'static str,
    /// `""` or `"s"`.
    pub unit: &'static str,
    /// The estimate.
    pub estimate: f64,
    /// Its natural log (finite where the estimate overflows).
    pub ln_estimate: f64,
    /// The 95 % interval.
    pub ci95: [f64; 2],
    /// `"exact"`, `"direct"` or `"ams"`.
    pub method: &'static str,
    /// Independent replicas.
    pub replicas: usize,
    /// Trajectories simulated.
    pub trajectories: u64,
    /// Steps simulated.
    pub steps: u64,
    /// Wall-clock time \[s\] (the only field that changes between runs).
    pub wall_seconds: f64,
    /// The exact answer where it applies.
    pub exact: Option<ExactDoc>,
    /// Why there is none.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub exact_unavailable: Option<String>,
    /// The target condition (canonical form).
    pub target: String,
    /// The reset condition.
    pub reset: Option<String>,
    /// The horizon \[s\].
    pub horizon: Option<f64>,
    /// The step budget of one trajectory.
    pub max_steps: u64,
    /// The tallies of a direct ensemble.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tally: Option<TallyDoc>,
    /// The splitting's details (`--method ams`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ams: Option<AmsDoc>,
    /// `thermal.seed`.
    pub seed: Option<u64>,
    /// `thermal.run` of the first replica.
    pub first_run: u64,
    /// `thermal.temperature` \[K\].
    pub temperature: f64,
    /// The resolved scenario (TOML).
    pub scenario: String,
}

fn edge_doc(e: Option<exact::Edge>) -> Option<EdgeDoc> {
    e.map(|e| EdgeDoc {
        theta: e.theta,
        role: if e.target { "target" } else { "reset" },
    })
}

impl Report {
    /// The document of this report to `p`, with `wall_seconds` \[s\].
    pub fn document(&self, p: &Problem, wall_seconds: f64) -> Document {
        let ln_estimate = match (&self.exact, self.method) {
            (Some(e), RareMethod::Exact) => e.value.ln,
            _ => self.estimate.ln(),
        };
        Document {
            quantity: self.quantity.name(),
            unit: self.quantity.unit(),
            estimate: self.estimate,
            ln_estimate,
            ci95: self.ci95,
            method: self.method.name(),
            replicas: self.replicas,
            trajectories: self.trajectories,
            steps: self.steps,
            wall_seconds,
            exact: self.exact.map(|e| ExactDoc {
                value: e.value.value,
                ln_value: e.value.ln,
                watched: e.watched.map(|w| w.value),
                ln_watched: e.watched.map(|w| w.ln),
                watched_dt: p.scenario.solver.dt,
                theta0: e.theta0,
                lower: edge_doc(e.lower),
                upper: edge_doc(e.upper),
            }),
            exact_unavailable: self.exact_unavailable.clone(),
            target: p.target.to_string(),
            reset: p.reset.as_ref().map(|r| r.to_string()),
            horizon: p.horizon,
            max_steps: p.max_steps,
            tally: self.tally.as_ref().map(|t| TallyDoc {
                target: t.target,
                reset: t.reset,
                horizon: t.horizon,
                censored: t.censored,
                failed: t.failed,
                first_error: t.first_error.clone(),
            }),
            ams: self.ams.as_ref().map(ams_doc),
            seed: p.scenario.thermal.seed,
            first_run: p.scenario.thermal.run,
            temperature: p.scenario.thermal.temperature,
            scenario: p.scenario.to_toml_string(),
        }
    }
}
