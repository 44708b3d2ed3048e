//! The step check of a stochastic answer: the same question answered again
//! with the Langevin (or Brownian) step halved, and the change compared with
//! the answer's statistical interval (docs/physics.md#step-check).
//!
//! - [`refined`] is the scenario of the second answer: `solver.dt / 2`, a
//!   step limit twice as large, and an independent noise stream (the seed
//!   moved by [`REFINED_SEED_OFFSET`]), so the two answers are independent
//!   and their difference has the variance of the sum of theirs.
//! - [`StepCheck::new`] compares them: the step error is the change of the
//!   answer when the step is halved, `|x(dt/2) − x(dt)|` (for a quantity on
//!   a log scale, such as a mean escape time, `|ln x(dt/2) − ln x(dt)|`, a
//!   relative change); the statistical error is the 95 % half-width of the
//!   answer at `dt`. The answer is converged in the step when the step
//!   error is below the statistical one. For a scheme of weak order `p`
//!   the error of the answer at `dt` is `2^p/(2^p − 1)` times the change
//!   (4/3 for the Langevin splitting's `p = 2`, 2 for Euler–Maruyama's
//!   `p = 1`), so the change is the estimate of the step error that assumes
//!   no order; the answer at `dt/2`, whose error is the change divided by
//!   `2^p − 1`, is given beside it.
//!
//! When both answers carry no step error their difference is noise of
//! standard deviation `sqrt(2)` standard errors (equal intervals), and the
//! check then calls about 17 % of converged answers unconverged (`P(|Z| >
//! 1.96/sqrt 2)`): a false alarm costs a rerun at a smaller step, a false
//! "converged" would cost a wrong answer.

use serde::Serialize;

use crate::{Error, Scenario};

/// What the refined run adds to `thermal.seed` (wrapping): an odd constant
/// (the golden ratio's 64-bit fraction), so the refined run's streams are
/// not any of the seeds next to the scenario's.
pub const REFINED_SEED_OFFSET: u64 = 0x9E37_79B9_7F4A_7C15;

/// The scenario of the step check's second answer: `solver.dt / 2`, the
/// step limit doubled (capped at its largest valid value), the seed moved
/// by [`REFINED_SEED_OFFSET`]. Errors: not a Langevin or Brownian scenario
/// with a step, or the refined scenario invalid (the message names the key).
pub fn refined(sc: &Scenario) -> Result<Scenario, Error> {
    let dt = sc.solver.dt.ok_or_else(|| {
        Error::invalid(
            "solver.dt",
            "not set".to_string(),
            "the step check halves the Langevin or Brownian step solver.dt".into(),
        )
    })?;
    let mut r = sc.clone();
    r.solver.dt = Some(0.5 * dt);
    r.solver.max_steps = Some(
        sc.solver
            .step_limit()
            .saturating_mul(2)
            .min(crate::input::solver::STEP_LIMIT_MAX),
    );
    r.thermal.seed = sc.thermal.seed.map(|s| s.wrapping_add(REFINED_SEED_OFFSET));
    r.validate()?;
    Ok(r)
}

/// How two answers are compared: by their difference, or by the
/// difference of their logarithms (a relative change: escape times, rare
/// probabilities, whose intervals are log-normal).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Scale {
    /// `|x₂ − x₁|` against the half-width `(hi − lo)/2`.
    Linear,
    /// `|ln x₂ − ln x₁|` against `(ln hi − ln lo)/2`.
    Log,
}

/// One answer: the step it was computed with, the estimate and its 95 %
/// interval (the quantity's unit).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct AtStep {
    /// The step \[s\].
    pub dt: f64,
    /// The estimate.
    pub estimate: f64,
    /// Its 95 % interval `[lo, hi]`.
    pub ci95: [f64; 2],
}

/// The step check (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StepCheck {
    /// The comparison's scale.
    pub scale: Scale,
    /// The answer at the scenario's step.
    pub at_dt: AtStep,
    /// The answer at half that step (independent noise).
    pub at_half_dt: AtStep,
    /// The change when the step is halved: `|x(dt/2) − x(dt)|` (the
    /// quantity's unit) or `|ln x(dt/2) − ln x(dt)|` (1) on the log scale;
    /// `None` where it is undefined (an estimate 0 or not finite on the log
    /// scale).
    pub step_error: Option<f64>,
    /// The 95 % half-width of the answer at `dt`, on the same scale; `None`
    /// where the interval is open (an end not finite, or 0 on the log scale).
    pub statistical: Option<f64>,
    /// Whether the step error is below the statistical one.
    pub converged: bool,
}

impl StepCheck {
    /// Compare the answer at `dt` with the answer at `dt/2` on `scale`.
    pub fn new(at_dt: AtStep, at_half_dt: AtStep, scale: Scale) -> StepCheck {
        let (step_error, statistical) = match scale {
            Scale::Linear => (
                Some((at_half_dt.estimate - at_dt.estimate).abs()).filter(|d| d.is_finite()),
                Some(0.5 * (at_dt.ci95[1] - at_dt.ci95[0])).filter(|h| h.is_finite()),
            ),
            Scale::Log => {
                let ln = |x: f64| (x > 0.0 && x.is_finite()).then(|| x.ln());
                (
                    ln(at_half_dt.estimate)
                        .zip(ln(at_dt.estimate))
                        .map(|(b, a)| (b - a).abs()),
                    ln(at_dt.ci95[1])
                        .zip(ln(at_dt.ci95[0]))
                        .map(|(hi, lo)| 0.5 * (hi - lo)),
                )
            }
        };
        let converged = matches!((step_error, statistical), (Some(e), Some(s)) if e < s);
        StepCheck {
            scale,
            at_dt,
            at_half_dt,
            step_error,
            statistical,
            converged,
        }
    }

    /// The check in words, the numbers in `fmt` (a value with its unit):
    /// "at dt/2 = 2e-15 s: X (95 %: lo .. hi); the step error |Δ| = E
    /// (12.3 %) against the 95 % half-width S (37.1 %): converged".
    pub fn words(&self, fmt: &dyn Fn(f64) -> String) -> String {
        let h = &self.at_half_dt;
        let sig = |x: f64| crate::human::sig(x, 4);
        let amount = |x: Option<f64>| match (x, self.scale) {
            (None, _) => "undefined".to_string(),
            (Some(v), Scale::Linear) => fmt(v),
            (Some(v), Scale::Log) => format!("{} %", sig(100.0 * v.exp_m1())),
        };
        format!(
            "step check: at dt/2 = {} s {} (95 %: {} .. {}); the change {} against the 95 % half-width {}: {}",
            sig(h.dt),
            fmt(h.estimate),
            fmt(h.ci95[0]),
            fmt(h.ci95[1]),
            amount(self.step_error),
            amount(self.statistical),
            if self.converged {
                "converged in the step"
            } else {
                "NOT converged in the step (the step error is not below the statistical one: a smaller solver.dt)"
            }
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(dt: f64, x: f64, lo: f64, hi: f64) -> AtStep {
        AtStep {
            dt,
            estimate: x,
            ci95: [lo, hi],
        }
    }

    #[test]
    fn linear_change_below_the_half_width_is_converged() {
        let c = StepCheck::new(
            at(2.0, 0.50, 0.40, 0.60),
            at(1.0, 0.55, 0.45, 0.65),
            Scale::Linear,
        );
        assert!((c.step_error.unwrap() - 0.05).abs() < 1e-15);
        assert!((c.statistical.unwrap() - 0.10).abs() < 1e-15);
        assert!(c.converged);
        let c = StepCheck::new(
            at(2.0, 0.50, 0.40, 0.60),
            at(1.0, 0.61, 0.51, 0.71),
            Scale::Linear,
        );
        assert!(!c.converged);
    }

    #[test]
    fn log_scale_compares_relative_changes() {
        // x2 = 1.2 x1 with the interval x1 / 1.45 .. x1 * 1.45.
        let c = StepCheck::new(
            at(4e-15, 1.0, 1.0 / 1.45, 1.45),
            at(2e-15, 1.2, 1.2 / 1.45, 1.2 * 1.45),
            Scale::Log,
        );
        assert!((c.step_error.unwrap() - 1.2f64.ln()).abs() < 1e-15);
        assert!((c.statistical.unwrap() - 1.45f64.ln()).abs() < 1e-15);
        assert!(c.converged);
        let c = StepCheck::new(
            at(4e-15, 1.0, 1.0 / 1.1, 1.1),
            at(2e-15, 1.2, 1.2 / 1.1, 1.2 * 1.1),
            Scale::Log,
        );
        assert!(!c.converged);
    }

    #[test]
    fn an_open_interval_or_a_zero_estimate_is_not_converged() {
        let c = StepCheck::new(at(2.0, 0.0, 0.0, 1e-3), at(1.0, 0.0, 0.0, 1e-3), Scale::Log);
        assert_eq!(c.step_error, None);
        assert!(!c.converged);
        let c = StepCheck::new(
            at(2.0, 1.0, 0.5, f64::INFINITY),
            at(1.0, 1.0, 0.5, f64::INFINITY),
            Scale::Linear,
        );
        assert_eq!(c.statistical, None);
        assert!(!c.converged);
    }
}
