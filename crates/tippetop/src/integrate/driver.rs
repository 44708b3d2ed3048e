//! The driver of `solve`: segments between tstops, samples, events.

use super::dop853::Dop853;
use super::rk4::Rk4;
use super::roots::illinois;
use super::rosenbrock::Rodas4p;
use super::{
    Direction, Engine, Event, Fail, Fired, IntegrateError, OdeSystem, Options, Outcome, Stats,
    Stepper, StopReason,
};

/// Attach the last accepted state to a stepper failure.
fn convert<E, const N: usize>(f: Fail<E>, y_last: &[f64; N]) -> IntegrateError<E> {
    match f {
        Fail::Rhs { t, err } => IntegrateError::Rhs {
            t,
            y_last: y_last.to_vec(),
            err,
        },
        Fail::Underflow { t, h } => IntegrateError::StepUnderflow {
            t,
            h,
            y_last: y_last.to_vec(),
        },
        Fail::NonFinite { t } => IntegrateError::NonFinite {
            t,
            y_last: y_last.to_vec(),
        },
    }
}

/// Does `g` cross zero between `gp` (step start) and `gn` (step end) in the
/// allowed direction? `gp == 0` never counts.
fn crosses(gp: f64, gn: f64, direction: Direction) -> bool {
    let rising = gp < 0.0 && gn >= 0.0;
    let falling = gp > 0.0 && gn <= 0.0;
    match direction {
        Direction::Rising => rising,
        Direction::Falling => falling,
        Direction::Either => rising || falling,
    }
}

#[allow(clippy::too_many_arguments)]
pub(super) fn run<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    opts: &Options,
    t0: f64,
    y0: [f64; N],
    t_end: f64,
    tstops: &[f64],
    sample_times: &[f64],
    events: &[Event<S, N>],
    on_sample: &mut dyn FnMut(&S, f64, &[f64; N]),
    on_step: &mut dyn FnMut(&S, f64, &[f64; N]),
    on_event: &mut dyn FnMut(&S, &Fired<N>),
) -> Result<Outcome<N>, IntegrateError<S::Error>> {
    assert!(
        t0.is_finite() && t_end.is_finite() && t_end >= t0,
        "solve needs finite t0 <= t_end (got t0 {t0}, t_end {t_end})"
    );
    debug_assert!(
        sample_times.windows(2).all(|w| w[0] <= w[1]),
        "sample_times must be sorted"
    );
    // The engines are different types: one `drive` call per engine.
    macro_rules! drive_with {
        ($engine:expr) => {
            drive(
                $engine,
                sys,
                opts,
                t0,
                y0,
                t_end,
                tstops,
                sample_times,
                events,
                on_sample,
                on_step,
                on_event,
            )
        };
    }
    let h_max = default_h_max(opts, t0, t_end);
    match opts.stepper {
        Stepper::Rk4 { h } => drive_with!(Rk4::new(h)),
        Stepper::Dop853 {
            rtol,
            atol,
            beta,
            stability_cap,
        } => drive_with!(Dop853::new(rtol, atol, beta, stability_cap, opts.h0, h_max)),
        Stepper::Rosenbrock { rtol, atol } => {
            drive_with!(Rodas4p::new(rtol, atol, opts.h0, h_max))
        }
    }
}

/// The largest step of the adaptive steppers: `Options::h_max`, by default
/// the interval; for `t_end == t0` any positive value does (no step is taken).
fn default_h_max(opts: &Options, t0: f64, t_end: f64) -> f64 {
    let span = t_end - t0;
    opts.h_max.unwrap_or(if span > 0.0 { span } else { 1.0 })
}

#[allow(clippy::too_many_arguments)]
fn drive<S: OdeSystem<N>, E: Engine<N>, const N: usize>(
    mut eng: E,
    sys: &mut S,
    opts: &Options,
    t0: f64,
    y0: [f64; N],
    t_end: f64,
    tstops: &[f64],
    sample_times: &[f64],
    events: &[Event<S, N>],
    on_sample: &mut dyn FnMut(&S, f64, &[f64; N]),
    on_step: &mut dyn FnMut(&S, f64, &[f64; N]),
    on_event: &mut dyn FnMut(&S, &Fired<N>),
) -> Result<Outcome<N>, IntegrateError<S::Error>> {
    let mut stats = Stats::default();
    let mut stops: Vec<f64> = tstops
        .iter()
        .copied()
        .filter(|&s| s > t0 && s < t_end)
        .collect();
    stops.sort_by(f64::total_cmp);
    stops.dedup();

    let mut g_prev = vec![0.0; events.len()];
    let mut g_new = vec![0.0; events.len()];
    let mut crossings: Vec<(f64, usize)> = Vec::with_capacity(events.len());
    let mut ybuf = [0.0; N];
    let ns = sample_times.len();
    let mut si = sample_times.partition_point(|&s| s < t0);

    let mut t = t0;
    let mut y = y0;
    let mut seg = 0;
    loop {
        let t_stop = stops.get(seg).copied().unwrap_or(t_end);
        sys.begin_segment(t, &y);
        if seg == 0 {
            while si < ns && sample_times[si] == t0 {
                on_sample(sys, t0, &y0);
                si += 1;
            }
            if t_end == t0 {
                return Ok(Outcome {
                    t: t0,
                    y: y0,
                    stop: StopReason::End,
                    fired: Vec::new(),
                    stats,
                });
            }
        }
        for (gp, ev) in g_prev.iter_mut().zip(events) {
            *gp = (ev.g)(sys, t, &y);
        }
        eng.restart(sys, t, &y, t_stop, &mut stats)
            .map_err(|f| convert(f, &y))?;

        while eng.t() < t_stop {
            if stats.steps >= opts.max_steps {
                return Err(IntegrateError::TooManySteps {
                    t: eng.t(),
                    max_steps: opts.max_steps,
                });
            }
            if let Err(f) = eng.step(sys, t_stop, &mut stats) {
                return Err(convert(f, eng.y()));
            }
            stats.steps += 1;
            let tn = eng.t();
            let tp = eng.t_prev();

            // Events: sign changes between the step ends, located on the
            // dense output.
            crossings.clear();
            for (i, ev) in events.iter().enumerate() {
                let gn = (ev.g)(sys, tn, eng.y());
                g_new[i] = gn;
                if crosses(g_prev[i], gn, ev.direction) {
                    if let Err(f) = eng.prepare_dense(sys, &mut stats) {
                        return Err(convert(f, eng.y()));
                    }
                    let tol = 4.0 * f64::EPSILON * tn.abs().max(tn - tp);
                    let sys_ref: &S = sys;
                    let eng_ref = &eng;
                    let tr = illinois(
                        |tc| {
                            eng_ref.dense(tc, &mut ybuf);
                            (ev.g)(sys_ref, tc, &ybuf)
                        },
                        tp,
                        tn,
                        g_prev[i],
                        gn,
                        tol,
                    );
                    crossings.push((tr, i));
                }
            }
            crossings.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
            let terminal = crossings.iter().position(|&(_, i)| events[i].terminal);
            let t_lim = terminal.map_or(tn, |k| crossings[k].0);

            // Samples in (tp, t_lim].
            while si < ns && sample_times[si] <= t_lim {
                let ts = sample_times[si];
                if ts == tn {
                    on_sample(sys, tn, eng.y());
                } else {
                    if let Err(f) = eng.prepare_dense(sys, &mut stats) {
                        return Err(convert(f, eng.y()));
                    }
                    eng.dense(ts, &mut ybuf);
                    on_sample(sys, ts, &ybuf);
                }
                si += 1;
            }

            // Non-terminal crossings up to the terminal one, in time order,
            // then the terminal one with its restart state.
            let upto = terminal.unwrap_or(crossings.len());
            for &(tr, i) in &crossings[..upto] {
                eng.dense(tr, &mut ybuf);
                on_event(
                    sys,
                    &Fired {
                        index: i,
                        t: tr,
                        y: ybuf,
                    },
                );
            }
            if let Some(k) = terminal {
                let (tr, i) = crossings[k];
                eng.dense(tr, &mut ybuf);
                if events[i].step_to_event {
                    // The restart state as accurate as a step, not only as
                    // the interpolant (errors there add up over many events).
                    let dense = ybuf;
                    if let Err(f) = eng.state_at(sys, tr, &mut ybuf, &mut stats) {
                        on_event(
                            sys,
                            &Fired {
                                index: i,
                                t: tr,
                                y: dense,
                            },
                        );
                        return Err(convert(f, eng.y()));
                    }
                }
                on_event(
                    sys,
                    &Fired {
                        index: i,
                        t: tr,
                        y: ybuf,
                    },
                );
                on_step(sys, tr, &ybuf);
                return Ok(Outcome {
                    t: tr,
                    y: ybuf,
                    stop: StopReason::Terminal(i),
                    fired: Vec::new(),
                    stats,
                });
            }
            on_step(sys, tn, eng.y());
            std::mem::swap(&mut g_prev, &mut g_new);
        }

        t = t_stop;
        y = *eng.y();
        if seg >= stops.len() {
            return Ok(Outcome {
                t,
                y,
                stop: StopReason::End,
                fired: Vec::new(),
                stats,
            });
        }
        seg += 1;
    }
}
