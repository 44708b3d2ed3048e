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
use crate::analysis::rare::direct::{self, Tally};
use crate::analysis::rare::exact::{self, Exact, Quantity};
use crate::limits::MAX_STEPS;
use crate::thermal::MAX_RUNS;
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
            if !(t.is_finite() && t > 0.0) || !(steps <= max_steps as f64) {
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
    })
}

/// The direct method's report: `replicas` runs (`1 <=` and the run
/// indices below 2^32, key `--replicas`) on `threads` threads, `progress`
/// called with the number of runs done after each. A probability with its
/// Wilson interval ([`Tally::probability`]), a mean time with its
/// t-interval ([`Tally::mean_time`]; NaN if every run failed).
/// The same bits for any thread count.
pub fn by_direct(
    p: &Problem,
    replicas: usize,
    threads: Option<usize>,
    progress: &mut dyn FnMut(usize),
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
    direct::run_replicas(
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
            progress(done);
            true
        },
    )?;
    let quantity = p.quantity();
    let (estimate, ci95) = match quantity {
        Quantity::Probability => tally.probability(),
        Quantity::MeanFirstPassageTime => match tally.mean_time() {
            Some(m) => m,
            None => (f64::NAN, [0.0, f64::INFINITY]),
        },
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
    })
}
