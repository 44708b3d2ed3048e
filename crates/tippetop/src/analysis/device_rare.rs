//! The device report's rare events (issue 27 item 4, docs/physics.md
//! §device-rare): the lying state's retention and the write's error rate of
//! `nano-physical` (C60 on graphene, Langevin), computed directly by
//! adaptive multilevel splitting ([`super::rare::ams`]) at the temperature
//! that matters, with two closed answers beside them:
//!
//! - **transition-state theory** (TST), `1/k_TST` with
//!   `k_TST = Σ_edges sqrt(kT/(2π I(b))) π(b) / ∫_W π(θ) dθ`: the
//!   equilibrium one-way flux of θ through the window's edges `b` over
//!   the window's population, `π(θ) = sin θ sqrt(I(θ)/A) e^{−U(θ)/kT}`
//!   the θ marginal of the Langevin equilibrium and `I(θ) = A + m a²
//!   sin²θ` the tilt's inertia on the frictionless plane. Every escape
//!   crosses an edge, and the quasi-stationary state is depleted near the
//!   absorbing edges, so `k <= k_TST`: **the mean residence is at least
//!   `1/k_TST`** (a lower bound at any temperature, computed in log space
//!   by Simpson's rule: valid where no sampler reaches);
//! - **the overdamped twin**: the same top, wells and frictions in the
//!   Brownian mode on the plane, whose θ is an exact one-dimensional
//!   diffusion ([`super::rare::exact`]): its mean exit time from the well's
//!   bottom, exact (the mode without inertia, not the Langevin answer).
//!
//! A barrier of more than [`REACH_KT`] kT is beyond any sampler's reach
//! (a splitting replica needs about `n (1 + ΔU/kT)` paths; at 4 K the
//! lying well's barrier is ~1 600 kT, `p ~ 10^{−680}`, below f64): there
//! the report gives the TST bound and the twin's exact value, and says so.
//!
//! **The write's error rate** at phase `P` with hold `h` (the bit's
//! criterion, θ in the `one` window over the last `h`; here checked at
//! every step, stricter than the bit's rows): with `θ_s` =
//! [`SETTLE`] inside the window and `δ` = [`RELAX`] for the fall's
//! transient to damp (`1/γ_r` = 0.45 ps), `P(fail) <= P_late + P_hold`:
//! `P_late = P(θ < θ_s for all t <= P − h − δ)` by splitting on the time
//! coordinate (target `t > P − h − δ`, reset `θ > θ_s`), and
//! `P_hold = 1 − exp(−h/τ)` the chance that the settled top leaves the
//! window during the hold (its exit time is exponential with the mean
//! residence `τ`).

use serde::Serialize;

use super::ensemble::Exit;
use super::rare::ams::{Ams, Coordinate, Estimate, Hooks, Problem, Replica, Settings};
use super::rare::exact::ThetaDiffusion;
use super::step_check::{self, AtStep, Scale, StepCheck};
use crate::input::thermal::BOLTZMANN;
use crate::{Error, Scenario};

/// Largest barrier \[kT\] the report sends to the sampler.
pub const REACH_KT: f64 = 200.0;
/// θ_s: the fall counts as arrived at θ > `ONE[0] + 0.1` rad.
pub const SETTLE_INSET: f64 = 0.1;
/// δ \[s\]: the time left after the arrival for the fall's excess energy
/// to damp (22 times `1/γ_r`) before the hold starts.
pub const RELAX: f64 = 1e-11;
/// The error rate the design must meet.
pub const ERROR_TARGET: f64 = 1e-9;
/// Ten years \[s\] (Julian).
pub const TEN_YEARS: f64 = 10.0 * 365.25 * 86400.0;
/// One electronvolt \[J\].
pub const EV: f64 = 1.602176634e-19;
/// The lying window \[rad\] (the bit's default `one`).
pub const ONE: [f64; 2] = crate::input::scenario::bit::ONE_DEFAULT;
/// θ_s \[rad\].
pub const SETTLE: f64 = ONE[0] + SETTLE_INSET;

/// Splitting sizes.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Sizes {
    /// Independent replicas.
    pub replicas: usize,
    /// Particles per replica.
    pub particles: usize,
}

/// A time that may exceed f64: seconds (`None` past 1.8e308 s) and its
/// base-10 logarithm.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BigTime {
    /// Seconds, if within f64.
    pub seconds: Option<f64>,
    /// `log10` of the seconds.
    pub log10_seconds: f64,
}

impl BigTime {
    /// From `ln` of seconds.
    pub fn from_ln(ln: f64) -> BigTime {
        let s = ln.exp();
        BigTime {
            seconds: s.is_finite().then_some(s),
            log10_seconds: ln / std::f64::consts::LN_10,
        }
    }
}

/// A splitting estimate, flattened for the report.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Measured {
    /// The estimate (probability, or seconds).
    pub estimate: f64,
    /// Its 95 % interval.
    pub ci95: [f64; 2],
    /// How the interval was made (see [`Estimate::interval`]).
    pub interval: &'static str,
    /// Replicas.
    pub replicas: usize,
    /// Particles per replica.
    pub particles: usize,
    /// Paths run.
    pub trajectories: u64,
    /// Steps integrated.
    pub steps: u64,
    /// Paths cut by the step budget.
    pub truncated: u64,
    /// No particle of any replica reached the target (estimate 0, `ci95`
    /// its upper bound).
    pub extinct: bool,
}

fn measured(e: &Estimate) -> Measured {
    Measured {
        estimate: e.estimate,
        ci95: e.ci95,
        interval: e.interval,
        replicas: e.replicas,
        particles: e.particles,
        trajectories: e.trajectories,
        steps: e.steps,
        truncated: e.truncated,
        extinct: e.extinct,
    }
}

/// The lying state's retention at one temperature and well depth.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LyingRetention {
    /// Temperature \[K\].
    pub temperature: f64,
    /// The stem's well depth \[J\].
    pub depth: f64,
    /// The potential's rise from the well's bottom to the window's edge \[J\].
    pub barrier: f64,
    /// The same in kT.
    pub barrier_kt: f64,
    /// Mean residence by splitting (Langevin, from the well's bottom) \[s\];
    /// `None`: beyond the sampler's reach (barrier above [`REACH_KT`] kT)
    /// or not asked.
    pub ams: Option<Measured>,
    /// Why `ams` is `None`: `"beyond_reach"` (a barrier above
    /// [`REACH_KT`] kT) or `"not_asked"` (no sizes given, `--quick`).
    pub not_measured: Option<&'static str>,
    /// Transition-state theory: a lower bound of the mean residence.
    pub tst: BigTime,
    /// The overdamped twin's exact mean exit time from the well's bottom.
    pub overdamped_exact: BigTime,
    /// The step \[s\] of the splitting (the device's step rule).
    pub dt: f64,
    /// Whether the measured residence is converged in the step (`None`:
    /// not measured, or the check not asked).
    pub dt_converged: Option<bool>,
    /// The step check of the measured residence: the splitting again at
    /// `dt/2` (docs/physics.md#step-check), on the log scale.
    pub step_check: Option<StepCheck>,
}

/// The step rule of the device's rare events, `dt · max rate <=
/// STEP_RATE`, half what stability allows (0.02), set by the step's
/// measured effect on the 300 K lying residence (docs/physics.md#step-check):
/// at 0.018 (4 fs) halving the step raised it by 27 % over six seeds each
/// (0.848 → 1.075 ms, 3.1 standard errors); at 0.009 (2 fs) thirteen seeds
/// at 2 fs and fourteen at 1 fs differ within their noise (1.073 ± 0.031
/// and 1.000 ± 0.050 ms, standard errors over the seeds), both at the
/// transition-state bound (1.020 ms).
pub const STEP_RATE: f64 = 0.009;
/// The largest step of the device's rare events \[s\].
pub const MAX_DT: f64 = 2e-15;

/// The Langevin scenario of the lying state: `nano-physical` at `t` K with
/// well depth `depth` J, at rest at the well's bottom; the step rule of
/// the device's rare events ([`STEP_RATE`], at most [`MAX_DT`]).
pub fn lying_scenario(t: f64, depth: f64) -> Result<Scenario, Error> {
    let mut sc = Scenario::load(Some("nano-physical"), None, &[])?;
    sc.initial.theta = std::f64::consts::FRAC_PI_2;
    sc.initial.spin = 0.0;
    prepare(sc, t, depth)
}

/// `sc` at `t` K with well depth `depth` J and the device's step rule.
fn prepare(mut sc: Scenario, t: f64, depth: f64) -> Result<Scenario, Error> {
    sc.thermal.temperature = t;
    {
        let mut wells = sc.wells();
        wells[0].depth = depth;
        sc.set_wells(&wells);
    }
    sc.solver.t_end = 1e-9;
    sc.solver.samples = 1001;
    let rate = crate::input::scenario::langevin::step_rates(&sc)
        .iter()
        .map(|r| r.0)
        .fold(0.0, f64::max);
    sc.solver.dt = Some((STEP_RATE / rate).min(MAX_DT));
    sc.validate()?;
    Ok(sc)
}

/// The θ diffusion of `sc`'s top, wells and frictions (the overdamped
/// twin: no checks of the mode, see the module doc).
fn twin(sc: &Scenario) -> ThetaDiffusion {
    let th = &sc.thermal;
    let top = &sc.top;
    ThetaDiffusion {
        kt: th.kt(),
        mass: top.mass,
        radius: top.radius,
        offset: top.offset,
        inertia_transverse: top.inertia_transverse,
        gravity: sc.surface.gravity,
        damping_translational: th.damping_translational,
        damping_rotational: th.damping_rotational,
        damping_contact: th.damping_contact,
        hx: 0.0,
        wells: sc.wells(),
    }
}

/// `ln` of the TST mean residence in `ONE` \[ln s\] (module doc), Simpson's
/// rule on 20 000 panels with the largest exponent factored out.
pub fn ln_tst_residence(sc: &Scenario) -> f64 {
    let d = twin(sc);
    let (a, b) = (ONE[0], ONE[1]);
    let n = 20_000;
    let h = (b - a) / n as f64;
    let f: Vec<f64> = (0..=n).map(|i| d.ln_density(a + i as f64 * h)).collect();
    let top = f.iter().cloned().fold(f64::NEG_INFINITY, f64::max);
    let mut sum = 0.0;
    for (i, v) in f.iter().enumerate() {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += w * (v - top).exp();
    }
    let ln_z = top + (sum * h / 3.0).ln();
    let (m, aa, big_a) = (sc.top.mass, sc.top.offset, sc.top.inertia_transverse);
    let kt = d.kt;
    let ln_flux = |e: f64| {
        let inertia = big_a + m * aa * aa * e.sin().powi(2);
        0.5 * (kt / (2.0 * std::f64::consts::PI * inertia)).ln() + d.ln_density(e)
    };
    let (fa, fb) = (ln_flux(a), ln_flux(b));
    let hi = fa.max(fb);
    let ln_k = hi + ((fa - hi).exp() + (fb - hi).exp()).ln() - ln_z;
    -ln_k
}

/// `ln` of the overdamped twin's exact mean exit time from `ONE`, from
/// the well's bottom π/2 \[ln s\].
pub fn ln_overdamped_residence(sc: &Scenario) -> Result<f64, Error> {
    let d = twin(sc).diffusion();
    Ok(
        d.mean_exit_time(Some(ONE[0]), Some(ONE[1]), std::f64::consts::FRAC_PI_2)?
            .ln,
    )
}

/// The potential's rise from π/2 to the window's (higher) edge \[J\].
pub fn barrier(sc: &Scenario) -> f64 {
    let d = twin(sc);
    let mid = std::f64::consts::FRAC_PI_2;
    d.potential(ONE[0]).min(d.potential(ONE[1])) - d.potential(mid)
}

fn window() -> Exit {
    Exit::parse(&format!("theta<{},theta>{}", ONE[0], ONE[1])).expect("a valid window")
}

/// The lying state's retention at `t` K, well depth `depth` J; splitting
/// if `sizes` is given and the barrier is within [`REACH_KT`].
pub fn lying_retention(
    t: f64,
    depth: f64,
    sizes: Option<Sizes>,
    threads: Option<usize>,
) -> Result<LyingRetention, Error> {
    lying_retention_checked(t, depth, sizes, threads, false)
}

/// [`lying_retention`]; with `check`, a measured residence gets its step
/// check: the same splitting at `dt/2` ([`step_check::refined`]), twice
/// the cost of the first.
pub fn lying_retention_checked(
    t: f64,
    depth: f64,
    sizes: Option<Sizes>,
    threads: Option<usize>,
    check: bool,
) -> Result<LyingRetention, Error> {
    let sc = lying_scenario(t, depth)?;
    let dt = sc.solver.dt.unwrap_or(f64::NAN);
    let barrier = barrier(&sc);
    let barrier_kt = barrier / (BOLTZMANN * t);
    let tst = BigTime::from_ln(ln_tst_residence(&sc));
    let overdamped_exact = BigTime::from_ln(ln_overdamped_residence(&sc)?);
    let not_measured = if barrier_kt > REACH_KT {
        Some("beyond_reach")
    } else if sizes.is_none() {
        Some("not_asked")
    } else {
        None
    };
    let splitting = |sc: Scenario, s: Sizes| -> Result<Option<Measured>, Error> {
        let problem = Problem::new(sc, window(), None);
        let settings = Settings {
            replicas: s.replicas,
            particles: s.particles,
            ..Settings::default()
        };
        let ams = Ams::new(problem, settings)?;
        Ok(ams
            .estimate(threads, Hooks::default())?
            .as_ref()
            .map(measured))
    };
    let (mut ams, mut step) = (None, None);
    if let (Some(s), None) = (sizes, not_measured) {
        ams = splitting(sc.clone(), s)?;
        if let (true, Some(m)) = (check, &ams) {
            if let Some(f) = splitting(step_check::refined(&sc)?, s)? {
                let at = |m: &Measured, dt: f64| AtStep {
                    dt,
                    estimate: m.estimate,
                    ci95: m.ci95,
                };
                step = Some(StepCheck::new(at(m, dt), at(&f, 0.5 * dt), Scale::Log));
            }
        }
    }
    Ok(LyingRetention {
        temperature: t,
        depth,
        barrier,
        barrier_kt,
        ams,
        not_measured,
        tst,
        overdamped_exact,
        dt,
        dt_converged: step.map(|c| c.converged),
        step_check: step,
    })
}

/// The smallest well depth \[J\] whose `ln τ(depth)` reaches `ln(10 yr)`:
/// bisection in `[0.01, 100]` eV to 1e-6 relative (`ln τ` increases with
/// the depth). `None` if even 100 eV does not.
pub fn min_depth(ln_tau: &dyn Fn(f64) -> Result<f64, Error>) -> Result<Option<f64>, Error> {
    let want = TEN_YEARS.ln();
    let (mut a, mut b) = (0.01 * EV, 100.0 * EV);
    if ln_tau(b)? < want {
        return Ok(None);
    }
    if ln_tau(a)? >= want {
        return Ok(Some(a));
    }
    while b / a - 1.0 > 1e-6 {
        let m = (a * b).sqrt();
        if ln_tau(m)? >= want {
            b = m;
        } else {
            a = m;
        }
    }
    Ok(Some(b))
}

/// One write's error rate at `t` K.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct WriteError {
    /// What the write is.
    pub label: String,
    /// Its force `(H_x, H_y)` \[N\] at the contact point over the phase.
    pub force: [f64; 2],
    /// Temperature \[K\].
    pub temperature: f64,
    /// The well depth \[J\].
    pub depth: f64,
    /// The phase \[s\].
    pub phase: f64,
    /// The hold \[s\].
    pub hold: f64,
    /// Where `P_late` was measured \[s\]: `phase − hold − δ`, or earlier
    /// (the horizon of the budget): `P_late` only decreases with the time,
    /// so the figure is then an upper bound.
    pub late_at: f64,
    /// `late_at < phase − hold − δ`: `late` bounds `P_late` from above.
    pub late_bound: bool,
    /// `P_late`: not arrived at θ_s by `late_at` (splitting on the time).
    pub late: Measured,
    /// `P_hold = 1 − exp(−hold/τ)` with `τ` the lying state's mean
    /// residence (its estimate), and its 95 % interval from τ's.
    pub hold_escape: f64,
    /// `P_hold`'s 95 % interval.
    pub hold_escape_ci95: [f64; 2],
    /// The error rate `P_late + P_hold` (an upper bound: module doc).
    pub rate: f64,
    /// Its 95 % interval (the ends added).
    pub ci95: [f64; 2],
}

/// The scenario of a write: `nano-physical` at `t` K, well depth `depth`,
/// from the preset's standing state, force `(hx, hy)` over `[0, ∞)`.
fn write_scenario(t: f64, depth: f64, force: [f64; 2]) -> Result<Scenario, Error> {
    let windows = if force == [0.0, 0.0] {
        String::new()
    } else {
        format!("[[force]]\nhx = {:e}\nhy = {:e}\n", force[0], force[1])
    };
    let text = format!("preset = \"nano-physical\"\n{windows}");
    prepare(Scenario::load(None, Some(&text), &[])?, t, depth)
}

/// `P(θ stays below θ_s until t_late)` by splitting on the time, with the
/// replicas (for the survival curve of their levels).
fn late(
    t: f64,
    depth: f64,
    force: [f64; 2],
    t_late: f64,
    sizes: Sizes,
    threads: Option<usize>,
) -> Result<(Estimate, Vec<Replica>), Error> {
    let sc = write_scenario(t, depth, force)?;
    let target = Exit::parse(&format!("t>{t_late:e}"))?;
    let reset = Exit::parse(&format!("theta>{SETTLE}"))?;
    let mut problem = Problem::new(sc, target, Some(reset));
    problem.coordinate = Coordinate::parse("t")?;
    let settings = Settings {
        replicas: sizes.replicas,
        particles: sizes.particles,
        ..Settings::default()
    };
    let ams = Ams::new(problem, settings)?;
    let mut reps = Vec::new();
    ams.run(0..sizes.replicas, threads, Hooks::default(), &mut |r| {
        reps.push(r);
        true
    })?;
    let e = ams.combine(&reps)?;
    Ok((e, reps))
}

/// The write's error rate (module doc), with `tau` the lying state's
/// mean residence and its 95 % interval \[s\].
#[allow(clippy::too_many_arguments)]
pub fn write_error(
    label: &str,
    t: f64,
    depth: f64,
    force: [f64; 2],
    phase: f64,
    hold: f64,
    tau: (f64, [f64; 2]),
    horizon: f64,
    sizes: Sizes,
    threads: Option<usize>,
) -> Result<WriteError, Error> {
    let t_late = phase - hold - RELAX;
    let late_at = t_late.min(horizon);
    let (e, _) = late(t, depth, force, late_at, sizes, threads)?;
    let p_hold = |tau: f64| -(-hold / tau).exp_m1();
    let hold_escape = p_hold(tau.0);
    let hold_escape_ci95 = [p_hold(tau.1[1]), p_hold(tau.1[0])];
    Ok(WriteError {
        label: label.into(),
        force,
        temperature: t,
        depth,
        phase,
        hold,
        late_at,
        late_bound: late_at < t_late,
        late: measured(&e),
        hold_escape,
        hold_escape_ci95,
        rate: e.estimate + hold_escape,
        ci95: [
            e.ci95[0] + hold_escape_ci95[0],
            e.ci95[1] + hold_escape_ci95[1],
        ],
    })
}

/// The replicas' mean of `P̂(score > z)` from their levels: each
/// replica's product after its last level below `z` (its final estimate
/// past its last level).
pub fn survival(reps: &[Replica], z: f64) -> f64 {
    let mut s = 0.0;
    for r in reps {
        let mut p = 1.0;
        let mut past = true;
        for l in &r.levels {
            if l[0] < z {
                p = 10f64.powf(l[1]);
            } else {
                past = false;
                break;
            }
        }
        s += if past { r.estimate } else { p };
    }
    s / reps.len().max(1) as f64
}

/// The design's write: no force (the standing state has no barrier: the
/// top falls into the lying well by itself) and the shortest phase whose
/// error rate is at most [`ERROR_TARGET`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DesignWrite {
    /// The smallest write force \[N\] (0: none needed).
    pub force: f64,
    /// The arrival time by which the replicas' survival curve falls to
    /// [`ERROR_TARGET`] minus the hold's share \[s\] (`None`: not within
    /// `horizon`).
    pub arrival: Option<f64>,
    /// The shortest write time: `arrival + δ` \[s\] (the hold starts then).
    pub write_time: Option<f64>,
    /// The survival curve's horizon \[s\].
    pub horizon: f64,
    /// The error rate at `write_time` (a fresh splitting run, unbiased).
    pub check: Option<WriteError>,
}

/// The design's write at `t` K and depth `depth`, hold `hold` \[s\], the
/// survival curve up to `horizon` \[s\].
#[allow(clippy::too_many_arguments)]
pub fn design_write(
    t: f64,
    depth: f64,
    hold: f64,
    tau: (f64, [f64; 2]),
    horizon: f64,
    sizes: Sizes,
    threads: Option<usize>,
) -> Result<DesignWrite, Error> {
    let p_hold = -(-hold / tau.0).exp_m1();
    let want = ERROR_TARGET - p_hold;
    let (_, reps) = late(t, depth, [0.0, 0.0], horizon, sizes, threads)?;
    let mut arrival = None;
    if want > 0.0 {
        // The smallest z on a 0.1 ps grid where the curve is at most `want`.
        let n = (horizon / 1e-13).round() as usize;
        for i in 1..=n {
            let z = horizon * i as f64 / n as f64;
            if survival(&reps, z) <= want {
                arrival = Some(z);
                break;
            }
        }
    }
    let write_time = arrival.map(|z| z + RELAX);
    let check = match write_time {
        Some(w) => Some(write_error(
            "no force, shortest write",
            t,
            depth,
            [0.0, 0.0],
            w + hold,
            hold,
            tau,
            w,
            sizes,
            threads,
        )?),
        None => None,
    };
    Ok(DesignWrite {
        force: 0.0,
        arrival,
        write_time,
        horizon,
        check,
    })
}
