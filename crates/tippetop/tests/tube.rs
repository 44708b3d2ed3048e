//! The rigid model inside a horizontal tube (issue #30 item 2,
//! docs/physics.md#tube-dynamics), against closed forms that do not come
//! from the code:
//!
//! - a uniform ball rolling without slipping at the bottom of the tube is a
//!   pendulum of length `7 (b − R)/5` (kinetic energy `7/10 m (b − R)² φ̇²`,
//!   potential `m g (b − R)(1 − cos φ)`): `ω² = 5 g/(7 (b − R))` at small
//!   amplitude, and the exact period `2π/(ω AGM(1, cos(φ₀/2)))` at any;
//! - a frictionless ball slides without turning: a pendulum of length
//!   `b − R`, `ω² = g/(b − R)`;
//! - a spinning eccentric top with friction keeps `E(t) − E(0) = W_f` and
//!   stays on the wall (the gap held at 0, never below);
//! - as `b → ∞` the tube is the plane (the classical preset's run).
//!
//! The periods are fitted from the zero crossings of the centre's `y` (the
//! centre's angle about the axis is `asin(y/(b − R))`), linearly
//! interpolated between samples (the crossing of a sine is a point of
//! inflection: the interpolation's error is third order in the sample step).

use tippetop::input::solver::ModelKind;
use tippetop::model::rigid::DIM;
use tippetop::{FrictionLaw, Scenario, Top, input::surface::Shape};

/// A uniform ball of radius `r` (classical preset's mass) at rest in a tube
/// of radius `b`, its contact turned by `phi0` from the lowest line.
fn ball_in_tube(r: f64, b: f64, phi0: f64, mu: f64, law: FrictionLaw) -> Scenario {
    let mut sc = Scenario::classical();
    let m = sc.top.mass;
    sc.top = Top {
        radius: r,
        offset: 0.0,
        mass: m,
        inertia_transverse: 0.4 * m * r * r,
        inertia_axial: 0.4 * m * r * r,
        stem: None,
    };
    sc.surface.friction = mu;
    sc.surface.law = law;
    sc.surface.shape = Shape::Tube {
        radius: b,
        angle: phi0,
    };
    sc.solver.model = ModelKind::Rigid;
    sc.initial.theta = 0.0;
    sc.initial.theta_dot = 0.0;
    sc.initial.precession = 0.0;
    sc.initial.spin = 0.0;
    sc.initial.ux = 0.0;
    sc.initial.uy = 0.0;
    sc
}

/// The mean period from the first to the last zero crossing of `y(t)`
/// (linear interpolation between samples) and the number of half periods.
fn period_from_crossings(t: &[f64], y: &[f64]) -> (f64, usize) {
    let mut cross = Vec::new();
    for i in 1..y.len() {
        if (y[i - 1] < 0.0) != (y[i] < 0.0) {
            let s = y[i - 1] / (y[i - 1] - y[i]);
            cross.push(t[i - 1] + s * (t[i] - t[i - 1]));
        }
    }
    assert!(cross.len() >= 3, "only {} crossings", cross.len());
    let n = cross.len() - 1;
    (2.0 * (cross[n] - cross[0]) / n as f64, n)
}

/// Arithmetic–geometric mean.
fn agm(mut a: f64, mut b: f64) -> f64 {
    while (a - b).abs() > 1e-16 * a {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    a
}

/// The run's period and the worst |gap| (scaled by R) at the accepted steps.
fn measure(sc: &Scenario) -> (f64, usize, f64, bool) {
    let r = sc.top.radius;
    let mut worst_gap: f64 = 0.0;
    let mut rolled = true;
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, _, y: &[f64; DIM]| {
        worst_gap = worst_gap.max(m.gap(y).abs());
        rolled &= m.contact.mode == tippetop::model::rigid::Mode::Rolling;
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let t: Vec<f64> = tr.samples.iter().map(|s| s.t).collect();
    let y: Vec<f64> = tr.samples.iter().map(|s| s.y).collect();
    let (p, n) = period_from_crossings(&t, &y);
    let _ = r;
    (p, n, worst_gap, rolled)
}

const G: f64 = 9.8;

/// A uniform ball rolling at the bottom of the tube, amplitude 1e-3 rad
/// (the pendulum's shift φ₀²/16 = 6e-8): `ω² = 5 g/(7 (b − R))` to 1e-6.
#[test]
fn rolling_ball_small_amplitude() {
    let (r, b) = (0.01, 0.05);
    let w0 = (5.0 * G / (7.0 * (b - r))).sqrt();
    let t0 = 2.0 * std::f64::consts::PI / w0;
    let mut sc = ball_in_tube(r, b, 1e-3, 1.0, FrictionLaw::Coulomb);
    sc.solver.t_end = 6.25 * t0;
    sc.solver.samples = 20001;
    let (p, n, gap, rolled) = measure(&sc);
    let err = p / t0 - 1.0;
    println!(
        "rolling ball: period {p:.9e} s over {n} half periods, closed form {t0:.9e} s, rel. error {err:.2e}; worst |gap| {gap:.1e} R; rolled throughout: {rolled}"
    );
    assert!(rolled, "the ball did not roll throughout");
    assert!(err.abs() < 1e-6, "rolling period off by {err:e}");
    assert!(gap < 1e-12, "the wall's constraint drifted by {gap:e} R");
}

/// The same ball at 0.3 rad: the exact pendulum period
/// `2π/(ω AGM(1, cos(φ₀/2)))` (a 0.56 % shift from the small-amplitude one)
/// to 1e-6.
#[test]
fn rolling_ball_large_amplitude_is_a_pendulum() {
    let (r, b, phi0): (f64, f64, f64) = (0.01, 0.05, 0.3);
    let w0 = (5.0 * G / (7.0 * (b - r))).sqrt();
    let t_exact = 2.0 * std::f64::consts::PI / (w0 * agm(1.0, (0.5 * phi0).cos()));
    let mut sc = ball_in_tube(r, b, phi0, 1.0, FrictionLaw::Coulomb);
    sc.solver.t_end = 6.25 * t_exact;
    sc.solver.samples = 20001;
    let (p, n, gap, rolled) = measure(&sc);
    let err = p / t_exact - 1.0;
    println!(
        "rolling ball at 0.3 rad: period {p:.9e} s over {n} half periods, exact {t_exact:.9e} s, rel. error {err:.2e}; worst |gap| {gap:.1e} R"
    );
    assert!(rolled, "the ball did not roll throughout");
    assert!(err.abs() < 1e-6, "rolling period off by {err:e}");
    assert!(gap < 1e-12, "the wall's constraint drifted by {gap:e} R");
}

/// A frictionless ball slides without turning: `ω² = g/(b − R)` to 1e-6
/// (amplitude 1e-3 rad).
#[test]
fn sliding_ball_small_amplitude() {
    let (r, b) = (0.01, 0.05);
    let w0 = (G / (b - r)).sqrt();
    let t0 = 2.0 * std::f64::consts::PI / w0;
    let mut sc = ball_in_tube(r, b, 1e-3, 0.0, FrictionLaw::CoulombSliding);
    sc.solver.t_end = 6.25 * t0;
    sc.solver.samples = 20001;
    let (p, n, gap, _) = measure(&sc);
    let err = p / t0 - 1.0;
    println!(
        "sliding ball: period {p:.9e} s over {n} half periods, closed form {t0:.9e} s, rel. error {err:.2e}; worst |gap| {gap:.1e} R"
    );
    assert!(err.abs() < 1e-6, "sliding period off by {err:e}");
    assert!(gap < 1e-12, "the wall's constraint drifted by {gap:e} R");
}

/// The classical preset's eccentric top, spinning, with the exact Coulomb
/// law in a tube of radius `b`, its contact turned by 0.2 rad.
/// A rigid run of `sc` with its contact watched at every accepted step:
/// the trajectory (no error), the largest |gap| and the smallest gap \[m\],
/// and whether it slid and rolled.
fn watched(sc: &Scenario) -> (tippetop::Trajectory, f64, f64, bool, bool) {
    let (mut worst_gap, mut min_gap) = (0.0f64, f64::INFINITY);
    let (mut slid, mut rolled) = (false, false);
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, _, y: &[f64; DIM]| {
        let g = m.gap(y);
        worst_gap = worst_gap.max(g.abs());
        min_gap = min_gap.min(g);
        match m.contact.mode {
            tippetop::model::rigid::Mode::Rolling => rolled = true,
            tippetop::model::rigid::Mode::Sliding => slid = true,
        }
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    (tr, worst_gap, min_gap, slid, rolled)
}

/// The energy balance's largest miss over the samples,
/// `max |E − E0 − W_f − W_a| / |E0|` (`W_a` is 0 without applied forces).
fn worst_balance(tr: &tippetop::Trajectory) -> f64 {
    let e0 = tr.samples[0].energy;
    tr.samples
        .iter()
        .map(|s| (s.energy - e0 - s.work_friction - s.work_applied).abs() / e0.abs())
        .fold(0.0, f64::max)
}

fn top_in_tube(b: f64) -> Scenario {
    let mut sc = Scenario::classical();
    sc.surface.shape = Shape::Tube {
        radius: b,
        angle: 0.2,
    };
    sc.solver.model = ModelKind::Rigid;
    sc
}

/// Energy balance `E(t) − E(0) = W_f` for a spinning eccentric top with
/// friction in the tube (the normal force does no work on a fixed wall;
/// gravity is in E), to 1e-7 of the initial energy at every sample (the
/// integrator's tolerance is 1e-10 per step), and no penetration: the gap
/// stays within 1e-9 R of 0 at every accepted step (never below −1e-9 R).
/// The run slides and rolls (both are checked to occur).
#[test]
fn energy_balance_and_no_penetration() {
    let mut sc = top_in_tube(0.05);
    sc.solver.t_end = 2.0;
    sc.solver.samples = 2001;
    let (tr, worst_gap, min_gap, slid, rolled) = watched(&sc);
    let e0 = tr.samples[0].energy;
    let worst = worst_balance(&tr);
    let wf = tr.samples.last().unwrap().work_friction;
    println!(
        "top in the tube: |E - E0 - W_f|/E0 <= {worst:.2e} (W_f = {:.3e} of E0); gap in [{min_gap:.1e}, {worst_gap:.1e}] R; slid {slid}, rolled {rolled}; theta {:.3} -> {:.3} rad",
        wf / e0,
        tr.samples[0].theta,
        tr.samples.last().unwrap().theta
    );
    assert!(wf < -1e-3 * e0.abs(), "friction did no work: {wf:e}");
    assert!(worst < 1e-7, "energy balance off by {worst:e} E0");
    assert!(min_gap > -1e-9, "penetration {min_gap:e} R");
    assert!(
        worst_gap < 1e-9,
        "the wall's constraint drifted by {worst_gap:e} R"
    );
}

/// Frictionless sliding in the tube keeps what the forces cannot change
/// (docs/physics.md#tube-dynamics): the normal force `N n` lies across the
/// axis (`n·X = 0`) and gravity too, so `m v_x` is constant; the torque
/// about the centre of mass, `a N k × n`, is normal to `k`, so the spin
/// `w·k` is constant; and `E` is constant. Each to 1e-9 (relative to its
/// initial scale) at every sample. `L·n`, conserved in no general way, is
/// printed beside them.
#[test]
fn frictionless_top_keeps_axial_momentum_spin_and_energy() {
    let mut sc = top_in_tube(0.05);
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.ux = 0.3;
    sc.initial.uy = 0.1;
    sc.solver.t_end = 1.0;
    sc.solver.samples = 1001;
    let mut first: Option<(f64, f64, f64)> = None;
    let (mut dvx, mut dspin, mut de, mut dln) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let tr = tippetop::simulate::simulate_rigid_observed(&sc, &mut |m, _, y: &[f64; DIM]| {
        let vx = y[tippetop::model::rigid::VEL];
        let spin = m.spin_scaled(y);
        let l = m.angular_momentum(y);
        let nrm = m.tube_at(y).expect("in the tube").n;
        let ln = l[0] * nrm[0] + l[1] * nrm[1] + l[2] * nrm[2];
        let e = m.energy_scaled(y);
        match first {
            None => first = Some((vx, spin, e)),
            Some((vx0, s0, e0)) => {
                dvx = dvx.max((vx - vx0).abs() / vx0.abs());
                dspin = dspin.max((spin - s0).abs() / s0.abs());
                de = de.max((e - e0).abs() / e0.abs());
                dln = dln.max(ln.abs());
            }
        }
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    println!(
        "frictionless top: rel. change of v_x {dvx:.1e}, of w.k {dspin:.1e}, of E {de:.1e}; max |L.n| {dln:.3e} (scaled)"
    );
    assert!(dvx < 1e-9 && dspin < 1e-9 && de < 1e-9);
}

/// `plane` run on the plane and in a tube of radius `radius` [m] (the
/// contact at the lowest line), both to their end without error.
fn plane_and_tube(plane: &Scenario, radius: f64) -> (tippetop::Trajectory, tippetop::Trajectory) {
    let mut tube = plane.clone();
    tube.surface.shape = Shape::Tube { radius, angle: 0.0 };
    let a = tippetop::simulate(plane).unwrap();
    let b = tippetop::simulate(&tube).unwrap();
    assert!(
        a.error.is_none() && b.error.is_none(),
        "{:?} {:?}",
        a.error,
        b.error
    );
    (a, b)
}

/// The plane recovered as `b → ∞`: the classical preset's rigid run on
/// the plane and in a tube of radius 1e6 m (the wall's tilt over the ~3 cm
/// the top travels is 3e-8 rad) give the same θ(t) and spin to 1e-6 over
/// 2 s (rolling, sliding and the tilt's growth included).
#[test]
fn wide_tube_is_the_plane() {
    let mut plane = Scenario::classical();
    plane.solver.model = ModelKind::Rigid;
    plane.solver.t_end = 2.0;
    plane.solver.samples = 201;
    let (a, b) = plane_and_tube(&plane, 1e6);
    let (mut dth, mut dsp) = (0.0f64, 0.0f64);
    for (p, q) in a.samples.iter().zip(&b.samples) {
        dth = dth.max((p.theta - q.theta).abs());
        dsp = dsp.max((p.spin - q.spin).abs() / p.spin.abs().max(1.0));
    }
    println!(
        "b = 1e6 m against the plane over 2 s: max |d theta| {dth:.2e} rad, max rel. d spin {dsp:.2e}; theta {:.4} -> {:.4} rad",
        a.samples[0].theta,
        a.samples.last().unwrap().theta
    );
    assert!(dth < 1e-6 && dsp < 1e-6);
}

/// The paper's force in the tube (docs/physics.md#tube-dynamics): `H` at
/// the contact point in the contact's frame. A rolling contact's motion
/// does not contain `H` (the constraint force solves `K F = b`, which `H`
/// does not enter; the friction takes it up), so a uniform ball rolling at
/// the bottom of the tube under a constant `H` (its axis tilted 0.3 rad
/// towards the tube's axis, so the frame's `x̂` is continuous) keeps the
/// pendulum's closed form `ω² = 5 g/(7 (b − R))` to 1e-6, rolls
/// throughout, and the force does no work (`|W_a| ≤ 1e-9 m g R`).
#[test]
fn rolling_ball_with_the_force_on_keeps_its_period() {
    let (r, b) = (0.01, 0.05);
    let w0 = (5.0 * G / (7.0 * (b - r))).sqrt();
    let t0 = 2.0 * std::f64::consts::PI / w0;
    let mut sc = ball_in_tube(r, b, 1e-3, 1.0, FrictionLaw::Coulomb);
    sc.initial.theta = 0.3;
    let mg = sc.top.mass * G;
    sc.forcing = tippetop::Forcing::constant(0.05 * mg, 0.03 * mg);
    sc.solver.t_end = 6.25 * t0;
    sc.solver.samples = 20001;
    let (p, n, gap, rolled) = measure(&sc);
    let err = p / t0 - 1.0;
    let tr = tippetop::simulate(&sc).unwrap();
    let wa = tr
        .samples
        .iter()
        .map(|s| s.work_applied.abs())
        .fold(0.0, f64::max);
    let hx = tr.samples[0].hx;
    println!(
        "rolling ball with H: period {p:.9e} s over {n} half periods, closed form {t0:.9e} s, rel. error {err:.2e}; max |W_a| {wa:.1e} J; H_x {hx:.3e} N"
    );
    assert!(
        (hx - 0.05 * mg).abs() < 1e-12 * mg,
        "the force is not on: {hx:e}"
    );
    assert!(rolled, "the ball did not roll throughout");
    assert!(err.abs() < 1e-6, "rolling period off by {err:e}");
    assert!(gap < 1e-8, "the wall's constraint drifted by {gap:e} R");
    assert!(
        wa <= 1e-9 * mg * r,
        "the force did work at a rolling contact: {wa:e} J"
    );
}

/// Energy balance with the force on: `E(t) − E(0) = W_f + W_a` for the
/// spinning eccentric top in the tube under a force window of 0.2 m g in
/// each component for the first second (switched off inside the run), to
/// 1e-7 E₀ at every sample, with the gap held; the force's work is not
/// negligible (`|W_a| > 1e-4 E₀`) and the top both slides and rolls.
#[test]
fn energy_balance_with_the_force_in_the_tube() {
    let mut sc = top_in_tube(0.05);
    let mg = sc.top.mass * G;
    sc.forcing = tippetop::Forcing {
        windows: vec![tippetop::ForceWindow {
            hx: 0.2 * mg,
            hy: 0.2 * mg,
            hz: 0.0,
            start: 0.0,
            stop: 1.0,
        }],
    };
    sc.solver.t_end = 2.0;
    sc.solver.samples = 2001;
    let (tr, worst_gap, _, slid, rolled) = watched(&sc);
    let e0 = tr.samples[0].energy;
    let worst = worst_balance(&tr);
    let last = tr.samples.last().unwrap();
    println!(
        "top in the tube with H: |E - E0 - W_f - W_a|/E0 <= {worst:.2e}; W_f {:.3e}, W_a {:.3e} of E0; worst |gap| {worst_gap:.1e} R; slid {slid}, rolled {rolled}",
        last.work_friction / e0,
        last.work_applied / e0
    );
    assert!(
        last.work_applied.abs() > 1e-4 * e0.abs(),
        "the force did no work"
    );
    assert!(worst < 1e-7, "energy balance off by {worst:e} E0");
    assert!(
        worst_gap < 1e-9,
        "the wall's constraint drifted by {worst_gap:e} R"
    );
    assert!(slid && rolled);
}

/// The plane recovered as `b → ∞` with the paper's force on: the nano
/// preset (rigid model, bilateral, H = (0.1, 0.1) zN) on the plane and in a
/// tube of radius 1 m (the wall's tilt over the ~1e-9 m the contact
/// travels is ~1e-9 rad) give the same θ(t), spin and W_a over 10 µs, in
/// which the top lies down (θ passes π/2): θ within 1e-6 rad.
#[test]
fn wide_tube_is_the_plane_with_the_paper_force() {
    let mut plane = Scenario::nano();
    plane.solver.model = ModelKind::Rigid;
    plane.solver.t_end = 1e-5;
    plane.solver.samples = 201;
    let (a, b) = plane_and_tube(&plane, 1.0);
    let (mut dth, mut dsp, mut dwa) = (0.0f64, 0.0f64, 0.0f64);
    let wa_scale = a
        .samples
        .iter()
        .map(|s| s.work_applied.abs())
        .fold(0.0, f64::max);
    for (p, q) in a.samples.iter().zip(&b.samples) {
        dth = dth.max((p.theta - q.theta).abs());
        dsp = dsp.max((p.spin - q.spin).abs() / p.spin.abs().max(1.0));
        dwa = dwa.max((p.work_applied - q.work_applied).abs() / wa_scale);
    }
    let th_max = a.samples.iter().map(|s| s.theta).fold(0.0, f64::max);
    println!(
        "nano, b = 1 m against the plane over 10 us: max |d theta| {dth:.2e} rad, max rel. d spin {dsp:.2e}, d W_a {dwa:.2e} of max |W_a| = {wa_scale:.3e} J; theta_max {th_max:.3} rad"
    );
    assert!(
        th_max > std::f64::consts::FRAC_PI_2,
        "the top did not lie down"
    );
    assert!(wa_scale > 0.0);
    assert!(dth < 1e-6 && dsp < 1e-6 && dwa < 1e-6);
}

/// Adhesion in the tube (`[adhesion]` with shape = "tube",
/// docs/physics.md#tube-dynamics): the load `F_a` along `−n` at the contact
/// in contact. A frictionless uniform ball released at rest at `φ₀` in the
/// tube is a pendulum whatever the load (it acts along the contact's normal
/// through the centre): its speed is `v² = 2 g (b − R)(cos φ − cos φ₀)`, so
/// the wall's reaction is `N = F_a + m g (3 cos φ − 2 cos φ₀)`, `φ` the
/// centre's angle about the axis (`sin φ = y/(b − R)`). Checked at every
/// sample to 1e-9 of `F_a` (`F_a = 10 m g`), with `E` constant (the load does
/// no work on a fixed wall) and the sliding period `2π/√(g/(b − R))` as
/// without adhesion (to 1e-6 at φ₀ = 1e-3).
#[test]
fn sliding_ball_with_adhesion_has_the_closed_form_reaction() {
    let (r, b, phi0) = (0.01, 0.05, 1e-3);
    let mut sc = ball_in_tube(r, b, phi0, 0.0, FrictionLaw::CoulombSliding);
    let mg = sc.top.mass * G;
    sc.set_adhesion(tippetop::Adhesion {
        force: 10.0 * mg,
        energy: 1e-3,
    });
    let t0 = 2.0 * std::f64::consts::PI / (G / (b - r)).sqrt();
    sc.solver.t_end = 6.25 * t0;
    sc.solver.samples = 20001;
    let (p, _, gap, _) = measure(&sc);
    let tr = tippetop::simulate(&sc).unwrap();
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let (mut worst_n, mut worst_e) = (0.0f64, 0.0f64);
    let e0 = tr.samples[0].energy;
    for s in &tr.samples {
        let phi = (s.y / (b - r)).asin();
        let n = 10.0 * mg + mg * (3.0 * phi.cos() - 2.0 * phi0.cos());
        worst_n = worst_n.max((s.normal - n).abs() / (10.0 * mg));
        worst_e = worst_e.max((s.energy - e0).abs() / e0.abs().max(mg * r * phi0 * phi0));
    }
    let err = p / t0 - 1.0;
    println!(
        "sliding ball with F_a = 10 m g: |N - closed form| <= {worst_n:.2e} F_a, |E - E0| <= {worst_e:.2e}, period rel. error {err:.2e}, worst |gap| {gap:.1e} R"
    );
    assert!(worst_n < 1e-9, "reaction off by {worst_n:e} F_a");
    assert!(worst_e < 1e-9, "energy moved by {worst_e:e}");
    assert!(err.abs() < 1e-6, "sliding period off by {err:e}");
}

/// Energy balance with adhesion and the force in the tube: the spinning
/// eccentric top of [`energy_balance_with_the_force_in_the_tube`] with a
/// load `F_a = 2 m g` keeps `E − E0 = W_f + W_a` to 1e-7 E₀ (in contact the
/// adhesion's potential is constant: no term in E), its reaction above
/// `F_a` less what gravity and the motion take (`N ≥ F_a − 3 m g`), and its
/// friction's work differs from the run without adhesion (friction sees
/// `N`).
#[test]
fn energy_balance_with_adhesion_in_the_tube() {
    let mut sc = top_in_tube(0.05);
    let mg = sc.top.mass * G;
    sc.forcing = tippetop::Forcing::constant(0.2 * mg, 0.2 * mg);
    sc.solver.t_end = 1.0;
    sc.solver.samples = 1001;
    let without = tippetop::simulate(&sc).unwrap();
    sc.set_adhesion(tippetop::Adhesion {
        force: 2.0 * mg,
        energy: 1.0,
    });
    let tr = tippetop::simulate(&sc).unwrap();
    assert!(tr.error.is_none() && without.error.is_none());
    let worst = worst_balance(&tr);
    let n_min = tr
        .samples
        .iter()
        .map(|s| s.normal)
        .fold(f64::INFINITY, f64::min);
    let (wf, wf0) = (
        tr.samples.last().unwrap().work_friction,
        without.samples.last().unwrap().work_friction,
    );
    println!(
        "top in the tube with H and F_a = 2 m g: |E - E0 - W_f - W_a|/E0 <= {worst:.2e}; N_min {:.3} m g; W_f {wf:.4e} J (without adhesion {wf0:.4e} J)",
        n_min / mg
    );
    assert!(worst < 1e-7, "energy balance off by {worst:e} E0");
    assert!(n_min > 2.0 * mg - 3.0 * mg, "N_min {n_min:e}");
    assert!(
        (wf - wf0).abs() > 1e-3 * wf0.abs(),
        "adhesion changed nothing"
    );
}

/// A Langevin (or Brownian) run's keys for the classical preset at
/// `kT ≈ m g R` (docs/physics.md#tube-langevin).
fn hot_sets(method: &str) -> Vec<&'static str> {
    vec![
        if method == "brownian" {
            "solver.method=\"brownian\""
        } else {
            "solver.method=\"langevin\""
        },
        "solver.dt=1e-5",
        "surface.friction=0",
        "thermal.temperature=1e17",
        "thermal.damping_translational=20",
        "thermal.damping_rotational=20",
        "thermal.seed=1",
    ]
}

/// The keys: the tube read from `--set`s, and each refusal one error naming
/// its key (the CLI's exit 2 is tippetop-cli's tests/hardening_cli.rs).
/// Langevin with `[thermal]` is taken; Brownian is refused naming
/// `solver.method` (its drift correction is the plane's).
#[test]
fn tube_keys_and_refusals() {
    let load = |preset: &str, sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        Scenario::load(Some(preset), None, &sets)
    };
    let rigid = "solver.model=\"rigid\"";
    let tube = "surface.shape=\"tube\"";
    let sc = load(
        "classical",
        &[
            rigid,
            tube,
            "surface.tube_radius=0.05",
            "surface.tube_angle=0.1",
        ],
    )
    .unwrap();
    assert_eq!(
        sc.surface.shape,
        Shape::Tube {
            radius: 0.05,
            angle: 0.1
        }
    );
    // The scenario written back reads back the same.
    assert_eq!(Scenario::from_toml_str(&sc.to_toml_string()).unwrap(), sc);
    let hot = load(
        "classical",
        &[
            &[rigid, tube, "surface.tube_radius=0.05"][..],
            &hot_sets("langevin"),
        ]
        .concat(),
    );
    assert!(hot.is_ok(), "{hot:?}");
    let brownian = load(
        "classical",
        &[
            &[rigid, tube, "surface.tube_radius=0.05"][..],
            &hot_sets("brownian"),
        ]
        .concat(),
    )
    .expect_err("brownian in the tube accepted")
    .to_string();
    assert!(
        brownian.contains("tube") && brownian.contains("plane only"),
        "{brownian}"
    );
    println!("{brownian}");
    for (preset, sets, key) in [
        ("classical", vec![rigid, tube], "surface.tube_radius"),
        (
            "classical",
            vec![rigid, tube, "surface.tube_radius=0.015"],
            "surface.tube_radius",
        ),
        (
            "classical",
            vec![rigid, tube, "surface.tube_radius=nan"],
            "surface.tube_radius",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                "surface.tube_radius=0.05",
                "surface.tube_angle=1.6",
            ],
            "surface.tube_angle",
        ),
        (
            "classical",
            vec!["surface.tube_radius=0.05"],
            "surface.tube_radius",
        ),
        (
            "classical",
            vec![tube, "solver.model=\"reduced\"", "surface.tube_radius=0.05"],
            "surface.shape",
        ),
        (
            "classical",
            vec![tube, "solver.model=\"vector\"", "surface.tube_radius=0.05"],
            "surface.shape",
        ),
        (
            "nano",
            vec![
                rigid,
                tube,
                "surface.tube_radius=1e-9",
                "force.1.kind=\"tip\"",
                "force.1.point=[0.0, 0.0, 0.0]",
                "force.1.force=[0.0, 0.0, 1e-25]",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                "surface.tube_radius=0.05",
                "well.0.theta=1.0",
                "well.0.depth=1e-3",
                "well.0.width=0.5",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                "surface.tube_radius=0.05",
                "top.stem_radius=0.0025",
                "top.stem_distance=0.0185",
                "surface.contact=\"unilateral\"",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![
                rigid,
                tube,
                "surface.tube_radius=0.05",
                "surface.friction_law=\"contensou\"",
                "surface.contact_radius=1e-4",
            ],
            "surface.shape",
        ),
        (
            "classical",
            vec![rigid, "surface.shape=\"cone\""],
            "surface.shape",
        ),
        (
            "classical",
            [
                &[rigid, tube, "surface.tube_radius=0.05"][..],
                &hot_sets("brownian"),
            ]
            .concat(),
            "solver.method",
        ),
    ] {
        let err = load(preset, &sets).expect_err(&format!("{sets:?} accepted"));
        let msg = err.to_string();
        assert!(
            msg.starts_with(&format!("{key}: ")) && !msg.contains('\n'),
            "{sets:?}: {msg}"
        );
    }
}

// ---------------------------------------------------------------------------
// Langevin dynamics in the tube (docs/physics.md#tube-langevin).

/// A frictionless uniform ball (classical preset's size and mass) on the
/// wall of a tube with `b − R = R/2`, hot: `κ = m g (b − R)/kT`,
/// `γ_t = γ_r = γ` and the contact damping `c = m γ` (it couples the slip
/// `v + w × r` to the rotation through the contact's frame), the step at
/// the step rule's limit, `steps` steps, started at rest at 0.2 rad.
fn hot_ball(kappa: f64, steps: usize) -> Scenario {
    let (r, b) = (0.01, 0.015);
    let mut sc = ball_in_tube(r, b, 0.2, 0.0, FrictionLaw::Coulomb);
    let m = sc.top.mass;
    let kt = m * G * (b - r) / kappa;
    sc.thermal.temperature = kt / tippetop::input::thermal::BOLTZMANN;
    // The pendulum's rate ω₀ = sqrt(g/(b − R)); the bath's at ω₀.
    let w0 = (G / (b - r)).sqrt();
    sc.thermal.damping_translational = w0;
    sc.thermal.damping_rotational = w0;
    sc.thermal.damping_contact = m * w0;
    sc.thermal.seed = Some(20261128);
    sc.solver.method = tippetop::Method::Langevin;
    let fastest = tippetop::input::scenario::langevin::step_rates(&sc)
        .iter()
        .map(|r| r.0)
        .fold(0.0, f64::max);
    let dt = 0.02 / fastest;
    sc.solver.dt = Some(dt);
    sc.solver.t_end = dt * steps as f64;
    sc.solver.samples = 11;
    sc
}

/// Mean and standard error from 40 batch means.
fn batch_mean_se(values: &[f64]) -> (f64, f64) {
    let nb = 40;
    let per = values.len() / nb;
    let means: Vec<f64> = (0..nb)
        .map(|b| values[b * per..(b + 1) * per].iter().sum::<f64>() / per as f64)
        .collect();
    let m = means.iter().sum::<f64>() / nb as f64;
    let var = means.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / (nb - 1) as f64;
    (m, (var / nb as f64).sqrt())
}

/// The modified Bessel function `I_n(x)` from its power series
/// `Σ (x/2)^{2j+n}/(j! (j+n)!)` (independent of any code under test).
fn bessel_i(n: u32, x: f64) -> f64 {
    let mut term = (0.5 * x).powi(n as i32) / (1..=n).map(f64::from).product::<f64>();
    let mut sum = term;
    for j in 1..200 {
        term *= 0.25 * x * x / (f64::from(j) * f64::from(j + n));
        sum += term;
        if term < 1e-17 * sum {
            break;
        }
    }
    sum
}

/// A hot ball's run in the tube, observed at every step end: per step the
/// contact's angle's cosine `cos φ = n_Z`, the kinetic energies of the two
/// tangent velocity components (along the axis `e₁` and around it `e₂`)
/// and the rotational one `½ w·I w`, each over kT (after 5 % burn-in); and
/// the worst |gap| [R].
fn hot_ball_run(sc: &Scenario) -> ([Vec<f64>; 4], f64) {
    use tippetop::model::rigid::{OMEGA, VEL};
    let mut cols: [Vec<f64>; 4] = Default::default();
    let mut worst_gap: f64 = 0.0;
    let n_burn = (sc.solver.t_end / sc.solver.dt.unwrap() / 20.0) as usize;
    let mut step = 0usize;
    let tr = tippetop::simulate::simulate_rigid_observed(sc, &mut |m, _, y: &[f64; DIM]| {
        worst_gap = worst_gap.max(m.gap(y).abs());
        step += 1;
        if step <= n_burn {
            return;
        }
        let kt = sc.thermal.kt() / m.scales.energy();
        let at = m.tube_at(y).expect("in the tube");
        let v = [y[VEL], y[VEL + 1], y[VEL + 2]];
        let w = [y[OMEGA], y[OMEGA + 1], y[OMEGA + 2]];
        let ve2 = v[1] * at.e2[1] + v[2] * at.e2[2];
        // Scaled: m = R = 1, A = C = 2/5.
        let rot = 0.5 * 0.4 * (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        cols[0].push(at.n[2]);
        cols[1].push(0.5 * v[0] * v[0] / kt);
        cols[2].push(0.5 * ve2 * ve2 / kt);
        cols[3].push(rot / kt);
    });
    assert!(tr.error.is_none(), "{:?}", tr.error);
    (cols, worst_gap)
}

/// `|mean − want| < 4 SE` with the SE below `max_se` (the test's power).
fn within(what: &str, (mean, se): (f64, f64), want: f64, max_se: f64) {
    println!(
        "{what}: {mean:.5} ± {se:.5} (want {want:.5}, {:+.2} SE)",
        (mean - want) / se
    );
    assert!(
        se < max_se,
        "{what}: SE {se:e} too large for a test with power"
    );
    assert!(
        (mean - want).abs() < 4.0 * se,
        "{what}: {mean} ± {se}, want {want}"
    );
}

/// The Boltzmann distribution on the tube's wall: a frictionless ball at
/// `κ = m g (b − R)/kT = 2` with the contact damping on has `p(φ) ∝
/// exp(κ cos φ)` on the circle (its configuration metric is flat: the mass
/// matrix of a ball does not depend on where it sits), so `⟨cos φ⟩ =
/// I₁(κ)/I₀(κ)` = 0.6978, and each velocity degree of freedom `kT/2`:
/// `⟨½ m v_{e₁}²⟩ = ⟨½ m v_{e₂}²⟩ = kT/2`, `⟨½ w·I w⟩ = 3 kT/2` (4 SE, 40
/// batch means of 2 000 000 steps, SE ≤ 1.5 % of the values). A plane's step
/// in the lab frame (no rotation to the contact's) gives the circumferential
/// mode the noise of its horizontal part only. The gap stays at 0 (within
/// 1e-12 R: the O step puts the centre back on the wall). The longer twin is `boltzmann_on_the_tube_wall_long`.
#[test]
fn boltzmann_on_the_tube_wall() {
    boltzmann_on_the_tube_wall_steps(2_000_000, 0.015);
}

/// [`boltzmann_on_the_tube_wall`] over 20 000 000 steps (SE ≤ 0.5 %):
/// `cargo test --release -p tippetop --test tube -- --ignored boltzmann_on_the_tube_wall_long`.
#[test]
#[ignore]
fn boltzmann_on_the_tube_wall_long() {
    boltzmann_on_the_tube_wall_steps(20_000_000, 0.005);
}

fn boltzmann_on_the_tube_wall_steps(steps: usize, max_se: f64) {
    let kappa = 2.0;
    let sc = hot_ball(kappa, steps);
    let (cols, gap) = hot_ball_run(&sc);
    let want = bessel_i(1, kappa) / bessel_i(0, kappa);
    within("<cos phi>", batch_mean_se(&cols[0]), want, max_se * want);
    within("<v_e1^2/2>/kT", batch_mean_se(&cols[1]), 0.5, max_se * 0.5);
    within("<v_e2^2/2>/kT", batch_mean_se(&cols[2]), 0.5, max_se * 0.5);
    within("<w.I w/2>/kT", batch_mean_se(&cols[3]), 1.5, max_se * 1.5);
    println!("worst |gap| {gap:.2e} R");
    assert!(gap < 1e-12, "the wall's constraint drifted by {gap:e} R");
}

/// A hot eccentric top in the tube (the classical preset frictionless,
/// `kT = m g R`, the bath at 20 s⁻¹ with the contact damping, 40 000 steps
/// at the step rule's limit, started spinning at 0.2 rad around the axis):
/// `E − E0 = W_f` at every sample, `W_f` including the bath's work (the
/// kinetic energy's change in each O step), to 1e-7 kT; the bath's work is
/// itself of order kT (so a `W_f` without it, or an O step that moved the
/// energy without booking it, fails by ~kT).
#[test]
fn hot_energy_balance_in_the_tube() {
    let mut sc = top_in_tube(0.05);
    let kt = sc.top.mass * G * sc.top.radius;
    hot(&mut sc, kt, 20.0, 40_000);
    sc.solver.samples = 401;
    let (tr, gap, _, _, _) = watched(&sc);
    let e0 = tr.samples[0].energy;
    let worst = tr
        .samples
        .iter()
        .map(|s| (s.energy - e0 - s.work_friction - s.work_applied).abs())
        .fold(0.0, f64::max);
    let wf = tr
        .samples
        .iter()
        .map(|s| s.work_friction.abs())
        .fold(0.0, f64::max);
    println!(
        "hot top in the tube: |E - E0 - W_f| <= {:.2e} kT; max |W_f| {:.3} kT; worst |gap| {gap:.2e} R",
        worst / kt,
        wf / kt
    );
    assert!(wf > 0.1 * kt, "the bath did no work: {wf:e}");
    assert!(
        worst < 1e-7 * kt,
        "energy balance off by {:e} kT",
        worst / kt
    );
}

/// `sc` made a Langevin run at `kT` [J] with `γ_t = γ_r = gamma` [1/s] and
/// the contact damping `c = m γ`, frictionless, seed fixed, `steps` steps at
/// the step rule's limit.
fn hot(sc: &mut Scenario, kt: f64, gamma: f64, steps: usize) {
    sc.surface.friction = 0.0;
    sc.thermal.temperature = kt / tippetop::input::thermal::BOLTZMANN;
    sc.thermal.damping_translational = gamma;
    sc.thermal.damping_rotational = gamma;
    sc.thermal.damping_contact = sc.top.mass * gamma;
    sc.thermal.seed = Some(7);
    sc.solver.method = tippetop::Method::Langevin;
    let fastest = tippetop::input::scenario::langevin::step_rates(sc)
        .iter()
        .map(|r| r.0)
        .fold(0.0, f64::max);
    let dt = 0.02 / fastest;
    sc.solver.dt = Some(dt);
    sc.solver.t_end = dt * steps as f64;
}

/// `b → ∞`: the same hot top (seed, steps) on the plane and in a tube of
/// radius 1e6 m (at the lowest line, where the contact's frame is the lab's
/// to 1e-8 over the few cm the top moves) follow the same path: θ and the
/// spin within 1e-6 over 5 000 steps (the path is chaotic: the rounding of
/// the frame's rotation grows, but not to 1e-6 in this window). Without the
/// contact damping: with it the O step's noise goes through the
/// eigenvectors of a 5×5 problem, whose signs (and, where eigenvalues
/// coincide, directions) are not continuous in the axis, so two runs an ulp
/// apart draw the same noise in distribution but not path by path.
#[test]
fn hot_wide_tube_is_the_plane() {
    let mut plane = Scenario::classical();
    plane.solver.model = ModelKind::Rigid;
    let kt = plane.top.mass * G * plane.top.radius;
    hot(&mut plane, kt, 20.0, 5_000);
    plane.thermal.damping_contact = 0.0;
    plane.solver.samples = 101;
    let (a, b) = plane_and_tube(&plane, 1e6);
    let (mut dth, mut dsp, mut moved) = (0.0f64, 0.0f64, 0.0f64);
    for (p, q) in a.samples.iter().zip(&b.samples) {
        dth = dth.max((p.theta - q.theta).abs());
        dsp = dsp.max((p.spin - q.spin).abs() / p.spin.abs().max(1.0));
        moved = moved.max((p.theta - a.samples[0].theta).abs());
    }
    println!(
        "hot, b = 1e6 m against the plane over 5 000 steps: max |d theta| {dth:.2e} rad, max rel. d spin {dsp:.2e}; theta moved up to {moved:.3} rad"
    );
    assert!(moved > 0.01, "nothing happened: {moved}");
    assert!(dth < 1e-6 && dsp < 1e-6);
}
