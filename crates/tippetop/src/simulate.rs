//! Run a scenario: the driver that turns a [`Scenario`] into a [`Trajectory`].
//!
//! The driver owns what the integrator does not know about: the switch
//! times of the force schedule (each one ends a `solve` call, so the driver
//! can re-examine stick/slip with the new force there), the events that
//! diagnostics need (θ crossing π/2, local maxima of θ, N crossing zero)
//! and, for the exact Coulomb law, the stick/slip switches (terminal events
//! after which the model changes mode and the integration restarts).

use crate::{
    ContactMode, Error, ModelKind, Sample, Scenario, Trajectory,
    integrate::{self, Direction, Event, IntegrateError, Stepper, StopReason},
    model::ContactModel,
    model::{
        reduced::{self, DIM, Mode, ModelError, Reduced},
        vector::{self, Vector},
    },
    sim::events::{Happened, Watch},
    sim::messages::{nonfinite_output_error, painleve_why, step_limit_why, unstable_rk4},
    sim::record::{EventList, NormalLog, RunEnd, RunSetup, Track, summarize, unit},
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
        ModelKind::Reduced => Ok(run_contact::<Reduced, DIM>(scenario, progress)),
        ModelKind::Vector => Ok(run_contact::<Vector, { vector::DIM }>(scenario, progress)),
        ModelKind::Rigid => Ok(crate::model::rigid::run_with_progress(
            scenario,
            &mut |_, _, _| {},
            progress,
        )),
    }
}

fn events_for<M: ContactModel<D>, const D: usize>(m: &M) -> Vec<(Watch, Event<M, D>)> {
    let mut ev: Vec<(Watch, Event<M, D>)> = vec![
        (
            Watch::ThetaAboveHalfPi,
            Event {
                g: Box::new(|m: &M, _, y| m.above_half_pi(y)),
                direction: Direction::Rising,
                terminal: false,
                step_to_event: false,
            },
        ),
        (
            Watch::ThetaMax,
            Event {
                g: Box::new(|m: &M, _, y| m.theta_rate(y)),
                direction: Direction::Falling,
                terminal: false,
                step_to_event: false,
            },
        ),
        (Watch::NormalZero, {
            // Bilateral contact, sliding: N = 0 ends the segment, where the
            // driver flips the latched branch; watched only in the direction
            // that leaves the latched sign (a restart a rounding error short
            // of the zero must not fire again).
            let plane = m.plane();
            let (direction, terminal) = match (plane.latches_normal(), plane.normal_branch) {
                (true, Some(true)) => (Direction::Falling, true),
                (true, Some(false)) => (Direction::Rising, true),
                _ => (
                    Direction::Either,
                    plane.contact_mode() == ContactMode::Unilateral,
                ),
            };
            Event {
                g: Box::new(|m: &M, _, y| m.contact_forces(y).map(|(n, _)| n).unwrap_or(f64::NAN)),
                direction,
                terminal,
                // Latched: smooth through N = 0, so the restart state can
                // come from a step (restarting from the interpolant raised
                // the J drift of reproduce's nano run without gravity to
                // 1.05e-10; docs/physics.md §4).
                step_to_event: terminal && plane.latches_normal(),
            }
        }),
    ];
    if m.plane().is_exact() {
        match m.plane().mode {
            Mode::Sliding => ev.push((
                Watch::SlipZero,
                Event {
                    g: Box::new(|m: &M, _, y| {
                        let v = m.slip_of(y);
                        let r = m.plane().slip_ref.get();
                        v[0] * r[0] + v[1] * r[1]
                    }),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            )),
            Mode::Rolling => ev.push((
                Watch::StickLimit,
                Event {
                    g: Box::new(|m: &M, _, y| m.stick_margin(y).unwrap_or(f64::NAN)),
                    direction: Direction::Falling,
                    terminal: true,
                    step_to_event: false,
                },
            )),
        }
    }
    ev
}

/// Record a state in `track`.
fn visit<M: ContactModel<D>, const D: usize>(track: &mut Track, m: &M, y: &[f64; D]) {
    track.record(
        m.theta(y),
        m.spin(y),
        m.jellett_scaled(y),
        m.energy_scaled(y),
        m.work_scaled(y),
    );
}

/// Decide stick or slip at zero slip (exact law). Returns the state to
/// continue from; sets the model's mode and slip hint.
fn settle_at_zero_slip<M: ContactModel<D>, const D: usize>(
    m: &mut M,
    y: &[f64; D],
) -> ([f64; D], bool) {
    let yr = m.to_rolling(y);
    m.plane_mut().mode = Mode::Rolling;
    if let Ok((_, f)) = m.contact_forces(&yr) {
        if m.stick_margin(&yr).is_some_and(|s| s >= 0.0) {
            m.plane_mut().slip_hint = [0.0, 0.0];
            return (yr, true);
        }
        // Slide off in the direction the needed friction dictates: friction
        // keeps its direction (magnitude μN), the slip grows opposite to it.
        m.plane_mut().slip_hint = unit([-f[0], -f[1]]);
    }
    m.plane_mut().mode = Mode::Sliding;
    m.plane().slip_ref.set(m.plane().slip_hint);
    (yr, false)
}

/// The driver of the models that keep the sphere on the plane (see
/// [`ContactModel`]).
fn run_contact<M: ContactModel<D>, const D: usize>(
    sc: &Scenario,
    progress: &mut dyn FnMut(f64),
) -> Trajectory {
    let mut m = M::build(sc);
    let tu = m.scales().time;
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
        *beta = m.dop853_beta();
        *stability_cap = m.dop853_stability_cap();
    }
    let ns = sc.solver.samples;

    let mut y = m.initial_state(&sc.initial);
    m.latch_force(0.0);
    let mut events_out = EventList::default();
    for &ts in &tstops {
        events_out.push(ts * tu, Happened::ForceSwitch);
    }
    if m.plane().is_exact() {
        let v = m.slip_of(&y);
        if v[0].hypot(v[1]) == 0.0 {
            let (yn, stuck) = settle_at_zero_slip(&mut m, &y);
            y = yn;
            events_out.push(
                0.0,
                if stuck {
                    Happened::Stick
                } else {
                    Happened::Slip
                },
            );
        } else {
            m.plane().slip_ref.set(unit(v));
        }
    }

    let mut track = Track::new(
        m.theta(&y),
        m.spin(&y),
        m.jellett_scaled(&y),
        m.energy_scaled(&y),
    );
    let n_initial = m.contact_forces(&y).map(|(n, _)| n).unwrap_or(f64::NAN);

    let mut samples: Vec<Sample> = Vec::with_capacity(ns);
    let mut stats = integrate::Stats::default();
    // Step count and last accepted state, kept here too so that a failed
    // run still reports them.
    let mut steps_seen: u64 = 0;
    // The step limit holds for the whole run, over all its `solve` calls.
    let step_cap = opts.max_steps;
    let mut reversals: u32 = 0;
    let mut last_slip = m.slip_of(&y);
    let mut last_accepted: (f64, [f64; D]) = (0.0, y);
    let mut t = 0.0;
    let mut error: Option<Error> = None;
    let mut first_above: Option<f64> = if m.theta(&y) > std::f64::consts::FRAC_PI_2 {
        Some(0.0)
    } else {
        None
    };
    let mut normal_log = NormalLog::new(n_initial);
    let mut rolling_since: Option<f64> = (m.plane().mode == Mode::Rolling).then_some(0.0);
    let mut rolling_time = 0.0;
    let mut switches = 0usize;
    let mut event_track = track.clone();
    let mut nonfinite_at: Option<f64> = None;

    loop {
        let seg_end = tstops.iter().copied().find(|&ts| ts > t).unwrap_or(t_end);
        if !m.plane().latches_normal() {
            m.plane_mut().normal_branch = None;
        } else if m.plane().normal_branch.is_none() {
            // The self-consistent branch at the segment's start.
            if let Ok((n, _)) = m.contact_forces(&y) {
                m.plane_mut().normal_branch = Some(n >= 0.0);
            }
        }
        let (watches, events): (Vec<_>, Vec<_>) = events_for(&m).into_iter().unzip();
        opts.max_steps = step_cap.saturating_sub(steps_seen);
        let next = samples.len();
        let mut on_sample = |s: &M, t: f64, y: &[f64; D]| {
            let row = s.sample(t, y);
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
            if s.plane().can_chatter() {
                let v = s.slip_of(y);
                if v[0] * last_slip[0] + v[1] * last_slip[1] < 0.0 {
                    reversals += 1;
                    if reversals >= reduced::CHATTER_REVERSALS {
                        s.plane().chattering.set(true);
                    }
                }
                last_slip = v;
            }
            visit(&mut track, s, y);
            if s.plane().mode == Mode::Sliding && s.plane().is_exact() {
                let v = unit(s.slip_of(y));
                if v != [0.0, 0.0] {
                    s.plane().slip_ref.set(v);
                }
            }
        };
        // The events of this call as they fire (also those before a
        // failure). θ maxima go into their own track, merged below (the
        // maxima do not depend on the order).
        let mut on_event = |s: &M, f: &integrate::Fired<D>| match watches[f.index] {
            Watch::ThetaAboveHalfPi if first_above.is_none() => {
                first_above = Some(f.t * tu);
                events_out.push(f.t * tu, Happened::ThetaAboveHalfPi);
            }
            Watch::ThetaMax => visit(&mut event_track, s, &f.y),
            Watch::NormalZero => {
                let what = normal_log.cross(f.t);
                events_out.push(f.t * tu, what);
            }
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
                &m.describe_state(&last_accepted.1),
            ));
            t = last_accepted.0;
            y = last_accepted.1;
            stats.steps = steps_seen;
            stats.rhs_evals = m.plane().evaluations;
            break;
        }
        match res {
            Err(e) => {
                let (te, why, ylast) = match e {
                    IntegrateError::Rhs { t, y_last, err } => {
                        let why = match err {
                            ModelError::Painleve { theta, solutions } => {
                                painleve_why(sc, "theta_ddot-N system", theta, solutions)
                            }
                            ModelError::Singular { .. } | ModelError::Chattering { .. } => {
                                err.to_string()
                            }
                        };
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
                    format!("{why}; {}", m.describe_state(&ylast)),
                ));
                stats.steps = steps_seen;
                stats.rhs_evals = m.plane().evaluations;
                if ylast.len() == D {
                    let mut yl = [0.0; D];
                    yl.copy_from_slice(&ylast);
                    y = yl;
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
                match o.stop {
                    StopReason::End if seg_end >= t_end => break,
                    StopReason::End => {
                        // A force switch: the integrator restarts with the new
                        // force latched; while rolling, check that the contact
                        // can still hold it. N may jump across zero here, which
                        // no event can see: record the crossing at the switch.
                        let n_before = m.contact_forces(&y).map(|(n, _)| n).ok();
                        m.latch_force(t);
                        m.plane_mut().normal_branch = None;
                        let n_after = m.contact_forces(&y).map(|(n, _)| n).ok();
                        if let (Some(nb), Some(na)) = (n_before, n_after) {
                            if (nb < 0.0) != (na < 0.0) {
                                let kind = normal_log.cross(t);
                                events_out.push(t * tu, kind);
                                if na < 0.0 && m.plane().contact_mode() == ContactMode::Unilateral {
                                    error = Some(Error::runtime(
                                        t * tu,
                                        format!(
                                            "lift-off at a force switch: the normal force N jumped below zero (contact = \"unilateral\"); the reduced and vector models keep the sphere on the plane and cannot follow a flight, use model = \"rigid\"; {}",
                                            m.describe_state(&y)
                                        ),
                                    ));
                                    break;
                                }
                            }
                        }
                        if m.plane().is_exact() && m.plane().mode == Mode::Rolling {
                            if let Ok((_, f)) = m.contact_forces(&y) {
                                if m.stick_margin(&y).is_some_and(|s| s < 0.0) {
                                    m.plane_mut().mode = Mode::Sliding;
                                    m.plane_mut().slip_hint = unit([-f[0], -f[1]]);
                                    m.plane().slip_ref.set(m.plane().slip_hint);
                                    if let Some(s0) = rolling_since.take() {
                                        rolling_time += t - s0;
                                    }
                                    events_out.push(t * tu, Happened::Slip);
                                }
                            }
                        }
                    }
                    StopReason::Terminal(i)
                        if watches[i] == Watch::NormalZero && m.plane().latches_normal() =>
                    {
                        // N = 0 (bilateral): continue on the other branch.
                        let b = m.plane().normal_branch;
                        m.plane_mut().normal_branch = b.map(|pos| !pos);
                    }
                    StopReason::Terminal(i) if watches[i] == Watch::NormalZero => {
                        error = Some(Error::runtime(
                            t * tu,
                            format!(
                                "lift-off: the normal force N fell to zero (contact = \"unilateral\"); the reduced and vector models keep the sphere on the plane and cannot follow a flight, use model = \"rigid\"; {}",
                                m.describe_state(&y)
                            ),
                        ));
                        break;
                    }
                    StopReason::Terminal(i)
                        if matches!(watches[i], Watch::SlipZero | Watch::StickLimit) =>
                    {
                        m.plane_mut().normal_branch = None;
                        switches += 1;
                        if switches > MAX_SWITCHES {
                            error = Some(Error::runtime(
                                t * tu,
                                format!("more than {MAX_SWITCHES} stick/slip switches"),
                            ));
                            break;
                        }
                        match m.plane().mode {
                            Mode::Sliding => {
                                let (yn, stuck) = settle_at_zero_slip(&mut m, &y);
                                y = yn;
                                if stuck {
                                    rolling_since = Some(t);
                                    events_out.push(t * tu, Happened::Stick);
                                }
                            }
                            Mode::Rolling => {
                                let forces = m.contact_forces(&y).ok();
                                y = m.to_rolling(&y);
                                m.plane_mut().mode = Mode::Sliding;
                                if let Some((_, f)) = forces {
                                    m.plane_mut().slip_hint = unit([-f[0], -f[1]]);
                                }
                                m.plane().slip_ref.set(m.plane().slip_hint);
                                if let Some(s0) = rolling_since.take() {
                                    rolling_time += t - s0;
                                }
                                events_out.push(t * tu, Happened::Slip);
                            }
                        }
                    }
                    StopReason::Terminal(_) => break,
                }
            }
        }
    }
    if let Some(s0) = rolling_since {
        rolling_time += t - s0;
    }
    visit(&mut track, &m, &y);

    let contact_lost_at = normal_log.first_negative().map(|tc| tc * tu);
    let events_out = events_out.into_sorted();

    let last = m.sample(t, &y);
    let summary = summarize(
        &track,
        RunEnd {
            t,
            time_unit: tu,
            axial: m.axial(),
            last: &last,
            samples: &samples,
            first_above,
            contact: (contact_lost_at, normal_log.negative_fraction(t)),
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
