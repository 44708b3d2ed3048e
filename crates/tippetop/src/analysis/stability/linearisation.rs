//! Linearisation of the axis model about a steady motion, the structural
//! zero eigenvalues removed, and the verdict; the closed forms of the
//! steady motions (relative equilibria, the sleeping threshold, Jellett's J).

// Dense linear algebra on small matrices reads best with indices.
#![allow(clippy::needless_range_loop)]

use serde::Serialize;

pub use super::axis_model::Physics;
use super::axis_model::{AxisModel, RDIM};
use crate::numeric::dual::seeded;
use crate::numeric::eigen::eigenvalues;
use crate::{Error, Top};

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
/// steady motion (the residual is reported). `tol_rel` as in [`super::Options`].
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
    let rig = AxisModel {
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
        let xd = seeded(&x0, j);
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
            crate::Failure::Numerics,
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
