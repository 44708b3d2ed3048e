//! Equations of motion, one file per formulation.

pub(crate) mod on_plane;
pub mod reduced;
pub mod rigid;
pub(crate) mod vec3;
pub mod vector;

use std::cell::Cell;

use crate::integrate::Event;
use crate::physics::forces::{ContactPointForce, Forces};
use crate::physics::units::Scales;
use crate::sim::events::Watch;
use crate::sim::record::RunLog;
use crate::{
    ContactMode, Error, FrictionLaw, Initial, Sample, Scenario, contact::SlidingLaw,
    integrate::OdeSystem,
};

/// Sliding or rolling (exact Coulomb law only).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Friction from the friction law.
    Sliding,
    /// Slip held at zero; friction is the constraint force.
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
                "theta = {theta:e} rad reached the pole of the Euler angles (|sin theta| < {:e}, or theta outside (0, pi)): the reduced model divides by sin theta there; use model = \"vector\" (the default) or \"rigid\"",
                reduced::SIN_GUARD
            ),
            ModelError::Chattering { reversals } => write!(
                f,
                "the sliding-only Coulomb law chatters: the slip reversed direction at {reversals} steps (it sits at zero slip, where mu N v/|v| is undefined); use friction_law = \"coulomb\" (exact stick/slip) or \"regularized\""
            ),
            ModelError::Painleve { theta, solutions } => write!(
                f,
                "Painleve paradox at theta = {theta}: the theta_ddot-N system with friction has {solutions} consistent solutions (m a h mu sin(theta)/A too large); no unique motion exists"
            ),
        }
    }
}

/// What the two models that keep the sphere on the plane ([`reduced`] and
/// [`vector`]) hold besides their ODE state, and the friction and contact
/// rules they share: the friction law, the contact mode, the applied
/// force terms and their latched value, sliding or rolling, and the flags
/// the driver sets.
#[derive(Debug, Clone)]
pub struct OnPlane {
    /// Friction law, ε in scaled units.
    law: FrictionLaw,
    /// True for the exact stick/slip law.
    exact: bool,
    /// μ.
    mu: f64,
    contact: ContactMode,
    /// The applied force terms, and the contact-point force (h_x, h_y, h_z)
    /// in the precessing frame latched for the segment, scaled.
    forces: Forces,
    /// Sliding or rolling.
    pub mode: Mode,
    /// Unit direction used for μ v/|v| at exactly v = 0 (set when leaving
    /// rolling; zero for the sliding-only law, giving no friction at v = 0).
    pub slip_hint: [f64; 2],
    /// Reference slip direction for the slip-zero event (updated per step).
    pub slip_ref: Cell<[f64; 2]>,
    /// Latched branch of the bilateral normal-force closure while sliding:
    /// `Some(true)` solves `N D(+) = Q` and the friction sees `+N`,
    /// `Some(false)` solves `N D(−) = Q` and it sees `−N`, whatever the sign
    /// of `N`; `None` takes the self-consistent branch at every evaluation
    /// (`bilateral_normal`) and the friction sees `|N|`. The driver
    /// latches the consistent branch at the start of each segment and makes
    /// `N = 0` a terminal event where it flips it, so that no step straddles
    /// the kink of `μ|N|` (docs/physics.md §4). Falls back to the
    /// consistent rule unless both `D(±) > 0`, so Painlevé states are still
    /// detected.
    pub normal_branch: Option<bool>,
    /// Set by the driver when the sliding-only law chatters (see
    /// [`ModelError::Chattering`]); the next evaluation then fails.
    pub chattering: Cell<bool>,
    /// Slip reversals counted at accepted steps (sliding-only law).
    reversals: Cell<u32>,
    /// The slip at the last accepted step (chatter detection).
    last_slip: Cell<[f64; 2]>,
    /// Right-hand-side evaluations so far (all segments).
    pub evaluations: u64,
}

impl OnPlane {
    /// The rules of `sc` in the units `scales`, sliding, no force latched.
    pub fn new(sc: &Scenario, scales: &Scales) -> Self {
        let law = sc.surface.law.scaled(scales.velocity());
        OnPlane {
            exact: law == FrictionLaw::Coulomb,
            law,
            mu: sc.surface.friction,
            contact: sc.surface.contact,
            forces: Forces::of(sc),
            mode: Mode::Sliding,
            slip_hint: [0.0, 0.0],
            slip_ref: Cell::new([0.0, 0.0]),
            normal_branch: None,
            chattering: Cell::new(false),
            reversals: Cell::new(0),
            last_slip: Cell::new([0.0, 0.0]),
            evaluations: 0,
        }
    }

    /// Chatter detection of the sliding-only law, at every accepted step
    /// with the slip `v` there: a genuine motion reverses its slip only at
    /// isolated instants; after [`reduced::CHATTER_REVERSALS`] reversals
    /// the next evaluation fails with [`ModelError::Chattering`].
    pub(crate) fn count_reversal(&self, v: [f64; 2]) {
        let l = self.last_slip.get();
        if v[0] * l[0] + v[1] * l[1] < 0.0 {
            let r = self.reversals.get() + 1;
            self.reversals.set(r);
            if r >= reduced::CHATTER_REVERSALS {
                self.chattering.set(true);
            }
        }
        self.last_slip.set(v);
    }

    /// Latch the applied force in effect at scaled time `t`.
    pub fn latch_force(&mut self, t: f64, scales: &Scales) {
        self.forces.latch(t * scales.time, scales.force());
    }

    /// Latched applied force (h_x, h_y) in the precessing frame, scaled.
    #[inline(always)]
    pub fn applied(&self) -> [f64; 2] {
        self.forces.contact_point().h
    }

    /// The latched contact-point force (H and the vertical load h_z), scaled,
    /// with the adhesion's load `F_a` added to `h_z` (the sphere is always
    /// in contact here; docs/physics.md §18): the closure, the reaction `N_c`
    /// and the friction all see it through this one value.
    #[inline(always)]
    pub fn contact_point(&self) -> ContactPointForce {
        self.forces
            .contact_point()
            .with_load(self.forces.centre_vertical().in_contact())
    }

    /// True when the scenario has adhesion (`F_a > 0`).
    pub fn adhesive(&self) -> bool {
        self.forces.centre_vertical().force > 0.0
    }

    /// Contact mode.
    pub fn contact_mode(&self) -> ContactMode {
        self.contact
    }

    /// True for the exact stick/slip law.
    pub fn is_exact(&self) -> bool {
        self.exact
    }

    /// True where the driver latches the normal-force branch
    /// ([`OnPlane::normal_branch`]): bilateral contact, sliding.
    pub fn latches_normal(&self) -> bool {
        self.contact == ContactMode::Bilateral && self.mode == Mode::Sliding
    }

    /// True for the sliding-only Coulomb law, which can chatter.
    pub fn can_chatter(&self) -> bool {
        self.law == FrictionLaw::CoulombSliding
    }

    /// Friction coefficient μ.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// `ε` (scaled) of the regularised law `μ v/sqrt(|v|² + ε²)`, `None`
    /// for the other laws.
    #[inline(always)]
    pub(crate) fn regularized_eps(&self) -> Option<f64> {
        match self.law {
            FrictionLaw::Regularized { eps } => Some(eps),
            _ => None,
        }
    }

    /// The friction coefficient vector `f(v)` (`|f| <= μ`) while sliding:
    /// the law's [`SlidingLaw::coefficient`], and for the exact law the slip
    /// hint at exactly zero slip and the smooth continuation through zero.
    ///
    /// Exact law, sliding: the slip-zero event is located on the dense
    /// output of the step that crosses zero. Continuing the friction
    /// smoothly through the crossing (keep its direction, i.e. flip `v/|v|`
    /// once `v·d < 0`, `d` the approach direction `slip_ref`) keeps that
    /// step smooth, so the event time is as accurate as the step; the stages
    /// past zero are discarded at the event. Always inlined: it is on the
    /// right-hand sides' critical path (docs/performance.md, "The inner
    /// loop").
    #[inline(always)]
    pub(crate) fn coefficient(&self, v: [f64; 2]) -> [f64; 2] {
        let mu = self.mu;
        if !self.exact {
            return self.law.coefficient(mu, v);
        }
        if v[0] == 0.0 && v[1] == 0.0 {
            return [mu * self.slip_hint[0], mu * self.slip_hint[1]];
        }
        let f = self.law.coefficient(mu, v);
        let d = self.slip_ref.get();
        if v[0] * d[0] + v[1] * d[1] < 0.0 {
            [-f[0], -f[1]]
        } else {
            f
        }
    }

    /// The normal force `N` from the contact closure `N D(σ) = Q`, where
    /// `D(σ) = dp` for the friction that `N >= 0` gives and `dm` for `N < 0`
    /// (the friction sees `|N|`): `"paper"` contact takes `Q/dp` with its
    /// sign (no solution if `dp <= 0`); unilateral contact, and bilateral
    /// contact with no branch latched, take the one self-consistent branch
    /// ([`bilateral_normal`]); bilateral contact with a latched branch
    /// ([`OnPlane::normal_branch`]) takes that branch's quotient while both
    /// `dp` and `dm` are positive. The error is
    /// the Painlevé case at `theta()` \[rad\] (evaluated only then).
    #[inline(always)]
    pub(crate) fn normal(
        &self,
        q: f64,
        dp: f64,
        dm: f64,
        theta: impl Fn() -> f64,
    ) -> Result<f64, ModelError> {
        closure_normal(self.contact, self.normal_branch, q, dp, dm).map_err(|solutions| {
            ModelError::Painleve {
                theta: theta(),
                solutions,
            }
        })
    }

    /// The normal force the friction sees: `N` with its sign for the paper's
    /// contact, `σN` for bilateral contact with the branch `σ` latched
    /// ([`OnPlane::normal_branch`]), `|N|` otherwise.
    #[inline(always)]
    pub(crate) fn friction_normal(&self, normal: f64) -> f64 {
        friction_normal(self.contact, self.normal_branch, normal)
    }

    /// Count a right-hand-side evaluation; fails once the driver has
    /// flagged the sliding-only law as chattering.
    #[inline(always)]
    pub(crate) fn start_evaluation(&mut self) -> Result<(), ModelError> {
        self.evaluations += 1;
        if self.chattering.get() {
            return Err(ModelError::Chattering {
                reversals: reduced::CHATTER_REVERSALS,
            });
        }
        Ok(())
    }

    /// Stick margin `μ |N| − |F_f|` (scaled force) for a normal force and a
    /// friction force; rolling ends when it falls through zero.
    pub fn stick_margin(&self, normal: f64, friction: [f64; 2]) -> f64 {
        self.mu * normal.abs() - friction[0].hypot(friction[1])
    }
}

/// The normal force from the contact closure `N D(σ) = Q` (`dp = D(+)`,
/// `dm = D(−)`), written once for every model: `"paper"` contact takes
/// `Q/dp` with its sign (no solution if `dp <= 0`); unilateral contact, and
/// bilateral contact with no branch latched, take the one self-consistent
/// branch ([`bilateral_normal`]); bilateral contact with a latched branch
/// (`branch`, see [`OnPlane::normal_branch`]) takes that branch's quotient
/// while both `dp` and `dm` are positive and finite. `Err` is the number of
/// consistent solutions (0 or 2: a Painlevé case).
#[inline(always)]
pub(crate) fn closure_normal(
    contact: ContactMode,
    branch: Option<bool>,
    q: f64,
    dp: f64,
    dm: f64,
) -> Result<f64, usize> {
    match contact {
        ContactMode::Paper if dp <= 0.0 => Err(0),
        ContactMode::Paper => Ok(q / dp),
        ContactMode::Bilateral => match branch {
            // Both denominators positive: no Painlevé case, both quotients
            // have the sign of q; continue the latched one.
            Some(pos) if dp > 0.0 && dm > 0.0 && dp < f64::INFINITY && dm < f64::INFINITY => {
                Ok(q / if pos { dp } else { dm })
            }
            _ => bilateral_normal(q, dp, dm),
        },
        ContactMode::Unilateral => bilateral_normal(q, dp, dm),
    }
}

/// The normal force the friction sees, for every model: `N` with its sign
/// for the paper's contact, `σN` for bilateral contact with the branch `σ`
/// latched, `|N|` otherwise.
#[inline(always)]
pub(crate) fn friction_normal(contact: ContactMode, branch: Option<bool>, normal: f64) -> f64 {
    match (contact, branch) {
        (ContactMode::Paper, _) => normal,
        // Latched: the branch's sign, continued through N = 0.
        (ContactMode::Bilateral, Some(true)) => normal,
        (ContactMode::Bilateral, Some(false)) => -normal,
        _ => normal.abs(),
    }
}

/// N from `N d_σ = q` with `d_σ = d_+` for N >= 0 and `d_−` for N < 0
/// (σ the sign of N the friction sees, bilateral and unilateral contact):
/// the consistent solution, or `Err(number of consistent solutions)`
/// (0 or 2, a Painlevé paradox).
///
/// A solution `q/d_+` is consistent when `d_+ != 0` and it is `>= 0`
/// (−0 included), `q/d_−` when `d_− != 0` and it is `< 0`; a NaN is
/// consistent with neither. In the common case (`0 < d_± < 1e100`,
/// `|q| > 1e-200`) neither quotient can be NaN or underflow to ±0 (an
/// overflow to ±∞ keeps the sign), so both have the sign of `q`, exactly
/// one is consistent and one division gives it; everywhere else (NaN, zero,
/// tiny, huge or negative inputs) both quotients are formed and tested as
/// written above. The result is the same, bit for bit, either way.
#[inline(always)]
pub(crate) fn bilateral_normal(q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
    // Comparisons are false for NaN, so NaNs take the general path.
    if dp > 0.0 && dm > 0.0 && dp < 1e100 && dm < 1e100 && q.abs() > 1e-200 {
        return Ok(if q > 0.0 { q / dp } else { q / dm });
    }
    let np = q / dp;
    let nm = q / dm;
    let okp = dp != 0.0 && np >= 0.0;
    let okm = dm != 0.0 && nm < 0.0;
    match (okp, okm) {
        (true, false) => Ok(np),
        (false, true) => Ok(nm),
        (true, true) => Err(2),
        (false, false) => Err(0),
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
    /// what it watches for.
    fn events(&self) -> Vec<(Watch, Event<Self, D>)>;
    /// After every accepted step: update the slip reference and the
    /// chatter detection.
    fn accepted(&self, y: &[f64; D]);
    /// θ \[rad\], spin, Jellett's J, the energy (if it can be evaluated)
    /// and the work done by friction and the applied force (scaled): what
    /// the run's [`Track`] follows.
    fn track_point(&self, y: &[f64; D]) -> (f64, f64, f64, Option<f64>, f64);
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
    /// A force switch at `t` (the new force is not latched yet): latch it
    /// and re-decide what depends on it.
    fn on_force_switch(&mut self, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow;
    /// A terminal event `what` at `t` with state `y`.
    fn on_terminal(&mut self, what: Watch, t: f64, y: &mut [f64; D], log: &mut RunLog) -> Flow;
    /// Why the right-hand side failed: its kind and the error message.
    fn explain(&self, sc: &Scenario, err: Self::Error) -> (crate::Failure, String);
    /// The output row at scaled time `t`.
    fn row(&self, t: f64, y: &[f64; D]) -> Sample;
    /// The state in SI units, for error messages.
    fn describe(&self, y: &[f64]) -> String;
}

/// What a model whose sphere stays on the plane provides: the reduced
/// Euler-angle model ([`reduced::Reduced`]) and its vector form
/// ([`vector::Vector`]). Both share the friction laws, the contact modes
/// and the stick/slip logic (their [`Model`] implementation, written once
/// in `on_plane.rs`); they differ in their state.
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

#[cfg(test)]
mod tests {
    use super::*;

    /// `bilateral_normal` as first written: both quotients, then their signs.
    fn bilateral_normal_reference(q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
        let np = q / dp;
        let nm = q / dm;
        let okp = dp != 0.0 && np >= 0.0;
        let okm = dm != 0.0 && nm < 0.0;
        match (okp, okm) {
            (true, false) => Ok(np),
            (false, true) => Ok(nm),
            (true, true) => Err(2),
            (false, false) => Err(0),
        }
    }

    /// Same result, bit for bit (sign of zero and NaN included), as the
    /// reference.
    fn same(a: Result<f64, usize>, b: Result<f64, usize>) -> bool {
        match (a, b) {
            (Ok(x), Ok(y)) => x.to_bits() == y.to_bits(),
            (Err(m), Err(n)) => m == n,
            _ => false,
        }
    }

    #[test]
    fn bilateral_normal_matches_two_division_reference() {
        let mags = [
            0.0,
            5e-324,
            1e-310,
            1e-300,
            1e-200,
            1.0000000000000002e-200,
            1e-150,
            1e-8,
            0.5,
            1.0,
            3.0,
            1e99,
            1e100,
            1e150,
            1e300,
            f64::MAX,
            f64::INFINITY,
        ];
        let mut vals: Vec<f64> = mags.iter().flat_map(|&m| [m, -m]).collect();
        vals.push(f64::NAN);
        vals.push(-f64::NAN);
        let mut n = 0;
        for &q in &vals {
            for &dp in &vals {
                for &dm in &vals {
                    let got = bilateral_normal(q, dp, dm);
                    let want = bilateral_normal_reference(q, dp, dm);
                    assert!(
                        same(got, want),
                        "q {q:e} dp {dp:e} dm {dm:e}: {got:?} vs {want:?}"
                    );
                    n += 1;
                }
            }
        }
        // Random physical-range triples (a fixed xorshift sequence).
        let mut x: u64 = 0x9E37_79B9_7F4A_7C15;
        let mut next = || {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Uniform in [-4, 4).
            (x >> 11) as f64 / (1u64 << 53) as f64 * 8.0 - 4.0
        };
        for _ in 0..100_000 {
            let (q, dp, dm) = (next(), next(), next());
            assert!(same(
                bilateral_normal(q, dp, dm),
                bilateral_normal_reference(q, dp, dm)
            ));
            n += 1;
        }
        assert!(n > 100_000);
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
        y[super::reduced::UX] = 0.2;
        y[super::reduced::UY] = -0.1;
        y[super::reduced::PHI] = 0.7;
        y[super::reduced::PSI] = -1.1;
        check(&mut r, y);
        let mut v = super::vector::Vector::new(&sc);
        let mut y = v.scale_state(&sc.initial);
        y[super::vector::OMEGA + 1] = 0.4;
        y[super::vector::QUAT..super::vector::QUAT + 4].copy_from_slice(&[0.5, -0.5, 0.1, 0.7]);
        check(&mut v, y);
    }
}
