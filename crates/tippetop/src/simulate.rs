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

use crate::{
    Error, ModelKind, Sample, Scenario, Trajectory,
    integrate::{self, IntegrateError, Stepper, StopReason},
    model::{
        ContactModel, Flow, Model,
        reduced::{DIM, Reduced},
        rigid::{self, Rigid},
        vector::{self, Vector},
    },
    sim::events::{Happened, Watch},
    sim::messages::{nonfinite_output_error, step_limit_why, unstable_rk4},
    sim::record::{RunEnd, RunLog, RunSetup, Track, summarize},
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

/// Accepted steps between two calls of the progress callback of
/// [`simulate_with_progress`].
pub use crate::sim::record::PROGRESS_EVERY;

/// As [`simulate`], calling `progress(fraction)` with the fraction `t / t_end`
/// of the run done (in `[0, 1]`) every [`PROGRESS_EVERY`] accepted steps (a
/// few hundred times per second at most: cheap enough to print or to
/// update a bar from). Not called for a run that is rejected as bad input.
pub fn simulate_with_progress(
    scenario: &Scenario,
    progress: &mut dyn FnMut(f64),
) -> Result<Trajectory, Error> {
    scenario.validate()?;
    match scenario.solver.model {
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

/// Record a state in `track`.
fn visit<M: Model<D>, const D: usize>(track: &mut Track, m: &M, y: &[f64; D]) {
    let (theta, spin, j, e, w) = m.track_point(y);
    track.record(theta, spin, j, e, w);
}

/// The one driver: runs model `m` over the scenario `sc` (validated),
/// calling `observe(m, t, y)` after every accepted step and `progress`
/// every [`PROGRESS_EVERY`] steps.
///
/// It integrates from one force switch to the next (one `solve` call per
/// segment, so the model can re-decide stick/slip, branch and contact at
/// the switch), with the events the model needs in its discrete state now;
/// a terminal event ends the call and the model's handler says how to go
/// on. It owns the samples, the error mapping, the step limit over the
/// whole run, the run's record ([`RunLog`]) and the summary.
fn run<M: Model<D>, const D: usize>(
    sc: &Scenario,
    mut m: M,
    observe: &mut dyn FnMut(&M, f64, &[f64; D]),
    progress: &mut dyn FnMut(f64),
) -> Trajectory {
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
    let ns = sc.solver.samples;

    let mut log = RunLog::new(tu, f64::NAN);
    for &ts in &tstops {
        log.push(ts, Happened::ForceSwitch);
    }
    m.latch_force(0.0);
    let (mut y, n_initial) = m.start(sc, &mut log);
    log.normal = crate::sim::record::NormalLog::new(n_initial);

    let mut track = {
        let (theta, spin, j, e, _) = m.track_point(&y);
        Track::new(theta, spin, j, e)
    };
    let mut samples: Vec<Sample> = Vec::with_capacity(ns);
    let mut stats = integrate::Stats::default();
    // Step count and last accepted state, kept here too so that a failed
    // run still reports them.
    let mut steps_seen: u64 = 0;
    // The step limit holds for the whole run, over all its `solve` calls.
    let step_cap = opts.max_steps;
    let mut last_accepted: (f64, [f64; D]) = (0.0, y);
    let mut t = 0.0;
    let mut error: Option<Error> = None;
    let mut first_above: Option<f64> =
        (m.track_point(&y).0 > std::f64::consts::FRAC_PI_2).then_some(0.0);
    let mut switches = 0usize;
    let mut event_track = track.clone();
    let mut nonfinite_at: Option<f64> = None;
    let logs_crossings = !m.flies();

    loop {
        let seg_end = tstops.iter().copied().find(|&ts| ts > t).unwrap_or(t_end);
        m.latch_branch(&y);
        let (watches, events): (Vec<_>, Vec<_>) = m.events().into_iter().unzip();
        opts.max_steps = step_cap.saturating_sub(steps_seen);
        let next = samples.len();
        let mut on_sample = |s: &M, t: f64, y: &[f64; D]| {
            let row = s.row(t, y);
            if nonfinite_at.is_none() && !row.is_finite() {
                nonfinite_at = Some(t);
            }
            samples.push(row);
        };
        let mut on_step = |s: &M, t: f64, y: &[f64; D]| {
            last_accepted = (t, *y);
            steps_seen += 1;
            if steps_seen % PROGRESS_EVERY == 0 {
                progress((t / t_end).clamp(0.0, 1.0));
            }
            s.accepted(y);
            visit(&mut track, s, y);
            observe(s, t, y);
        };
        // The events of this call as they fire (also those before a
        // failure). θ maxima go into their own track, merged below (the
        // maxima do not depend on the order).
        let mut on_event = |s: &M, f: &integrate::Fired<D>| match watches[f.index] {
            Watch::ThetaAboveHalfPi if first_above.is_none() => {
                first_above = Some(f.t * tu);
                log.push(f.t, Happened::ThetaAboveHalfPi);
            }
            Watch::ThetaMax => visit(&mut event_track, s, &f.y),
            Watch::NormalZero if logs_crossings => log.cross_normal(f.t),
            _ => {}
        };
        let res = integrate::solve_with_events(
            &mut m,
            &opts,
            t,
            y,
            seg_end,
            &[],
            &sample_times[next..],
            &events,
            &mut on_sample,
            &mut on_step,
            &mut on_event,
        );
        track.merge(&event_track);
        // (A failed call explains itself: its rows may be NaN where the
        // model could not be evaluated.)
        if let (Some(ts), Ok(_)) = (nonfinite_at, &res) {
            // A value of the output overflowed (in SI units) although the
            // scaled state is finite: stop at the first such row.
            samples.retain(|r| r.t < ts * tu);
            error = Some(nonfinite_output_error(
                ts * tu,
                &m.describe(&last_accepted.1),
            ));
            t = last_accepted.0;
            y = last_accepted.1;
            stats.steps = steps_seen;
            stats.rhs_evals = m.evaluations();
            break;
        }
        match res {
            Err(e) => {
                let (te, why, ylast) = match e {
                    IntegrateError::Rhs { t, y_last, err } => {
                        let why = m.explain(sc, err);
                        (t, unstable_rk4(sc, &track, why), y_last)
                    }
                    IntegrateError::StepUnderflow { t, h, y_last } => (
                        t,
                        format!("step size underflow (h = {:e} s)", h * tu),
                        y_last,
                    ),
                    IntegrateError::NonFinite { t, y_last } => (
                        t,
                        unstable_rk4(
                            sc,
                            &track,
                            "the solution became NaN or infinite".to_string(),
                        ),
                        y_last,
                    ),
                    IntegrateError::TooManySteps { t, .. } => {
                        (t, step_limit_why(sc, step_cap), last_accepted.1.to_vec())
                    }
                };
                error = Some(Error::runtime(
                    te * tu,
                    format!("{why}; {}", m.describe(&ylast)),
                ));
                stats.steps = steps_seen;
                stats.rhs_evals = m.evaluations();
                if ylast.len() == D {
                    y.copy_from_slice(&ylast);
                }
                t = te;
                break;
            }
            Ok(o) => {
                stats.rhs_evals += o.stats.rhs_evals;
                stats.steps += o.stats.steps;
                debug_assert_eq!(stats.steps, steps_seen);
                stats.rejected += o.stats.rejected;
                t = o.t;
                y = o.y;
                let flow = match o.stop {
                    StopReason::End if seg_end >= t_end => break,
                    StopReason::End => m.on_force_switch(t, &mut y, &mut log),
                    StopReason::Terminal(i) => {
                        let what = watches[i];
                        if matches!(what, Watch::SlipZero | Watch::StickLimit) {
                            switches += 1;
                            if switches > MAX_SWITCHES {
                                error = Some(Error::runtime(
                                    t * tu,
                                    format!("more than {MAX_SWITCHES} stick/slip switches"),
                                ));
                                break;
                            }
                        }
                        m.on_terminal(what, t, &mut y, &mut log)
                    }
                };
                match flow {
                    Flow::Continue => {}
                    Flow::Stop(e) => {
                        error = Some(e);
                        break;
                    }
                    Flow::End => break,
                }
            }
        }
    }
    let rolling_time = log.finish(t);
    visit(&mut track, &m, &y);

    let contact = if m.flies() {
        let (first, fraction) = log.flights(t);
        (first.map(|tc| tc * tu), fraction)
    } else {
        (
            log.normal.first_negative().map(|tc| tc * tu),
            log.normal.negative_fraction(t),
        )
    };
    let events_out = log.events.into_sorted();

    let last = m.row(t, &y);
    let summary = summarize(
        &track,
        RunEnd {
            t,
            time_unit: tu,
            axial: m.axial_ratio(),
            last: &last,
            samples: &samples,
            first_above,
            contact,
            rolling_time,
            stats,
            error: error.as_ref(),
        },
    );
    Trajectory {
        samples,
        events: events_out,
        summary,
        error,
    }
}
