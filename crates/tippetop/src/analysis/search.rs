//! Protocol search for a memory bit at T = 0 (issue #16 item 5,
//! docs/physics.md#search): minimise `time + weight × energy` over the
//! windows of one phase, subject to success with a margin.
//!
//! **Optimiser.** Nelder–Mead from the `argmin` crate (a maintained
//! derivative-free optimiser; the merit is piecewise smooth and a run is
//! tens of ms, so a gradient-free simplex with restarts is the right tool),
//! on the unit cube: a parameter vector `u` maps to the box by
//! `x = lo + clamp(u, 0, 1) (hi − lo)`, and a point outside the cube costs
//! its distance to it on top (so the simplex comes back). The first start
//! is the box's centre, restart `r >= 1` starts at Philox uniforms
//! `(seed, r)`; each start's simplex steps 0.25 along every axis (inwards).
//! Restarts go on until `budget` evaluations are spent (or fewer than a
//! simplex's `n + 1` are left); the best point ever
//! evaluated is the answer. Deterministic: same input, same bits.
//!
//! **Merit** (dimensionless; `P` = `bit.phase`): on success in the target
//! window shrunk by `margin` (over the last `hold` of the phase, the bit's
//! own test on the continuous solution, [`super::bit::judge_phase`]) `(t_s + weight |E|)/P` with
//! `t_s` the switching time from the phase start and `E` the net work of
//! the actuators over the phase (a simple actuator cannot take energy back,
//! so either sign costs); otherwise `FAIL + d/π`, where `d` is the largest
//! distance of θ from the shrunk window over the rows of the last `hold`
//! (π + 1 if the run failed): a continuous measure of how far the protocol
//! is from working, so the simplex can walk towards success. `FAIL = 1e3`
//! exceeds every successful merit for `weight |E| < 999 P`.

use std::cell::{Cell, RefCell};

use argmin::core::{CostFunction, Executor};
use argmin::solver::neldermead::NelderMead;
use toml::{Table, Value};

use super::bit::{self, Mode};
use crate::input::scenario::bit::BitScenario;
use crate::input::scenario::search::{
    SearchActuator, SearchPhase, SearchSpec, apply_sets, document, split,
};
use crate::numeric::random::Stream;
use crate::sim::watch::ThetaWatch;
use crate::{Error, simulate_watching_with_pose};

/// The merit of a failed protocol before its distance is added.
pub const FAIL: f64 = 1e3;

/// What [`minimize_box`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct Optimum {
    /// The best point \[the box's units\].
    pub x: Vec<f64>,
    /// Its value.
    pub value: f64,
    /// Evaluations spent.
    pub evaluations: usize,
    /// Starts made (the first counts).
    pub starts: usize,
}

/// The function minimised (a run per call for the protocol search).
type Objective<'a> = &'a mut dyn FnMut(&[f64]) -> f64;

struct Boxed<'a> {
    f: RefCell<Objective<'a>>,
    lo: &'a [f64],
    hi: &'a [f64],
    budget: usize,
    evals: Cell<usize>,
    best: RefCell<Option<(f64, Vec<f64>)>>,
}

#[derive(Debug)]
struct Spent;

impl std::fmt::Display for Spent {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("budget spent")
    }
}

impl std::error::Error for Spent {}

impl Boxed<'_> {
    fn point(&self, u: &[f64]) -> (Vec<f64>, f64) {
        let mut out = 0.0;
        let x = u
            .iter()
            .zip(self.lo.iter().zip(self.hi))
            .map(|(&ui, (&l, &h))| {
                let c = ui.clamp(0.0, 1.0);
                out += (ui - c) * (ui - c);
                l + c * (h - l)
            })
            .collect();
        (x, out.sqrt())
    }
}

/// The executor owns its problem: it gets a reference.
struct ByRef<'b, 'a>(&'b Boxed<'a>);

impl CostFunction for ByRef<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Self::Param) -> Result<f64, argmin::core::Error> {
        let this = self.0;
        this.cost(u)
    }
}

impl Boxed<'_> {
    fn cost(&self, u: &[f64]) -> Result<f64, argmin::core::Error> {
        if self.evals.get() >= self.budget {
            return Err(Spent.into());
        }
        self.evals.set(self.evals.get() + 1);
        let (x, outside) = self.point(u);
        let v = (self.f.borrow_mut())(&x);
        let v = if v.is_nan() { f64::INFINITY } else { v };
        let mut best = self.best.borrow_mut();
        if best.as_ref().is_none_or(|(b, _)| v < *b) {
            *best = Some((v, x));
        }
        Ok(v + outside)
    }
}

/// Minimise `f` over the box `[lo, hi]` (per coordinate, `lo <= hi`) with
/// Nelder–Mead and restarts (module docs) in at most `budget` evaluations
/// (the last `n` may stay unspent: a start needs `n + 1`).
/// `None` if `budget` is 0 or the box has no coordinate.
pub fn minimize_box(
    f: &mut dyn FnMut(&[f64]) -> f64,
    lo: &[f64],
    hi: &[f64],
    seed: u64,
    budget: usize,
) -> Option<Optimum> {
    let n = lo.len();
    if n == 0 || budget == 0 || hi.len() != n {
        return None;
    }
    let problem = Boxed {
        f: RefCell::new(f),
        lo,
        hi,
        budget,
        evals: Cell::new(0),
        best: RefCell::new(None),
    };
    let stream = Stream::new(seed, 0);
    let mut starts = 0;
    // A start needs n + 1 evaluations for its simplex (argmin's Nelder–Mead
    // cannot stop inside its initialisation): fewer left ends the search.
    while budget - problem.evals.get() > n {
        let u0: Vec<f64> = if starts == 0 {
            vec![0.5; n]
        } else {
            (0..n as u64)
                .map(|i| stream.uniform(starts as u64, i))
                .collect()
        };
        starts += 1;
        let mut simplex = vec![u0.clone()];
        for i in 0..n {
            let mut v = u0.clone();
            v[i] += if v[i] + 0.25 <= 1.0 { 0.25 } else { -0.25 };
            simplex.push(v);
        }
        let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(1e-12) else {
            break;
        };
        let before = problem.evals.get();
        let res = Executor::new(ByRef(&problem), solver)
            .configure(|s| s.max_iters(budget as u64))
            .run();
        // A start that spent nothing (cannot happen with budget left) ends
        // the loop rather than spin.
        if res.is_err() || problem.evals.get() == before {
            break;
        }
    }
    let evaluations = problem.evals.get();
    let (value, x) = problem.best.into_inner()?;
    Some(Optimum {
        x,
        value,
        evaluations,
        starts,
    })
}

/// One evaluated protocol.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// The merit (module docs).
    pub merit: f64,
    /// Success in the target window shrunk by the margin.
    pub success_with_margin: bool,
    /// Success by the bit's own definition (no margin).
    pub success: bool,
    /// Why the phase failed (no margin), if it did.
    pub failure: Option<Mode>,
    /// Switching time from the phase start \[s\] (no margin; success only).
    pub time: Option<f64>,
    /// Net work of the actuators over the phase \[J\].
    pub energy: Option<f64>,
    /// Largest distance of θ from the shrunk window over the hold \[rad\]
    /// (π + 1 if the run failed).
    pub distance: f64,
}

/// A protocol search: the scenario document without `[search]` and without
/// the searched window list, and the spec.
#[derive(Debug, Clone)]
pub struct ProtocolSearch {
    base: Table,
    /// The `[search]` table.
    pub spec: SearchSpec,
    /// The bit scenario with the first candidate (the box's centre).
    pub first: BitScenario,
}

impl ProtocolSearch {
    /// Set up a search from a bit scenario file's text with a `[search]`
    /// table, a preset (inserted as the document's `preset` if it has none)
    /// and `--set` overrides (table keys). Errors name the key: no
    /// `[search]`, its bad keys, a run at T > 0.
    pub fn new(text: Option<&str>, preset: Option<&str>, sets: &[String]) -> Result<Self, Error> {
        let mut doc = document(text)?;
        if let Some(p) = preset {
            doc.entry("preset".to_string())
                .or_insert_with(|| Value::String(p.to_string()));
        }
        apply_sets(&mut doc, sets)?;
        let (mut doc, search) = split(doc)?;
        let Some(search) = search else {
            return Err(Error::invalid(
                "search",
                "missing: --search needs a [search] table".into(),
                "[search] with phase, windows, magnitude, angle, start, duration, ...".into(),
            ));
        };
        // The bit without the search: its phase and windows.
        let probe = BitScenario::load(None, Some(&toml::to_string(&doc).unwrap_or_default()), &[])?;
        if probe.scenario.thermal.temperature > 0.0 {
            return Err(Error::invalid(
                "thermal.temperature",
                format!(
                    "{} K: the search runs deterministic runs",
                    probe.scenario.thermal.temperature
                ),
                "0 with --search".into(),
            ));
        }
        let (zero, one) = (probe.bit.zero, probe.bit.one);
        let spec = SearchSpec::parse(&search, probe.bit.phase, |p| match p {
            SearchPhase::Write => one,
            SearchPhase::Erase => zero,
        })?;
        doc.remove(spec.phase.name());
        let mut s = ProtocolSearch {
            base: doc,
            spec,
            first: probe,
        };
        let (lo, hi) = s.spec.bounds();
        let mid: Vec<f64> = lo.iter().zip(&hi).map(|(l, h)| 0.5 * (l + h)).collect();
        s.first = s.scenario(&mid)?;
        Ok(s)
    }

    /// The bit scenario document of protocol `x` (per window: magnitude
    /// \[N\], angle \[rad\], start \[s\], duration \[s\]): the file with the
    /// searched list replaced. What `best.toml` holds.
    pub fn document(&self, x: &[f64]) -> Table {
        let phase = self.first.bit.phase;
        let windows: Vec<Value> = x
            .chunks(4)
            .map(|w| {
                let (mag, ang, start, dur) = (w[0], w[1], w[2].clamp(0.0, phase), w[3]);
                let stop = (start + dur).min(phase);
                let mut t = Table::new();
                match self.spec.actuator {
                    SearchActuator::Contact => {
                        t.insert("kind".into(), Value::String("contact".into()));
                        t.insert("hx".into(), Value::Float(mag * ang.cos()));
                        t.insert("hy".into(), Value::Float(mag * ang.sin()));
                    }
                    SearchActuator::Tip { point } => {
                        let arr = |v: [f64; 3]| {
                            Value::Array(v.iter().map(|&c| Value::Float(c)).collect())
                        };
                        t.insert("kind".into(), Value::String("tip".into()));
                        t.insert("point".into(), arr(point));
                        t.insert("force".into(), arr([mag * ang.cos(), mag * ang.sin(), 0.0]));
                    }
                    SearchActuator::Magnetic { moment } => {
                        let field = [mag * ang.sin(), 0.0, mag * ang.cos()];
                        t.insert("kind".into(), Value::String("magnetic".into()));
                        t.insert("moment".into(), Value::Float(moment));
                        t.insert(
                            "field".into(),
                            Value::Array(field.iter().map(|&c| Value::Float(c)).collect()),
                        );
                    }
                }
                t.insert("start".into(), Value::Float(start));
                t.insert("stop".into(), Value::Float(stop));
                Value::Table(t)
            })
            .collect();
        let mut doc = self.base.clone();
        doc.insert(self.spec.phase.name().into(), Value::Array(windows));
        doc
    }

    /// The TOML text of [`Self::document`].
    pub fn text(&self, x: &[f64]) -> String {
        toml::to_string(&self.document(x)).unwrap_or_default()
    }

    /// The loaded bit scenario of protocol `x`.
    pub fn scenario(&self, x: &[f64]) -> Result<BitScenario, Error> {
        BitScenario::load(None, Some(&self.text(x)), &[])
    }

    /// Run and judge protocol `x`.
    pub fn evaluate(&self, x: &[f64]) -> Evaluation {
        let failed = |distance: f64| Evaluation {
            merit: FAIL + distance / std::f64::consts::PI,
            success_with_margin: false,
            success: false,
            failure: Some(Mode::RunFailed),
            time: None,
            energy: None,
            distance,
        };
        let pi = std::f64::consts::PI;
        let Ok(bs) = self.scenario(x) else {
            return failed(pi + 1.0);
        };
        let sc = bs.run_scenario(0);
        let b = &bs.bit;
        let (target, t0) = match self.spec.phase {
            SearchPhase::Write => (b.one, 0.0),
            SearchPhase::Erase => (b.zero, b.phase),
        };
        let t1 = t0 + b.phase;
        let m = self.spec.margin;
        let shrunk = [target[0] + m, target[1] - m];
        let [w, e] = bit::watches(&bs);
        let margin_watch = ThetaWatch {
            from: t0,
            to: t1,
            window: shrunk,
        };
        // θ's windows and rows, the work and the summary: no pose.
        let watched = [w, e, margin_watch];
        let Ok((traj, stays)) = simulate_watching_with_pose(&sc, &watched, false, &mut |_| {})
        else {
            return failed(pi + 1.0);
        };
        let r = bit::evaluate_run(&bs, sc.thermal.run, &traj, &stays);
        let plain = match self.spec.phase {
            SearchPhase::Write => r.write,
            SearchPhase::Erase => r.erase,
        };
        let rows: Vec<(f64, f64)> = traj.samples.iter().map(|s| (s.t, s.theta)).collect();
        let failure = traj.error.as_ref().and_then(|e| e.failure());
        let pm = bit::judge_phase(&stays[2], t0, t1, b.hold, failure);
        let tol = 1e-9 * b.phase;
        let hold_rows: Vec<f64> = rows
            .iter()
            .filter(|&&(t, _)| t >= t1 - b.hold - tol && t <= t1 + tol)
            .map(|&(_, th)| th)
            .collect();
        let distance = if failure.is_some() || hold_rows.is_empty() {
            pi + 1.0
        } else {
            hold_rows
                .iter()
                .map(|&th| (shrunk[0] - th).max(th - shrunk[1]).max(0.0))
                .fold(0.0, f64::max)
        };
        let energy = plain.energy;
        let merit = match (pm.success(), pm.time) {
            (true, Some(ts)) => (ts + self.spec.weight * energy.unwrap_or(0.0).abs()) / b.phase,
            _ => FAIL + distance / pi,
        };
        Evaluation {
            merit,
            success_with_margin: pm.success(),
            success: plain.success(),
            failure: plain.failure,
            time: plain.time,
            energy,
            distance,
        }
    }

    /// Run the search; `each` sees every evaluation (its index from 0, the
    /// protocol, the result) in order.
    pub fn run(&self, each: &mut dyn FnMut(usize, &[f64], &Evaluation)) -> Option<SearchResult> {
        let (lo, hi) = self.spec.bounds();
        let mut k = 0;
        let mut f = |x: &[f64]| {
            let e = self.evaluate(x);
            each(k, x, &e);
            k += 1;
            e.merit
        };
        let opt = minimize_box(&mut f, &lo, &hi, self.spec.seed, self.spec.budget)?;
        let best = self.evaluate(&opt.x);
        let robustness = self.robustness(&opt.x);
        Some(SearchResult {
            best_x: opt.x,
            best,
            evaluations: opt.evaluations,
            starts: opt.starts,
            robustness,
        })
    }

    /// Success fraction of `perturbations` copies of `x`, each parameter
    /// multiplied by `1 + 0.05 (2u − 1)` (`u` Philox uniforms of
    /// `(seed, 1)`): (successes, runs), the bit's own test (no margin).
    pub fn robustness(&self, x: &[f64]) -> (usize, usize) {
        let stream = Stream::new(self.spec.seed, 1);
        let n = self.spec.perturbations;
        let ok = (0..n as u64)
            .filter(|&i| {
                let p: Vec<f64> = x
                    .iter()
                    .enumerate()
                    .map(|(j, &v)| v * (1.0 + 0.05 * (2.0 * stream.uniform(i, j as u64) - 1.0)))
                    .collect();
                self.evaluate(&p).success
            })
            .count();
        (ok, n)
    }
}

/// What a search found.
#[derive(Debug, Clone, PartialEq)]
pub struct SearchResult {
    /// The best protocol (per window: magnitude \[N\], angle \[rad\],
    /// start \[s\], duration \[s\]).
    pub best_x: Vec<f64>,
    /// Its evaluation.
    pub best: Evaluation,
    /// Evaluations spent by the optimiser.
    pub evaluations: usize,
    /// Nelder–Mead starts.
    pub starts: usize,
    /// (successes, runs) of the ±5 % perturbations.
    pub robustness: (usize, usize),
}
