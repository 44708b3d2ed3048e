//! The contact state every model shares while its sphere touches the plane
//! (the reduced and vector models always, the rigid model in its contact
//! phase): the friction law and its coefficient, μ, the contact mode and the
//! normal-force closure with its branches, the applied force terms latched
//! for the segment, sliding or rolling, the slip hint and reference, the
//! latched `N = 0` branch, the stick margin, chatter detection and the
//! evaluation count (docs/physics.md#normal-force, §coulomb).

use std::cell::Cell;

use super::{Mode, ModelError};
use crate::physics::forces::{ContactPointForce, Forces};
use crate::physics::units::Scales;
use crate::sim::record::unit;
use crate::{ContactMode, FrictionLaw, Scenario, input::surface::SlidingLaw};

/// Slip reversals between accepted steps after which the sliding-only law is
/// declared to chatter (a genuine motion reverses its slip only at isolated
/// instants).
pub const CHATTER_REVERSALS: u32 = 1000;

pub use crate::input::surface::CONTENSOU_STICK_SPEED;

/// `|v| + r_c |n_Z|` (scaled) below which the Coulomb–Contensou law takes
/// its slip-off hint after a stick ([`ContactState::drilling`]): far above
/// the rounding of `r_c n_Z` in a stuck state (`1e-16` of the spin), far
/// below the stick speed [`CONTENSOU_STICK_SPEED`].
pub const CONTENSOU_HINT_SPEED: f64 = 1e-15;

/// The contact state and its rules, written once for every model: the two
/// that keep the sphere on the plane ([`super::reduced`], [`super::vector`])
/// hold one, and so does the rigid model ([`super::rigid`]) for its contact
/// phase (its flight is its own `phase`). It holds the friction law (ε
/// scaled), μ, the contact mode, the applied force terms and their latched
/// value, sliding or rolling, the slip hint and reference, the latched
/// `N = 0` branch, the chatter detection and flag, and the evaluation
/// count; its rules are the friction coefficient (with the smooth
/// continuation through zero slip), the normal-force closure and the normal
/// the friction sees, the branch-latching rule and the stick margin.
/// Horizontal vectors (slip, friction, hint, reference) are 2D, in the
/// model's own horizontal frame (the rigid model's world X, Y: its 3D
/// vectors with z = 0 convert at the call).
#[derive(Debug, Clone)]
pub struct ContactState {
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
    /// rolling; zero otherwise, and always for the sliding-only law, giving
    /// no friction at v = 0).
    pub slip_hint: [f64; 2],
    /// Reference slip direction (unit) for the slip-zero event and the
    /// smooth continuation of the exact law through zero slip (updated at
    /// every accepted step while sliding).
    pub slip_ref: Cell<[f64; 2]>,
    /// Latched branch of the bilateral normal-force closure while sliding:
    /// `Some(true)` solves `N D(+) = Q` and the friction sees `+N`,
    /// `Some(false)` solves `N D(−) = Q` and it sees `−N`, whatever the sign
    /// of `N`; `None` takes the self-consistent branch at every evaluation
    /// (`bilateral_normal`) and the friction sees `|N|`. The driver
    /// latches the consistent branch at the start of each segment and makes
    /// `N = 0` a terminal event where it flips it, so that no step straddles
    /// the kink of `μ|N|` (docs/physics.md#normal-force). Falls back to the
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
    /// Coulomb–Contensou friction with `r_c > 0` (docs/physics.md#contensou):
    /// the contact radius (scaled), the pressure and the Padé flag. `None`
    /// for every other law, and for `r_c = 0`, which runs as the exact
    /// point law.
    contensou: Option<(f64, crate::input::surface::Pressure, bool)>,
    /// Coulomb–Contensou slip-off: the force and torque coefficients
    /// `(f, τ)` that [`ContactState::drilling`] gives at exactly `v = 0`,
    /// `n_z = 0` after the stick ends (the point of the limit curve where
    /// the needed wrench left it, §contensou); `None` in stick and before any
    /// stick (zero friction there).
    contensou_hint: Option<([f64; 2], f64)>,
    /// Bumped at every change of `contensou_hint`: the models' evaluation
    /// caches key on it.
    hint_generation: u64,
    /// A Langevin run (`solver.method = "langevin"`, μ = 0): the normal
    /// force has one branch (no friction in the closure: nothing to latch)
    /// and θ's maxima are not located between steps (the noise makes θ̇
    /// change sign at almost every step; the step ends are tracked).
    pub langevin: bool,
    /// `cos θ_td` of the stem's touchdown (docs/physics.md#stem), `None`
    /// without a stem: the on-plane models stop there.
    pub stem_cos: Option<f64>,
}

impl ContactState {
    /// The rules of `sc` in the units `scales`, sliding, no force latched.
    pub fn new(sc: &Scenario, scales: &Scales) -> Self {
        // Langevin (μ = 0 checked at validation): the thermostat holds the
        // contact's dissipation; the law is a smooth one that never sticks
        // and never counts slip reversals (the noise reverses the slip at
        // every step).
        let law = if sc.solver.method.is_stochastic() {
            FrictionLaw::Viscous { eps: 1.0 }
        } else {
            sc.surface.law.scaled(scales.velocity())
        };
        // Contensou with r_c = 0 is the exact point law, run as it (bit for
        // bit); with r_c > 0 a smooth law of (v, n_Z) without a rolling
        // mode (§contensou).
        let (law, contensou) = match law.contensou() {
            Some((0.0, _, _)) => (FrictionLaw::Coulomb, None),
            Some((r, p, pade)) => (law, Some((r / scales.length, p, pade))),
            None => (law, None),
        };
        let mut forces = Forces::of(sc);
        forces.scale_wells(scales.energy());
        ContactState {
            exact: law == FrictionLaw::Coulomb,
            law,
            mu: sc.surface.friction,
            contact: sc.surface.contact,
            forces,
            mode: Mode::Sliding,
            slip_hint: [0.0, 0.0],
            slip_ref: Cell::new([0.0, 0.0]),
            normal_branch: None,
            chattering: Cell::new(false),
            reversals: Cell::new(0),
            last_slip: Cell::new([0.0, 0.0]),
            evaluations: 0,
            langevin: sc.solver.method.is_stochastic(),
            contensou,
            contensou_hint: None,
            hint_generation: 0,
            stem_cos: sc.top.stem_touchdown_cos(),
        }
    }

    /// Coulomb–Contensou friction (§contensou), `None` unless the law is it with
    /// `r_c > 0`: for the slip `v` and the spin about the contact normal
    /// `n_z` (scaled), the force coefficient vector `f` (the friction force
    /// is `−N_f f`, `|f| <= μ`) and the torque coefficient `τ` (the drilling
    /// torque about the normal is `−N_f τ`, `|τ| <= μ r_c m(0)`):
    /// `f = μ f(d) v/|v|`, `τ = μ r_c m(d) sign(n_z)`, `d = |v|/(r_c |n_z|)`.
    /// After a stick, while `|v| + r_c |n_z|` is below
    /// [`CONTENSOU_HINT_SPEED`], they are the slip-off hint, the point of
    /// the limit curve where the stick ended; before any stick, zero at
    /// exactly `v = 0`, `n_z = 0` (§contensou).
    /// Inlined test for the law: the other laws pay one branch, not a call.
    #[inline(always)]
    pub(crate) fn drilling(&self, v: [f64; 2], nz: f64) -> Option<([f64; 2], f64)> {
        let (rc, p, pade) = self.contensou?;
        Some(self.drilling_law(v, nz, rc, p, pade))
    }

    /// [`ContactState::drilling`] for Coulomb–Contensou friction with
    /// contact radius `rc`, pressure `p` and Padé flag `pade`.
    #[inline(never)]
    fn drilling_law(
        &self,
        v: [f64; 2],
        nz: f64,
        rc: f64,
        p: crate::input::surface::Pressure,
        pade: bool,
    ) -> ([f64; 2], f64) {
        let mu = self.mu;
        let speed = v[0].hypot(v[1]);
        let spin = rc * nz.abs();
        if let Some(hint) = self.contensou_hint {
            // Just off the stick: the slip is exactly zero there, the spin
            // about Z zero to the rounding of the state (its drift in the
            // stick), which must not pick the torque's sign.
            if speed + spin <= CONTENSOU_HINT_SPEED {
                return hint;
            }
        } else if speed == 0.0 && spin == 0.0 {
            return ([0.0, 0.0], 0.0);
        }
        let d = speed / spin;
        let (f, m) = if pade {
            crate::physics::contensou::pade(p, d)
        } else {
            crate::physics::contensou::exact(p, d)
        };
        let k = if speed > 0.0 { mu * f / speed } else { 0.0 };
        ([k * v[0], k * v[1]], mu * rc * m * nz.signum())
    }

    /// The arrival at the Coulomb–Contensou stick (sliding and spinning
    /// both stopped, §contensou) as an event function: `|v| + r_c |n_z| − δ`,
    /// `δ` = [`CONTENSOU_STICK_SPEED`] (scaled). Near the stick the law is
    /// smooth but stiff (the torque's slope in `n_z` grows like `1/|v|`),
    /// and `|v| + r_c |n_z|` reaches zero without changing sign, so the
    /// arrival is located at this small speed instead.
    pub(crate) fn contensou_stick_gap(&self, v: [f64; 2], nz: f64) -> f64 {
        match self.contensou {
            Some(_) => v[0].hypot(v[1]) + nz.abs() - CONTENSOU_STICK_SPEED,
            None => f64::NAN,
        }
    }

    /// Coulomb–Contensou friction's contact radius (scaled), pressure and
    /// Padé flag; `None` for the other laws and `r_c = 0`.
    pub(crate) fn contensou_params(&self) -> Option<(f64, crate::input::surface::Pressure, bool)> {
        self.contensou
    }

    /// True for Coulomb–Contensou friction with `r_c > 0`.
    pub fn is_contensou(&self) -> bool {
        self.contensou.is_some()
    }

    /// Chatter detection of the sliding-only law, at every accepted step
    /// with the slip `v` there: a genuine motion reverses its slip only at
    /// isolated instants; after [`CHATTER_REVERSALS`] reversals
    /// the next evaluation fails with [`ModelError::Chattering`].
    pub(crate) fn count_reversal(&self, v: [f64; 2]) {
        let l = self.last_slip.get();
        if v[0] * l[0] + v[1] * l[1] < 0.0 {
            let r = self.reversals.get() + 1;
            self.reversals.set(r);
            if r >= CHATTER_REVERSALS {
                self.chattering.set(true);
            }
        }
        self.last_slip.set(v);
    }

    /// Set the slip at the start of a run (the reference of the chatter
    /// detection's first reversal).
    pub(crate) fn start_slip(&self, v: [f64; 2]) {
        self.last_slip.set(v);
    }

    /// What every accepted step in contact updates, with `slip()` the
    /// horizontal slip there (evaluated only if needed): the chatter
    /// detection of the sliding-only law ([`ContactState::count_reversal`]),
    /// and for the exact law while sliding the slip reference (the slip's
    /// direction, unless it is exactly zero).
    pub(crate) fn accepted(&self, slip: impl Fn() -> [f64; 2]) {
        if self.can_chatter() {
            self.count_reversal(slip());
        }
        if self.mode == Mode::Sliding && self.exact {
            let v = unit(slip());
            if v != [0.0, 0.0] {
                self.slip_ref.set(v);
            }
        }
    }

    /// Start rolling (the Coulomb–Contensou stick for that law): the slip
    /// hints are cleared.
    pub(crate) fn stick(&mut self) {
        self.mode = Mode::Rolling;
        self.slip_hint = [0.0, 0.0];
        self.set_contensou_hint(None);
    }

    /// Set the Coulomb–Contensou slip-off hint (and bump its generation).
    fn set_contensou_hint(&mut self, hint: Option<([f64; 2], f64)>) {
        self.contensou_hint = hint;
        self.hint_generation += 1;
    }

    /// The generation of the Coulomb–Contensou slip-off hint, for the
    /// models' evaluation caches (everything an evaluation reads must be in
    /// their keys).
    pub(crate) fn hint_generation(&self) -> u64 {
        self.hint_generation
    }

    /// Leave rolling or the stick for a flight (rigid model): sliding, no
    /// slip hint.
    pub(crate) fn unstick(&mut self) {
        self.mode = Mode::Sliding;
        self.slip_hint = [0.0, 0.0];
        self.set_contensou_hint(None);
    }

    /// Stick margin of a contact wrench, `normal` the normal force, the
    /// needed friction force `friction` and the drilling torque about the
    /// normal `torque` (scaled): the point law's `μ|N| − |F_f|`
    /// ([`ContactState::stick_margin`]; the torque is zero there) and for
    /// Coulomb–Contensou friction `μ|N| (1 − λ)`, `λ` the gauge of
    /// `(|F_f|/(μ|N|), |M|/(μ|N| r_c))` with respect to the law's limit
    /// curve ([`crate::physics::contensou::gauge`]), which is the point
    /// law's margin where `M = 0`. The stick holds while it is `>= 0`
    /// (docs/physics.md#contensou).
    pub(crate) fn stick_margin_wrench(&self, normal: f64, friction: [f64; 2], torque: f64) -> f64 {
        let Some((rc, p, pade)) = self.contensou else {
            return self.stick_margin(normal, friction);
        };
        let cap = self.mu * normal.abs();
        let fm = friction[0].hypot(friction[1]);
        if cap <= 0.0 {
            return -(fm + torque.abs() / rc);
        }
        let (lambda, _) =
            crate::physics::contensou::gauge(p, pade, fm / cap, torque.abs() / (cap * rc));
        cap * (1.0 - lambda)
    }

    /// Slide off at zero slip with the friction continuous, `needed` the
    /// wrench `(N, F_f, M)` the stick needs or needed: the point law's
    /// [`ContactState::slip_off`] with `F_f`, and for Coulomb–Contensou
    /// friction the slip-off hint the point of the limit curve on the ray
    /// through the needed pair (`f = −μ f(d) F_f/|F_f|`,
    /// `τ = −μ r_c m(d) sign M`: the friction force and the drilling torque
    /// keep their directions; the slip grows opposite to the force, the
    /// spin opposite to the torque, in the ratio `d` of the law there).
    pub(crate) fn slip_off_wrench(&mut self, needed: Option<(f64, [f64; 2], f64)>) {
        if let (Some((rc, p, pade)), Some((n, f, m))) = (self.contensou, needed) {
            let cap = self.mu * n.abs();
            let fm = f[0].hypot(f[1]);
            let hint = (cap > 0.0).then(|| {
                let (_, d) =
                    crate::physics::contensou::gauge(p, pade, fm / cap, m.abs() / (cap * rc));
                let (fd, md) = crate::physics::contensou::law(p, pade, d);
                let u = unit(f);
                let sm = if m == 0.0 { 0.0 } else { m.signum() };
                (
                    [-self.mu * fd * u[0], -self.mu * fd * u[1]],
                    -self.mu * rc * md * sm,
                )
            });
            self.set_contensou_hint(hint);
        }
        self.slip_off(needed.map(|w| w.1));
    }

    /// Slide (on) at zero slip with the friction continuous in direction:
    /// with `needed` the friction (scaled, horizontal) rolling needs or
    /// needed, the slip hint becomes its opposite direction (the slip grows
    /// opposite to it; unchanged if `None`), and the slip reference the
    /// hint.
    pub(crate) fn slip_off(&mut self, needed: Option<[f64; 2]>) {
        self.mode = Mode::Sliding;
        if let Some(f) = needed {
            self.slip_hint = unit([-f[0], -f[1]]);
        }
        self.slip_ref.set(self.slip_hint);
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
    /// with the adhesion's load `F_a` in contact added to `h_z`
    /// (docs/physics.md#adhesion): the on-plane models' closure, reaction `N_c`
    /// and friction all see it through this one value (the rigid model
    /// adds its phase's own load to `ContactState::forces`).
    #[inline(always)]
    pub fn contact_point(&self) -> ContactPointForce {
        self.forces.contact_point_in_contact()
    }

    /// The applied force terms with the latched contact-point force, no
    /// adhesion folded in (the rigid model adds its phase's own).
    pub(crate) fn forces(&self) -> &Forces {
        &self.forces
    }

    /// The orientation wells, depths scaled (docs/physics.md#wells; empty
    /// without wells).
    #[inline(always)]
    pub fn wells(&self) -> &[crate::physics::forces::wells::Well] {
        self.forces.wells()
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
    /// ([`ContactState::normal_branch`]): bilateral contact, sliding.
    pub fn latches_normal(&self) -> bool {
        self.contact == ContactMode::Bilateral && self.mode == Mode::Sliding && !self.langevin
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
    /// ([`ContactState::normal_branch`]) takes that branch's quotient while both
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
        self.closure(q, dp, dm)
            .map_err(|solutions| ModelError::Painleve {
                theta: theta(),
                solutions,
            })
    }

    /// The closure of [`ContactState::normal`] with the Painlevé case as
    /// `Err(number of consistent solutions)` (0 or 2), for a model with its
    /// own error type.
    #[inline(always)]
    pub(crate) fn closure(&self, q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
        closure_normal(self.contact, self.normal_branch, q, dp, dm)
    }

    /// The normal force the friction sees: `N` with its sign for the paper's
    /// contact, `σN` for bilateral contact with the branch `σ` latched
    /// ([`ContactState::normal_branch`]), `|N|` otherwise.
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
                reversals: CHATTER_REVERSALS,
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

/// The body's view of the contact ([`crate::physics::body`]): the law and
/// the closure as [`ContactState`]'s own methods.
impl crate::physics::body::Friction for ContactState {
    #[inline(always)]
    fn mu(&self) -> f64 {
        ContactState::mu(self)
    }
    #[inline(always)]
    fn regularized_eps(&self) -> Option<f64> {
        ContactState::regularized_eps(self)
    }
    #[inline(always)]
    fn drilling(&self, v: [f64; 2], wz: f64) -> Option<([f64; 2], f64)> {
        ContactState::drilling(self, v, wz)
    }
    #[inline(always)]
    fn coefficient(&self, v: [f64; 2]) -> [f64; 2] {
        ContactState::coefficient(self, v)
    }
    #[inline(always)]
    fn closure(&self, q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
        ContactState::closure(self, q, dp, dm)
    }
    #[inline(always)]
    fn friction_normal(&self, normal: f64) -> f64 {
        ContactState::friction_normal(self, normal)
    }
    #[inline(always)]
    fn is_contensou(&self) -> bool {
        ContactState::is_contensou(self)
    }
}

/// `a == b`, as one OR of XORs (no early exit, no `memcmp` call: the
/// models' evaluation caches are checked at every step end, and the
/// arrays are short).
#[inline(always)]
pub(crate) fn same_bits<const K: usize>(a: &[u64; K], b: &[u64; K]) -> bool {
    a.iter().zip(b).fold(0, |acc, (x, y)| acc | (x ^ y)) == 0
}

/// True if an evaluation made with the slip reference `r`, at the slip
/// `v` (its `slip`), is the one a fresh evaluation with the reference `d`
/// gives: the models' evaluation caches key on everything else. The slip
/// reference enters an evaluation only through the exact law's
/// continuation test `v·d < 0` ([`ContactState::coefficient`], read while
/// sliding at `v ≠ 0`), so the reference the driver moves at every accepted
/// step ([`ContactState::accepted`]) still finds the evaluation made before
/// it where the test comes out the same. (While rolling, with the other
/// laws or at zero slip, `d` is not read: the same test on the cached `v`
/// then errs only towards a miss.)
#[inline(always)]
pub(crate) fn same_continuation(r: [f64; 2], v: [f64; 2], d: [f64; 2]) -> bool {
    if r[0].to_bits() == d[0].to_bits() && r[1].to_bits() == d[1].to_bits() {
        return true;
    }
    (v[0] * r[0] + v[1] * r[1] < 0.0) == (v[0] * d[0] + v[1] * d[1] < 0.0)
}

/// The normal force from the contact closure `N D(σ) = Q` (`dp = D(+)`,
/// `dm = D(−)`), written once for every model: `"paper"` contact takes
/// `Q/dp` with its sign (no solution if `dp <= 0`); unilateral contact, and
/// bilateral contact with no branch latched, take the one self-consistent
/// branch ([`bilateral_normal`]); bilateral contact with a latched branch
/// (`branch`, see [`ContactState::normal_branch`]) takes that branch's quotient
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

/// For the models' cache tests of [`same_continuation`]: a slip reference
/// `r` drawn from `next` (numbers in [−1, 1)) and the directions `d` it is
/// read under, `r` itself, `−r`, a perpendicular and another drawn one.
/// `read(r, d)` evaluates under `r`, reads again under `d` (checking the
/// result against a fresh evaluation) and returns the first evaluation's
/// slip, or `None` if there is no evaluation there. `counts` gathers, over
/// the `d ≠ r`, the reads whose continuation test `v·d < 0` came out as
/// under `r` (the cache may keep the evaluation) and those where it flipped
/// (it must not).
#[cfg(test)]
pub(crate) fn read_under_moved_references(
    next: &mut impl FnMut() -> f64,
    mut read: impl FnMut([f64; 2], [f64; 2]) -> Option<[f64; 2]>,
    counts: &mut (usize, usize),
) {
    let a = std::f64::consts::PI * next();
    let r = [a.cos(), a.sin()];
    let b = std::f64::consts::PI * next();
    for d in [r, [-r[0], -r[1]], [-r[1], r[0]], [b.cos(), b.sin()]] {
        let Some(v) = read(r, d) else { continue };
        if d != r {
            if (v[0] * r[0] + v[1] * r[1] < 0.0) == (v[0] * d[0] + v[1] * d[1] < 0.0) {
                counts.0 += 1;
            } else {
                counts.1 += 1;
            }
        }
    }
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
