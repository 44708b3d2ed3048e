//! The step check of a stochastic answer: the same question answered again
//! with the Langevin (or Brownian) step halved, and the change compared with
//! the answer's statistical interval (docs/physics.md#step-check).
//!
//! - [`refined`] is the scenario of the second answer: `solver.dt / 2`, a
//!   step limit twice as large, and an independent noise stream (the seed
//!   moved by [`REFINED_SEED_OFFSET`]), so the two answers are independent
//!   and their difference has the variance of the sum of theirs.
//! - [`StepCheck::new`] compares them. The step error is the change of the
//!   answer when the step is halved, `Δ = x(dt/2) − x(dt)` (for a quantity
//!   on a log scale, such as a mean escape time, `ln x(dt/2) − ln x(dt)`, a
//!   relative change). Its noise is that of two independent answers: the
//!   95 % half-width of `Δ` is `sqrt(w₁² + w₂²)`, `w` the answers' 95 %
//!   half-widths on the same scale. The answer is **converged in the step**
//!   when `|Δ|` is below that half-width: the step's effect is not resolved
//!   at the answer's own precision, so the step error is below the
//!   statistical one. Otherwise it is NOT converged: the step error is
//!   resolved and the answer is not given as converged.
//! - Several statistics judged together ([`StepCheck::in_family`], `m` of
//!   them: an ensemble's means, a bit's probabilities) widen each half-width
//!   by the Bonferroni factor `z(1 − 0.025/m)/1.96`, so that `m` answers
//!   with no step error raise a false alarm about 5 % of the time in all
//!   (without it, 7 statistics at 95 % each would raise one 30 % of the
//!   time).
//!
//! For a scheme of weak order `p` the error of the answer at `dt` is
//! `2^p/(2^p − 1)` times `Δ` (4/3 for the Langevin splitting's `p = 2`, 2
//! for Euler–Maruyama's `p = 1`), and the answer at `dt/2`'s is `Δ/(2^p −
//! 1)`: both are given, and `|Δ|` is the estimate of the step error that
//! assumes no order.

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

/// `z(1 − 0.025/m)` for `m` = 1 ..= 16, the standard normal's quantiles
/// (Python's `statistics.NormalDist().inv_cdf`, 4 decimals): the 95 %
/// half-width's factor of one of `m` statistics judged together.
const Z_FAMILY: [f64; 16] = [
    1.96, 2.2414, 2.394, 2.4977, 2.5758, 2.6383, 2.6901, 2.7344, 2.7729, 2.807, 2.8376, 2.8653,
    2.8905, 2.9137, 2.9352, 2.9552,
];

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
    /// The 95 % half-width of the change, `sqrt(w₁² + w₂²)` of the two
    /// answers' half-widths on the same scale (times the Bonferroni factor
    /// of a family); `None` where an interval is open (an end not finite,
    /// or 0 on the log scale).
    pub statistical: Option<f64>,
    /// The number of statistics judged together (1 alone).
    pub family: usize,
    /// Whether the step error is below the statistical one.
    pub converged: bool,
}

impl StepCheck {
    /// Compare the answer at `dt` with the answer at `dt/2` on `scale`.
    pub fn new(at_dt: AtStep, at_half_dt: AtStep, scale: Scale) -> StepCheck {
        StepCheck::in_family(at_dt, at_half_dt, scale, 1)
    }

    /// [`StepCheck::new`] for one of `family` statistics judged together
    /// (the Bonferroni factor, module docs; `family` 1 to 16, larger is
    /// taken as 16).
    pub fn in_family(at_dt: AtStep, at_half_dt: AtStep, scale: Scale, family: usize) -> StepCheck {
        let family = family.clamp(1, Z_FAMILY.len());
        let widen = Z_FAMILY[family - 1] / Z_FAMILY[0];
        let ln = |x: f64| (x > 0.0 && x.is_finite()).then(|| x.ln());
        let half = |a: &AtStep| match scale {
            Scale::Linear => Some(0.5 * (a.ci95[1] - a.ci95[0])).filter(|h| h.is_finite()),
            Scale::Log => ln(a.ci95[1])
                .zip(ln(a.ci95[0]))
                .map(|(hi, lo)| 0.5 * (hi - lo)),
        };
        let step_error = match scale {
            Scale::Linear => {
                Some((at_half_dt.estimate - at_dt.estimate).abs()).filter(|d| d.is_finite())
            }
            Scale::Log => ln(at_half_dt.estimate)
                .zip(ln(at_dt.estimate))
                .map(|(b, a)| (b - a).abs()),
        };
        let statistical = half(&at_dt)
            .zip(half(&at_half_dt))
            .map(|(a, b)| widen * a.hypot(b));
        let converged = matches!((step_error, statistical), (Some(e), Some(s)) if e < s);
        StepCheck {
            scale,
            at_dt,
            at_half_dt,
            step_error,
            statistical,
            family,
            converged,
        }
    }

    /// The check in words, the numbers in `fmt` (a value with its unit;
    /// a log-scale change as a percentage): "step check: at dt/2 = 2.000e-15
    /// s X (95 %: lo .. hi); the change 58.02 % against its 95 % half-width
    /// 65.26 %: converged in the step".
    pub fn words(&self, fmt: &dyn Fn(f64) -> String) -> String {
        let h = &self.at_half_dt;
        let sig = |x: f64| crate::human::sig(x, 4);
        let amount = |x: Option<f64>| match (x, self.scale) {
            (None, _) => "undefined".to_string(),
            (Some(v), Scale::Linear) => fmt(v),
            (Some(v), Scale::Log) => format!("{} %", sig(100.0 * v.exp_m1())),
        };
        format!(
            "step check: at dt/2 = {} s {} (95 %: {} .. {}); the change {} against its 95 % half-width {}: {}",
            sig(h.dt),
            fmt(h.estimate),
            fmt(h.ci95[0]),
            fmt(h.ci95[1]),
            amount(self.step_error),
            amount(self.statistical),
            if self.converged {
                "converged in the step"
            } else {
                "NOT converged in the step (halving the step moved the answer by more than the noise: a smaller solver.dt)"
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
    fn linear_change_within_its_noise_is_converged() {
        // Half-widths 0.1 and 0.1: the change's is 0.1 sqrt 2 = 0.1414.
        let c = StepCheck::new(
            at(2.0, 0.50, 0.40, 0.60),
            at(1.0, 0.63, 0.53, 0.73),
            Scale::Linear,
        );
        assert!((c.step_error.unwrap() - 0.13).abs() < 1e-15);
        assert!((c.statistical.unwrap() - 0.1 * 2f64.sqrt()).abs() < 1e-15);
        assert!(c.converged);
        let c = StepCheck::new(
            at(2.0, 0.50, 0.40, 0.60),
            at(1.0, 0.65, 0.55, 0.75),
            Scale::Linear,
        );
        assert!(!c.converged);
    }

    #[test]
    fn a_family_widens_each_half_width_by_bonferroni() {
        // 0.15 > 0.1414 alone, < 0.1414 * 2.6901/1.96 = 0.1941 as one of 7.
        let (a, b) = (at(2.0, 0.50, 0.40, 0.60), at(1.0, 0.65, 0.55, 0.75));
        assert!(!StepCheck::new(a, b, Scale::Linear).converged);
        let c = StepCheck::in_family(a, b, Scale::Linear, 7);
        let want = 0.1 * 2f64.sqrt() * 2.6901 / 1.96;
        assert!((c.statistical.unwrap() - want).abs() < 1e-12);
        assert!(c.converged);
        assert_eq!(c.family, 7);
        // The table's quantiles are the normal law's: z(1 - 0.025/m) from
        // the complementary error function's tail, P(Z > z) = 0.025/m.
        for (m, z) in Z_FAMILY.iter().enumerate() {
            let tail = 0.5 * erfc(z / 2f64.sqrt());
            let want = 0.025 / (m + 1) as f64;
            assert!((tail / want - 1.0).abs() < 2e-3, "m = {} z = {z}", m + 1);
        }
    }

    /// `erfc` by its continued fraction's classic rational fit
    /// (Numerical Recipes' `erfcc`, relative error below 1.2e-7).
    fn erfc(x: f64) -> f64 {
        let t = 1.0 / (1.0 + 0.5 * x.abs());
        let y = t
            * (-x * x - 1.26551223
                + t * (1.00002368
                    + t * (0.37409196
                        + t * (0.09678418
                            + t * (-0.18628806
                                + t * (0.27886807
                                    + t * (-1.13520398
                                        + t * (1.48851587
                                            + t * (-0.82215223 + t * 0.17087277)))))))))
                .exp();
        if x >= 0.0 { y } else { 2.0 - y }
    }

    #[test]
    fn log_scale_compares_relative_changes() {
        // x2 = 1.5 x1, each interval x / 1.45 .. x * 1.45: the change
        // ln 1.5 = 0.405 against ln(1.45) sqrt 2 = 0.525.
        let c = StepCheck::new(
            at(4e-15, 1.0, 1.0 / 1.45, 1.45),
            at(2e-15, 1.5, 1.5 / 1.45, 1.5 * 1.45),
            Scale::Log,
        );
        assert!((c.step_error.unwrap() - 1.5f64.ln()).abs() < 1e-15);
        assert!((c.statistical.unwrap() - 1.45f64.ln() * 2f64.sqrt()).abs() < 1e-15);
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
