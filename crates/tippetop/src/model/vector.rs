//! The reduced model's physics in vector form: the sphere stays on the
//! plane (bilateral or paper contact; unilateral contact stops at lift-off),
//! written with the symmetry axis `k`, the angular velocity `w` and the
//! horizontal centre-of-mass velocity, all in the space frame
//! (docs/physics.md#vector-model).
//!
//! Same physics as [`super::reduced`] (same friction laws, normal-force
//! closure, exact stick/slip, applied force in the precessing frame), but:
//!
//! - no Euler angles: nothing is singular at `θ = 0` or `π`, and the
//!   precession rate `Ω`, which swings through ±∞-like spikes when the axis
//!   passes close to the vertical, is an output, not a state variable;
//! - no trigonometry and fewer divisions per evaluation;
//! - the centre-of-mass velocity is not in a rotating frame.
//!
//! It is the fast formulation: on the classical top the step-size control
//! of DOP853 needs 2–5x fewer steps than with the Euler angles
//! (docs/performance.md).
//!
//! # State and units
//!
//! Scaled units of [`Scales`] (lengths by R, masses by m). State
//! (`DIM = 17`): `[k (3), w (3), v_x, v_y, W_f, W_a, p (4), χ, x, y]`; the
//! last seven are quadratures outside the error norm ([`CONTROLLED`]): the
//! attitude (body → lab, carried for the rotation about `k`, which the
//! dynamics never needs) as `q = p ⊗ q_Z(ψ)` with `p` the frame carried
//! along `k` without turning about it (`ṗ = ½ (0, w − (w·k) k) ⊗ p`) and
//! the spin angle `ψ = ω₀ t + χ`, `χ̇ = w·k − ω₀` (`ω₀` the initial spin),
//! and the centre of mass's lab position (`ẋ = v_x`, `ẏ = v_y`),
//! docs/physics.md#position.
//!
//! # Equations (m = R = 1)
//!
//! CM `O`, geometric centre `C = O + a k` at height 1, contact `P = C − Z`,
//! `r = P − O = a k − Z`. `k̇ = w × k`, `z_O = 1 − a k_Z`,
//! `v_Z = −a k̇_Z`. With the contact force `F = N Z + F_f − H`
//! (`H = h_x x̂ + h_y ŷ`, `x̂` along the horizontal projection of `k`,
//! `ŷ = Z × x̂`; world `X`, `Y` if `k` is vertical):
//!
//! - `v̇_h = F_h`;
//! - `I ẇ = r × F − (C − A)(w·k) k̇`, `I⁻¹ x = x/A + (1/C − 1/A)(x·k) k`;
//! - a vertical load `h_z` at `P` (the force on the top is `−h_z Z`) adds
//!   `h_z (1 + a u_Z)` to `Q` below; the vertical force at `P` is `N − h_z`
//!   (docs/physics.md#vertical-load);
//! - the contact closure `v̇_Z = N − g = −a k̈_Z` gives
//!   `N D(σ) = Q` with `e = k × Z`, `u = (e × r)/A`,
//!   `D(σ) = 1 + a (u_Z − σ f·u)`,
//!   `Q = g + a (H·u − ẇ₀·e − (w × k̇)_Z)`, `ẇ₀ = −(C − A)(w·k) k̇ / A`;
//! - rolling (exact law): the contact force solves
//!   `F − r × I⁻¹ (r × F) = g Z − ẇ₀ × r − a w × k̇`;
//! - `Ẇ_f = F_f · v_P`, `Ẇ_a = −H · v_P`, `v_P = v + w × r` (sliding).
//!
//! `k̇ = w × k` keeps `|k|` constant exactly, so `|k| = 1` drifts only by
//! the integration error; no stabilising term is added (one was tried,
//! `− κ (|k|² − 1) k`: at κ = 1 per time unit it cost up to 26 % more
//! evaluations and six times the J drift, docs/physics.md#vector-model).

use std::cell::RefCell;

use super::ContactState;
use super::reduced::{Mode, ModelError, Scales};
use super::vec3::{V3, add, cross, dot, scale};
use crate::physics::body;
use crate::physics::forces::{AppliedClass, ContactPointForce};
use crate::{Initial, Sample, Scenario, Top, integrate::OdeSystem};

/// Number of state components.
pub const DIM: usize = 17;
/// Number of components under error control (`k … W_a`); the quadratures
/// `p, χ, x, y` follow ([`OdeSystem::CONTROLLED`]).
pub const CONTROLLED: usize = 10;
/// Index of the symmetry axis `k` (3 components).
pub const K: usize = 0;
/// Index of the angular velocity `w` (space frame, 3 components).
pub const OMEGA: usize = 3;
/// Index of the horizontal centre-of-mass velocity (2 components).
pub const VEL: usize = 6;
/// Index of the friction work.
pub const WF: usize = 8;
/// Index of the applied-force work.
pub const WA: usize = 9;
/// Index of the attitude's untwisted frame `p` `(w, x, y, z)`, a
/// quaternion body → lab whose axis follows `k` without turning about it
/// (quadrature; the attitude is `p ⊗ q_Z(ψ)`, [`Vector::attitude`]).
pub const QUAT: usize = 10;
/// Index of `χ = ψ − ω₀ t` \[rad\], the spin angle about `k` less the
/// initial spin's share (quadrature; [`Vector::spin_reference`]).
pub const TWIST: usize = 14;
/// Index of the centre of mass's lab x (quadrature; y follows).
pub const POS: usize = 15;

/// The attitude's rates: `ṗ = ½ (0, w_⊥) ⊗ p` with `w_⊥ = w − (w·k) k`
/// (`wk = w·k`), and `χ̇ = w·k − ω₀`. `p` turns only as fast as the axis
/// does (`|w_⊥| = |k̇|`), which the step-size control resolves; the spin,
/// however fast, enters the scalar quadrature `χ` alone (docs/physics.md
/// §position).
#[inline(always)]
fn attitude_rate<const N: usize>(
    w: V3,
    k: V3,
    wk: f64,
    spin_ref: f64,
    y: &[f64; N],
) -> ([f64; 4], f64) {
    let w = [w[0] - wk * k[0], w[1] - wk * k[1], w[2] - wk * k[2]];
    let q = [y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3]];
    (
        [
            0.5 * (-w[0] * q[1] - w[1] * q[2] - w[2] * q[3]),
            0.5 * (w[0] * q[0] + w[1] * q[3] - w[2] * q[2]),
            0.5 * (w[1] * q[0] + w[2] * q[1] - w[0] * q[3]),
            0.5 * (w[2] * q[0] + w[0] * q[2] - w[1] * q[1]),
        ],
        wk - spin_ref,
    )
}
/// [`OdeSystem::STAGE_READ`] with the pose: `k, w, v`, the works and `p`
/// (`χ` and the position are read by no derivative).
// A list of ranges (here one), not the range's elements.
#[allow(clippy::single_range_in_vec_init)]
const STAGE_POSE: &[std::ops::Range<usize>] = &[0..TWIST];
/// [`OdeSystem::STAGE_READ`] without the pose: the controlled components.
#[allow(clippy::single_range_in_vec_init)]
const STAGE_MOTION: &[std::ops::Range<usize>] = &[0..CONTROLLED];

/// DOP853's step-size control for this model
/// ([`crate::integrate::Stepper::Dop853`]): `β` of the stabilised (PI)
/// control and the cap of the step at the stability limit `6.1/ρ`. Without
/// the Euler angles' 1/sin θ the classical top with regularised friction is
/// stability-bound (the slip relaxes at ≈ 3μg/ε), and the error-based
/// control alone overshoots the limit again and again (docs/physics.md#vector-model;
/// the measurements that chose these values: docs/performance.md,
/// "DOP853's step control for the vector model").
pub const DOP853_BETA: f64 = 0.04;
/// See [`DOP853_BETA`].
pub const DOP853_STABILITY_CAP: bool = true;

/// Everything the right-hand side computes at one state (scaled units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eval<const N: usize = DIM> {
    /// State derivative.
    pub dy: [f64; N],
    /// Normal force N.
    pub normal: f64,
    /// Friction force on the top (space frame x, y), excluding the applied force.
    pub friction: [f64; 2],
    /// Slip velocity v_P (space frame x, y) (zero while rolling).
    pub slip: [f64; 2],
    /// Centre-of-mass velocity (x, y, z) (constraint values while rolling).
    pub v: V3,
    /// Drilling torque about Z (Coulomb–Contensou friction: the law's
    /// while sliding, the constraint torque in the stick; 0 otherwise).
    pub torque: f64,
}

/// One entry of [`Vector::eval`]'s cache: the key (the state's bits, and
/// the mode and every input but the slip reference, [`Vector::cache_inputs`]),
/// the slip reference the evaluation saw, and the evaluation.
#[derive(Debug, Clone, Copy)]
struct CacheEntry<const N: usize> {
    y: [u64; N],
    inputs: [u64; INPUTS],
    slip_ref: [f64; 2],
    eval: Eval<N>,
}

/// The number of inputs besides the state in [`CacheEntry`]'s key.
const INPUTS: usize = 9;

impl<const N: usize> CacheEntry<N> {
    /// An entry for the evaluation `eval` at `y`.
    #[inline(always)]
    fn new(y: &[f64; N], inputs: [u64; INPUTS], slip_ref: [f64; 2], eval: Eval<N>) -> Self {
        CacheEntry {
            y: y.map(f64::to_bits),
            inputs,
            slip_ref,
            eval,
        }
    }

    /// True if a fresh evaluation at `y` with `inputs` and the slip
    /// reference `d` gives this entry's bits. The state is compared first,
    /// component by component (a miss is nearly always a different state,
    /// found at its first component); the slip reference `d` by
    /// [`super::contact::same_continuation`].
    #[inline(always)]
    fn holds(&self, y: &[f64; N], inputs: &[u64; INPUTS], d: [f64; 2]) -> bool {
        for (a, b) in self.y.iter().zip(y) {
            if *a != b.to_bits() {
                return false;
            }
        }
        if !super::contact::same_bits(&self.inputs, inputs) {
            return false;
        }
        super::contact::same_continuation(self.slip_ref, self.eval.slip, d)
    }
}

/// The vector-form model as an ODE system in scaled units.
#[derive(Debug, Clone)]
pub struct Vector<const N: usize = DIM> {
    /// Unit system.
    pub scales: Scales,
    a: f64,
    ia: f64,
    ic: f64,
    /// The body's constants (`a`, the inertia with 1/A, 1/C − 1/A and
    /// (C − A)/A so the right-hand side multiplies instead of dividing, g).
    body: body::Body,
    g: f64,
    /// Friction law, contact, applied force, sliding/rolling and the
    /// driver's flags (shared with the Euler-angle model).
    pub plane: ContactState,
    /// The SI top.
    pub top: Top,
    /// `ω₀` (scaled): the initial spin `n·k`, the rate the spin angle
    /// `ψ = ω₀ t + χ` is measured from (0 with `method = "brownian"`,
    /// whose velocities are drifts).
    spin_ref: f64,
    /// The last evaluation made by [`Vector::eval`] and its key (state bits,
    /// mode and every input), so the driver's repeated evaluations at an
    /// accepted step (N event, energy, samples) are computed once. The key
    /// is compared bit for bit: the result is what a fresh evaluation gives
    /// (the slip reference too, through [`CacheEntry::holds`]).
    last: RefCell<Option<CacheEntry<N>>>,
    /// The evaluation at the last accepted step's end
    /// ([`OdeSystem::rhs_accepted`]) and its key, kept apart from `last`:
    /// the samples and event searches inside the step overwrite `last`, and
    /// the observers at the step's end then still find this one (the same
    /// key, so the same result as a fresh evaluation).
    accepted: RefCell<Option<CacheEntry<N>>>,
    /// The Langevin thermostat (scaled), `None` unless `method = "langevin"`.
    thermal: Option<super::thermostat::Bath>,
    /// The Ornstein–Uhlenbeck step's coefficients from the last call
    /// (`ou_step`), reused where their inputs are the same bits.
    ou: super::thermostat::OuCache,
    /// The wells' torque at the last axis `k` ([`body::WellsTorque`]).
    wells_torque: body::WellsTorque,
}

/// `(sin θ, cos θ)` for the initial axis, moved by a few ulps so that the
/// axis reads back as `θ` exactly (`atan2(sin θ, cos θ)` is `θ` only to
/// rounding: 0.1 would come back as 0.09999999999999999 in the first output
/// row). `sin θ` is stepped towards `θ` one ulp at a time; where that steps
/// over `θ` (atan2 rounds two neighbouring values of `sin θ` to either side
/// of it), `cos θ` is moved by one or two ulps and the search repeated. If
/// nothing reads back exactly, the rounded pair is kept. `0 <= θ <= π`.
fn axis(theta: f64) -> (f64, f64) {
    let (s0, c0) = theta.sin_cos();
    let cs = [
        c0,
        c0.next_up(),
        c0.next_down(),
        c0.next_up().next_up(),
        c0.next_down().next_down(),
    ];
    for c in cs {
        let mut s = s0;
        for _ in 0..8 {
            let back = s.atan2(c);
            if back == theta {
                return (s, c);
            }
            if s <= 0.0 {
                break;
            }
            s = if back < theta {
                s.next_up()
            } else {
                s.next_down()
            };
        }
    }
    (s0, c0)
}

/// Kinematic quantities shared by both modes.
type Kin = body::At;

/// The applied terms a segment has, as [`Vector::eval_now`] specialises on
/// them: any ([`GENERAL`]), at most the horizontal force `H`
/// ([`crate::physics::forces::Forces::only_horizontal`]), none
/// ([`crate::physics::forces::Forces::nothing_applied`]).
const GENERAL: u8 = 0;
/// See [`GENERAL`].
const ONLY_H: u8 = 1;
/// See [`GENERAL`].
const PLAIN: u8 = 2;

/// The contact's law known to be the regularised one with `ε = eps`
/// (scaled): [`ContactState`]'s own answers, with the law's test made once
/// per evaluation instead of inside the solution ([`Vector::eval_now`]).
struct Regularized<'a> {
    plane: &'a ContactState,
    eps: f64,
}

impl body::Friction for Regularized<'_> {
    #[inline(always)]
    fn mu(&self) -> f64 {
        self.plane.mu()
    }
    #[inline(always)]
    fn regularized_eps(&self) -> Option<f64> {
        Some(self.eps)
    }
    #[inline(always)]
    fn drilling(&self, _v: [f64; 2], _wz: f64) -> Option<([f64; 2], f64)> {
        None
    }
    #[inline(always)]
    fn coefficient(&self, v: [f64; 2]) -> [f64; 2] {
        self.plane.coefficient(v)
    }
    #[inline(always)]
    fn closure(&self, q: f64, dp: f64, dm: f64) -> Result<f64, usize> {
        self.plane.closure(q, dp, dm)
    }
    #[inline(always)]
    fn friction_normal(&self, normal: f64) -> f64 {
        self.plane.friction_normal(normal)
    }
    #[inline(always)]
    fn is_contensou(&self) -> bool {
        false
    }
}

impl Vector {
    /// Build the scaled model of a scenario (the pose carried: [`DIM`]).
    pub fn new(sc: &Scenario) -> Self {
        Self::with_state(sc)
    }
}

impl<const N: usize> Vector<N> {
    /// True if the state carries the pose (`N = DIM`): the attitude
    /// `p, χ` and the position `x, y`. Without it (`N = CONTROLLED`) the
    /// motion's ten components alone, the same bits
    /// (docs/performance.md#pose).
    pub const POSE: bool = {
        assert!(N == DIM || N == CONTROLLED);
        N > CONTROLLED
    };

    /// Build the scaled model of a scenario with the state length `N`
    /// ([`DIM`]: the pose carried; [`CONTROLLED`]: not).
    pub fn with_state(sc: &Scenario) -> Self {
        let _ = Self::POSE;
        let scales = Scales::of(sc);
        let ia = sc.top.inertia_transverse / scales.inertia();
        let ic = sc.top.inertia_axial / scales.inertia();
        let g = sc.surface.gravity * scales.time * scales.time / scales.length;
        Vector {
            scales,
            a: sc.top.offset / scales.length,
            ia,
            ic,
            body: body::Body {
                a: sc.top.offset / scales.length,
                inertia: body::Inertia::new(ia, ic),
                g,
            },
            g,
            plane: ContactState::new(sc, &scales),
            top: sc.top,
            spin_ref: if sc.solver.method == crate::Method::Brownian {
                0.0
            } else {
                sc.initial.spin * scales.time
            },
            last: RefCell::new(None),
            accepted: RefCell::new(None),
            thermal: super::thermostat::Bath::of(sc, &scales),
            ou: super::thermostat::OuCache::default(),
            wells_torque: body::WellsTorque::default(),
        }
    }

    /// Kinetic energy (scaled) of the generalised velocities of a state:
    /// `½ (|v_h|² + v_Z²) + ½ w·I w` with `v_Z = −a (w × k)_Z`.
    fn kinetic(&self, y: &[f64; N]) -> f64 {
        let k = [y[K], y[K + 1], y[K + 2]];
        let w = [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]];
        super::thermostat::kinetic_in_contact(
            self.a,
            &self.body.inertia,
            k,
            [y[VEL], y[VEL + 1]],
            w,
        )
    }

    /// The exact Ornstein–Uhlenbeck step over `h` (scaled) of the
    /// generalised velocities `u = (v_x, v_y, w)` at fixed axis `k`
    /// (docs/physics.md#langevin): `du = −M⁻¹Γ u dt + M⁻¹ dF`, `⟨dF dFᵀ⟩ =
    /// 2 kT Γ dt`. Without contact damping `M` and `Γ` are diagonal in the
    /// basis `(X, Y | k, ê, f̂)`, `ê = k × Z/|k × Z|`, `f̂ = k × ê`:
    /// `M = (1, 1 | C, A + a² sin²θ, A)`, `Γ = (γ_t, γ_t | γ_r C,
    /// γ_r A + γ_t a² sin²θ, γ_r A)`; each mode relaxes at `λ = Γ_i/M_i`
    /// with the variance `kT (1 − e^{−2λh})/M_i` added. The change of the
    /// kinetic energy is added to the friction work `W_f` (the bath's work).
    fn ou_step(&mut self, y: &mut [f64; N], h: f64, xi: &[f64]) {
        let Some(b) = self.thermal else { return };
        let body = super::thermostat::Body {
            a: self.a,
            ia: self.ia,
            ic: self.ic,
        };
        let k = [y[K], y[K + 1], y[K + 2]];
        let mut vh = [y[VEL], y[VEL + 1]];
        let mut w = [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]];
        let inertia = &self.body.inertia;
        let (_, work) = super::thermostat::ou_in_contact(
            &b,
            &body,
            inertia,
            &mut self.ou,
            k,
            &mut vh,
            &mut w,
            h,
            xi,
        );
        y[VEL] = vh[0];
        y[VEL + 1] = vh[1];
        y[OMEGA..OMEGA + 3].copy_from_slice(&w);
        y[WF] += work;
    }

    /// One Euler–Maruyama step over `h` (scaled) of the overdamped
    /// (Brownian) dynamics, `solver.method = "brownian"` (docs/physics.md
    /// §langevin): the generalised velocity is `p = Γ⁻¹ Q + sqrt(2 kT/h) Γ^{−1/2} ξ`
    /// in the basis `(X, Y | k̂, ê, f̂)` (`Γ` diagonal there without contact
    /// damping; with it, the coupled step of §brownian,
    /// [`super::thermostat::overdamped_coupled`]), `Q` the generalised force
    /// at rest (the right-hand side at
    /// zero velocity times `M`: gravity, the applied force, wells, the
    /// constraint); plus the drift along θ that makes the stationary density
    /// the Langevin run's configuration marginal `e^{−U/kT} sin θ
    /// sqrt(1 + m a² sin²θ/A)`: `kT [(μ_θ − μ_φ) cot θ + μ_θ ∂_θ ln s +
    /// ∂_θ μ_θ]` with `μ_θ = 1/Γ_ê`, `μ_φ = 1/Γ_f̂` (the geodesic step itself
    /// supplies `kT μ_φ cot θ`). The configuration moves by the rotation
    /// vector `w h` (Rodrigues, exact on the sphere) and `v h`; the state's
    /// velocities are set to the drift part (the noise has no velocity),
    /// and `W_f` takes the energy change (the bath's work).
    fn brownian_step(
        &mut self,
        t: f64,
        y: &mut [f64; N],
        h: f64,
        xi: &[f64],
    ) -> Result<(), ModelError> {
        let Some(b) = self.thermal else { return Ok(()) };
        let e0 = self.eval_now(y)?;
        let en0 = self.energy_scaled(y, &e0);
        // The generalised force at rest.
        let mut rest = *y;
        rest[OMEGA..OMEGA + 3].fill(0.0);
        rest[VEL..VEL + 2].fill(0.0);
        let mut dy = [0.0; N];
        <Self as OdeSystem<N>>::rhs(self, t, &rest, &mut dy)?;
        let ([kn, eh, fh], s2) = super::thermostat::modes_basis([y[K], y[K + 1], y[K + 2]]);
        let body = super::thermostat::Body {
            a: self.a,
            ia: self.ia,
            ic: self.ic,
        };
        let wd = [dy[OMEGA], dy[OMEGA + 1], dy[OMEGA + 2]];
        let acc = [dy[VEL], dy[VEL + 1], dot(wd, kn), dot(wd, eh), dot(wd, fh)];
        let (p, drift) = super::thermostat::overdamped(&b, &body, [kn, eh, fh], s2, acc, h, xi);
        let w = add(add(scale(p[2], kn), scale(p[3], eh)), scale(p[4], fh));
        let rv = scale(h, w);
        let k = super::vec3::rotate(rv, [y[K], y[K + 1], y[K + 2]]);
        if Self::POSE {
            let (p_new, twist) = super::vec3::swing_twist_turn(
                rv,
                [y[K], y[K + 1], y[K + 2]],
                [y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3]],
            );
            y[QUAT..QUAT + 4].copy_from_slice(&p_new);
            y[TWIST] += twist - self.spin_ref * h;
            y[POS] += h * p[0];
            y[POS + 1] += h * p[1];
        }
        y[K..K + 3].copy_from_slice(&k);
        let wdrift = add(
            add(scale(drift[2], kn), scale(drift[3], eh)),
            scale(drift[4], fh),
        );
        y[OMEGA..OMEGA + 3].copy_from_slice(&wdrift);
        y[VEL] = drift[0];
        y[VEL + 1] = drift[1];
        let e1 = self.eval_now(y)?;
        y[WF] += self.energy_scaled(y, &e1) - en0;
        Ok(())
    }

    /// Latch the applied force in effect at scaled time `t`.
    pub fn latch_force(&mut self, t: f64) {
        self.plane.latch_force(t, &self.scales);
    }

    /// C/(m R²).
    pub fn ic(&self) -> f64 {
        self.ic
    }

    /// Scaled state from SI initial values, with the precessing x along the
    /// space X: `k = (s, 0, c)`, `w = ((ω − Ω c) s, θ̇, Ω s² + ω c)`,
    /// `v = (u_x, u_y)`, `p = (cos θ/2, 0, sin θ/2, 0)` (a turn by θ about
    /// the lab Y), `χ = 0`, `x = y = 0`.
    pub fn scale_state(&self, i: &Initial) -> [f64; N] {
        let y = self.scale_pose_state(i);
        std::array::from_fn(|j| y[j])
    }

    /// [`Vector::scale_state`] with the pose ([`DIM`] components).
    fn scale_pose_state(&self, i: &Initial) -> [f64; DIM] {
        let t = self.scales.time;
        let vu = self.scales.velocity();
        let (s, c) = axis(i.theta);
        let (thd, om, w) = (i.theta_dot * t, i.precession * t, i.spin * t);
        let y = [
            s,
            0.0,
            c,
            (w - om * c) * s,
            thd,
            om * s * s + w * c,
            i.ux / vu,
            i.uy / vu,
            0.0,
            0.0,
            (0.5 * i.theta).cos(),
            0.0,
            (0.5 * i.theta).sin(),
            0.0,
            0.0,
            0.0,
            0.0,
        ];
        if i.heading == 0.0 {
            return y;
        }
        // Turned by the heading about Z: k, w, v, and the attitude
        // q_Z(φ₀) ⊗ q (the dynamics are the same; docs/physics.md#position).
        let mut y = y;
        let rz = super::vec3::RotZ::new(i.heading);
        for at in [K, OMEGA] {
            let v = rz.apply([y[at], y[at + 1], y[at + 2]]);
            y[at..at + 3].copy_from_slice(&v);
        }
        let v = rz.apply([y[VEL], y[VEL + 1], 0.0]);
        y[VEL..VEL + 2].copy_from_slice(&v[..2]);
        let q = rz.turn_quaternion([y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3]]);
        y[QUAT..QUAT + 4].copy_from_slice(&q);
        y
    }

    #[inline(always)]
    fn kin(&self, y: &[f64; N]) -> Kin {
        let k = [y[K], y[K + 1], y[K + 2]];
        let w = [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]];
        body::At::new(&body::Plane, self.a, 1.0, k, w)
    }

    /// I⁻¹ x for the symmetry axis k.
    #[inline(always)]
    fn inv_inertia(&self, k: V3, x: V3) -> V3 {
        self.body.inertia.inverse(k, x)
    }

    /// I x for the symmetry axis k.
    #[inline(always)]
    fn inertia(&self, k: V3, x: V3) -> V3 {
        self.body.inertia.apply(k, x)
    }

    /// The precessing frame's x̂ and ŷ (horizontal; X, Y if k is vertical).
    #[inline]
    fn frame(k: V3) -> (V3, V3) {
        body::precessing_frame(k)
    }

    /// Horizontal slip velocity `v + w × r` (space frame) from the state's v.
    pub fn slip_of(&self, y: &[f64; N]) -> [f64; 2] {
        let kn = self.kin(y);
        [y[VEL] + kn.wr[0], y[VEL + 1] + kn.wr[1]]
    }

    /// Horizontal centre-of-mass velocity of zero slip, `−(w × r)_h`.
    pub fn rolling_velocity(&self, y: &[f64; N]) -> [f64; 2] {
        let kn = self.kin(y);
        [-kn.wr[0], -kn.wr[1]]
    }

    /// θ = atan2(|k_h|, k_Z) \[rad\]. `|k_h|` as a plain square root, not
    /// `hypot` (|k| ≈ 1: nothing to overflow; it underflows only for
    /// `|k_h| < 1e-154`, θ then reads 0): the driver calls this at every
    /// accepted step.
    pub fn theta(y: &[f64; N]) -> f64 {
        (y[K] * y[K] + y[K + 1] * y[K + 1]).sqrt().atan2(y[K + 2])
    }

    /// Evaluate the model at a state in the current mode (cached: see
    /// the `last` field).
    pub fn eval(&self, y: &[f64; N]) -> Result<Eval<N>, ModelError> {
        self.with_eval(y, |e| *e)
    }

    /// `read` of [`Vector::eval`]'s evaluation at `y`, read in place (a
    /// cached evaluation is not copied out: the driver's observers read
    /// one or two of its fields at every accepted step).
    #[inline(always)]
    fn with_eval<R>(
        &self,
        y: &[f64; N],
        read: impl FnOnce(&Eval<N>) -> R,
    ) -> Result<R, ModelError> {
        let inputs = self.cache_inputs();
        let d = self.plane.slip_ref.get();
        for slot in [&self.accepted, &self.last] {
            if let Some(c) = &*slot.borrow() {
                if c.holds(y, &inputs, d) {
                    return Ok(read(&c.eval));
                }
            }
        }
        let e = self.eval_now(y)?;
        let r = read(&e);
        *self.last.borrow_mut() = Some(CacheEntry::new(y, inputs, d, e));
        Ok(r)
    }

    /// The inputs besides the state in [`Vector::eval`]'s cache key: the
    /// mode and every input the evaluation reads but the slip reference
    /// ([`CacheEntry::holds`]).
    #[inline(always)]
    fn cache_inputs(&self) -> [u64; INPUTS] {
        let p = &self.plane;
        let h = p.applied();
        [
            p.mode as u64,
            h[0].to_bits(),
            h[1].to_bits(),
            p.slip_hint[0].to_bits(),
            p.slip_hint[1].to_bits(),
            match p.normal_branch {
                None => 0,
                Some(false) => 1,
                Some(true) => 2,
            },
            p.contact_point().hz.to_bits(),
            // The body actuators change only at a latch (§actuators).
            p.forces().generation(),
            // The Coulomb–Contensou slip-off hint (§contensou).
            p.hint_generation(),
        ]
    }

    /// Evaluate the model at a state in the current mode, uncached.
    ///
    /// Where the segment applies nothing ([`crate::physics::forces::Forces::nothing_applied`])
    /// or at most `H` ([`crate::physics::forces::Forces::only_horizontal`]),
    /// the sliding and rolling solutions are taken with the absent terms as
    /// constants ([`PLAIN`], [`ONLY_H`]) and, with nothing applied and the
    /// regularised law, the law known at compile time ([`Regularized`]):
    /// the same arithmetic on the same values (the terms' zeros included),
    /// without the tests and loads that find each term absent at every
    /// evaluation.
    #[inline(always)]
    fn eval_now(&self, y: &[f64; N]) -> Result<Eval<N>, ModelError> {
        let kn = self.kin(y);
        match (self.plane.mode, self.plane.forces().applied()) {
            (Mode::Sliding, AppliedClass::Nothing) => match self.plane.regularized_eps() {
                Some(eps) => {
                    let law = Regularized {
                        plane: &self.plane,
                        eps,
                    };
                    self.eval_sliding::<_, PLAIN>(&law, y, &kn)
                }
                None => self.eval_sliding::<_, PLAIN>(&self.plane, y, &kn),
            },
            (Mode::Sliding, AppliedClass::OnlyHorizontal) => {
                self.eval_sliding::<_, ONLY_H>(&self.plane, y, &kn)
            }
            (Mode::Sliding, AppliedClass::General) => {
                self.eval_sliding::<_, GENERAL>(&self.plane, y, &kn)
            }
            (Mode::Rolling, AppliedClass::Nothing) => Ok(self.eval_rolling::<PLAIN>(y, &kn)),
            (Mode::Rolling, AppliedClass::OnlyHorizontal) => {
                Ok(self.eval_rolling::<ONLY_H>(y, &kn))
            }
            (Mode::Rolling, AppliedClass::General) => Ok(self.eval_rolling::<GENERAL>(y, &kn)),
        }
    }

    /// The free accelerations, the applied force `H` at `kn`
    /// ([`body::Body::free`]) and the contact-point force. With `PLAIN`
    /// (nothing applied) the gyroscopic term alone, `H = 0` and no load,
    /// as constants; with `ONLY_H` the gyroscopic term alone and no load
    /// as constants, `H` as latched: the same values the general path finds.
    #[inline(always)]
    fn terms<const T: u8>(&self, kn: &Kin) -> (body::Free, V3, ContactPointForce) {
        match T {
            PLAIN => (
                self.body.free(kn, None, None),
                [0.0; 3],
                ContactPointForce::default(),
            ),
            ONLY_H => {
                let h = self.plane.applied();
                (
                    self.body.free(kn, None, None),
                    body::applied_world(h, kn.k),
                    ContactPointForce { h, hz: 0.0 },
                )
            }
            _ => {
                let (free, hw) = self.free(kn);
                (free, hw, self.plane.contact_point())
            }
        }
    }

    /// The free accelerations and the applied force `H` at `kn`
    /// ([`body::Body::free`]).
    #[inline(always)]
    fn free(&self, kn: &Kin) -> (body::Free, V3) {
        let k = kn.k;
        let wells = self.wells_torque.at(self.plane.wells(), k);
        // Only actuators on the axis: the material axes an off-axis one
        // needs are the attitude's, whose spin angle `ω₀ t + χ` needs the
        // time, which the evaluation does not read; the scenario's
        // validation refuses them in this model.
        let wrench = body::wrench(self.plane.forces(), k, || {
            unreachable!(
                "an off-axis actuator in model = \"vector\" (refused by physics::forces::actuators::check_model)"
            )
        });
        (
            self.body.free(kn, wells, wrench),
            body::applied_world(self.plane.applied(), k),
        )
    }

    /// Sliding: [`body::Body::slide`] at the state's slip.
    #[inline(always)]
    fn eval_sliding<F: body::Friction, const T: u8>(
        &self,
        law: &F,
        y: &[f64; N],
        kn: &Kin,
    ) -> Result<Eval<N>, ModelError> {
        let Kin {
            k, w, kd, wk, wr, ..
        } = *kn;
        let v = [y[VEL], y[VEL + 1]];
        let vp = [v[0] + wr[0], v[1] + wr[1]];
        let (free, hw, cp) = self.terms::<T>(kn);
        let c = self
            .body
            .slide(law, kn, &free, hw, &cp, vp)
            .map_err(|solutions| ModelError::Painleve {
                theta: Self::theta(y),
                solutions,
            })?;
        let vo = [v[0], v[1], -self.a * kd[2]];
        let mut dy = [0.0; N];
        dy[..CONTROLLED].copy_from_slice(&[
            kd[0], kd[1], kd[2], c.wd[0], c.wd[1], c.wd[2], c.force[0], c.force[1], c.wf, c.wa,
        ]);
        if Self::POSE {
            let (qd, chi) = attitude_rate(w, k, wk, self.spin_ref, y);
            dy[CONTROLLED..].copy_from_slice(&[qd[0], qd[1], qd[2], qd[3], chi, v[0], v[1]]);
        }
        if let Some(wr) = free.wrench {
            // Its horizontal force and its power F·v_O + τ·w (§actuators).
            dy[VEL] += wr.0[0];
            dy[VEL + 1] += wr.0[1];
            dy[WA] += body::power(wr, vo, w);
        }
        Ok(Eval {
            dy,
            normal: c.normal,
            friction: c.friction,
            slip: vp,
            v: vo,
            torque: c.torque,
        })
    }

    /// Rolling: [`body::Body::roll`], the slip held at zero.
    #[inline(always)]
    fn eval_rolling<const T: u8>(&self, y: &[f64; N], kn: &Kin) -> Eval<N> {
        let Kin {
            k, w, kd, wk, wr, ..
        } = *kn;
        let (free, hw, cp) = self.terms::<T>(kn);
        let c = self.body.roll(&self.plane, kn, &free, hw, &cp);
        let vo = [-wr[0], -wr[1], -self.a * kd[2]];
        let mut dy = [0.0; N];
        dy[..CONTROLLED].copy_from_slice(&[
            kd[0], kd[1], kd[2], c.wd[0], c.wd[1], c.wd[2], c.force[0], c.force[1], 0.0, 0.0,
        ]);
        if Self::POSE {
            let (qd, chi) = attitude_rate(w, k, wk, self.spin_ref, y);
            dy[CONTROLLED..].copy_from_slice(&[qd[0], qd[1], qd[2], qd[3], chi, -wr[0], -wr[1]]);
        }
        if let Some(wr) = free.wrench {
            // The centre of mass accelerates with F + the contact force;
            // the actuators' power F·v_O + τ·w (§actuators; the contact force does
            // no work while rolling).
            dy[VEL] += wr.0[0];
            dy[VEL + 1] += wr.0[1];
            dy[WA] = body::power(wr, vo, w);
        }
        Eval {
            dy,
            normal: c.normal,
            friction: c.friction,
            slip: [0.0, 0.0],
            v: vo,
            torque: c.torque,
        }
    }

    /// The state put on the Coulomb–Contensou stick by the impulse
    /// ([`body::stick_solve`] with `b = −v_P`, `β = −w_Z`) that
    /// brings the slip and the spin about Z to zero; `v` then the rolling
    /// velocity, the kinetic energy's change added to `W_f` (§contensou).
    pub fn stick_state(&self, y: &[f64; N]) -> [f64; N] {
        let kn = self.kin(y);
        let vp = [y[VEL] + kn.wr[0], y[VEL + 1] + kn.wr[1], 0.0];
        let (imp, m) = body::stick_solve(&self.body.inertia, kn.k, kn.r, scale(-1.0, vp), -kn.w[2]);
        let w = add(
            kn.w,
            self.inv_inertia(kn.k, add(cross(kn.r, imp), [0.0, 0.0, m])),
        );
        let mut ys = *y;
        // w_Z is zero by construction: held so exactly, not to rounding.
        ys[OMEGA..OMEGA + 3].copy_from_slice(&[w[0], w[1], 0.0]);
        let v = self.rolling_velocity(&ys);
        ys[VEL] = v[0];
        ys[VEL + 1] = v[1];
        ys[WF] += self.kinetic(&ys) - self.kinetic(y);
        ys
    }

    /// Stick margin while rolling: `μ |N| − |F_f|` (scaled force).
    pub fn stick_margin(&self, e: &Eval<N>) -> f64 {
        self.plane.stick_margin(e.normal, e.friction)
    }

    /// Jellett's J = −L·r in scaled units (J / (m R³ / T)).
    pub fn jellett_scaled(&self, y: &[f64; N]) -> f64 {
        let kn = self.kin(y);
        -dot(self.inertia(kn.k, kn.w), kn.r)
    }

    /// Total energy in scaled units, with the velocity `e.v`.
    pub fn energy_scaled(&self, y: &[f64; N], e: &Eval<N>) -> f64 {
        self.energy_with(y, e.v)
    }

    /// Total energy in scaled units with the centre-of-mass velocity `v`.
    fn energy_with(&self, y: &[f64; N], v: V3) -> f64 {
        let kn = self.kin(y);
        let en = 0.5 * dot(v, v)
            + 0.5 * dot(kn.w, self.inertia(kn.k, kn.w))
            + self.g * (1.0 - self.a * kn.k[2]);
        // The wells' potential U(θ) (§wells; nothing without wells, and θ,
        // an `atan2` the compiler cannot drop, only computed with them).
        let wells = self.plane.wells();
        if wells.is_empty() {
            return en;
        }
        crate::physics::forces::wells::with_potential(wells, en, Self::theta(y))
    }

    /// The Euler-angle quantities `(θ, θ̇, Ω, ω)` (scaled rates) and the
    /// precessing frame `(x̂, ŷ)` at a state. `Ω` is reported as 0 where
    /// `|k_h| < 1e-12` (the axis vertical: Ω undefined).
    pub fn euler(&self, y: &[f64; N]) -> ((f64, f64, f64, f64), (V3, V3)) {
        let kn = self.kin(y);
        let (xh, yh) = Self::frame(kn.k);
        let kh2 = kn.k[0] * kn.k[0] + kn.k[1] * kn.k[1];
        let om = if kh2.sqrt() < 1e-12 {
            0.0
        } else {
            (kn.k[0] * kn.kd[1] - kn.k[1] * kn.kd[0]) / kh2
        };
        ((Self::theta(y), dot(kn.w, yh), om, kn.wk), (xh, yh))
    }

    /// The initial spin `ω₀ = n·k` (scaled; 0 with `method = "brownian"`),
    /// the rate the spin angle is measured from: `ψ = ω₀ t + χ`.
    pub fn spin_reference(&self) -> f64 {
        self.spin_ref
    }

    /// The attitude at scaled time `t`, a unit quaternion body → lab
    /// `(w, x, y, z)`: the untwisted frame `p` (normalised) turned onto the
    /// integrated axis `k` by the smallest rotation
    /// (`observe::attitude_with_axis`: it agrees with θ to rounding), then
    /// about the body axis by the spin angle `ψ = ω₀ t + χ`,
    /// `q = p ⊗ (cos ψ/2, 0, 0, sin ψ/2)`. `ω₀ t` is one rounded product, so
    /// the angle keeps its precision at any number of turns (its absolute
    /// error is that of `t` itself times ω₀; docs/physics.md#position).
    /// Only for the state that carries the pose ([`Vector::POSE`]; it
    /// panics on the motion's state alone).
    pub fn attitude(&self, t: f64, y: &[f64; N]) -> [f64; 4] {
        assert!(Self::POSE, "the attitude of a state without the pose");
        let p = crate::observe::attitude_with_axis(
            [y[QUAT], y[QUAT + 1], y[QUAT + 2], y[QUAT + 3]],
            [y[K], y[K + 1], y[K + 2]],
        );
        let psi = self.spin_ref * t + y[TWIST];
        let (s, c) = (0.5 * psi).sin_cos();
        crate::observe::quat_mul(p, [c, 0.0, 0.0, s])
    }

    /// The output row at scaled time `t`.
    pub fn sample_at(&self, t: f64, y: &[f64; N]) -> Sample {
        let sc = self.scales;
        let (tu, vu) = (sc.time, sc.velocity());
        let ((theta, thd, om, w), (xh, yh)) = self.euler(y);
        let e = self.eval(y).ok();
        let (v, normal, slip, energy) = match &e {
            Some(e) => (e.v, e.normal, e.slip, self.energy_scaled(y, e)),
            None => {
                // Only the sliding evaluation fails (no consistent normal
                // force: a Painlevé case, the run's failure): N is undefined
                // there, the velocity (v_Z = −a k̇_Z) and the energy are not.
                let v = [y[VEL], y[VEL + 1], -self.a * self.kin(y).kd[2]];
                (v, f64::NAN, self.slip_of(y), self.energy_with(y, v))
            }
        };
        // Position and attitude (docs/physics.md#position); without the
        // pose (`N = CONTROLLED`) NaN, not computed (the driver's
        // finiteness check skips them, `Sample::first_non_finite_of`).
        let [x, yy, z, xp, yp] = if Self::POSE {
            let (l, a) = (sc.length, self.a);
            // The unit axis (|k| = 1 holds only to the integration error), as θ.
            let k = [y[K], y[K + 1], y[K + 2]];
            let nk = (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
            let k = [k[0] / nk, k[1] / nk, k[2] / nk];
            let (x, yy) = (y[POS] * l, y[POS + 1] * l);
            [
                x,
                yy,
                (1.0 - a * k[2]) * l,
                x + a * k[0] * l,
                yy + a * k[1] * l,
            ]
        } else {
            [f64::NAN; 5]
        };
        let q = if Self::POSE {
            self.attitude(t, y)
        } else {
            [f64::NAN; 4]
        };
        Sample {
            t: t * tu,
            theta,
            theta_dot: thd / tu,
            precession: om / tu,
            spin: w / tu,
            ux: dot(v, xh) * vu,
            uy: dot(v, yh) * vu,
            uz: v[2] * vu,
            normal: normal * sc.force(),
            slip: slip[0].hypot(slip[1]) * vu,
            jellett: self.jellett_scaled(y) * sc.inertia() * sc.length / tu,
            energy: energy * sc.energy(),
            work_friction: y[WF] * sc.energy(),
            work_applied: y[WA] * sc.energy(),
            hx: self.plane.applied()[0] * sc.force(),
            hy: self.plane.applied()[1] * sc.force(),
            rolling: (self.plane.mode == Mode::Rolling) as u8,
            x,
            y: yy,
            z,
            qw: q[0],
            qx: q[1],
            qy: q[2],
            qz: q[3],
            xp,
            yp,
        }
    }

    /// The state in SI units, for error messages.
    pub fn describe(&self, y: &[f64]) -> String {
        let tu = self.scales.time;
        let vu = self.scales.velocity();
        let h = crate::human::s4;
        format!(
            "state: k = ({}, {}, {}), w = ({}, {}, {}) rad/s, v = ({}, {}) m/s",
            h(y[K]),
            h(y[K + 1]),
            h(y[K + 2]),
            h(y[OMEGA] / tu),
            h(y[OMEGA + 1] / tu),
            h(y[OMEGA + 2] / tu),
            h(y[VEL] * vu),
            h(y[VEL + 1] * vu)
        )
    }
}

impl<const N: usize> OdeSystem<N> for Vector<N> {
    type Error = ModelError;
    const CONTROLLED: usize = CONTROLLED;
    /// `k, w, v` and the works (controlled), `p`: `χ` and the position are
    /// read by no derivative.
    /// Without the pose: `..CONTROLLED`.
    const STAGE_READ: &'static [std::ops::Range<usize>] = if N > CONTROLLED {
        STAGE_POSE
    } else {
        STAGE_MOTION
    };
    /// The events (`model::on_plane`: θ, θ̇'s sign, the spin, N, the slip,
    /// the stick margin) read `k, w, v` only.
    const EVENT_READ: usize = CONTROLLED;

    /// `∂ṗ/∂p = ½ L(w_⊥)` (left multiplication by `(0, w − (w·k) k)`); `χ`
    /// and the position read no quadrature.
    fn quadrature_jacobian(&self, _t: f64, y: &[f64; N], _f: &[f64; N], jac: &mut [[f64; N]; N]) {
        if !Self::POSE {
            return;
        }
        let (w, k) = (
            [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]],
            [y[K], y[K + 1], y[K + 2]],
        );
        let wk = dot(w, k);
        let w = [w[0] - wk * k[0], w[1] - wk * k[1], w[2] - wk * k[2]];
        let l = [
            [0.0, -w[0], -w[1], -w[2]],
            [w[0], 0.0, -w[2], w[1]],
            [w[1], w[2], 0.0, -w[0]],
            [w[2], -w[1], w[0], 0.0],
        ];
        for (i, row) in l.iter().enumerate() {
            for (j, v) in row.iter().enumerate() {
                jac[QUAT + i][QUAT + j] = 0.5 * v;
            }
        }
    }

    fn begin_segment(&mut self, t: f64, _y: &[f64; N]) {
        self.latch_force(t);
    }

    /// Five normals per half step: `v_x, v_y` and the three rotational
    /// modes (see `ou_step`).
    const NOISE: usize = 5;

    fn thermostat(&mut self, y: &mut [f64; N], h: f64, xi: &[f64]) {
        self.ou_step(y, h, xi);
    }

    fn overdamped_step(
        &mut self,
        t: f64,
        y: &mut [f64; N],
        h: f64,
        xi: &[f64],
    ) -> Result<(), ModelError> {
        self.brownian_step(t, y, h, xi)
    }

    fn rhs(&mut self, _t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), ModelError> {
        self.plane.start_evaluation()?;
        *dy = self.eval_now(y)?.dy;
        Ok(())
    }

    /// `rhs`, the evaluation kept in [`Vector::eval`]'s cache: the driver's
    /// events and observers read the accepted state next (the normal
    /// force, the energy), which then costs no second evaluation.
    fn rhs_accepted(&mut self, _t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), ModelError> {
        self.plane.start_evaluation()?;
        let e = self.eval_now(y)?;
        *dy = e.dy;
        *self.accepted.get_mut() = Some(CacheEntry::new(
            y,
            self.cache_inputs(),
            self.plane.slip_ref.get(),
            e,
        ));
        Ok(())
    }
}

impl<const N: usize> super::ContactModel<N> for Vector<N> {
    fn build(sc: &Scenario) -> Self {
        Vector::with_state(sc)
    }
    fn scales(&self) -> Scales {
        self.scales
    }
    fn initial_state(&self, i: &Initial) -> [f64; N] {
        self.scale_state(i)
    }
    fn plane(&self) -> &ContactState {
        &self.plane
    }
    fn plane_mut(&mut self) -> &mut ContactState {
        &mut self.plane
    }
    fn slip_of(&self, y: &[f64; N]) -> [f64; 2] {
        Vector::slip_of(self, y)
    }
    fn spin_z(&self, y: &[f64; N]) -> f64 {
        y[OMEGA + 2]
    }
    fn to_rolling(&self, y: &[f64; N]) -> [f64; N] {
        let mut yr = *y;
        let v = self.rolling_velocity(y);
        yr[VEL] = v[0];
        yr[VEL + 1] = v[1];
        yr
    }
    fn contact_forces(&self, y: &[f64; N]) -> Result<(f64, [f64; 2]), ModelError> {
        self.with_eval(y, |e| (e.normal, e.friction))
    }
    fn contact_wrench(&self, y: &[f64; N]) -> Result<(f64, [f64; 2], f64), ModelError> {
        self.with_eval(y, |e| (e.normal, e.friction, e.torque))
    }
    fn to_stick(&self, y: &[f64; N]) -> [f64; N] {
        self.stick_state(y)
    }
    fn theta(&self, y: &[f64; N]) -> f64 {
        Vector::theta(y)
    }
    fn cos_theta(&self, y: &[f64; N]) -> f64 {
        // k_Z/|k|: a few ulps from the cosine of `theta`'s angle.
        let n2 = y[K] * y[K] + y[K + 1] * y[K + 1] + y[K + 2] * y[K + 2];
        y[K + 2] / n2.sqrt()
    }
    fn above_half_pi(&self, y: &[f64; N]) -> f64 {
        // θ − π/2 has the sign and the zero of −k_Z (no atan2 per step).
        -y[K + 2]
    }
    fn theta_rate(&self, y: &[f64; N]) -> f64 {
        // θ̇ = −k̇_Z / sin θ: the same sign and zeros for 0 < θ < π.
        -(y[OMEGA] * y[K + 1] - y[OMEGA + 1] * y[K])
    }
    fn spin(&self, y: &[f64; N]) -> f64 {
        y[K] * y[OMEGA] + y[K + 1] * y[OMEGA + 1] + y[K + 2] * y[OMEGA + 2]
    }
    fn jellett_scaled(&self, y: &[f64; N]) -> f64 {
        Vector::jellett_scaled(self, y)
    }
    fn energy_scaled(&self, y: &[f64; N]) -> Option<f64> {
        self.with_eval(y, |e| e.v)
            .ok()
            .map(|v| self.energy_with(y, v))
    }
    fn work_scaled(&self, y: &[f64; N]) -> f64 {
        y[WF] + y[WA]
    }
    fn axial(&self) -> f64 {
        self.ic
    }
    fn dop853_beta(&self) -> f64 {
        DOP853_BETA
    }
    fn dop853_stability_cap(&self) -> bool {
        DOP853_STABILITY_CAP
    }
    const HAS_POSE: bool = N > CONTROLLED;
    fn sample(&self, t: f64, y: &[f64; N]) -> Sample {
        self.sample_at(t, y)
    }
    fn describe_state(&self, y: &[f64]) -> String {
        self.describe(y)
    }
    fn axis_norm_sq(&self, y: &[f64]) -> Option<f64> {
        let k = y.get(K..K + 3)?;
        Some(k[0] * k[0] + k[1] * k[1] + k[2] * k[2])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bits of everything an evaluation gives.
    fn bits(e: &Eval) -> Vec<u64> {
        let mut b: Vec<u64> = e.dy.iter().map(|x| x.to_bits()).collect();
        b.extend([e.normal, e.friction[0], e.friction[1], e.slip[0], e.slip[1]].map(f64::to_bits));
        b.extend(e.v.map(f64::to_bits));
        b.push(e.torque.to_bits());
        b
    }

    /// The solutions specialised on the terms present (`PLAIN`, `ONLY_H`,
    /// the regularised law as a type: `Vector::eval_now`) are the general
    /// path's, bit for bit (the specialisation may only drop the tests that
    /// find absent terms): both laws, with and without `H`, sliding and
    /// rolling, at 400 states spread over axes, spins, slips and attitudes
    /// (a fixed sequence), the axis vertical included.
    #[test]
    fn specialised_terms_are_the_general_path_bit_for_bit() {
        let law = |name| match name {
            "regularized" => "friction_law = \"regularized\"\nfriction_eps = 1e-3",
            _ => "friction_law = \"coulomb\"",
        };
        let force = "[[force]]\nhx = 2e-3\nhy = -7e-4\nstart = 0.0\nstop = 1.0\n";
        let mut uniform = crate::testing::uniform_sequence(0x9e37_79b9_7f4a_7c15);
        let mut next = move || uniform() * 2.0 - 1.0;
        for name in ["regularized", "coulomb"] {
            for with_h in [false, true] {
                let text = format!(
                    "preset = \"classical\"\n{}[surface]\n{}\n",
                    if with_h { force } else { "" },
                    law(name)
                );
                let sc = Scenario::from_toml_str(&text).unwrap();
                let mut m = Vector::new(&sc);
                m.latch_force(0.0);
                let f = m.plane.forces();
                assert_eq!(
                    (f.nothing_applied(), f.only_horizontal()),
                    (!with_h, true),
                    "{text}"
                );
                for i in 0..400 {
                    let mut y = [0.0; DIM];
                    let (th, ph) = if i == 0 {
                        (0.0, 0.0)
                    } else {
                        (1.6 * (next() + 1.0), 3.2 * next())
                    };
                    y[K..K + 3].copy_from_slice(&[
                        th.sin() * ph.cos(),
                        th.sin() * ph.sin(),
                        th.cos(),
                    ]);
                    for x in &mut y[OMEGA..QUAT] {
                        *x = 30.0 * next();
                    }
                    let q = [next(), next(), next(), next()];
                    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
                    for j in 0..4 {
                        y[QUAT + j] = q[j] / n;
                    }
                    for mode in [Mode::Sliding, Mode::Rolling] {
                        m.plane.mode = mode;
                        let kn = m.kin(&y);
                        let general = match mode {
                            Mode::Sliding => m.eval_sliding::<_, GENERAL>(&m.plane, &y, &kn),
                            Mode::Rolling => Ok(m.eval_rolling::<GENERAL>(&y, &kn)),
                        };
                        let special = m.eval_now(&y);
                        match (general, special) {
                            (Ok(g), Ok(s)) => {
                                assert_eq!(bits(&g), bits(&s), "{name} H {with_h} {mode:?} {y:?}")
                            }
                            (Err(_), Err(_)) => {}
                            (g, s) => panic!("{name} H {with_h} {mode:?}: {g:?} against {s:?}"),
                        }
                    }
                }
            }
        }
    }

    /// The cache's slip-reference rule (`contact::same_continuation`): an
    /// evaluation cached under the reference `r` and read under another
    /// `d` is, bit for bit, a fresh evaluation under `d`: exact Coulomb
    /// law, sliding, 300 states of the classical top, each read under
    /// `d = r`, `−r`, a perpendicular and a random direction; both the
    /// relaxed hit and the miss occur. Fails if the rule keeps an
    /// evaluation whose continuation test flipped.
    #[test]
    fn cached_evaluation_is_a_fresh_one_under_a_moved_slip_reference() {
        let sc = Scenario::classical();
        let mut m = Vector::new(&sc);
        m.latch_force(0.0);
        assert_eq!(m.plane.mode, Mode::Sliding);
        let y0 = m.scale_state(&sc.initial);
        let mut uniform = crate::testing::uniform_sequence(0x2545_f491_4f6c_dd1d);
        let mut next = move || uniform() * 2.0 - 1.0;
        let mut counts = (0, 0);
        for _ in 0..300 {
            let mut y = y0;
            for x in &mut y[OMEGA..WF] {
                *x += 3.0 * next();
            }
            let read = |r, d| {
                m.plane.slip_ref.set(r);
                let first = m.eval(&y).ok()?;
                m.plane.slip_ref.set(d);
                let cached = m.eval(&y).unwrap();
                let fresh = m.eval_now(&y).unwrap();
                assert_eq!(bits(&cached), bits(&fresh), "y {y:?} r {r:?} d {d:?}");
                Some(first.slip)
            };
            super::super::contact::read_under_moved_references(&mut next, read, &mut counts);
        }
        assert!(counts.0 > 100 && counts.1 > 100, "{counts:?}");
    }

    /// The initial axis reads back as the given θ, bit for bit, and is a
    /// unit vector to rounding, at 100 001 values over [0, π]. (Stepping
    /// `sin θ` alone missed 4 of them, near 0.07 rad.)
    #[test]
    fn initial_axis_reads_back_exactly() {
        let n = 100_000;
        let mut missed = Vec::new();
        for i in 0..=n {
            let theta = std::f64::consts::PI * i as f64 / n as f64;
            let (s, c) = axis(theta);
            let (s0, _) = theta.sin_cos();
            assert!((s - s0).abs() <= 8.0 * f64::EPSILON * s0.max(f64::MIN_POSITIVE));
            assert!((s * s + c * c - 1.0).abs() < 4.0 * f64::EPSILON);
            if s.atan2(c) != theta {
                missed.push(theta);
            }
        }
        assert!(missed.is_empty(), "{missed:?}");
        assert_eq!(axis(0.1).0.atan2(axis(0.1).1), 0.1);
        assert_eq!(axis(0.0), (0.0, 1.0));
    }
}
