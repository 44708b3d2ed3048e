//! The step check of an ensemble (`tippetop ensemble` and Python's
//! `tt.ensemble`; docs/physics.md#step-check): the same runs again on the
//! scenario at `solver.dt / 2` ([`crate::analysis::step_check::refined`]),
//! every statistic with a 95 % interval compared with its value there, and
//! summary.json's fields that carry the outcome.
//!
//! The statistics checked: the means of the final θ, ω, Ω and energy and
//! of the observed passage times (by their difference), the censored
//! fraction (its Wilson 95 % interval) and the escape rate (by the ratio,
//! on a log scale), judged together (each half-width widened by the
//! family's Bonferroni factor, [`StepCheck::in_family`]).

use serde::Serialize;
use serde::ser::SerializeMap;

use super::{Ensemble, EnsembleStats, FirstPassage, MeanCi, StatsAcc, Z95, csv_row};
use crate::Error;
use crate::analysis::step_check::{self, AtStep, Scale, StepCheck};
use crate::analysis::sweep::Shard;

/// One checked statistic: its name in summary.json (a path through its
/// objects, `first_passage.escape_rate`), the unit of its values (`""`
/// for a fraction), the comparison.
pub type Check = (&'static str, &'static str, StepCheck);

/// What the step check of one ensemble does.
#[derive(Debug, Clone, PartialEq)]
pub enum Plan {
    /// Run the ensemble again as this one: the scenario at `solver.dt / 2`,
    /// the same runs and first-passage criterion.
    Run(Box<Ensemble>),
    /// No check, and why (summary.json's `step_unchecked`).
    Off(String),
}

/// The step check's plan for the runs `shard` of `ens`: off for a shard
/// (it compares the whole ensemble's statistics) and for one run (no
/// interval); else the refined ensemble. Error: the refined scenario is
/// invalid (the key named, and `switch`, the option that turns the check
/// off, e.g. `--no-step-check`).
pub fn plan(ens: &Ensemble, shard: Shard, switch: &str) -> Result<Plan, Error> {
    if shard != Shard::ALL {
        return Ok(Plan::Off(format!(
            "sharded (--shard {}/{}): the check compares the whole ensemble's statistics; run the \
             ensemble without --shard, or at --set solver.dt=DT/2 and compare",
            shard.k, shard.n
        )));
    }
    if ens.runs < 2 {
        return Ok(Plan::Off(
            "one run: no statistic has a 95 % interval".into(),
        ));
    }
    let scenario = step_check::refined(&ens.scenario).map_err(|e| match e {
        Error::Invalid { key, what, range } => Error::Invalid {
            key,
            what: format!("{what} in the step check's scenario at solver.dt/2"),
            range: format!("{range}; {switch} skips the check"),
        },
        other => other,
    })?;
    Ok(Plan::Run(Box::new(Ensemble {
        scenario,
        ..ens.clone()
    })))
}

/// The statistics of the refined ensemble `fine`, all its runs on
/// `threads` threads, `each` called after each run (returning false stops
/// the runs: then `Ok(None)`). Its rows go through their CSV form, as the
/// ensemble's own statistics do (`ensemble.csv` read back), so both are
/// computed from the same numbers.
pub fn refined_stats(
    fine: &Ensemble,
    threads: Option<usize>,
    each: &mut dyn FnMut() -> bool,
) -> Result<Option<EnsembleStats>, Error> {
    let mut acc = StatsAcc::default();
    let mut bad: Option<Error> = None;
    let done = fine.run_streaming(0..fine.runs, threads, &mut |row| {
        let line = csv_row(&row);
        if let Err(e) = acc.push_line(row.index + 2, line.trim_end_matches('\n')) {
            bad = Some(e);
            return false;
        }
        each()
    })?;
    if let Some(e) = bad {
        return Err(e);
    }
    Ok(done.then(|| acc.finish()))
}

/// The answer of a mean at step `dt` (`None` without its interval).
fn mean_at(m: &MeanCi, dt: f64) -> Option<AtStep> {
    m.mean
        .zip(m.ci95)
        .map(|(estimate, ci95)| AtStep { dt, estimate, ci95 })
}

/// An answer that the refined ensemble did not give (no value, or no
/// interval): NaN where missing (`null` in summary.json), so its check is
/// not converged.
fn missing_at(dt: f64, estimate: Option<f64>) -> AtStep {
    AtStep {
        dt,
        estimate: estimate.unwrap_or(f64::NAN),
        ci95: [f64::NAN; 2],
    }
}

/// The censored fraction at step `dt` with its Wilson 95 % score interval
/// (a binomial proportion's interval that stays within [0, 1] and is not
/// empty at 0 or 1 passages); `None` without runs.
fn censored_at(fp: &FirstPassage, dt: f64) -> Option<AtStep> {
    let estimate = fp.censored_fraction?;
    let n = (fp.observed + fp.censored) as f64;
    let z2 = Z95 * Z95;
    let d = 1.0 + z2 / n;
    let centre = (estimate + z2 / (2.0 * n)) / d;
    let half = Z95 / d * (estimate * (1.0 - estimate) / n + z2 / (4.0 * n * n)).sqrt();
    Some(AtStep {
        dt,
        estimate,
        ci95: [(centre - half).max(0.0), (centre + half).min(1.0)],
    })
}

/// The step checks of the ensemble's statistics `a` (of `ens`, at its
/// step) against `b` (of `fine`, at half of it): every statistic with a 95
/// % interval at dt, means and the censored fraction on a linear scale,
/// the escape rate on a log scale (a rate's interval is log-normal; the
/// mean residence time 1/rate has the same check); in the order of the
/// console.
pub fn checks(ens: &Ensemble, a: &EnsembleStats, fine: &Ensemble, b: &EnsembleStats) -> Vec<Check> {
    let dt = ens.scenario.solver.dt.unwrap_or(f64::NAN);
    let dt2 = fine.scenario.solver.dt.unwrap_or(f64::NAN);
    let mut out = Vec::new();
    let means = [
        ("theta_final", "rad", &a.theta_final, &b.theta_final),
        ("omega_final", "rad/s", &a.omega_final, &b.omega_final),
        (
            "Omega_final",
            "rad/s",
            &a.precession_final,
            &b.precession_final,
        ),
        ("energy_final", "J", &a.energy_final, &b.energy_final),
        (
            "first_passage.mean_observed",
            "s",
            &a.first_passage.mean_observed,
            &b.first_passage.mean_observed,
        ),
    ];
    for (name, unit, x, y) in means {
        if let Some(at) = mean_at(x, dt) {
            let half = mean_at(y, dt2).unwrap_or_else(|| missing_at(dt2, y.mean));
            out.push((name, unit, StepCheck::new(at, half, Scale::Linear)));
        }
    }
    let (fa, fb) = (&a.first_passage, &b.first_passage);
    if let Some(at) = censored_at(fa, dt) {
        let half = censored_at(fb, dt2).unwrap_or_else(|| missing_at(dt2, None));
        out.push((
            "first_passage.censored_fraction",
            "",
            StepCheck::new(at, half, Scale::Linear),
        ));
    }
    if let Some(r) = &fa.escape_rate {
        let at = AtStep {
            dt,
            estimate: r.rate,
            ci95: r.ci95,
        };
        // No passage at dt/2: the rate's estimate is 0 (passages over the
        // time at risk), without an interval; its log is undefined, so the
        // check is not converged.
        let half = fb.escape_rate.as_ref().map_or_else(
            || missing_at(dt2, Some(0.0)),
            |r| AtStep {
                dt: dt2,
                estimate: r.rate,
                ci95: r.ci95,
            },
        );
        out.push((
            "first_passage.escape_rate",
            "1/s",
            StepCheck::new(at, half, Scale::Log),
        ));
    }
    // Judged together: each half-width gets the family's Bonferroni
    // factor, so an ensemble with no step error is flagged about 5 % of
    // the time in all.
    let m = out.len();
    out.into_iter()
        .map(|(n, u, c)| {
            (
                n,
                u,
                StepCheck::in_family(c.at_dt, c.at_half_dt, c.scale, m),
            )
        })
        .collect()
}

/// The refined ensemble's comparison with the ensemble.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// Each checked statistic ([`checks`]).
    pub checks: Vec<Check>,
    /// The refined ensemble's runs.
    pub runs: u64,
    /// How many of them failed.
    pub failed: u64,
}

impl Refined {
    /// The comparison of the ensemble `ens` (its statistics `stats`) with
    /// the refined ensemble `fine` (its statistics `fine_stats`).
    pub fn new(
        ens: &Ensemble,
        stats: &EnsembleStats,
        fine: &Ensemble,
        fine_stats: &EnsembleStats,
    ) -> Refined {
        Refined {
            checks: checks(ens, stats, fine, fine_stats),
            runs: fine_stats.runs,
            failed: fine_stats.failed,
        }
    }
}

/// The step check's result.
#[derive(Debug, Clone, PartialEq)]
pub enum Outcome {
    /// The refined ensemble ran.
    Done(Refined),
    /// No check, and why.
    Off(String),
}

impl Outcome {
    /// `dt_converged`: whether every checked statistic converged; `None`
    /// without a check (or with no statistic to check).
    pub fn converged(&self) -> Option<bool> {
        match self {
            Outcome::Done(r) if !r.checks.is_empty() => {
                Some(r.checks.iter().all(|c| c.2.converged))
            }
            _ => None,
        }
    }

    /// Why the step is unchecked (`None`: checked).
    pub fn unchecked(&self) -> Option<&str> {
        match self {
            Outcome::Off(why) => Some(why),
            Outcome::Done(r) if r.checks.is_empty() => {
                Some("no statistic has a 95 % interval (fewer than 2 ok runs)")
            }
            Outcome::Done(_) => None,
        }
    }

    /// summary.json's step-check fields.
    pub fn fields(&self) -> Fields<'_> {
        Fields {
            dt_converged: self.converged(),
            step_check: match self {
                Outcome::Done(r) if !r.checks.is_empty() => Some(Checks(&r.checks)),
                _ => None,
            },
            step_unchecked: self.unchecked(),
        }
    }
}

/// summary.json's (and Python's `tt.ensemble` summary's) step-check
/// fields.
#[derive(Debug, Clone, Serialize)]
pub struct Fields<'a> {
    /// True: every checked statistic converged; false: one or more did
    /// not; `null`: unchecked.
    pub dt_converged: Option<bool>,
    /// Per statistic, by its name: both answers with their steps and
    /// intervals, the change, its half-width (`null`: unchecked).
    pub step_check: Option<Checks<'a>>,
    /// Why the step is unchecked (absent when checked).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub step_unchecked: Option<&'a str>,
}

/// The checks as a JSON object, name to [`StepCheck`], in their order.
#[derive(Debug, Clone)]
pub struct Checks<'a>(pub &'a [Check]);

impl Serialize for Checks<'_> {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut m = s.serialize_map(Some(self.0.len()))?;
        for (name, _, c) in self.0 {
            m.serialize_entry(name, c)?;
        }
        m.end()
    }
}
