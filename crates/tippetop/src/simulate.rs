//! Run a scenario: the driver that turns a [`Scenario`] into a [`Trajectory`].
//!
//! The driver owns what the integrator does not know about: the switch
//! times of the force schedule (each one ends a `solve` call, so the driver
//! can re-examine stick/slip with the new force there), the events that
//! diagnostics need (θ crossing π/2, local maxima of θ, N crossing zero)
//! and, for the exact Coulomb law, the stick/slip switches (terminal events
//! after which the model changes mode and the integration restarts).

use crate::{
    ContactMode, Error, EventRecord, Initial, Method, ModelKind, Sample, Scenario, Summary,
    Trajectory,
    integrate::{self, Direction, Event, IntegrateError, OdeSystem, Options, Stepper, StopReason},
    model::{
        OnPlane,
        reduced::{self, DIM, Mode, ModelError, OM, Reduced, Scales, TH, THD, UX, UY, W, WA, WF},
        vector::{self, Vector},
    },
    observe,
};

/// Largest number of accepted steps of one run before it is stopped (see
/// [`crate::limits::MAX_STEPS`] and [`crate::limits::max_steps_for`]).
pub use crate::limits::MAX_STEPS;
/// Largest number of stick/slip switches of one run before it is stopped.
pub const MAX_SWITCHES: usize = 200_000;

/// Run `scenario`. `Err` only for bad input; a run that fails while
/// integrating returns `Ok` with `trajectory.error` set and the samples up to
/// the failure.
pub fn simulate(scenario: &Scenario) -> Result<Trajectory, Error> {
    simulate_with_progress(scenario, &mut |_| {})
}

/// Accepted steps between two calls of the progress callback of
/// [`simulate_with_progress`].
pub const PROGRESS_EVERY: u64 = 1 << 14;

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

/// Why a run of `sc` stopped at its step limit `cap`, with a hint at why it
/// cannot make progress.
pub(crate) fn step_limit_why(sc: &Scenario, cap: u64) -> String {
    let mean = sc.solver.t_end / cap as f64;
    let hint = match (sc.surface.law, sc.solver.method) {
        (crate::FrictionLaw::Coulomb, _) => {
            "stick/slip switches or N = 0 crossings that follow each other ever faster, or a rate far faster than t_end"
        }
        (crate::FrictionLaw::CoulombSliding, _) => {
            "a slip that chatters around zero: try friction_law = \"coulomb\" (exact stick/slip)"
        }
        (_, Method::Stiff) => "a stiff friction law near rolling: try a larger friction_eps",
        _ => "a stiff friction law near rolling: try method = \"stiff\" or a larger friction_eps",
    };
    let periods = sc.solver.t_end / crate::limits::time_unit(sc);
    format!(
        "step limit {cap} reached (the run cannot make progress: the motion needs steps far shorter than t_end / {cap} = {mean:e} s; {hint}; t_end is {periods:.3e} time units T_ref of the fastest initial rate; solver.max_steps sets the limit, at most {})",
        crate::limits::MAX_STEPS
    )
}

/// The error of a run whose output row at `t` \[s\] is not finite.
pub(crate) fn nonfinite_output_error(t: f64, state: &str) -> Error {
    Error::runtime(
        t,
        format!(
            "the output became NaN or infinite (a value overflows f64 in SI units); last accepted {state}"
        ),
    )
}

/// The friction law as a phrase for messages.
pub(crate) fn law_phrase(law: crate::FrictionLaw) -> String {
    match law {
        crate::FrictionLaw::Coulomb => "Coulomb friction (friction_law = \"coulomb\")".into(),
        crate::FrictionLaw::CoulombSliding => {
            "sliding Coulomb friction (friction_law = \"coulomb_sliding\")".into()
        }
        crate::FrictionLaw::Regularized { eps } => {
            format!(
                "regularized friction (friction_law = \"regularized\", friction_eps = {eps} m/s)"
            )
        }
        crate::FrictionLaw::Viscous { eps } => {
            format!("viscous friction (friction_law = \"viscous\", friction_eps = {eps} m/s)")
        }
    }
}

/// Why a run of `sc` failed with the Painlevé case at `theta` \[rad\]
/// (`solutions` consistent normal forces, 0 or 2, of the model's `system`
/// of equations), naming the run's law.
pub(crate) fn painleve_why(sc: &Scenario, system: &str, theta: f64, solutions: usize) -> String {
    format!(
        "Painleve paradox at theta = {theta}: the {system} with {} has {solutions} consistent solutions (m a h mu sin(theta)/A too large); no unique motion exists",
        law_phrase(sc.surface.law)
    )
}

/// Relative energy-balance error beyond which a failed fixed-step (RK4) run
/// is reported as unstable rather than by the failure that ended it.
pub(crate) const RK4_UNSTABLE_BALANCE: f64 = 1e-2;

/// A failed RK4 run whose energy balance was already off by more than
/// [`RK4_UNSTABLE_BALANCE`]: the fixed step made the solution unstable, and
/// `why` (a Painlevé case, a NaN) is a consequence, not the physics. Any
/// other failure of an RK4 run says that its fixed step may be the cause.
pub(crate) fn unstable_rk4(sc: &Scenario, track: &Track, why: String) -> String {
    let rel = track.balance_rel();
    if sc.solver.method == Method::Rk4 && (rel.is_nan() || rel > RK4_UNSTABLE_BALANCE) {
        format!(
            "the RK4 solution became unstable (energy balance error {rel:.1e} of max |E|): the fixed step t_end / steps = {:e} s is too long for this motion, raise solver.steps or use method = \"adaptive\"; it ended with: {why}",
            sc.solver.t_end / sc.solver.steps as f64
        )
    } else if sc.solver.method == Method::Rk4 {
        format!(
            "{why} (method = \"rk4\" with a fixed step t_end / steps = {:e} s: check that it persists with more steps or method = \"adaptive\")",
            sc.solver.t_end / sc.solver.steps as f64
        )
    } else {
        why
    }
}

/// The events a run records: at most [`crate::limits::MAX_EVENTS`], then one
/// `"event_limit_reached"` record (see there).
#[derive(Debug, Default)]
pub(crate) struct EventList {
    list: Vec<EventRecord>,
    dropped: u64,
}

impl EventList {
    /// Record an event of `kind` at `t` \[s\] (or count it if the list is full).
    pub(crate) fn push(&mut self, t: f64, kind: &str) {
        if self.list.len() < crate::limits::MAX_EVENTS {
            self.list.push(EventRecord {
                t,
                kind: kind.into(),
            });
        } else {
            if self.dropped == 0 {
                self.list.push(EventRecord {
                    t,
                    kind: "event_limit_reached".into(),
                });
            }
            self.dropped += 1;
        }
    }

    /// The records in time order.
    pub(crate) fn into_sorted(mut self) -> Vec<EventRecord> {
        self.list.sort_by(|a, b| a.t.total_cmp(&b.t));
        self.list
    }
}

// Event indices.
const EV_HALF_PI: usize = 0;
const EV_THETA_MAX: usize = 1;
const EV_NORMAL: usize = 2;
const EV_SWITCH: usize = 3;

fn events_for<M: ContactModel<D>, const D: usize>(m: &M) -> Vec<Event<M, D>> {
    let mut ev: Vec<Event<M, D>> = vec![
        Event {
            g: Box::new(|m: &M, _, y| m.above_half_pi(y)),
            direction: Direction::Rising,
            terminal: false,
            step_to_event: false,
        },
        Event {
            g: Box::new(|m: &M, _, y| m.theta_rate(y)),
            direction: Direction::Falling,
            terminal: false,
            step_to_event: false,
        },
        {
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
        },
    ];
    if m.plane().is_exact() {
        match m.plane().mode {
            Mode::Sliding => ev.push(Event {
                g: Box::new(|m: &M, _, y| {
                    let v = m.slip_of(y);
                    let r = m.plane().slip_ref.get();
                    v[0] * r[0] + v[1] * r[1]
                }),
                direction: Direction::Falling,
                terminal: true,
                step_to_event: false,
            }),
            Mode::Rolling => ev.push(Event {
                g: Box::new(|m: &M, _, y| m.stick_margin(y).unwrap_or(f64::NAN)),
                direction: Direction::Falling,
                terminal: true,
                step_to_event: false,
            }),
        }
    }
    ev
}

fn unit(v: [f64; 2]) -> [f64; 2] {
    let n = v[0].hypot(v[1]);
    if n > 0.0 {
        [v[0] / n, v[1] / n]
    } else {
        [0.0, 0.0]
    }
}

/// Running diagnostics of a run (scaled units), updated at every accepted
/// step, sample and event by the drivers of every model.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Track {
    j0: f64,
    j_dev_max: f64,
    omega_abs_max: f64,
    e0: f64,
    e_abs_max: f64,
    balance_max: f64,
    theta_max: f64,
}

impl Track {
    /// Start from θ, ω, J and the energy E (if it could be evaluated) at t = 0.
    pub(crate) fn new(theta: f64, omega: f64, j: f64, energy: Option<f64>) -> Self {
        let e0 = energy.unwrap_or(0.0);
        Track {
            j0: j,
            j_dev_max: 0.0,
            omega_abs_max: omega.abs(),
            e0,
            e_abs_max: e0.abs(),
            balance_max: 0.0,
            theta_max: theta,
        }
    }

    /// The largest energy-balance error so far relative to max |E| (NaN-safe:
    /// infinite if the balance is not finite).
    pub(crate) fn balance_rel(&self) -> f64 {
        let r = if self.e_abs_max > 0.0 {
            self.balance_max / self.e_abs_max
        } else {
            self.balance_max
        };
        if r.is_nan() { f64::INFINITY } else { r }
    }

    /// Take the maxima of `other` (a track of the same run) too.
    pub(crate) fn merge(&mut self, other: &Track) {
        self.j_dev_max = self.j_dev_max.max(other.j_dev_max);
        self.omega_abs_max = self.omega_abs_max.max(other.omega_abs_max);
        self.e_abs_max = self.e_abs_max.max(other.e_abs_max);
        self.balance_max = self.balance_max.max(other.balance_max);
        self.theta_max = self.theta_max.max(other.theta_max);
    }

    /// Record a state: θ, ω, J, the energy E (if it could be evaluated) and
    /// the work done so far `W_f + W_a`.
    pub(crate) fn record(
        &mut self,
        theta: f64,
        omega: f64,
        j: f64,
        energy: Option<f64>,
        work: f64,
    ) {
        self.theta_max = self.theta_max.max(theta);
        self.omega_abs_max = self.omega_abs_max.max(omega.abs());
        self.j_dev_max = self.j_dev_max.max((j - self.j0).abs());
        if let Some(en) = energy {
            self.e_abs_max = self.e_abs_max.max(en.abs());
            self.balance_max = self.balance_max.max((en - self.e0 - work).abs());
        }
    }
}

/// What a driver knows at the end of a run, besides its [`Track`].
pub(crate) struct RunEnd<'a> {
    /// Time reached (scaled).
    pub t: f64,
    /// Time unit \[s\].
    pub time_unit: f64,
    /// C/(m R²): the J drift is relative to C max|ω| R.
    pub axial: f64,
    /// The final output row and θ there.
    pub last: &'a Sample,
    /// All output rows.
    pub samples: &'a [Sample],
    /// First time θ > π/2 \[s\].
    pub first_above: Option<f64>,
    /// First time N < 0 \[s\] and fraction of the time with N < 0.
    pub contact: (Option<f64>, f64),
    /// Time spent rolling (scaled).
    pub rolling_time: f64,
    /// Work counters.
    pub stats: integrate::Stats,
    /// The run-time failure, if any.
    pub error: Option<&'a Error>,
}

/// The run's [`Summary`] from its [`Track`] and its end.
pub(crate) fn summarize(track: &Track, end: RunEnd<'_>) -> Summary {
    let ratio = |num: f64, den: f64| if den > 0.0 { num / den } else { num };
    let t = end.t;
    Summary {
        t_end: t * end.time_unit,
        theta_final: end.last.theta,
        theta_max: track.theta_max,
        omega_final: end.last.spin,
        precession_final: end.last.precession,
        jellett_initial: end.samples.first().map(|s| s.jellett).unwrap_or(f64::NAN),
        jellett_max_rel_drift: ratio(track.j_dev_max, end.axial * track.omega_abs_max),
        energy_initial: end.samples.first().map(|s| s.energy).unwrap_or(f64::NAN),
        energy_final: end.last.energy,
        energy_balance_max_rel_error: ratio(track.balance_max, track.e_abs_max),
        first_time_theta_above_half_pi: end.first_above,
        contact_lost_at: end.contact.0,
        negative_normal_fraction: end.contact.1,
        rolling_fraction: if t > 0.0 { end.rolling_time / t } else { 0.0 },
        steps: end.stats.steps,
        rejected_steps: end.stats.rejected,
        rhs_evaluations: end.stats.rhs_evals,
        status: match end.error {
            None => "ok".into(),
            Some(e) => e.to_string(),
        },
    }
}

/// What the contact driver ([`run_contact`]) needs from a model whose
/// sphere stays on the plane: the reduced Euler-angle model ([`Reduced`])
/// and its vector form ([`Vector`]). Both share the friction laws, the
/// contact modes and the stick/slip logic; they differ in their state.
pub(crate) trait ContactModel<const D: usize>: OdeSystem<D, Error = ModelError> {
    /// The scaled model of a scenario.
    fn build(sc: &Scenario) -> Self;
    /// Unit system.
    fn scales(&self) -> Scales;
    /// Scaled state from the SI initial values.
    fn initial_state(&self, i: &Initial) -> [f64; D];
    /// The friction and contact rules and the sliding/rolling state.
    fn plane(&self) -> &OnPlane;
    /// The same, to switch modes and set the slip hint.
    fn plane_mut(&mut self) -> &mut OnPlane;
    /// Latch the applied force in effect at scaled time `t`.
    fn latch_force(&mut self, t: f64) {
        let scales = self.scales();
        self.plane_mut().latch_force(t, &scales);
    }
    /// Horizontal slip velocity at a state (scaled; the model's own frame).
    fn slip_of(&self, y: &[f64; D]) -> [f64; 2];
    /// The state with its velocity replaced by the rolling (zero-slip) one.
    fn to_rolling(&self, y: &[f64; D]) -> [f64; D];
    /// Normal force and friction (scaled, the model's frame) at a state in
    /// the current mode.
    fn contact_forces(&self, y: &[f64; D]) -> Result<(f64, [f64; 2]), ModelError>;
    /// Stick margin `μ|N| − |F_f|` (scaled force) while rolling.
    fn stick_margin(&self, y: &[f64; D]) -> Option<f64> {
        self.contact_forces(y)
            .ok()
            .map(|(n, f)| self.plane().stick_margin(n, f))
    }
    /// Nutation angle θ \[rad\].
    fn theta(&self, y: &[f64; D]) -> f64;
    /// A function with the sign and the zero of θ − π/2 (the inversion
    /// event).
    fn above_half_pi(&self, y: &[f64; D]) -> f64 {
        self.theta(y) - std::f64::consts::FRAC_PI_2
    }
    /// A function with the sign of θ̇ that is zero where θ̇ is (θ maxima).
    fn theta_rate(&self, y: &[f64; D]) -> f64;
    /// Spin ω = n·k (scaled).
    fn spin(&self, y: &[f64; D]) -> f64;
    /// Jellett's J (scaled).
    fn jellett_scaled(&self, y: &[f64; D]) -> f64;
    /// Total energy (scaled), if the state can be evaluated.
    fn energy_scaled(&self, y: &[f64; D]) -> Option<f64>;
    /// Work done so far by friction and the applied force (scaled).
    fn work_scaled(&self, y: &[f64; D]) -> f64;
    /// C/(m R²).
    fn axial(&self) -> f64;
    /// `β` of DOP853's stabilised step-size control for this model
    /// ([`Stepper::Dop853`]); 0 (pure I control, `dop853.f`'s default)
    /// unless the model says otherwise.
    fn dop853_beta(&self) -> f64 {
        0.0
    }
    /// Whether DOP853 caps the step at its stability limit for this model
    /// ([`Stepper::Dop853`]'s `stability_cap`); `false` (`dop853.f`'s
    /// step-size control) unless the model says otherwise.
    fn dop853_stability_cap(&self) -> bool {
        false
    }
    /// The output row at scaled time `t`.
    fn sample(&self, t: f64, y: &[f64; D]) -> Sample;
    /// The state in SI units, for error messages.
    fn describe_state(&self, y: &[f64]) -> String;
}

impl ContactModel<DIM> for Reduced {
    fn build(sc: &Scenario) -> Self {
        Reduced::new(sc)
    }
    fn scales(&self) -> Scales {
        self.scales
    }
    fn initial_state(&self, i: &Initial) -> [f64; DIM] {
        self.scale_state(i)
    }
    fn plane(&self) -> &OnPlane {
        &self.plane
    }
    fn plane_mut(&mut self) -> &mut OnPlane {
        &mut self.plane
    }
    fn slip_of(&self, y: &[f64; DIM]) -> [f64; 2] {
        Reduced::slip_of(self, y)
    }
    fn to_rolling(&self, y: &[f64; DIM]) -> [f64; DIM] {
        let mut yr = *y;
        let u = self.rolling_velocity(y);
        yr[UX] = u[0];
        yr[UY] = u[1];
        yr
    }
    fn contact_forces(&self, y: &[f64; DIM]) -> Result<(f64, [f64; 2]), ModelError> {
        self.eval(y).map(|e| (e.normal, e.friction))
    }
    fn theta(&self, y: &[f64; DIM]) -> f64 {
        y[TH]
    }
    fn theta_rate(&self, y: &[f64; DIM]) -> f64 {
        y[THD]
    }
    fn spin(&self, y: &[f64; DIM]) -> f64 {
        y[W]
    }
    fn jellett_scaled(&self, y: &[f64; DIM]) -> f64 {
        Reduced::jellett_scaled(self, y)
    }
    fn energy_scaled(&self, y: &[f64; DIM]) -> Option<f64> {
        self.eval(y)
            .ok()
            .map(|e| Reduced::energy_scaled(self, y, &e))
    }
    fn work_scaled(&self, y: &[f64; DIM]) -> f64 {
        y[WF] + y[WA]
    }
    fn axial(&self) -> f64 {
        self.ic()
    }
    fn sample(&self, t: f64, y: &[f64; DIM]) -> Sample {
        let m = self;
        let sc = m.scales;
        let (tu, vu) = (sc.time, sc.velocity());
        let e = m.eval(y).ok();
        let (u, normal, slip) = match &e {
            Some(e) => (e.u, e.normal, e.slip),
            None => ([y[UX], y[UY], f64::NAN], f64::NAN, m.slip_of(y)),
        };
        let u_si = [u[0] * vu, u[1] * vu, u[2] * vu];
        let (theta, thd, om, w) = (y[TH], y[THD] / tu, y[OM] / tu, y[W] / tu);
        let h = m.applied();
        Sample {
            t: t * tu,
            theta,
            theta_dot: thd,
            precession: om,
            spin: w,
            ux: u_si[0],
            uy: u_si[1],
            uz: u_si[2],
            normal: normal * sc.force(),
            slip: slip[0].hypot(slip[1]) * vu,
            jellett: observe::jellett(&m.top, theta, om, w),
            energy: observe::energy(&m.top, m.gravity_si, theta, thd, om, w, u_si),
            work_friction: y[WF] * sc.energy(),
            work_applied: y[WA] * sc.energy(),
            hx: h[0] * sc.force(),
            hy: h[1] * sc.force(),
            rolling: (m.plane.mode == Mode::Rolling) as u8,
        }
    }
    fn describe_state(&self, y: &[f64]) -> String {
        let tu = self.scales.time;
        let vu = self.scales.velocity();
        format!(
            "state: theta = {}, theta_dot = {:e} rad/s, Omega = {:e} rad/s, omega = {:e} rad/s, ux = {:e} m/s, uy = {:e} m/s",
            y[TH],
            y[THD] / tu,
            y[OM] / tu,
            y[W] / tu,
            y[UX] * vu,
            y[UY] * vu
        )
    }
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

/// The sign history of the normal force N: its sign at t = 0 and the
/// (scaled) times it crossed zero, from events or from jumps at force
/// switches. Shared by the drivers of every model. Constant memory: the
/// first crossing, the number of crossings and the time with N < 0 so far.
#[derive(Debug, Clone, PartialEq)]
pub struct NormalLog {
    negative_at_start: bool,
    first: Option<f64>,
    count: u64,
    last: f64,
    neg_time: f64,
}

impl NormalLog {
    /// Start with N(0) = `n_initial` (NaN counts as non-negative).
    pub fn new(n_initial: f64) -> Self {
        NormalLog {
            negative_at_start: n_initial < 0.0,
            first: None,
            count: 0,
            last: 0.0,
            neg_time: 0.0,
        }
    }

    /// Record a crossing at scaled time `t`; returns the event kind,
    /// "contact_lost" (N now < 0) or "contact_regained".
    pub fn cross(&mut self, t: f64) -> &'static str {
        if self.negative_now() {
            self.neg_time += t - self.last;
        }
        self.last = t;
        self.first.get_or_insert(t);
        self.count += 1;
        if self.negative_now() {
            "contact_lost"
        } else {
            "contact_regained"
        }
    }

    /// Whether N is negative after the crossings recorded so far.
    pub fn negative_now(&self) -> bool {
        self.negative_at_start != (self.count % 2 == 1)
    }

    /// First time N < 0 (scaled), if ever.
    pub fn first_negative(&self) -> Option<f64> {
        if self.negative_at_start {
            Some(0.0)
        } else {
            self.first
        }
    }

    /// Fraction of `[0, t_final]` with N < 0 (`t_final` not before the
    /// last crossing).
    pub fn negative_fraction(&self, t_final: f64) -> f64 {
        if t_final <= 0.0 {
            return 0.0;
        }
        let mut neg_time = self.neg_time;
        if self.negative_now() {
            neg_time += t_final - self.last;
        }
        neg_time / t_final
    }
}

/// What every model's driver needs from a scenario, in scaled time: the
/// end time, the sample times, the force-switch times inside the run, and
/// the integrator options.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSetup {
    /// End time (scaled).
    pub t_end: f64,
    /// Evenly spaced sample times on `[0, t_end]`, the last exactly `t_end`.
    pub sample_times: Vec<f64>,
    /// Switch times of the force schedule strictly inside `(0, t_end)`.
    pub tstops: Vec<f64>,
    /// Integrator options from `[solver]`.
    pub opts: Options,
}

impl RunSetup {
    /// The setup of `sc` with time unit `time_unit` \[s\].
    pub fn new(sc: &Scenario, time_unit: f64) -> Self {
        let t_end = sc.solver.t_end / time_unit;
        let ns = sc.solver.samples;
        let sample_times = (0..ns)
            .map(|i| {
                if i + 1 == ns {
                    t_end
                } else {
                    t_end * i as f64 / (ns - 1) as f64
                }
            })
            .collect();
        let tstops = sc
            .forcing
            .switch_times()
            .into_iter()
            .map(|t| t / time_unit)
            .filter(|&t| t > 0.0 && t < t_end)
            .collect();
        let opts = Options {
            stepper: match sc.solver.method {
                Method::Adaptive => Stepper::Dop853 {
                    rtol: sc.solver.rtol,
                    atol: sc.solver.rtol,
                    beta: 0.0,
                    stability_cap: false,
                },
                Method::Stiff => Stepper::Rosenbrock {
                    rtol: sc.solver.rtol,
                    atol: sc.solver.rtol,
                },
                Method::Rk4 => Stepper::Rk4 {
                    h: t_end / sc.solver.steps as f64,
                },
            },
            max_steps: sc.solver.step_limit(),
            h0: None,
            // Samples and events are read from the dense output, whose error
            // the step-size control does not see: with steps much longer than
            // the time scale of the motion (a tiny nutation on a steady
            // precession lets DOP853 take steps of a whole period) the
            // interpolant is far less accurate than the step ends. No step
            // longer than the sample spacing keeps the dense output at the
            // step-error level.
            h_max: Some(t_end / (ns - 1) as f64),
        };
        RunSetup {
            t_end,
            sample_times,
            tstops,
            opts,
        }
    }
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
        events_out.push(ts * tu, "force_switch");
    }
    if m.plane().is_exact() {
        let v = m.slip_of(&y);
        if v[0].hypot(v[1]) == 0.0 {
            let (yn, stuck) = settle_at_zero_slip(&mut m, &y);
            y = yn;
            events_out.push(0.0, if stuck { "stick" } else { "slip" });
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
        let events = events_for(&m);
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
        let mut on_event = |s: &M, f: &integrate::Fired<D>| match f.index {
            EV_HALF_PI if first_above.is_none() => {
                first_above = Some(f.t * tu);
                events_out.push(f.t * tu, "theta_above_half_pi");
            }
            EV_THETA_MAX => visit(&mut event_track, s, &f.y),
            EV_NORMAL => {
                let kind = normal_log.cross(f.t);
                events_out.push(f.t * tu, kind);
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
                                    events_out.push(t * tu, "slip");
                                }
                            }
                        }
                    }
                    StopReason::Terminal(EV_NORMAL) if m.plane().latches_normal() => {
                        // N = 0 (bilateral): continue on the other branch.
                        let b = m.plane().normal_branch;
                        m.plane_mut().normal_branch = b.map(|pos| !pos);
                    }
                    StopReason::Terminal(EV_NORMAL) => {
                        error = Some(Error::runtime(
                            t * tu,
                            format!(
                                "lift-off: the normal force N fell to zero (contact = \"unilateral\"); the reduced and vector models keep the sphere on the plane and cannot follow a flight, use model = \"rigid\"; {}",
                                m.describe_state(&y)
                            ),
                        ));
                        break;
                    }
                    StopReason::Terminal(EV_SWITCH) => {
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
                                    events_out.push(t * tu, "stick");
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
                                events_out.push(t * tu, "slip");
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

#[cfg(test)]
mod tests {
    use super::{EventList, NormalLog};
    use crate::limits::MAX_EVENTS;

    /// At most MAX_EVENTS records, then one marker; memory stays bounded
    /// however many events a run has.
    #[test]
    fn event_list_is_capped() {
        let mut l = EventList::default();
        for k in 0..MAX_EVENTS + 1000 {
            l.push(k as f64, "contact_lost");
        }
        assert_eq!(l.dropped, 1000);
        let v = l.into_sorted();
        assert_eq!(v.len(), MAX_EVENTS + 1);
        assert_eq!(v[MAX_EVENTS].kind, "event_limit_reached");
        assert_eq!(v[MAX_EVENTS].t, MAX_EVENTS as f64);
        assert_eq!(v[MAX_EVENTS - 1].kind, "contact_lost");
    }

    #[test]
    fn normal_log_fraction_and_first_time() {
        let mut l = NormalLog::new(1.0);
        assert_eq!(l.first_negative(), None);
        assert_eq!(l.cross(2.0), "contact_lost");
        assert_eq!(l.cross(3.0), "contact_regained");
        assert_eq!(l.cross(8.0), "contact_lost");
        assert_eq!(l.first_negative(), Some(2.0));
        // Negative on [2, 3) and [8, 10]: 3 of 10.
        assert_eq!(l.negative_fraction(10.0), 0.3);
        let mut l = NormalLog::new(-1.0);
        assert_eq!(l.first_negative(), Some(0.0));
        assert_eq!(l.cross(4.0), "contact_regained");
        assert_eq!(l.negative_fraction(8.0), 0.5);
    }
}
