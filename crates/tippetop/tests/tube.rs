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

use tippetop::model::rigid::DIM;
use tippetop::state::ModelKind;
use tippetop::{FrictionLaw, Scenario, Top, contact::Shape};

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
    assert!(gap < 1e-8, "the wall's constraint drifted by {gap:e} R");
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
    assert!(gap < 1e-8, "the wall's constraint drifted by {gap:e} R");
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
    assert!(gap < 1e-8, "the wall's constraint drifted by {gap:e} R");
}
