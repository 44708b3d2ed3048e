//! Time stepping: classical fixed-step RK4 (the paper's method), an
//! adaptive Dormand–Prince 8(5,3) ("DOP853") with 7th-order dense output,
//! and a linearly implicit Rosenbrock method (Rodas4P) for stiff problems,
//! stops at prescribed times (`tstops`, for discontinuous forcing) and event
//! location on the dense output.
//!
//! API CONTRACT (used by the models; do not change signatures without
//! updating them): see `solve`.
//!
//! # Why in-house
//!
//! The simulator needs, on a fixed-size `[f64; N]` state (no heap traffic in
//! the inner loop):
//!
//! - dense output whose error is of the size of the step error, because
//!   event times (touch-down, inversion, contact-mode switches) and the
//!   uniformly sampled output are read from it;
//! - event location (zero crossings with a direction, terminal or not);
//! - `tstops` with a restart, so that a step never straddles a jump of the
//!   applied force.
//!
//! Crates surveyed (2026-11), none of which provides all three:
//!
//! - `ode_solvers` 0.6: no root finding; its Dopri5 dense output error grows
//!   relative to the step error as the tolerance is tightened;
//! - `differential-equations` 0.7: its DOP853 dense output is about 1e4 times
//!   less accurate than the step error at tol 1e-12 on `y'' = -y`;
//! - `diffsol` 0.18: heap vectors, about 88 dependencies, API churn;
//! - `russell_ode`: heap vectors, no root finding.
//!
//! The methods are small and well documented, so they are written here
//! (about 1 200 lines with the coefficient table) and tested against the
//! properties we rely on (`tests/integrate/`).
//!
//! # Methods
//!
//! - RK4 (`Stepper::Rk4`): classical 4-stage Runge–Kutta on the grid
//!   `t_k = t_seg + k h` (computed by multiplication), the last step of a
//!   segment shortened (or lengthened by at most `1e-9 h`) to land exactly on
//!   the next tstop or `t_end`. Dense output: cubic Hermite interpolation of
//!   `(y_k, f_k, y_{k+1}, f_{k+1})`.
//! - DOP853 (`Stepper::Dop853`): Hairer's `dop853.f` algorithm: 12-stage
//!   8th-order method with FSAL, error norm combining the 5th- and 3rd-order
//!   estimates (`err = |h| e5² / sqrt(C (e5² + 0.01 e3²))`, with
//!   `sk_i = atol + rtol max(|y_i|, |y_new_i|)`, summed over the `C =
//!   OdeSystem::CONTROLLED` controlled components), automatic initial step
//!   (`hinit`), step-size control with safety 0.9, `fac1 = 0.333`,
//!   `fac2 = 6.0` and `dop853.f`'s stabilised (PI) control with a
//!   configurable `beta` (`Stepper::Dop853::beta`; `0`, Hairer's default, is
//!   the pure I controller), an optional cap of the step at the stability
//!   limit `6.1/ρ` from `dop853.f`'s own stiffness estimate `ρ`
//!   (`Stepper::Dop853::stability_cap`; the vector model uses it), and
//!   the 7th-order dense output with 3 extra stages, computed lazily (only in
//!   steps where a sample or an event needs the interpolant). The
//!   coefficients were transcribed from SciPy's
//!   `scipy/integrate/_ivp/dop853_coefficients.py`, itself from Hairer's
//!   `dop853.f` (see `dop853_coefficients.rs`).
//! - Rodas4P (`Stepper::Rodas4P`): Steinebach's variant of Hairer &
//!   Wanner's Rodas4, a stiffly accurate, L-stable Rosenbrock method of
//!   order 4(3) with an order-3 continuous extension, Jacobian by central
//!   and `∂f/∂t` by forward differences at every step, dense LU with partial pivoting on `[[f64; N]; N]`. For the
//!   regularised friction law near rolling, whose time scale `ε/(μ g)`
//!   holds DOP853 to its stability limit. See `rosenbrock.rs`.
//!
//! # Counting right-hand-side evaluations (`Stats::rhs_evals`)
//!
//! Every call of `OdeSystem::rhs` is counted, including failed ones:
//!
//! - RK4: 1 per segment start (the first stage after `begin_segment`) plus 4
//!   per step (3 stages plus `f(t_{k+1}, y_{k+1})`, which is both the Hermite
//!   end slope and the next step's first stage):
//!   `rhs_evals = segments + 4 * steps`.
//! - DOP853: 1 per segment start, 1 for `hinit` (first segment, only when
//!   `Options::h0` is `None`), 11 per attempted step (accepted or rejected),
//!   1 per accepted step for the FSAL stage `f(t_new, y_new)`, and 3 per
//!   accepted step in which the dense output is used (a sample strictly
//!   inside the step, or an event crossing):
//!   `rhs_evals = segments + [h0 is None] + 12 * steps + 11 * rejected
//!   + 3 * dense_steps`.
//! - Rodas4P: 1 per segment start, 1 for `hinit` (as DOP853), `2 C + 7`
//!   per accepted step (`2 C` for the Jacobian, `C` =
//!   `OdeSystem::CONTROLLED`, 1 for `∂f/∂t`, 5 stages, 1 for
//!   `f(t_new, y_new)`), 5 per rejected attempt (the Jacobian is reused):
//!   `rhs_evals = segments + [h0 is None] + (2 C + 7) * steps +
//!   5 * rejected`.
//!
//! `Stats::rejected` counts every rejected DOP853 or Rodas4P attempt (also
//! those before the first accepted step, which `dop853.f` does not count).

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
    /// [`OdeSystem::rhs`] at the end of a step the engine has accepted
    /// (DOP853's FSAL stage `f(t_new, y_new)`): the state the driver's
    /// event functions and observers read next, so a model may keep what it
    /// computed here for them. Must give the same `dy` as `rhs`. Default:
    /// `rhs`.
    #[inline(always)]
    fn rhs_accepted(&mut self, t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), Self::Error> {
        self.rhs(t, y, dy)
    }

    /// Number of leading components under error control: the adaptive
    /// engines' error norm, Hairer's initial step (`hinit`) and DOP853's
    /// stiffness estimate see `y[..CONTROLLED]` only, and Rodas4P
    /// differentiates the right-hand side numerically with respect to these
    /// components only. The components from `CONTROLLED` on are
    /// *quadratures* (positions, orientation angles): integrated with the
    /// same steps, dense output and events as the rest, but their errors do
    /// not steer the step size. The contract: no derivative of a controlled
    /// component reads a quadrature (so appending quadratures leaves the
    /// controlled components, the step sequence and the counters bit for bit
    /// as they were). Default: every component.
    const CONTROLLED: usize = N;

    /// The components DOP853 forms at its intermediate stages, as ranges of
    /// indices: those the right-hand side reads, and at least the
    /// controlled ones (`..CONTROLLED`, which the stiffness estimate reads
    /// at the 12th stage). A component outside (a quadrature or a work
    /// integral no derivative reads) is still integrated, with the same
    /// bits: its stage values are simply never formed, which the right-hand
    /// side does not notice (they hold NaN in debug builds, so a read shows
    /// in the tests). Default: every component.
    // A list of ranges (here one), not the range's elements.
    #[allow(clippy::single_range_in_vec_init)]
    const STAGE_READ: &'static [std::ops::Range<usize>] = &[0..N];

    /// The event functions read `y[..EVENT_READ]` only: the driver's root
    /// search interpolates just these components of the dense output (the
    /// others of the state it passes hold stale values). The events' fired
    /// states, the samples and the restarts are interpolated whole.
    /// Default: every component.
    const EVENT_READ: usize = N;

    /// The Jacobian's block among the quadratures, `∂f_i/∂y_j` for `i, j >=
    /// CONTROLLED`, written into `jac[i][j]` (the caller has zeroed it), at
    /// `(t, y)` with `f = f(t, y)`. Used by Rodas4P, which takes the other
    /// columns by finite differences; a quadrature that reads another
    /// quadrature (a position rotated by a precession angle) states the
    /// dependence here, so the method keeps its order for the quadratures
    /// without the `2 (N − CONTROLLED)` evaluations per step that finite
    /// differences would cost. Default: zero (no quadrature reads another).
    fn quadrature_jacobian(&self, _t: f64, _y: &[f64; N], _f: &[f64; N], _jac: &mut [[f64; N]; N]) {
    }

    /// Number of standard normals [`OdeSystem::thermostat`] takes per half
    /// step of the Langevin engine ([`Stepper::Langevin`]); with
    /// [`OdeSystem::NOISE_EXTRA`] at most 16. Default 0: no thermostat.
    /// The engine draws `2 (NOISE + NOISE_EXTRA)` normals per step: the
    /// first half gets numbers `0 .. NOISE` and `2 NOISE .. 2 NOISE +
    /// NOISE_EXTRA`, the second `NOISE .. 2 NOISE` and the rest, so a
    /// system that needs more normals in some states (the rigid model in
    /// flight) shares the first `NOISE` of each half with one that does not.
    const NOISE: usize = 0;
    /// Extra normals per half step, after the `NOISE` ones (see
    /// [`OdeSystem::NOISE`]). Default 0.
    const NOISE_EXTRA: usize = 0;

    /// The exact Ornstein–Uhlenbeck step over `h` of the velocities at
    /// fixed configuration (damping and its fluctuation–dissipation noise),
    /// with the standard normals `xi` (`NOISE` of them), applied to `y` in
    /// place. Called by the Langevin engine before and after each RK4 step
    /// of `rhs`. Default: nothing (no damping).
    fn thermostat(&mut self, _y: &mut [f64; N], _h: f64, _xi: &[f64]) {}

    /// One step over `h` of the overdamped (Brownian) dynamics from
    /// `(t, y)`, in place, with `NOISE` standard normals `xi`
    /// ([`Stepper::Brownian`]). Default: nothing.
    fn overdamped_step(
        &mut self,
        _t: f64,
        _y: &mut [f64; N],
        _h: f64,
        _xi: &[f64],
    ) -> Result<(), Self::Error> {
        Ok(())
    }
}

/// Which stepper, with its settings: each variant is named after its
/// algorithm (the user's `solver.method` picks one: `Method`).
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
        /// `β` of the stabilised (PI, Lund) step-size control of
        /// `dop853.f`: `h_new = h / (err^(1/8 − 0.2 β) / err_prev^β / 0.9)`
        /// (clamped), with `err_prev` the error of the last accepted step.
        /// `0` is `dop853.f`'s default (pure I control); Hairer recommends
        /// `0 < β <= 0.04` to damp the accept/reject oscillation of the step
        /// size where stability, not accuracy, limits it. Range `[0, 0.2]`.
        beta: f64,
        /// Cap each next step at the stability limit `6.1/ρ`, with `ρ` the
        /// estimate of the dominant eigenvalue's modulus that `dop853.f`
        /// computes for its stiffness detection from the last accepted step
        /// (`ρ = |f(y₁) − f(ŷ)| / |y₁ − ŷ|`, `ŷ` the 12th stage's state,
        /// also at `t + h`). DOP853 is stable on `[−6.39, 0]` of the real
        /// axis (`|R(−6.1)| = 0.59`): where a stiff mode holds the step at
        /// that limit, the error-based controller alone overshoots it and
        /// has the step rejected, about one attempt in four on the classical
        /// top with regularised friction; the cap stops that. The cap never
        /// shrinks a step by more than the controller may (to 0.333 of the
        /// last one), and is never binding on a problem that is
        /// accuracy-bound (there `h ρ` stays below 6.1). `false` is
        /// `dop853.f`'s behaviour.
        stability_cap: bool,
    },
    /// Rodas4P (linearly implicit, L-stable, order 4 with an order-3 error
    /// estimate and order-3 dense output) with error control
    /// `RMS(err_i / (atol + rtol * max(|y_i|, |y_new_i|))) <= 1`, for stiff
    /// problems. Numerical Jacobian (central differences over the controlled
    /// components, `2 C + 1` evaluations per step with `∂f/∂t`). What
    /// `solver.method = "stiff"` runs.
    Rodas4P {
        /// Relative tolerance.
        rtol: f64,
        /// Absolute tolerance.
        atol: f64,
    },
    /// The Langevin engine: `O(h/2) Φ(h) O(h/2)` with `O` the system's
    /// [`OdeSystem::thermostat`] and `Φ` an RK4 step, on the grid `k h`
    /// (a segment start off the grid takes one shorter step to it); dense
    /// output by linear interpolation (`integrate::langevin`).
    Langevin {
        /// Grid step (same time unit as `t`).
        h: f64,
        /// Key of the random stream.
        seed: u64,
        /// Run index of the random stream.
        run: u64,
        /// Global number of the first step (the stream's counter), so a
        /// run restarted at a segment continues its stream.
        first_step: u64,
    },
    /// The overdamped (Brownian) engine: one [`OdeSystem::overdamped_step`]
    /// per step on the grid `k h`, the same grid, stream and dense output
    /// as [`Stepper::Langevin`].
    Brownian {
        /// Grid step (same time unit as `t`).
        h: f64,
        /// Key of the random stream.
        seed: u64,
        /// Run index of the random stream.
        run: u64,
        /// Global number of the first step (the stream's counter).
        first_step: u64,
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
    #[allow(clippy::type_complexity)]
    pub g: Box<dyn Fn(&S, f64, &[f64; N]) -> f64 + Send + Sync>,
    /// Which crossings count.
    pub direction: Direction,
    /// Stop the integration at the first crossing.
    pub terminal: bool,
    /// For a terminal event: the state at the event is computed by a step
    /// of the method from the last step's start to the event (DOP853:
    /// order 8) instead of the interpolant (order 7). Only where the
    /// right-hand side is smooth at the event: a kink continued through the
    /// event is (the branch of `μ|N|` latched at `N = 0`); the zero of `v/|v|`
    /// at zero slip is not (the stages next to it see `v/|v|` turn).
    pub step_to_event: bool,
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
    /// The event function rose through zero (it was negative at the step's
    /// start); else it fell.
    pub rising: bool,
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
    /// Every event that fired, in time order (the terminal one last); empty
    /// from [`solve_with_events`], which reports them as they fire.
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

impl Options {
    /// Default limit on the number of accepted steps.
    pub const DEFAULT_MAX_STEPS: u64 = 10_000_000;

    /// Classical RK4 with fixed step `h`; `max_steps` 10 000 000.
    pub fn rk4(h: f64) -> Self {
        Options {
            stepper: Stepper::Rk4 { h },
            max_steps: Self::DEFAULT_MAX_STEPS,
            h0: None,
            h_max: None,
        }
    }

    /// DOP853 with tolerances `rtol`, `atol`, `β = 0` and no stability cap
    /// (`dop853.f`'s step-size control); automatic initial
    /// step, no step limit other than the interval, `max_steps` 10 000 000.
    pub fn dop853(rtol: f64, atol: f64) -> Self {
        Options {
            stepper: Stepper::Dop853 {
                rtol,
                atol,
                beta: 0.0,
                stability_cap: false,
            },
            max_steps: Self::DEFAULT_MAX_STEPS,
            h0: None,
            h_max: None,
        }
    }

    /// Rodas4P with tolerances `rtol`, `atol`; automatic initial step, no
    /// step limit other than the interval, `max_steps` 10 000 000.
    pub fn rosenbrock(rtol: f64, atol: f64) -> Self {
        Options {
            stepper: Stepper::Rodas4P { rtol, atol },
            max_steps: Self::DEFAULT_MAX_STEPS,
            h0: None,
            h_max: None,
        }
    }
}

mod dop853;
mod dop853_coefficients;
mod driver;
pub(crate) use driver::{AnyEngine, Stepped, Stepping};
mod langevin;
pub(crate) use langevin::nearest_grid;
mod rk4;
mod roots;
mod rosenbrock;
#[cfg(test)]
mod weak_order;

/// One counted right-hand-side evaluation (every stepper counts through here).
/// [`eval`] through [`OdeSystem::rhs_accepted`].
fn eval_accepted<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t: f64,
    y: &[f64; N],
    dy: &mut [f64; N],
    stats: &mut Stats,
) -> Result<(), Fail<S::Error>> {
    stats.rhs_evals += 1;
    sys.rhs_accepted(t, y, dy)
        .map_err(|err| Fail::Rhs { t, err })
}

fn eval<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t: f64,
    y: &[f64; N],
    dy: &mut [f64; N],
    stats: &mut Stats,
) -> Result<(), Fail<S::Error>> {
    stats.rhs_evals += 1;
    sys.rhs(t, y, dy).map_err(|err| Fail::Rhs { t, err })
}

/// Panic unless the settings of an adaptive stepper (`name` in messages)
/// make sense: tolerances finite, non-negative, not both zero; `h_max` and
/// `h0` (if given) finite and positive.
fn check_adaptive(name: &str, rtol: f64, atol: f64, h0: Option<f64>, h_max: f64) {
    assert!(
        rtol.is_finite() && atol.is_finite() && rtol >= 0.0 && atol >= 0.0,
        "{name} tolerances must be finite and non-negative (rtol {rtol}, atol {atol})"
    );
    assert!(
        rtol > 0.0 || atol > 0.0,
        "{name} tolerances must not both be zero"
    );
    assert!(
        h_max.is_finite() && h_max > 0.0,
        "h_max must be finite and positive, got {h_max}"
    );
    if let Some(h) = h0 {
        assert!(
            h.is_finite() && h > 0.0,
            "h0 must be finite and positive, got {h}"
        );
    }
}

/// Hairer's `hinit` (`dop853.f`) for a method of order `order`: an initial
/// step from the sizes of `y`, `f0 = f(t, y)` and an estimate of the second
/// derivative (one extra evaluation), capped at `h_max`; 1e-6 if the
/// estimate is not a finite positive number.
#[allow(clippy::too_many_arguments)]
fn hinit<S: OdeSystem<N>, const N: usize>(
    sys: &mut S,
    t: f64,
    y: &[f64; N],
    f0: &[f64; N],
    (rtol, atol): (f64, f64),
    order: i32,
    h_max: f64,
    stats: &mut Stats,
) -> Result<f64, Fail<S::Error>> {
    let mut dnf = 0.0;
    let mut dny = 0.0;
    for n in 0..S::CONTROLLED {
        let sk = atol + rtol * y[n].abs();
        dnf += (f0[n] / sk).powi(2);
        dny += (y[n] / sk).powi(2);
    }
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1.0e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(h_max);
    let mut y1 = [0.0; N];
    for n in 0..N {
        y1[n] = y[n] + h * f0[n];
    }
    let mut f1 = [0.0; N];
    eval(sys, t + h, &y1, &mut f1, stats)?;
    let mut der2 = 0.0;
    for n in 0..S::CONTROLLED {
        let sk = atol + rtol * y[n].abs();
        der2 += ((f1[n] - f0[n]) / sk).powi(2);
    }
    let der2 = der2.sqrt() / h;
    let der12 = der2.abs().max(dnf.sqrt());
    let h1 = if der12 <= 1e-15 {
        (h * 1.0e-3).max(1.0e-6)
    } else {
        (0.01 / der12).powf(1.0 / f64::from(order))
    };
    let h = (100.0 * h).min(h1).min(h_max);
    Ok(if h.is_finite() && h > 0.0 { h } else { 1.0e-6 })
}

/// A stepper failure, before the driver attaches the last accepted state.
pub(crate) enum Fail<E> {
    /// `rhs` failed at `t`.
    Rhs { t: f64, err: E },
    /// Step size underflow at `t` with step `h`.
    Underflow { t: f64, h: f64 },
    /// Non-finite solution at (last accepted) `t`.
    NonFinite { t: f64 },
}

/// What the driver needs from a stepper. After `restart` the stepper holds
/// `(t, y)` and `f(t, y)`; after `step` it holds the accepted step
/// `(t_prev, y_prev) -> (t, y)` and can interpolate in it.
pub(crate) trait Engine<const N: usize> {
    /// Start a segment at `(t, y)`: evaluate the first stage afresh.
    fn restart<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        y: &[f64; N],
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>>;
    /// Take one accepted step, landing exactly on `t_stop` at most
    /// (rejected attempts are counted in `stats.rejected`).
    fn step<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t_stop: f64,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>>;
    /// Current (last accepted) time.
    fn t(&self) -> f64;
    /// Current (last accepted) state.
    fn y(&self) -> &[f64; N];
    /// Start time of the last accepted step.
    fn t_prev(&self) -> f64;
    /// Make the interpolant of the last step available (may evaluate `rhs`).
    fn prepare_dense<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>>;
    /// Interpolated state at `t` in `[t_prev, t]` (exact at both ends);
    /// `prepare_dense` must have been called for this step.
    fn dense(&self, t: f64, out: &mut [f64; N]);
    /// [`Engine::dense`] for the components `..n` only (the others of `out`
    /// are left as they are), the same bits for those; by default the
    /// whole state.
    fn dense_prefix(&self, t: f64, out: &mut [f64; N], n: usize) {
        let _ = n;
        self.dense(t, out);
    }
    /// The state at `t` in `[t_prev, t]` for a restart at a terminal event:
    /// by default the dense output; DOP853 takes a step of its method from
    /// `t_prev` to `t` instead (order 8 rather than the interpolant's 7).
    fn state_at<S: OdeSystem<N>>(
        &mut self,
        sys: &mut S,
        t: f64,
        out: &mut [f64; N],
        stats: &mut Stats,
    ) -> Result<(), Fail<S::Error>> {
        self.prepare_dense(sys, stats)?;
        self.dense(t, out);
        Ok(())
    }
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
///
/// Details of the driver:
///
/// - `sys.begin_segment` is called at `t0` and at every tstop, before the
///   samples at that time (at `t0`) and before the event functions are
///   evaluated at the segment start; samples and `on_step` at a tstop see the
///   system as it was during the segment that ends there.
/// - A crossing is a sign change of `g` between consecutive step ends in the
///   allowed direction; `g == 0` at the start of a step never counts, so an
///   event that fired exactly at a step end, at `t0` or at a restart does not
///   fire again. Two crossings of the same `g` within one step are not seen.
///   Roots are bracketed (Illinois method with bisection safeguard) to
///   `|Δt| <= 4 eps max(|t|, h)`; the reported time is the bracket end on
///   the far side of the crossing.
/// - With a terminal event, the last `on_step` call is at the event time
///   and state (the truncated step), equal to `Outcome::t`, `Outcome::y`.
/// - Samples before `t0` or after `t_end` are ignored.
///
/// # Panics
///
/// If `t0`, `t_end` are not finite or `t_end < t0`; if the RK4 step is not
/// finite and positive; if `rtol`/`atol` are negative, not finite or both
/// zero; if `h0`/`h_max` are given but not finite and positive.
#[allow(clippy::too_many_arguments)]
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
    let mut fired = Vec::new();
    let out = driver::run(
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
        &mut |_, f| fired.push(*f),
    );
    out.map(|o| Outcome { fired, ..o })
}

/// As [`solve`], but every event that fires is passed to `on_event(sys,
/// fired)` at once, in time order (the terminal one last, with the restart
/// state), instead of being collected: [`Outcome::fired`] is empty. Memory
/// stays constant however many events a long integration has, and a failed
/// integration has reported every event before its failure.
///
/// # Panics
///
/// As [`solve`].
#[allow(clippy::too_many_arguments)]
pub fn solve_with_events<S: OdeSystem<N>, const N: usize>(
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
    driver::run(
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
}
