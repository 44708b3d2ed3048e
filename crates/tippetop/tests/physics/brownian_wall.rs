//! The rigid model's Brownian mode above a wall (`surface.contact =
//! "unilateral"`, docs/physics.md#brownian-wall): the overdamped free body with the
//! plane as a reflecting wall.
//!
//! - the closed form in gravity (no adhesion, no wells): the density
//!   `∝ e^{−m g z_O/kT}` on `z_O >= R − a cos θ`, so `p(θ) ∝ sin θ e^{b cos θ}`
//!   (`b = m g a/kT`) and the gap exponential with mean `kT/(m g)`;
//! - with adhesion: the same θ marginal (the gap and the orientation
//!   separate), the gap's density `∝ e^{−m g z/kT + (E_b/kT) e^{−F_a z/E_b}}`
//!   (quadrature);
//! - the free body far from the wall: MSD `6 D τ`, `⟨k(0)·k(τ)⟩ =
//!   e^{−2 D_r τ}`;
//! - the records (lift-off above the level ℓ, touchdown at a wall hit);
//! - the paper's contact on the plane is the bilateral run bit for bit.
//!
//! Statistics as in `thermal.rs`: one long run with a fixed seed, batch
//! means (40 batches) for the standard error, `|mean − exact| < 5 SE` with
//! the SE bounded so that the test has power. The wrong walls (clipping,
//! the projection, a vertical mirror) are measured against the same closed
//! form in the unit test `model::rigid::brownian::tests` (10 to 49 SE off).

use super::thermal::{density_mean, mean_se};
use tippetop::input::thermal::{BOLTZMANN, MAX_BROWNIAN_STEP_RATE};
use tippetop::{
    Adhesion, ContactMode, ForceWindow, Forcing, Method, ModelKind, Sample, Scenario, Trajectory,
    simulate,
};

const T: f64 = 300.0;

fn kt() -> f64 {
    BOLTZMANN * T
}

/// The eccentric nano top (`a = 0.6 R`, `A = C = m a²/2`) at 300 K,
/// `γ_t = γ_r = 1e11 s⁻¹`, gravity with `m g R/kT = beta_mgr`, unilateral
/// contact, the rigid model's Brownian method; the step `dt` and length
/// are set by [`at_rule`].
fn wall_top(beta_mgr: f64) -> Scenario {
    let mut sc = Scenario::nano();
    let r = sc.top.radius;
    sc.top.offset = 0.6 * r;
    let ma2 = sc.top.mass * sc.top.offset * sc.top.offset;
    sc.top.inertia_transverse = ma2 / 2.0;
    sc.top.inertia_axial = ma2 / 2.0;
    sc.surface.friction = 0.0;
    sc.surface.contact = ContactMode::Unilateral;
    sc.surface.gravity = beta_mgr * kt() / (sc.top.mass * r);
    sc.forcing = Forcing { windows: vec![] };
    sc.initial.theta = 1.0;
    sc.initial.spin = 0.0;
    sc.solver.model = ModelKind::Rigid;
    sc.solver.method = Method::Brownian;
    sc.thermal.temperature = T;
    sc.thermal.damping_translational = 1e11;
    sc.thermal.damping_rotational = 1e11;
    sc.thermal.seed = Some(20261124);
    sc
}

/// The step at the Brownian rule's limit (docs/physics.md#langevin, §brownian-wall:
/// the fastest of `kT/(γ_r A)`, `kT/(γ_r C)`, the tilt's rate under the
/// load, the gap's diffusion over the wall's thermal length and the
/// adhesion's curvature), `steps` steps, a row every `every`.
fn at_rule(mut sc: Scenario, steps: usize, every: usize) -> Scenario {
    let (m, g, r, a) = (
        sc.top.mass,
        sc.surface.gravity,
        sc.top.radius,
        sc.top.offset,
    );
    let (ia, ic) = (sc.top.inertia_transverse, sc.top.inertia_axial);
    let (gt, gr) = (
        sc.thermal.damping_translational,
        sc.thermal.damping_rotational,
    );
    let hz = sc
        .forcing
        .windows
        .iter()
        .map(|w| w.hz.abs())
        .fold(0.0, f64::max);
    let (fa, eb) = (sc.adhesion().force, sc.adhesion().energy);
    let load = m * g + fa + hz;
    let mut rates = vec![
        kt() / (gr * ia),
        kt() / (gr * ic),
        load * (r + a) / (gr * ia),
        load * load * (1.0 / (m * gt) + a * a / (gr * ia)) / kt(),
    ];
    if fa > 0.0 {
        rates.push(fa * fa / (eb * m * gt));
    }
    for w in &sc.wells() {
        rates.push(w.depth / (w.width * w.width * gr * ia));
    }
    let rate = rates.into_iter().fold(0.0, f64::max);
    let dt = MAX_BROWNIAN_STEP_RATE / rate;
    sc.solver.dt = Some(dt);
    sc.solver.t_end = dt * steps as f64;
    sc.solver.samples = steps / every + 1;
    sc
}

fn check(what: &str, (mean, se): (f64, f64), want: f64, max_se: f64) {
    eprintln!(
        "{what}: {mean:.6} ± {se:.6} (want {want:.6}, {:+.2} SE)",
        (mean - want) / se
    );
    assert!(se < max_se, "{what}: standard error {se:e} too large");
    assert!(
        (mean - want).abs() < 5.0 * se,
        "{what}: {mean} ± {se}, want {want}"
    );
}

/// The gap `z_O + a cos θ − R` of a row, in units of `len`.
fn gap(sc: &Scenario, s: &Sample, len: f64) -> f64 {
    (s.z + sc.top.offset * s.theta.cos() - sc.top.radius) / len
}

/// Rows after 5 % (the run starts on the wall, out of equilibrium).
fn settled(tr: &Trajectory) -> &[Sample] {
    &tr.samples[tr.samples.len() / 20..]
}

/// `∫₀^top f p dz` (composite Simpson, 40 000 intervals).
fn integral(top: f64, p: impl Fn(f64) -> f64) -> f64 {
    let n = 40_000;
    let h = top / n as f64;
    let mut sum = 0.0;
    for i in 0..=n {
        let w = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        sum += w * p(i as f64 * h);
    }
    sum * h / 3.0
}

/// `∫ f p dz / ∫ p dz` over `[0, 40]` (the densities below are
/// `< e^{−50}` beyond).
fn gap_mean(p: impl Fn(f64) -> f64, f: impl Fn(f64) -> f64) -> f64 {
    integral(40.0, |z| p(z) * f(z)) / integral(40.0, p)
}

/// The records alternate lift-off, touchdown, lift-off, ... from the start
/// on the wall; returns their numbers.
fn records(tr: &Trajectory) -> (usize, usize) {
    let kinds: Vec<&str> = tr
        .events
        .iter()
        .map(|e| e.kind.as_str())
        .filter(|k| *k == "lift_off" || *k == "touchdown")
        .collect();
    for (i, k) in kinds.iter().enumerate() {
        let want = if i % 2 == 0 { "lift_off" } else { "touchdown" };
        assert_eq!(*k, want, "record {i} of {kinds:?}");
    }
    let lifts = kinds.iter().filter(|k| **k == "lift_off").count();
    (lifts, kinds.len() - lifts)
}

/// Test 1 of §brownian-wall: `m g R/kT = 1.5`, `a = 0.6 R` (`b = m g a/kT = 0.9`):
/// `⟨cos θ⟩ = coth b − 1/b` = 0.284956, `⟨cos²θ⟩ = 1 − 2⟨cos θ⟩/b`
/// = 0.366764 (uniform: 0 and 1/3; the on-plane top's would differ), the
/// gap's mean `kT/(m g)` and `P(gap < 0.05 kT/(m g)) = 1 − e^{−0.05}`
/// (an atom on the wall, as a projection leaves, raises it: unit test).
/// Euler–Maruyama's bias is `O(dt · rate) = O(0.002)`, below the SE.
/// 16 000 000 steps (about 12 s).
#[test]
fn gibbs_density_above_the_wall() {
    let sc = at_rule(wall_top(1.5), 16_000_000, 50);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let rows = settled(&tr);
    let len = kt() / (sc.top.mass * sc.surface.gravity);
    let b = 0.9f64;
    let want_cos = 1.0 / b.tanh() - 1.0 / b;
    let gaps: Vec<f64> = rows.iter().map(|s| gap(&sc, s, len)).collect();
    assert!(
        gaps.iter().all(|&g| g >= -1e-9),
        "below the wall: {:e}",
        gaps.iter().copied().fold(f64::INFINITY, f64::min)
    );
    check(
        "wall <cos theta>",
        mean_se(&rows.iter().map(|s| s.theta.cos()).collect::<Vec<_>>()),
        want_cos,
        0.012,
    );
    check(
        "wall <cos^2 theta>",
        mean_se(
            &rows
                .iter()
                .map(|s| s.theta.cos().powi(2))
                .collect::<Vec<_>>(),
        ),
        1.0 - 2.0 * want_cos / b,
        0.005,
    );
    check("wall <gap> / (kT/mg)", mean_se(&gaps), 1.0, 0.04);
    let near: Vec<f64> = gaps
        .iter()
        .map(|&g| f64::from(u8::from(g < 0.05)))
        .collect();
    check(
        "wall P(gap < 0.05 kT/mg)",
        mean_se(&near),
        1.0 - (-0.05f64).exp(),
        0.0025,
    );
    // The wall's force (the N column: its impulse over each step): its
    // time average balances the weight (the centre's vertical balance over
    // the run: Σ λ = m g T + m γ_t (z_T − z_0) − the noise's sum, whose
    // relative size is sqrt(2 D T)/(g T/γ_t) = sqrt(2/N_r), N_r = T D/ℓ_T²
    // the run's length in relaxation times of the height), and the rows'
    // average (1 step in 50) agrees.
    let w = sc.top.mass * sc.surface.gravity;
    let ni = tr.summary.normal_intervals.expect("a stochastic run");
    let d = kt() / (sc.top.mass * sc.thermal.damping_translational);
    let n_r = sc.solver.t_end * d / (len * len);
    let bar = (2.0 / n_r).sqrt();
    eprintln!(
        "wall force: time average {:.5} of the weight (noise {bar:.4})",
        ni.mean / w
    );
    assert!((ni.mean / w - 1.0).abs() < 5.0 * bar, "{} vs {w}", ni.mean);
    check(
        "wall <N> (rows) / (m g)",
        mean_se(&rows.iter().map(|s| s.normal / w).collect::<Vec<_>>()),
        1.0,
        0.05,
    );
    // Records: the level is min(R, kT/(m g)) = kT/(m g) here; lift-offs
    // and touchdowns alternate, and many excursions happen.
    let (lifts, downs) = records(&tr);
    eprintln!(
        "records: {lifts} lift-offs, {downs} touchdowns; first lift-off {:?} s, off the wall {:.3} of the time",
        tr.summary.contact_lost_at, tr.summary.negative_normal_fraction
    );
    assert!(lifts > 100 && lifts - downs <= 1, "{lifts} {downs}");
    assert!(tr.summary.negative_normal_fraction > 0.0 && tr.summary.negative_normal_fraction < 1.0);
}

/// With adhesion (`F_a R/kT = 3`, `E_b/kT = 2`, range `E_b/F_a = 0.67 R`)
/// the θ marginal is unchanged (the potential is
/// `m g (gap + R − a cos θ) + U(gap)`: the gap and the orientation
/// separate) and the gap's density is
/// `∝ e^{−m g z/kT + (E_b/kT) e^{−F_a z/E_b}}`: mean 0.38439 R by
/// quadrature, against `kT/(m g)` = 0.667 R without adhesion (11 SE off),
/// `P(gap < 0.1 R)` 0.28120 against 0.139 (20 SE off); the wall's force
/// `⟨N⟩ = m g + F_a ⟨e^{−F_a gap/E_b}⟩`. 16 000 000 steps.
#[test]
fn adhesion_above_the_wall() {
    let mut sc = wall_top(1.5);
    let r = sc.top.radius;
    sc.set_adhesion(Adhesion {
        force: 3.0 * kt() / r,
        energy: 2.0 * kt(),
    });
    let sc = at_rule(sc, 16_000_000, 50);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let rows = settled(&tr);
    let b = 0.9f64;
    let want_cos = 1.0 / b.tanh() - 1.0 / b;
    check(
        "adhesive wall <cos theta>",
        mean_se(&rows.iter().map(|s| s.theta.cos()).collect::<Vec<_>>()),
        want_cos,
        // The step is smaller here (the wall's rate with F_a): a uniform
        // orientation (0) is still ~17 SE off.
        0.02,
    );
    let p = |z: f64| (-1.5 * z + 2.0 * (-1.5 * z).exp()).exp();
    let want = gap_mean(p, |z| z);
    assert!((want - 0.384394).abs() < 1e-5, "{want}");
    let gaps: Vec<f64> = rows.iter().map(|s| gap(&sc, s, r)).collect();
    check("adhesive wall <gap> / R", mean_se(&gaps), want, 0.03);
    // The wall's force balances the weight and the adhesion's mean pull:
    // `⟨N⟩ = m g + F_a ⟨e^{−F_a gap/E_b}⟩` (Gibbs, by quadrature; without
    // the adhesion's pull it would be m g).
    let unit = kt() / r;
    let want_n = 1.5 + 3.0 * gap_mean(p, |z| (-1.5 * z).exp());
    let ni = tr.summary.normal_intervals.expect("a stochastic run");
    check(
        "adhesive wall <N> (rows) / (kT/R)",
        mean_se(&rows.iter().map(|s| s.normal / unit).collect::<Vec<_>>()),
        want_n,
        0.2,
    );
    eprintln!(
        "adhesive wall force: time average {:.5} kT/R (want {want_n:.5})",
        ni.mean / unit
    );
    // Near the wall, where the adhesion is strongest: P(gap < 0.1 R).
    let want_near = integral(0.1, p) / integral(40.0, p);
    assert!((want_near - 0.281202).abs() < 1e-5, "{want_near}");
    check(
        "adhesive wall P(gap < 0.1 R)",
        mean_se(
            &gaps
                .iter()
                .map(|&g| f64::from(u8::from(g < 0.1)))
                .collect::<Vec<_>>(),
        ),
        want_near,
        0.01,
    );
    records(&tr);
}

/// A well above the wall (θ = 2, depth 2 kT, width 0.5; the closed form's
/// gravity): the orientation's density is `sin θ e^{b cos θ} e^{−U_w/kT}`
/// (the wells' torque in the drift), `⟨cos θ⟩` = −0.039155 by quadrature
/// (0.284956 without the well: 33 SE away). 16 000 000 steps.
#[test]
fn well_above_the_wall() {
    let mut sc = wall_top(1.5);
    sc.set_wells(&[tippetop::Well {
        theta: 2.0,
        depth: 2.0 * kt(),
        width: 0.5,
    }]);
    let sc = at_rule(sc, 16_000_000, 50);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let rows = settled(&tr);
    let want = density_mean(
        |th| {
            let u = -2.0 * (-0.5 * ((th - 2.0) / 0.5f64).powi(2)).exp();
            th.sin() * (0.9 * th.cos()).exp() * (-u).exp()
        },
        f64::cos,
    );
    assert!((want + 0.039155).abs() < 1e-5, "{want}");
    check(
        "well above the wall <cos theta>",
        mean_se(&rows.iter().map(|s| s.theta.cos()).collect::<Vec<_>>()),
        want,
        0.02,
    );
}

/// Test 2 of §brownian-wall: the free body far from the wall (g = 0): pulled up
/// 100 R by an upward force at the contact point (`h_z = −1.3 kT/R` for
/// the first 80 % of a rise time), then free: the centre's MSD is
/// `6 D τ` (`D = kT/(m γ_t)`) and the axis correlation `⟨k(0)·k(τ)⟩ =
/// e^{−2 D_r τ}` (`D_r = kT/(γ_r A)`) at `D_r τ` = 0.25 and 1. One
/// lift-off (gap above `ℓ = R`), no touchdown. 3 000 000 steps.
#[test]
fn free_body_far_from_the_wall() {
    let mut sc = wall_top(0.0);
    let (m, r) = (sc.top.mass, sc.top.radius);
    let gamma = sc.thermal.damping_translational;
    let pull = 1.3 * kt() / r;
    // Rise of 100 R at the drift pull/(m γ).
    let rise = 100.0 * r * m * gamma / pull;
    sc.forcing = Forcing {
        windows: vec![ForceWindow {
            hx: 0.0,
            hy: 0.0,
            hz: -pull,
            start: 0.0,
            stop: rise,
        }],
    };
    let sc = at_rule(sc, 3_000_000, 10);
    let tr = simulate(&sc).expect("valid");
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let rows: Vec<Sample> = tr.samples.iter().filter(|s| s.t > rise).copied().collect();
    assert!(rows.len() > 1_000, "{}", rows.len());
    let lowest = rows
        .iter()
        .map(|s| gap(&sc, s, r))
        .fold(f64::INFINITY, f64::min);
    assert!(lowest > 30.0, "came back near the wall: gap {lowest} R");
    let (lifts, downs) = records(&tr);
    assert_eq!((lifts, downs), (1, 0));
    let d = kt() / (m * gamma);
    let d_r = kt() / (sc.thermal.damping_rotational * sc.top.inertia_transverse);
    let axis = |s: &Sample| {
        let (w, x, y, z) = (s.qw, s.qx, s.qy, s.qz);
        [
            2.0 * (x * z + w * y),
            2.0 * (y * z - w * x),
            1.0 - 2.0 * (x * x + y * y),
        ]
    };
    let dt_row = rows[1].t - rows[0].t;
    for tau_dr in [0.25, 1.0] {
        let lag = (tau_dr / d_r / dt_row).round() as usize;
        let tau = lag as f64 * dt_row;
        let msd: Vec<f64> = rows
            .windows(lag + 1)
            .map(|w| {
                let (a, b) = (&w[0], &w[lag]);
                (b.x - a.x).powi(2) + (b.y - a.y).powi(2) + (b.z - a.z).powi(2)
            })
            .collect();
        let want = 6.0 * d * tau;
        let (mm, se) = mean_se(&msd);
        check(
            &format!("free MSD / (6 D tau) at D_r tau = {tau_dr}"),
            (mm / want, se / want),
            1.0,
            0.04,
        );
        let c: Vec<f64> = rows
            .windows(lag + 1)
            .map(|w| {
                let (a, b) = (axis(&w[0]), axis(&w[lag]));
                a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
            })
            .collect();
        check(
            &format!("free <k(0).k(tau)> at D_r tau = {tau_dr}"),
            mean_se(&c),
            (-2.0 * d_r * tau).exp(),
            0.03,
        );
    }
}

/// Test 3 of §brownian-wall: the paper's contact (which never flies) takes the
/// on-plane step as bilateral contact does: with μ = 0 the same path bit
/// for bit (nano-physical, 20 000 steps).
#[test]
fn paper_contact_is_the_bilateral_run() {
    let mut sc = Scenario::nano_physical();
    sc.solver.model = ModelKind::Rigid;
    sc.solver.method = Method::Brownian;
    sc.solver.dt = Some(1e-16);
    sc.solver.t_end = 2e-12;
    sc.solver.samples = 101;
    let b = simulate(&sc).expect("valid");
    let mut p = sc.clone();
    p.surface.contact = ContactMode::Paper;
    p.surface.law = tippetop::FrictionLaw::Viscous { eps: 1e-3 };
    let p = simulate(&p).expect("valid");
    assert!(b.error.is_none() && p.error.is_none());
    for (x, y) in b.samples.iter().zip(&p.samples) {
        assert_eq!(x.theta.to_bits(), y.theta.to_bits(), "at {}", x.t);
        assert_eq!(x.x.to_bits(), y.x.to_bits(), "at {}", x.t);
    }
    assert!((b.samples.last().unwrap().theta - 0.1).abs() > 1e-3);
}
