//! Run a scenario: the one driver that turns a [`Scenario`] into a
//! [`Trajectory`], for every model (reduced, vector, rigid: each implements
//! `model::Model`).
//!
//! The driver owns what the integrator does not know about: the switch
//! times of the force schedule (each one ends a `solve` call, so the model
//! can re-examine stick/slip, the normal-force branch and contact with the
//! new force there), the events the model needs in its current discrete
//! state (θ crossing π/2, local maxima of θ, N crossing zero, the
//! stick/slip switches of the exact Coulomb law, lift-off and touchdown),
//! the samples, the step limit over the whole run, the mapping of
//! integration failures to messages, the record of events and intervals
//! and the summary. What a terminal event does is the model's
//! (`Model::on_terminal`): continue on the other branch, switch between
//! sliding and rolling, lift off, apply an impact; the driver restarts the
//! integration from the state the handler leaves.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use crate::{
    Error, Failure, ModelKind, Sample, Scenario, Trajectory,
    integrate::{self, AnyEngine, Engine, Event, IntegrateError, Stepped, Stepper, Stepping},
    model::{
        ContactModel, Flow, Model,
        reduced::{self, DIM, Reduced},
        rigid::{self, Rigid},
        vector::{self, Vector},
    },
    sim::events::{Happened, Watch},
    sim::messages::{nonfinite_output_why, step_limit_why, unstable_rk4},
    sim::record::{RunEnd, RunLog, RunSetup, Track, summarize},
    sim::runaway::{axis_blown, blow_up_why},
    sim::watch::{ThetaWatch, Watcher, WindowStay},
};

/// Largest number of accepted steps of one run before it is stopped (see
/// [`crate::limits::MAX_STEPS`] and [`crate::limits::max_steps_for`]).
pub use crate::limits::MAX_STEPS;
/// Largest number of stick/slip switches of one run before it is stopped.
pub use crate::sim::record::MAX_SWITCHES;

/// Run `scenario`. `Err` only for bad input; a run that fails while
/// integrating returns `Ok` with `trajectory.error` set and the samples up to
/// the failure.
pub fn simulate(scenario: &Scenario) -> Result<Trajectory, Error> {
    simulate_with_progress(scenario, &mut |_| {})
}

/// As [`simulate`], for one run of an ensemble (`analysis::ensemble`):
/// the same steps, samples, events and θ, spin and N statistics (so the
/// row is the same bits as [`simulate`]'s, which replays it), but the
/// per-step record skips Jellett's J and the energy, which the row does not
/// read: the summary's J drift and energy balance of such a run are those
/// of its events and segment ends only (docs/performance.md#langevin-step).
pub(crate) fn simulate_for_row(scenario: &Scenario) -> Result<Trajectory, Error> {
    scenario.validate()?;
    fn go<M: Model<D> + Clone, const D: usize>(sc: &Scenario, m: M) -> Trajectory {
        let mut sim = Sim::new(sc, m);
        sim.light = true;
        let t_end = sim.t_end;
        sim.advance(t_end, &mut |_, _, _| {}, &mut |_| {});
        sim.finish()
    }
    Ok(match scenario.solver.model {
        ModelKind::Reduced => go(scenario, <Reduced as ContactModel<DIM>>::build(scenario)),
        ModelKind::Vector => go(
            scenario,
            <Vector as ContactModel<{ vector::DIM }>>::build(scenario),
        ),
        ModelKind::Rigid => go(scenario, Rigid::new(scenario)),
    })
}

/// As [`simulate`], watching the θ windows `watches` on the continuous
/// solution ([`crate::sim::watch`]: events at the windows' edges and at the
/// intervals' ends): the trajectory (the same bits as [`simulate`]'s: the
/// watch events never change a step) and what each watch saw, in the order
/// given. Each watch needs `0 <= from <= to` \[s\] and a window
/// `0 <= lo < hi <= π` \[rad\].
pub fn simulate_watching(
    scenario: &Scenario,
    watches: &[ThetaWatch],
) -> Result<(Trajectory, Vec<WindowStay>), Error> {
    simulate_watching_with_progress(scenario, watches, &mut |_| {})
}

/// As [`simulate_watching`], with the progress callback of
/// [`simulate_with_progress`].
pub fn simulate_watching_with_progress(
    scenario: &Scenario,
    watches: &[ThetaWatch],
    progress: &mut dyn FnMut(&Progress),
) -> Result<(Trajectory, Vec<WindowStay>), Error> {
    simulate_watching_with_pose(scenario, watches, true, progress)
}

/// As [`simulate_watching_with_progress`], the pose computed or not
/// ([`simulate_with_pose`]).
pub fn simulate_watching_with_pose(
    scenario: &Scenario,
    watches: &[ThetaWatch],
    pose: bool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<(Trajectory, Vec<WindowStay>), Error> {
    scenario.validate()?;
    for w in watches {
        assert!(
            0.0 <= w.from && w.from <= w.to && w.to.is_finite(),
            "a watch needs 0 <= from <= to (got {w:?})"
        );
        assert!(
            0.0 <= w.window[0] && w.window[0] < w.window[1] && w.window[1] <= std::f64::consts::PI,
            "a watch needs 0 <= lo < hi <= pi (got {w:?})"
        );
    }
    fn go<M: Model<D> + Clone, const D: usize>(
        sc: &Scenario,
        m: M,
        watches: &[ThetaWatch],
        progress: &mut dyn FnMut(&Progress),
    ) -> (Trajectory, Vec<WindowStay>) {
        let mut sim = Sim::new_watching(sc, m, watches);
        let t_end = sim.t_end;
        sim.advance(t_end, &mut |_, _, _| {}, progress);
        sim.finish_watching()
    }
    Ok(match scenario.solver.model {
        ModelKind::Reduced if !pose => go(
            scenario,
            <Reduced<{ reduced::CONTROLLED }> as ContactModel<{ reduced::CONTROLLED }>>::build(
                scenario,
            ),
            watches,
            progress,
        ),
        ModelKind::Reduced => go(
            scenario,
            <Reduced as ContactModel<DIM>>::build(scenario),
            watches,
            progress,
        ),
        ModelKind::Vector if !pose => go(
            scenario,
            <Vector<{ vector::CONTROLLED }> as ContactModel<{ vector::CONTROLLED }>>::build(
                scenario,
            ),
            watches,
            progress,
        ),
        ModelKind::Vector => go(
            scenario,
            <Vector as ContactModel<{ vector::DIM }>>::build(scenario),
            watches,
            progress,
        ),
        ModelKind::Rigid => go(scenario, Rigid::new(scenario), watches, progress),
    })
}

/// Accepted steps between two calls of the progress callback of
/// [`simulate_with_progress`], and what it is told.
pub use crate::sim::record::{PROGRESS_EVERY, Progress};
pub use crate::sim::runaway::RunawayWatch;

/// Accepted steps between two questions to the `keep_going` callback of
/// [`Simulation::integrate_to_while`]: 1024 (a step takes 0.1 to 10 µs, so
/// a few hundred times a second or more).
pub const CHECK_EVERY: u64 = 1024;

thread_local! {
    /// The flag of the [`stoppable`] call this thread is inside, if any.
    static STOP: std::cell::RefCell<Option<Arc<AtomicBool>>> =
        const { std::cell::RefCell::new(None) };
}

/// Run `f` so that once `stop` is set, every run made inside it (on this
/// thread, or on the worker threads of a sweep, an ensemble or a direct
/// rare-event ensemble it starts) ends within [`CHECK_EVERY`] accepted
/// steps, failed ("interrupted"), and those analyses start no further run
/// (their sink is still called with each result, in order, until it says
/// stop). For a caller that runs a long analysis on one thread and watches
/// for an interrupt (Python's Ctrl-C) on another: without it a run in
/// progress could go on for minutes.
pub fn stoppable<R>(stop: &Arc<AtomicBool>, f: impl FnOnce() -> R) -> R {
    with_stop_flag(Some(stop.clone()), f)
}

/// The flag of the [`stoppable`] call this thread is inside (`None`:
/// none), for a thread pool to hand to its workers ([`with_stop_flag`]).
pub(crate) fn stop_flag() -> Option<Arc<AtomicBool>> {
    STOP.with(|s| s.borrow().clone())
}

/// Run `f` with `flag` as this thread's stop flag (see [`stoppable`]),
/// the previous one restored afterwards, also if `f` panics.
pub(crate) fn with_stop_flag<R>(flag: Option<Arc<AtomicBool>>, f: impl FnOnce() -> R) -> R {
    struct Restore(Option<Arc<AtomicBool>>);
    impl Drop for Restore {
        fn drop(&mut self) {
            let prev = self.0.take();
            STOP.with(|s| *s.borrow_mut() = prev);
        }
    }
    let _restore = Restore(STOP.with(|s| s.replace(flag)));
    f()
}

/// True if this thread is inside a [`stoppable`] call whose flag is set.
pub(crate) fn stop_requested() -> bool {
    STOP.with(|s| {
        s.borrow()
            .as_ref()
            .is_some_and(|f| f.load(Ordering::Relaxed))
    })
}

/// As [`simulate`], calling `progress` with the fraction `t / t_end` of the
/// run done (in `[0, 1]`), the time, the step count and the spin
/// ([`Progress`]) every [`PROGRESS_EVERY`] accepted steps (a few hundred
/// times per second at most: cheap enough to print or to update a bar
/// from; the state lets a caller see a run running away before it fails).
/// Not called for a run that is rejected as bad input. The calls never
/// change a step.
pub fn simulate_with_progress(
    scenario: &Scenario,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Trajectory, Error> {
    simulate_with_pose(scenario, true, progress)
}

/// As [`simulate_with_progress`], computing the pose (the centre of
/// mass's position and the attitude: the columns [`crate::trajectory::POSE_COLUMNS`])
/// only if `pose`. Without it the vector model integrates the motion's
/// ten components alone (`k, w, v`, the works: not the attitude's
/// quadratures and the position, which no other rate reads), the reduced
/// model its eight (not `φ, ψ`, the position and `(c_φ, s_φ)`), so the
/// steps, the events, the summary and every other column are the same
/// bits as with the pose, at less cost (docs/performance.md#pose); the
/// pose columns of its rows are NaN. The rigid model computes the pose
/// either way (its rows are the same as with `pose`: the pose is its
/// state).
pub fn simulate_with_pose(
    scenario: &Scenario,
    pose: bool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Trajectory, Error> {
    scenario.validate()?;
    match scenario.solver.model {
        ModelKind::Reduced if !pose => Ok(run(
            scenario,
            <Reduced<{ reduced::CONTROLLED }> as ContactModel<{ reduced::CONTROLLED }>>::build(
                scenario,
            ),
            &mut |_, _, _| {},
            progress,
        )),
        ModelKind::Vector if !pose => Ok(run(
            scenario,
            <Vector<{ vector::CONTROLLED }> as ContactModel<{ vector::CONTROLLED }>>::build(
                scenario,
            ),
            &mut |_, _, _| {},
            progress,
        )),
        ModelKind::Reduced => Ok(run(
            scenario,
            <Reduced as ContactModel<DIM>>::build(scenario),
            &mut |_, _, _| {},
            progress,
        )),
        ModelKind::Vector => Ok(run(
            scenario,
            <Vector as ContactModel<{ vector::DIM }>>::build(scenario),
            &mut |_, _, _| {},
            progress,
        )),
        ModelKind::Rigid => Ok(run(
            scenario,
            Rigid::new(scenario),
            &mut |_, _, _| {},
            progress,
        )),
    }
}

/// Run `sc` with the rigid model, calling `observe(model, t, y)` (scaled
/// time and state) after every accepted step (the scenario is assumed
/// validated). For tests and diagnostics that need the rigid model's own
/// state (quaternion, body rates).
pub fn simulate_rigid_observed(
    sc: &Scenario,
    observe: &mut dyn FnMut(&Rigid, f64, &[f64; rigid::DIM]),
) -> Trajectory {
    run(sc, Rigid::new(sc), observe, &mut |_| {})
}

/// A run you can step, inspect, copy and continue (REBOUND-style): the same
/// driver as [`simulate`], paused and resumed at accepted steps only, so
/// where you stop it never changes a step.
///
/// - [`Simulation::integrate_to`] integrates until the run has passed `t`
///   (never shortening a step to land on it); [`Simulation::state`] is the
///   state at `t`, read from the dense output of the step that contains it.
///   Integrating to `t1` and then to `t2` gives the same trajectory, bit for
///   bit, as one call to `t2`.
/// - [`Simulation::snapshot`] copies everything (the integrator's last
///   step, the model's discrete state: sliding or rolling, the latched
///   normal-force branch, contact or flight; the record so far) with exact
///   floats; [`Simulation::restore`] goes back to it.
/// - [`Simulation::into_trajectory`] is the run so far (samples up to the
///   last accepted step, events, summary): after `integrate_to(t_end)` it
///   equals [`simulate`]'s.
///
/// ```
/// use tippetop::{Scenario, Simulation};
///
/// let mut sc = Scenario::nano();
/// sc.solver.t_end = 20e-6; // s
/// let mut sim = Simulation::new(&sc)?;
/// sim.integrate_to(10e-6)?;
/// let mid = sim.state(); // SI, one trajectory.csv row
/// println!("θ = {} rad at t = {} s", mid.theta, mid.t);
/// let saved = sim.snapshot();
/// sim.integrate_to(20e-6)?;
/// sim.restore(&saved);
/// sim.integrate_to(20e-6)?;
/// let tr = sim.into_trajectory();
/// assert_eq!(tr.samples, tippetop::simulate(&sc)?.samples);
/// # Ok::<(), tippetop::Error>(())
/// ```
pub struct Simulation {
    inner: AnySim,
    /// The time `state` refers to (scaled).
    at: f64,
    #[allow(clippy::type_complexity)]
    observer: Option<Box<dyn FnMut(&Sample) + Send>>,
}

/// A copy of a [`Simulation`] at one instant ([`Simulation::snapshot`]).
#[derive(Clone)]
pub struct Snapshot {
    inner: AnySim,
    at: f64,
}

/// The driver over each model (no generic parameter at the API).
#[derive(Clone)]
enum AnySim {
    Reduced(Box<Sim<Reduced, DIM>>),
    Vector(Box<Sim<Vector, { vector::DIM }>>),
    /// The vector model without the pose ([`simulate_with_pose`]).
    Motion(Box<Sim<Vector<{ vector::CONTROLLED }>, { vector::CONTROLLED }>>),
    /// The reduced model without the pose ([`simulate_with_pose`]).
    ReducedMotion(Box<Sim<Reduced<{ reduced::CONTROLLED }>, { reduced::CONTROLLED }>>),
    Rigid(Box<Sim<Rigid, { rigid::DIM }>>),
}

/// `$body` with `$s` bound to the inner `Sim` of whichever model.
macro_rules! with_sim {
    ($inner:expr, $s:ident => $body:expr) => {
        match $inner {
            AnySim::Reduced($s) => $body,
            AnySim::Vector($s) => $body,
            AnySim::Motion($s) => $body,
            AnySim::ReducedMotion($s) => $body,
            AnySim::Rigid($s) => $body,
        }
    };
}

impl Snapshot {
    /// The run as it stood at the snapshot, as [`Simulation::into_trajectory`]
    /// gives it (without a second copy of the run).
    pub fn into_trajectory(self) -> Trajectory {
        with_sim!(self.inner, s => (*s).finish())
    }
}

impl Simulation {
    /// Set up a run of `scenario` at `t = 0` (validated: `Err` for bad
    /// input, as [`simulate`]).
    pub fn new(scenario: &Scenario) -> Result<Self, Error> {
        Self::with_pose(scenario, true)
    }

    /// As [`Simulation::new`], computing the pose only if `pose`
    /// ([`simulate_with_pose`]: the same steps and the same bits in every
    /// other column; the pose columns NaN without it).
    pub fn with_pose(scenario: &Scenario, pose: bool) -> Result<Self, Error> {
        scenario.validate()?;
        let sc = scenario;
        let inner = match sc.solver.model {
            ModelKind::Reduced if !pose => AnySim::ReducedMotion(Box::new(Sim::new(
                sc,
                <Reduced<{ reduced::CONTROLLED }> as ContactModel<{ reduced::CONTROLLED }>>::build(
                    sc,
                ),
            ))),
            ModelKind::Vector if !pose => AnySim::Motion(Box::new(Sim::new(
                sc,
                <Vector<{ vector::CONTROLLED }> as ContactModel<{ vector::CONTROLLED }>>::build(sc),
            ))),
            ModelKind::Reduced => AnySim::Reduced(Box::new(Sim::new(
                sc,
                <Reduced as ContactModel<DIM>>::build(sc),
            ))),
            ModelKind::Vector => AnySim::Vector(Box::new(Sim::new(
                sc,
                <Vector as ContactModel<{ vector::DIM }>>::build(sc),
            ))),
            ModelKind::Rigid => AnySim::Rigid(Box::new(Sim::new(sc, Rigid::new(sc)))),
        };
        Ok(Simulation {
            inner,
            at: 0.0,
            observer: None,
        })
    }

    /// Call `observer` with the state (one trajectory row, SI) after every
    /// accepted step from now on (at the step's end; at a terminal event,
    /// at the event).
    pub fn set_observer(&mut self, observer: impl FnMut(&Sample) + Send + 'static) {
        self.observer = Some(Box::new(observer));
    }

    /// The same run with the per-step record of an ensemble's run
    /// ([`simulate_for_row`]): θ and the spin at every step, not Jellett's
    /// J and the energy. Samples, events and every row statistic are the
    /// same bits; the summary's J drift and energy balance are those of
    /// the events and segment ends only. For `analysis::ensemble`'s
    /// `--first-passage` runs (docs/performance.md#langevin-step).
    pub(crate) fn lean(mut self) -> Self {
        with_sim!(&mut self.inner, s => s.light = true);
        self
    }

    /// A path of `analysis::rare`: the ensemble's lean per-step record
    /// ([`Simulation::lean`]) and no event record (nothing reads it, and a
    /// path is copied at every branching). The steps are the same bits.
    pub(crate) fn for_paths(mut self) -> Self {
        with_sim!(&mut self.inner, s => {
            s.light = true;
            s.log.events.off = true;
        });
        self
    }

    /// Step until `stop` returns true for the state at the end of an
    /// accepted step (`analysis::rare`: conditions checked at every step):
    /// `true` then, the run paused just after that step (continuing it
    /// gives the same steps as never pausing); `false` if the run reached
    /// `solver.t_end` or failed first ([`Simulation::error`]).
    pub(crate) fn advance_until(&mut self, stop: &mut dyn FnMut(&dyn StepProbe) -> bool) -> bool {
        let hit = with_sim!(&mut self.inner, s => {
            let tu = s.tu;
            s.advance_until(&mut |m, t, y| stop(&Probe { m, t, y, tu }))
        });
        self.at = with_sim!(&self.inner, s => s.reached());
        hit
    }

    /// Accepted steps of the run so far (its global step count, the
    /// random stream's counter without the branch).
    pub(crate) fn steps_taken(&self) -> u64 {
        with_sim!(&self.inner, s => s.steps_seen)
    }

    /// Where the run stands, as the progress callback of
    /// [`simulate_with_progress`] is told it: the fraction of `solver.t_end`
    /// done, the time \[s\] ([`Simulation::time`]), the accepted steps so
    /// far and the spin there \[rad/s\]. For a caller that integrates in
    /// pieces ([`Simulation::integrate_to_while`]) and watches for a run
    /// that runs away ([`RunawayWatch`]).
    pub fn progress(&self) -> Progress {
        let (tu, t_end) = with_sim!(&self.inner, s => (s.tu, s.t_end));
        Progress {
            fraction: (self.at / t_end).clamp(0.0, 1.0),
            t: self.at * tu,
            steps: self.steps_taken(),
            spin: self.state().spin,
        }
    }

    /// From the next step on, draw the noise of branch `branch`: step `k`
    /// of the run takes the stream's counter [`noise_counter`]`(branch, k)`
    /// (branch 0 is every other run's stream). For `analysis::rare`, which
    /// continues a copied path with fresh noise.
    pub(crate) fn set_noise_branch(&mut self, branch: u64) {
        debug_assert!(branch < 1 << (64 - BRANCH_SHIFT));
        with_sim!(&mut self.inner, s => s.set_noise_base(noise_counter(branch, 0)));
    }

    /// Integrate until the run has passed `t` \[s\] (or ended, or failed:
    /// see [`Simulation::error`]). `Err` if `t` is not finite, before the
    /// time of the last call, or after `solver.t_end`.
    pub fn integrate_to(&mut self, t: f64) -> Result<(), Error> {
        self.integrate_to_while(t, &mut || true).map(|_| ())
    }

    /// As [`Simulation::integrate_to`], asking `keep_going()` every
    /// [`CHECK_EVERY`] accepted steps (a few hundred times a second or
    /// more): when it returns `false` the integration stops after the
    /// current step and this returns `Ok(false)`. The run is then paused
    /// at an accepted step before `t`: [`Simulation::time`] is where it
    /// stands, and integrating on from there gives the same steps, bit for
    /// bit, as if it had not stopped. `Ok(true)`: the run has passed `t`
    /// (or ended). For an interrupt (Python's Ctrl-C) in a long call.
    pub fn integrate_to_while(
        &mut self,
        t: f64,
        keep_going: &mut dyn FnMut() -> bool,
    ) -> Result<bool, Error> {
        let (tu, t_end) = with_sim!(&self.inner, s => (s.tu, s.t_end));
        let target = t / tu;
        if !(target.is_finite() && target >= self.at && target <= t_end) {
            return Err(Error::invalid(
                "t",
                format!("{t} s"),
                format!(
                    "finite, from the last time integrated to ({} s) to solver.t_end ({} s)",
                    self.at * tu,
                    t_end * tu
                ),
            ));
        }
        let observer = &mut self.observer;
        let done = with_sim!(&mut self.inner, s => match observer {
            Some(f) => s.advance_while(target, &mut |m, t, y| f(&m.row(t, y)), &mut |_| {}, keep_going),
            None => s.advance_while(target, &mut |_, _, _| {}, &mut |_| {}, keep_going),
        });
        let reached = with_sim!(&self.inner, s => s.reached());
        // Stopped early, the run stands at the end of its last step.
        self.at = target.min(reached).max(self.at);
        Ok(done)
    }

    /// The time \[s\] the [`Simulation::state`] refers to: the last time
    /// integrated to (earlier if the run failed before it).
    pub fn time(&self) -> f64 {
        self.at * with_sim!(&self.inner, s => s.tu)
    }

    /// The state at [`Simulation::time`], as one trajectory.csv row (SI).
    pub fn state(&self) -> Sample {
        let at = self.at;
        with_sim!(&self.inner, s => {
            let y = s.state_at(at);
            s.m.row(at, &y)
        })
    }

    /// The error that ended the run, if it failed.
    pub fn error(&self) -> Option<&Error> {
        with_sim!(&self.inner, s => s.error.as_ref())
    }

    /// The output rows emitted so far (the samples up to the last
    /// accepted step), in time order.
    pub fn samples(&self) -> &[Sample] {
        with_sim!(&self.inner, s => &s.samples)
    }

    /// True once the run has reached `solver.t_end` or failed.
    pub fn is_finished(&self) -> bool {
        with_sim!(&self.inner, s => s.done)
    }

    /// A copy of the whole run as it stands (see [`Simulation`]); the
    /// observer is not part of it.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            inner: self.inner.clone(),
            at: self.at,
        }
    }

    /// Go back to `snapshot` (taken from a simulation of the same
    /// scenario or any other: it replaces the run entirely; the observer
    /// stays).
    pub fn restore(&mut self, snapshot: &Snapshot) {
        self.inner = snapshot.inner.clone();
        self.at = snapshot.at;
    }

    /// The run so far: samples up to the last accepted step, events and
    /// summary (all of the run after `integrate_to(t_end)`).
    pub fn into_trajectory(self) -> Trajectory {
        with_sim!(self.inner, s => (*s).finish())
    }
}

/// Bits of a random stream's step counter below a branch's index
/// ([`noise_counter`]): a run takes at most
/// [`crate::limits::STEP_LIMIT_MAX`] < 2⁴⁰ steps.
pub(crate) const BRANCH_SHIFT: u32 = 40;

/// The random stream's counter of step `step` of branch `branch`
/// (`analysis::rare`): `branch · 2⁴⁰ + step`, a bijection for steps below
/// 2⁴⁰ and branches below 2²⁴; branch 0 is a plain run's counter.
pub(crate) fn noise_counter(branch: u64, step: u64) -> u64 {
    (branch << BRANCH_SHIFT) + step
}

/// The state at the end of an accepted step, as [`Simulation::advance_until`]
/// shows it: the time, θ alone (cheap), or the whole output row.
pub(crate) trait StepProbe {
    /// Time \[s\].
    fn time(&self) -> f64;
    /// θ \[rad\] (the run's θ: the bits of its largest θ's record).
    fn theta(&self) -> f64;
    /// The whole trajectory.csv row (SI).
    fn row(&self) -> Sample;
}

struct Probe<'a, M, const D: usize> {
    m: &'a M,
    t: f64,
    y: &'a [f64; D],
    tu: f64,
}

impl<M: Model<D>, const D: usize> StepProbe for Probe<'_, M, D> {
    fn time(&self) -> f64 {
        self.t * self.tu
    }
    fn theta(&self) -> f64 {
        self.m.track_angles(self.y).0
    }
    fn row(&self) -> Sample {
        self.m.row(self.t, self.y)
    }
}

/// `cos θ` of a state: the model's own (a few ulps) where it has one, else
/// from θ.
fn cos_theta_of<M: Model<D>, const D: usize>(m: &M, y: &[f64; D]) -> f64 {
    let c = m.cos_theta(y);
    if c.is_nan() {
        m.track_angles(y).0.cos()
    } else {
        c
    }
}

/// Call `progress` for the state `y` of `m` at scaled time `t`, with the
/// time unit `tu` \[s\], the run's scaled end `t_end` and the accepted
/// steps so far: out of line and cold, so the per-step loop stays as
/// small as it was without it.
#[cold]
#[inline(never)]
fn report_progress<M: Model<D>, const D: usize>(
    progress: &mut dyn FnMut(&Progress),
    m: &M,
    t: f64,
    y: &[f64; D],
    (tu, t_end, steps): (f64, f64, u64),
) {
    progress(&Progress {
        fraction: (t / t_end).clamp(0.0, 1.0),
        t: t * tu,
        steps,
        spin: m.row(t, y).spin,
    });
}

/// Record a state in `track`.
fn visit<M: Model<D>, const D: usize>(track: &mut Track, m: &M, y: &[f64; D]) {
    let (theta, spin, j, e, w) = m.track_point(y);
    track.record(theta, spin, j, e, w);
}

/// Run model `m` over the validated scenario `sc` to its end, calling
/// `observe(m, t, y)` after every accepted step and `progress` every
/// [`PROGRESS_EVERY`] steps.
fn run<M: Model<D> + Clone, const D: usize>(
    sc: &Scenario,
    m: M,
    observe: &mut dyn FnMut(&M, f64, &[f64; D]),
    progress: &mut dyn FnMut(&Progress),
) -> Trajectory {
    let mut sim = Sim::new(sc, m);
    let t_end = sim.t_end;
    sim.advance(t_end, observe, progress);
    sim.finish()
}

/// A segment being integrated: its stepper, events, and how it ended (if it
/// did) before the model has handled that.
struct Active<M, const D: usize> {
    st: Stepping<AnyEngine<D>, D>,
    watches: Vec<Watch>,
    events: Vec<Event<M, D>>,
    /// End of the segment: the next force switch or the run's end (scaled).
    seg_end: f64,
    /// The segment ended (at the force switch or end, or at a terminal
    /// event: `Some(i)`), at `(t, y)`, not yet handled.
    ended: Option<(Option<usize>, f64, [f64; D])>,
}

/// The one driver, resumable (see the module doc): model `M` with state
/// dimension `D`, and everything a run records.
struct Sim<M, const D: usize> {
    sc: Scenario,
    m: M,
    tu: f64,
    t_end: f64,
    sample_times: Vec<f64>,
    tstops: Vec<f64>,
    opts: integrate::Options,
    log: RunLog,
    track: Track,
    event_track: Track,
    samples: Vec<Sample>,
    stats: integrate::Stats,
    /// Accepted steps and the last accepted state, kept here too so that a
    /// failed run still reports them.
    steps_seen: u64,
    /// The step limit holds for the whole run, over all its segments.
    step_cap: u64,
    last_accepted: (f64, [f64; D]),
    /// Start of the current segment, or where the run ended (scaled).
    t: f64,
    y: [f64; D],
    error: Option<Error>,
    first_above: Option<f64>,
    switches: usize,
    nonfinite_at: Option<f64>,
    /// The first output row whose state has blown up ([`axis_blown`]): its
    /// index in `samples` and `|k|²` there (`nonfinite_at` is its time).
    blown_row: Option<(usize, f64)>,
    logs_crossings: bool,
    /// The segment being integrated, boxed: a segment's start and end move
    /// a pointer, not the engine's ~2 kB (a nano run has one segment per
    /// ~7 steps).
    active: Option<Box<Active<M, D>>>,
    /// The last ended segment, reused for the next one: its engine renewed
    /// ([`AnyEngine::renew`]: no 3 kB cleared per segment), its lists
    /// refilled in place.
    spare: Option<Box<Active<M, D>>>,
    /// The model's events of a segment as it lists them, before
    /// `begin_segment` splits them into `Active`'s lists (kept: no
    /// allocation per segment).
    event_pairs: Vec<(Watch, Event<M, D>)>,
    done: bool,
    /// An ensemble's run ([`simulate_for_row`]): the per-step record keeps
    /// θ and the spin only (not J and the energy, which the row does not
    /// read).
    light: bool,
    /// Stochastic runs: `∫ N dt` over each output interval (index `i`:
    /// `(s_{i−1}, s_i]`, SI N times scaled time) and the end of the last
    /// step (scaled).
    normal_buckets: Option<Vec<f64>>,
    last_step_t: f64,
    /// θ windows watched on the continuous solution (bit runs:
    /// [`simulate_watching`]).
    watcher: Option<Watcher>,
    /// Added to the random stream's counter of every step: a branch of
    /// `analysis::rare` (`branch << BRANCH_SHIFT`, [`noise_counter`]); 0 for
    /// every other run.
    noise_base: u64,
}

impl<M: Model<D> + Clone, const D: usize> Clone for Sim<M, D> {
    /// A copy of the whole run, the engine's last step and the model's
    /// discrete state included. The events (closures) are rebuilt from the
    /// model: within a segment they depend only on its discrete state,
    /// which does not change until the segment ends.
    fn clone(&self) -> Self {
        Sim {
            sc: self.sc.clone(),
            m: self.m.clone(),
            tu: self.tu,
            t_end: self.t_end,
            sample_times: self.sample_times.clone(),
            tstops: self.tstops.clone(),
            opts: self.opts,
            log: self.log.clone(),
            track: self.track.clone(),
            event_track: self.event_track.clone(),
            samples: self.samples.clone(),
            stats: self.stats,
            steps_seen: self.steps_seen,
            step_cap: self.step_cap,
            last_accepted: self.last_accepted,
            t: self.t,
            y: self.y,
            error: self.error.clone(),
            first_above: self.first_above,
            switches: self.switches,
            nonfinite_at: self.nonfinite_at,
            blown_row: self.blown_row,
            logs_crossings: self.logs_crossings,
            active: self.active.as_ref().map(|a| {
                let mut pairs = Vec::new();
                self.m.events(&mut pairs);
                let (mut watches, mut events): (Vec<_>, Vec<_>) = pairs.into_iter().unzip();
                for &w in &a.watches[watches.len()..] {
                    watches.push(w);
                    events.push(self.watch_event(w));
                }
                debug_assert_eq!(watches, a.watches);
                Box::new(Active {
                    st: a.st.clone(),
                    watches,
                    events,
                    seg_end: a.seg_end,
                    ended: a.ended,
                })
            }),
            spare: None,
            event_pairs: Vec::new(),
            done: self.done,
            light: self.light,
            normal_buckets: self.normal_buckets.clone(),
            last_step_t: self.last_step_t,
            watcher: self.watcher.clone(),
            noise_base: self.noise_base,
        }
    }
}

impl<M: Model<D> + Clone, const D: usize> Sim<M, D> {
    /// Set up the run of model `m` over the validated scenario `sc` at
    /// `t = 0`: the discrete state decided, the samples at `t = 0` not yet
    /// emitted.
    fn new(sc: &Scenario, m: M) -> Self {
        Self::new_watching(sc, m, &[])
    }

    /// As [`Sim::new`], watching the θ windows `watches` on the continuous
    /// solution ([`crate::sim::watch`]).
    fn new_watching(sc: &Scenario, mut m: M, watches: &[ThetaWatch]) -> Self {
        let tu = m.time_unit();
        let RunSetup {
            t_end,
            sample_times,
            tstops,
            mut opts,
        } = RunSetup::new(sc, tu);
        if let Stepper::Dop853 {
            beta,
            stability_cap,
            ..
        } = &mut opts.stepper
        {
            (*beta, *stability_cap) = m.step_hints();
        }
        let mut log = RunLog::new(tu, f64::NAN);
        for &ts in &tstops {
            log.push(ts, Happened::ForceSwitch);
        }
        m.latch_force(0.0);
        let (y, n_initial) = m.start(sc, &mut log);
        log.normal = crate::sim::record::NormalLog::new(n_initial);
        let (theta, spin, j, e, _) = m.track_point(&y);
        let track = Track::new(theta, spin, j, e);
        let step_cap = opts.max_steps;
        let mut sim = Sim {
            sc: sc.clone(),
            tu,
            t_end,
            samples: Vec::with_capacity(sc.solver.samples),
            sample_times,
            tstops,
            opts,
            log,
            event_track: track.clone(),
            track,
            stats: integrate::Stats::default(),
            steps_seen: 0,
            step_cap,
            last_accepted: (0.0, y),
            t: 0.0,
            y,
            error: None,
            first_above: (theta > std::f64::consts::FRAC_PI_2).then_some(0.0),
            switches: 0,
            nonfinite_at: None,
            blown_row: None,
            logs_crossings: !m.flies(),
            active: None,
            spare: None,
            event_pairs: Vec::new(),
            done: false,
            light: false,
            normal_buckets: sc
                .solver
                .method
                .is_stochastic()
                .then(|| vec![0.0; sc.solver.samples]),
            last_step_t: 0.0,
            watcher: None,
            noise_base: 0,
            m,
        };
        if !watches.is_empty() {
            let work0 = sim.m.row(0.0, &sim.y).work_applied;
            sim.watcher = Some(Watcher::new(watches, tu, theta, work0));
        }
        sim.begin_segment();
        sim
    }

    /// How far the run has got (scaled): the end of the last accepted step,
    /// or the end of the run.
    fn reached(&self) -> f64 {
        match self.active.as_deref() {
            Some(Active {
                ended: Some((_, t, _)),
                ..
            }) => *t,
            Some(a) if a.st.stats.steps > 0 => a.st.eng.t(),
            _ => self.t,
        }
    }

    /// The state at scaled time `t`, which must lie in the last accepted
    /// step (or be where the run stands): from the dense output, on copies
    /// of the engine and the model, so nothing the run does changes.
    fn state_at(&self, t: f64) -> [f64; D] {
        if let Some(a) = &self.active {
            if let Some((_, te, ye)) = a.ended {
                if t >= te {
                    return ye;
                }
            }
            if a.st.stats.steps > 0 {
                let eng = &a.st.eng;
                if t >= eng.t() {
                    return *eng.y();
                }
                let mut eng = eng.clone();
                let mut m = self.m.clone();
                let mut stats = integrate::Stats::default();
                let mut out = *eng.y();
                if eng.prepare_dense(&mut m, &mut stats).is_ok() {
                    eng.dense(t.max(eng.t_prev()), &mut out);
                }
                return out;
            }
        }
        self.y
    }

    /// Integrate until the run has reached scaled time `target` (or its
    /// end, or a failure): whole steps only, so where it pauses does not
    /// change any step. What ends a segment is handled only when the run
    /// goes on past it.
    fn advance(
        &mut self,
        target: f64,
        observe: &mut dyn FnMut(&M, f64, &[f64; D]),
        progress: &mut dyn FnMut(&Progress),
    ) {
        self.advance_while(target, observe, progress, &mut || true);
    }

    /// [`Sim::advance`], asking `keep_going()` every [`CHECK_EVERY`]
    /// accepted steps: when it says no, the run stops there (after an
    /// accepted step, so it can go on later, bit for bit as if it had not
    /// stopped) and this returns `false`.
    fn advance_while(
        &mut self,
        target: f64,
        observe: &mut dyn FnMut(&M, f64, &[f64; D]),
        progress: &mut dyn FnMut(&Progress),
        keep_going: &mut dyn FnMut() -> bool,
    ) -> bool {
        // Also here: a caller integrating in pieces shorter than
        // CHECK_EVERY steps never reaches the check in the loop.
        if !self.done && stop_requested() {
            self.interrupt();
            return true;
        }
        let mut checked = self.steps_seen;
        while !self.done {
            if target < self.t_end && self.reached() >= target {
                return true;
            }
            match self.active.as_deref() {
                None => self.begin_segment(),
                Some(a) if a.ended.is_some() => self.handle_end(),
                Some(_) => self.step_once(observe, progress),
            }
            if self.steps_seen >= checked + CHECK_EVERY {
                checked = self.steps_seen;
                if stop_requested() {
                    self.interrupt();
                    return true;
                }
                if !keep_going() {
                    return false;
                }
            }
        }
        true
    }

    /// Stopped from outside ([`stoppable`]): the run ends at its last
    /// accepted step, failed. The segment in progress stays, to be merged
    /// as a pause's is ([`Sim::finish`]).
    fn interrupt(&mut self) {
        self.error = Some(Error::runtime(
            self.last_accepted.0 * self.tu,
            Failure::Numerics,
            "interrupted (the call was stopped from outside the run)",
        ));
        self.done = true;
    }

    /// Integrate step by step until `stop(m, t, y)` (called after every
    /// accepted step, at its end or at a terminal event) returns true:
    /// `true` then (the run paused just after that step, as
    /// [`Sim::advance`] pauses), `false` if the run ended or failed first.
    fn advance_until(&mut self, stop: &mut dyn FnMut(&M, f64, &[f64; D]) -> bool) -> bool {
        while !self.done {
            match self.active.as_deref() {
                None => self.begin_segment(),
                Some(a) if a.ended.is_some() => self.handle_end(),
                Some(_) => {
                    let mut hit = false;
                    self.step_once(
                        &mut |m, t, y| {
                            if stop(m, t, y) {
                                hit = true;
                            }
                        },
                        &mut |_| {},
                    );
                    if hit {
                        return true;
                    }
                }
            }
        }
        false
    }

    /// From the next step on, draw the noise with the counters
    /// `base + step` ([`noise_counter`]).
    fn set_noise_base(&mut self, base: u64) {
        self.noise_base = base;
        let next = base + self.steps_seen;
        if let Some(a) = self.active.as_mut() {
            a.st.eng.set_noise_counter(next);
        }
    }

    /// Start a segment at `(t, y)`, emitting the samples at exactly `t`
    /// (only the run's start has any: later segments start where the last
    /// one's samples ended).
    fn begin_segment(&mut self) {
        let t = self.t;
        let seg_end = self
            .tstops
            .iter()
            .copied()
            .find(|&ts| ts > t)
            .unwrap_or(self.t_end);
        self.m.latch_branch(&self.y);
        // The last segment's box and lists, reused in place.
        let mut spare = self.spare.take();
        let (mut watches, mut events) = match spare.as_mut() {
            Some(a) => {
                let (mut w, mut e) = (
                    std::mem::take(&mut a.watches),
                    std::mem::take(&mut a.events),
                );
                w.clear();
                e.clear();
                (w, e)
            }
            None => (Vec::new(), Vec::new()),
        };
        self.m.events(&mut self.event_pairs);
        for (w, e) in self.event_pairs.drain(..) {
            watches.push(w);
            events.push(e);
        }
        if let Some(w) = self.watcher.as_mut() {
            // Marks reached by the restart itself (a segment that starts on
            // one) are passed here; the later ones are events.
            let work = self.m.row(t, &self.y).work_applied;
            w.pass_marks(t, work);
            let extra: Vec<Watch> = (0..w.levels().len())
                .map(Watch::ThetaLevel)
                .chain(w.pending_marks().map(|(i, _)| Watch::TimeMark(i)))
                .collect();
            for x in extra {
                watches.push(x);
                events.push(self.watch_event(x));
            }
        }
        self.opts.max_steps = self.step_cap.saturating_sub(self.steps_seen);
        // The Langevin stream's counter continues over the segments.
        if let Stepper::Langevin { first_step, .. } | Stepper::Brownian { first_step, .. } =
            &mut self.opts.stepper
        {
            *first_step = self.noise_base + self.steps_seen;
        }
        let mut a = match spare {
            Some(mut a) => {
                a.st.eng.renew(&self.opts, t, seg_end);
                a.st.reset(events.len(), self.samples.len());
                a
            }
            None => Box::new(Active {
                st: Stepping::new(
                    AnyEngine::new(&self.opts, t, seg_end),
                    events.len(),
                    self.samples.len(),
                ),
                watches: Vec::new(),
                events: Vec::new(),
                seg_end,
                ended: None,
            }),
        };
        a.watches = watches;
        a.events = events;
        a.seg_end = seg_end;
        a.ended = None;
        let samples = &mut self.samples;
        let nonfinite_at = &mut self.nonfinite_at;
        let blown_row = &mut self.blown_row;
        let mut on_sample = |s: &M, t: f64, y: &[f64; D]| {
            let row = crate::testing::planted(s.row(t, y));
            if nonfinite_at.is_none() {
                if let Some(k2) = s.axis_norm_sq(y).filter(|&k2| axis_blown(k2)) {
                    *blown_row = Some((samples.len(), k2));
                    *nonfinite_at = Some(t);
                } else if row.first_non_finite_of(M::HAS_POSE).is_some() {
                    *nonfinite_at = Some(t);
                }
            }
            samples.push(row);
        };
        let Active { st, events, .. } = &mut *a;
        match st.begin(
            &mut self.m,
            t,
            &self.y,
            seg_end,
            true,
            &self.sample_times,
            events,
            &mut on_sample,
        ) {
            Ok(started) => {
                // An empty segment (at the run's end) ends at once.
                a.ended = (!started).then_some((None, t, self.y));
                self.active = Some(a);
                if self.nonfinite_at.is_some() {
                    self.end_at_nonfinite_row();
                }
            }
            Err(e) => self.fail(e),
        }
    }

    /// One accepted step of the active segment.
    fn step_once(
        &mut self,
        observe: &mut dyn FnMut(&M, f64, &[f64; D]),
        progress: &mut dyn FnMut(&Progress),
    ) {
        let a = &mut **self.active.as_mut().expect("an active segment");
        let Active {
            st,
            watches,
            events,
            ..
        } = a;
        let tu = self.tu;
        let t_end = self.t_end;
        let samples = &mut self.samples;
        let nonfinite_at = &mut self.nonfinite_at;
        let blown_row = &mut self.blown_row;
        let last_accepted = &mut self.last_accepted;
        let steps_seen = &mut self.steps_seen;
        let track = &mut self.track;
        let event_track = &mut self.event_track;
        let first_above = &mut self.first_above;
        let log = &mut self.log;
        let logs_crossings = self.logs_crossings;
        let light = self.light;
        let buckets = &mut self.normal_buckets;
        let last_step_t = &mut self.last_step_t;
        let sample_times = &self.sample_times;
        let watcher = std::cell::RefCell::new(self.watcher.as_mut());
        let mut on_sample = |s: &M, t: f64, y: &[f64; D]| {
            let row = crate::testing::planted(s.row(t, y));
            if nonfinite_at.is_none() {
                if let Some(k2) = s.axis_norm_sq(y).filter(|&k2| axis_blown(k2)) {
                    *blown_row = Some((samples.len(), k2));
                    *nonfinite_at = Some(t);
                } else if row.first_non_finite_of(M::HAS_POSE).is_some() {
                    *nonfinite_at = Some(t);
                }
            }
            samples.push(row);
        };
        let mut on_step = |s: &M, t: f64, y: &[f64; D]| {
            *last_accepted = (t, *y);
            *steps_seen += 1;
            s.accepted(y);
            if light {
                // θ (an atan2) only where it could raise θ's maximum.
                track.record_angles_guarded(
                    s.cos_theta(y),
                    || s.track_angles(y),
                    || s.track_spin(y),
                );
            } else {
                s.record_step(track, y);
            }
            observe(s, t, y);
            if let Some(w) = watcher.borrow_mut().as_mut() {
                w.step_end(t, cos_theta_of(s, y));
            }
            if let Some(b) = buckets.as_mut() {
                // The step (last, t] falls in the interval (s_{i−1}, s_i]
                // with i the first sample time >= t.
                let i = sample_times.partition_point(|&st| st < t).min(b.len() - 1);
                let n = s.normal_force(y).unwrap_or(f64::NAN);
                b[i] += n * (t - *last_step_t);
                *last_step_t = t;
            }
            // After the step is recorded (the row reads the model as the
            // samples do).
            if *steps_seen % PROGRESS_EVERY == 0 {
                report_progress(progress, s, t, y, (tu, t_end, *steps_seen));
            }
        };
        // The events as they fire (also those before a failure). θ maxima
        // go into their own track, merged at the segment's end (the maxima
        // do not depend on the order).
        let mut on_event = |s: &M, f: &integrate::Fired<D>| match watches[f.index] {
            Watch::ThetaAboveHalfPi if first_above.is_none() => {
                *first_above = Some(f.t * tu);
                log.push(f.t, Happened::ThetaAboveHalfPi);
            }
            Watch::ThetaMax => visit(event_track, s, &f.y),
            Watch::NormalZero if logs_crossings => log.cross_normal(f.t),
            Watch::ThetaLevel(j) => {
                if let Some(w) = watcher.borrow_mut().as_mut() {
                    w.level_crossed(j, f.t, f.rising);
                }
            }
            Watch::TimeMark(j) => {
                if let Some(w) = watcher.borrow_mut().as_mut() {
                    w.mark_reached(j, s.row(f.t, &f.y).work_applied);
                }
            }
            _ => {}
        };
        let res = st.step(
            &mut self.m,
            &self.opts,
            &self.sample_times,
            events,
            &mut on_sample,
            &mut on_step,
            &mut on_event,
        );
        match res {
            Ok(Stepped::Step) => {}
            Ok(Stepped::SegmentEnd) => {
                let y = *st.eng.y();
                a.ended = Some((None, a.seg_end, y));
            }
            Ok(Stepped::Terminal { index, t, y }) => a.ended = Some((Some(index), t, y)),
            Err(e) => self.fail(e),
        }
        if self.nonfinite_at.is_some() && !self.done {
            self.end_at_nonfinite_row();
        }
    }

    /// The integration failed: record the error (with the state it
    /// failed from) and end the run.
    fn fail(&mut self, e: IntegrateError<M::Error>) {
        let tu = self.tu;
        self.track.merge(&self.event_track);
        let (te, why, ylast) = match e {
            IntegrateError::Rhs { t, y_last, err } => {
                let (kind, why) = self
                    .blown_up(&y_last)
                    .unwrap_or_else(|| self.m.explain(&self.sc, err));
                (t, unstable_rk4(&self.sc, &self.track, kind, why), y_last)
            }
            IntegrateError::StepUnderflow { t, h, y_last } => (
                t,
                (
                    Failure::StepUnderflow,
                    format!("step size underflow (h = {:e} s)", h * tu),
                ),
                y_last,
            ),
            IntegrateError::NonFinite { t, y_last } => {
                let (kind, why) = self.blown_up(&y_last).unwrap_or_else(|| {
                    (
                        Failure::NonFinite,
                        "the solution became NaN or infinite".to_string(),
                    )
                });
                (t, unstable_rk4(&self.sc, &self.track, kind, why), y_last)
            }
            IntegrateError::TooManySteps { t, .. } => (
                t,
                (
                    Failure::StepLimit,
                    step_limit_why(&self.sc, &self.track, self.step_cap, t * tu),
                ),
                self.last_accepted.1.to_vec(),
            ),
        };
        let (kind, why) = why;
        self.error = Some(Error::runtime(
            te * tu,
            kind,
            format!("{why}; {}", self.m.describe(&ylast)),
        ));
        self.stats.steps = self.steps_seen;
        self.stats.rhs_evals = self.m.evaluations();
        if ylast.len() == D {
            self.y.copy_from_slice(&ylast);
        }
        self.t = te;
        self.active = None;
        self.done = true;
    }

    /// The failure of a run whose state `y` has blown up ([`axis_blown`]):
    /// named as the blow-up, not as what the blown-up state made fail
    /// next (a Painlevé case, a NaN); `None` for a state that has not.
    fn blown_up(&self, y: &[f64]) -> Option<(Failure, String)> {
        let k2 = self.m.axis_norm_sq(y).filter(|&k2| axis_blown(k2))?;
        Some((Failure::BlowUp, blow_up_why(&self.sc, k2.sqrt())))
    }

    /// An output row's state has blown up ([`axis_blown`]), at scaled time
    /// `ts`: the run ends there, as at a non-finite row, with the rows
    /// before that one (`first` of them) and the state there as its final
    /// state; the error (`blow_up`, `unstable` for an RK4 run that lost
    /// its energy balance) says so and shows that state.
    fn end_at_blown_row(&mut self, ts: f64, first: usize, k2: f64) {
        let y = self.state_at(ts);
        if let Some(a) = self.active.take() {
            self.stats.rejected += a.st.stats.rejected;
        }
        self.track.merge(&self.event_track);
        self.samples.truncate(first);
        let why = blow_up_why(&self.sc, k2.sqrt());
        let (kind, why) = unstable_rk4(&self.sc, &self.track, Failure::BlowUp, why);
        self.error = Some(Error::runtime(
            ts * self.tu,
            kind,
            format!("{why}; {}", self.m.describe(&y)),
        ));
        (self.t, self.y) = (ts, y);
        self.stats.steps = self.steps_seen;
        self.stats.rhs_evals = self.m.evaluations();
        self.done = true;
    }

    /// An output row came out with a value that is not a finite number (at
    /// scaled time `nonfinite_at`, in the step just taken, or at the
    /// segment's start) although the integrated state is finite: a run is
    /// finite or failed, so it ends there. The rows before that one are
    /// kept; the error (`non_finite` for a NaN, `output_overflow` for an
    /// infinity; `unstable` for an RK4 run that lost its energy balance)
    /// names the column; the state at that time (the last step's dense
    /// output) is the run's final state.
    fn end_at_nonfinite_row(&mut self) {
        let ts = self.nonfinite_at.expect("a non-finite row");
        if let Some((first, k2)) = self.blown_row {
            return self.end_at_blown_row(ts, first, k2);
        }
        let y = self.state_at(ts);
        if let Some(a) = self.active.take() {
            self.stats.rejected += a.st.stats.rejected;
        }
        self.track.merge(&self.event_track);
        let tu = self.tu;
        let first = self
            .samples
            .iter()
            .position(|r| r.first_non_finite_of(M::HAS_POSE).is_some())
            .expect("the non-finite row");
        let (column, value) = self.samples[first]
            .first_non_finite_of(M::HAS_POSE)
            .expect("a non-finite column");
        self.samples.truncate(first);
        // An RK4 run whose energy balance was lost: its fixed step is the
        // cause (as for a state that became NaN).
        let (kind, why) = nonfinite_output_why(column, value);
        let (kind, why) = unstable_rk4(&self.sc, &self.track, kind, why);
        self.error = Some(Error::runtime(
            ts * tu,
            kind,
            format!(
                "{why}; last accepted {}",
                self.m.describe(&self.last_accepted.1)
            ),
        ));
        (self.t, self.y) = (ts, y);
        self.stats.steps = self.steps_seen;
        self.stats.rhs_evals = self.m.evaluations();
        self.done = true;
    }

    /// Handle the end of the active segment: merge its counters, check the
    /// output, and let the model handle a force switch or terminal event.
    fn handle_end(&mut self) {
        let a = self.active.take().expect("an active segment");
        let (index, t, y) = a.ended.expect("an ended segment");
        self.track.merge(&self.event_track);
        self.stats.rhs_evals += a.st.stats.rhs_evals;
        self.stats.steps += a.st.stats.steps;
        debug_assert_eq!(self.stats.steps, self.steps_seen);
        self.stats.rejected += a.st.stats.rejected;
        let seg_end = a.seg_end;
        let what = index.map(|i| a.watches[i]);
        self.spare = Some(a);
        self.t = t;
        self.y = y;
        let flow = match what {
            None if seg_end >= self.t_end => Flow::End,
            None => self.m.on_force_switch(t, &mut self.y, &mut self.log),
            Some(what) => {
                if matches!(what, Watch::SlipZero | Watch::StickLimit) {
                    self.switches += 1;
                    if self.switches > MAX_SWITCHES {
                        self.error = Some(Error::runtime(
                            t * self.tu,
                            Failure::SwitchLimit,
                            format!("more than {MAX_SWITCHES} stick/slip switches"),
                        ));
                        self.done = true;
                        return;
                    }
                }
                self.m.on_terminal(what, t, &mut self.y, &mut self.log)
            }
        };
        match flow {
            Flow::Continue => {}
            Flow::Stop(e) => {
                self.error = Some(e);
                self.done = true;
            }
            Flow::End => self.done = true,
        }
    }

    /// The trajectory so far: samples up to the last accepted step (the
    /// whole run once it has ended), events, summary.
    fn finish(self) -> Trajectory {
        self.finish_watching().0
    }

    /// The event function of a watched θ level or time mark
    /// ([`crate::sim::watch`]).
    fn watch_event(&self, w: Watch) -> Event<M, D> {
        let watcher = self.watcher.as_ref().expect("a watcher");
        match w {
            Watch::ThetaLevel(j) => {
                // cos(level) − cos θ: the sign of θ − level (cos falls on
                // [0, π]), without θ's atan2.
                let c = watcher.levels()[j].cos();
                Event {
                    g: Box::new(move |m: &M, _, y| c - cos_theta_of(m, y)),
                    direction: integrate::Direction::Either,
                    terminal: false,
                    step_to_event: false,
                }
            }
            Watch::TimeMark(j) => {
                let mark = watcher.mark(j);
                Event {
                    g: Box::new(move |_: &M, t, _| t - mark),
                    direction: integrate::Direction::Rising,
                    terminal: false,
                    step_to_event: false,
                }
            }
            other => unreachable!("{other:?} is not a watch event"),
        }
    }

    /// As [`Sim::finish`], with what each watched θ window saw.
    fn finish_watching(mut self) -> (Trajectory, Vec<WindowStay>) {
        if self.active.as_ref().is_some_and(|a| a.ended.is_some()) {
            self.handle_end();
        }
        if let Some(a) = self.active.take() {
            // Paused inside a segment: the run so far ends at its last step.
            self.track.merge(&self.event_track);
            self.stats.rhs_evals += a.st.stats.rhs_evals;
            self.stats.steps += a.st.stats.steps;
            self.stats.rejected += a.st.stats.rejected;
            (self.t, self.y) = self.last_accepted;
        }
        let (t, y, tu) = (self.t, self.y, self.tu);
        let rolling_time = self.log.finish(t);
        visit(&mut self.track, &self.m, &y);
        let contact = if self.m.flies() {
            let (first, fraction) = self.log.flights(t);
            (first.map(|tc| tc * tu), fraction)
        } else {
            (
                self.log.normal.first_negative().map(|tc| tc * tu),
                self.log.normal.negative_fraction(t),
            )
        };
        let stem = self.m.has_stem().then(|| {
            let (first, fraction) = self.log.stem(t);
            (first.map(|ts| ts * tu), fraction)
        });
        let last = self.m.row(t, &y);
        let summary = summarize(
            &self.track,
            RunEnd {
                t,
                time_unit: tu,
                axial: self.m.axial_ratio(),
                last: &last,
                samples: &self.samples,
                first_above: self.first_above,
                contact,
                rolling_time,
                stats: self.stats,
                error: self.error.as_ref(),
                adhesive: self.m.adhesive(),
                stem,
                normal_buckets: self
                    .normal_buckets
                    .as_deref()
                    .map(|b| (b, &self.sample_times[..])),
            },
        );
        let stays = match self.watcher.as_mut() {
            Some(w) => {
                if self.error.is_none() {
                    // A run that ended normally reached its end: marks there
                    // (at t_end to rounding) are passed with the final state.
                    w.pass_marks(t, last.work_applied);
                }
                w.stays()
            }
            None => Vec::new(),
        };
        (
            Trajectory {
                samples: self.samples,
                events: self.log.events.into_sorted(),
                summary,
                error: self.error,
            },
            stays,
        )
    }
}
