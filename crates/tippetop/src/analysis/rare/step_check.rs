//! The step check of a rare-event answer (`tippetop rare` and Python's
//! `tt.rare`; docs/physics.md#step-check): the same question at
//! `solver.dt / 2` ([`crate::analysis::step_check::refined`]) with every
//! budget counted in steps doubled (within its range), so the paths cover
//! the same times; the two answers compared; and rare.json's fields that
//! carry the outcome. The caller runs the refined question (direct runs or
//! the splitting's replicas: it owns the threads, the progress and the
//! interruption); the rest is here.

use serde::Serialize;

use crate::Error;
use crate::analysis::rare::ams::{self, Ams, Replica, Settings};
use crate::analysis::rare::exact::Quantity;
use crate::analysis::rare::problem::{self, Document, Problem, RareMethod, Report};
use crate::analysis::step_check::{self, AtStep, Scale, StepCheck};
use crate::limits::MAX_STEPS;

/// Why the exact method has no step check (rare.json's `step_unchecked`).
pub const EXACT_UNCHECKED: &str =
    "the exact answer has no step: the continuous path's, and the path watched every solver.dt";

/// The largest `--pilot-steps` of the splitting.
const PILOT_STEPS_MAX: u64 = 10_000_000;

/// The step check of an answer: done, with the refined run's work, or the
/// reason it was not run.
#[derive(Debug, Clone, PartialEq)]
pub enum Checked {
    /// The answer again at `solver.dt / 2`.
    Done {
        /// The comparison.
        check: StepCheck,
        /// Trajectories of the refined run.
        trajectories: u64,
        /// Steps of the refined run.
        steps: u64,
    },
    /// Why the step is unchecked.
    Off(String),
}

impl Checked {
    /// The check of `coarse` (the answer to `p`) against `refined` (the
    /// answer to [`refined_problem`]`(p)`): a mean first-passage time of
    /// the splitting on the log scale (its interval is log-normal),
    /// everything else linear.
    pub fn of(p: &Problem, coarse: &Report, refined: &Report) -> Checked {
        let dt = p.scenario.solver.dt.unwrap_or(f64::NAN);
        let scale = if coarse.method == RareMethod::Ams
            && coarse.quantity == Quantity::MeanFirstPassageTime
        {
            Scale::Log
        } else {
            Scale::Linear
        };
        let at = |r: &Report, dt: f64| AtStep {
            dt,
            estimate: r.estimate,
            ci95: r.ci95,
        };
        Checked::Done {
            check: StepCheck::new(at(coarse, dt), at(refined, 0.5 * dt), scale),
            trajectories: refined.trajectories,
            steps: refined.steps,
        }
    }

    /// The check of a splitting's answer `coarse` (to `p`) from the refined
    /// splitting `fine` ([`refined_ams`]) and all its replicas, in replica
    /// order. A refined splitting without an answer, or with failed paths,
    /// makes the check say so instead of failing the answer at `dt`; bad
    /// input is an error.
    pub fn of_ams(
        p: &Problem,
        coarse: &Report,
        fine: &(Problem, Ams),
        replicas: Vec<Replica>,
    ) -> Result<Checked, Error> {
        let refined = match problem::by_ams(&fine.0, &fine.1, replicas) {
            Ok(r) => r,
            Err(e) if e.is_input() => return Err(e),
            Err(e) => {
                return Ok(Checked::Off(format!(
                    "the splitting at solver.dt/2 gave no answer: {e}"
                )));
            }
        };
        let failed = refined.ams.as_ref().map_or(0, |a| a.estimate.failed);
        if failed > 0 {
            return Ok(Checked::Off(format!(
                "{failed} paths of the splitting at solver.dt/2 failed"
            )));
        }
        Ok(Checked::of(p, coarse, &refined))
    }

    /// `dt_converged`: whether the step error is below the statistical
    /// one (`None`: unchecked).
    pub fn converged(&self) -> Option<bool> {
        match self {
            Checked::Done { check, .. } => Some(check.converged),
            Checked::Off(_) => None,
        }
    }

    /// rare.json: `doc` with the check's fields after it.
    pub fn document(&self, doc: Document) -> CheckedDocument<'_> {
        CheckedDocument {
            doc,
            dt_converged: self.converged(),
            step_check: match self {
                Checked::Done {
                    check,
                    trajectories,
                    steps,
                } => Some(StepCheckDoc {
                    check,
                    refined_trajectories: *trajectories,
                    refined_steps: *steps,
                    refined_seed_offset: step_check::REFINED_SEED_OFFSET,
                }),
                Checked::Off(_) => None,
            },
            step_unchecked: match self {
                Checked::Off(why) => Some(why.as_str()),
                Checked::Done { .. } => None,
            },
        }
    }
}

/// rare.json (and Python's `tt.rare` dict): the report's [`Document`],
/// then the step check's fields.
#[derive(Debug, Clone, Serialize)]
pub struct CheckedDocument<'a> {
    /// The answer at the scenario's step.
    #[serde(flatten)]
    pub doc: Document,
    /// Whether the step error is below the statistical one (`null`:
    /// unchecked).
    pub dt_converged: Option<bool>,
    /// The two answers and their comparison (`null`: unchecked).
    pub step_check: Option<StepCheckDoc<'a>>,
    /// Why the step is unchecked (absent when checked).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_unchecked: Option<&'a str>,
}

/// rare.json's `step_check`: the comparison, then the refined run's work.
#[derive(Debug, Clone, Serialize)]
pub struct StepCheckDoc<'a> {
    /// The comparison ([`StepCheck`]'s fields).
    #[serde(flatten)]
    pub check: &'a StepCheck,
    /// Trajectories of the refined run.
    pub refined_trajectories: u64,
    /// Steps of the refined run.
    pub refined_steps: u64,
    /// What the refined run added to `thermal.seed`.
    pub refined_seed_offset: u64,
}

/// The step check's question for `method` (direct or ams): `p`'s scenario
/// at `solver.dt / 2`, the same conditions and horizon, the step budget
/// doubled (within [`MAX_STEPS`] per trajectory, [`ams::MAX_PATH_STEPS`]
/// per path of the splitting). Errors: the refined scenario or budget
/// invalid (the key named).
pub fn refined_problem(p: &Problem, method: RareMethod) -> Result<Problem, Error> {
    let scenario = step_check::refined(&p.scenario)?;
    let target = p.target.to_string();
    let reset = p.reset.as_ref().map(|r| r.to_string());
    let (reset, horizon) = (reset.as_deref(), p.horizon);
    match method {
        RareMethod::Ams => {
            let m = p.max_steps.saturating_mul(2).min(ams::MAX_PATH_STEPS);
            Problem::for_ams(scenario, &target, reset, horizon, Some(m))
        }
        _ => {
            let m = p.max_steps.saturating_mul(2).min(MAX_STEPS);
            Problem::new(scenario, &target, reset, horizon, Some(m))
        }
    }
}

/// The splitting of the step check: [`refined_problem`] of `p`, and
/// `settings` (as given to [`problem::ams_for`] for `p`) with the direct
/// run's and the pilot run's budgets doubled within their ranges, on the
/// same `coordinate`. Runs the refined pilot run of a mean first-passage
/// time. Errors as [`problem::ams_for`]'s.
pub fn refined_ams(
    p: &Problem,
    coordinate: Option<&str>,
    settings: &Settings,
) -> Result<(Problem, Ams), Error> {
    let fine = refined_problem(p, RareMethod::Ams)?;
    let settings = Settings {
        direct_steps: settings
            .direct_steps
            .saturating_mul(2)
            .min(ams::MAX_PATH_STEPS),
        pilot_steps: settings.pilot_steps.saturating_mul(2).min(PILOT_STEPS_MAX),
        ..settings.clone()
    };
    let ams = problem::ams_for(&fine, coordinate, settings)?;
    Ok((fine, ams))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The nano top lying in the Brownian mode at 300 K.
    fn brownian() -> Problem {
        let sets: Vec<String> = [
            "surface.friction=0",
            "solver.method=brownian",
            "solver.dt=2e-15",
            "solver.t_end=1e-12",
            "solver.samples=2",
            "initial.theta=1.5707963267948966",
            "initial.spin=0",
            "thermal.temperature=300",
            "thermal.damping_translational=2.2e12",
            "thermal.damping_rotational=2.2e12",
            "thermal.seed=5",
        ]
        .map(String::from)
        .into();
        let sc = crate::Scenario::load(Some("nano"), None, &sets).unwrap();
        Problem::new(sc, "theta>1.75", Some("theta<1.3"), None, Some(600)).unwrap()
    }

    #[test]
    fn the_refined_question_halves_the_step_and_doubles_the_budget() {
        let p = brownian();
        let f = refined_problem(&p, RareMethod::Direct).unwrap();
        assert_eq!(f.scenario.solver.dt, Some(1e-15));
        assert_eq!(f.max_steps, 1200);
        assert_eq!((&f.target, &f.reset), (&p.target, &p.reset));
        let seed = p.scenario.thermal.seed.unwrap();
        assert_eq!(
            f.scenario.thermal.seed,
            Some(seed.wrapping_add(step_check::REFINED_SEED_OFFSET))
        );
        let big = Problem {
            max_steps: ams::MAX_PATH_STEPS - 1,
            ..p.clone()
        };
        let f = refined_problem(&big, RareMethod::Ams).unwrap();
        assert_eq!(f.max_steps, ams::MAX_PATH_STEPS);
    }

    #[test]
    fn the_document_says_why_the_step_is_unchecked() {
        let p = brownian();
        let r = problem::by_direct(&p, 4, Some(1), &mut |_| true).unwrap();
        let off = Checked::Off("why".into());
        let d = off.document(r.document(&p, 0.0));
        assert_eq!(
            (d.dt_converged, d.step_check.is_none(), d.step_unchecked),
            (None, true, Some("why"))
        );
        // A refined answer equal to the first: no change, converged.
        let done = Checked::of(&p, &r, &r);
        let Checked::Done { check, steps, .. } = &done else {
            panic!("{done:?}")
        };
        assert_eq!((check.at_half_dt.dt, check.step_error), (1e-15, Some(0.0)));
        assert_eq!(*steps, r.steps);
        let d = done.document(r.document(&p, 0.0));
        assert_eq!(d.dt_converged, Some(check.converged));
        assert!(d.step_unchecked.is_none());
    }
}
