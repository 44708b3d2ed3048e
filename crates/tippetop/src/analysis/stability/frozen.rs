//! Frozen-spin (quasi-static) analysis of the reduced model's θ equation,
//! for H ≠ 0 where nothing is steady: the assumption of the paper's B1–B4,
//! and a variant that keeps the gyroscopic coupling through Jellett's J.

use serde::Serialize;

use super::axis_model::SmoothLaw;
use super::linearisation::{Eig, Verdict, verdict_of};
use crate::{
    FrictionLaw, Scenario,
    model::reduced::{DIM, OM, Reduced, THD},
};

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
        (a, b) = bisect(&f, a, b);
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
    let eigs = eigenvalues_of(dth, dthd, tu);
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

/// Shrink the bracket `[a, b]` of a root of θ̈(θ, 0) (`f(θ, 0)`) by
/// bisection, to 1e-15 rad or an exact zero.
fn bisect(f: &dyn Fn(f64, f64) -> Option<f64>, mut a: f64, mut b: f64) -> (f64, f64) {
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
    (a, b)
}

/// The roots λ of λ² − dthd λ − dth = 0 (scaled units; `tu` the time
/// unit [s]) as eigenvalues [1/s].
fn eigenvalues_of(dth: f64, dthd: f64, tu: f64) -> Vec<Eig> {
    let disc = dthd * dthd + 4.0 * dth;
    if disc >= 0.0 {
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
    }
}
