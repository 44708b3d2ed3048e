//! The ε study: the regularised Coulomb law `μ N v/√(|v|² + ε²)` against the
//! exact stick/slip law as ε → 0 (docs/physics.md#coulomb).
//!
//! What is compared, for each ε and for the exact law:
//! - the end state θ(t_end), ω(t_end);
//! - the time spent rolling: for the exact law the time in the rolling mode,
//!   for the regularised law the time with slip speed ≤ ε (its linear,
//!   "near-rolling" regime);
//! - the inversion time (first θ > π/2), if any;
//! - the cost in right-hand-side evaluations.

use serde::Serialize;

use crate::{Error, FrictionLaw, Scenario, Trajectory, simulate};

/// One row of the ε study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EpsRow {
    /// ε \[m/s\]; `None` for the exact law.
    pub eps: Option<f64>,
    /// θ at the end \[rad\].
    pub theta_final: f64,
    /// ω at the end \[rad/s\].
    pub omega_final: f64,
    /// Fraction of the time rolling (exact) or with slip ≤ ε (regularised).
    pub rolling_fraction: f64,
    /// First time θ > π/2 \[s\], if any.
    pub inversion_time: Option<f64>,
    /// Right-hand-side evaluations.
    pub rhs_evaluations: u64,
    /// "ok" or the error.
    pub status: String,
}

/// Run `base` with the exact law and with the regularised law for each ε.
/// Returns the rows (exact first) and the trajectories in the same order.
pub fn eps_study(base: &Scenario, eps: &[f64]) -> Result<Vec<(EpsRow, Trajectory)>, Error> {
    let mut out = Vec::new();
    let mut sc = base.clone();
    sc.surface.law = FrictionLaw::Coulomb;
    let tr = simulate(&sc)?;
    out.push((
        EpsRow {
            eps: None,
            theta_final: tr.summary.theta_final,
            omega_final: tr.summary.omega_final,
            rolling_fraction: tr.summary.rolling_fraction,
            inversion_time: tr.summary.first_time_theta_above_half_pi,
            rhs_evaluations: tr.summary.rhs_evaluations,
            status: tr.summary.status.clone(),
        },
        tr,
    ));
    for &e in eps {
        let mut sc = base.clone();
        sc.surface.law = FrictionLaw::Regularized { eps: e };
        let tr = simulate(&sc)?;
        let n = tr.samples.len().max(1) as f64;
        let near = tr.samples.iter().filter(|s| s.slip <= e).count() as f64 / n;
        out.push((
            EpsRow {
                eps: Some(e),
                theta_final: tr.summary.theta_final,
                omega_final: tr.summary.omega_final,
                rolling_fraction: near,
                inversion_time: tr.summary.first_time_theta_above_half_pi,
                rhs_evaluations: tr.summary.rhs_evaluations,
                status: tr.summary.status.clone(),
            },
            tr,
        ));
    }
    Ok(out)
}

/// The study as a Markdown table.
pub fn eps_table(rows: &[EpsRow]) -> String {
    let mut s = String::from(
        "| friction law | θ(t_end) [rad] | ω(t_end) [rad/s] | time rolling (exact) / slip ≤ ε | first θ > π/2 [s] | RHS evaluations | status |\n|---|---|---|---|---|---|---|\n",
    );
    for r in rows {
        s.push_str(&format!(
            "| {} | {:.6} | {:.6} | {:.1}% | {} | {} | {} |\n",
            r.eps
                .map(|e| format!("regularised ε = {e:e} m/s"))
                .unwrap_or_else(|| "exact Coulomb".into()),
            r.theta_final,
            r.omega_final,
            100.0 * r.rolling_fraction,
            r.inversion_time
                .map(|t| format!("{t:.4}"))
                .unwrap_or_else(|| "never".into()),
            r.rhs_evaluations,
            r.status.replace('|', "/")
        ));
    }
    s
}
