//! Direct simulation of a rare-event question (see the module [`super`]):
//! a plain ensemble of independent runs, each until it meets the target or
//! the reset (or the horizon, or its step budget), with the conditions
//! checked at every step. The cross-check of the exact answers
//! ([`super::exact`]) and of the splitting sampler ([`super::ams`]). No I/O.
//!
//! Run `k` (`0 <= k < replicas`) is the scenario with `thermal.run = r0 + k`
//! (as `tippetop ensemble`'s run `k`), its `solver.t_end` and
//! `solver.samples` replaced: a run goes on until a condition holds at the
//! end of a step, or until `horizon` \[s\], or for `max_steps` steps. Its
//! noise is a pure function of `(thermal.seed, r0 + k, step)`, so the
//! outcomes, and everything computed from them in run order, are the same
//! bits whatever the thread count.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Arc, Mutex};

use crate::analysis::ensemble::Exit;
use crate::analysis::sweep;
use crate::{Error, Scenario, Simulation};

/// How one run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Ending {
    /// The target held at the end of a step (a tie with the reset goes to
    /// the target).
    Target,
    /// The reset held (and not the target).
    Reset,
    /// Neither, up to the horizon.
    Horizon,
    /// Neither, within the step budget (censored).
    Budget,
    /// The run failed (its error in [`Outcome::error`]).
    Failed,
}

/// The outcome of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    /// How it ended.
    pub ending: Ending,
    /// When \[s\]: the end of the step where a condition held, the horizon,
    /// the budget's end, or the failure.
    pub time: f64,
    /// Steps taken up to then.
    pub steps: u64,
    /// The error of a failed run.
    pub error: Option<String>,
}

/// Steps seen by the observer, and the first hit: (time \[s\], target?).
type Seen = (u64, Option<(f64, bool)>);

/// Steps per call to [`Simulation::integrate_to`] between checks of the
/// observer's flag (the steps past a hit are wasted, not counted).
const CHUNK: u64 = 512;

/// Run one trajectory of `sc` (its `thermal.run` set by the caller) until
/// `target` or `reset` holds at a step's end, the horizon `t_stop` \[s\]
/// (`horizon = true`) or `t_stop` as the step budget's end.
pub fn run_one(
    sc: &Scenario,
    target: &Exit,
    reset: Option<&Exit>,
    t_stop: f64,
    horizon: bool,
) -> Outcome {
    let failed = |e: String, t: f64, steps: u64| Outcome {
        ending: Ending::Failed,
        time: t,
        steps,
        error: Some(e),
    };
    let mut sc = sc.clone();
    sc.solver.t_end = t_stop;
    sc.solver.samples = 2;
    sc.solver.max_steps = Some(crate::limits::MAX_STEPS);
    let dt = sc.solver.dt.unwrap_or(t_stop);
    let seen: Arc<Mutex<Seen>> = Arc::new(Mutex::new((0, None)));
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<Outcome, Error> {
        let mut sim = Simulation::new(&sc)?.lean();
        {
            let seen = seen.clone();
            let (target, reset) = (target.clone(), reset.cloned());
            sim.set_observer(move |row| {
                let mut s = seen.lock().unwrap_or_else(|e| e.into_inner());
                if s.1.is_some() {
                    return;
                }
                s.0 += 1;
                let v = row.values();
                if target.hit(&v) {
                    s.1 = Some((row.t, true));
                } else if reset.as_ref().is_some_and(|r| r.hit(&v)) {
                    s.1 = Some((row.t, false));
                }
            });
        }
        let mut k: u64 = 0;
        loop {
            k += 1;
            let t = (dt * (k * CHUNK) as f64).min(t_stop);
            sim.integrate_to(t)?;
            let s = *seen.lock().unwrap_or_else(|e| e.into_inner());
            if let Some((time, is_target)) = s.1 {
                return Ok(Outcome {
                    ending: if is_target {
                        Ending::Target
                    } else {
                        Ending::Reset
                    },
                    time,
                    steps: s.0,
                    error: None,
                });
            }
            if let Some(e) = sim.error() {
                return Ok(failed(e.to_string(), sim.time(), s.0));
            }
            if sim.is_finished() || t >= t_stop {
                return Ok(Outcome {
                    ending: if horizon {
                        Ending::Horizon
                    } else {
                        Ending::Budget
                    },
                    time: sim.time(),
                    steps: s.0,
                    error: None,
                });
            }
        }
    }));
    let steps = seen.lock().map(|s| s.0).unwrap_or(0);
    match outcome {
        Ok(Ok(o)) => o,
        Ok(Err(e)) => failed(e.to_string(), 0.0, steps),
        Err(panic) => {
            let msg = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "unknown panic".into());
            failed(format!("panicked: {msg}"), 0.0, steps)
        }
    }
}

/// Run the replicas `0..replicas` of `sc` (run `k` with `thermal.run =
/// r0 + k`) on `threads` threads; `sink` gets each outcome in run order
/// (return false to stop). `t_stop` and `horizon` as [`run_one`].
#[allow(clippy::too_many_arguments)]
pub fn run_replicas(
    sc: &Scenario,
    target: &Exit,
    reset: Option<&Exit>,
    t_stop: f64,
    horizon: bool,
    replicas: usize,
    threads: Option<usize>,
    sink: &mut dyn FnMut(usize, Outcome) -> bool,
) -> Result<bool, Error> {
    let r0 = sc.thermal.run;
    let job = |k: usize| {
        let mut s = sc.clone();
        s.thermal.run = r0 + k as u64;
        (k, run_one(&s, target, reset, t_stop, horizon))
    };
    sweep::run_ordered(0..replicas, threads, &job, &mut |(k, o)| sink(k, o))
}

/// The two-sided 97.5 % quantile of Student's t with `dof` degrees of
/// freedom (`dof >= 1`): exact to 9 digits for 1 to 4, the Cornish–Fisher
/// expansion in `1/dof` (Abramowitz & Stegun 26.7.5, four terms, error
/// below 1e-4 at 5 and falling as `dof^-5`) beyond.
pub fn t975(dof: u64) -> f64 {
    match dof {
        0 => f64::NAN,
        1 => 12.706_204_736,
        2 => 4.302_652_730,
        3 => 3.182_446_305,
        4 => 2.776_445_105,
        _ => {
            let z: f64 = 1.959_963_984_540_054;
            let v = dof as f64;
            let (z3, z5, z7, z9) = (z.powi(3), z.powi(5), z.powi(7), z.powi(9));
            let g1 = (z3 + z) / 4.0;
            let g2 = (5.0 * z5 + 16.0 * z3 + 3.0 * z) / 96.0;
            let g3 = (3.0 * z7 + 19.0 * z5 + 17.0 * z3 - 15.0 * z) / 384.0;
            let g4 = (79.0 * z9 + 776.0 * z7 + 1482.0 * z5 - 1920.0 * z3 - 945.0 * z) / 92160.0;
            z + g1 / v + g2 / (v * v) + g3 / v.powi(3) + g4 / v.powi(4)
        }
    }
}

/// The tallies of a direct ensemble, fed outcomes in run order.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Tally {
    /// Runs that met the target.
    pub target: u64,
    /// Runs that met the reset.
    pub reset: u64,
    /// Runs that reached the horizon.
    pub horizon: u64,
    /// Runs that used their whole step budget (censored).
    pub censored: u64,
    /// Runs that failed.
    pub failed: u64,
    /// Steps over all runs (up to each run's ending).
    pub steps: u64,
    /// The first failure's message, if any.
    pub first_error: Option<String>,
    /// Welford's count, mean and sum of squares of `min(T, budget)` over
    /// the runs that met the target or were censored.
    n: u64,
    mean: f64,
    m2: f64,
}

impl Tally {
    /// Add one outcome.
    pub fn push(&mut self, o: &Outcome) {
        self.steps += o.steps;
        match o.ending {
            Ending::Target => {
                self.target += 1;
                self.add_time(o.time);
            }
            Ending::Reset => self.reset += 1,
            Ending::Horizon => self.horizon += 1,
            Ending::Budget => {
                self.censored += 1;
                self.add_time(o.time);
            }
            Ending::Failed => {
                self.failed += 1;
                if self.first_error.is_none() {
                    self.first_error = o.error.clone();
                }
            }
        }
    }

    fn add_time(&mut self, t: f64) {
        self.n += 1;
        let d = t - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (t - self.mean);
    }

    /// Runs counted.
    pub fn runs(&self) -> u64 {
        self.target + self.reset + self.horizon + self.censored + self.failed
    }

    /// `P(target first)` \[1\] with its 95 % interval: the Wilson score
    /// interval of the target's count among the runs, its upper end taken
    /// with every undecided run (censored or failed) counted as a hit, its
    /// lower end with none: the estimate is `target/runs`, a lower bound
    /// when runs are undecided.
    pub fn probability(&self) -> (f64, [f64; 2]) {
        let n = self.runs() as usize;
        if n == 0 {
            return (f64::NAN, [0.0, 1.0]);
        }
        let k = self.target as usize;
        let undecided = (self.censored + self.failed) as usize;
        let lo = crate::analysis::bit::wilson(k, n, crate::analysis::ensemble::Z95).unwrap()[0];
        let hi = crate::analysis::bit::wilson(k + undecided, n, crate::analysis::ensemble::Z95)
            .unwrap()[1];
        (k as f64 / n as f64, [lo, hi])
    }

    /// The mean first-passage time \[s\] with its 95 % interval
    /// `mean ± t_{0.975, n−1} s/sqrt(n)` over the runs that met the target.
    /// With censored runs (no hit within the budget) it is the mean of
    /// `min(T, budget)` over the hits and the censored runs, a lower bound
    /// of the mean, and the interval's upper end is `inf` (unknown). `None`
    /// when no run met the target or was censored (all failed).
    pub fn mean_time(&self) -> Option<(f64, [f64; 2])> {
        if self.n == 0 {
            return None;
        }
        let half = if self.n > 1 {
            t975(self.n - 1) * (self.m2 / (self.n - 1) as f64).sqrt() / (self.n as f64).sqrt()
        } else {
            f64::INFINITY
        };
        let lo = (self.mean - half).max(0.0);
        let hi = if self.censored == 0 {
            self.mean + half
        } else {
            f64::INFINITY
        };
        Some((self.mean, [lo, hi]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn student_quantiles_against_tables() {
        // Published two-sided 95 % values (e.g. NIST/SEMATECH e-Handbook,
        // table 1.3.6.7.2).
        for (dof, want) in [
            (5, 2.571),
            (10, 2.228),
            (20, 2.086),
            (30, 2.042),
            (100, 1.984),
        ] {
            assert!(
                (t975(dof) - want).abs() < 1e-3,
                "dof {dof}: {} against {want}",
                t975(dof)
            );
        }
        assert!((t975(1_000_000) - 1.959964).abs() < 1e-5);
    }

    #[test]
    fn undecided_runs_widen_the_interval_upwards() {
        let mut t = Tally::default();
        let o = |ending, time| Outcome {
            ending,
            time,
            steps: 10,
            error: None,
        };
        for _ in 0..30 {
            t.push(&o(Ending::Target, 1.0));
        }
        for _ in 0..60 {
            t.push(&o(Ending::Reset, 1.0));
        }
        let (p, ci) = t.probability();
        assert_eq!(p, 30.0 / 90.0);
        let want = crate::analysis::bit::wilson(30, 90, 1.96).unwrap();
        assert_eq!(ci, want);
        for _ in 0..10 {
            t.push(&o(Ending::Budget, 5.0));
        }
        let (p, ci) = t.probability();
        assert_eq!(p, 0.3);
        assert_eq!(
            ci[0],
            crate::analysis::bit::wilson(30, 100, 1.96).unwrap()[0]
        );
        assert_eq!(
            ci[1],
            crate::analysis::bit::wilson(40, 100, 1.96).unwrap()[1]
        );
        // The mean time is a lower bound with censored runs.
        let (m, ci) = t.mean_time().unwrap();
        assert_eq!(m, (30.0 + 50.0) / 40.0);
        assert!(ci[1].is_infinite());
        assert_eq!(t.steps, 1000);
    }
}
