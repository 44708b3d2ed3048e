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
        Stepper::Rodas4P { rtol, atol } => {
            drive_with!(Rodas4p::new(rtol, atol, opts.h0, h_max))
        }
        Stepper::Langevin {
            h,
            seed,
            run,
            first_step,
        } => drive_with!(super::langevin::Langevin::new(
            h, seed, run, first_step, false
        )),
        Stepper::Brownian {
            h,
            seed,
            run,
            first_step,
        } => drive_with!(super::langevin::Langevin::new(
            h, seed, run, first_step, true
        )),
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
    eng: E,
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
    let mut stops: Vec<f64> = tstops
        .iter()
        .copied()
        .filter(|&s| s > t0 && s < t_end)
        .collect();
    stops.sort_by(f64::total_cmp);
    stops.dedup();

    let si = sample_times.partition_point(|&s| s < t0);
    let mut st = Stepping::new(eng, events.len(), si);
    let mut t = t0;
    let mut y = y0;
    let mut seg = 0;
    loop {
        let t_stop = stops.get(seg).copied().unwrap_or(t_end);
        let first = seg == 0;
        if !st.begin(sys, t, &y, t_stop, first, sample_times, events, on_sample)? {
            return Ok(Outcome {
                t: t0,
                y: y0,
                stop: StopReason::End,
                fired: Vec::new(),
                stats: st.stats,
            });
        }
        loop {
            match st.step(
                sys,
                opts,
                sample_times,
                events,
                on_sample,
                on_step,
                on_event,
            )? {
                Stepped::Step => {}
                Stepped::SegmentEnd => break,
                Stepped::Terminal { index, t, y } => {
                    return Ok(Outcome {
                        t,
                        y,
                        stop: StopReason::Terminal(index),
                        fired: Vec::new(),
                        stats: st.stats,
                    });
                }
            }
        }
        t = t_stop;
        y = *st.eng.y();
        if seg >= stops.len() {
            return Ok(Outcome {
                t,
                y,
                stop: StopReason::End,
                fired: Vec::new(),
                stats: st.stats,
            });
        }
        seg += 1;
    }
}

/// The engine of one of the three methods, chosen at run time (for the
/// resumable driver, which keeps one across calls).
#[derive(Clone)]
pub(crate) enum AnyEngine<const N: usize> {
    /// Classical RK4.
    Rk4(Rk4<N>),
    /// DOP853.
    Dop853(Dop853<N>),
    /// Rodas4P.
    Rodas4p(Rodas4p<N>),
    /// The Langevin splitting.
    Langevin(super::langevin::Langevin<N>),
}

impl<const N: usize> AnyEngine<N> {
    /// The engine `opts` asks for, for a segment `[t0, t_end]` (the adaptive
    /// steppers' largest step defaults to the segment's length).
    pub(crate) fn new(opts: &Options, t0: f64, t_end: f64) -> Self {
        let h_max = default_h_max(opts, t0, t_end);
        match opts.stepper {
            Stepper::Rk4 { h } => AnyEngine::Rk4(Rk4::new(h)),
            Stepper::Dop853 {
                rtol,
                atol,
                beta,
                stability_cap,
            } => AnyEngine::Dop853(Dop853::new(rtol, atol, beta, stability_cap, opts.h0, h_max)),
            Stepper::Rodas4P { rtol, atol } => {
                AnyEngine::Rodas4p(Rodas4p::new(rtol, atol, opts.h0, h_max))
            }
            Stepper::Langevin {
                h,
                seed,
                run,
                first_step,
            } => AnyEngine::Langevin(super::langevin::Langevin::new(
                h, seed, run, first_step, false,
            )),
            Stepper::Brownian {
                h,
                seed,
                run,
                first_step,
            } => AnyEngine::Langevin(super::langevin::Langevin::new(
                h, seed, run, first_step, true,
            )),
        }
    }
}

impl<const N: usize> AnyEngine<N> {
    /// Become [`AnyEngine::new`]`(opts, t0, t_end)`: a DOP853 engine for
    /// DOP853 settings is renewed in place (its buffers kept, see
    /// `Dop853::renew`), any other is replaced.
    pub(crate) fn renew(&mut self, opts: &Options, t0: f64, t_end: f64) {
        match (self, opts.stepper) {
            (
                AnyEngine::Dop853(e),
                Stepper::Dop853 {
                    rtol,
                    atol,
                    beta,
                    stability_cap,
                },
            ) => e.renew(
                rtol,
                atol,
                beta,
                stability_cap,
                opts.h0,
                default_h_max(opts, t0, t_end),
            ),
            (this, _) => *this = AnyEngine::new(opts, t0, t_end),
        }
    }

    /// Set the random stream's counter of the next step (stochastic
    /// engines; nothing for the deterministic ones).
    pub(crate) fn set_noise_counter(&mut self, next_step: u64) {
        if let AnyEngine::Langevin(e) = self {
            e.set_counter(next_step);
        }
    }
}

macro_rules! each_engine {
    ($self:expr, $e:ident => $body:expr) => {
        match $self {
            AnyEngine::Rk4($e) => $body,
            AnyEngine::Dop853($e) => $body,
            AnyEngine::Rodas4p($e) => $body,
            AnyEngine::Langevin($e) => $body,
        }
    };
}

impl<const N: usize> Engine<N> for AnyEngine<N> {
    fn restart<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        each_engine!(self, e => e.restart(sys, t, y, t_stop, stats))
    }
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        each_engine!(self, e => e.step(sys, t_stop, stats))
    }
    fn t(&self) -> f64 {
        each_engine!(self, e => e.t())
    }
    fn y(&self) -> &[f64; N] {
        each_engine!(self, e => e.y())
    }
    fn t_prev(&self) -> f64 {
        each_engine!(self, e => e.t_prev())
    }
    fn prepare_dense<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        each_engine!(self, e => e.prepare_dense(sys, stats))
    }
    fn dense(&self, t: f64, out: &mut [f64; N]) {
        each_engine!(self, e => e.dense(t, out))
    }
    fn dense_prefix(&self, t: f64, out: &mut [f64; N], n: usize) {
        each_engine!(self, e => e.dense_prefix(t, out, n))
    }
    fn state_at<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        out: &mut [f64; N],
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        each_engine!(self, e => e.state_at(sys, t, out, stats))
    }
}

/// What one call of [`Stepping::step`] did.
pub(crate) enum Stepped<const N: usize> {
    /// An accepted step inside the segment.
    Step,
    /// The accepted step reached the segment's end.
    SegmentEnd,
    /// A terminal event fired: the segment ends at `t` with state `y`.
    Terminal {
        /// Index of the event.
        index: usize,
        /// Event time.
        t: f64,
        /// Restart state.
        y: [f64; N],
    },
}

/// One segment of an integration taken a step at a time: the engine, the
/// event functions' values at the last step end, the next sample and the
/// work counters. `solve` runs it to the end of each segment; the resumable
/// driver (`crate::simulate::Simulation`) keeps it between calls, so a
/// pause never changes a step.
#[derive(Clone)]
pub(crate) struct Stepping<E, const N: usize> {
    /// The engine (its last accepted step and dense output).
    pub(crate) eng: E,
    t_stop: f64,
    /// Work counters since this `Stepping` was made.
    pub(crate) stats: Stats,
    g_prev: Vec<f64>,
    g_new: Vec<f64>,
    crossings: Vec<(f64, usize, bool)>,
    /// Index of the next sample time not yet emitted.
    pub(crate) si: usize,
}

impl<E: Engine<N>, const N: usize> Stepping<E, N> {
    /// A stepper with `n_events` events, the next sample at index `si`.
    pub(crate) fn new(eng: E, n_events: usize, si: usize) -> Self {
        Stepping {
            eng,
            t_stop: 0.0,
            stats: Stats::default(),
            g_prev: vec![0.0; n_events],
            g_new: vec![0.0; n_events],
            crossings: Vec::with_capacity(n_events),
            si,
        }
    }

    /// Become [`Stepping::new`]`(eng, n_events, si)` with the engine it has
    /// (renewed by the caller) and its lists' storage kept.
    pub(crate) fn reset(&mut self, n_events: usize, si: usize) {
        self.t_stop = 0.0;
        self.stats = Stats::default();
        self.g_prev.clear();
        self.g_prev.resize(n_events, 0.0);
        self.g_new.clear();
        self.g_new.resize(n_events, 0.0);
        self.crossings.clear();
        self.si = si;
    }

    /// Start a segment at `(t, y)` ending at `t_stop`: `sys.begin_segment`,
    /// then (for the `first` segment) the samples at exactly `t`, the event
    /// functions at the start and the engine's restart. `Ok(false)` if the
    /// segment is empty (`t_stop == t`, first segment only: nothing to do).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn begin<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        t_stop: f64,
        first: bool,
        sample_times: &[f64],
        events: &[Event<S, N>],
        on_sample: &mut dyn FnMut(&S, f64, &[f64; N]),
    ) -> Result<bool, IntegrateError<S::Error>> {
        self.t_stop = t_stop;
        sys.begin_segment(t, y);
        if first {
            while self.si < sample_times.len() && sample_times[self.si] == t {
                on_sample(sys, t, y);
                self.si += 1;
            }
            if t_stop == t {
                return Ok(false);
            }
        }
        for (gp, ev) in self.g_prev.iter_mut().zip(events) {
            *gp = (ev.g)(sys, t, y);
        }
        self.eng
            .restart(sys, t, y, t_stop, &mut self.stats)
            .map_err(|f| convert(f, y))?;
        Ok(true)
    }

    /// Take one accepted step (the segment must not have ended): locate the
    /// events in it, emit the samples and the non-terminal events up to the
    /// terminal one (if any), call `on_step`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        opts: &Options,
        sample_times: &[f64],
        events: &[Event<S, N>],
        on_sample: &mut dyn FnMut(&S, f64, &[f64; N]),
        on_step: &mut dyn FnMut(&S, f64, &[f64; N]),
        on_event: &mut dyn FnMut(&S, &Fired<N>),
    ) -> Result<Stepped<N>, IntegrateError<S::Error>> {
        let t_stop = self.t_stop;
        let eng = &mut self.eng;
        let stats = &mut self.stats;
        let mut ybuf = [0.0; N];
        let ns = sample_times.len();
        if stats.steps >= opts.max_steps {
            return Err(IntegrateError::TooManySteps {
                t: eng.t(),
                max_steps: opts.max_steps,
            });
        }
        if let Err(f) = eng.step(sys, t_stop, stats) {
            return Err(convert(f, eng.y()));
        }
        stats.steps += 1;
        let tn = eng.t();
        let tp = eng.t_prev();

        // Events: sign changes between the step ends, located on the
        // dense output.
        self.crossings.clear();
        for (i, ev) in events.iter().enumerate() {
            let gn = (ev.g)(sys, tn, eng.y());
            self.g_new[i] = gn;
            if crosses(self.g_prev[i], gn, ev.direction) {
                if let Err(f) = eng.prepare_dense(sys, stats) {
                    return Err(convert(f, eng.y()));
                }
                let tol = 4.0 * f64::EPSILON * tn.abs().max(tn - tp);
                let sys_ref: &S = sys;
                let eng_ref = &*eng;
                let tr = illinois(
                    |tc| {
                        eng_ref.dense_prefix(tc, &mut ybuf, S::EVENT_READ);
                        (ev.g)(sys_ref, tc, &ybuf)
                    },
                    tp,
                    tn,
                    self.g_prev[i],
                    gn,
                    tol,
                );
                self.crossings.push((tr, i, self.g_prev[i] < 0.0));
            }
        }
        let crossings = &mut self.crossings;
        crossings.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let terminal = crossings.iter().position(|&(_, i, _)| events[i].terminal);
        let t_lim = terminal.map_or(tn, |k| crossings[k].0);

        // Samples in (tp, t_lim].
        while self.si < ns && sample_times[self.si] <= t_lim {
            let ts = sample_times[self.si];
            if ts == tn {
                on_sample(sys, tn, eng.y());
            } else {
                if let Err(f) = eng.prepare_dense(sys, stats) {
                    return Err(convert(f, eng.y()));
                }
                eng.dense(ts, &mut ybuf);
                on_sample(sys, ts, &ybuf);
            }
            self.si += 1;
        }

        // Non-terminal crossings up to the terminal one, in time order,
        // then the terminal one with its restart state.
        let upto = terminal.unwrap_or(crossings.len());
        for &(tr, i, rising) in &crossings[..upto] {
            eng.dense(tr, &mut ybuf);
            on_event(
                sys,
                &Fired {
                    index: i,
                    t: tr,
                    y: ybuf,
                    rising,
                },
            );
        }
        if let Some(k) = terminal {
            let (tr, i, rising) = crossings[k];
            eng.dense(tr, &mut ybuf);
            if events[i].step_to_event {
                // The restart state as accurate as a step, not only as
                // the interpolant (errors there add up over many events).
                let dense = ybuf;
                if let Err(f) = eng.state_at(sys, tr, &mut ybuf, stats) {
                    on_event(
                        sys,
                        &Fired {
                            index: i,
                            t: tr,
                            y: dense,
                            rising,
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
                    rising,
                },
            );
            on_step(sys, tr, &ybuf);
            return Ok(Stepped::Terminal {
                index: i,
                t: tr,
                y: ybuf,
            });
        }
        on_step(sys, tn, eng.y());
        std::mem::swap(&mut self.g_prev, &mut self.g_new);
        Ok(if eng.t() < t_stop {
            Stepped::Step
        } else {
            Stepped::SegmentEnd
        })
    }
}
