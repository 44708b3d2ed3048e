//! The model the stability analysis linearises: the axis-vector form of the
//! paper's physics with a smooth friction law, generic over `Num` (`numeric::dual`) so that
//! dual numbers give its exact Jacobian. See the module doc of
//! [`super`] for the equations.

use serde::Serialize;

use crate::Top;
use crate::numeric::dual::{Num, cross, dot, lift};

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
    let rig = AxisModel {
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

/// The axis-vector model that is linearised, in scaled units (R = m = 1,
/// time 1/rate): the paper's physics with a smooth friction law, written for
/// the axis `k` in a chart regular at the poles. It is not the simulated
/// vector model (`model::vector`): it needs a generic number type for the
/// dual-number Jacobian and a frame turning at a chosen rate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AxisModel {
    pub(crate) a: f64,
    pub(crate) ia: f64,
    pub(crate) ic: f64,
    pub(crate) g: f64,
    pub(crate) mu: f64,
    pub(crate) law: SmoothLaw,
    pub(crate) eps: f64,
    /// Rotation rate of the frame about Z.
    pub(crate) frame: f64,
    pub(crate) kstar: [f64; 3],
    pub(crate) e1: [f64; 3],
    pub(crate) e2: [f64; 3],
}

impl AxisModel {
    pub(crate) fn k_of<S: Num>(&self, xi: S, eta: S) -> [S; 3] {
        let w: [S; 3] = std::array::from_fn(|i| {
            S::k(self.kstar[i]) + xi * S::k(self.e1[i]) + eta * S::k(self.e2[i])
        });
        let n = dot(w, w).sqrt();
        [w[0] / n, w[1] / n, w[2] / n]
    }

    /// `I⁻¹ y` with `I = A 1 + (C − A) k kᵀ`.
    pub(crate) fn inv_i<S: Num>(&self, k: [S; 3], y: [S; 3]) -> [S; 3] {
        let c = S::k((self.ic - self.ia) / (self.ia * self.ic)) * dot(k, y);
        let ia = S::k(self.ia);
        [
            y[0] / ia - c * k[0],
            y[1] / ia - c * k[1],
            y[2] / ia - c * k[2],
        ]
    }

    /// Right-hand side and normal force.
    pub(crate) fn rhs<S: Num>(&self, x: &[S; RDIM]) -> ([S; RDIM], S) {
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
    pub(crate) fn jellett<S: Num>(&self, x: &[S; RDIM]) -> S {
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
