//! Equations of motion, one file per formulation.

pub mod contact;
pub(crate) mod on_plane;
pub mod reduced;
pub mod rigid;
pub(crate) mod thermostat;
pub(crate) use crate::numeric::vec3;
pub mod vector;

pub use contact::ContactState;

use crate::integrate::Event;
use crate::physics::units::Scales;
use crate::sim::events::Watch;
use crate::sim::record::{RunLog, Track};
use crate::{Error, Initial, Sample, Scenario, integrate::OdeSystem};

/// Sliding or rolling (exact Coulomb law), sliding or stuck
/// (Coulomb–Contensou friction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Friction from the friction law.
    Sliding,
    /// Slip held at zero; friction is the constraint force. Under
    /// Coulomb–Contensou friction the stick: the spin about the vertical is
    /// held at zero too, and the drilling torque is a constraint torque
    /// (docs/physics.md#contensou).
    Rolling,
}

/// Why the right-hand side cannot be evaluated.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelError {
    /// |sin θ| < [`reduced::SIN_GUARD`], or θ outside `(0, π)` (a step passed a
    /// pole): the Ω equation divides by sin θ.
    Singular {
        /// θ \[rad\].
        theta: f64,
    },
    /// The θ̈–N system has no or two consistent solutions.
    Painleve {
        /// θ \[rad\].
        theta: f64,
        /// Number of consistent solutions found (0 or 2).
        solutions: usize,
    },
    /// The sliding-only Coulomb law reversed the slip direction at step
    /// after step: the slip sits at zero, where that law has no solution.
    Chattering {
        /// Slip reversals counted.
        reversals: u32,
    },
}

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelError::Singular { theta } => write!(
                f,
                "theta = {} rad reached the pole of the Euler angles (|sin theta| < {:e}, or theta outside (0, pi)): the reduced model divides by sin theta there; use model = \"vector\" (the default) or \"rigid\"",
                crate::human::s4(*theta),
                reduced::SIN_GUARD
            ),
            ModelError::Chattering { reversals } => write!(
                f,
                "the sliding-only Coulomb law chatters: the slip reversed direction at {reversals} steps (it sits at zero slip, where mu N v/|v| is undefined); use friction_law = \"coulomb\" (exact stick/slip) or \"regularized\""
            ),
            ModelError::Painleve { theta, solutions } => write!(
                f,
                "Painleve paradox at theta = {} rad: the theta_ddot-N system with friction has {solutions} consistent solutions (m a h mu sin(theta)/A too large); no unique motion exists",
                crate::human::s4(*theta)
            ),
        }
    }
}

/// What an event handler of a [`Model`] tells the driver to do next.
#[derive(Debug)]
pub(crate) enum Flow {
    /// Integrate on from the (possibly changed) state.
    Continue,
    /// Stop the run with this error (the samples so far are kept).
    Stop(Error),
    /// Stop the run without an error.
    End,
}

/// What the one driver ([`crate::simulate`]) needs from a model: the
/// right-hand side ([`OdeSystem`]), the events the model needs in its
/// current discrete state and what each does, the observables of a state,
/// and its step-control hints. The reduced and vector models implement it
/// through [`ContactModel`] (their shared on-plane contact logic,
/// `on_plane.rs`), the rigid model directly. The driver owns the loop, the
/// samples, the error mapping, the run's record ([`RunLog`]) and the
/// summary.
pub(crate) trait Model<const D: usize>: OdeSystem<D> + Sized {
    /// Seconds per scaled time unit.
    fn time_unit(&self) -> f64;
    /// C/(m R²).
    fn axial_ratio(&self) -> f64;
    /// Right-hand-side evaluations so far.
    fn evaluations(&self) -> u64;
    /// `(β, stability_cap)` of DOP853's step-size control for this model
    /// ([`crate::integrate::Stepper::Dop853`]).
    fn step_hints(&self) -> (f64, bool) {
        (0.0, false)
    }
    /// The scaled initial state of `sc` with the discrete state at `t = 0`
    /// decided (stick or slip at zero slip, contact or flight), recording
    /// what happened in `log`; returns the state and N(0) (scaled; NaN if
    /// it cannot be evaluated).
    fn start(&mut self, sc: &Scenario, log: &mut RunLog) -> ([f64; D], f64);
    /// Latch the applied force in effect at scaled time `t`.
    fn latch_force(&mut self, t: f64);
    /// At the start of each integration segment: latch the normal-force
    /// branch where the model latches it (bilateral contact, sliding),
    /// clear it elsewhere.
    fn latch_branch(&mut self, y: &[f64; D]);
    /// The events the model needs in its current discrete state, each with
    /// what it watches for, pushed onto `ev` (the driver's list, kept
    /// between segments: no allocation per segment).
    fn events(&self, ev: &mut Vec<(Watch, Event<Self, D>)>);
    /// After every accepted step: update the slip reference and the
    /// chatter detection.
    fn accepted(&self, y: &[f64; D]);
    /// θ \[rad\], spin, Jellett's J, the energy (if it can be evaluated)
    /// and the work done by friction and the applied force (scaled): what
    /// the run's [`Track`] follows.
    fn track_point(&self, y: &[f64; D]) -> (f64, f64, f64, Option<f64>, f64);
    /// Record an accepted step's state in the run's `track`: what
    /// [`Model::track_point`] gives, the same maxima bit for bit (a model
    /// may skip θ where [`Model::cos_theta`] shows it below the maximum).
    fn record_step(&self, track: &mut Track, y: &[f64; D]) {
        let (theta, spin, j, e, w) = self.track_point(y);
        track.record(theta, spin, j, e, w);
    }
    /// θ \[rad\] and the spin of [`Model::track_point`] alone, the same
    /// bits (what an ensemble's run records at every step).
    fn track_angles(&self, y: &[f64; D]) -> (f64, f64) {
        let (theta, spin, ..) = self.track_point(y);
        (theta, spin)
    }
    /// `cos θ` of a state to a few ulps, without θ itself: where it is
    /// above the cosine of the run's largest θ so far (with a margin), θ
    /// cannot raise that maximum and its `atan2` is skipped
    /// ([`crate::sim::record::Track::record_angles_guarded`]). NaN (the
    /// default): θ is always computed.
    fn cos_theta(&self, _y: &[f64; D]) -> f64 {
        f64::NAN
    }
    /// The spin of [`Model::track_angles`] alone (where θ is skipped).
    fn track_spin(&self, y: &[f64; D]) -> f64 {
        self.track_angles(y).1
    }
    /// The plane's reaction N \[N\] at a state, as the output row's `N`
    /// column has it (`None` where it cannot be evaluated; 0 in flight).
    /// The driver averages it over each output interval of a stochastic
    /// run ([`crate::Summary::normal_intervals`]).
    fn normal_force(&self, y: &[f64; D]) -> Option<f64>;
    /// True where the top can leave the plane (rigid model, unilateral
    /// contact): the summary's contact entries then count flights, not
    /// zero crossings of N.
    fn flies(&self) -> bool {
        false
    }
    /// True when the scenario has adhesion: the summary then reports
    /// `pull_off_margin_min`.
    fn adhesive(&self) -> bool {
        false
    }
    /// True when the top has a stem (docs/physics.md#stem): the summary then
    /// reports `first_stem_contact_at` and `stem_contact_fraction`.
    fn has_stem(&self) -> bool {
        false
    }
    /// A force switch at `t` (the new force is not latched yet): latch it
    /// and re-decide what depends on it.
    fn on_force_switch(&mut self, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow;
    /// A terminal event `what` at `t` with state `y`.
    fn on_terminal(&mut self, what: Watch, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow;
    /// Why the right-hand side failed: its kind and the error message.
    fn explain(&self, sc: &Scenario, err: Self::Error) -> (crate::Failure, String);
    /// True if the output rows carry the pose (position and attitude);
    /// false for the vector model's motion alone (`Vector<CONTROLLED>`),
    /// whose pose columns are NaN and skipped by the finiteness check
    /// ([`Sample::first_non_finite_of`]).
    const HAS_POSE: bool = true;
    /// The output row at scaled time `t`.
    fn row(&self, t: f64, y: &[f64; D]) -> Sample;
    /// The state in SI units, for error messages.
    fn describe(&self, y: &[f64]) -> String;
    /// `|k|²` of a state that carries the symmetry axis `k` as a vector
    /// (the vector and rigid models: 1 up to the integration error), for
    /// the driver's blow-up check ([`crate::sim::runaway::axis_blown`]);
    /// `None` where the state has no such vector (the Euler angles).
    fn axis_norm_sq(&self, _y: &[f64]) -> Option<f64> {
        None
    }
}

/// What a model whose sphere stays on the plane provides: the reduced
/// Euler-angle model ([`reduced::Reduced`]) and its vector form
/// ([`vector::Vector`]). Both hold a [`ContactState`] (friction laws,
/// contact modes, stick/slip rules; the rigid model holds one too) and share
/// their events and handlers (their [`Model`] implementation, written once
/// in `on_plane.rs`); they differ in their state.
pub(crate) trait ContactModel<const D: usize>: OdeSystem<D, Error = ModelError> {
    /// The scaled model of a scenario.
    fn build(sc: &Scenario) -> Self;
    /// Unit system.
    fn scales(&self) -> Scales;
    /// Scaled state from the SI initial values.
    fn initial_state(&self, i: &Initial) -> [f64; D];
    /// The contact state: friction and contact rules, sliding/rolling.
    fn plane(&self) -> &ContactState;
    /// The same, to switch modes and set the slip hint.
    fn plane_mut(&mut self) -> &mut ContactState;
    /// Latch the applied force in effect at scaled time `t`.
    fn latch_force(&mut self, t: f64) {
        let scales = self.scales();
        self.plane_mut().latch_force(t, &scales);
    }
    /// Horizontal slip velocity at a state (scaled; the model's own frame).
    fn slip_of(&self, y: &[f64; D]) -> [f64; 2];
    /// The spin about the contact normal, `n_Z` (scaled): the drilling
    /// rate of Coulomb–Contensou friction (docs/physics.md#contensou).
    fn spin_z(&self, y: &[f64; D]) -> f64;
    /// The state with its velocity replaced by the rolling (zero-slip) one.
    fn to_rolling(&self, y: &[f64; D]) -> [f64; D];
    /// Normal force and friction (scaled, the model's frame) at a state in
    /// the current mode.
    fn contact_forces(&self, y: &[f64; D]) -> Result<(f64, [f64; 2]), ModelError>;
    /// Normal force, friction and the drilling torque about the vertical
    /// (scaled, the model's frame) at a state in the current mode: the
    /// torque is the Coulomb–Contensou law's while sliding, the stick's
    /// constraint torque in its stick (docs/physics.md#contensou), zero for the
    /// other laws.
    fn contact_wrench(&self, y: &[f64; D]) -> Result<(f64, [f64; 2], f64), ModelError>;
    /// The state with its velocities changed by the impulse at the contact
    /// (force and torque about the vertical) that brings the slip and the
    /// spin about the vertical to zero: the Coulomb–Contensou stick
    /// (docs/physics.md#contensou; [`crate::physics::body::stick_solve`]), the impulse's work
    /// (the kinetic energy's change, `<= 0`) added to `W_f`.
    fn to_stick(&self, y: &[f64; D]) -> [f64; D];
    /// Stick margin while rolling or stuck (scaled force):
    /// [`ContactState::stick_margin_wrench`] of the needed wrench.
    fn stick_margin(&self, y: &[f64; D]) -> Option<f64> {
        self.contact_wrench(y)
            .ok()
            .map(|(n, f, m)| self.plane().stick_margin_wrench(n, f, m))
    }
    /// Nutation angle θ \[rad\].
    fn theta(&self, y: &[f64; D]) -> f64;
    /// `cos θ` to a few ulps without θ ([`Model::cos_theta`]); NaN where
    /// the model has none.
    fn cos_theta(&self, _y: &[f64; D]) -> f64 {
        f64::NAN
    }
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
    /// See [`Model::HAS_POSE`].
    const HAS_POSE: bool = true;
    /// The output row at scaled time `t`.
    fn sample(&self, t: f64, y: &[f64; D]) -> Sample;
    /// The state in SI units, for error messages.
    fn describe_state(&self, y: &[f64]) -> String;
    /// See [`Model::axis_norm_sq`].
    fn axis_norm_sq(&self, _y: &[f64]) -> Option<f64> {
        None
    }
}

#[cfg(test)]
mod quadrature_tests {
    use crate::Scenario;
    use crate::integrate::OdeSystem;

    /// `quadrature_jacobian` against central differences of `rhs` over the
    /// quadrature columns, and no controlled derivative reads a quadrature
    /// (their columns are zero in the controlled rows): the contract of
    /// `OdeSystem::CONTROLLED`. Step 1e-6 on O(1) components: truncation
    /// O(1e-12), cancellation O(1e-10); bound 1e-8.
    fn check<S: OdeSystem<N>, const N: usize>(sys: &mut S, y: [f64; N]) {
        let c = S::CONTROLLED;
        assert!(c < N);
        let mut f = [0.0; N];
        sys.rhs(0.0, &y, &mut f).ok().unwrap();
        let mut jac = [[0.0; N]; N];
        sys.quadrature_jacobian(0.0, &y, &f, &mut jac);
        for j in c..N {
            let h = 1e-6;
            let (mut yp, mut ym) = (y, y);
            yp[j] += h;
            ym[j] -= h;
            let (mut fp, mut fm) = ([0.0; N], [0.0; N]);
            sys.rhs(0.0, &yp, &mut fp).ok().unwrap();
            sys.rhs(0.0, &ym, &mut fm).ok().unwrap();
            for i in 0..N {
                let fd = (fp[i] - fm[i]) / (2.0 * h);
                if i < c {
                    assert_eq!(fp[i], fm[i], "controlled {i} reads quadrature {j}");
                } else {
                    assert!(
                        (fd - jac[i][j]).abs() <= 1e-8,
                        "d{i}/d{j}: {fd} vs {}",
                        jac[i][j]
                    );
                }
            }
        }
    }

    #[test]
    fn quadrature_jacobians_match_finite_differences() {
        let sc = Scenario::classical();
        let mut r = super::reduced::Reduced::new(&sc);
        let mut y = r.scale_state(&sc.initial);
        y[super::reduced::THD] = 0.3;
        y[super::reduced::OM] = 0.4;
        y[super::reduced::UX] = 0.2;
        y[super::reduced::UY] = -0.1;
        y[super::reduced::PHI] = 0.7;
        y[super::reduced::PSI] = -1.1;
        // (c_φ, s_φ) off the unit circle, as the integration leaves them.
        y[super::reduced::DIR] = 1.01 * 0.7f64.cos();
        y[super::reduced::DIR + 1] = 0.99 * 0.7f64.sin();
        check(&mut r, y);
        // Rolling: the position's derivative reads the constraint velocity.
        r.plane.mode = super::Mode::Rolling;
        check(&mut r, y);
        let mut v = super::vector::Vector::new(&sc);
        let mut y = v.scale_state(&sc.initial);
        y[super::vector::OMEGA + 1] = 0.4;
        y[super::vector::QUAT..super::vector::QUAT + 4].copy_from_slice(&[0.5, -0.5, 0.1, 0.7]);
        check(&mut v, y);
    }
}
