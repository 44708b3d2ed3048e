//! Stability of the steady motions (the paper's App. B), by exact numerical
//! linearisation in coordinates that are regular at the poles.
//!
//! # Method
//!
//! **Model.** The reduced Euler-angle model divides by sin θ, so it cannot be
//! linearised at θ = 0 or π. Here the same physics (docs/physics.md §2–§5) is
//! written for the symmetry axis `k` directly: state
//! `x = (ξ, η, n_1, n_2, n_3, u_1, u_2)`, where `n` is the angular velocity and
//! `u` the horizontal centre-of-mass velocity (components in a frame turning
//! about the vertical `Z` at a chosen rate `Ω_f`), and `(ξ, η)` is a chart of
//! the unit sphere centred on the steady axis `k*`:
//! `k = (k* + ξ e_1 + η e_2)/|k* + ξ e_1 + η e_2|`, with `e_1 = ∂k/∂θ`,
//! `e_2 = Z × x`. The chart is regular at every `k*`, poles included. The
//! equations are Euler's about the centre of mass,
//! `I ṅ = r × F_P − (C − A)(k·n)(n × k)`, `r = a k − R Z`, Newton's
//! `m u̇ = F_P − m g Z`, with the normal force solved from the contact
//! constraint `u_z = −a k̇_z` together with `ṅ` (as in §4), and a **smooth**
//! friction law (Coulomb is not differentiable at zero slip):
//! regularised `μ N v/√(|v|² + ε²)` or viscous `μ N v/ε`. Both have the same
//! linearisation at zero slip (`μ N/ε` per unit slip), so at the steady
//! motions below (all with zero slip) they give the same eigenvalues; ε is
//! the user's choice ([`Options::eps`]). The model is checked against the
//! reduced model's right-hand side away from the poles (tests).
//!
//! **Jacobian.** Exact to rounding: forward-mode automatic differentiation
//! (dual numbers) through the right-hand side, in units `R`, `m`,
//! `1/rate` (rate = the largest of |n*|, |Ω*|, √(g/R)), then converted to 1/s.
//!
//! **Steady motions with H = 0** (derived in the physics-doc section):
//! - sleeping upright (θ = 0) and inverted (θ = π), `n = ω k`, `u = 0`: a
//!   true equilibrium for every ω;
//! - relative equilibria at `θ* ∈ (0, π)` with θ̇ = 0 and zero slip: with a
//!   smooth law, steady ⇒ no friction ⇒ zero slip and `u = 0`, which forces
//!   `ω* = Ω* (cos θ* − a/R)` (n parallel to OP) and
//!   `Ω*² [(A − C) cos θ* + C a/R] = m g a`.
//!
//! Steady motions come in families, and Jellett's `J` is conserved, so the
//! Jacobian always has structural zero eigenvalues: one for the family (its
//! left null vector is `∇J`) and, at `θ* ∈ (0, π)` in the frame turning with
//! `Ω*`, one for the rotation about `Z`. These are removed exactly: the
//! eigenvalues reported are those of `M` restricted to `{∇J·δx = 0}` and
//! taken modulo the rotation generator. What remains decides.
//!
//! **Verdict.** With `ρ` the largest |λ| and `tol = tol_rel ρ`
//! ([`Options::tol_rel`], default 1e-10): stable if every Re λ < −tol,
//! unstable if some Re λ > tol, marginal otherwise (e.g. frictionless: a
//! conservative system has at best purely imaginary eigenvalues).
//!
//! **H ≠ 0.** Nothing is steady (ω changes at the rate `R sin θ F_y/C`).
//! The frozen-spin analysis holds ω, the applied force and `u` fixed and
//! linearises the reduced model's θ equation about its quasi-equilibrium
//! `θ̈(θ_q, 0) = 0`, in two variants: Ω frozen (the assumption of the
//! paper's B1–B4) and Ω from Jellett's J (`Ω = (J − C ω (R cos θ − a))/(A R
//! sin²θ)`, which keeps the gyroscopic coupling). Both are labelled
//! "frozen-spin (quasi-static), not a true equilibrium".

// Dense linear algebra on small matrices reads best with indices.
#![allow(clippy::needless_range_loop)]

use std::ops::{Add, Div, Mul, Neg, Sub};

use serde::Serialize;

use crate::{
    Error, FrictionLaw, Scenario, Top,
    model::reduced::{DIM, OM, Reduced, THD},
    simulate,
};

/// Derivatives of the reduced variables computed by the axis-vector model
/// (SI), for checking it against the reduced model away from the poles.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AxisDerivatives {
    /// θ̈ \[rad/s²\].
    pub theta_ddot: f64,
    /// Ω̇ \[rad/s²\].
    pub precession_dot: f64,
    /// ω̇ \[rad/s²\].
    pub spin_dot: f64,
    /// u̇_x in the precessing frame \[m/s²\].
    pub ux_dot: f64,
    /// u̇_y in the precessing frame \[m/s²\].
    pub uy_dot: f64,
    /// Normal force \[N\].
    pub normal: f64,
}

/// Evaluate the axis-vector model used for linearisation at a reduced state
/// (θ, θ̇, Ω, ω, u_x, u_y) (SI, H = 0) and return the reduced variables'
/// derivatives. Requires sin θ ≠ 0.
pub fn axis_model_derivatives(ph: &Physics, y: [f64; 6]) -> AxisDerivatives {
    let [th, thd, om, w, ux, uy] = y;
    let top = &ph.top;
    let (s, c) = th.sin_cos();
    let mr2 = top.mass * top.radius * top.radius;
    // SI-like units with R = m = 1 and time in seconds.
    let rig = Rigid {
        a: top.offset / top.radius,
        ia: top.inertia_transverse / mr2,
        ic: top.inertia_axial / mr2,
        g: ph.gravity / top.radius,
        mu: ph.mu,
        law: ph.law,
        eps: ph.eps / top.radius,
        frame: 0.0,
        kstar: [s, 0.0, c],
        e1: [c, 0.0, -s],
        e2: [0.0, 1.0, 0.0],
    };
    let n = [(w - om * c) * s, thd, om * s * s + w * c];
    let x = [0.0, 0.0, n[0], n[1], n[2], ux / top.radius, uy / top.radius];
    let (d, nn) = rig.rhs(&x);
    let nd = [d[2], d[3], d[4]];
    let wd = nd[0] * s + nd[2] * c;
    let thdd = nd[1] - om * n[0];
    let omd = (nd[2] - 2.0 * om * s * c * thd - wd * c + w * s * thd) / (s * s);
    AxisDerivatives {
        theta_ddot: thdd,
        precession_dot: omd,
        spin_dot: wd,
        ux_dot: (d[5] + om * uy / top.radius) * top.radius,
        uy_dot: (d[6] - om * ux / top.radius) * top.radius,
        normal: nn * top.mass * top.radius,
    }
}

// ---------------------------------------------------------------------------
// Numbers: f64 and dual numbers for exact Jacobians.

trait Num:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    fn k(x: f64) -> Self;
    fn sqrt(self) -> Self;
}

impl Num for f64 {
    fn k(x: f64) -> Self {
        x
    }
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

/// Dual number `v + d ε`, ε² = 0.
#[derive(Debug, Clone, Copy)]
struct Dual {
    v: f64,
    d: f64,
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, o: Dual) -> Dual {
        Dual {
            v: self.v + o.v,
            d: self.d + o.d,
        }
    }
}
impl Sub for Dual {
    type Output = Dual;
    fn sub(self, o: Dual) -> Dual {
        Dual {
            v: self.v - o.v,
            d: self.d - o.d,
        }
    }
}
impl Mul for Dual {
    type Output = Dual;
    fn mul(self, o: Dual) -> Dual {
        Dual {
            v: self.v * o.v,
            d: self.d * o.v + self.v * o.d,
        }
    }
}
impl Div for Dual {
    type Output = Dual;
    fn div(self, o: Dual) -> Dual {
        Dual {
            v: self.v / o.v,
            d: (self.d * o.v - self.v * o.d) / (o.v * o.v),
        }
    }
}
impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            v: -self.v,
            d: -self.d,
        }
    }
}
impl Num for Dual {
    fn k(x: f64) -> Self {
        Dual { v: x, d: 0.0 }
    }
    fn sqrt(self) -> Self {
        let s = self.v.sqrt();
        Dual {
            v: s,
            d: self.d / (2.0 * s),
        }
    }
}

fn cross<S: Num>(a: [S; 3], b: [S; 3]) -> [S; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn dot<S: Num>(a: [S; 3], b: [S; 3]) -> S {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn lift<S: Num>(a: [f64; 3]) -> [S; 3] {
    [S::k(a[0]), S::k(a[1]), S::k(a[2])]
}

// ---------------------------------------------------------------------------
// The regular (axis-vector) model.

/// Smooth friction law used for linearisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SmoothLaw {
    /// `μ N v/√(|v|² + ε²)`.
    Regularized,
    /// `μ N v/ε`.
    Viscous,
}

impl SmoothLaw {
    /// Scenario name of the law.
    pub fn name(&self) -> &'static str {
        match self {
            SmoothLaw::Regularized => "regularized",
            SmoothLaw::Viscous => "viscous",
        }
    }
}

/// Number of state components of the regular model.
pub const RDIM: usize = 7;

/// The regular model in scaled units (R = m = 1, time 1/rate).
#[derive(Debug, Clone, Copy)]
struct Rigid {
    a: f64,
    ia: f64,
    ic: f64,
    g: f64,
    mu: f64,
    law: SmoothLaw,
    eps: f64,
    /// Rotation rate of the frame about Z.
    frame: f64,
    kstar: [f64; 3],
    e1: [f64; 3],
    e2: [f64; 3],
}

impl Rigid {
    fn k_of<S: Num>(&self, xi: S, eta: S) -> [S; 3] {
        let w: [S; 3] = std::array::from_fn(|i| {
            S::k(self.kstar[i]) + xi * S::k(self.e1[i]) + eta * S::k(self.e2[i])
        });
        let n = dot(w, w).sqrt();
        [w[0] / n, w[1] / n, w[2] / n]
    }

    /// `I⁻¹ y` with `I = A 1 + (C − A) k kᵀ`.
    fn inv_i<S: Num>(&self, k: [S; 3], y: [S; 3]) -> [S; 3] {
        let c = S::k((self.ic - self.ia) / (self.ia * self.ic)) * dot(k, y);
        let ia = S::k(self.ia);
        [
            y[0] / ia - c * k[0],
            y[1] / ia - c * k[1],
            y[2] / ia - c * k[2],
        ]
    }

    /// Right-hand side and normal force.
    fn rhs<S: Num>(&self, x: &[S; RDIM]) -> ([S; RDIM], S) {
        let a = S::k(self.a);
        let k = self.k_of(x[0], x[1]);
        let n = [x[2], x[3], x[4]];
        let kd = cross(n, k);
        let u = [x[5], x[6], -a * kd[2]];
        let r = [a * k[0], a * k[1], a * k[2] - S::k(1.0)];
        let nr = cross(n, r);
        let v = [u[0] + nr[0], u[1] + nr[1]];
        let mu = S::k(self.mu);
        let eps = S::k(self.eps);
        let f = match self.law {
            SmoothLaw::Regularized => {
                let d = (v[0] * v[0] + v[1] * v[1] + eps * eps).sqrt();
                [mu * v[0] / d, mu * v[1] / d]
            }
            SmoothLaw::Viscous => [mu * v[0] / eps, mu * v[1] / eps],
        };
        // Contact force per unit N.
        let fp1 = [-f[0], -f[1], S::k(1.0)];
        let kn = dot(k, n);
        let nk = cross(n, k);
        let gc = -S::k(self.ic - self.ia) * kn;
        let nd0 = self.inv_i(k, [gc * nk[0], gc * nk[1], gc * nk[2]]);
        let nd1 = self.inv_i(k, cross(r, fp1));
        // N (1 + a (ṅ1 × k)_z) = g − a [(ṅ0 × k)_z + (n × k̇)_z]
        let c1 = cross(nd1, k)[2];
        let c0 = cross(nd0, k)[2] + cross(n, kd)[2];
        let nn = (S::k(self.g) - a * c0) / (S::k(1.0) + a * c1);
        let nd = [
            nd0[0] + nn * nd1[0],
            nd0[1] + nn * nd1[1],
            nd0[2] + nn * nd1[2],
        ];
        let ud = [nn * fp1[0], nn * fp1[1]];
        // Components in the turning frame: d/dt|frame = d/dt|inertial − Ω_f Z ×.
        let om = S::k(self.frame);
        let kdf = [kd[0] + om * k[1], kd[1] - om * k[0], kd[2]];
        let ndf = [nd[0] + om * n[1], nd[1] - om * n[0], nd[2]];
        let udf = [ud[0] + om * u[1], ud[1] - om * u[0]];
        // Chart: ξ = k·e1 / k·k*, η = k·e2 / k·k*.
        let ks = lift(self.kstar);
        let kk = dot(k, ks);
        let kdk = dot(kdf, ks);
        let xid = dot(kdf, lift(self.e1)) / kk - dot(k, lift(self.e1)) * kdk / (kk * kk);
        let etad = dot(kdf, lift(self.e2)) / kk - dot(k, lift(self.e2)) * kdk / (kk * kk);
        ([xid, etad, ndf[0], ndf[1], ndf[2], udf[0], udf[1]], nn)
    }

    /// Jellett's J = −L·r (scaled).
    fn jellett<S: Num>(&self, x: &[S; RDIM]) -> S {
        let k = self.k_of(x[0], x[1]);
        let n = [x[2], x[3], x[4]];
        let c = S::k(self.ic - self.ia) * dot(k, n);
        let ia = S::k(self.ia);
        let l = [
            ia * n[0] + c * k[0],
            ia * n[1] + c * k[1],
            ia * n[2] + c * k[2],
        ];
        let a = S::k(self.a);
        let r = [a * k[0], a * k[1], a * k[2] - S::k(1.0)];
        -dot(l, r)
    }
}

fn duals(x: &[f64; RDIM], j: usize) -> [Dual; RDIM] {
    std::array::from_fn(|i| Dual {
        v: x[i],
        d: if i == j { 1.0 } else { 0.0 },
    })
}

// ---------------------------------------------------------------------------
// Eigenvalues of a real matrix: balance, Hessenberg, shifted QR (EISPACK hqr).

/// Eigenvalues `(re, im)` of a real square matrix (rows), by balancing,
/// reduction to Hessenberg form and the Francis double-shift QR algorithm.
/// Returns `None` if QR does not converge (60 iterations per eigenvalue).
pub fn eigenvalues(m: &[Vec<f64>]) -> Option<Vec<(f64, f64)>> {
    let n = m.len();
    if n == 0 {
        return Some(vec![]);
    }
    let mut a: Vec<Vec<f64>> = m.to_vec();
    balance(&mut a);
    hessenberg(&mut a);
    for i in 0..n {
        for j in 0..n {
            if i > j + 1 {
                a[i][j] = 0.0;
            }
        }
    }
    hqr(&mut a)
}

fn balance(a: &mut [Vec<f64>]) {
    let n = a.len();
    const RADIX: f64 = 2.0;
    let sqrdx = RADIX * RADIX;
    loop {
        let mut done = true;
        for i in 0..n {
            let (mut r, mut c) = (0.0, 0.0);
            for j in 0..n {
                if j != i {
                    c += a[j][i].abs();
                    r += a[i][j].abs();
                }
            }
            if c != 0.0 && r != 0.0 {
                let mut g = r / RADIX;
                let mut f = 1.0;
                let s = c + r;
                while c < g {
                    f *= RADIX;
                    c *= sqrdx;
                }
                g = r * RADIX;
                while c > g {
                    f /= RADIX;
                    c /= sqrdx;
                }
                if (c + r) / f < 0.95 * s {
                    done = false;
                    let g = 1.0 / f;
                    for j in 0..n {
                        a[i][j] *= g;
                    }
                    for row in a.iter_mut() {
                        row[i] *= f;
                    }
                }
            }
        }
        if done {
            break;
        }
    }
}

fn hessenberg(a: &mut [Vec<f64>]) {
    let n = a.len();
    for m in 1..n.saturating_sub(1) {
        let mut x: f64 = 0.0;
        let mut i = m;
        for j in m..n {
            if a[j][m - 1].abs() > x.abs() {
                x = a[j][m - 1];
                i = j;
            }
        }
        if i != m {
            for j in (m - 1)..n {
                let t = a[i][j];
                a[i][j] = a[m][j];
                a[m][j] = t;
            }
            for row in a.iter_mut() {
                row.swap(i, m);
            }
        }
        if x != 0.0 {
            for i in (m + 1)..n {
                let mut y = a[i][m - 1];
                if y != 0.0 {
                    y /= x;
                    a[i][m - 1] = y;
                    for j in m..n {
                        a[i][j] -= y * a[m][j];
                    }
                    for row in a.iter_mut() {
                        row[m] += y * row[i];
                    }
                }
            }
        }
    }
}

#[allow(clippy::many_single_char_names, unused_assignments)]
fn hqr(a: &mut [Vec<f64>]) -> Option<Vec<(f64, f64)>> {
    let n = a.len() as isize;
    let mut wr = vec![0.0; n as usize];
    let mut wi = vec![0.0; n as usize];
    let at = |i: isize| i as usize;
    let mut anorm = 0.0;
    for i in 0..n {
        for j in (i - 1).max(0)..n {
            anorm += a[at(i)][at(j)].abs();
        }
    }
    let sign = |a: f64, b: f64| if b >= 0.0 { a.abs() } else { -a.abs() };
    let mut nn = n - 1;
    let mut t = 0.0;
    let (mut p, mut q, mut r, mut s, mut w, mut x, mut y, mut z) = (
        0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64,
    );
    while nn >= 0 {
        let mut its = 0;
        loop {
            let mut l = nn;
            while l >= 1 {
                s = a[at(l - 1)][at(l - 1)].abs() + a[at(l)][at(l)].abs();
                if s == 0.0 {
                    s = anorm;
                }
                if a[at(l)][at(l - 1)].abs() + s == s {
                    a[at(l)][at(l - 1)] = 0.0;
                    break;
                }
                l -= 1;
            }
            x = a[at(nn)][at(nn)];
            if l == nn {
                wr[at(nn)] = x + t;
                wi[at(nn)] = 0.0;
                nn -= 1;
                break;
            }
            y = a[at(nn - 1)][at(nn - 1)];
            w = a[at(nn)][at(nn - 1)] * a[at(nn - 1)][at(nn)];
            if l == nn - 1 {
                p = 0.5 * (y - x);
                q = p * p + w;
                z = q.abs().sqrt();
                x += t;
                if q >= 0.0 {
                    z = p + sign(z, p);
                    wr[at(nn - 1)] = x + z;
                    wr[at(nn)] = x + z;
                    if z != 0.0 {
                        wr[at(nn)] = x - w / z;
                    }
                    wi[at(nn - 1)] = 0.0;
                    wi[at(nn)] = 0.0;
                } else {
                    wr[at(nn - 1)] = x + p;
                    wr[at(nn)] = x + p;
                    wi[at(nn - 1)] = -z;
                    wi[at(nn)] = z;
                }
                nn -= 2;
                break;
            }
            if its == 60 {
                return None;
            }
            if its == 10 || its == 20 || its == 40 {
                t += x;
                for i in 0..=nn {
                    a[at(i)][at(i)] -= x;
                }
                s = a[at(nn)][at(nn - 1)].abs() + a[at(nn - 1)][at(nn - 2)].abs();
                x = 0.75 * s;
                y = x;
                w = -0.4375 * s * s;
            }
            its += 1;
            let mut m = nn - 2;
            while m >= l {
                z = a[at(m)][at(m)];
                r = x - z;
                s = y - z;
                p = (r * s - w) / a[at(m + 1)][at(m)] + a[at(m)][at(m + 1)];
                q = a[at(m + 1)][at(m + 1)] - z - r - s;
                r = a[at(m + 2)][at(m + 1)];
                s = p.abs() + q.abs() + r.abs();
                p /= s;
                q /= s;
                r /= s;
                if m == l {
                    break;
                }
                let u = a[at(m)][at(m - 1)].abs() * (q.abs() + r.abs());
                let v = p.abs()
                    * (a[at(m - 1)][at(m - 1)].abs() + z.abs() + a[at(m + 1)][at(m + 1)].abs());
                if u + v == v {
                    break;
                }
                m -= 1;
            }
            for i in (m + 2)..=nn {
                a[at(i)][at(i - 2)] = 0.0;
                if i != m + 2 {
                    a[at(i)][at(i - 3)] = 0.0;
                }
            }
            let mut k = m;
            while k < nn {
                if k != m {
                    p = a[at(k)][at(k - 1)];
                    q = a[at(k + 1)][at(k - 1)];
                    r = 0.0;
                    if k != nn - 1 {
                        r = a[at(k + 2)][at(k - 1)];
                    }
                    x = p.abs() + q.abs() + r.abs();
                    if x != 0.0 {
                        p /= x;
                        q /= x;
                        r /= x;
                    }
                }
                s = sign((p * p + q * q + r * r).sqrt(), p);
                if s != 0.0 {
                    if k == m {
                        if l != m {
                            a[at(k)][at(k - 1)] = -a[at(k)][at(k - 1)];
                        }
                    } else {
                        a[at(k)][at(k - 1)] = -s * x;
                    }
                    p += s;
                    x = p / s;
                    y = q / s;
                    z = r / s;
                    q /= p;
                    r /= p;
                    for j in k..=nn {
                        p = a[at(k)][at(j)] + q * a[at(k + 1)][at(j)];
                        if k != nn - 1 {
                            p += r * a[at(k + 2)][at(j)];
                            a[at(k + 2)][at(j)] -= p * z;
                        }
                        a[at(k + 1)][at(j)] -= p * y;
                        a[at(k)][at(j)] -= p * x;
                    }
                    let mmin = if nn < k + 3 { nn } else { k + 3 };
                    for i in l..=mmin {
                        p = x * a[at(i)][at(k)] + y * a[at(i)][at(k + 1)];
                        if k != nn - 1 {
                            p += z * a[at(i)][at(k + 2)];
                            a[at(i)][at(k + 2)] -= p * r;
                        }
                        a[at(i)][at(k + 1)] -= p * q;
                        a[at(i)][at(k)] -= p;
                    }
                }
                k += 1;
            }
        }
    }
    let mut out: Vec<(f64, f64)> = wr.into_iter().zip(wi).collect();
    out.sort_by(|a, b| b.0.total_cmp(&a.0).then(b.1.total_cmp(&a.1)));
    Some(out)
}

// ---------------------------------------------------------------------------
// Public results.

/// One eigenvalue \[1/s\].
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Eig {
    /// Real part \[1/s\] (growth rate if > 0).
    pub re: f64,
    /// Imaginary part \[rad/s\].
    pub im: f64,
}

/// Stability verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Verdict {
    /// Every Re λ < −tol.
    Stable,
    /// Some Re λ > tol.
    Unstable,
    /// Neither: the largest Re λ is within ±tol of 0.
    Marginal,
}

impl Verdict {
    /// Lower-case name.
    pub fn as_str(&self) -> &'static str {
        match self {
            Verdict::Stable => "stable",
            Verdict::Unstable => "unstable",
            Verdict::Marginal => "marginal",
        }
    }
}

/// Verdict from eigenvalues, with `tol = tol_rel · max|λ|`. Returns
/// (verdict, max Re λ, tol).
pub fn verdict_of(eigs: &[Eig], tol_rel: f64) -> (Verdict, f64, f64) {
    let rho = eigs.iter().map(|e| e.re.hypot(e.im)).fold(0.0, f64::max);
    let tol = tol_rel * rho;
    let max_re = eigs.iter().map(|e| e.re).fold(f64::NEG_INFINITY, f64::max);
    let v = if eigs.is_empty() {
        Verdict::Marginal
    } else if max_re > tol {
        Verdict::Unstable
    } else if max_re < -tol {
        Verdict::Stable
    } else {
        Verdict::Marginal
    };
    (v, max_re, tol)
}

/// Physical parameters of a linearisation (SI).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Physics {
    /// The body.
    #[serde(skip)]
    pub top: Top,
    /// g \[m/s²\].
    pub gravity: f64,
    /// μ.
    pub mu: f64,
    /// Smooth friction law.
    pub law: SmoothLaw,
    /// ε \[m/s\].
    pub eps: f64,
}

/// The linearisation at one steady motion.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Linearisation {
    /// θ* \[rad\].
    pub theta: f64,
    /// Ω* \[rad/s\] (0 at the poles, where it is not defined).
    pub precession: f64,
    /// ω* = n·k \[rad/s\].
    pub spin: f64,
    /// Normal force at the steady motion \[N\].
    pub normal: f64,
    /// Eigenvalues after removing the structural zeros, largest real part first \[1/s\].
    pub eigenvalues: Vec<Eig>,
    /// What was removed (structural zero eigenvalues).
    pub removed: Vec<String>,
    /// max Re λ \[1/s\].
    pub max_re: f64,
    /// The tolerance of the verdict \[1/s\].
    pub tol: f64,
    /// Verdict.
    pub verdict: Verdict,
    /// max |ẋ| at the steady state, scaled (should be ~1e-16: it is steady).
    pub residual: f64,
    /// |∇J · M| / (|∇J| |M|): the check that J is a left null vector (~1e-16).
    pub jellett_check: f64,
}

/// Ω*² of the zero-slip relative equilibrium at θ (H = 0, smooth friction):
/// `Ω*² = m g a/[(A − C) cos θ + C a/R]` \[rad²/s²\]; `None` where the right
/// side is not positive and finite (no such steady motion).
pub fn relative_equilibrium_precession_sq(top: &Top, gravity: f64, theta: f64) -> Option<f64> {
    let (a, ia, ic, r, m) = (
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
        top.radius,
        top.mass,
    );
    let den = (ia - ic) * theta.cos() + ic * a / r;
    let o2 = m * gravity * a / den;
    (den > 0.0 && o2.is_finite() && o2 > 0.0).then_some(o2)
}

/// Spin of the zero-slip relative equilibrium: `ω* = Ω* (cos θ − a/R)` \[rad/s\].
pub fn relative_equilibrium_spin(top: &Top, theta: f64, precession: f64) -> f64 {
    precession * (theta.cos() - top.offset / top.radius)
}

/// Jellett's `J = A Ω R sin²θ + C ω (R cos θ − a)` \[kg m³/s\].
pub fn jellett(top: &Top, theta: f64, precession: f64, spin: f64) -> f64 {
    let s = theta.sin();
    top.inertia_transverse * precession * top.radius * s * s
        + top.inertia_axial * spin * (top.radius * theta.cos() - top.offset)
}

/// Sleeping-top threshold at θ = π on a frictionless plane:
/// `ω_c = 2 √(A m g a)/C` \[rad/s\] (stable for |ω| > ω_c).
pub fn sleeping_threshold(top: &Top, gravity: f64) -> f64 {
    2.0 * (top.inertia_transverse * top.mass * gravity * top.offset).sqrt() / top.inertia_axial
}

/// Linearise about the steady motion (θ*, Ω*, ω*) (SI) with H = 0. At the
/// poles (sin θ* < 1e-12) Ω* is ignored; elsewhere (θ*, Ω*, ω*) must be a
/// steady motion (the residual is reported). `tol_rel` as in [`Options`].
pub fn linearise(
    ph: &Physics,
    theta: f64,
    precession: f64,
    spin: f64,
    tol_rel: f64,
) -> Result<Linearisation, Error> {
    let top = &ph.top;
    let (s, c) = theta.sin_cos();
    let pole = s.abs() < 1e-12;
    let (s, c) = if pole { (0.0, c.signum()) } else { (s, c) };
    let om = if pole { 0.0 } else { precession };
    // n* in the frame with x towards the tilt.
    let n_si = [(spin - om * c) * s, 0.0, om * s * s + spin * c];
    let nmag = (n_si[0] * n_si[0] + n_si[2] * n_si[2]).sqrt();
    let rate = [nmag, om.abs(), (ph.gravity / top.radius).sqrt()]
        .into_iter()
        .fold(0.0, f64::max);
    let rate = if rate > 0.0 { rate } else { 1.0 };
    let tu = 1.0 / rate;
    let vu = top.radius * rate;
    let mr2 = top.mass * top.radius * top.radius;
    let rig = Rigid {
        a: top.offset / top.radius,
        ia: top.inertia_transverse / mr2,
        ic: top.inertia_axial / mr2,
        g: ph.gravity * tu * tu / top.radius,
        mu: ph.mu,
        law: ph.law,
        eps: ph.eps / vu,
        frame: om * tu,
        kstar: [s, 0.0, c],
        e1: [c, 0.0, -s],
        e2: [0.0, 1.0, 0.0],
    };
    if !(ph.eps > 0.0 && ph.eps.is_finite()) {
        return Err(Error::invalid(
            "eps",
            format!("{} is not allowed", ph.eps),
            "a finite speed > 0 [m/s]".into(),
        ));
    }
    let x0 = [0.0, 0.0, n_si[0] * tu, 0.0, n_si[2] * tu, 0.0, 0.0];
    let (f0, n0) = rig.rhs(&x0);
    let residual = f0.iter().map(|v| v.abs()).fold(0.0, f64::max);
    let mut jac = vec![vec![0.0; RDIM]; RDIM];
    let mut dj = [0.0; RDIM];
    for j in 0..RDIM {
        let xd = duals(&x0, j);
        let (f, _) = rig.rhs(&xd);
        for i in 0..RDIM {
            jac[i][j] = f[i].d;
        }
        dj[j] = rig.jellett(&xd).d;
    }
    // Check ∇J M = 0.
    let jm: Vec<f64> = (0..RDIM)
        .map(|j| (0..RDIM).map(|i| dj[i] * jac[i][j]).sum())
        .collect();
    let mnorm = jac.iter().flatten().map(|v| v * v).sum::<f64>().sqrt();
    let djn = dj.iter().map(|v| v * v).sum::<f64>().sqrt();
    let jellett_check = jm.iter().map(|v| v * v).sum::<f64>().sqrt() / (djn * mnorm).max(1e-300);
    // Structural directions: ∇J (left null), rotation generator (right null).
    let mut remove: Vec<[f64; RDIM]> = Vec::new();
    let mut removed = Vec::new();
    if djn > 0.0 {
        remove.push(dj);
        removed.push("0 (Jellett's J is conserved: family of steady motions)".to_string());
    }
    let rot = [0.0, s, 0.0, x0[2], 0.0, 0.0, 0.0];
    if !pole {
        remove.push(rot);
        removed.push("0 (rotation about Z: symmetry, turning frame)".to_string());
    }
    let basis = complement(&remove);
    let k = basis.len();
    let red: Vec<Vec<f64>> = (0..k)
        .map(|i| {
            (0..k)
                .map(|j| {
                    let mut acc = 0.0;
                    for a in 0..RDIM {
                        let mut mp = 0.0;
                        for b in 0..RDIM {
                            mp += jac[a][b] * basis[j][b];
                        }
                        acc += basis[i][a] * mp;
                    }
                    acc
                })
                .collect()
        })
        .collect();
    let ev = eigenvalues(&red).ok_or_else(|| {
        Error::runtime(
            0.0,
            "the QR eigenvalue iteration did not converge".to_string(),
        )
    })?;
    let eigs: Vec<Eig> = ev
        .iter()
        .map(|&(re, im)| Eig {
            re: re / tu,
            im: im / tu,
        })
        .collect();
    let (verdict, max_re, tol) = verdict_of(&eigs, tol_rel);
    Ok(Linearisation {
        theta,
        precession: om,
        spin,
        normal: n0 * top.mass * top.radius / (tu * tu),
        eigenvalues: eigs,
        removed,
        max_re,
        tol,
        verdict,
        residual,
        jellett_check,
    })
}

/// Orthonormal basis of the orthogonal complement of span(vs) in R^7.
fn complement(vs: &[[f64; RDIM]]) -> Vec<[f64; RDIM]> {
    let mut q: Vec<[f64; RDIM]> = Vec::new();
    let push = |q: &mut Vec<[f64; RDIM]>, v: [f64; RDIM]| -> bool {
        let mut w = v;
        for _ in 0..2 {
            for b in q.iter() {
                let d: f64 = (0..RDIM).map(|i| w[i] * b[i]).sum();
                for i in 0..RDIM {
                    w[i] -= d * b[i];
                }
            }
        }
        let n = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let n0 = v.iter().map(|x| x * x).sum::<f64>().sqrt();
        if n > 1e-10 * n0.max(1e-300) && n > 0.0 {
            q.push(std::array::from_fn(|i| w[i] / n));
            true
        } else {
            false
        }
    };
    for v in vs {
        push(&mut q, *v);
    }
    let nfixed = q.len();
    for e in 0..RDIM {
        let v: [f64; RDIM] = std::array::from_fn(|i| if i == e { 1.0 } else { 0.0 });
        push(&mut q, v);
        if q.len() == RDIM {
            break;
        }
    }
    q.split_off(nfixed)
}

// ---------------------------------------------------------------------------
// Frozen-spin analysis on the reduced model.

/// How Ω is treated in the frozen-spin analysis.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrozenVariant {
    /// Ω held at a given value (the paper's assumption in B1–B4).
    PrecessionFrozen,
    /// Ω from Jellett's J at each θ (keeps the gyroscopic coupling).
    PrecessionFromJellett,
}

/// Frozen-spin (quasi-static) analysis of the θ equation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrozenSpin {
    /// Always "frozen-spin (quasi-static), not a true equilibrium".
    pub label: String,
    /// Variant.
    pub variant: FrozenVariant,
    /// Where the search started \[rad\].
    pub theta_start: f64,
    /// Quasi-equilibrium θ_q \[rad\] (θ̈(θ_q, 0) = 0), if found.
    pub theta_quasi: Option<f64>,
    /// Ω at θ_q \[rad/s\].
    pub precession: f64,
    /// Frozen ω \[rad/s\].
    pub spin: f64,
    /// Applied force (H_x, H_y) \[N\].
    pub applied: [f64; 2],
    /// ∂θ̈/∂θ \[1/s²\] at θ_q.
    pub d_theta: f64,
    /// ∂θ̈/∂θ̇ \[1/s\] at θ_q.
    pub d_theta_dot: f64,
    /// Roots of λ² − (∂θ̈/∂θ̇) λ − ∂θ̈/∂θ = 0 \[1/s\].
    pub eigenvalues: Vec<Eig>,
    /// Verdict (of the frozen problem only).
    pub verdict: Option<Verdict>,
    /// What happened.
    pub note: String,
}

/// Inputs of a frozen-spin analysis (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrozenInput {
    /// Start of the root search \[rad\].
    pub theta: f64,
    /// ω \[rad/s\].
    pub spin: f64,
    /// Ω \[rad/s\] (used by [`FrozenVariant::PrecessionFrozen`]).
    pub precession: f64,
    /// Jellett's J \[kg m³/s\] (used by [`FrozenVariant::PrecessionFromJellett`]).
    pub jellett: f64,
    /// Centre-of-mass velocity (u_x, u_y) \[m/s\], held fixed.
    pub u: [f64; 2],
    /// Time at which the applied force is read \[s\].
    pub t_force: f64,
}

/// Frozen-spin analysis of the reduced model's θ equation (scenario `sc`
/// with its friction law replaced by the smooth law `law`, ε `eps`).
pub fn frozen_spin(
    sc: &Scenario,
    law: SmoothLaw,
    eps: f64,
    inp: &FrozenInput,
    variant: FrozenVariant,
    tol_rel: f64,
) -> FrozenSpin {
    let mut sc2 = sc.clone();
    sc2.surface.law = match law {
        SmoothLaw::Regularized => FrictionLaw::Regularized { eps },
        SmoothLaw::Viscous => FrictionLaw::Viscous { eps },
    };
    let mut m = Reduced::new(&sc2);
    let tu = m.scales.time;
    let vu = m.scales.velocity();
    m.latch_force(inp.t_force / tu);
    let top = sc.top;
    let omega_of = |th: f64| -> f64 {
        match variant {
            FrozenVariant::PrecessionFrozen => inp.precession,
            FrozenVariant::PrecessionFromJellett => {
                let s = th.sin();
                (inp.jellett - top.inertia_axial * inp.spin * (top.radius * th.cos() - top.offset))
                    / (top.inertia_transverse * top.radius * s * s)
            }
        }
    };
    // θ̈ in scaled units.
    let f = |th: f64, thd: f64| -> Option<f64> {
        let mut y = [0.0; DIM];
        y[0] = th;
        y[THD] = thd;
        y[OM] = omega_of(th) * tu;
        y[3] = inp.spin * tu;
        y[4] = inp.u[0] / vu;
        y[5] = inp.u[1] / vu;
        m.eval(&y).ok().map(|e| e.dy[THD]).filter(|v| v.is_finite())
    };
    let h = m.applied();
    let applied = [h[0] * m.scales.force(), h[1] * m.scales.force()];
    let mut out = FrozenSpin {
        label: "frozen-spin (quasi-static), not a true equilibrium".into(),
        variant,
        theta_start: inp.theta,
        theta_quasi: None,
        precession: f64::NAN,
        spin: inp.spin,
        applied,
        d_theta: f64::NAN,
        d_theta_dot: f64::NAN,
        eigenvalues: vec![],
        verdict: None,
        note: String::new(),
    };
    // Bracket a root of θ̈(θ, 0) by scanning outwards from the start.
    let lo_lim = 1e-4;
    let hi_lim = std::f64::consts::PI - 1e-4;
    let t0 = inp.theta.clamp(lo_lim, hi_lim);
    let steps = 400;
    let span = 0.8;
    let mut bracket = None;
    let f0 = f(t0, 0.0);
    if f0 == Some(0.0) {
        bracket = Some((t0, t0));
    }
    'scan: for i in 1..=steps {
        let d = span * i as f64 / steps as f64;
        let dprev = span * (i - 1) as f64 / steps as f64;
        for sgn in [1.0, -1.0] {
            let a = (t0 + sgn * dprev).clamp(lo_lim, hi_lim);
            let b = (t0 + sgn * d).clamp(lo_lim, hi_lim);
            if a == b {
                continue;
            }
            if let (Some(fa), Some(fb)) = (f(a, 0.0), f(b, 0.0)) {
                if fa == 0.0 || fa * fb < 0.0 {
                    bracket = Some((a.min(b), a.max(b)));
                    break 'scan;
                }
            }
        }
    }
    let Some((mut a, mut b)) = bracket else {
        out.note = format!(
            "no quasi-equilibrium within ±{span} rad of θ = {:.4}: θ̈(θ, 0) keeps one sign ({:+.3e} rad/s² at the start), the drive pushes θ away",
            inp.theta,
            f0.unwrap_or(f64::NAN) / (tu * tu)
        );
        return out;
    };
    if a < b {
        let mut fa = f(a, 0.0).unwrap_or(f64::NAN);
        for _ in 0..200 {
            let mid = 0.5 * (a + b);
            let fm = f(mid, 0.0).unwrap_or(f64::NAN);
            if fm == 0.0 {
                a = mid;
                b = mid;
                break;
            }
            if fa * fm < 0.0 {
                b = mid;
            } else {
                a = mid;
                fa = fm;
            }
            if b - a < 1e-15 {
                break;
            }
        }
    }
    let tq = 0.5 * (a + b);
    let hs = 1e-6;
    let (Some(fp), Some(fm), Some(gp), Some(gm)) =
        (f(tq + hs, 0.0), f(tq - hs, 0.0), f(tq, hs), f(tq, -hs))
    else {
        out.note = "the reduced model could not be evaluated near the quasi-equilibrium".into();
        return out;
    };
    let dth = (fp - fm) / (2.0 * hs);
    let dthd = (gp - gm) / (2.0 * hs);
    // λ² − dthd λ − dth = 0
    let disc = dthd * dthd + 4.0 * dth;
    let eigs: Vec<Eig> = if disc >= 0.0 {
        let sq = disc.sqrt();
        vec![
            Eig {
                re: 0.5 * (dthd + sq) / tu,
                im: 0.0,
            },
            Eig {
                re: 0.5 * (dthd - sq) / tu,
                im: 0.0,
            },
        ]
    } else {
        let sq = (-disc).sqrt();
        vec![
            Eig {
                re: 0.5 * dthd / tu,
                im: 0.5 * sq / tu,
            },
            Eig {
                re: 0.5 * dthd / tu,
                im: -0.5 * sq / tu,
            },
        ]
    };
    let (v, _, _) = verdict_of(&eigs, tol_rel);
    out.theta_quasi = Some(tq);
    out.precession = omega_of(tq);
    out.d_theta = dth / (tu * tu);
    out.d_theta_dot = dthd / tu;
    out.eigenvalues = eigs;
    out.verdict = Some(v);
    out.note = match variant {
        FrozenVariant::PrecessionFrozen => {
            "Ω, ω, u and H held fixed (the paper's App. B assumption)".into()
        }
        FrozenVariant::PrecessionFromJellett => {
            "ω, u and H held fixed, Ω from Jellett's J (gyroscopic coupling kept)".into()
        }
    };
    out
}

// ---------------------------------------------------------------------------
// The analysis of a scenario.

/// Options of [`analyse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Smooth friction law for the linearisation.
    pub law: SmoothLaw,
    /// ε \[m/s\]. `None`: the scenario's ε if its law is regularised or
    /// viscous, else `1e-3 R max(|ω0|, √(g/R))`.
    pub eps: Option<f64>,
    /// Spin about the vertical at the poles \[rad/s\]. `None`: the spin that
    /// has the scenario's initial Jellett J (upright `J/(C(R − a))`,
    /// inverted `J/(C(R + a))`).
    pub spin: Option<f64>,
    /// Relative tolerance of the verdicts (`tol = tol_rel max|λ|`).
    pub tol_rel: f64,
    /// Run the scenario to find the late-time state.
    pub run: bool,
    /// Fraction of the run (at its end) that defines the late-time state.
    pub late_fraction: f64,
}

/// Largest |[`Options::spin`]| \[rad/s\]: beyond about 1e150 the
/// linearisation's matrices overflow (QR does not converge); 1e100 leaves a
/// margin.
pub const MAX_SPIN: f64 = 1e100;

/// Range of [`Options::eps`] \[m/s\]: outside about 1e-150 ..= 1e150 the
/// linearised friction terms overflow or vanish against the others; these
/// bounds leave a margin.
pub const EPS_RANGE: (f64, f64) = (1e-100, 1e100);

/// A number for a message: plain for ordinary magnitudes, else `1e308` style.
fn num(x: f64) -> String {
    if x == 0.0 || !x.is_finite() || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

impl Options {
    /// Check the options' ranges (errors name the CLI argument: `spin`,
    /// `eps`, `tol`, `late_fraction`).
    pub fn validate(&self) -> Result<(), Error> {
        if let Some(spin) = self.spin {
            if spin.is_nan() || spin.abs() > MAX_SPIN {
                return Err(Error::invalid(
                    "spin",
                    format!("{} is not allowed", num(spin)),
                    format!("a finite spin, |spin| <= {MAX_SPIN:e} [rad/s]"),
                ));
            }
        }
        if let Some(eps) = self.eps {
            if !(EPS_RANGE.0..=EPS_RANGE.1).contains(&eps) {
                return Err(Error::invalid(
                    "eps",
                    format!("{} is not allowed", num(eps)),
                    format!(
                        "a finite speed, {:e} <= eps <= {:e} [m/s]",
                        EPS_RANGE.0, EPS_RANGE.1
                    ),
                ));
            }
        }
        if !(0.0..1.0).contains(&self.tol_rel) {
            return Err(Error::invalid(
                "tol",
                format!("{} is not allowed", num(self.tol_rel)),
                "0 <= tol < 1 (relative to max |lambda|; default 1e-10)".into(),
            ));
        }
        if !(self.late_fraction > 0.0 && self.late_fraction <= 1.0) {
            return Err(Error::invalid(
                "late_fraction",
                format!("{} is not allowed", num(self.late_fraction)),
                "0 < late_fraction <= 1".into(),
            ));
        }
        Ok(())
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            law: SmoothLaw::Regularized,
            eps: None,
            spin: None,
            tol_rel: 1e-10,
            run: true,
            late_fraction: 0.25,
        }
    }
}

/// One steady motion (H = 0) with its linearisation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SteadyMotion {
    /// Short name ("upright", "inverted", "relative equilibrium at θ = π/2", ...).
    pub name: String,
    /// How the motion was chosen.
    pub how: String,
    /// With the scenario's μ and the smooth law.
    pub with_friction: Linearisation,
    /// The same motion with μ = 0.
    pub frictionless: Linearisation,
}

/// The late-time state of the scenario's run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LateState {
    /// Window start \[s\].
    pub t_from: f64,
    /// Window end \[s\].
    pub t_to: f64,
    /// Mean θ \[rad\].
    pub theta_mean: f64,
    /// Half peak-to-peak of θ \[rad\].
    pub theta_amplitude: f64,
    /// Mean Ω \[rad/s\].
    pub precession_mean: f64,
    /// Mean ω \[rad/s\].
    pub spin_mean: f64,
    /// ω at the end \[rad/s\].
    pub spin_final: f64,
    /// Mean (u_x, u_y) \[m/s\].
    pub u_mean: [f64; 2],
    /// Mean J \[kg m³/s\].
    pub jellett: f64,
    /// "upright", "inverted", "lying" or "intermediate".
    pub class: String,
    /// The run's status ("ok" or the error).
    pub status: String,
}

/// One frozen-spin analysis with its place.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrozenCase {
    /// Where ("near θ = 0", "late-time state", ...).
    pub name: String,
    /// The analysis.
    pub result: FrozenSpin,
}

/// The paper's B1–B4 against the full analysis.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PaperCheck {
    /// "B1" … "B4".
    pub id: String,
    /// The configuration.
    pub configuration: String,
    /// What the paper's equation predicts here, with numbers.
    pub paper: String,
    /// What the full analysis gives.
    pub full: String,
    /// "yes", "no", "partly" or "n/a".
    pub agree: String,
    /// What App. B dropped.
    pub dropped: String,
}

/// Everything [`analyse`] finds.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StabilityReport {
    /// Smooth law used.
    pub law: SmoothLaw,
    /// ε \[m/s\].
    pub eps: f64,
    /// Relative tolerance of the verdicts.
    pub tol_rel: f64,
    /// μ.
    pub mu: f64,
    /// g \[m/s²\].
    pub gravity: f64,
    /// Jellett's J of the initial state \[kg m³/s\].
    pub jellett: f64,
    /// Largest applied force |H| of the schedule \[N\].
    pub applied_max: f64,
    /// Sleeping-top threshold `2 √(A m g a)/C` \[rad/s\].
    pub sleeping_threshold: f64,
    /// Steady motions (H = 0).
    pub steady: Vec<SteadyMotion>,
    /// Late-time state of the run, if run.
    pub late: Option<LateState>,
    /// Frozen-spin analyses (only if the scenario applies a force).
    pub frozen: Vec<FrozenCase>,
    /// B1–B4.
    pub paper: Vec<PaperCheck>,
}

fn late_state(sc: &Scenario, frac: f64) -> Result<LateState, Error> {
    let tr = simulate(sc)?;
    let t_to = tr.samples.last().map(|s| s.t).unwrap_or(0.0);
    let t_from = t_to * (1.0 - frac);
    let w: Vec<&crate::Sample> = tr.samples.iter().filter(|s| s.t >= t_from).collect();
    let n = w.len().max(1) as f64;
    let mean = |f: &dyn Fn(&crate::Sample) -> f64| w.iter().map(|s| f(s)).sum::<f64>() / n;
    let th_mean = mean(&|s| s.theta);
    let th_max = w.iter().map(|s| s.theta).fold(f64::NEG_INFINITY, f64::max);
    let th_min = w.iter().map(|s| s.theta).fold(f64::INFINITY, f64::min);
    let pi = std::f64::consts::PI;
    let class = if th_mean < 0.15 {
        "upright"
    } else if th_mean > pi - 0.15 {
        "inverted"
    } else if (th_mean - pi / 2.0).abs() < 0.3 {
        "lying"
    } else {
        "intermediate"
    };
    Ok(LateState {
        t_from,
        t_to,
        theta_mean: th_mean,
        theta_amplitude: 0.5 * (th_max - th_min),
        precession_mean: mean(&|s| s.precession),
        spin_mean: mean(&|s| s.spin),
        spin_final: w.last().map(|s| s.spin).unwrap_or(f64::NAN),
        u_mean: [mean(&|s| s.ux), mean(&|s| s.uy)],
        jellett: mean(&|s| s.jellett),
        class: class.into(),
        status: tr.summary.status.clone(),
    })
}

fn eig_list(e: &[Eig]) -> String {
    e.iter()
        .map(|e| {
            if e.im == 0.0 {
                format!("{:.3e}", e.re)
            } else {
                format!("{:.3e}{:+.3e}i", e.re, e.im)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Analyse the steady motions of a scenario (see the [module docs](self)).
pub fn analyse(sc: &Scenario, opts: &Options) -> Result<StabilityReport, Error> {
    opts.validate()?;
    sc.validate()?;
    let top = sc.top;
    let g = sc.surface.gravity;
    let mu = sc.surface.friction;
    let (r, a, ia, ic, m) = (
        top.radius,
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
        top.mass,
    );
    let pi = std::f64::consts::PI;
    let eps =
        match opts.eps {
            Some(e) => e,
            None => sc.surface.law.eps().unwrap_or_else(|| {
                1e-3 * r * sc.initial.spin.abs().max((g / r).sqrt()).max(1e-300)
            }),
        };
    if !(eps > 0.0 && eps.is_finite()) {
        return Err(Error::invalid(
            "eps",
            format!("{eps} is not allowed"),
            "a finite speed > 0 [m/s]".into(),
        ));
    }
    let ph = Physics {
        top,
        gravity: g,
        mu,
        law: opts.law,
        eps,
    };
    let ph0 = Physics { mu: 0.0, ..ph };
    let tol = opts.tol_rel;
    let i = &sc.initial;
    let j0 = jellett(&top, i.theta, i.precession, i.spin);
    let both =
        |name: String, how: String, th: f64, om: f64, w: f64| -> Result<SteadyMotion, Error> {
            Ok(SteadyMotion {
                name,
                how,
                with_friction: linearise(&ph, th, om, w, tol)?,
                frictionless: linearise(&ph0, th, om, w, tol)?,
            })
        };
    let mut steady = Vec::new();
    // Poles.
    let (nz_up, nz_inv, how_pole) = match opts.spin {
        Some(s) => (
            s,
            s,
            "spin about the vertical given by the user".to_string(),
        ),
        None => (
            j0 / (ic * (r - a)),
            j0 / (ic * (r + a)),
            "spin with the scenario's Jellett J".to_string(),
        ),
    };
    steady.push(both(
        "upright (θ = 0)".into(),
        format!("{how_pole}: n_Z = {nz_up:.4e} rad/s"),
        0.0,
        0.0,
        nz_up,
    )?);
    steady.push(both(
        "inverted (θ = π)".into(),
        format!("{how_pole}: n_Z = {nz_inv:.4e} rad/s"),
        pi,
        0.0,
        -nz_inv,
    )?);
    let sgn = if j0 < 0.0 { -1.0 } else { 1.0 };
    // θ* = π/2 member of the family.
    if let Some(o2) = relative_equilibrium_precession_sq(&top, g, pi / 2.0) {
        let om = sgn * o2.sqrt();
        steady.push(both(
            "relative equilibrium at θ = π/2".into(),
            "zero slip, u = 0: Ω*² = m g R/C, ω* = −Ω* a/R (any J)".into(),
            pi / 2.0,
            om,
            relative_equilibrium_spin(&top, pi / 2.0, om),
        )?);
    }
    // Members with the scenario's J.
    let jof = |th: f64| -> Option<(f64, f64)> {
        let o2 = relative_equilibrium_precession_sq(&top, g, th)?;
        let om = sgn * o2.sqrt();
        Some((
            jellett(&top, th, om, relative_equilibrium_spin(&top, th, om)) - j0,
            om,
        ))
    };
    let ngrid = 4000;
    let mut prev: Option<(f64, f64)> = None;
    let mut found = 0;
    for k in 1..ngrid {
        let th = pi * k as f64 / ngrid as f64;
        let cur = jof(th).map(|(d, _)| (th, d));
        if let (Some((t0, d0)), Some((t1, d1))) = (prev, cur) {
            if d0 * d1 <= 0.0 && found < 4 {
                let (mut lo, mut hi, mut dlo) = (t0, t1, d0);
                for _ in 0..100 {
                    let mid = 0.5 * (lo + hi);
                    let dm = jof(mid).map(|x| x.0).unwrap_or(f64::NAN);
                    if dlo * dm <= 0.0 {
                        hi = mid;
                    } else {
                        lo = mid;
                        dlo = dm;
                    }
                }
                let th = 0.5 * (lo + hi);
                if let Some((_, om)) = jof(th) {
                    found += 1;
                    steady.push(both(
                        format!("relative equilibrium with the scenario's J, θ* = {th:.4}"),
                        "zero slip, u = 0, J = J(initial)".into(),
                        th,
                        om,
                        relative_equilibrium_spin(&top, th, om),
                    )?);
                }
            }
        }
        prev = cur;
    }
    if g == 0.0 && ia != ic {
        let c = -ic * a / (r * (ia - ic));
        if c.abs() < 1.0 {
            let th = c.acos();
            let s = th.sin();
            let om = j0 / (ia * r * s * s + ic * (r * c - a).powi(2) / r);
            steady.push(both(
                format!("g = 0 relative equilibrium θ* = {th:.4}"),
                "g = 0: cos θ* = −C a/(R (A − C)) for every Ω; Ω from the scenario's J".into(),
                th,
                om,
                relative_equilibrium_spin(&top, th, om),
            )?);
        }
    }

    // Late-time state.
    let late = if opts.run {
        Some(late_state(sc, opts.late_fraction)?)
    } else {
        None
    };
    let h_late = sc.forcing.at(sc.solver.t_end);
    let h_late_mag = h_late.0.hypot(h_late.1);
    if let Some(l) = &late {
        if h_late_mag == 0.0 && l.class != "upright" && l.class != "inverted" {
            let th = l.theta_mean;
            if let Some(o2) = relative_equilibrium_precession_sq(&top, g, th) {
                let om = if l.precession_mean < 0.0 { -1.0 } else { 1.0 } * o2.sqrt();
                steady.push(both(
                    format!("relative equilibrium at the late mean θ = {th:.4}"),
                    "member of the zero-slip family at the θ the run settles to".into(),
                    th,
                    om,
                    relative_equilibrium_spin(&top, th, om),
                )?);
            }
        }
    }

    // Frozen spin (H ≠ 0).
    let mut frozen = Vec::new();
    let applied_max = sc.forcing.max_magnitude();
    if applied_max > 0.0 {
        let mut add = |name: &str, inp: FrozenInput| {
            for v in [
                FrozenVariant::PrecessionFrozen,
                FrozenVariant::PrecessionFromJellett,
            ] {
                frozen.push(FrozenCase {
                    name: name.to_string(),
                    result: frozen_spin(sc, opts.law, eps, &inp, v, tol),
                });
            }
        };
        add(
            "near θ = 0 (initial spin, force at t = 0)",
            FrozenInput {
                theta: 0.02,
                spin: i.spin,
                precession: 0.0,
                jellett: j0,
                u: [0.0, 0.0],
                t_force: 0.0,
            },
        );
        add(
            "near θ = π (initial J, force at t = 0)",
            FrozenInput {
                theta: pi - 0.02,
                spin: -j0 / (ic * (r + a)),
                precession: -j0 / (ic * (r + a)),
                jellett: j0,
                u: [0.0, 0.0],
                t_force: 0.0,
            },
        );
        if let Some(l) = &late {
            add(
                "late-time state of the run",
                FrozenInput {
                    theta: l.theta_mean,
                    spin: l.spin_mean,
                    precession: l.precession_mean,
                    jellett: l.jellett,
                    u: l.u_mean,
                    t_force: l.t_to,
                },
            );
        } else {
            add(
                "near θ = π/2 (initial spin, force at t = 0)",
                FrozenInput {
                    theta: pi / 2.0,
                    spin: i.spin,
                    precession: 0.0,
                    jellett: j0,
                    u: [0.0, 0.0],
                    t_force: 0.0,
                },
            );
        }
    }

    // B1–B4.
    let n0 = m * g;
    let h = applied_max / std::f64::consts::SQRT_2; // H_x = H_y = H in the paper
    let wc = sleeping_threshold(&top, g);
    let up = &steady[0];
    let inv = &steady[1];
    let mut paper = Vec::new();
    {
        let w = up.with_friction.spin;
        let nu_p = (ic * w + (ic * ic * w * w + 4.0 * ia * a * n0).sqrt()) / (2.0 * ia);
        let nu_m = (ic * w - (ic * ic * w * w + 4.0 * ia * a * n0).sqrt()) / (2.0 * ia);
        let v = up.with_friction.verdict;
        paper.push(PaperCheck {
            id: "B1".into(),
            configuration: format!("θ = 0, H = 0, ω = {w:.4e} rad/s"),
            paper: format!(
                "ε̈ = −aNε/A: always stable, one frequency √(a m g/A) = {:.4e} rad/s",
                (a * n0 / ia).sqrt()
            ),
            full: format!(
                "μ = 0: marginal (stable), two frequencies ν± = [Cω ± √(C²ω² + 4 A a m g)]/(2A) = {nu_p:.4e}, {nu_m:.4e} rad/s (verdict {}); with friction ({} ε = {eps:.3e} m/s): {} (max Re λ = {:.3e} 1/s; λ = {})",
                up.frictionless.verdict.as_str(),
                opts.law.name(),
                v.as_str(),
                up.with_friction.max_re,
                eig_list(&up.with_friction.eigenvalues)
            ),
            agree: if v == Verdict::Unstable { "no" } else { "partly" }.into(),
            dropped: "the gyroscopic term −Ω(Cω − AΩ cos θ) sin θ (Ω set to 0; with J conserved Ω → Cω/(2A) at θ → 0, which adds C²ω²/(4A) to the stiffness), and the friction torque −h F_x, which is what destabilises the upright top".into(),
        });
    }
    {
        if h == 0.0 {
            paper.push(PaperCheck {
                id: "B2".into(),
                configuration: "θ = 0 with H_x = H_y = H".into(),
                paper: "n/a: the scenario has H = 0 (B2 reduces to B1)".into(),
                full: "n/a".into(),
                agree: "n/a".into(),
                dropped: "as B1, and the fact that H ≠ 0 leaves no equilibrium".into(),
            });
        } else {
            let eq = (r - a) * h / (a * n0);
            let fz: Vec<&FrozenCase> = frozen
                .iter()
                .filter(|f| f.name.starts_with("near θ = 0"))
                .collect();
            let desc = fz
                .iter()
                .map(|f| match f.result.theta_quasi {
                    Some(tq) => format!(
                        "{:?}: θ_q = {tq:.4}, λ = {} ({})",
                        f.result.variant,
                        eig_list(&f.result.eigenvalues),
                        f.result.verdict.map(|v| v.as_str()).unwrap_or("-")
                    ),
                    None => format!("{:?}: {}", f.result.variant, f.result.note),
                })
                .collect::<Vec<_>>()
                .join("; ");
            paper.push(PaperCheck {
                id: "B2".into(),
                configuration: format!("θ = 0, H = {h:.3e} N"),
                paper: format!(
                    "ε̈ = −aNε/A + (R − a)H/A: 'stable', about ε_q = (R − a)H/(a m g) = {eq:.3e} rad"
                ),
                full: format!(
                    "no equilibrium (H ≠ 0: ω changes). Frozen-spin (quasi-static), not a true equilibrium: {desc}"
                ),
                agree: if eq > 0.3 { "no" } else { "partly" }.into(),
                dropped: "as B1; and ε_q is not small when (R − a)H > 0.3 a m g, so the linearisation about θ = 0 does not apply: the drive tips the top over".into(),
            });
        }
    }
    {
        let w = inv.with_friction.spin;
        let grow = (((ic + ia) * w * w + a * n0) / ia).sqrt();
        let v = inv.with_friction.verdict;
        paper.push(PaperCheck {
            id: "B3".into(),
            configuration: format!("θ = π, H = 0, ω = {w:.4e} rad/s (spin about the vertical {:.4e})", -w),
            paper: format!(
                "ε̈ = [(C + A)Ω² + aN]ε/A with Ω = ω: always unstable, growth {grow:.3e} 1/s"
            ),
            full: format!(
                "μ = 0: stable iff C²ω² > 4 A m g a, ω_c = {wc:.4e} rad/s, here |ω|/ω_c = {:.3}: {}; with friction ({} ε = {eps:.3e} m/s): {} (max Re λ = {:.3e} 1/s; λ = {})",
                w.abs() / wc,
                inv.frictionless.verdict.as_str(),
                opts.law.name(),
                v.as_str(),
                inv.with_friction.max_re,
                eig_list(&inv.with_friction.eigenvalues)
            ),
            agree: if v == Verdict::Unstable { "yes" } else { "no" }.into(),
            dropped: "Ω = ω is not a property of θ → π (there Ω is undefined; with J conserved Ω → −Cω/(2A)); with that, −Ω(Cω − AΩ cos θ) sin θ gives −C²ω²/(4A) ε instead of +(C + A)ω² ε, i.e. ε̈ = [a m g − C²ω²/(4A)]ε/A: the sleeping-top criterion. Friction (R + a)F_x is dropped too.".into(),
        });
    }
    {
        let lying = steady
            .iter()
            .find(|s| s.name == "relative equilibrium at θ = π/2");
        let mut full = String::new();
        let mut agree = "n/a".to_string();
        if let Some(l) = lying {
            let o = l.with_friction.precession;
            full += &format!(
                "H = 0: the zero-slip steady motion at π/2 has Ω* = {o:.4e} rad/s, ω* = {:.4e}; paper (AΩ² > aH = 0) says stable; full linearisation: {} (max Re λ = {:.3e} 1/s; λ = {}); μ = 0: {}. ",
                l.with_friction.spin,
                l.with_friction.verdict.as_str(),
                l.with_friction.max_re,
                eig_list(&l.with_friction.eigenvalues),
                l.frictionless.verdict.as_str()
            );
            agree = if l.with_friction.verdict == Verdict::Unstable {
                "no".into()
            } else {
                "yes".into()
            };
        } else {
            full += "H = 0: no zero-slip steady motion at π/2 (g = 0). ";
        }
        let mut paper_txt =
            "ε̈ = −(AΩ² − aH)ε/A − (HR − CωΩ − aN)/A: stable iff AΩ² > aH".to_string();
        if h > 0.0 {
            for f in frozen
                .iter()
                .filter(|f| f.name.starts_with("late") || f.name.contains("π/2"))
            {
                full += &match f.result.theta_quasi {
                    Some(tq) => format!(
                        "H ≠ 0, frozen-spin (quasi-static), not a true equilibrium, {:?} at the {}: θ_q = {tq:.4} (θ_q − π/2 = {:+.3e}), Ω = {:.3e}, ω = {:.3e}, λ = {} ({}). ",
                        f.result.variant,
                        f.name,
                        tq - pi / 2.0,
                        f.result.precession,
                        f.result.spin,
                        eig_list(&f.result.eigenvalues),
                        f.result.verdict.map(|v| v.as_str()).unwrap_or("-")
                    ),
                    None => format!("H ≠ 0, {:?}: {}. ", f.result.variant, f.result.note),
                };
            }
            if let Some(l) = &late {
                let o = l.precession_mean;
                paper_txt += &format!(
                    "; at the late state Ω = {o:.3e}: AΩ² − aH = {:.3e} ⇒ {}",
                    ia * o * o - a * h,
                    if ia * o * o > a * h {
                        "stable"
                    } else {
                        "unstable"
                    }
                );
                let fj = frozen.iter().find(|f| {
                    f.name.starts_with("late")
                        && f.result.variant == FrozenVariant::PrecessionFromJellett
                });
                let ff = frozen.iter().find(|f| {
                    f.name.starts_with("late")
                        && f.result.variant == FrozenVariant::PrecessionFrozen
                });
                let paper_stable = ia * o * o > a * h;
                if let (Some(fj), Some(ff)) = (fj, ff) {
                    let vj = fj.result.verdict;
                    let vf = ff.result.verdict;
                    agree = format!(
                        "{} (Ω frozen: {}; Ω from J: {})",
                        if vj
                            .map(|v| (v != Verdict::Unstable) == paper_stable)
                            .unwrap_or(false)
                        {
                            "partly"
                        } else {
                            "no"
                        },
                        vf.map(|v| v.as_str()).unwrap_or("no quasi-equilibrium"),
                        vj.map(|v| v.as_str()).unwrap_or("no quasi-equilibrium")
                    );
                }
            }
        }
        paper.push(PaperCheck {
            id: "B4".into(),
            configuration: format!("θ = π/2, H = {h:.3e} N"),
            paper: paper_txt,
            full,
            agree,
            dropped: "the gyroscopic coupling through Ω(θ): with J conserved ∂Ω/∂θ = Cω/A at π/2, which adds ≈ C²ω²/A to the stiffness (the nutation frequency Cω/A); the friction μN in F_x; and that H ≠ 0 leaves no equilibrium (ω changes at −R H/C)".into(),
        });
    }

    Ok(StabilityReport {
        law: opts.law,
        eps,
        tol_rel: tol,
        mu,
        gravity: g,
        jellett: j0,
        applied_max,
        sleeping_threshold: wc,
        steady,
        late,
        frozen,
        paper,
    })
}
