//! Time stepping: classical fixed-step RK4 (the paper's method) and an
//! adaptive Dormand–Prince 8(5,3) ("DOP853") with 7th-order dense output,
//! stops at prescribed times (`tstops`, for discontinuous forcing) and event
//! location on the dense output.
//!
//! API CONTRACT (used by the models; do not change signatures without
//! updating them): see `solve`.

/// A first-order ODE system `y' = f(t, y)` on a fixed-size state.
pub trait OdeSystem<const N: usize> {
    /// Error the right-hand side may return (the integration stops with it).
    type Error;
    /// Called by the driver at `t0` and again at every `tstop`, with the
    /// segment's start time and state, before any right-hand-side evaluation
    /// of that segment. Piecewise-constant inputs (the applied force) are
    /// latched here, so a step never straddles a discontinuity.
    fn begin_segment(&mut self, _t: f64, _y: &[f64; N]) {}
    /// Evaluate `dy = f(t, y)`.
    fn rhs(&mut self, t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), Self::Error>;
}

/// Which stepper, with its settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stepper {
    /// Classical RK4 with fixed step `h` (shortened only to land on a tstop
    /// or on `t_end`; after a tstop the grid restarts from it). Dense output
    /// by cubic Hermite interpolation from the step-end values and slopes.
    Rk4 {
        /// Step size (same time unit as `t`).
        h: f64,
    },
    /// DOP853 with error control `|err_i| <= atol + rtol * max(|y_i|, |y_new_i|)`.
    Dop853 {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
}

/// Direction of a zero crossing that triggers an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// g goes from negative to positive.
    Rising,
    /// g goes from positive to negative.
    Falling,
    /// Either.
    Either,
}

/// An event: a zero crossing of `g(system, t, y)`.
pub struct Event<S, const N: usize> {
    /// The event function.
    pub g: Box<dyn Fn(&S, f64, &[f64; N]) -> f64>,
    /// Which crossings count.
    pub direction: Direction,
    /// Stop the integration at the first crossing.
    pub terminal: bool,
}

/// An event that fired.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fired<const N: usize> {
    /// Index into the `events` slice.
    pub index: usize,
    /// Time of the zero crossing.
    pub t: f64,
    /// State there (dense output).
    pub y: [f64; N],
}

/// Work counters.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Right-hand-side evaluations.
    pub rhs_evals: u64,
    /// Accepted steps.
    pub steps: u64,
    /// Rejected steps.
    pub rejected: u64,
}

/// Why `solve` returned.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    /// Reached `t_end`.
    End,
    /// A terminal event fired (index into `events`).
    Terminal(usize),
}

/// Result of a successful `solve`.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome<const N: usize> {
    /// Final time (t_end, or the terminal event's time).
    pub t: f64,
    /// Final state.
    pub y: [f64; N],
    /// Why it stopped.
    pub stop: StopReason,
    /// Every event that fired, in time order (the terminal one last).
    pub fired: Vec<Fired<N>>,
    /// Work counters.
    pub stats: Stats,
}

/// Failures of the integration.
#[derive(Debug, Clone, PartialEq)]
pub enum IntegrateError<E> {
    /// The right-hand side returned an error at time `t`.
    Rhs {
        /// Time of the failing evaluation.
        t: f64,
        /// Last accepted state.
        y_last: Vec<f64>,
        /// The error.
        err: E,
    },
    /// The step size fell below `16 * eps * |t|` (or 1e-300).
    StepUnderflow {
        /// Time reached.
        t: f64,
        /// Step size attempted.
        h: f64,
        /// Last accepted state.
        y_last: Vec<f64>,
    },
    /// The solution became NaN or infinite.
    NonFinite {
        /// Time reached.
        t: f64,
        /// Last accepted (finite) state.
        y_last: Vec<f64>,
    },
    /// More than `max_steps` accepted steps.
    TooManySteps {
        /// Time reached.
        t: f64,
        /// The limit.
        max_steps: u64,
    },
}

/// Options of `solve`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// The stepper.
    pub stepper: Stepper,
    /// Largest number of accepted steps before `TooManySteps`.
    pub max_steps: u64,
    /// Initial step (adaptive); `None` for Hairer's automatic choice.
    pub h0: Option<f64>,
    /// Largest step (adaptive); `None` for `t_end - t0`.
    pub h_max: Option<f64>,
}

/// Integrate `sys` from `(t0, y0)` to `t_end`.
///
/// - `tstops`: times in `(t0, t_end)` (others ignored) where the integrator
///   lands exactly, calls `sys.begin_segment`, and restarts (fresh first
///   stage, no FSAL reuse across it).
/// - `sample_times`: sorted times in `[t0, t_end]`; `on_sample(sys, t, y)` is
///   called once for each, in order, from dense output (exact at `t0`, at
///   `t_end` and at step ends). Samples after a terminal event are not emitted.
/// - `events`: zero crossings located on the dense output to near machine
///   precision in t; an event exactly at `t0` does not fire.
/// - `on_step(sys, t, y)`: called after every accepted step with its end point.
pub fn solve<S: OdeSystem<N>, const N: usize>(
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
) -> Result<Outcome<N>, IntegrateError<S::Error>> {
    let _ = (
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
    );
    todo!("integrator driver")
}
