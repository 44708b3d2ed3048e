//! The memory bit (issue #16): whether each phase of a bit run succeeded,
//! its switching time and energy, and the statistics over runs (success
//! probabilities with Wilson 95 % intervals). The scenario side (`[bit]`,
//! `[[write]]`, `[[erase]]`) is [`crate::input::scenario::bit`]. No I/O.
//!
//! # Success of a phase
//!
//! A phase `[t0, t1]` (write: `[0, phase]`, erase: `[phase, 2 phase]`)
//! succeeds iff θ stays in the target window (`one` for write, `zero` for
//! erase; closed intervals) at every time of the last `hold` seconds of the
//! phase, `t1 − hold <= t <= t1`, on the continuous solution: the run
//! watches the windows ([`watches`], [`crate::simulate_watching`]) with
//! events at their edges and at the phases' ends ([`crate::sim::watch`]),
//! so an excursion between two output rows is seen (one within a single
//! integration step is not: the step is the resolution). The switching
//! time is the start of the final stay (the last entry into the window, or
//! `t0` if θ was already in at `t0`), measured from `t0`. Failure modes
//! ([`Mode`]):
//! - `never_entered`: θ was never in the window during the phase;
//! - `left`: θ was in the window at some time but not at the phase's end;
//! - `too_late`: θ is in the window at the end, but its final stay began
//!   less than `hold` before the end;
//! - `run_failed` / `lifted_off`: the run failed before the phase's end
//!   (`lifted_off` when the failure is a lift-off, [`crate::Failure::LiftOff`]).
//!
//! The energy of a phase is the change of `work_applied` (net work of the
//! applied force on the top, J) from `t0` to `t1` (at the watch's marks; up
//! to the last row for a run that failed in the phase).

use serde::Serialize;

use crate::analysis::sweep::{fmt_f64, status_field};
use crate::input::scenario::bit::{Actuator, BitScenario};
use crate::sim::watch::{ThetaWatch, WindowStay};
use crate::{Failure, Trajectory};

/// z of the two-sided 95 % interval.
pub const Z95: f64 = 1.959963984540054;

/// Why a phase failed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Mode {
    /// θ never was in the target window during the phase.
    NeverEntered,
    /// θ was in the window but not at the end of the phase.
    Left,
    /// θ is in the window at the end, but entered it less than `hold` before.
    TooLate,
    /// The run failed (any run-time failure but lift-off) before the end.
    RunFailed,
    /// The run failed by lift-off before the end.
    LiftedOff,
}

impl Mode {
    /// All modes, in report order.
    pub const ALL: [Mode; 5] = [
        Mode::NeverEntered,
        Mode::Left,
        Mode::TooLate,
        Mode::RunFailed,
        Mode::LiftedOff,
    ];

    /// The mode's name in `bit.json`.
    pub fn as_str(self) -> &'static str {
        match self {
            Mode::NeverEntered => "never_entered",
            Mode::Left => "left",
            Mode::TooLate => "too_late",
            Mode::RunFailed => "run_failed",
            Mode::LiftedOff => "lifted_off",
        }
    }
}

/// The outcome of one phase of one run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseResult {
    /// `None` on success, else why it failed.
    pub failure: Option<Mode>,
    /// Switching time from the phase start \[s\] (success only).
    pub time: Option<f64>,
    /// Net work of the applied force on the top over the phase \[J\]
    /// (`None` when the run has no row in the phase).
    pub energy: Option<f64>,
}

impl PhaseResult {
    /// Whether the phase succeeded.
    pub fn success(&self) -> bool {
        self.failure.is_none()
    }
}

/// Judge a phase `[t0, t1]` \[s\] with `hold` \[s\] from what the watch
/// of its target window saw on the continuous solution
/// ([`crate::sim::watch`]); `failure`: the run's failure if it failed.
/// The stay counts as held if it began no later than `t1 − hold` (to
/// `1e-9 × (t1 − t0)`: the times carry the rounding of scaled time).
pub fn judge_phase(
    stay: &WindowStay,
    t0: f64,
    t1: f64,
    hold: f64,
    failure: Option<Failure>,
) -> PhaseResult {
    let fail = |mode| PhaseResult {
        failure: Some(mode),
        time: None,
        energy: None,
    };
    if !stay.reached_end {
        return fail(match failure {
            Some(Failure::LiftOff) => Mode::LiftedOff,
            _ => Mode::RunFailed,
        });
    }
    let tol = 1e-9 * (t1 - t0);
    match stay.stay_from {
        Some(from) if stay.inside_at_end => {
            if from <= t1 - hold + tol {
                PhaseResult {
                    failure: None,
                    time: Some((from - t0).max(0.0)),
                    energy: None,
                }
            } else {
                fail(Mode::TooLate)
            }
        }
        _ if stay.ever_inside => fail(Mode::Left),
        _ => fail(Mode::NeverEntered),
    }
}

/// The outcome of one bit run (write, then erase).
#[derive(Debug, Clone, PartialEq)]
pub struct RunResult {
    /// `thermal.run` of the run.
    pub run: u64,
    /// `"ok"` or the run's error.
    pub status: String,
    /// The write phase.
    pub write: PhaseResult,
    /// The erase phase.
    pub erase: PhaseResult,
    /// Smallest pull-off margin of the run \[N\] (with adhesion; `None`
    /// for a failed run: its rows up to the failure are no margin of the
    /// bit, and the state it failed in may be blown up).
    pub pull_off_margin_min: Option<f64>,
}

/// The header of `runs.csv` (one row per run, [`csv_row`]).
pub const CSV_HEADER: &str =
    "run,status,write,write_time,write_energy,erase,erase_time,erase_energy,pull_off_margin_min";

/// One line of `runs.csv` (with its `\n`): `thermal.run`, the status (a
/// CSV field, quoted when needed), then for write and erase the outcome
/// (`ok` or the [`Mode`]), the switching time \[s\] and the energy \[J\],
/// and the smallest pull-off margin \[N\]; an empty field is a missing
/// value, floats in the shortest round-trip form.
pub fn csv_row(r: &RunResult) -> String {
    let o = |v: Option<f64>| v.map(fmt_f64).unwrap_or_default();
    let outcome = |p: &PhaseResult| p.failure.map(Mode::as_str).unwrap_or("ok");
    format!(
        "{},{},{},{},{},{},{},{},{}\n",
        r.run,
        status_field(&r.status),
        outcome(&r.write),
        o(r.write.time),
        o(r.write.energy),
        outcome(&r.erase),
        o(r.erase.time),
        o(r.erase.energy),
        o(r.pull_off_margin_min),
    )
}

/// Parse a `runs.csv` line (without its `\n`) back into the run's result:
/// the inverse of [`csv_row`] (floats round-trip exactly). `None` if the
/// line is not one [`csv_row`] writes.
pub fn parse_csv_row(line: &str) -> Option<RunResult> {
    let (run, rest) = line.split_once(',')?;
    let run = run.parse::<u64>().ok()?;
    let (status, rest) = match rest.strip_prefix('"') {
        Some(quoted) => {
            // The closing quote is the first one not doubled.
            let mut status = String::new();
            let mut chars = quoted.char_indices().peekable();
            let mut end = None;
            while let Some((i, c)) = chars.next() {
                if c == '"' {
                    if chars.peek().is_some_and(|&(_, d)| d == '"') {
                        chars.next();
                        status.push('"');
                    } else {
                        end = Some(i + 1);
                        break;
                    }
                } else {
                    status.push(c);
                }
            }
            (status, quoted[end?..].strip_prefix(',')?)
        }
        None => {
            let (status, rest) = rest.split_once(',')?;
            (status.to_string(), rest)
        }
    };
    let f: Vec<&str> = rest.split(',').collect();
    let [w, wt, we, e, et, ee, margin] = f.as_slice() else {
        return None;
    };
    let num = |s: &str| -> Option<Option<f64>> {
        if s.is_empty() {
            Some(None)
        } else {
            s.parse::<f64>().ok().map(Some)
        }
    };
    let phase = |o: &str, t: &str, en: &str| -> Option<PhaseResult> {
        let failure = match o {
            "ok" => None,
            m => Some(*Mode::ALL.iter().find(|x| x.as_str() == m)?),
        };
        Some(PhaseResult {
            failure,
            time: num(t)?,
            energy: num(en)?,
        })
    };
    Some(RunResult {
        run,
        status,
        write: phase(w, wt, we)?,
        erase: phase(e, et, ee)?,
        pull_off_margin_min: num(margin)?,
    })
}

/// Net work of the applied forces on the top over a phase \[J\]: from the
/// watch's marks at the phase's ends, or, for a run that failed in the
/// phase, up to its last row.
fn phase_energy(stay: &WindowStay, traj: &Trajectory) -> Option<f64> {
    let from = stay.work_at_from?;
    let to = match stay.work_at_to {
        Some(w) => w,
        None => traj.samples.last()?.work_applied,
    };
    Some(to - from)
}

/// The θ windows a bit run watches: `one` over the write phase, `zero` over
/// the erase phase (in this order; [`evaluate_run`] reads them so).
pub fn watches(bs: &BitScenario) -> [ThetaWatch; 2] {
    let b = &bs.bit;
    [
        ThetaWatch {
            from: 0.0,
            to: b.phase,
            window: b.one,
        },
        ThetaWatch {
            from: b.phase,
            to: 2.0 * b.phase,
            window: b.zero,
        },
    ]
}

/// Evaluate run `traj` of the bit scenario `bs` (its `thermal.run` is
/// `run`), `stays` what the [`watches`] saw (`simulate_watching`).
pub fn evaluate_run(
    bs: &BitScenario,
    run: u64,
    traj: &Trajectory,
    stays: &[WindowStay],
) -> RunResult {
    let failure = traj.error.as_ref().and_then(|e| e.failure());
    let b = &bs.bit;
    let mut write = judge_phase(&stays[0], 0.0, b.phase, b.hold, failure);
    write.energy = phase_energy(&stays[0], traj);
    let mut erase = judge_phase(&stays[1], b.phase, 2.0 * b.phase, b.hold, failure);
    erase.energy = phase_energy(&stays[1], traj);
    RunResult {
        run,
        status: traj.summary.status.clone(),
        write,
        erase,
        pull_off_margin_min: traj
            .summary
            .pull_off_margin_min
            .filter(|m| traj.error.is_none() && m.is_finite()),
    }
}

/// How many runs of a bit ensemble of `runs` runs may run at once within
/// [`crate::limits::MEMORY_BUDGET`]: at most `threads`, each keeping its
/// run ([`crate::limits::run_memory_bytes`]); the command keeps every
/// run's result and its row of `runs.csv` (read back for the statistics).
/// Error (key `solver.samples`) if not even one run fits.
pub fn threads_within_memory(
    bs: &BitScenario,
    runs: usize,
    threads: usize,
) -> Result<usize, crate::Error> {
    let result = (std::mem::size_of::<RunResult>() + 256) as u64;
    let per_run = crate::limits::run_memory_bytes(&bs.scenario.solver) + 9 * result;
    crate::limits::fit_threads("solver.samples", threads, per_run, runs as u64 * result)
}

/// Run `k` of the bit scenario (`thermal.run = r0 + k`) and evaluate it.
/// Never fails: bad input (which [`BitScenario::load`] has excluded) and
/// panics become a failed run.
pub fn run_one(bs: &BitScenario, k: u64) -> RunResult {
    let sc = bs.run_scenario(k);
    let run = sc.thermal.run;
    let failed = |status: String| RunResult {
        run,
        status,
        write: PhaseResult {
            failure: Some(Mode::RunFailed),
            time: None,
            energy: None,
        },
        erase: PhaseResult {
            failure: Some(Mode::RunFailed),
            time: None,
            energy: None,
        },
        pull_off_margin_min: None,
    };
    let watched = watches(bs);
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
        // The result reads θ's windows, the work and the summary: no pose.
        crate::simulate_watching_with_pose(&sc, &watched, false, &mut |_| {})
    })) {
        Ok(Ok((traj, stays))) => evaluate_run(bs, run, &traj, &stays),
        Ok(Err(e)) => failed(e.to_string()),
        Err(_) => failed("panicked".into()),
    }
}

/// The Wilson score interval for `successes` of `n` at `z` (`None` for
/// `n = 0`): the `p` with `|p̂ − p| <= z sqrt(p (1 − p)/n)`. At the ends
/// the closed forms: 0 of `n` is `[0, z²/(n + z²)]` and `n` of `n`
/// `[n/(n + z²), 1]`, with 0 and 1 exact (`centre − half` leaves a
/// rounding residue, 3.5e-18 for 0 of 100).
pub fn wilson(successes: usize, n: usize, z: f64) -> Option<[f64; 2]> {
    if n == 0 {
        return None;
    }
    let nf = n as f64;
    let z2 = z * z;
    if successes == 0 {
        return Some([0.0, z2 / (nf + z2)]);
    }
    if successes >= n {
        return Some([nf / (nf + z2), 1.0]);
    }
    let p = successes as f64 / nf;
    let denom = 1.0 + z2 / nf;
    let centre = (p + z2 / (2.0 * nf)) / denom;
    let half = z / denom * (p * (1.0 - p) / nf + z2 / (4.0 * nf * nf)).sqrt();
    Some([(centre - half).max(0.0), (centre + half).min(1.0)])
}

/// The `q` quantile (`0 <= q <= 1`) of `values` by linear interpolation
/// between order statistics (position `q (n − 1)`); `None` if empty.
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut v = values.to_vec();
    v.sort_by(f64::total_cmp);
    let pos = q * (v.len() - 1) as f64;
    let i = pos.floor() as usize;
    let frac = pos - i as f64;
    Some(match v.get(i + 1) {
        Some(next) => v[i] + frac * (next - v[i]),
        None => v[i],
    })
}

/// Statistics of one phase (or the cycle) over runs, as in `bit.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Block {
    /// Runs counted.
    pub runs: usize,
    /// Runs that succeeded.
    pub successes: usize,
    /// `successes / runs` (`None` without runs).
    pub probability: Option<f64>,
    /// 95 % interval of the probability: Wilson for an ensemble, `[p, p]`
    /// for a single deterministic run.
    pub ci95: Option<[f64; 2]>,
    /// A single run at T = 0.
    pub deterministic: bool,
    /// Median switching time of the successful runs \[s\] from the phase
    /// start (the cycle: from the write's start to the erase's switch).
    pub time_median: Option<f64>,
    /// 25 % quantile of the switching time \[s\].
    pub time_q25: Option<f64>,
    /// 75 % quantile of the switching time \[s\].
    pub time_q75: Option<f64>,
    /// Median net work of the applied force on the top over the phase, over
    /// the runs that have it \[J\].
    pub energy_median: Option<f64>,
    /// Largest total applied force `|Σ (h_x, h_y, h_z)|` of the windows
    /// acting at once \[N\].
    pub max_applied_force: f64,
    /// Failed runs per [`Mode`], every mode listed.
    pub failures: std::collections::BTreeMap<&'static str, usize>,
}

/// The statistics of `bit.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// Runs.
    pub runs: usize,
    /// A single run at T = 0.
    pub deterministic: bool,
    /// The write phase over all runs.
    pub write: Block,
    /// The erase phase over all runs.
    pub erase: Block,
    /// The erase phase over the runs whose write succeeded.
    pub erase_given_write: Block,
    /// Write and erase both succeeded.
    pub cycle: Block,
    /// Smallest pull-off margin over the runs that completed \[N\] (`None`
    /// without adhesion, or when no run completed).
    pub pull_off_margin_min: Option<f64>,
}

/// Largest `|Σ h|` of windows acting at the same time \[N\] (the total is
/// piecewise constant and changes only at window starts and stops, so its
/// largest value is taken at some start). Body actuators (docs/physics.md
/// §actuators) add `|Σ F_tip|` (lab frame) and `Σ |μ| |G|` (a magnet's largest
/// gradient force, `|G|` the Frobenius norm): exact for one kind, an upper
/// bound when kinds in different frames act together.
pub fn max_applied_force(windows: &[Actuator]) -> f64 {
    windows
        .iter()
        .map(|w| {
            let (mut x, mut y, mut z) = (0.0, 0.0, 0.0);
            let mut tip = [0.0; 3];
            let mut magnet = 0.0;
            for v in windows
                .iter()
                .filter(|v| v.start <= w.start && w.start < v.stop)
            {
                x += v.hx;
                y += v.hy;
                z += v.hz;
                match v.kind {
                    crate::input::scenario::bit::ActuatorKind::Body(crate::BodyActuator::Tip {
                        force,
                        ..
                    }) => {
                        for (t, f) in tip.iter_mut().zip(force) {
                            *t += f;
                        }
                    }
                    crate::input::scenario::bit::ActuatorKind::Body(
                        crate::BodyActuator::Magnetic {
                            moment, gradient, ..
                        },
                    ) => {
                        let g2: f64 = gradient.iter().flatten().map(|g| g * g).sum();
                        magnet += moment.abs() * g2.sqrt();
                    }
                    crate::input::scenario::bit::ActuatorKind::Contact => {}
                }
            }
            let tip = (tip[0] * tip[0] + tip[1] * tip[1] + tip[2] * tip[2]).sqrt();
            (x * x + y * y + z * z).sqrt() + tip + magnet
        })
        .fold(0.0, f64::max)
}

fn block(results: &[PhaseResult], deterministic: bool, max_force: f64) -> Block {
    let runs = results.len();
    let successes = results.iter().filter(|r| r.success()).count();
    let probability = (runs > 0).then(|| successes as f64 / runs as f64);
    let ci95 = if deterministic {
        probability.map(|p| [p, p])
    } else {
        wilson(successes, runs, Z95)
    };
    let times: Vec<f64> = results.iter().filter_map(|r| r.time).collect();
    let energies: Vec<f64> = results.iter().filter_map(|r| r.energy).collect();
    let failures = Mode::ALL
        .iter()
        .map(|m| {
            (
                m.as_str(),
                results.iter().filter(|r| r.failure == Some(*m)).count(),
            )
        })
        .collect();
    Block {
        runs,
        successes,
        probability,
        ci95,
        deterministic,
        time_median: quantile(&times, 0.5),
        time_q25: quantile(&times, 0.25),
        time_q75: quantile(&times, 0.75),
        energy_median: quantile(&energies, 0.5),
        max_applied_force: max_force,
        failures,
    }
}

/// The cycle of one run: both phases succeeded; time from the write's
/// start to the start of the erase's final stay; energy the sum; the
/// failure that of the first failed phase.
pub fn cycle(r: &RunResult, phase: f64) -> PhaseResult {
    let energy = match (r.write.energy, r.erase.energy) {
        (Some(a), Some(b)) => Some(a + b),
        _ => None,
    };
    PhaseResult {
        failure: r.write.failure.or(r.erase.failure),
        time: match (r.write.success(), r.erase.time) {
            (true, Some(t)) => Some(phase + t),
            _ => None,
        },
        energy,
    }
}

/// The statistics over `results` (in any order) of the bit scenario `bs`;
/// `deterministic`: a single run at T = 0.
pub fn report(bs: &BitScenario, results: &[RunResult], deterministic: bool) -> Report {
    report_of(&Protocol::of(bs), results, deterministic)
}

/// What [`report`] needs of a bit scenario besides the runs: the largest
/// total applied forces \[N\] and the phase \[s\] (small and `Copy`, so a
/// map's job hands it on without the scenario).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Protocol {
    /// [`max_applied_force`] of the write windows \[N\].
    pub write_force: f64,
    /// [`max_applied_force`] of the erase windows \[N\].
    pub erase_force: f64,
    /// `bit.phase` \[s\].
    pub phase: f64,
}

impl Protocol {
    /// The protocol figures of `bs`.
    pub fn of(bs: &BitScenario) -> Protocol {
        Protocol {
            write_force: max_applied_force(&bs.write),
            erase_force: max_applied_force(&bs.erase),
            phase: bs.bit.phase,
        }
    }
}

/// Whether `bs` is an ensemble: a stochastic method at T > 0 (else one
/// deterministic run).
pub fn is_stochastic(bs: &BitScenario) -> bool {
    bs.scenario.solver.method.is_stochastic() && bs.scenario.thermal.is_hot()
}

/// [`report`] from the protocol figures ([`Protocol::of`]).
pub fn report_of(p: &Protocol, results: &[RunResult], deterministic: bool) -> Report {
    let (fw, fe) = (p.write_force, p.erase_force);
    let write: Vec<PhaseResult> = results.iter().map(|r| r.write).collect();
    let erase: Vec<PhaseResult> = results.iter().map(|r| r.erase).collect();
    let given: Vec<PhaseResult> = results
        .iter()
        .filter(|r| r.write.success())
        .map(|r| r.erase)
        .collect();
    let cycles: Vec<PhaseResult> = results.iter().map(|r| cycle(r, p.phase)).collect();
    Report {
        runs: results.len(),
        deterministic,
        write: block(&write, deterministic, fw),
        erase: block(&erase, deterministic, fe),
        erase_given_write: block(&given, deterministic, fe),
        cycle: block(&cycles, deterministic, fw.max(fe)),
        pull_off_margin_min: results
            .iter()
            .filter(|r| r.status == "ok")
            .filter_map(|r| r.pull_off_margin_min)
            .filter(|m| m.is_finite())
            .reduce(f64::min),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const W: [f64; 2] = [1.0, 2.0];

    /// What the watch of `W` over `[t0, t1]` sees on a path given by its
    /// crossings `(t, edge, rising)` (edge 0: lo, 1: hi), θ(0) = `theta0`,
    /// the run ending at `t_stop` (scaled = seconds here).
    fn stay(
        theta0: f64,
        t0: f64,
        t1: f64,
        cross: &[(f64, usize, bool)],
        t_stop: f64,
    ) -> WindowStay {
        use crate::sim::watch::Watcher;
        let mut w = Watcher::new(
            &[ThetaWatch {
                from: t0,
                to: t1,
                window: W,
            }],
            1.0,
            theta0,
            0.0,
        );
        let mut marks: Vec<(usize, f64)> = w.pending_marks().collect();
        marks.retain(|&(_, m)| m <= t_stop);
        /// A crossing `(edge, rising)` or mark `i`, at a time.
        enum Ev {
            Cross(usize, bool),
            Mark(usize),
        }
        let mut all: Vec<(f64, Ev)> = cross
            .iter()
            .filter(|c| c.0 <= t_stop)
            .map(|&(t, e, r)| (t, Ev::Cross(e, r)))
            .chain(marks.iter().map(|&(i, m)| (m, Ev::Mark(i))))
            .collect();
        all.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (t, ev) in all {
            match ev {
                Ev::Cross(e, r) => w.level_crossed(e, t, r),
                Ev::Mark(i) => w.mark_reached(i, t),
            }
        }
        w.stays()[0]
    }

    #[test]
    fn held_from_an_entry_mid_phase() {
        // In from t = 4.25 to the end (10): held over the last 3 s.
        let s = stay(0.1, 0.0, 10.0, &[(4.25, 0, true)], 10.0);
        let p = judge_phase(&s, 0.0, 10.0, 3.0, None);
        assert_eq!((p.failure, p.time), (None, Some(4.25)));
        assert_eq!(s.work_at_to.unwrap() - s.work_at_from.unwrap(), 10.0);
    }

    #[test]
    fn entered_late_still_in_time_and_too_late() {
        // Enters at 7, hold 3: exactly in time (t1 - hold = 7).
        let s = stay(0.1, 0.0, 10.0, &[(7.0, 0, true)], 10.0);
        let p = judge_phase(&s, 0.0, 10.0, 3.0, None);
        assert_eq!((p.failure, p.time), (None, Some(7.0)));
        // Hold 4: the stay began less than 4 s before the end.
        let p = judge_phase(&s, 0.0, 10.0, 4.0, None);
        assert_eq!((p.failure, p.time), (Some(Mode::TooLate), None));
    }

    #[test]
    fn an_excursion_between_rows_breaks_the_stay() {
        // In at 2, out above at 4.5, back at 4.6 (between rows 1 s apart,
        // which the row test did not see): the stay counts from 4.6.
        let c = [(2.0, 0, true), (4.5, 1, true), (4.6, 1, false)];
        let s = stay(0.1, 0.0, 10.0, &c, 10.0);
        let p = judge_phase(&s, 0.0, 10.0, 3.0, None);
        assert_eq!((p.failure, p.time), (None, Some(4.6)));
        // Out at 8.5 and back at 8.6: inside the hold, so the stay is
        // too late.
        let c = [(2.0, 0, true), (8.5, 0, false), (8.6, 0, true)];
        let p = judge_phase(&stay(0.1, 0.0, 10.0, &c, 10.0), 0.0, 10.0, 3.0, None);
        assert_eq!(p.failure, Some(Mode::TooLate));
    }

    #[test]
    fn left_and_never_entered() {
        let left = stay(0.1, 0.0, 10.0, &[(1.0, 0, true), (9.9, 0, false)], 10.0);
        let p = judge_phase(&left, 0.0, 10.0, 3.0, None);
        assert_eq!((p.failure, p.time), (Some(Mode::Left), None));
        // Crossed the whole window (in at 3, out above at 3.5) and ended
        // above: it was inside, so `left`; never near it: `never_entered`.
        let through = stay(0.1, 0.0, 10.0, &[(3.0, 0, true), (3.5, 1, true)], 10.0);
        assert_eq!(
            judge_phase(&through, 0.0, 10.0, 3.0, None).failure,
            Some(Mode::Left)
        );
        let never = stay(0.1, 0.0, 10.0, &[], 10.0);
        let p = judge_phase(&never, 0.0, 10.0, 3.0, None);
        assert_eq!((p.failure, p.time), (Some(Mode::NeverEntered), None));
    }

    #[test]
    fn phase_limits_and_failed_runs() {
        // Second phase [5, 10], in since 4.5: the stay starts with the
        // phase (time 0).
        let s = stay(0.1, 5.0, 10.0, &[(4.5, 0, true)], 10.0);
        let p = judge_phase(&s, 5.0, 10.0, 2.0, None);
        assert_eq!((p.failure, p.time), (None, Some(0.0)));
        // A stay that ended before the phase does not count as entered.
        let s = stay(0.1, 5.0, 10.0, &[(1.0, 0, true), (2.0, 0, false)], 10.0);
        assert_eq!(
            judge_phase(&s, 5.0, 10.0, 2.0, None).failure,
            Some(Mode::NeverEntered)
        );
        // A run that failed at 8 did not reach the phase's end.
        let cut = stay(0.1, 5.0, 10.0, &[(4.5, 0, true)], 8.0);
        assert!(!cut.reached_end);
        let p = judge_phase(&cut, 5.0, 10.0, 2.0, Some(Failure::LiftOff));
        assert_eq!(p.failure, Some(Mode::LiftedOff));
        let p = judge_phase(&cut, 5.0, 10.0, 2.0, Some(Failure::StepLimit));
        assert_eq!(p.failure, Some(Mode::RunFailed));
    }

    /// The Wilson interval's closed form on hand values.
    #[test]
    fn wilson_hand_values() {
        // n = 10, 5 successes, z = 2: centre (0.5 + 0.2)/1.4 = 0.5,
        // half = 2/1.4 sqrt(0.025 + 0.01) = 0.267261...
        let [lo, hi] = wilson(5, 10, 2.0).unwrap();
        let half = 2.0 / 1.4 * 0.035f64.sqrt();
        assert!((lo - (0.5 - half)).abs() < 1e-15 && (hi - (0.5 + half)).abs() < 1e-15);
        // 0 of 10 at z = 2: [0, z^2/(n + z^2)] = [0, 4/14].
        let [lo, hi] = wilson(0, 10, 2.0).unwrap();
        assert!(lo.abs() < 1e-15, "{lo}");
        assert!((hi - 4.0 / 14.0).abs() < 1e-15, "{hi}");
        // 10 of 10: [n/(n + z^2), 1] = [10/14, 1].
        let [lo, hi] = wilson(10, 10, 2.0).unwrap();
        assert!((lo - 10.0 / 14.0).abs() < 1e-15 && hi == 1.0, "{lo} {hi}");
        // Every endpoint solves the score equation (p̂ − p)² = z² p (1 − p)/n.
        for (s, n) in [(3, 7), (17, 40), (1, 100)] {
            let [lo, hi] = wilson(s, n, Z95).unwrap();
            let ph = s as f64 / n as f64;
            for p in [lo, hi] {
                let lhs = (ph - p).powi(2);
                let rhs = Z95 * Z95 * p * (1.0 - p) / n as f64;
                assert!((lhs - rhs).abs() < 1e-14, "{s}/{n}: {lhs} vs {rhs}");
            }
        }
        assert_eq!(wilson(0, 0, Z95), None);
    }

    /// The closed forms at the ends, exactly: 0 of n gives
    /// `[0, z²/(n + z²)]` and n of n `[n/(n + z²), 1]`, the bounds 0 and 1
    /// bit for bit (not the rounding residue of `centre − half`, which is
    /// 3.5e-18 for 0 of 100 at z = 1.96), the others to 2 ulps.
    #[test]
    fn wilson_ends_are_exact() {
        for n in [1, 2, 3, 7, 10, 16, 100, 1000, 4096, 1_000_000] {
            for z in [Z95, 1.0, 2.0, 2.5758293035489004] {
                let (nf, z2) = (n as f64, z * z);
                let close = |a: f64, b: f64| (a - b).abs() <= 2.0 * f64::EPSILON * b;
                let [lo, hi] = wilson(0, n, z).unwrap();
                assert_eq!(lo.to_bits(), 0.0f64.to_bits(), "0 of {n}, z {z}: {lo:e}");
                assert!(close(hi, z2 / (nf + z2)), "0 of {n}, z {z}: {hi}");
                let [lo, hi] = wilson(n, n, z).unwrap();
                assert_eq!(hi, 1.0, "{n} of {n}, z {z}: {hi}");
                assert!(close(lo, nf / (nf + z2)), "{n} of {n}, z {z}: {lo}");
            }
        }
    }

    fn binomial_pmf(n: usize, k: usize, p: f64) -> f64 {
        // ln C(n, k) by sums of logs (exact enough for n <= 200).
        let ln_c: f64 = (1..=k)
            .map(|i| ((n - k + i) as f64).ln() - (i as f64).ln())
            .sum();
        (ln_c + k as f64 * p.ln() + (n - k) as f64 * (1.0 - p).ln()).exp()
    }

    /// Exact coverage: Σ_k P(X = k) [p ∈ CI(k)].
    fn coverage(n: usize, p: f64) -> f64 {
        (0..=n)
            .filter(|&k| {
                let [lo, hi] = wilson(k, n, Z95).unwrap();
                lo <= p && p <= hi
            })
            .map(|k| binomial_pmf(n, k, p))
            .sum()
    }

    /// The coverage against the exact binomial coverage: p ∈ CI(k) iff
    /// |k − n p| <= z sqrt(n p (1 − p)) (the score test the interval
    /// inverts), so for n = 20, p = 1/2 the interval covers exactly for
    /// k = 6..14 (|k − 10| <= 4.38): 1 − 2 P(X <= 5) = 1 − 2 × 21700/2^20.
    #[test]
    fn wilson_coverage_is_the_exact_binomial_coverage() {
        let exact = 1.0 - 2.0 * 21700.0 / 1048576.0;
        assert!(
            (coverage(20, 0.5) - exact).abs() < 1e-12,
            "{}",
            coverage(20, 0.5)
        );
        // Other (n, p): the covered k are those of the score test.
        for (n, p) in [(50, 0.3), (100, 0.1), (100, 0.5), (37, 0.8)] {
            let score: f64 = (0..=n)
                .filter(|&k| {
                    (k as f64 - n as f64 * p).abs() <= Z95 * (n as f64 * p * (1.0 - p)).sqrt()
                })
                .map(|k| binomial_pmf(n, k, p))
                .sum();
            let c = coverage(n, p);
            assert!((c - score).abs() < 1e-12, "n {n} p {p}: {c} vs {score}");
            // Wilson is near nominal for these (n, p).
            assert!((0.92..0.98).contains(&c), "n {n} p {p}: coverage {c}");
        }
    }

    /// `parse_csv_row` inverts `csv_row`, quoted statuses and missing
    /// values included, and rejects other lines.
    #[test]
    fn runs_csv_rows_parse_back() {
        let p = |failure, time, energy| PhaseResult {
            failure,
            time,
            energy,
        };
        for r in [
            RunResult {
                run: 7,
                status: "ok".into(),
                write: p(None, Some(4.07e-5), Some(-1.25e-30)),
                erase: p(Some(Mode::Left), None, Some(0.1 + 0.2)),
                pull_off_margin_min: None,
            },
            RunResult {
                run: 4294967295,
                status: "run failed at t = 1e-9 s: lift-off, \"N < 0\", here".into(),
                write: p(Some(Mode::LiftedOff), None, None),
                erase: p(Some(Mode::RunFailed), None, None),
                pull_off_margin_min: Some(3.5e-11),
            },
        ] {
            let line = csv_row(&r);
            assert_eq!(
                parse_csv_row(line.trim_end_matches('\n')),
                Some(r),
                "{line}"
            );
        }
        for bad in [
            "",
            "x,ok,ok,,,ok,,,",
            "1,ok,ok,,,ok,,",
            "1,ok,maybe,,,ok,,,",
        ] {
            assert_eq!(parse_csv_row(bad), None, "{bad}");
        }
    }

    #[test]
    fn quantiles_and_forces() {
        assert_eq!(quantile(&[3.0, 1.0, 2.0, 4.0], 0.5), Some(2.5));
        assert_eq!(quantile(&[3.0, 1.0, 2.0, 4.0], 0.25), Some(1.75));
        assert_eq!(quantile(&[], 0.5), None);
        let w = |hx: f64, start: f64, stop: f64| Actuator {
            kind: crate::input::scenario::bit::ActuatorKind::Contact,
            hx,
            hy: 0.0,
            hz: 0.0,
            start,
            stop,
        };
        // Overlapping windows add: 3 + 4 on [1, 2).
        assert_eq!(
            max_applied_force(&[w(3.0, 0.0, 2.0), w(4.0, 1.0, 3.0)]),
            7.0
        );
        // Disjoint windows do not.
        assert_eq!(
            max_applied_force(&[w(3.0, 0.0, 1.0), w(4.0, 1.0, 3.0)]),
            4.0
        );
        assert_eq!(max_applied_force(&[]), 0.0);
    }
}
