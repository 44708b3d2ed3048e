//! The paths of the splitting: a path is a [`Simulation`] run from a start
//! state with its own noise branch until it meets the target or the reset
//! (or its horizon, or its step budget), watched at every step. What it
//! keeps is what a later branching needs: its start (a snapshot), the
//! running maxima of the reaction coordinate (step, value), and a few
//! checkpoints (snapshots) along the way, so that the state at the first
//! step above a level is found by replaying at most a few checkpoint
//! intervals of its own noise.
//!
//! Why replay works: the noise of step `k` of branch `b` is a pure function
//! of (seed, run, b, k) ([`crate::simulate::noise_counter`]), and a
//! [`Simulation`] paused after any accepted step and continued takes the
//! same steps as one never paused. So restoring a checkpoint of a path and
//! stepping on gives, bit for bit, the states the path went through.

use std::rc::Rc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::{Coordinate, TiltEnergy};
use crate::Scenario;
use crate::analysis::ensemble::Exit;
use crate::simulate::{Simulation, Snapshot, StepProbe};

/// Steps between the first checkpoints of a path; the interval doubles
/// each time the path holds more than [`MAX_CHECKPOINTS`] (every other one
/// is dropped), so a path keeps at most that many snapshots and a replay
/// takes at most about `4 / MAX_CHECKPOINTS` of the path's length.
const CHECKPOINT_EVERY: u64 = 512;

/// Largest number of checkpoints a path keeps.
const MAX_CHECKPOINTS: usize = 16;

/// Steps between two looks at the cancel flag inside a path.
const CANCEL_EVERY: u64 = 1024;

/// What ends a path besides the target: a condition, the basin of the
/// flux relation (`ξ <= level`), or nothing.
#[derive(Debug, Clone, PartialEq)]
pub(super) enum Reset {
    /// A condition over trajectory.csv columns (`--reset`).
    Cond(Exit),
    /// Back in the basin: `ξ <= level`.
    Basin(f64),
    /// No reset (a direct run towards the target).
    Never,
}

/// The reaction coordinate, the target and the reset, evaluated on a
/// step's state: θ alone where nothing else is read (an `atan2`), else the
/// whole output row.
#[derive(Debug, Clone)]
pub(super) struct Watch {
    pub(super) coordinate: Coordinate,
    /// The tilt energy's parameters ([`Coordinate::TiltEnergy`]).
    tilt: Option<TiltEnergy>,
    pub(super) target: Exit,
    pub(super) reset: Reset,
    row: bool,
}

/// Columns that need no output row: `t` (0) and `theta` (1).
fn cheap(column: usize) -> bool {
    column <= 1
}

impl Watch {
    pub(super) fn new(coordinate: Coordinate, target: Exit, reset: Reset, sc: &Scenario) -> Watch {
        let mut row = coordinate.columns().into_iter().any(|c| !cheap(c))
            || target.columns().any(|c| !cheap(c));
        if let Reset::Cond(r) = &reset {
            row |= r.columns().any(|c| !cheap(c));
        }
        Watch {
            coordinate,
            tilt: (coordinate == Coordinate::TiltEnergy).then(|| TiltEnergy::of(sc)),
            target,
            reset,
            row,
        }
    }

    /// `(ξ, target holds, reset holds)` from a row's values ([`COLUMNS`]
    /// order).
    ///
    /// [`COLUMNS`]: crate::trajectory::COLUMNS
    pub(super) fn eval_values(&self, get: &dyn Fn(usize) -> f64) -> (f64, bool, bool) {
        let xi = match &self.tilt {
            Some(e) => e.value(get(1), get(2)),
            None => self.coordinate.value(get),
        };
        let target = self.target.hit_by(get);
        let reset = match &self.reset {
            Reset::Cond(r) => r.hit_by(get),
            Reset::Basin(level) => xi <= *level,
            Reset::Never => false,
        };
        (xi, target, reset)
    }

    /// The same at the end of a step.
    pub(super) fn eval(&self, p: &dyn StepProbe) -> (f64, bool, bool) {
        if self.row {
            let v = p.row().values();
            self.eval_values(&|i| v[i])
        } else {
            let (t, theta) = (p.time(), p.theta());
            self.eval_values(&|i| if i == 0 { t } else { theta })
        }
    }
}

/// How a path ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum End {
    /// The target held at a step (score `+∞`).
    Target,
    /// The reset held at a step.
    Reset,
    /// The horizon `T` passed (the run reached its `t_end`).
    Horizon,
    /// The step budget ran out (counted from the path's root).
    Budget,
    /// The run failed (a run-time error of the simulation).
    Failed,
}

/// One particle of the splitting (see the module doc).
#[derive(Clone)]
pub(super) struct Path {
    /// Its start, with its own noise branch set.
    start: Rc<Snapshot>,
    /// Running maxima of ξ over its own steps: `(global step, ξ)`, the
    /// start first; increasing in both.
    records: Vec<(u64, f64)>,
    /// Snapshots along the path, `(global step, snapshot)`, in step order.
    checkpoints: Vec<(u64, Rc<Snapshot>)>,
    /// Global step of the root's start (the path's step budget counts
    /// from there).
    pub(super) root_steps: u64,
    /// Time of the root's start \[s\].
    pub(super) root_time: f64,
    /// How it ended.
    pub(super) end: End,
    /// Its score: the largest ξ over its steps before the one that ended
    /// it, `+∞` if it met the target.
    pub(super) score: f64,
    /// The time it ended \[s\].
    pub(super) end_time: f64,
}

/// The cancel flag was seen set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Cancelled;

/// Why [`Runner::extend`] paused the run.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Pause {
    None,
    Target,
    Reset,
    Budget,
    Checkpoint,
    Cancel,
}

/// Runs and branches paths on one [`Simulation`] (one replica's, on one
/// thread).
pub(super) struct Runner<'a> {
    pub(super) sim: Simulation,
    pub(super) watch: &'a Watch,
    /// Step budget of a path, from its root's start.
    pub(super) max_steps: u64,
    /// Whether the run's `t_end` is the horizon (else it is a backstop
    /// beyond the budget: reaching it counts as the budget).
    pub(super) horizon: bool,
    pub(super) cancel: Option<&'a AtomicBool>,
    /// Steps integrated so far, replays included.
    pub(super) steps: u64,
    /// The steps of every replica so far, for progress ([`super::Hooks`]).
    pub(super) all_steps: Option<&'a std::sync::atomic::AtomicU64>,
    /// Paths ended by a failure, and the first failure's message.
    pub(super) failed: u64,
    pub(super) first_failure: Option<String>,
}

impl Runner<'_> {
    /// Count `steps` more steps, here and in the progress counter.
    pub(super) fn count(&mut self, steps: u64) {
        self.steps += steps;
        if let Some(all) = self.all_steps {
            all.fetch_add(steps, Ordering::Relaxed);
        }
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// A root path from the state `start` with noise branch `branch`: its
    /// steps and time count from there.
    pub(super) fn root(&mut self, start: &Snapshot, branch: u64) -> Result<Path, Cancelled> {
        self.sim.restore(start);
        self.sim.set_noise_branch(branch);
        let row = self.sim.state().values();
        let (xi, target, reset) = self.watch.eval_values(&|i| row[i]);
        let steps = self.sim.steps_taken();
        let t = self.sim.time();
        let mut path = Path {
            start: Rc::new(self.sim.snapshot()),
            records: vec![(steps, xi)],
            checkpoints: Vec::new(),
            root_steps: steps,
            root_time: t,
            end: End::Budget,
            score: xi,
            end_time: t,
        };
        if target {
            path.end = End::Target;
            path.score = f64::INFINITY;
        } else if reset {
            path.end = End::Reset;
            path.score = f64::NEG_INFINITY;
        } else {
            self.extend(&mut path)?;
        }
        Ok(path)
    }

    /// A copy of `parent` up to its first step with `ξ > level` (the state
    /// there, replayed from its last checkpoint before it), continued with
    /// the noise of `branch`. If `parent` exceeds `level` only by meeting
    /// the target, the copy is `parent` itself.
    pub(super) fn branch(
        &mut self,
        parent: &Path,
        level: f64,
        branch: u64,
    ) -> Result<Path, Cancelled> {
        let i = parent.records.partition_point(|r| r.1 <= level);
        let Some(&(at, xi)) = parent.records.get(i) else {
            debug_assert_eq!(parent.end, End::Target);
            return Ok(parent.clone());
        };
        match parent.checkpoints.iter().rev().find(|c| c.0 <= at) {
            Some((_, snap)) => self.sim.restore(snap),
            None => self.sim.restore(&parent.start),
        }
        let mut steps = self.sim.steps_taken();
        if steps < at {
            let from = steps;
            let reached = self.sim.advance_until(&mut |_| {
                steps += 1;
                steps >= at
            });
            self.count(steps - from);
            assert!(
                reached && steps == at,
                "a replayed path ended before its step {at} (at {steps}): not the same steps"
            );
        }
        if cfg!(debug_assertions) {
            let row = self.sim.state().values();
            let again = self.watch.eval_values(&|i| row[i]).0;
            assert!(
                (again - xi).abs() <= 1e-9 * xi.abs().max(1e-300),
                "a replayed path is not the path: ξ = {again} at step {at}, recorded {xi}"
            );
        }
        self.sim.set_noise_branch(branch);
        let t = self.sim.time();
        let mut path = Path {
            start: Rc::new(self.sim.snapshot()),
            records: vec![(at, xi)],
            checkpoints: Vec::new(),
            root_steps: parent.root_steps,
            root_time: parent.root_time,
            end: End::Budget,
            score: xi,
            end_time: t,
        };
        self.extend(&mut path)?;
        Ok(path)
    }

    /// Run a fresh path (the simulation stands at its start) until it ends.
    fn extend(&mut self, path: &mut Path) -> Result<(), Cancelled> {
        let watch = self.watch;
        let budget_end = path.root_steps.saturating_add(self.max_steps);
        let mut steps = self.sim.steps_taken();
        let mut interval = CHECKPOINT_EVERY;
        let mut next_checkpoint = steps + interval;
        let mut max = path.score;
        let cancel = self.cancel;
        if steps >= budget_end {
            // A copy made at the budget's last step: nothing left to run.
            path.end = End::Budget;
            path.end_time = self.sim.time();
            return Ok(());
        }
        loop {
            let from = steps;
            let mut pause = Pause::None;
            let records = &mut path.records;
            let stopped = self.sim.advance_until(&mut |p| {
                steps += 1;
                let (xi, target, reset) = watch.eval(p);
                if target {
                    pause = Pause::Target;
                    return true;
                }
                if reset {
                    pause = Pause::Reset;
                    return true;
                }
                if xi > max {
                    max = xi;
                    records.push((steps, xi));
                }
                if steps >= budget_end {
                    pause = Pause::Budget;
                    return true;
                }
                if steps >= next_checkpoint {
                    pause = Pause::Checkpoint;
                    return true;
                }
                if steps % CANCEL_EVERY == 0 && cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    pause = Pause::Cancel;
                    return true;
                }
                false
            });
            self.count(steps - from);
            path.end_time = self.sim.time();
            path.end = match (stopped, pause) {
                (true, Pause::Checkpoint) => {
                    path.checkpoints.push((steps, Rc::new(self.sim.snapshot())));
                    if path.checkpoints.len() > MAX_CHECKPOINTS {
                        let mut k = 0;
                        path.checkpoints.retain(|_| {
                            k += 1;
                            k % 2 == 0
                        });
                        interval *= 2;
                    }
                    next_checkpoint = steps + interval;
                    continue;
                }
                (true, Pause::Cancel) => return Err(Cancelled),
                (true, Pause::Target) => End::Target,
                (true, Pause::Reset) => End::Reset,
                (true, _) => End::Budget,
                (false, _) => match self.sim.error() {
                    Some(e) => {
                        self.failed += 1;
                        self.first_failure.get_or_insert_with(|| e.to_string());
                        End::Failed
                    }
                    None if self.horizon => End::Horizon,
                    None => End::Budget,
                },
            };
            break;
        }
        path.score = match path.end {
            End::Target => f64::INFINITY,
            _ => max,
        };
        if self.cancelled() {
            return Err(Cancelled);
        }
        Ok(())
    }
}
