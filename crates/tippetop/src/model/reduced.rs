//! The paper's Euler-angle model (App. A), derived afresh in
//! `docs/physics.md` §kinematics–§normal-force, with the normal force solved together with θ̈.
//!
//! State (scaled units, see [`Scales`]):
//! `[θ, θ̇, Ω, ω, u_x, u_y, W_f, W_a, φ, ψ, x, y, c_φ, s_φ]`
//! where `W_f`, `W_a` are the work done so far by friction and by the
//! applied force (integrated alongside so the energy balance can be checked
//! to the integrator's accuracy), and `φ, ψ, x, y, c_φ, s_φ` are quadratures
//! outside the error norm ([`CONTROLLED`]): the precession and spin angles
//! (`φ̇ = Ω`, `ψ̇ = ω − Ω cos θ`), the centre of mass's lab position
//! (`ẋ + i ẏ = (c_φ + i s_φ)(u_x + i u_y)`) and the precession's direction
//! `(c_φ, s_φ) ≈ (cos φ, sin φ)`, carried as `ċ_φ = −s_φ Ω`, `ṡ_φ = c_φ Ω` so
//! that the right-hand side takes no sine or cosine of φ (docs/physics.md
//! §position).
//!
//! Two modes: [`Mode::Sliding`] (friction from the friction law) and
//! [`Mode::Rolling`] (exact Coulomb law only: slip held at zero, the
//! friction is the constraint force, §normal-force of docs/physics.md).

use std::cell::RefCell;

use super::ContactState;
use super::contact::{same_bits, same_continuation};
/// The shared types, re-exported where they used to live.
pub use super::{Mode, ModelError};
pub use crate::physics::units::Scales;
use crate::{Scenario, Top, integrate::OdeSystem};

/// Number of state components.
pub const DIM: usize = 14;
/// Number of components under error control (`θ … W_a`); the quadratures
/// `φ, ψ, x, y, c_φ, s_φ` follow ([`OdeSystem::CONTROLLED`]).
pub const CONTROLLED: usize = 8;
/// Index of θ.
pub const TH: usize = 0;
/// Index of θ̇.
pub const THD: usize = 1;
/// Index of Ω.
pub const OM: usize = 2;
/// Index of ω.
pub const W: usize = 3;
/// Index of u_x.
pub const UX: usize = 4;
/// Index of u_y.
pub const UY: usize = 5;
/// Index of the friction work.
pub const WF: usize = 6;
/// Index of the applied-force work.
pub const WA: usize = 7;
/// Index of the precession angle φ (quadrature).
pub const PHI: usize = 8;
/// Index of the spin angle ψ (quadrature).
pub const PSI: usize = 9;
/// Index of the centre of mass's lab x (quadrature; y follows).
pub const POS: usize = 10;
/// Index of `c_φ ≈ cos φ` (quadrature; `s_φ ≈ sin φ` follows). Not
/// normalised: `c_φ² + s_φ²` drifts from 1 by the integration error
/// (docs/physics.md#position gives the measured size).
pub const DIR: usize = 12;

/// The quadratures' derivatives `[φ̇, ψ̇, ẋ, ẏ, ċ_φ, ṡ_φ]` at a state, with
/// the centre-of-mass velocity `u` in the precessing frame (the constraint
/// value while rolling) and `c = cos θ`. Linear in the quadratures: the
/// velocity is rotated by the carried `(c_φ, s_φ)`, not by `sin_cos(φ)`.
#[inline(always)]
fn quadratures<const N: usize>(y: &[f64; N], c: f64, u: [f64; 2]) -> [f64; 6] {
    let (cp, sp) = (y[DIR], y[DIR + 1]);
    let om = y[OM];
    [
        om,
        y[W] - om * c,
        u[0] * cp - u[1] * sp,
        u[0] * sp + u[1] * cp,
        -sp * om,
        cp * om,
    ]
}

/// [`OdeSystem::STAGE_READ`] with the pose: the controlled components and
/// `(c_φ, s_φ)` (`φ, ψ` and the position are read by no derivative).
const STAGE_POSE: &[std::ops::Range<usize>] = &[0..CONTROLLED, DIR..DIM];
/// [`OdeSystem::STAGE_READ`] without the pose: the controlled components.
#[allow(clippy::single_range_in_vec_init)]
const STAGE_MOTION: &[std::ops::Range<usize>] = &[0..CONTROLLED];

/// The chatter criterion, re-exported where it used to live.
pub use super::contact::CHATTER_REVERSALS;

/// |sin θ| below which the reduced equations are declared singular
/// (defined with the initial state, which is checked against it).
pub use crate::input::initial::SIN_GUARD;

/// θ (with `s = sin θ`) is at a pole of the Euler angles or past one:
/// `sin θ < SIN_GUARD` or θ outside `(0, π)`. A step can jump over the
/// pole (θ̇ large, θ near 0 or π), to where `sin θ` is of the right size
/// again but the angles no longer describe the motion; the model stops there
/// as it does at the pole.
#[inline(always)]
fn at_pole(theta: f64, s: f64) -> bool {
    !(theta > 0.0 && theta < std::f64::consts::PI && s >= SIN_GUARD)
}

/// Everything the right-hand side computes at one state (scaled units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Eval<const N: usize = DIM> {
    /// State derivative.
    pub dy: [f64; N],
    /// Normal force N.
    pub normal: f64,
    /// Friction force on the top (x, y), excluding the applied force.
    pub friction: [f64; 2],
    /// Slip velocity v_P (x, y) (zero while rolling).
    pub slip: [f64; 2],
    /// Centre-of-mass velocity (x, y, z) (constraint values while rolling).
    pub u: [f64; 3],
    /// Drilling torque about Z (Coulomb–Contensou friction: the law's
    /// while sliding, the constraint torque in the stick; 0 otherwise).
    pub torque: f64,
}

/// The last successful evaluation made by [`Reduced::eval`] (not by
/// [`OdeSystem::rhs`], whose stages are never asked for again), with every
/// input it depended on. At each accepted step the driver evaluates the
/// model at the step end for the N = 0 event, again for the running
/// diagnostics (energy), and takes sin θ, cos θ there for Jellett's J and
/// the slip: the later calls get this copy instead of recomputing it. The
/// key is compared bit for bit, so the result is the one a fresh evaluation
/// would give.
#[derive(Debug, Clone, Copy)]
struct LastEval<const N: usize> {
    /// The state, as bits.
    y: [u64; N],
    /// Mode at the evaluation.
    mode: Mode,
    /// Latched normal-force branch.
    branch: Option<bool>,
    /// Latched force and slip hint ([`inputs_key`]).
    key: [u64; 6],
    /// The slip reference the evaluation saw
    /// ([`super::contact::same_continuation`]).
    slip_ref: [f64; 2],
    /// sin θ, cos θ.
    sc: (f64, f64),
    eval: Eval<N>,
}

/// Everything besides the state that an evaluation depends on and that can
/// change between evaluations (the model constants cannot).
fn inputs_key(h: [f64; 3], hint: [f64; 2], generation: u64) -> [u64; 6] {
    [
        h[0].to_bits(),
        h[1].to_bits(),
        h[2].to_bits(),
        hint[0].to_bits(),
        hint[1].to_bits(),
        generation,
    ]
}

fn bits<const N: usize>(y: &[f64; N]) -> [u64; N] {
    y.map(f64::to_bits)
}

/// The reduced model as an ODE system in scaled units.
#[derive(Debug, Clone)]
pub struct Reduced<const N: usize = DIM> {
    /// Unit system.
    pub scales: Scales,
    /// Offset a/R.
    a: f64,
    /// A/(m R²).
    ia: f64,
    /// C/(m R²).
    ic: f64,
    /// 1/ia, 1/ic (the right-hand side multiplies by these instead of
    /// dividing: rounding-level differences, fewer divisions on its
    /// latency-bound dependency chain).
    inv_ia: f64,
    inv_ic: f64,
    /// g in scaled units.
    g: f64,
    /// Friction law, contact, applied force, sliding/rolling and the
    /// driver's flags (shared with the vector model).
    pub plane: ContactState,
    /// The SI top (for observables).
    pub top: Top,
    /// g \[m/s²\].
    pub gravity_si: f64,
    /// The orientation wells in SI (for the energy column; §wells).
    wells_si: Vec<crate::physics::forces::wells::Well>,
    /// The last evaluation made by `eval` (see [`LastEval`]).
    last: RefCell<Option<LastEval<N>>>,
}

impl Reduced {
    /// Build the scaled model of a scenario (the pose carried: [`DIM`]).
    pub fn new(sc: &Scenario) -> Self {
        Self::with_state(sc)
    }
}

impl<const N: usize> Reduced<N> {
    /// True if the state carries the pose (`N = DIM`): `φ, ψ`, the
    /// position and `(c_φ, s_φ)`. Without it (`N = CONTROLLED`) the
    /// motion's eight components alone, the same bits
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
        Reduced {
            scales,
            a: sc.top.offset / scales.length,
            ia,
            ic,
            inv_ia: 1.0 / ia,
            inv_ic: 1.0 / ic,
            g: sc.surface.gravity * scales.time * scales.time / scales.length,
            plane: ContactState::new(sc, &scales),
            top: sc.top,
            gravity_si: sc.surface.gravity,
            wells_si: sc.wells(),
            last: RefCell::new(None),
        }
    }

    /// Latched applied force (H_x, H_y) in scaled units.
    pub fn applied(&self) -> [f64; 2] {
        self.plane.applied()
    }

    /// Latch the applied force in effect at scaled time `t`.
    pub fn latch_force(&mut self, t: f64) {
        self.plane.latch_force(t, &self.scales);
    }

    /// Scaled state from SI initial values.
    pub fn scale_state(&self, i: &crate::Initial) -> [f64; N] {
        let y = self.scale_pose_state(i);
        std::array::from_fn(|j| y[j])
    }

    /// [`Reduced::scale_state`] with the pose ([`DIM`] components).
    fn scale_pose_state(&self, i: &crate::Initial) -> [f64; DIM] {
        let t = self.scales.time;
        let v = self.scales.velocity();
        [
            i.theta,
            i.theta_dot * t,
            i.precession * t,
            i.spin * t,
            i.ux / v,
            i.uy / v,
            0.0,
            0.0,
            // φ = the heading (0: the axis tilts towards the lab X), ψ = 0,
            // x = y = 0, (c_φ, s_φ) = (cos φ, sin φ).
            i.heading,
            0.0,
            0.0,
            0.0,
            i.heading.cos(),
            i.heading.sin(),
        ]
    }

    /// `θ.sin_cos()`, taken from the last `eval` when it was at the same θ
    /// (the same value either way).
    #[inline]
    fn sin_cos(&self, th: f64) -> (f64, f64) {
        match &*self.last.borrow() {
            Some(l) if l.y[TH] == th.to_bits() => l.sc,
            _ => th.sin_cos(),
        }
    }

    /// Slip velocity at a state (scaled), from the state's u (sliding).
    pub fn slip_of(&self, y: &[f64; N]) -> [f64; 2] {
        let (s, c) = self.sin_cos(y[TH]);
        let h = 1.0 - self.a * c;
        [
            y[UX] - h * y[THD],
            y[UY] + s * (y[W] - y[OM] * c + self.a * y[OM]),
        ]
    }

    /// Centre-of-mass horizontal velocity that makes the slip zero (rolling constraint).
    pub fn rolling_velocity(&self, y: &[f64; N]) -> [f64; 2] {
        let (s, c) = self.sin_cos(y[TH]);
        let h = 1.0 - self.a * c;
        [h * y[THD], -s * (y[W] - y[OM] * c + self.a * y[OM])]
    }

    /// Evaluate the model at a state in the current mode.
    pub fn eval(&self, y: &[f64; N]) -> Result<Eval<N>, ModelError> {
        self.with_eval(y, |e| *e)
    }

    /// `read` of [`Reduced::eval`]'s evaluation at `y`, read in place (a
    /// cached evaluation is not copied out: the driver's events and
    /// observers read one or two of its fields at every accepted step).
    #[inline(always)]
    fn with_eval<R>(
        &self,
        y: &[f64; N],
        read: impl FnOnce(&Eval<N>) -> R,
    ) -> Result<R, ModelError> {
        let yb = bits(y);
        let p = &self.plane;
        let cp = p.contact_point();
        let key = inputs_key([cp.h[0], cp.h[1], cp.hz], p.slip_hint, p.hint_generation());
        let d = p.slip_ref.get();
        if let Some(l) = &*self.last.borrow() {
            if same_bits(&l.y, &yb)
                && l.mode == self.plane.mode
                && l.branch == p.normal_branch
                && same_bits(&l.key, &key)
                && same_continuation(l.slip_ref, l.eval.slip, d)
            {
                return Ok(read(&l.eval));
            }
        }
        let (s, c) = y[TH].sin_cos();
        let e = self.eval_sc(y, s, c)?;
        let r = read(&e);
        *self.last.borrow_mut() = Some(LastEval {
            y: yb,
            mode: self.plane.mode,
            branch: p.normal_branch,
            key,
            slip_ref: d,
            sc: (s, c),
            eval: e,
        });
        Ok(r)
    }

    /// Keep `e`, the evaluation at `y` with `(s, c) = y[TH].sin_cos()`, in
    /// [`Reduced::eval`]'s cache.
    #[inline(always)]
    fn remember(&mut self, y: &[f64; N], s: f64, c: f64, e: Eval<N>) {
        let p = &self.plane;
        let cp = p.contact_point();
        let key = inputs_key([cp.h[0], cp.h[1], cp.hz], p.slip_hint, p.hint_generation());
        *self.last.get_mut() = Some(LastEval {
            y: bits(y),
            mode: p.mode,
            branch: p.normal_branch,
            key,
            slip_ref: p.slip_ref.get(),
            sc: (s, c),
            eval: e,
        });
    }

    /// `eval` with `(s, c) = y[TH].sin_cos()` given.
    #[inline(always)]
    fn eval_sc(&self, y: &[f64; N], s: f64, c: f64) -> Result<Eval<N>, ModelError> {
        match self.plane.mode {
            Mode::Sliding => self.eval_sliding(y, s, c),
            Mode::Rolling => Ok(self.eval_rolling(y, s, c)),
        }
    }

    #[inline(always)]
    fn eval_sliding(&self, y: &[f64; N], s: f64, c: f64) -> Result<Eval<N>, ModelError> {
        let (th, thd, om, w, ux, uy) = (y[TH], y[THD], y[OM], y[W], y[UX], y[UY]);
        if at_pole(th, s) {
            return Err(ModelError::Singular { theta: th });
        }
        let (a, ia, ic) = (self.a, self.ia, self.ic);
        let (inv_ia, inv_ic) = (self.inv_ia, self.inv_ic);
        let h = 1.0 - a * c;
        let v = [ux - h * thd, uy + s * (w - om * c + a * om)];
        // Off the critical path (independent of the friction): 1/(ia s).
        let inv_ias = inv_ia / s;
        // Coulomb–Contensou (§contensou): the force coefficient and the drilling
        // torque's, from the slip and the spin about Z, n_Z = Ω s² + ω c.
        let nz = om * s * s + w * c;
        let (f, tau) = match self.plane.drilling(v, nz) {
            Some((f, tau)) => (f, Some(tau)),
            None => (self.plane.coefficient(v), None),
        };
        let cp = self.plane.contact_point();
        let [hx, hy] = cp.h;
        // Gyroscopic term of A θ̈, with the wells' torque τ_y = −U′(θ)
        // (docs/physics.md#wells).
        let gyro = self.with_wells(-om * (ic * w - ia * om * c) * s, th);
        let as_ = a * s;
        let q = self.g + a * c * thd * thd + as_ * (gyro + h * hx) * inv_ia;
        // The vertical load h_z at P: Q + h_z D₀, D₀ = 1 + a² s²/A
        // (docs/physics.md#vertical-load).
        let q = cp.closure_q(q, 1.0 + as_ * as_ * inv_ia);
        // N (1 + a s (a s − σ h f_x)/A) = Q, σ the sign of N the friction sees.
        let dp = 1.0 + as_ * (as_ - h * f[0]) * inv_ia;
        let dm = 1.0 + as_ * (as_ + h * f[0]) * inv_ia;
        let normal = self.plane.normal(q, dp, dm, || th)?;
        let nf = self.plane.friction_normal(normal);
        let ff = [-nf * f[0], -nf * f[1]];
        let fx = ff[0] - hx;
        let fy = ff[1] - hy;
        // The vertical force at P is N − h_z (§vertical-load).
        let thdd = (gyro - as_ * cp.vertical_total(normal) - h * fx) * inv_ia;
        let mut omd = (thd * (ic * w - 2.0 * ia * om * c) + (a - c) * fy) * inv_ias;
        let mut wd = s * fy * inv_ic;
        let mut wf = ff[0] * v[0] + ff[1] * v[1];
        let mut torque = 0.0;
        if let Some(tau) = tau {
            // The drilling torque M Z (M = −N_f τ): A s Ω̇ gains M s, C ω̇
            // gains M c, θ̈ and the closure none (Z ⟂ ŷ); its power M n_Z.
            let mz = -nf * tau;
            omd += mz * inv_ia;
            wd += mz * c * inv_ic;
            wf += mz * nz;
            torque = mz;
        }
        let mut dy = [0.0; N];
        dy[..CONTROLLED].copy_from_slice(&[
            thd,
            thdd,
            omd,
            wd,
            om * uy + fx,
            -om * ux + fy,
            wf,
            -hx * v[0] - hy * v[1],
        ]);
        if Self::POSE {
            dy[CONTROLLED..].copy_from_slice(&quadratures(y, c, [ux, uy]));
        }
        Ok(Eval {
            dy,
            normal,
            friction: ff,
            slip: v,
            u: [ux, uy, as_ * thd],
            torque,
        })
    }

    /// Rolling: v_P = 0 held; θ̈, N and the friction solved with the motion
    /// (docs/physics.md#normal-force). Regular at every θ except through the Ω
    /// equation's 1/sin θ, which the caller guards.
    #[inline(always)]
    fn eval_rolling(&self, y: &[f64; N], s: f64, c: f64) -> Eval<N> {
        let (thd, om, w) = (y[THD], y[OM], y[W]);
        let (a, ia, ic) = (self.a, self.ia, self.ic);
        let (inv_ia, inv_ic) = (self.inv_ia, self.inv_ic);
        let inv_ias = inv_ia / s;
        let h = 1.0 - a * c;
        let weff = w - om * c + a * om;
        let ux = h * thd;
        let uy = -s * weff;
        let gyro = self.with_wells(-om * (ic * w - ia * om * c) * s, y[TH]);
        let thdd = (gyro - a * s * self.g - a * s * thd * thd + h * om * uy)
            / (ia + a * a * s * s + h * h);
        // The plane's reaction: the vertical constraint force plus the
        // load h_z (§vertical-load).
        let cp = self.plane.contact_point();
        let normal = cp.reaction(self.g + a * c * thd * thd + a * s * thdd);
        let fx = h * thdd + a * s * thd * thd - om * uy;
        let p = thd * (ic * w - 2.0 * ia * om * c);
        // The point law's expression, in its order of operations (bit for
        // bit with the rolling equations before the stick was added).
        let b1 = om * ux
            - c * thd * weff
            - (a - c) * thd * (ic * w - 2.0 * ia * om * c) * inv_ia
            - om * s * s * thd;
        let a11 = 1.0 + s * s * inv_ic + (a - c) * (a - c) * inv_ia;
        let (fy, torque) = if self.plane.is_contensou() {
            // The Coulomb–Contensou stick (§contensou): n_Z = Ω s² + ω c held at
            // zero too, the drilling torque M about Z a fourth unknown.
            // With A s Ω̇ = P + (a − c) F_y + M s and C ω̇ = s F_y + M c,
            // the ŷ rolling equation and d n_Z/dt = 0 are the symmetric
            // system [a11 a12; a12 a22] (F_y, M) = (b1, b2).
            let a12 = s * (a - c) * inv_ia + s * c * inv_ic;
            let a22 = s * s * inv_ia + c * c * inv_ic;
            let b2 = s * thd * w - 2.0 * om * s * c * thd - s * p * inv_ia;
            let det = a11 * a22 - a12 * a12;
            ((b1 * a22 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det)
        } else {
            (b1 / a11, 0.0)
        };
        let [hx, hy] = cp.h;
        let ff = [fx + hx, fy + hy];
        let omd = (p + (a - c) * fy + torque * s) * inv_ias;
        let wd = (s * fy + torque * c) * inv_ic;
        let mut dy = [0.0; N];
        dy[..CONTROLLED].copy_from_slice(&[
            thd,
            thdd,
            omd,
            wd,
            om * uy + fx,
            -om * ux + fy,
            0.0,
            0.0,
        ]);
        if Self::POSE {
            dy[CONTROLLED..].copy_from_slice(&quadratures(y, c, [ux, uy]));
        }
        Eval {
            dy,
            normal,
            friction: ff,
            slip: [0.0, 0.0],
            u: [ux, uy, a * s * thd],
            torque,
        }
    }

    /// The state put on the Coulomb–Contensou stick by the impulse that
    /// brings the slip and the spin about Z to zero (§contensou): in the
    /// precessing frame `k = (s, 0, c)`, `w = ((ω − Ω c) s, θ̇, n_Z)`,
    /// `r = a k − Z`, the impulse of [`crate::physics::body::stick_solve`]
    /// (`b = −v_P`, `β = −n_Z`) changes `u` by its horizontal part and `w`
    /// by `I⁻¹ (r × Π + M Z)`; back to `θ̇ = w_y`, `ω = w·k`,
    /// `Ω = w_Z − w_x c/s`; `u` then the rolling velocity; the kinetic
    /// energy's change added to `W_f`.
    pub fn stick_state(&self, y: &[f64; N]) -> [f64; N] {
        let (s, c) = y[TH].sin_cos();
        let k = [s, 0.0, c];
        let r = [self.a * s, 0.0, self.a * c - 1.0];
        let w = [(y[W] - y[OM] * c) * s, y[THD], y[OM] * s * s + y[W] * c];
        let v = self.slip_of(y);
        let (imp, m) = crate::physics::body::stick_solve(
            &crate::physics::body::Inertia::new(self.ia, self.ic),
            k,
            r,
            [-v[0], -v[1], 0.0],
            -w[2],
        );
        let torque = [
            r[1] * imp[2] - r[2] * imp[1],
            r[2] * imp[0] - r[0] * imp[2],
            r[0] * imp[1] - r[1] * imp[0] + m,
        ];
        // I⁻¹ x = x/A + (1/C − 1/A)(x·k) k.
        let xk = torque[0] * k[0] + torque[2] * k[2];
        let dinv = self.inv_ic - self.inv_ia;
        let wn = [
            w[0] + torque[0] * self.inv_ia + dinv * xk * k[0],
            w[1] + torque[1] * self.inv_ia,
            w[2] + torque[2] * self.inv_ia + dinv * xk * k[2],
        ];
        let mut ys = *y;
        ys[THD] = wn[1];
        ys[W] = wn[0] * s + wn[2] * c;
        ys[OM] = wn[2] - wn[0] * c / s;
        let u = self.rolling_velocity(&ys);
        ys[UX] = u[0];
        ys[UY] = u[1];
        let kinetic = |y: &[f64; N]| {
            let uz = self.a * s * y[THD];
            0.5 * (y[UX] * y[UX] + y[UY] * y[UY] + uz * uz)
                + 0.5 * self.ia * (y[THD] * y[THD] + y[OM] * y[OM] * s * s)
                + 0.5 * self.ic * y[W] * y[W]
        };
        ys[WF] += kinetic(&ys) - kinetic(y);
        ys
    }

    /// `gyro` plus the wells' torque about ŷ, `τ_y = −U′(θ)` (§wells): it
    /// enters `A θ̈` beside the gyroscopic term, and so the closure's `Q`
    /// (`a s τ_y/A`) and the rolling equation.
    #[inline(always)]
    fn with_wells(&self, gyro: f64, theta: f64) -> f64 {
        crate::physics::forces::wells::with_torque(self.plane.wells(), gyro, theta)
    }

    /// `e + U(θ)`, the wells' potential (scaled; `e` itself without
    /// wells, §wells).
    #[inline]
    fn with_well_potential(&self, e: f64, theta: f64) -> f64 {
        crate::physics::forces::wells::with_potential(self.plane.wells(), e, theta)
    }

    /// Stick margin while rolling: `μ |N| − |F_f|` (scaled force); rolling
    /// ends when it falls through zero.
    pub fn stick_margin(&self, e: &Eval<N>) -> f64 {
        self.plane.stick_margin(e.normal, e.friction)
    }

    /// Jellett's J in scaled units (J / (m R³ / T)).
    pub fn jellett_scaled(&self, y: &[f64; N]) -> f64 {
        let (s, c) = self.sin_cos(y[TH]);
        self.ia * y[OM] * s * s + self.ic * y[W] * (c - self.a)
    }

    /// Total energy in scaled units, using `u` from `e` (constraint values while rolling).
    pub fn energy_scaled(&self, y: &[f64; N], e: &Eval<N>) -> f64 {
        let (s, c) = self.sin_cos(y[TH]);
        let u = e.u;
        let e = 0.5 * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
            + 0.5 * self.ia * (y[THD] * y[THD] + y[OM] * y[OM] * s * s)
            + 0.5 * self.ic * y[W] * y[W]
            + self.g * (1.0 - self.a * c);
        self.with_well_potential(e, y[TH])
    }

    /// C · R in scaled units times the largest |ω| gives the J scale.
    pub fn ic(&self) -> f64 {
        self.ic
    }
}

impl<const N: usize> OdeSystem<N> for Reduced<N> {
    type Error = ModelError;
    const CONTROLLED: usize = CONTROLLED;
    /// The controlled components and `(c_φ, s_φ)`: `φ, ψ` and the position
    /// are read by no derivative.
    /// Without the pose: `..CONTROLLED`.
    const STAGE_READ: &'static [std::ops::Range<usize>] = if N > CONTROLLED {
        STAGE_POSE
    } else {
        STAGE_MOTION
    };

    /// With `(c, s) = (c_φ, s_φ)`: `ẋ = c u_x − s u_y`, `ẏ = s u_x + c u_y`
    /// give `∂ẋ/∂c = u_x`, `∂ẋ/∂s = −u_y`, `∂ẏ/∂c = u_y`, `∂ẏ/∂s = u_x`;
    /// `ċ = −s Ω`, `ṡ = c Ω` give `∂ċ/∂s = −Ω`, `∂ṡ/∂c = Ω`. Nothing reads
    /// φ, ψ, x or y. (The dependence on the controlled Ω and u, the block
    /// below the controlled columns, is in Rodas4P's finite differences.)
    fn quadrature_jacobian(&self, _t: f64, y: &[f64; N], f: &[f64; N], jac: &mut [[f64; N]; N]) {
        if !Self::POSE {
            return;
        }
        // u as the right-hand side used it (the constraint value while
        // rolling); Ω = φ̇.
        let u = match self.plane.mode {
            Mode::Rolling => self.rolling_velocity(y),
            Mode::Sliding => [y[UX], y[UY]],
        };
        let om = f[PHI];
        jac[POS][DIR] = u[0];
        jac[POS][DIR + 1] = -u[1];
        jac[POS + 1][DIR] = u[1];
        jac[POS + 1][DIR + 1] = u[0];
        jac[DIR][DIR + 1] = -om;
        jac[DIR + 1][DIR] = om;
    }

    fn begin_segment(&mut self, t: f64, _y: &[f64; N]) {
        self.latch_force(t);
    }

    fn rhs(&mut self, _t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), ModelError> {
        self.plane.start_evaluation()?;
        // One sin_cos per evaluation (the guard shares it).
        let (s, c) = y[TH].sin_cos();
        if self.plane.mode == Mode::Rolling && at_pole(y[TH], s) {
            return Err(ModelError::Singular { theta: y[TH] });
        }
        *dy = self.eval_sc(y, s, c)?.dy;
        Ok(())
    }

    /// `rhs`, the evaluation kept in [`Reduced::eval`]'s cache for the
    /// driver's events and observers, which read the accepted state next.
    fn rhs_accepted(&mut self, _t: f64, y: &[f64; N], dy: &mut [f64; N]) -> Result<(), ModelError> {
        self.plane.start_evaluation()?;
        let (s, c) = y[TH].sin_cos();
        if self.plane.mode == Mode::Rolling && at_pole(y[TH], s) {
            return Err(ModelError::Singular { theta: y[TH] });
        }
        let e = self.eval_sc(y, s, c)?;
        *dy = e.dy;
        self.remember(y, s, c, e);
        Ok(())
    }
}

impl<const N: usize> super::ContactModel<N> for Reduced<N> {
    fn build(sc: &Scenario) -> Self {
        Reduced::with_state(sc)
    }
    fn scales(&self) -> Scales {
        self.scales
    }
    fn initial_state(&self, i: &crate::Initial) -> [f64; N] {
        self.scale_state(i)
    }
    fn plane(&self) -> &ContactState {
        &self.plane
    }
    fn plane_mut(&mut self) -> &mut ContactState {
        &mut self.plane
    }
    fn slip_of(&self, y: &[f64; N]) -> [f64; 2] {
        Reduced::slip_of(self, y)
    }
    fn spin_z(&self, y: &[f64; N]) -> f64 {
        let (s, c) = self.sin_cos(y[TH]);
        y[OM] * s * s + y[W] * c
    }
    fn to_rolling(&self, y: &[f64; N]) -> [f64; N] {
        let mut yr = *y;
        let u = self.rolling_velocity(y);
        yr[UX] = u[0];
        yr[UY] = u[1];
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
        y[TH]
    }
    fn theta_rate(&self, y: &[f64; N]) -> f64 {
        y[THD]
    }
    fn spin(&self, y: &[f64; N]) -> f64 {
        y[W]
    }
    fn jellett_scaled(&self, y: &[f64; N]) -> f64 {
        Reduced::jellett_scaled(self, y)
    }
    fn energy_scaled(&self, y: &[f64; N]) -> Option<f64> {
        self.with_eval(y, |e| Reduced::energy_scaled(self, y, e))
            .ok()
    }
    fn work_scaled(&self, y: &[f64; N]) -> f64 {
        y[WF] + y[WA]
    }
    fn axial(&self) -> f64 {
        self.ic()
    }
    const HAS_POSE: bool = N > CONTROLLED;
    fn sample(&self, t: f64, y: &[f64; N]) -> crate::Sample {
        let m = self;
        let sc = m.scales;
        let (tu, vu) = (sc.time, sc.velocity());
        let e = m.eval(y).ok();
        let (u, normal, slip) = match &e {
            Some(e) => (e.u, e.normal, e.slip),
            // No consistent normal force (a Painlevé case, the run's
            // failure): N is undefined, the velocity (u_Z = a sin θ θ̇)
            // and so the energy are not.
            None => (
                [y[UX], y[UY], m.a * y[TH].sin() * y[THD]],
                f64::NAN,
                m.slip_of(y),
            ),
        };
        let u_si = [u[0] * vu, u[1] * vu, u[2] * vu];
        let (theta, thd, om, w) = (y[TH], y[THD] / tu, y[OM] / tu, y[W] / tu);
        let h = m.applied();
        // Position and attitude (docs/physics.md#position): the plane is z = 0,
        // the centre of mass at height R − a cos θ, the contact point below
        // the sphere's centre C = O + a k.
        // Without the pose (`N = CONTROLLED`): NaN, not computed (the
        // driver's finiteness check skips them, `Sample::first_non_finite_of`).
        let ([x, yy, z, xp, yp], q) = if Self::POSE {
            let (l, a) = (sc.length, m.a);
            let (s, c) = theta.sin_cos();
            let (sp, cp) = y[PHI].sin_cos();
            let q = crate::observe::attitude_from_euler(y[PHI], theta, y[PSI]);
            let (x, yy) = (y[POS] * l, y[POS + 1] * l);
            (
                [
                    x,
                    yy,
                    (1.0 - a * c) * l,
                    x + a * s * cp * l,
                    yy + a * s * sp * l,
                ],
                q,
            )
        } else {
            ([f64::NAN; 5], [f64::NAN; 4])
        };
        crate::Sample {
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
            jellett: crate::observe::jellett(&m.top, theta, om, w),
            energy: crate::physics::forces::wells::with_potential(
                &m.wells_si,
                crate::observe::energy(&m.top, m.gravity_si, theta, thd, om, w, u_si),
                theta,
            ),
            work_friction: y[WF] * sc.energy(),
            work_applied: y[WA] * sc.energy(),
            hx: h[0] * sc.force(),
            hy: h[1] * sc.force(),
            rolling: (m.plane.mode == Mode::Rolling) as u8,
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
    fn describe_state(&self, y: &[f64]) -> String {
        let tu = self.scales.time;
        let vu = self.scales.velocity();
        let h = crate::human::s4;
        format!(
            "state: theta = {} rad, theta_dot = {} rad/s, Omega = {} rad/s, omega = {} rad/s, ux = {} m/s, uy = {} m/s",
            h(y[TH]),
            h(y[THD] / tu),
            h(y[OM] / tu),
            h(y[W] / tu),
            h(y[UX] * vu),
            h(y[UY] * vu)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ContactMode, FrictionLaw};

    /// The cache's slip-reference rule (`contact::same_continuation`): an
    /// evaluation cached under the reference `r` and read under another
    /// `d` is, bit for bit, a fresh evaluation under `d`. Exact Coulomb law,
    /// sliding, 300 states near the classical preset's start, each read
    /// under `d = r`, `−r`, a perpendicular and a random direction; both the
    /// relaxed hit (`d ≠ r`, the test unchanged) and the miss (the test
    /// flipped) occur. Fails if the rule keeps an evaluation whose
    /// continuation test flipped.
    #[test]
    fn cached_evaluation_is_a_fresh_one_under_a_moved_slip_reference() {
        let sc = Scenario::classical();
        assert!(matches!(sc.surface.law, FrictionLaw::Coulomb));
        let m = Reduced::new(&sc);
        assert_eq!(m.plane.mode, Mode::Sliding);
        let y0 = m.scale_state(&sc.initial);
        let bits = |e: &Eval| -> Vec<u64> {
            let mut b: Vec<u64> = e.dy.iter().map(|x| x.to_bits()).collect();
            b.extend(
                [e.normal, e.friction[0], e.friction[1], e.slip[0], e.slip[1]].map(f64::to_bits),
            );
            b.extend(e.u.map(f64::to_bits));
            b.push(e.torque.to_bits());
            b
        };
        let mut uniform = crate::testing::uniform_sequence(0x2545_f491_4f6c_dd1d);
        let mut next = move || uniform() * 2.0 - 1.0;
        let mut counts = (0, 0);
        for _ in 0..300 {
            let mut y = y0;
            y[TH] = 0.1 + 1.4 * (next() + 1.0);
            for x in &mut y[THD..=UY] {
                *x += 3.0 * next();
            }
            let read = |r, d| {
                m.plane.slip_ref.set(r);
                let first = m.eval(&y).ok()?;
                m.plane.slip_ref.set(d);
                let cached = m.eval(&y).unwrap();
                let (s, c) = y[TH].sin_cos();
                let fresh = m.eval_sc(&y, s, c).unwrap();
                assert_eq!(bits(&cached), bits(&fresh), "y {y:?} r {r:?} d {d:?}");
                Some(first.slip)
            };
            super::super::contact::read_under_moved_references(&mut next, read, &mut counts);
        }
        assert!(counts.0 > 100 && counts.1 > 100, "{counts:?}");
    }

    #[test]
    fn nan_state_is_no_solution_in_bilateral_contact() {
        let mut sc = Scenario::classical();
        sc.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
        sc.surface.contact = ContactMode::Bilateral;
        let m = Reduced::new(&sc);
        let y0 = m.scale_state(&sc.initial);
        assert!(m.eval(&y0).is_ok());
        for i in 0..UY + 1 {
            let mut y = y0;
            y[i] = f64::NAN;
            // Not turned into a finite-looking normal force: every NaN
            // reaches q or d_± and leaves no consistent solution.
            match m.eval(&y) {
                Err(ModelError::Painleve { solutions: 0, .. }) => {}
                // A NaN θ is not in (0, π): the pole guard stops it first.
                Err(ModelError::Singular { .. }) if i == TH => {}
                other => panic!("NaN in component {i}: {other:?}"),
            }
        }
    }
}
