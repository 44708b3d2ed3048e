//! Stability of the steady motions (the paper's App. B), by exact numerical
//! linearisation in coordinates that are regular at the poles.
//!
//! # Method
//!
//! **Model.** The reduced Euler-angle model divides by sin θ, so it cannot be
//! linearised at θ = 0 or π. Here the same physics (docs/physics.md#kinematics–§normal-force, §friction-laws) is
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
//! constraint `u_z = −a k̇_z` together with `ṅ` (as in §normal-force), and a **smooth**
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
//!
//! # Layout
//!
//! - [`axis_model`]: the model that is linearised (generic over the number
//!   type, for dual-number Jacobians from `numeric::dual`);
//! - [`linearisation`]: the Jacobian at a steady motion, the structural zeros
//!   removed, eigenvalues (`numeric::eigen`) and verdict; the
//!   closed forms of the steady motions;
//! - [`frozen`]: the frozen-spin analysis for H ≠ 0;
//! - this module: [`analyse`], which finds the steady motions of a scenario
//!   and sets each of the paper's B1–B4 beside the full linearisation.

pub mod axis_model;
pub mod frozen;
pub mod inversion;
pub mod linearisation;

use serde::Serialize;

pub use crate::numeric::eigen::eigenvalues;
pub use axis_model::{AxisDerivatives, RDIM, SmoothLaw, axis_model_derivatives};
pub use frozen::{FrozenInput, FrozenSpin, FrozenVariant, frozen_spin};
pub use inversion::{Inversion, inversion};
pub use linearisation::{
    Eig, Linearisation, Physics, Verdict, jellett, linearise, relative_equilibrium_precession_sq,
    relative_equilibrium_spin, sleeping_threshold, verdict_of,
};

use crate::human::s4;
use crate::{Error, Scenario, Top};

/// Options of [`analyse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Smooth friction law for the linearisation. `None`: the scenario's
    /// law if it is regularised or viscous, else the regularised law
    /// ([`law_and_eps`]).
    pub law: Option<SmoothLaw>,
    /// ε \[m/s\]. `None`: the scenario's ε if its law is regularised or
    /// viscous (and the one linearised), else `1e-3 R max(|ω0|, √(g/R))`.
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

    /// The law linearised, once [`analyse`] has resolved it.
    fn smooth(&self) -> SmoothLaw {
        self.law.unwrap_or(SmoothLaw::Regularized)
    }
}

impl Default for Options {
    fn default() -> Self {
        Options {
            law: None,
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
    /// Full inversion: the least energy at the scenario's J
    /// ([`inversion`], H = 0, wells included).
    pub inversion: Inversion,
    /// Late-time state of the run, if run.
    pub late: Option<LateState>,
    /// Frozen-spin analyses (only if the scenario applies a force).
    pub frozen: Vec<FrozenCase>,
    /// B1–B4.
    pub paper: Vec<PaperCheck>,
}

fn late_state(sc: &Scenario, frac: f64) -> Result<LateState, Error> {
    // θ, the rates, the velocity and J of the late rows: no pose.
    let tr = crate::simulate_with_pose(sc, false, &mut |_| {})?;
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
                s4(e.re)
            } else {
                crate::human::complex(e.re, e.im)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// Whether the analysis covers `sc`: the linearised model has no drilling
/// torque (Coulomb–Contensou friction over a disc, docs/physics.md#contensou),
/// no vertical load (`force.K.hz`, docs/physics.md#vertical-load), no
/// adhesion (§adhesion) and no body actuator (§actuators), so a scenario
/// with one is bad input naming the key.
pub fn supports(sc: &Scenario) -> Result<(), Error> {
    if let crate::FrictionLaw::Contensou { radius, .. } = sc.surface.law {
        // A disc of radius 0 is the point law, exact Coulomb bit for bit,
        // which the smooth law stands in for as it does for "coulomb".
        if radius > 0.0 {
            return Err(Error::invalid(
                "surface.friction_law",
                format!(
                    "the stability analysis does not linearise {}: its model has no drilling torque",
                    crate::sim::messages::law_phrase(sc.surface.law)
                ),
                "\"coulomb\", \"coulomb_sliding\", \"regularized\" or \"viscous\", or contact_radius = 0; use `tippetop run` for the contact disc".into(),
            ));
        }
    }
    if sc.adhesion().is_on() {
        return Err(Error::invalid(
            "adhesion.force",
            "the stability analysis does not model adhesion".into(),
            "0; use `tippetop run` for an adhesive top".into(),
        ));
    }
    if !sc.actuators.is_empty() {
        let k = sc.forcing.windows.len();
        return Err(Error::invalid(
            &format!("force.{k}.kind"),
            format!(
                "the stability analysis does not model a body actuator (\"{}\", docs/physics.md#actuators)",
                sc.actuators[0].actuator.name()
            ),
            "\"contact\"; use `tippetop run` for a tip or a magnet".into(),
        ));
    }
    if let Some(key) = crate::input::scenario::plugins::first_key(sc) {
        return Err(Error::invalid(
            &key,
            "the stability analysis does not model the force plug-ins' tables".into(),
            "no such table; use `tippetop run`".into(),
        ));
    }
    match sc.forcing.windows.iter().position(|w| w.hz != 0.0) {
        Some(k) => Err(Error::invalid(
            &format!("force.{k}.hz"),
            "the stability analysis does not model a vertical load".into(),
            "0; use `tippetop run` for a loaded top".into(),
        )),
        None => Ok(()),
    }
}

/// Analyse the steady motions of a scenario (see the [module docs](self)).
pub fn analyse(sc: &Scenario, opts: &Options) -> Result<StabilityReport, Error> {
    opts.validate()?;
    sc.validate()?;
    supports(sc)?;
    let top = sc.top;
    let g = sc.surface.gravity;
    let mu = sc.surface.friction;
    let (law, eps) = law_and_eps(sc, opts)?;
    let opts = &Options {
        law: Some(law),
        ..*opts
    };
    let ph = Physics {
        top,
        gravity: g,
        mu,
        law,
        eps,
    };
    let ph0 = Physics { mu: 0.0, ..ph };
    let tol = opts.tol_rel;
    let i = &sc.initial;
    let j0 = jellett(&top, i.theta, i.precession, i.spin);
    let lin = Both {
        ph: &ph,
        ph0: &ph0,
        tol,
    };
    let mut steady = steady_motions(sc, opts, &lin, j0)?;

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
                steady.push(lin.both(
                    format!("relative equilibrium at the late mean θ = {th:.4}"),
                    "member of the zero-slip family at the θ the run settles to".into(),
                    th,
                    om,
                    relative_equilibrium_spin(&top, th, om),
                )?);
            }
        }
    }

    let applied_max = sc.forcing.max_magnitude();
    let frozen = frozen_cases(sc, opts, eps, j0, late.as_ref());

    // B1–B4.
    let n0 = top.mass * g;
    let h = applied_max / std::f64::consts::SQRT_2; // H_x = H_y = H in the paper
    let wc = sleeping_threshold(&top, g);
    let paper = vec![
        paper_b1(&top, n0, eps, opts, &steady[0]),
        paper_b2(&top, n0, h, &frozen),
        paper_b3(&top, n0, wc, eps, opts, &steady[1]),
        paper_b4(&top, h, &steady, &frozen, late.as_ref()),
    ];

    Ok(StabilityReport {
        law,
        eps,
        tol_rel: tol,
        mu,
        gravity: g,
        jellett: j0,
        applied_max,
        sleeping_threshold: wc,
        inversion: inversion(&top, g, &sc.wells(), i.theta, i.precession, i.spin),
        steady,
        late,
        frozen,
        paper,
    })
}

/// The smooth law [`analyse`] linearises and its ε \[m/s\]: the law
/// `opts.law`, else the scenario's if it is regularised or viscous, else
/// the regularised law; ε `opts.eps`, else the scenario's, else
/// `1e-3 R max(|ω0|, √(g/R))`. The scenario's ε belongs to its own law:
/// asking for the other smooth law without an ε of its own is bad input
/// (key `law`), not that law analysed with the scenario's ε.
pub fn law_and_eps(sc: &Scenario, opts: &Options) -> Result<(SmoothLaw, f64), Error> {
    use crate::FrictionLaw;
    let own = match sc.surface.law {
        FrictionLaw::Regularized { eps } => Some((SmoothLaw::Regularized, eps)),
        FrictionLaw::Viscous { eps } => Some((SmoothLaw::Viscous, eps)),
        _ => None,
    };
    let law = opts
        .law
        .or(own.map(|(l, _)| l))
        .unwrap_or(SmoothLaw::Regularized);
    if let (Some((own_law, own_eps)), None) = (own, opts.eps) {
        if own_law != law {
            return Err(Error::invalid(
                "law",
                format!(
                    "{} with the scenario's friction_eps = {} m/s, the ε of its {} law (surface.friction_law = \"{}\")",
                    law.name(),
                    num(own_eps),
                    own_law.name(),
                    own_law.name()
                ),
                format!(
                    "the scenario's law, --law {}; or the {} law with an ε of its own, --eps",
                    own_law.name(),
                    law.name()
                ),
            ));
        }
    }
    let (r, g) = (sc.top.radius, sc.surface.gravity);
    let eps = match (opts.eps, own) {
        (Some(e), _) => e,
        (None, Some((_, e))) => e,
        (None, None) => 1e-3 * r * sc.initial.spin.abs().max((g / r).sqrt()).max(1e-300),
    };
    if !(eps > 0.0 && eps.is_finite()) {
        return Err(Error::invalid(
            "eps",
            format!("{eps} is not allowed"),
            "a finite speed > 0 [m/s]".into(),
        ));
    }
    Ok((law, eps))
}

/// Linearises a steady motion with friction and without.
struct Both<'a> {
    ph: &'a Physics,
    ph0: &'a Physics,
    tol: f64,
}

impl Both<'_> {
    fn both(
        &self,
        name: String,
        how: String,
        th: f64,
        om: f64,
        w: f64,
    ) -> Result<SteadyMotion, Error> {
        Ok(SteadyMotion {
            name,
            how,
            with_friction: linearise(self.ph, th, om, w, self.tol)?,
            frictionless: linearise(self.ph0, th, om, w, self.tol)?,
        })
    }
}

/// The steady motions: the poles, the π/2 member of the zero-slip family,
/// its members with the scenario's Jellett `j0`, and at g = 0 the
/// relative equilibrium of any Ω.
fn steady_motions(
    sc: &Scenario,
    opts: &Options,
    lin: &Both,
    j0: f64,
) -> Result<Vec<SteadyMotion>, Error> {
    let top = sc.top;
    let g = sc.surface.gravity;
    let (r, a, ia, ic) = (
        top.radius,
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
    );
    let pi = std::f64::consts::PI;
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
    steady.push(lin.both(
        "upright (θ = 0)".into(),
        format!("{how_pole}: n_Z = {} rad/s", s4(nz_up)),
        0.0,
        0.0,
        nz_up,
    )?);
    steady.push(lin.both(
        "inverted (θ = π)".into(),
        format!("{how_pole}: n_Z = {} rad/s", s4(nz_inv)),
        pi,
        0.0,
        -nz_inv,
    )?);
    let sgn = if j0 < 0.0 { -1.0 } else { 1.0 };
    // θ* = π/2 member of the family.
    if let Some(o2) = relative_equilibrium_precession_sq(&top, g, pi / 2.0) {
        let om = sgn * o2.sqrt();
        steady.push(lin.both(
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
                    steady.push(lin.both(
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
            steady.push(lin.both(
                format!("g = 0 relative equilibrium θ* = {th:.4}"),
                "g = 0: cos θ* = −C a/(R (A − C)) for every Ω; Ω from the scenario's J".into(),
                th,
                om,
                relative_equilibrium_spin(&top, th, om),
            )?);
        }
    }
    Ok(steady)
}

/// The frozen-spin analyses (H ≠ 0): near θ = 0 and π, and at the late
/// state of the run (near π/2 without a run), each with Ω frozen and Ω
/// from Jellett's J.
fn frozen_cases(
    sc: &Scenario,
    opts: &Options,
    eps: f64,
    j0: f64,
    late: Option<&LateState>,
) -> Vec<FrozenCase> {
    let (r, a, ic) = (sc.top.radius, sc.top.offset, sc.top.inertia_axial);
    let pi = std::f64::consts::PI;
    let tol = opts.tol_rel;
    let i = &sc.initial;
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
                    result: frozen_spin(sc, opts.smooth(), eps, &inp, v, tol),
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
        if let Some(l) = late {
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
    frozen
}

/// B1: the upright top without a force.
fn paper_b1(top: &Top, n0: f64, eps: f64, opts: &Options, up: &SteadyMotion) -> PaperCheck {
    let (a, ia, ic) = (top.offset, top.inertia_transverse, top.inertia_axial);
    let w = up.with_friction.spin;
    let nu_p = (ic * w + (ic * ic * w * w + 4.0 * ia * a * n0).sqrt()) / (2.0 * ia);
    let nu_m = (ic * w - (ic * ic * w * w + 4.0 * ia * a * n0).sqrt()) / (2.0 * ia);
    let v = up.with_friction.verdict;
    PaperCheck {
        id: "B1".into(),
        configuration: format!("θ = 0, H = 0, ω = {} rad/s", s4(w)),
        paper: format!("ε̈ = −aNε/A: always stable, one frequency √(a m g/A) = {} rad/s",
            s4((a * n0 / ia).sqrt())),
        full: format!(
            "μ = 0: marginal (stable), two frequencies ν± = [Cω ± √(C²ω² + 4 A a m g)]/(2A) = {}, {} rad/s (verdict {}); with friction ({} ε = {} m/s): {} (max Re λ = {} 1/s; λ = {})",
            s4(nu_p),
            s4(nu_m),
            up.frictionless.verdict.as_str(),
            opts.smooth().name(),
            s4(eps),
            v.as_str(),
            s4(up.with_friction.max_re),
            eig_list(&up.with_friction.eigenvalues)
        ),
        agree: if v == Verdict::Unstable { "no" } else { "partly" }.into(),
        dropped: "the gyroscopic term −Ω(Cω − AΩ cos θ) sin θ (Ω set to 0; with J conserved Ω → Cω/(2A) at θ → 0, which adds C²ω²/(4A) to the stiffness), and the friction torque −h F_x, which is what destabilises the upright top".into(),
    }
}

/// B2: the upright top with the force H_x = H_y = H.
fn paper_b2(top: &Top, n0: f64, h: f64, frozen: &[FrozenCase]) -> PaperCheck {
    let (r, a) = (top.radius, top.offset);
    if h == 0.0 {
        PaperCheck {
            id: "B2".into(),
            configuration: "θ = 0 with H_x = H_y = H".into(),
            paper: "n/a: the scenario has H = 0 (B2 reduces to B1)".into(),
            full: "n/a".into(),
            agree: "n/a".into(),
            dropped: "as B1, and the fact that H ≠ 0 leaves no equilibrium".into(),
        }
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
        PaperCheck {
            id: "B2".into(),
            configuration: format!("θ = 0, H = {} N", s4(h)),
            paper: format!("ε̈ = −aNε/A + (R − a)H/A: 'stable', about ε_q = (R − a)H/(a m g) = {} rad", s4(eq)),
            full: format!(
                "no equilibrium (H ≠ 0: ω changes). Frozen-spin (quasi-static), not a true equilibrium: {desc}"
            ),
            agree: if eq > 0.3 { "no" } else { "partly" }.into(),
            dropped: "as B1; and ε_q is not small when (R − a)H > 0.3 a m g, so the linearisation about θ = 0 does not apply: the drive tips the top over".into(),
        }
    }
}

/// B3: the inverted top without a force.
fn paper_b3(
    top: &Top,
    n0: f64,
    wc: f64,
    eps: f64,
    opts: &Options,
    inv: &SteadyMotion,
) -> PaperCheck {
    let (a, ia, ic) = (top.offset, top.inertia_transverse, top.inertia_axial);
    let w = inv.with_friction.spin;
    let grow = (((ic + ia) * w * w + a * n0) / ia).sqrt();
    let v = inv.with_friction.verdict;
    PaperCheck {
        id: "B3".into(),
        configuration: format!(
            "θ = π, H = 0, ω = {} rad/s (spin about the vertical {})",
            s4(w),
            s4(-w)
        ),
        paper: format!("ε̈ = [(C + A)Ω² + aN]ε/A with Ω = ω: always unstable, growth {} 1/s", s4(grow)),
        full: format!(
            "μ = 0: stable iff C²ω² > 4 A m g a, ω_c = {} rad/s, here |ω|/ω_c = {:.3}: {}; with friction ({} ε = {} m/s): {} (max Re λ = {} 1/s; λ = {})",
            s4(wc),
            w.abs() / wc,
            inv.frictionless.verdict.as_str(),
            opts.smooth().name(),
            s4(eps),
            v.as_str(),
            s4(inv.with_friction.max_re),
            eig_list(&inv.with_friction.eigenvalues)
        ),
        agree: if v == Verdict::Unstable { "yes" } else { "no" }.into(),
        dropped: "Ω = ω is not a property of θ → π (there Ω is undefined; with J conserved Ω → −Cω/(2A)); with that, −Ω(Cω − AΩ cos θ) sin θ gives −C²ω²/(4A) ε instead of +(C + A)ω² ε, i.e. ε̈ = [a m g − C²ω²/(4A)]ε/A: the sleeping-top criterion. Friction (R + a)F_x is dropped too.".into(),
    }
}

/// B4: the lying top, with the force H_x = H_y = H.
fn paper_b4(
    top: &Top,
    h: f64,
    steady: &[SteadyMotion],
    frozen: &[FrozenCase],
    late: Option<&LateState>,
) -> PaperCheck {
    let (a, ia) = (top.offset, top.inertia_transverse);
    let pi = std::f64::consts::PI;
    let lying = steady
        .iter()
        .find(|s| s.name == "relative equilibrium at θ = π/2");
    let mut full = String::new();
    let mut agree = "n/a".to_string();
    if let Some(l) = lying {
        let o = l.with_friction.precession;
        full += &format!(
            "H = 0: the zero-slip steady motion at π/2 has Ω* = {} rad/s, ω* = {}; paper (AΩ² > aH = 0) says stable; full linearisation: {} (max Re λ = {} 1/s; λ = {}); μ = 0: {}. ",
            s4(o),
            s4(l.with_friction.spin),
            l.with_friction.verdict.as_str(),
            s4(l.with_friction.max_re),
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
    let mut paper_txt = "ε̈ = −(AΩ² − aH)ε/A − (HR − CωΩ − aN)/A: stable iff AΩ² > aH".to_string();
    if h > 0.0 {
        for f in frozen
            .iter()
            .filter(|f| f.name.starts_with("late") || f.name.contains("π/2"))
        {
            full += &match f.result.theta_quasi {
                Some(tq) => format!(
                    "H ≠ 0, frozen-spin (quasi-static), not a true equilibrium, {:?} at the {}: θ_q = {tq:.4} (θ_q − π/2 = {}), Ω = {}, ω = {}, λ = {} ({}). ",
                    f.result.variant,
                    f.name,
                    s4(tq - pi / 2.0),
                    s4(f.result.precession),
                    s4(f.result.spin),
                    eig_list(&f.result.eigenvalues),
                    f.result.verdict.map(|v| v.as_str()).unwrap_or("-")
                ),
                None => format!("H ≠ 0, {:?}: {}. ", f.result.variant, f.result.note),
            };
        }
        if let Some(l) = late {
            let o = l.precession_mean;
            paper_txt += &format!(
                "; at the late state Ω = {}: AΩ² − aH = {} ⇒ {}",
                s4(o),
                s4(ia * o * o - a * h),
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
                f.name.starts_with("late") && f.result.variant == FrozenVariant::PrecessionFrozen
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
    PaperCheck {
        id: "B4".into(),
        configuration: format!("θ = π/2, H = {} N", s4(h)),
        paper: paper_txt,
        full,
        agree,
        dropped: "the gyroscopic coupling through Ω(θ): with J conserved ∂Ω/∂θ = Cω/A at π/2, which adds ≈ C²ω²/A to the stiffness (the nutation frequency Cω/A); the friction μN in F_x; and that H ≠ 0 leaves no equilibrium (ω changes at −R H/C)".into(),
    }
}
