//! Langevin dynamics (`solver.method = "langevin"`, `[thermal]`,
//! docs/physics.md#langevin), vector model: equipartition of the constrained
//! top, the orientation density at `g = 0` (not uniform: the centre's
//! height follows the tilt), the Ornstein–Uhlenbeck mean-square
//! displacement, the exact energy decay at `T = 0`, the splitting without
//! damping equal to RK4 bit for bit, and replay by (seed, run).
//!
//! Statistics: time averages over one long run with a fixed seed; the
//! standard error from 40 batch means (each batch is hundreds of
//! correlation times, so the batch means are independent to a good
//! approximation); every check is `|mean − exact| < 5 SE` with the SE
//! itself bounded (so the test has the power to fail a wrong model).

use std::sync::OnceLock;
use tippetop::input::thermal::BOLTZMANN;
use tippetop::{ForceWindow, Forcing, Method, Scenario, Simulation, Trajectory, simulate};

/// An eccentric light top (`m a²/A = 2`: the mass matrix's tilt mode
/// `A + m a² sin²θ` is up to three times `A`, so a model that forgot the
/// centre's vertical motion is far outside the error bars), no gravity, no
/// applied force, frictionless, at `T`, with `γ_t = γ_r = γ`.
fn hot_top(temperature: f64, gamma: f64, dt: f64, t_end: f64, samples: usize) -> Scenario {
    let mut sc = Scenario::nano();
    sc.top.offset = 0.6 * sc.top.radius;
    let ma2 = sc.top.mass * sc.top.offset * sc.top.offset;
    sc.top.inertia_transverse = ma2 / 2.0;
    sc.top.inertia_axial = ma2 / 2.0;
    sc.surface.friction = 0.0;
    sc.surface.gravity = 0.0;
    sc.forcing = Forcing { windows: vec![] };
    sc.initial.theta = 1.0;
    sc.initial.spin = 0.0;
    sc.solver.method = Method::Langevin;
    sc.solver.dt = Some(dt);
    sc.solver.t_end = t_end;
    sc.solver.samples = samples;
    sc.thermal.temperature = temperature;
    sc.thermal.damping_translational = gamma;
    sc.thermal.damping_rotational = gamma;
    sc.thermal.seed = Some(20261124);
    sc
}

const T: f64 = 300.0;

/// The fastest rate of [`hot_top`] at 300 K: `sqrt(kT/A)` (A = C).
fn thermal_rate(sc: &Scenario) -> f64 {
    (BOLTZMANN * T / sc.top.inertia_transverse).sqrt()
}

/// The long equilibrium run shared by the equipartition, density and
/// diffusion tests: γ at the thermal rate, the step at the rule's limit
/// (`dt · rate = 0.02`), 2 000 000 steps (40 000 relaxation times),
/// a row every 10 steps. About 2 s.
fn long_run() -> &'static (Scenario, Trajectory) {
    static RUN: OnceLock<(Scenario, Trajectory)> = OnceLock::new();
    RUN.get_or_init(|| {
        let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
        let rate = thermal_rate(&probe);
        let dt = 0.02 / rate;
        let n = 2_000_000usize;
        let sc = hot_top(T, rate, dt, dt * n as f64, n / 10 + 1);
        let tr = simulate(&sc).expect("valid");
        assert!(tr.error.is_none(), "{:?}", tr.error);
        (sc, tr)
    })
}

/// Mean and standard error of a time series from 40 batch means (each
/// batch much longer than the correlation time, so the batch means are
/// independent to a good approximation).
pub(super) fn mean_se(values: &[f64]) -> (f64, f64) {
    let nb = 40;
    let per = values.len() / nb;
    let means: Vec<f64> = (0..nb)
        .map(|b| values[b * per..(b + 1) * per].iter().sum::<f64>() / per as f64)
        .collect();
    let m = means.iter().sum::<f64>() / nb as f64;
    let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (nb - 1) as f64;
    (m, (var / nb as f64).sqrt())
}

/// [`mean_se`] of `f` over the rows after the first 5 % (burn-in: the run
/// starts at rest, far from equilibrium).
fn batch_mean(tr: &Trajectory, f: impl Fn(&tippetop::Sample) -> f64) -> (f64, f64) {
    let rows = &tr.samples[tr.samples.len() / 20..];
    mean_se(&rows.iter().map(f).collect::<Vec<f64>>())
}

/// `∫ g p dθ / ∫ p dθ` over `[0, π]` (composite Simpson, 20 000
/// intervals: error far below the Monte Carlo's): the mean of `g` under the
/// orientation density `p`.
pub(super) fn density_mean(p: impl Fn(f64) -> f64, g: impl Fn(f64) -> f64) -> f64 {
    let n = 20_000;
    let h = std::f64::consts::PI / n as f64;
    let (mut num, mut den) = (0.0, 0.0);
    for i in 0..=n {
        let th = i as f64 * h;
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        num += w * p(th) * g(th);
        den += w * p(th);
    }
    num / den
}

fn check(what: &str, (mean, se): (f64, f64), want: f64, max_rel_se: f64) {
    eprintln!(
        "{what}: {mean:e} ± {se:e} (want {want:e}, {:+.2} SE)",
        (mean - want) / se
    );
    assert!(
        se < max_rel_se * want.abs(),
        "{what}: standard error {se:e} too large for a test with power"
    );
    assert!(
        (mean - want).abs() < 5.0 * se,
        "{what}: {mean:e} ± {se:e}, want {want:e}"
    );
}

/// Equipartition of the constrained top (exact for the invariant measure
/// of the Langevin dynamics, any configuration): `⟨C ω²⟩ = kT`,
/// `⟨m |u_h|²⟩ = 2 kT`, `⟨(A + m a² sin²θ) θ̇²⟩ = kT`,
/// `⟨A Ω² sin²θ⟩ = kT`. The splitting's bias is `O((dt·rate)²) = 4e-4`,
/// below the SE (~1 %).
#[test]
fn equipartition_on_the_plane() {
    let (sc, tr) = long_run();
    let kt = BOLTZMANN * T;
    let (m, a) = (sc.top.mass, sc.top.offset);
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    check(
        "<C w^2>",
        batch_mean(tr, |s| ic * s.spin * s.spin),
        kt,
        0.02,
    );
    check(
        "<m |u_h|^2>",
        batch_mean(tr, |s| m * (s.ux * s.ux + s.uy * s.uy)),
        2.0 * kt,
        0.02,
    );
    check(
        "<(A + m a^2 sin^2) thd^2>",
        batch_mean(tr, |s| {
            let sn = s.theta.sin();
            (ia + m * a * a * sn * sn) * s.theta_dot * s.theta_dot
        }),
        kt,
        0.02,
    );
    check(
        "<A Omega^2 sin^2>",
        batch_mean(tr, |s| {
            let sn = s.theta.sin();
            ia * s.precession * s.precession * sn * sn
        }),
        kt,
        0.02,
    );
    // A model without the centre's vertical motion would give
    // ⟨A θ̇²⟩ = kT: here it is well below (m a²/A = 2).
    let (wrong, se) = batch_mean(tr, |s| ia * s.theta_dot * s.theta_dot);
    assert!(
        wrong < kt - 10.0 * se,
        "<A thd^2> = {wrong:e} should be far below kT"
    );
}

/// At `g = 0` without wells the orientation's density is
/// `p(θ) ∝ sin θ sqrt(1 + (m a²/A) sin²θ)` (the configuration marginal of
/// `exp(−H/kT)`: `sqrt(det M(θ))`). Checked on `⟨cos²θ⟩` against the
/// quadrature of that density (uniform would be 1/3, 7 % higher here) and
/// on `⟨cos θ⟩ = 0`.
#[test]
fn orientation_density_at_zero_gravity() {
    let (sc, tr) = long_run();
    let r = sc.top.mass * sc.top.offset * sc.top.offset / sc.top.inertia_transverse;
    let p = |th: f64| th.sin() * (1.0 + r * th.sin().powi(2)).sqrt();
    let want = density_mean(p, |th| th.cos().powi(2));
    assert!(
        (want - 1.0 / 3.0).abs() > 0.02,
        "the density must not be uniform"
    );
    check(
        "<cos^2 theta>",
        batch_mean(tr, |s| s.theta.cos().powi(2)),
        want,
        0.03,
    );
    let (c1, se) = batch_mean(tr, |s| s.theta.cos());
    assert!(c1.abs() < 5.0 * se, "<cos theta> = {c1} ± {se}");
}

/// The centre's horizontal motion is a free Ornstein–Uhlenbeck process
/// (no friction, no horizontal force): mean-square displacement over a lag
/// `τ` in equilibrium `4 D [τ − (1 − e^{−γτ})/γ]`, `D = kT/(m γ_t)`. Lags
/// of 1 and 10 relaxation times (the ballistic and the diffusive regime),
/// from displacements `x(t + τ) − x(t)` over the run after the burn-in.
#[test]
fn ornstein_uhlenbeck_mean_square_displacement() {
    let (sc, tr) = long_run();
    let g = sc.thermal.damping_translational;
    let d = BOLTZMANN * T / (sc.top.mass * g);
    let rows = &tr.samples[tr.samples.len() / 20..];
    let dt_row = tr.samples[1].t - tr.samples[0].t;
    for relax in [1.0, 10.0] {
        let lag = (relax / g / dt_row).round() as usize;
        let tau = lag as f64 * dt_row;
        let want = 4.0 * d * (tau - (1.0 - (-g * tau).exp()) / g);
        // Batches of displacements: the squared displacement starting at
        // each row of a batch.
        let disp: Vec<f64> = rows
            .windows(lag + 1)
            .map(|w| {
                let (a, b) = (&w[0], &w[lag]);
                (b.x - a.x).powi(2) + (b.y - a.y).powi(2)
            })
            .collect();
        let (m, se) = mean_se(&disp);
        check(
            &format!("MSD at {relax} relaxation times"),
            (m, se),
            want,
            0.03,
        );
    }
}

/// At `T = 0` with `γ_t = γ_r = γ` the friction matrix is `γ M`: every
/// velocity decays at `γ`, and with no potential (g = 0, no force) the
/// constraint does no work, so `E(t) = E(0) e^{−2γt}` exactly; the run
/// reproduces it to the RK4 step's energy error (`(h·rate)^5` per step,
/// ~1e-9 over 1000 steps at `h·rate = 0.02`). The balance
/// `E − E0 = W_f` (the bath's work) holds to the same order.
#[test]
fn damped_energy_decays_exactly_at_zero_temperature() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let gamma = 0.3 * rate;
    let dt = 0.02 / rate;
    let mut sc = hot_top(0.0, gamma, dt, 1000.0 * dt, 101);
    sc.thermal.seed = None;
    // A tumbling, sliding top: every mode moving.
    sc.initial.theta_dot = 0.5 * rate;
    sc.initial.precession = 0.7 * rate;
    sc.initial.spin = 0.9 * rate;
    sc.initial.ux = 1.0;
    sc.initial.uy = -0.5;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none());
    let e0 = tr.samples[0].energy;
    let mut worst: f64 = 0.0;
    for s in &tr.samples {
        let want = e0 * (-2.0 * gamma * s.t).exp();
        worst = worst.max(((s.energy - want) / e0).abs());
        let bal = (s.energy - e0 - s.work_friction) / e0;
        assert!(bal.abs() < 1e-9, "balance {bal:e} at {}", s.t);
    }
    let last = tr.samples.last().unwrap();
    assert!(last.energy < 0.01 * e0, "it decayed: {}", last.energy / e0);
    assert!(worst < 1e-8, "E(t) vs E0 exp(-2 gamma t): {worst:e}");
}

/// Without damping and at `T = 0` the splitting's `O` steps are the
/// identity and the run is the RK4 run with the same steps, bit for bit
/// (the classical top without friction: the normal force stays positive,
/// so both methods have the same segments).
#[test]
fn langevin_without_bath_is_rk4() {
    let mut sc = Scenario::classical();
    sc.surface.friction = 0.0;
    sc.solver.t_end = 0.1;
    sc.solver.samples = 101;
    let mut lv = sc.clone();
    lv.solver.method = Method::Langevin;
    lv.solver.dt = Some(1e-4);
    let mut rk = sc.clone();
    rk.solver.method = Method::Rk4;
    rk.solver.steps = 1000;
    let (a, b) = (simulate(&lv).unwrap(), simulate(&rk).unwrap());
    assert!(a.error.is_none() && b.error.is_none());
    assert_eq!(a.samples.len(), b.samples.len());
    // Both land on t_end: the same step sequence gives the same bits.
    assert_eq!(a.samples.last(), b.samples.last());
    // Inside, the Langevin rows sit on the step ends `k h`, RK4's at
    // `t_end i/(n − 1)` read from its Hermite interpolant: a few ulps apart
    // in t. Every quantity compared changes at most at 100 × its size per
    // second (the spin is 100 rad/s), so they agree to 100 |Δt| + rounding.
    for (x, y) in a.samples.iter().zip(&b.samples) {
        let dt = (x.t - y.t).abs();
        assert!(dt <= 4.0 * f64::EPSILON * x.t, "{} vs {}", x.t, y.t);
        for (u, v) in [
            (x.theta, y.theta),
            (x.qx, y.qx),
            (x.qz, y.qz),
            (x.spin / 100.0, y.spin / 100.0),
            (x.energy / y.energy, 1.0),
        ] {
            assert!((u - v).abs() <= 100.0 * dt + 1e-15, "{u} vs {v} at {}", x.t);
        }
    }
}

/// Same (seed, run): the same bits; another run index or seed: another
/// path; a run paused, snapshotted and continued is the run in one go
/// (the stream's counter is the global step number).
#[test]
fn replay_by_seed_and_run() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let dt = 0.02 / rate;
    // A force window that switches off mid-run: a segment boundary off the
    // grid, where the engine restarts.
    let mut sc = hot_top(T, rate, dt, 2000.0 * dt, 21);
    sc.forcing = Forcing {
        windows: vec![ForceWindow {
            hx: 1e-12,
            hy: 0.0,
            hz: 0.0,
            start: 0.0,
            stop: 700.3 * dt,
        }],
    };
    let a = simulate(&sc).unwrap();
    let b = simulate(&sc).unwrap();
    assert_eq!(a.samples, b.samples);
    let mut other = sc.clone();
    other.thermal.run = 1;
    let c = simulate(&other).unwrap();
    assert_ne!(a.samples.last(), c.samples.last());
    let mut other = sc.clone();
    other.thermal.seed = Some(7);
    assert_ne!(a.samples.last(), simulate(&other).unwrap().samples.last());

    let mut sim = Simulation::new(&sc).unwrap();
    sim.integrate_to(333.7 * dt).unwrap();
    let snap = sim.snapshot();
    sim.integrate_to(1500.0 * dt).unwrap();
    sim.restore(&snap);
    sim.integrate_to(sc.solver.t_end).unwrap();
    assert_eq!(sim.into_trajectory().samples, a.samples);
}

/// The contact damping `−c v_P` on a uniform sphere (`a = 0`,
/// `A = C = 2/5 m R²`) at `T = 0`, no other damping: `m v̇ = −c v_P`,
/// `I ẇ = r × (−c v_P)` with `r = −R Z`, so the slip obeys
/// `v̇_P = −c (1/m + R²/A) v_P = −(7c/2m) v_P` and decays as
/// `|v_P(0)| e^{−7ct/(2m)}` exactly (nothing else moves the slip: the normal
/// force passes through the centre). The O step is exact and Φ leaves the
/// slip alone, so the run follows it to rounding.
#[test]
fn contact_damping_relaxes_the_slip_of_a_sphere() {
    let mut sc = Scenario::nano();
    sc.top.offset = 0.0;
    let i = 0.4 * sc.top.mass * sc.top.radius * sc.top.radius;
    sc.top.inertia_transverse = i;
    sc.top.inertia_axial = i;
    sc.surface.friction = 0.0;
    sc.forcing = Forcing { windows: vec![] };
    sc.initial.theta = 0.5;
    sc.initial.ux = 1.0;
    sc.initial.uy = -0.3;
    sc.initial.theta_dot = 2e9;
    sc.initial.spin = 3e9;
    let c = sc.top.mass * 1e11;
    sc.thermal.damping_contact = c;
    sc.solver.method = Method::Langevin;
    sc.solver.dt = Some(2e-14);
    sc.solver.t_end = 4e-12;
    sc.solver.samples = 41;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let s0 = tr.samples[0].slip;
    assert!(s0 > 0.1, "it slides: {s0}");
    let rate = 3.5 * c / sc.top.mass;
    for s in &tr.samples {
        let want = s0 * (-rate * s.t).exp();
        assert!(
            (s.slip - want).abs() <= 1e-12 * s0,
            "slip {} vs {want} at {}",
            s.slip,
            s.t
        );
    }
    assert!(tr.samples.last().unwrap().slip < 0.3 * s0);
}

/// Equipartition with the contact damping on (`c/m = γ`): the
/// Ornstein–Uhlenbeck step with the coupled friction matrix
/// `Γ + c Pᵀ P` must leave the same Maxwell distribution. 3 000 000 steps
/// (the step is 2.6 times shorter than without the contact damping).
#[test]
fn equipartition_with_contact_damping() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let mut sc = hot_top(T, rate, 1.0, 1.0, 2);
    sc.thermal.damping_contact = sc.top.mass * rate;
    // The contact's rotational rate c (R + a)²/A is the fastest: the step
    // at the rule's limit for it.
    let lever = sc.top.radius + sc.top.offset;
    let fastest = sc.thermal.damping_contact * lever * lever / sc.top.inertia_transverse;
    let dt = 0.02 / fastest.max(rate);
    let n = 3_000_000usize;
    sc.solver.dt = Some(dt);
    sc.solver.t_end = dt * n as f64;
    sc.solver.samples = n / 10 + 1;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let kt = BOLTZMANN * T;
    let (m, a) = (sc.top.mass, sc.top.offset);
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    check(
        "c: <C w^2>",
        batch_mean(&tr, |s| ic * s.spin * s.spin),
        kt,
        0.03,
    );
    check(
        "c: <m |u_h|^2>",
        batch_mean(&tr, |s| m * (s.ux * s.ux + s.uy * s.uy)),
        2.0 * kt,
        0.03,
    );
    check(
        "c: <(A + m a^2 sin^2) thd^2>",
        batch_mean(&tr, |s| {
            let sn = s.theta.sin();
            (ia + m * a * a * sn * sn) * s.theta_dot * s.theta_dot
        }),
        kt,
        0.03,
    );
}

/// The `nano-physical` preset (C60 on graphene at 300 K with a 1.1 eV lying
/// well, 1 ns): the top, started at θ = 0.1, diffuses in orientation
/// (`D_r = kT/(γ_r A)` = 1.9e10 s⁻¹: ~25 ps to wander a radian) into the
/// well and stays there: the well is 43 kT deep (escape ~e^{−43} per
/// attempt), its thermal width `w sqrt(kT/d)` = 0.046 rad. So after 0.2 ns
/// every row is within `π/2 ± 0.3` (6.5 thermal widths), and the contact
/// holds (the reaction never reaches the pull-off force).
#[test]
fn nano_physical_lies_down_into_its_well() {
    let sc = Scenario::nano_physical();
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let half_pi = std::f64::consts::FRAC_PI_2;
    for s in tr.samples.iter().filter(|s| s.t >= 2e-10) {
        assert!(
            (s.theta - half_pi).abs() < 0.3,
            "theta {} at {} s",
            s.theta,
            s.t
        );
    }
    let margin = tr.summary.pull_off_margin_min.expect("adhesion on");
    assert!(margin > 0.0, "pull-off margin {margin}");
}

/// `method = "brownian"` version of [`hot_top`]: the step at the Brownian
/// rule's limit for the rotational diffusion `kT/(γ A)`.
fn brownian_top(gamma: f64, steps: usize, every: usize) -> Scenario {
    let probe = hot_top(T, gamma, 1.0, 1.0, 2);
    let d_r = BOLTZMANN * T / (gamma * probe.top.inertia_transverse);
    let dt = tippetop::input::thermal::MAX_BROWNIAN_STEP_RATE / d_r;
    let mut sc = hot_top(T, gamma, dt, dt * steps as f64, steps / every + 1);
    sc.solver.method = Method::Brownian;
    sc
}

/// The Brownian mode has the Langevin run's stationary orientation density
/// at g = 0, `p(θ) ∝ sin θ sqrt(1 + (m a²/A) sin²θ)` (the same eccentric
/// top, `m a²/A = 2`): this checks the drift that the mobility's
/// dependence on θ and the metric's volume need (without it the density
/// would be that of `μ_θ`'s walk). Euler–Maruyama's bias is
/// `O(dt · D_r) = O(0.002)`, below the SE. 2 500 000 steps.
#[test]
fn brownian_orientation_density_at_zero_gravity() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let gamma = thermal_rate(&probe);
    let sc = brownian_top(gamma, 2_500_000, 10);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let r = sc.top.mass * sc.top.offset * sc.top.offset / sc.top.inertia_transverse;
    let p = |th: f64| th.sin() * (1.0 + r * th.sin().powi(2)).sqrt();
    let want = density_mean(p, |th| th.cos().powi(2));
    check(
        "brownian <cos^2 theta>",
        batch_mean(&tr, |s| s.theta.cos().powi(2)),
        want,
        0.03,
    );
    // The centre: free Brownian motion, MSD = 4 D τ at every lag,
    // D = kT/(m γ_t) (the Langevin MSD's long-time limit).
    let d = BOLTZMANN * T / (sc.top.mass * gamma);
    let rows = &tr.samples[tr.samples.len() / 20..];
    let lag = 100;
    let tau = rows[lag].t - rows[0].t;
    let disp: Vec<f64> = rows
        .windows(lag + 1)
        .map(|w| (w[lag].x - w[0].x).powi(2) + (w[lag].y - w[0].y).powi(2))
        .collect();
    let (m, se) = mean_se(&disp);
    check("brownian MSD", (m, se), 4.0 * d * tau, 0.03);
}

/// Rotational diffusion of a free body (a = 0, A = C, g = 0): the axis
/// correlation `⟨k(0)·k(τ)⟩ = e^{−2 D_r τ}`, `D_r = kT/(γ_r A)`, at
/// `τ = 1/(4 D_r)` and `1/D_r` (`e^{−1/2}`, `e^{−2}`). The axis is read
/// from the attitude quaternion's third column. 2 000 000 steps.
#[test]
fn brownian_rotational_diffusion_of_a_free_body() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let gamma = thermal_rate(&probe);
    let mut sc = brownian_top(gamma, 2_000_000, 10);
    sc.top.offset = 0.0;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let d_r = BOLTZMANN * T / (gamma * sc.top.inertia_transverse);
    let axis = |s: &tippetop::Sample| {
        let (w, x, y, z) = (s.qw, s.qx, s.qy, s.qz);
        [
            2.0 * (x * z + w * y),
            2.0 * (y * z - w * x),
            1.0 - 2.0 * (x * x + y * y),
        ]
    };
    // The quaternion's axis is the state's axis.
    for s in tr.samples.iter().step_by(1000) {
        let k = axis(s);
        assert!(
            (k[2] - s.theta.cos()).abs() < 1e-9,
            "{} vs {}",
            k[2],
            s.theta.cos()
        );
    }
    let rows = &tr.samples;
    let dt_row = rows[1].t - rows[0].t;
    for tau_dr in [0.25, 1.0] {
        let lag = (tau_dr / d_r / dt_row).round() as usize;
        let tau = lag as f64 * dt_row;
        let c: Vec<f64> = rows
            .windows(lag + 1)
            .map(|w| {
                let (a, b) = (axis(&w[0]), axis(&w[lag]));
                a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
            })
            .collect();
        let (m, se) = mean_se(&c);
        check(
            &format!("brownian <k(0).k(tau)> at D_r tau = {tau_dr}"),
            (m, se),
            (-2.0 * d_r * tau).exp(),
            0.05,
        );
    }
}

/// The rigid model's Langevin run (bilateral contact: the top stays on the
/// plane) integrates the same stochastic equations in another formulation
/// (Newton–Euler in 3D with the contact closure, its own state) with the
/// same noise (the same 5 normals per half step in the same basis): its
/// path is the vector model's to rounding. Measured: |Δθ| <= 1.1e-14 over
/// 10 000 steps at 300 K with a thermal spin; bar 1e-10 (rounding
/// differences grow with the flow's sensitivity, which over 0.1 ns of
/// thermal motion did not amplify them beyond 1e-14).
#[test]
fn rigid_langevin_follows_the_vector_path() {
    let mut sc = Scenario::nano();
    sc.surface.friction = 0.0;
    sc.solver.method = Method::Langevin;
    sc.solver.dt = Some(1e-14);
    sc.solver.t_end = 1e-10;
    sc.solver.samples = 101;
    sc.thermal.temperature = T;
    sc.thermal.damping_translational = 1e11;
    sc.thermal.damping_rotational = 1e11;
    sc.thermal.seed = Some(1);
    let v = simulate(&sc).unwrap();
    let mut r = sc.clone();
    r.solver.model = tippetop::ModelKind::Rigid;
    let r = simulate(&r).unwrap();
    assert!(v.error.is_none() && r.error.is_none());
    assert_eq!(v.samples.len(), r.samples.len());
    let mut worst: f64 = 0.0;
    for (a, b) in v.samples.iter().zip(&r.samples) {
        assert_eq!(a.t, b.t);
        worst = worst.max((a.theta - b.theta).abs());
        for (x, y) in [(a.spin, b.spin), (a.ux, b.ux), (a.energy, b.energy)] {
            assert!(
                (x - y).abs() <= 1e-9 * y.abs().max(1e-300),
                "{x} vs {y} at {}",
                a.t
            );
        }
    }
    eprintln!("rigid vs vector: max |dtheta| = {worst:e}");
    assert!(worst < 1e-10, "{worst}");
    // The rigid Langevin run is equipartitioned on its own too (a shorter
    // run than the vector model's: 1 000 000 steps, SE ~1.5 %).
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let dt = 0.02 / rate;
    let n = 1_000_000usize;
    let mut sc = hot_top(T, rate, dt, dt * n as f64, n / 10 + 1);
    sc.solver.model = tippetop::ModelKind::Rigid;
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let kt = BOLTZMANN * T;
    let (m, a) = (sc.top.mass, sc.top.offset);
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    check(
        "rigid <C w^2>",
        batch_mean(&tr, |s| ic * s.spin * s.spin),
        kt,
        0.03,
    );
    check(
        "rigid <(A + m a^2 sin^2) thd^2>",
        batch_mean(&tr, |s| {
            let sn = s.theta.sin();
            (ia + m * a * a * sn * sn) * s.theta_dot * s.theta_dot
        }),
        kt,
        0.03,
    );
    check(
        "rigid <m |u_h|^2>",
        batch_mean(&tr, |s| m * (s.ux * s.ux + s.uy * s.uy)),
        2.0 * kt,
        0.03,
    );
}

/// The normal force averaged over each output interval (stochastic runs,
/// `Summary::normal_intervals`): over the run its mean is `m g + F_a` by
/// the vertical momentum balance (the bath's vertical force has zero
/// mean, and `m Δv_z / t_end` ~ 1e-14 N is negligible), checked on the
/// `nano-physical` preset (1 ns, 1000 intervals) within 5 standard errors
/// of the time average (40 batch means of the output rows' N); the interval
/// means' range brackets it, none negative (the adhesion holds). A
/// deterministic run has no such entry.
#[test]
fn interval_averaged_normal_force_balances_the_load() {
    let sc = Scenario::nano_physical();
    let tr = simulate(&sc).unwrap();
    let ni = tr.summary.normal_intervals.expect("stochastic run");
    let want = sc.top.mass * sc.surface.gravity + sc.adhesion().force;
    let rows = &tr.samples;
    let (m, se) = mean_se(&rows.iter().map(|s| s.normal).collect::<Vec<f64>>());
    eprintln!(
        "interval mean {:e}, rows' mean {m:e} ± {se:e}, want {want:e}; min {:e}, max {:e}",
        ni.mean, ni.mean_min, ni.mean_max
    );
    assert_eq!(ni.intervals, sc.solver.samples - 1);
    assert!(se < 0.01 * want, "SE {se}");
    assert!(
        (ni.mean - want).abs() < 5.0 * se,
        "{} vs {want} (SE {se})",
        ni.mean
    );
    assert!(ni.mean_min < want && want < ni.mean_max);
    assert_eq!(ni.negative_fraction, 0.0);
    assert!(
        simulate(&Scenario::nano())
            .unwrap()
            .summary
            .normal_intervals
            .is_none()
    );
}

/// With a well the orientation has the Boltzmann density
/// `p(θ) ∝ sin θ sqrt(1 + (m a²/A) sin²θ) e^{−U(θ)/kT}` (g = 0): a
/// Gaussian well at θ = 1.2 of depth 2 kT and width 0.8 shifts the
/// distribution towards it; checked on `⟨cos θ⟩` and `⟨cos²θ⟩` against the
/// quadrature of that density (without the well: 0 and 0.2924), with the
/// Langevin and the Brownian method, each step at its rule's limit (the
/// well's curvature is the fastest rate); 3 000 000 steps each (~3 s).
#[test]
fn boltzmann_density_with_a_well() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let kt = BOLTZMANN * T;
    let ia = probe.top.inertia_transverse;
    let well = tippetop::Well {
        theta: 1.2,
        depth: 2.0 * kt,
        width: 0.8,
    };
    let r = probe.top.mass * probe.top.offset * probe.top.offset / ia;
    let u = |th: f64| -well.depth * (-0.5 * ((th - well.theta) / well.width).powi(2)).exp();
    let p = |th: f64| th.sin() * (1.0 + r * th.sin().powi(2)).sqrt() * (-u(th) / kt).exp();
    let want1 = density_mean(p, f64::cos);
    let want2 = density_mean(p, |th| th.cos().powi(2));
    eprintln!("Boltzmann with the well: <cos> = {want1}, <cos^2> = {want2}");
    assert!(
        want1 > 0.1,
        "the well must shift the density: <cos> = {want1}"
    );
    let steps = 3_000_000usize;
    let well_rate = (well.depth / (well.width * well.width * ia)).sqrt();
    let dt = 0.02 / rate.max(well_rate);
    let mut lv = hot_top(T, rate, dt, dt * steps as f64, steps / 10 + 1);
    lv.set_wells(&[well]);
    let d_r = kt / (rate * ia);
    let well_relax = well.depth / (well.width * well.width * rate * ia);
    let dtb = tippetop::input::thermal::MAX_BROWNIAN_STEP_RATE / d_r.max(well_relax);
    let mut br = hot_top(T, rate, dtb, dtb * steps as f64, steps / 10 + 1);
    br.solver.method = Method::Brownian;
    br.set_wells(&[well]);
    // The Brownian run's step is 1/500 of a decorrelation time (its rule),
    // so the same number of steps covers fewer independent samples: its SE
    // bound is wider (the well's shift of <cos θ> from 0 is still >10 SE).
    for (name, sc, bound) in [("langevin", lv, 0.06), ("brownian", br, 0.1)] {
        let tr = simulate(&sc).expect("valid");
        assert!(tr.error.is_none(), "{:?}", tr.error);
        check(
            &format!("{name} well <cos theta>"),
            batch_mean(&tr, |s| s.theta.cos()),
            want1,
            bound,
        );
        check(
            &format!("{name} well <cos^2 theta>"),
            batch_mean(&tr, |s| s.theta.cos().powi(2)),
            want2,
            bound,
        );
    }
}

/// A free body (the rigid model in flight) has a uniform orientation,
/// `⟨cos²θ⟩ = 1/3` (not the constrained top's 0.2924 for this eccentric
/// top: off the plane the centre's height no longer follows the tilt), and
/// equipartition `⟨C ω²⟩ = kT`, `⟨A (θ̇² + Ω² sin²θ)⟩ = 2 kT`. The top is
/// pulled off the plane (unilateral contact, g = 0, an upward pull of
/// 2.4e-11 N at the contact point for 10 ps gives it ~200 m/s) and the
/// translational damping is small (γ_t = 1e8 s⁻¹: it keeps flying away),
/// the rotational one thermal; rows after 50 ps, all in flight.
#[test]
fn free_body_in_flight_is_uniform() {
    let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
    let rate = thermal_rate(&probe);
    let pull = 2.4e-11;
    let lever = probe.top.radius + probe.top.offset;
    let pull_rate = (pull * lever / probe.top.inertia_transverse).sqrt();
    let dt = 0.02 / rate.max(pull_rate);
    let steps = 700_000usize;
    let mut sc = hot_top(T, rate, dt, dt * steps as f64, steps / 10 + 1);
    sc.solver.model = tippetop::ModelKind::Rigid;
    sc.surface.contact = tippetop::ContactMode::Unilateral;
    sc.thermal.damping_translational = 1e8;
    sc.forcing = Forcing {
        windows: vec![ForceWindow {
            hx: 0.0,
            hy: 0.0,
            hz: -pull,
            start: 0.0,
            stop: 1e-11,
        }],
    };
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let flying: Vec<tippetop::Sample> =
        tr.samples.iter().filter(|s| s.t > 5e-11).copied().collect();
    for s in &flying {
        assert!(
            s.z > 2.0 * sc.top.radius,
            "back on the plane at {}: z {}",
            s.t,
            s.z
        );
    }
    let ft = Trajectory {
        samples: flying,
        ..tr.clone()
    };
    let kt = BOLTZMANN * T;
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    check(
        "free <cos^2 theta>",
        batch_mean(&ft, |s| s.theta.cos().powi(2)),
        1.0 / 3.0,
        0.03,
    );
    check(
        "free <C w^2>",
        batch_mean(&ft, |s| ic * s.spin * s.spin),
        kt,
        0.03,
    );
    check(
        "free <A |n_perp|^2>",
        batch_mean(&ft, |s| {
            let sn = s.theta.sin();
            ia * (s.theta_dot * s.theta_dot + s.precession * s.precession * sn * sn)
        }),
        2.0 * kt,
        0.03,
    );
}

/// The rigid model's Brownian mode (bilateral contact) takes the vector
/// model's step with its own generalised force at rest: with the same seed
/// its path is the vector model's to rounding (100 000 steps of
/// nano-physical; bar 1e-12), without and with the contact damping
/// (`c/m = γ_t`, the coupled step of §brownian): measured max |Δθ| = 2.2e-16
/// and 1.1e-16 (θ moves by up to 1.55 and 0.59 rad).
#[test]
fn rigid_brownian_follows_the_vector_path() {
    for contact in [false, true] {
        rigid_brownian_vs_vector(contact);
    }
}

fn rigid_brownian_vs_vector(contact: bool) {
    let mut sc = Scenario::nano_physical();
    sc.solver.method = Method::Brownian;
    sc.solver.dt = Some(1e-16);
    sc.solver.t_end = 1e-11;
    sc.solver.samples = 101;
    if contact {
        sc.thermal.damping_contact = sc.top.mass * sc.thermal.damping_translational;
    }
    let v = simulate(&sc).unwrap();
    let mut r = sc.clone();
    r.solver.model = tippetop::ModelKind::Rigid;
    let r = simulate(&r).unwrap();
    assert!(v.error.is_none() && r.error.is_none());
    let worst = v
        .samples
        .iter()
        .zip(&r.samples)
        .map(|(a, b)| (a.theta - b.theta).abs())
        .fold(0.0, f64::max);
    eprintln!("rigid vs vector brownian (contact damping {contact}): max |dtheta| = {worst:e}");
    assert!(worst < 1e-12, "{worst}");
    let moved = v
        .samples
        .iter()
        .map(|s| (s.theta - 0.1).abs())
        .fold(0.0, f64::max);
    eprintln!("max |theta - 0.1| = {moved}");
    assert!(moved > 0.1, "it moved: {moved}");
}

/// The mobility of the top on the plane with the contact damping `c`
/// (SI), from its friction matrix in the frame `(ĥ, ê | k̂, ê, f̂)` (`ĥ` the
/// horizontal direction of the axis, `ê = k × Z/|k × Z|`), where it splits
/// into two blocks: the slip along `ĥ` is `v_ĥ + (R − a cos θ) w_ê` and
/// along `ê` it is `v_ê − R sin θ w_k + (a − R cos θ) w_f̂`, so
///
/// - `Γ_A = diag(m γ_t, γ_r A + m γ_t a² sin²θ) + c u uᵀ`, `u = (1, R − a cos θ)`
///   on `(v_ĥ, w_ê)`;
/// - `Γ_B = diag(m γ_t, γ_r C, γ_r A) + c u uᵀ`, `u = (1, −R sin θ, a − R cos θ)`
///   on `(v_ê, w_k, w_f̂)`.
///
/// Returns `(μ_A, μ_B)`, inverted here by hand (2×2 and Sherman–Morrison),
/// independently of the library's 5×5 Cholesky in the lab basis.
fn contact_mobility(sc: &Scenario, theta: f64) -> ([[f64; 2]; 2], [[f64; 3]; 3]) {
    let (m, a, r) = (sc.top.mass, sc.top.offset, sc.top.radius);
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    let th = &sc.thermal;
    let (gt, gr, c) = (
        th.damping_translational,
        th.damping_rotational,
        th.damping_contact,
    );
    let (s, co) = theta.sin_cos();
    let ua = [1.0, r - a * co];
    let ga = [
        [m * gt + c * ua[0] * ua[0], c * ua[0] * ua[1]],
        [
            c * ua[1] * ua[0],
            gr * ia + m * gt * a * a * s * s + c * ua[1] * ua[1],
        ],
    ];
    let det = ga[0][0] * ga[1][1] - ga[0][1] * ga[1][0];
    let mu_a = [
        [ga[1][1] / det, -ga[0][1] / det],
        [-ga[1][0] / det, ga[0][0] / det],
    ];
    let d = [1.0 / (m * gt), 1.0 / (gr * ic), 1.0 / (gr * ia)];
    let ub = [1.0, -r * s, a - r * co];
    let du: [f64; 3] = std::array::from_fn(|i| d[i] * ub[i]);
    let q = 1.0 + c * (0..3).map(|i| ub[i] * du[i]).sum::<f64>();
    let mu_b = std::array::from_fn(|i| {
        std::array::from_fn(|j| if i == j { d[i] } else { 0.0 } - c * du[i] * du[j] / q)
    });
    (mu_a, mu_b)
}

/// The centre's short-time and long-time diffusion coefficients (per axis,
/// SI) of the overdamped top with the contact damping, in equilibrium with
/// the orientation density `p(θ) ∝ sin θ s(θ) e^{−U/kT}`:
///
/// - short time: `D_s = kT ⟨(μ_A,ĥĥ + μ_B,êê)/2⟩_p` (the translational block
///   of the mobility, averaged over the orientation; the mean-square
///   displacement is `4 D_s τ` for `τ` short against the orientation's
///   relaxation);
/// - long time: `D_∞ = (kT/2) min_g ⟨(1, −g') μ_A (1, −g')ᵀ + (1, 0, g/sin θ)
///   μ_B (1, 0, g/sin θ)ᵀ⟩_p`, the homogenised coefficient of the reversible
///   diffusion (the Dirichlet form minimised over the corrector `χ = g(θ)
///   cos φ` of the displacement along X; Pavliotis & Stuart, *Multiscale
///   Methods* (2008) §13, Kipnis & Varadhan 1986): lower than `D_s`
///   because the orientation-dependent coupling drifts the centre along
///   the axis's horizontal direction. `g(0) = g(π) = 0`, piecewise linear
///   on 4000 intervals (a tridiagonal system; error O(h²) ~ 1e-7).
fn contact_diffusion(sc: &Scenario, p: impl Fn(f64) -> f64) -> (f64, f64) {
    let kt = BOLTZMANN * sc.thermal.temperature;
    let n = 4000usize;
    let h = std::f64::consts::PI / n as f64;
    // Unknowns g_1 … g_{n−1}: the quadratic form gᵀ K g − 2 rhsᵀ g.
    let (mut diag, mut off, mut rhs) = (vec![0.0; n - 1], vec![0.0; n - 1], vec![0.0; n - 1]);
    let (mut z, mut base) = (0.0, 0.0);
    for j in 0..n {
        let t = (j as f64 + 0.5) * h;
        let (ma, mb) = contact_mobility(sc, t);
        let w = p(t) * h;
        z += w;
        base += w * (ma[0][0] + mb[0][0]);
        // w (μ_A,11 g'² − 2 μ_A,01 g'), g' = (g_{j+1} − g_j)/h.
        let coef = w * ma[1][1] / (h * h);
        let lin = -2.0 * w * ma[0][1] / h;
        for (node, sign) in [(j, -1.0), (j + 1, 1.0)] {
            if (1..n).contains(&node) {
                diag[node - 1] += coef;
                rhs[node - 1] -= 0.5 * lin * sign;
            }
        }
        if j >= 1 && j + 1 < n {
            off[j - 1] -= coef;
        }
    }
    for (i, t) in (1..n).map(|i| (i - 1, i as f64 * h)) {
        let (_, mb) = contact_mobility(sc, t);
        let w = p(t) * h;
        let s = t.sin();
        diag[i] += w * mb[2][2] / (s * s);
        rhs[i] -= w * mb[0][2] / s;
    }
    // Thomas algorithm (K is symmetric positive definite, tridiagonal:
    // diag on the diagonal, off[i] at (i, i + 1)).
    let m = n - 1;
    let (mut cp, mut dp) = (vec![0.0; m], vec![0.0; m]);
    for i in 0..m {
        let lower = if i > 0 { off[i - 1] } else { 0.0 };
        let den = diag[i] - if i > 0 { lower * cp[i - 1] } else { 0.0 };
        cp[i] = if i + 1 < m { off[i] / den } else { 0.0 };
        dp[i] = (rhs[i] - if i > 0 { lower * dp[i - 1] } else { 0.0 }) / den;
    }
    let mut g = vec![0.0; m];
    for i in (0..m).rev() {
        g[i] = dp[i] - if i + 1 < m { cp[i] * g[i + 1] } else { 0.0 };
    }
    let jmin: f64 = -(0..m).map(|i| rhs[i] * g[i]).sum::<f64>();
    (0.5 * kt * base / z, 0.5 * kt * (base + jmin) / z)
}

/// The well of [`boltzmann_density_with_a_well`] (θ = 1.2, depth 2 kT,
/// width 0.8) and its Boltzmann density for the eccentric top of
/// [`hot_top`].
fn test_well(probe: &Scenario) -> (tippetop::Well, impl Fn(f64) -> f64) {
    let kt = BOLTZMANN * T;
    let well = tippetop::Well {
        theta: 1.2,
        depth: 2.0 * kt,
        width: 0.8,
    };
    let r = probe.top.mass * probe.top.offset * probe.top.offset / probe.top.inertia_transverse;
    let p = move |th: f64| {
        let u = -well.depth * (-0.5 * ((th - well.theta) / well.width).powi(2)).exp();
        th.sin() * (1.0 + r * th.sin().powi(2)).sqrt() * (-u / kt).exp()
    };
    (well, p)
}

/// The Brownian run with the contact damping on, `c/m = γ_t = γ_r` (the
/// contact's rotational rate `c (R + a)²/A` is 14 γ_r: the translation and
/// the tilt are strongly coupled), the well of [`test_well`], g = 0; the
/// step at the Brownian rule's limit (the rule's rates are those without
/// `c`, upper bounds: `c` only lowers the mobility), 6 000 000 steps, a
/// row every 15.
fn brownian_contact_run() -> &'static (Scenario, Trajectory) {
    static RUN: OnceLock<(Scenario, Trajectory)> = OnceLock::new();
    RUN.get_or_init(|| {
        let probe = hot_top(T, 1.0, 1.0, 1.0, 2);
        let rate = thermal_rate(&probe);
        let (well, _) = test_well(&probe);
        let ia = probe.top.inertia_transverse;
        let d_r = BOLTZMANN * T / (rate * ia);
        let well_relax = well.depth / (well.width * well.width * rate * ia);
        let dt = tippetop::input::thermal::MAX_BROWNIAN_STEP_RATE / d_r.max(well_relax);
        let steps = 6_000_000usize;
        let mut sc = hot_top(T, rate, dt, dt * steps as f64, steps / 15 + 1);
        sc.solver.method = Method::Brownian;
        sc.set_wells(&[well]);
        sc.thermal.damping_contact = sc.top.mass * rate;
        let tr = simulate(&sc).expect("valid");
        assert!(tr.error.is_none(), "{:?}", tr.error);
        (sc, tr)
    })
}

/// With the contact damping the Brownian mode's mobility `Γ⁻¹` depends on
/// θ and on the axis's horizontal direction and couples the centre to the
/// tilt and the spin (docs/physics.md#brownian); its drift `kT ∇·μ + kT μ ∇ ln
/// s` keeps the orientation at the Boltzmann density `sin θ s(θ)
/// e^{−U/kT}` (the Langevin run's; `μ_θ` is not symmetric about π/2 here,
/// so a wrong drift moves `⟨cos θ⟩`). Measured by editing the step (same
/// seed): without the drift correction `⟨cos θ⟩` = −0.353 ± 0.011 (−48 SE);
/// with `μ ∇ ln s` but not `∇·μ`, −0.309 ± 0.010 (−47 SE); with `∇·μ` of
/// the uncoupled `Γ` (`c = 0`, the hand-derived `cot θ` terms), −0.957 ±
/// 0.004 (the top is driven to θ = π). 6 000 000 steps, ~7 s. The SE
/// bound of `⟨cos θ⟩` is 15 % of its small value (SE < 0.023; measured
/// 0.014): the wrong models are more than 0.45 away, 20 SE at that bound.
#[test]
fn brownian_contact_damping_boltzmann_density_with_a_well() {
    let (sc, tr) = brownian_contact_run();
    let (_, p) = test_well(sc);
    let want1 = density_mean(&p, f64::cos);
    let want2 = density_mean(&p, |th| th.cos().powi(2));
    check(
        "brownian c: well <cos theta>",
        batch_mean(tr, |s| s.theta.cos()),
        want1,
        0.15,
    );
    check(
        "brownian c: well <cos^2 theta>",
        batch_mean(tr, |s| s.theta.cos().powi(2)),
        want2,
        0.1,
    );
}

/// The centre's diffusion with the contact damping against the closed
/// forms of [`contact_diffusion`]: the mean-square displacement over one
/// row (15 steps, `τ kT/(γ_r A)` = 0.01: short against the orientation's
/// relaxation) is `4 D_s τ` (SE 0.3 %), and over 4 orientation relaxation
/// times `1/(2 kT ⟨μ_ê⟩)` it is `4 D_∞ τ` (the long-time limit, which the
/// Langevin run shares at high friction; SE 3.5 %). `D_s` is 20 % below the
/// uncoupled `kT/(m γ_t)` and 60 % above `kT/(m γ_t + c)` (a mobility that
/// ignored the coupling), both far outside the error bars (the long-time
/// check asserts its power against them: 7.9 and 10.3 SE). `D_∞` is 1.6 %
/// below `D_s`, inside the long-time error bar. Without the drift
/// correction the short-time check fails by +42 SE (the orientation
/// density moves, and `μ_tt` with it).
#[test]
fn brownian_contact_damping_diffusion_of_the_centre() {
    let (sc, tr) = brownian_contact_run();
    let (_, p) = test_well(sc);
    let (ds, dinf) = contact_diffusion(sc, &p);
    let kt = BOLTZMANN * T;
    let free = kt / (sc.top.mass * sc.thermal.damping_translational);
    eprintln!("D_s = {ds:e}, D_inf = {dinf:e}, kT/(m gamma_t) = {free:e}");
    let rows = &tr.samples[tr.samples.len() / 20..];
    let dt_row = tr.samples[1].t - tr.samples[0].t;
    let msd = |lag: usize| {
        let disp: Vec<f64> = rows
            .windows(lag + 1)
            .map(|w| (w[lag].x - w[0].x).powi(2) + (w[lag].y - w[0].y).powi(2))
            .collect();
        mean_se(&disp)
    };
    let (m1, se1) = msd(1);
    check(
        "brownian c: short-time D",
        (m1 / (4.0 * dt_row), se1 / (4.0 * dt_row)),
        ds,
        0.01,
    );
    assert!((ds - free).abs() > 0.1 * free, "the coupling lowers D");
    // The orientation's relaxation time from the mean tilt mobility.
    let mu_e = density_mean(&p, |t| contact_mobility(sc, t).0[1][1]);
    let relax = 1.0 / (2.0 * kt * mu_e);
    let lag = (4.0 * relax / dt_row).round() as usize;
    let tau = lag as f64 * dt_row;
    let (m, se) = msd(lag);
    // The offset `4 (D_s − D_∞) τ_c` of the MSD's linear growth biases
    // this by about (D_s − D_∞) τ_c/τ ≈ 1.6 %/4, a tenth of the SE.
    check(
        "brownian c: long-time D",
        (m / (4.0 * tau), se / (4.0 * tau)),
        dinf,
        0.05,
    );
    for wrong in [
        free,
        kt / (sc.top.mass * sc.thermal.damping_translational + sc.thermal.damping_contact),
    ] {
        assert!(
            (wrong - dinf).abs() > 5.0 * se / (4.0 * tau),
            "power against {wrong:e}"
        );
    }
}
