//! The body on a surface, written once in lab vectors (scaled units, m = 1;
//! docs/physics.md#vector-model, docs/architecture.md): a symmetric top
//! whose contact sphere (radius `ρ`, centre `a` along the axis `k` from the
//! centre of mass) touches a [`Surface`]. The vector model
//! ([`crate::model::vector`]) and the rigid model in one-sphere contact
//! ([`crate::model::rigid`]) are coordinate adapters over it: they read
//! their state into [`At`], call [`Body::slide`] or [`Body::roll`] (the
//! rigid model in flight [`Body::free`] and [`Body::angular`]) and write
//! the state derivative in their own layout. Flight, impacts and the stem
//! stay in the rigid model; the reduced model keeps the paper's own
//! equations (an independent check).
//!
//! Here, with `r = P − O` the contact point from the centre of mass,
//! `w` the angular velocity and `k̇ = w × k`:
//!
//! - the free accelerations ([`Body::free`]): gravity, the gyroscopic
//!   `ẇ₀ = −I⁻¹(w × I w) = −((C − A)/A)(w·k) k̇`, and the applied terms by
//!   kind: a couple (the wells' torque, `τ/A`), a body wrench (the
//!   actuators' `F`, `I⁻¹τ`), a force at the contact point (`−H` and the
//!   vertical load `h_z`, [`ContactPointForce`]);
//! - the normal-force closure ([`Body::closure_q`]): `N D(σ) = Q` with
//!   `e = k × Z`, `u = (e × r)/A`, `D(σ) = 1 + a (u_Z − σ f·u)`,
//!   `Q = g − F_Z + a (H·u − ẇ₀·e − (w × k̇)_Z)` (+ `h_z (1 + a u_Z)`);
//! - the sliding solve ([`Body::slide`]): `F = N Z − N_f f(v_P) − H − h_z Z`;
//! - the rolling solve ([`Body::roll`]): `F − r × I⁻¹(r × F) = b`,
//!   `b = g Z − F_b − ẇ₀ × r − a w × k̇`, and the Coulomb–Contensou stick
//!   ([`stick_solve`]: the drilling torque a fourth unknown);
//! - the drilling torque `M Z` (sliding: `M = −N_f τ` from the law);
//! - the work rates `Ẇ_f = F_f·v_P + M w_Z`, `Ẇ_a = −H·v_P` (sliding; none
//!   while rolling) and the actuators' power ([`power`]).
//!
//! The operations are the vector model's, in its order (it is the fast
//! formulation; docs/performance.md): the vector model's output is the same
//! bits as before this module; the rigid model's moved by rounding once
//! when it came here (docs/physics.md#rigid-model).

use std::cell::Cell;

use crate::numeric::vec3::{V3, Z, add, cross, dot, scale, solve3, sub};
use crate::physics::forces::{ContactPointForce, Forces, wells::Well};

/// The surface the body's contact sphere touches. Today the plane `z = 0`
/// ([`Plane`]); the inside of a nanotube is issue #30's. The closure and
/// the solves below are written with the plane's constant normal `Z`
/// (its components read directly, which costs nothing); a curved surface
/// supplies [`Surface::normal`] at the contact and the formulas read it.
pub trait Surface {
    /// `r = P − O`, the contact point from the centre of mass for the axis
    /// `k`, a sphere of radius `rho` centred `a` along `k` (scaled lengths).
    fn offset(&self, k: V3, a: f64, rho: f64) -> V3;
    /// The unit normal at the contact point, pointing into the body.
    fn normal(&self) -> V3;
    /// The gap between the sphere of radius `rho` centred at `centre` and
    /// the surface (scaled length; 0 in contact, > 0 apart).
    fn gap(&self, centre: V3, rho: f64) -> f64;
}

/// The horizontal plane `z = 0`, normal `Z`.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Plane;

impl Surface for Plane {
    #[inline(always)]
    fn offset(&self, k: V3, a: f64, rho: f64) -> V3 {
        [a * k[0], a * k[1], a * k[2] - rho]
    }

    #[inline(always)]
    fn normal(&self) -> V3 {
        Z
    }

    #[inline(always)]
    fn gap(&self, centre: V3, rho: f64) -> f64 {
        centre[2] - rho
    }
}

/// What the contact's friction law gives the body (implemented by
/// [`crate::model::ContactState`]): the law `f(v)` (written once, in
/// [`crate::input::surface::SlidingLaw`]), the Coulomb–Contensou drilling, and the
/// normal-force closure's branch choice.
pub trait Friction {
    /// Friction coefficient μ.
    fn mu(&self) -> f64;
    /// `ε` (scaled) of the regularised law, `None` for the other laws.
    fn regularized_eps(&self) -> Option<f64>;
    /// Coulomb–Contensou friction's `(f, τ)` at slip `v` and spin about
    /// the normal `w_Z`; `None` for the other laws.
    fn drilling(&self, v: [f64; 2], wz: f64) -> Option<([f64; 2], f64)>;
    /// The friction coefficient vector `f(v)` while sliding.
    fn coefficient(&self, v: [f64; 2]) -> [f64; 2];
    /// The normal force of the closure `N D(σ) = Q` (`dp = D(+)`,
    /// `dm = D(−)`); `Err` the number of consistent solutions (Painlevé).
    fn closure(&self, q: f64, dp: f64, dm: f64) -> Result<f64, usize>;
    /// The normal force the friction sees.
    fn friction_normal(&self, normal: f64) -> f64;
    /// True for Coulomb–Contensou friction (the stick holds `w_Z` too).
    fn is_contensou(&self) -> bool;
}

/// The inertia of a symmetric body about its centre of mass (scaled:
/// `A`, `C` in m R²): `I = A 1 + (C − A) k kᵀ` for the axis `k`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Inertia {
    /// Transverse moment `A`.
    pub ia: f64,
    /// Axial moment `C`.
    pub ic: f64,
    /// `1/A`.
    pub inv_ia: f64,
    /// `1/C − 1/A`.
    pub dinv: f64,
    /// `(C − A)/A`.
    pub gyro: f64,
}

impl Inertia {
    /// The inertia of moments `A` (transverse) and `C` (axial).
    pub fn new(ia: f64, ic: f64) -> Self {
        Inertia {
            ia,
            ic,
            inv_ia: 1.0 / ia,
            dinv: 1.0 / ic - 1.0 / ia,
            gyro: (ic - ia) / ia,
        }
    }

    /// The columns of the contact matrix `K x = x − r × I⁻¹ (r × x)
    /// = (1 + |r|²/A) x − (r·x) r/A + (1/C − 1/A) (c·x) c`, `c = k × r`
    /// (`|k| = 1`): the rolling solve's `K F = b` (plane and tube).
    #[inline(always)]
    pub fn contact_matrix(&self, k: V3, r: V3) -> [V3; 3] {
        let (inv_ia, dinv) = (self.inv_ia, self.dinv);
        let c = cross(k, r);
        let alpha = 1.0 + inv_ia * dot(r, r);
        let col = |x: V3| {
            add(
                sub(scale(alpha, x), scale(inv_ia * dot(r, x), r)),
                scale(dinv * dot(c, x), c),
            )
        };
        [col([1.0, 0.0, 0.0]), col([0.0, 1.0, 0.0]), col(Z)]
    }

    /// `I x` for the symmetry axis `k`.
    #[inline(always)]
    pub fn apply(&self, k: V3, x: V3) -> V3 {
        add(scale(self.ia, x), scale((self.ic - self.ia) * dot(x, k), k))
    }

    /// `I⁻¹ x = x/A + (1/C − 1/A)(x·k) k` for the symmetry axis `k`.
    #[inline(always)]
    pub fn inverse(&self, k: V3, x: V3) -> V3 {
        add(scale(self.inv_ia, x), scale(self.dinv * dot(x, k), k))
    }
}

/// The body's kinematics at one state (lab frame, scaled).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct At {
    /// Symmetry axis `k`.
    pub k: V3,
    /// Angular velocity `w`.
    pub w: V3,
    /// `k̇ = w × k`.
    pub kd: V3,
    /// `w · k`.
    pub wk: f64,
    /// `r = P − O`.
    pub r: V3,
    /// `w × r`.
    pub wr: V3,
}

impl At {
    /// The kinematics of axis `k`, angular velocity `w`, contact sphere
    /// `(a, rho)` on `surface`.
    #[inline(always)]
    pub fn new<S: Surface>(surface: &S, a: f64, rho: f64, k: V3, w: V3) -> Self {
        let r = surface.offset(k, a, rho);
        At {
            k,
            w,
            kd: cross(w, k),
            wk: dot(w, k),
            r,
            wr: cross(w, r),
        }
    }
}

/// The free accelerations ([`Body::free`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Free {
    /// `ẇ₀`: the angular acceleration without the contact force
    /// (gyroscopic, the couples, the actuators' `I⁻¹τ`).
    pub w0: V3,
    /// `g Z − F_b`: gravity less the actuators' force (per unit mass).
    pub gv: V3,
    /// The actuators' wrench `(F_b, τ_b)`, `None` without actuators.
    pub wrench: Option<(V3, V3)>,
}

/// The contact's solution at one state ([`Body::slide`], [`Body::roll`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Contact {
    /// The plane's reaction `N`.
    pub normal: f64,
    /// The friction force on the top (horizontal).
    pub friction: [f64; 2],
    /// The whole force at `P` (contact and applied at `P`): `v̇ = F + F_b − g Z`.
    pub force: V3,
    /// `ẇ`.
    pub wd: V3,
    /// `Ẇ_f`, the friction's power (0 while rolling).
    pub wf: f64,
    /// `Ẇ_a`, the power of the force at `P` (0 while rolling); the
    /// actuators' [`power`] is the adapter's to add.
    pub wa: f64,
    /// The drilling torque about Z (Coulomb–Contensou; 0 otherwise).
    pub torque: f64,
}

/// The body's constants (scaled).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Body {
    /// Centre offset `a` of the contact sphere along `k`.
    pub a: f64,
    /// The inertia.
    pub inertia: Inertia,
    /// Gravity `g`.
    pub g: f64,
}

impl Body {
    /// The free accelerations at `at`: gyroscopic, the wells' torque
    /// `tau_wells` (a couple ⊥ `k`, so `I⁻¹τ = τ/A`), the actuators'
    /// `wrench`. `ẇ₀` is the gyroscopic term itself (bit for bit) without them.
    #[inline(always)]
    pub fn free(&self, at: &At, tau_wells: Option<V3>, wrench: Option<(V3, V3)>) -> Free {
        let w0 = scale(-self.inertia.gyro * at.wk, at.kd);
        let w0 = match tau_wells {
            Some(tau) => add(w0, scale(self.inertia.inv_ia, tau)),
            None => w0,
        };
        match wrench {
            // `g Z` as `(0, 0, g)`: the same bits as `g·Z` (g > 0), three
            // products less.
            Some((fb, tb)) => Free {
                w0: add(w0, self.inertia.inverse(at.k, tb)),
                gv: sub([0.0, 0.0, self.g], fb),
                wrench,
            },
            None => Free {
                w0,
                gv: [0.0, 0.0, self.g],
                wrench: None,
            },
        }
    }

    /// The closure's `Q` (with the load at `P`, `cp`) and `u = (e × r)/A`,
    /// for the horizontal force `H` (`hw`, the force on the top is `−H`).
    /// `−Q` is the gap's acceleration with `N = 0` and no friction.
    #[inline(always)]
    pub fn closure_q(&self, at: &At, free: &Free, hw: V3, cp: &ContactPointForce) -> (f64, V3) {
        let (a, k, w, kd) = (self.a, at.k, at.w, at.kd);
        let e = [k[1], -k[0], 0.0];
        let u = scale(self.inertia.inv_ia, cross(e, at.r));
        let wkd_z = w[0] * kd[1] - w[1] * kd[0];
        let q = free.gv[2] + a * (hw[0] * u[0] + hw[1] * u[1] - dot(free.w0, e) - wkd_z);
        // The vertical load h_z at P: Q + h_z D₀, D₀ = 1 + a u_Z
        // (docs/physics.md#vertical-load).
        (cp.closure_q(q, 1.0 + a * u[2]), u)
    }

    /// `ẇ = ẇ₀ + I⁻¹(r × F)` for the force `force` at `P`.
    #[inline(always)]
    pub fn angular(&self, at: &At, free: &Free, force: V3) -> V3 {
        add(free.w0, self.inertia.inverse(at.k, cross(at.r, force)))
    }

    /// Sliding at slip `vp` (horizontal): the friction coefficient of the
    /// law, the closure for `N`, the contact force, `ẇ` with the drilling
    /// torque, the work rates. `Err`: the Painlevé case's number of
    /// consistent solutions.
    #[inline(always)]
    pub fn slide<F: Friction>(
        &self,
        law: &F,
        at: &At,
        free: &Free,
        hw: V3,
        cp: &ContactPointForce,
        vp: [f64; 2],
    ) -> Result<Contact, usize> {
        let (a, w) = (self.a, at.w);
        // Regularised law: `f = μ v/d`, `d = sqrt(|v|² + ε²)`. The closure
        // `N D(σ) = Q` is solved as `N (d D(σ)) = d Q`, which needs `d` but
        // not `μ/d`: that division runs beside the one for N instead of
        // before it (one division less on the critical path).
        let reg_d = law
            .regularized_eps()
            .map(|eps| (vp[0] * vp[0] + vp[1] * vp[1] + eps * eps).sqrt());
        // Coulomb–Contensou (§contensou): the drilling torque's coefficient, from
        // the slip and the spin about Z, w_Z.
        let mut tau = None;
        let f = match reg_d {
            Some(d) => {
                let kf = law.mu() / d;
                [kf * vp[0], kf * vp[1]]
            }
            None => match law.drilling(vp, w[2]) {
                Some((f, t)) => {
                    tau = Some(t);
                    f
                }
                None => law.coefficient(vp),
            },
        };
        let (q, u) = self.closure_q(at, free, hw, cp);
        let (q, dp, dm) = match reg_d {
            Some(d) => {
                let base = d * (1.0 + a * u[2]);
                let t = a * law.mu() * (vp[0] * u[0] + vp[1] * u[1]);
                (d * q, base - t, base + t)
            }
            None => {
                let fu = f[0] * u[0] + f[1] * u[1];
                (q, 1.0 + a * (u[2] - fu), 1.0 + a * (u[2] + fu))
            }
        };
        let normal = law.closure(q, dp, dm)?;
        let nf = law.friction_normal(normal);
        let ff = [-nf * f[0], -nf * f[1]];
        // The vertical force at P is N − h_z (§vertical-load).
        let force = [ff[0] - hw[0], ff[1] - hw[1], cp.vertical_total(normal)];
        let mut wd = self.angular(at, free, force);
        let mut wf = ff[0] * vp[0] + ff[1] * vp[1];
        let mut torque = 0.0;
        if let Some(tau) = tau {
            // The drilling torque M Z (M = −N_f τ): I⁻¹ M Z; its power
            // M w_Z. It does not enter the closure (§contensou).
            let mz = -nf * tau;
            wd = add(wd, self.inertia.inverse(at.k, [0.0, 0.0, mz]));
            wf += mz * w[2];
            torque = mz;
        }
        Ok(Contact {
            normal,
            friction: ff,
            force,
            wd,
            wf,
            wa: -hw[0] * vp[0] - hw[1] * vp[1],
            torque,
        })
    }

    /// Rolling: the slip held at zero, the whole contact force from one
    /// 3×3 symmetric positive definite system (with Coulomb–Contensou
    /// friction `w_Z` held too, the drilling torque a fourth unknown).
    #[inline(always)]
    pub fn roll<F: Friction>(
        &self,
        law: &F,
        at: &At,
        free: &Free,
        hw: V3,
        cp: &ContactPointForce,
    ) -> Contact {
        let (k, r, w0) = (at.k, at.r, free.w0);
        let b = sub(
            sub(free.gv, cross(w0, r)),
            scale(self.a, cross(at.w, at.kd)),
        );
        let (force, wd, torque) = if law.is_contensou() {
            // The Coulomb–Contensou stick: w_Z held at zero too, the
            // drilling torque M a fourth unknown (§contensou).
            let (force, m) = stick_solve(&self.inertia, k, r, b, -w0[2]);
            let wd = add(
                w0,
                self.inertia.inverse(k, add(cross(r, force), [0.0, 0.0, m])),
            );
            (force, wd, m)
        } else {
            let force = solve3(self.inertia.contact_matrix(k, r), b);
            (force, self.angular(at, free, force), 0.0)
        };
        Contact {
            // The plane's reaction: the constraint force plus the load (§vertical-load).
            normal: cp.reaction(force[2]),
            friction: [force[0] + hw[0], force[1] + hw[1]],
            force,
            wd,
            wf: 0.0,
            wa: 0.0,
            torque,
        }
    }
}

/// The applied horizontal force `H = h_x x̂ + h_y ŷ` in the lab frame from
/// its latched components `h` in the precessing frame (`x̂` along the
/// horizontal projection of `k`, `ŷ = Z × x̂`; `X`, `Y` if `k` is
/// vertical). The force on the top is `−H`.
#[inline(always)]
pub fn applied_world(h: [f64; 2], k: V3) -> V3 {
    let [hx, hy] = h;
    if hx == 0.0 && hy == 0.0 {
        return [0.0; 3];
    }
    let (xh, yh) = precessing_frame(k);
    add(scale(hx, xh), scale(hy, yh))
}

/// The precessing frame's `x̂` and `ŷ` (horizontal; `X`, `Y` if `k` is
/// vertical).
#[inline]
pub fn precessing_frame(k: V3) -> (V3, V3) {
    // |k_h| is O(1) or 0 here: no overflow, so no need for hypot.
    let kh2 = k[0] * k[0] + k[1] * k[1];
    let xh = if kh2 > 0.0 {
        let inv = 1.0 / kh2.sqrt();
        [k[0] * inv, k[1] * inv, 0.0]
    } else {
        [1.0, 0.0, 0.0]
    };
    (xh, [-xh[1], xh[0], 0.0])
}

/// The body actuators' wrench `(F, τ)` (scaled, lab;
/// docs/physics.md#actuators), `None` without actuators; `axes` gives an
/// off-axis actuator's material axes `(e1, e2)` (from the attitude).
#[inline(always)]
pub fn wrench(forces: &Forces, k: V3, axes: impl FnOnce() -> (V3, V3)) -> Option<(V3, V3)> {
    if forces.body_is_zero() {
        return None;
    }
    Some(forces.body().wrench(k, axes))
}

/// The actuators' power `F·v_O + τ·w` (§actuators).
#[inline(always)]
pub fn power((fb, tb): (V3, V3), v: V3, w: V3) -> f64 {
    dot(fb, v) + dot(tb, w)
}

/// The wells' torque `τ = −U′(θ) ŷ` in the lab frame
/// ([`crate::physics::forces::wells::torque_world`]), kept for the last
/// axis `k` (its bits): it is a function of `k` alone, so a Langevin step's
/// first evaluation (after the O half step, which does not move `k`)
/// reuses the one at the previous step's end: one `atan2` and one `exp`
/// per well less per step, the same bits.
#[derive(Debug, Clone, Default)]
pub struct WellsTorque(Cell<Option<([u64; 3], V3)>>);

impl WellsTorque {
    /// The torque at `k`, `None` without wells.
    #[inline(always)]
    pub fn at(&self, wells: &[Well], k: V3) -> Option<V3> {
        if wells.is_empty() {
            return None;
        }
        let key = [k[0].to_bits(), k[1].to_bits(), k[2].to_bits()];
        Some(match self.0.get() {
            Some((kb, tau)) if kb == key => tau,
            _ => {
                let tau = crate::physics::forces::wells::torque_world(wells, k);
                self.0.set(Some((key, tau)));
                tau
            }
        })
    }
}

/// The Coulomb–Contensou stick's constraint wrench (docs/physics.md#contensou),
/// for every model (scaled, `m = 1`): with the inertia `I` about the axis
/// `k` and `r` from the centre of mass to the contact point, the contact
/// force `F` (at P) and the torque `M` about the vertical `Z` that solve
///
/// ```text
/// K F − c M = b,   −c·F + s M = β,
/// K x = x − r × I⁻¹(r × x),  c = r × I⁻¹ Z,  s = Z·I⁻¹ Z,
/// ```
///
/// the rolling constraint (`b` the rolling system's right-hand side) and
/// `ṅ_Z = 0` (`β = −ṅ₀·Z`, `ṅ₀` the angular acceleration without the
/// contact), or with `b = −v_P`, `β = −n_Z` the impulse `(Π, M)` that
/// brings the contact point's velocity and the spin about `Z` to zero.
/// By the Schur complement: `F = K⁻¹ (b + c M)`,
/// `M = (β + c·K⁻¹b)/(s − c·K⁻¹c)` (the whole matrix is symmetric
/// positive definite up to the sign of the last row: the denominator is
/// positive).
pub fn stick_solve(inertia: &Inertia, k: V3, r: V3, b: V3, beta: f64) -> (V3, f64) {
    let kmul = |p: V3| sub(p, cross(r, inertia.inverse(k, cross(r, p))));
    let cols = [kmul([1.0, 0.0, 0.0]), kmul([0.0, 1.0, 0.0]), kmul(Z)];
    let iz = inertia.inverse(k, Z);
    let c = cross(r, iz);
    let x1 = solve3(cols, b);
    let x2 = solve3(cols, c);
    let m = (beta + dot(c, x1)) / (iz[2] - dot(c, x2));
    (add(x1, scale(m, x2)), m)
}

/// The inside of a horizontal cylinder (docs/physics.md#tube-dynamics):
/// axis along lab X through `(y, z) = (0, radius)`, so its lowest line is
/// `z = 0` and `radius → ∞` is the plane in the same coordinates (scaled
/// lengths). Its contact at one state is a [`TubeAt`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tube {
    /// The radius `b` (scaled).
    pub radius: f64,
}

/// The tube at the contact of a sphere centred at `c`: the normal, the
/// circumferential tangent and the centre's distance from the axis
/// (a [`Surface`] for [`At::new`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TubeAt {
    /// The unit normal at the contact, pointing into the body (towards the
    /// axis): `n = −c⊥/|c⊥|`, `c⊥` the centre from the axis, across it.
    pub n: V3,
    /// The circumferential unit tangent `e₂ = n × X` (`Y` at the lowest
    /// line); with `e₁ = X` the contact's tangent basis (right-handed with
    /// `n`, as `X, Y, Z` on the plane).
    pub e2: V3,
    /// `|c⊥|`, the sphere centre's distance from the axis (`b − ρ` in contact).
    pub dist: f64,
    /// The tube's radius `b`.
    pub radius: f64,
}

impl Tube {
    /// The tube at the contact of a sphere centred at `c`.
    #[inline]
    pub fn at(&self, c: V3) -> TubeAt {
        let (py, pz) = (c[1], c[2] - self.radius);
        let dist = py.hypot(pz);
        let n = [0.0, -py / dist, -pz / dist];
        TubeAt {
            n,
            e2: [0.0, n[2], -n[1]],
            dist,
            radius: self.radius,
        }
    }

    /// The gap `b − |c⊥| − ρ` of a sphere of radius `rho` centred at `c`
    /// (0 in contact, > 0 inside the tube, apart from the wall).
    #[inline]
    pub fn gap(&self, c: V3, rho: f64) -> f64 {
        self.radius - c[1].hypot(c[2] - self.radius) - rho
    }

    /// The centre `c` moved across the axis onto the contact (`|c⊥| = b − ρ`).
    #[inline]
    pub fn onto(&self, c: V3, rho: f64) -> V3 {
        let at = self.at(c);
        let d = self.radius - rho;
        [c[0], -d * at.n[1], self.radius - d * at.n[2]]
    }
}

impl TubeAt {
    /// The lab vector of tangent components `t` (along `e₁ = X`, `e₂`).
    #[inline]
    pub fn tangent(&self, t: [f64; 2]) -> V3 {
        [t[0], t[1] * self.e2[1], t[1] * self.e2[2]]
    }

    /// The tangent components `(x·e₁, x·e₂)` of a lab vector.
    #[inline]
    pub fn components(&self, x: V3) -> [f64; 2] {
        [x[0], dot(x, self.e2)]
    }

    /// A lab vector's components in the contact's frame `(e₁, e₂, n)`, a
    /// right-handed orthonormal basis (`e₁ × e₂ = n`) in which the normal is
    /// `Z`: the rotation taking the tube's contact to the plane's
    /// (docs/physics.md#tube-langevin). [`TubeAt::from_frame`] is its inverse.
    #[inline]
    pub fn into_frame(&self, x: V3) -> V3 {
        [x[0], dot(x, self.e2), dot(x, self.n)]
    }

    /// The lab vector of components `x` in the contact's frame `(e₁, e₂, n)`.
    #[inline]
    pub fn from_frame(&self, x: V3) -> V3 {
        [
            x[0],
            x[1] * self.e2[1] + x[2] * self.n[1],
            x[1] * self.e2[2] + x[2] * self.n[2],
        ]
    }

    /// The normal's rate `ṅ = −(ċ·e₂) e₂/|c⊥|` for the centre's velocity
    /// `cd` (the normal turns only with the centre's motion around the axis).
    #[inline]
    pub fn normal_rate(&self, cd: V3) -> V3 {
        scale(-dot(cd, self.e2) / self.dist, self.e2)
    }
}

impl TubeAt {
    /// The applied force `H = h_x x̂ + h_y ŷ` (lab) at the contact from its
    /// latched components `h` in the tube's local frame: the contact normal
    /// `n` replaces `Z`, `x̂` is the projection of `k` onto the tangent plane
    /// at the contact (normalised), `ŷ = n × x̂`; `x̂ = e₁ = X`, `ŷ = e₂` if
    /// `k` is along `n`. At the lowest line (`n = Z`) these are the plane's
    /// precessing frame ([`precessing_frame`]). The force on the top is `−H`
    /// (docs/physics.md#tube-dynamics).
    #[inline]
    pub fn applied(&self, h: [f64; 2], k: V3) -> V3 {
        let [hx, hy] = h;
        if hx == 0.0 && hy == 0.0 {
            return [0.0; 3];
        }
        let n = self.n;
        let kt = sub(k, scale(dot(k, n), n));
        let l2 = dot(kt, kt);
        let xh = if l2 > 0.0 {
            scale(1.0 / l2.sqrt(), kt)
        } else {
            [1.0, 0.0, 0.0]
        };
        add(scale(hx, xh), scale(hy, cross(n, xh)))
    }
}

impl Surface for TubeAt {
    #[inline]
    fn offset(&self, k: V3, a: f64, rho: f64) -> V3 {
        sub(scale(a, k), scale(rho, self.n))
    }

    #[inline]
    fn normal(&self) -> V3 {
        self.n
    }

    #[inline]
    fn gap(&self, centre: V3, rho: f64) -> f64 {
        Tube {
            radius: self.radius,
        }
        .gap(centre, rho)
    }
}

impl Body {
    /// Sliding in the tube (docs/physics.md#tube-dynamics) at the tangent
    /// slip `vp` (components along `e₁`, `e₂`), the centre's velocity `cd`:
    /// the closure `N D(σ) = Q` with the normal `n` for `Z` and the
    /// curvature term, `D(σ) = 1 + a (u·n − σ f·u)`, `u = (e × r)/A`,
    /// `e = k × n`, `Q = g_v·n − a (ẇ₀·e + n·(w × k̇)) + (ċ·e₂)²/|c⊥| + a H·u`
    /// and the normal load `h_z` of `cp` as on the plane (`Q + h_z D₀`,
    /// `D₀ = 1 + a u·n`); the force `(N − h_z) n − N_f f − H` (`hw` is `H`,
    /// tangent, [`TubeAt::applied`]). The friction in [`Contact::friction`]
    /// is in tangent components. Point laws only (no drilling).
    #[inline]
    #[allow(clippy::too_many_arguments)]
    pub fn slide_tube<F: Friction>(
        &self,
        law: &F,
        at: &At,
        free: &Free,
        tube: &TubeAt,
        hw: V3,
        cp: &ContactPointForce,
        cd: V3,
        vp: [f64; 2],
    ) -> Result<Contact, usize> {
        let (a, k, r, n) = (self.a, at.k, at.r, tube.n);
        let fl = law.coefficient(vp);
        let f = tube.tangent(fl);
        let e = cross(k, n);
        let u = scale(self.inertia.inv_ia, cross(e, r));
        let kappa = dot(cd, tube.e2).powi(2) / tube.dist;
        let q = dot(free.gv, n) - a * (dot(free.w0, e) + dot(n, cross(at.w, at.kd)))
            + kappa
            + a * dot(hw, u);
        let (un, fu) = (dot(u, n), dot(f, u));
        let q = cp.closure_q(q, 1.0 + a * un);
        let normal = law.closure(q, 1.0 + a * (un - fu), 1.0 + a * (un + fu))?;
        let nf = law.friction_normal(normal);
        let ff = [-nf * fl[0], -nf * fl[1]];
        let force = sub(
            add(scale(cp.vertical_total(normal), n), tube.tangent(ff)),
            hw,
        );
        Ok(Contact {
            normal,
            friction: ff,
            force,
            wd: self.angular(at, free, force),
            wf: ff[0] * vp[0] + ff[1] * vp[1],
            wa: -dot(hw, tube.tangent(vp)),
            torque: 0.0,
        })
    }

    /// Rolling in the tube: `v + w × r = 0` held, whose rate is
    /// `v̇ + ẇ × r + w × ṙ = 0` with the contact offset's rate
    /// `ṙ = a k̇ − ρ ṅ` (the normal turns: [`TubeAt::normal_rate`] at
    /// `ċ = ρ w × n`): `K F = b + ρ w × ṅ` with the plane's `K` and `b`
    /// (`g_v − ẇ₀ × r − a w × k̇`), `F` the whole force at `P`, which
    /// neither `H` nor the load enters. The wall's reaction
    /// `N = F·n + h_z`, the friction `F − F·n n + H` in tangent components.
    #[inline]
    pub fn roll_tube(
        &self,
        at: &At,
        free: &Free,
        tube: &TubeAt,
        rho: f64,
        hw: V3,
        cp: &ContactPointForce,
    ) -> Contact {
        let (k, r, w) = (at.k, at.r, at.w);
        let ndot = tube.normal_rate(scale(rho, cross(w, tube.n)));
        let b = add(
            sub(
                sub(free.gv, cross(free.w0, r)),
                scale(self.a, cross(w, at.kd)),
            ),
            scale(rho, cross(w, ndot)),
        );
        let force = solve3(self.inertia.contact_matrix(k, r), b);
        Contact {
            normal: cp.reaction(dot(force, tube.n)),
            friction: tube.components(add(force, hw)),
            force,
            wd: self.angular(at, free, force),
            wf: 0.0,
            wa: 0.0,
            torque: 0.0,
        }
    }
}
