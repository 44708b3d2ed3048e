// Included by tests/physics_reduced.rs and tests/physics_vector.rs, each with its own `MODEL`.
//
// Physics validation of the on-plane models: invariants, closed forms,
// convergence orders. Every tolerance is justified next to its assertion.

use common::nano_schedules;
use tippetop::{ContactMode, ForceWindow, Forcing, FrictionLaw, Method, Scenario, Trajectory};

/// `tippetop::simulate` with this test crate's model (`MODEL`).
fn simulate(sc: &Scenario) -> Result<Trajectory, tippetop::Error> {
    let mut sc = sc.clone();
    sc.solver.model = MODEL;
    tippetop::simulate(&sc)
}

/// Run `sc` with `MODEL`; panics if it fails.
fn run(sc: &Scenario) -> Trajectory {
    common::run_as(sc, MODEL)
}

fn classical_smooth(eps: f64) -> Scenario {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Regularized { eps };
    sc
}

/// Jellett's J is conserved for any force at P (docs/physics.md §7): to
/// 1e-10 of C max|ω| R with rtol 1e-10, on both presets, every schedule.
#[test]
fn jellett_conserved_nano_all_schedules() {
    for (name, forcing) in nano_schedules() {
        for law in [
            FrictionLaw::CoulombSliding,
            FrictionLaw::Regularized { eps: 1e-4 },
        ] {
            let mut sc = Scenario::nano();
            sc.forcing = forcing.clone();
            sc.surface.law = law;
            let tr = run(&sc);
            let d = tr.summary.jellett_max_rel_drift;
            assert!(d <= 1e-10, "{name} {law:?}: J drift {d:e}");
            // Sampled J agrees with the tracked one.
            let j0 = tr.samples[0].jellett;
            let wmax = tr.samples.iter().map(|s| s.spin.abs()).fold(0.0, f64::max);
            let scale = sc.top.inertia_axial * wmax * sc.top.radius;
            for s in &tr.samples {
                assert!((s.jellett - j0).abs() <= 1e-10 * scale, "{name}: sample J");
            }
        }
    }
}

#[test]
fn jellett_conserved_classical() {
    let tr = run(&classical_smooth(1e-2));
    assert!(
        tr.summary.jellett_max_rel_drift <= 1e-10,
        "J drift {:e}",
        tr.summary.jellett_max_rel_drift
    );
    // J0 = C ω0 (R cos θ0 − a) ≠ 0: the paper's "J is zero" does not hold.
    let top = tippetop::Top::classical();
    let expect = top.inertia_axial * 100.0 * (top.radius * 0.1f64.cos() - top.offset);
    assert!((tr.summary.jellett_initial - expect).abs() <= 1e-14 * expect.abs());
}

/// With μ = 0 and H = 0 nothing does work: E conserved to 1e-10 over 10 s.
#[test]
fn energy_conserved_frictionless_classical() {
    let mut sc = Scenario::classical();
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    let tr = run(&sc);
    let e0 = tr.summary.energy_initial;
    let emax = tr
        .samples
        .iter()
        .map(|s| s.energy.abs())
        .fold(0.0, f64::max);
    for s in &tr.samples {
        assert!(
            (s.energy - e0).abs() <= 1e-10 * emax,
            "t = {}: E - E0 = {:e}",
            s.t,
            s.energy - e0
        );
    }
}

/// With friction and forcing, E(t) − E(0) = W_f + W_a to 1e-8 of max|E|.
#[test]
fn energy_balance_with_friction_and_forcing() {
    let mut cases: Vec<Scenario> = vec![classical_smooth(1e-2)];
    for (_, forcing) in nano_schedules() {
        let mut sc = Scenario::nano();
        sc.surface.law = FrictionLaw::CoulombSliding;
        sc.forcing = forcing;
        cases.push(sc);
    }
    for sc in cases {
        let tr = run(&sc);
        let e0 = tr.summary.energy_initial;
        let emax = tr
            .samples
            .iter()
            .map(|s| s.energy.abs())
            .fold(0.0, f64::max);
        let mut worst: f64 = 0.0;
        for s in &tr.samples {
            let r = (s.energy - e0 - s.work_friction - s.work_applied).abs() / emax;
            worst = worst.max(r);
        }
        assert!(worst <= 1e-8, "energy balance residual {worst:e}");
        assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
        // Friction only ever removes energy.
        assert!(
            tr.samples
                .windows(2)
                .all(|w| w[1].work_friction <= w[0].work_friction + 1e-12 * emax)
        );
    }
}

/// Steady free precession of a sphere (a = 0, μ = 0, H = 0):
/// Ω0 = C ω0/(A cos θ0) makes θ̈ = 0; θ, Ω, ω stay constant to ~rtol.
#[test]
fn steady_free_precession_sphere() {
    let mut sc = Scenario::classical();
    sc.top.offset = 0.0;
    sc.top.inertia_axial = 0.8 * sc.top.inertia_transverse;
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = 0.5;
    sc.initial.spin = 100.0;
    sc.initial.precession =
        sc.top.inertia_axial * 100.0 / (sc.top.inertia_transverse * 0.5f64.cos());
    sc.solver.t_end = 1.0;
    let tr = run(&sc);
    for s in &tr.samples {
        assert!((s.theta - 0.5).abs() <= 1e-9, "theta drifted: {}", s.theta);
        assert!((s.precession - sc.initial.precession).abs() <= 1e-9 * sc.initial.precession);
        assert!((s.spin - 100.0).abs() <= 1e-9 * 100.0);
    }
}

/// Small nutation about a steady precession on a frictionless plane: the
/// period matches the Routhian linearisation (docs/physics.md §10), an
/// independent Lagrangian route.
#[test]
fn nutation_frequency_matches_routhian() {
    let top = tippetop::Top::classical();
    let (m, a, r, ia, ic, g) = (
        top.mass,
        top.offset,
        top.radius,
        top.inertia_transverse,
        top.inertia_axial,
        9.8,
    );
    let th0: f64 = 0.6;
    let w = 150.0;
    // Slow steady precession: A c Ω² − C ω Ω − m g a = 0 (θ̈ = 0, N = m g).
    let c0 = th0.cos();
    let disc = (ic * w).powi(2) + 4.0 * ia * c0 * m * g * a;
    let om = (ic * w - disc.sqrt()) / (2.0 * ia * c0);
    let lz = ia * om * th0.sin().powi(2) + ic * w * c0;
    let v = |th: f64| {
        let (s, c) = th.sin_cos();
        (lz - ic * w * c).powi(2) / (2.0 * ia * s * s) + m * g * (r - a * c)
    };
    let d = 1e-4;
    let vpp = (v(th0 + d) - 2.0 * v(th0) + v(th0 - d)) / (d * d);
    let vp = (v(th0 + d) - v(th0 - d)) / (2.0 * d);
    assert!(
        vp.abs() * d < 1e-6 * vpp.abs() * d * d + 1e-12,
        "not an equilibrium"
    );
    let nu = (vpp / (ia + m * a * a * th0.sin().powi(2))).sqrt();

    let mut sc = Scenario::classical();
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = th0 + 1e-5;
    sc.initial.spin = w;
    sc.initial.precession = om;
    let period = 2.0 * std::f64::consts::PI / nu;
    sc.solver.t_end = 20.0 * period;
    sc.solver.samples = 20001;
    let tr = run(&sc);
    // Times of maxima of θ from the samples' upward-to-downward θ̇ sign change,
    // refined linearly in θ̇.
    let mut tmax = Vec::new();
    for w2 in tr.samples.windows(2) {
        if w2[0].theta_dot > 0.0 && w2[1].theta_dot <= 0.0 {
            let f = w2[0].theta_dot / (w2[0].theta_dot - w2[1].theta_dot);
            tmax.push(w2[0].t + f * (w2[1].t - w2[0].t));
        }
    }
    assert!(tmax.len() >= 18, "found {} maxima", tmax.len());
    let measured = (tmax[tmax.len() - 1] - tmax[0]) / (tmax.len() - 1) as f64;
    // Amplitude 1e-5 rad: nonlinear period shift O(1e-10); linear interpolation
    // of θ̇ on 1000 samples per period: O(1e-6) relative per crossing.
    assert!(
        (measured - period).abs() <= 1e-5 * period,
        "measured {measured}, Routhian {period}"
    );
    // Fast-top limit C ω/A is the right order (independent sanity check).
    assert!((nu / (ic * w / ia) - 1.0).abs() < 0.3);
}

/// RK4 converges at order 4 on the classical top before the first zero slip
/// (~0.05 s), so the sliding law is smooth there.
#[test]
fn rk4_order_four_classical() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.t_end = 0.04;
    sc.solver.samples = 2;
    let mut reference = sc.clone();
    reference.solver.rtol = 1e-13;
    let r = run(&reference);
    let yref = *r.samples.last().unwrap();
    let mut errs = Vec::new();
    for steps in [200, 400, 800] {
        let mut s = sc.clone();
        s.solver.method = Method::Rk4;
        s.solver.steps = steps;
        let tr = run(&s);
        let y = tr.samples.last().unwrap();
        let e = ((y.theta - yref.theta).abs())
            .max((y.spin - yref.spin).abs() / 100.0)
            .max((y.precession - yref.precession).abs() / 100.0);
        errs.push(e);
    }
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!(
            (13.0..19.0).contains(&ratio),
            "RK4 error ratio {ratio} ({errs:?})"
        );
    }
}

/// The adaptive method's error follows its rtol, and at tight settings RK4
/// and the adaptive method agree to 1e-8 relative.
#[test]
fn adaptive_error_follows_rtol_and_agrees_with_rk4() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.t_end = 0.04;
    sc.solver.samples = 2;
    let mut reference = sc.clone();
    reference.solver.rtol = 1e-13;
    let yref = *run(&reference).samples.last().unwrap();
    let mut prev = f64::INFINITY;
    for rtol in [1e-6, 1e-8, 1e-10] {
        let mut s = sc.clone();
        s.solver.rtol = rtol;
        let y = *run(&s).samples.last().unwrap();
        let e = (y.theta - yref.theta)
            .abs()
            .max((y.spin - yref.spin).abs() / 100.0);
        assert!(e <= 100.0 * rtol, "rtol {rtol:e}: error {e:e}");
        assert!(e < prev);
        prev = e;
    }
    let mut s = sc.clone();
    s.solver.method = Method::Rk4;
    s.solver.steps = 20000;
    let y = *run(&s).samples.last().unwrap();
    for (a, b, scale) in [
        (y.theta, yref.theta, 1.0),
        (y.spin, yref.spin, 100.0),
        (y.precession, yref.precession, 100.0),
    ] {
        assert!((a - b).abs() <= 1e-8 * scale, "{a} vs {b}");
    }
}

/// The classical top inverts with the regularised law (ε = 1e-2 m/s), and late
/// in the run n_Z approaches ω0 (R cos θ0 − a)/(R + a) within the bound that
/// θ's distance from π allows (docs/physics.md §7).
#[test]
fn classical_inverts_regularized_and_nz_limit() {
    let sc = classical_smooth(1e-2);
    let tr = run(&sc);
    let top = sc.top;
    let (r, a, ia, ic) = (
        top.radius,
        top.offset,
        top.inertia_transverse,
        top.inertia_axial,
    );
    assert!(
        tr.summary.theta_final > 3.0,
        "theta_final {}",
        tr.summary.theta_final
    );
    let j = tr.summary.jellett_initial;
    let target = 100.0 * (r * 0.1f64.cos() - a) / (r + a);
    let last = tr.samples.last().unwrap();
    let (s, c) = last.theta.sin_cos();
    let nz = tippetop::observe::vertical_spin(last.theta, last.precession, last.spin);
    let bound = (last.precession * s * s * (1.0 - ia * r * c / (ic * (r * c - a)))).abs()
        + (j * a * (1.0 + c) / (ic * (r * c - a) * (r + a))).abs();
    assert!(
        (nz - target).abs() <= bound + 1e-8 * target.abs(),
        "n_Z {nz} target {target} bound {bound}"
    );
    assert!(
        bound < 0.05 * target.abs(),
        "theta not close enough to pi: {}",
        last.theta
    );
}

/// The nano preset runs to 100 µs without tolerance trouble and meets the J bar.
#[test]
fn nano_preset_runs() {
    let tr = run(&Scenario::nano());
    assert_eq!(tr.summary.status, "ok");
    assert!((tr.summary.t_end - 1e-4).abs() < 1e-18);
    assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
    assert_eq!(tr.samples.len(), 1001);
}

/// The normal-force closure: m du_z/dt = N − m g, checked by differencing
/// the sampled u_z (independent of how N was computed).
#[test]
fn normal_force_closure_matches_vertical_acceleration() {
    let mut sc = classical_smooth(1e-2);
    sc.solver.t_end = 0.5;
    sc.solver.samples = 50001;
    let tr = run(&sc);
    let m = sc.top.mass;
    let nmax = tr
        .samples
        .iter()
        .map(|s| s.normal.abs())
        .fold(0.0, f64::max);
    for w in tr.samples.windows(3).step_by(97) {
        let dt = w[2].t - w[0].t;
        let az = (w[2].uz - w[0].uz) / dt;
        let n = m * (9.8 + az);
        // Central difference error ~ dt² u_z''' / 6 with dt = 2e-5 s.
        assert!(
            (n - w[1].normal).abs() <= 1e-4 * nmax,
            "t = {}: N {} vs m(g + u_z') {}",
            w[1].t,
            w[1].normal,
            n
        );
    }
}

/// Same input, same output, bit for bit.
#[test]
fn rerun_is_bit_identical() {
    let mut sc = Scenario::nano();
    sc.surface.law = FrictionLaw::CoulombSliding;
    let a = run(&sc);
    let b = run(&sc);
    assert_eq!(a.samples.len(), b.samples.len());
    for (x, y) in a.samples.iter().zip(&b.samples) {
        for (u, v) in x.values().iter().zip(y.values().iter()) {
            assert_eq!(u.to_bits(), v.to_bits());
        }
    }
    assert_eq!(a.summary, b.summary);
}

/// Contact "paper" uses N with its sign; "bilateral" |N|. Both hold J.
#[test]
fn contact_modes_run_and_report_negative_normal() {
    for contact in [ContactMode::Paper, ContactMode::Bilateral] {
        let mut sc = Scenario::nano();
        sc.surface.law = FrictionLaw::CoulombSliding;
        sc.surface.contact = contact;
        let tr = run(&sc);
        let s = &tr.summary;
        assert!(s.jellett_max_rel_drift <= 1e-10);
        let any_neg = tr.samples.iter().any(|x| x.normal < 0.0);
        assert_eq!(
            any_neg,
            s.contact_lost_at.is_some() || s.negative_normal_fraction > 0.0
        );
        if let Some(t) = s.contact_lost_at {
            assert!(s.negative_normal_fraction > 0.0 && t < s.t_end);
        }
    }
}

/// A force switch that makes N jump below zero is reported at the switch
/// time (no event can see a jump), and ends a unilateral run there. With
/// μ = 0, θ̇ = 0 and Ω = 0: N (1 + m a² s²/A) = m g + m a s h H_x/A, so
/// N < 0 exactly when H_x < −g A/(a s h) (≈ −1.35 N for the classical top at
/// θ = 0.5).
#[test]
fn normal_force_jump_at_a_switch_is_reported() {
    let mut sc = Scenario::classical();
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = 0.5;
    sc.initial.spin = 0.0;
    sc.solver.t_end = 0.01;
    let top = sc.top;
    let s = 0.5f64.sin();
    let h = top.height(0.5);
    let threshold = -9.8 * top.inertia_transverse / (top.offset * s * h);
    for (hx, lost) in [(1.05 * threshold, true), (0.95 * threshold, false)] {
        sc.forcing = Forcing {
            windows: vec![ForceWindow {
                hx,
                hy: 0.0,
                hz: 0.0,
                start: 0.005,
                stop: f64::INFINITY,
            }],
        };
        sc.surface.contact = ContactMode::Bilateral;
        let tr = run(&sc);
        if lost {
            assert_eq!(tr.summary.contact_lost_at, Some(0.005), "{:?}", tr.events);
            assert!(
                tr.events
                    .iter()
                    .any(|e| e.kind == "contact_lost" && e.t == 0.005)
            );
        } else {
            assert_eq!(tr.summary.contact_lost_at, None, "{:?}", tr.events);
        }
        sc.surface.contact = ContactMode::Unilateral;
        let tr = simulate(&sc).unwrap();
        match (&tr.error, lost) {
            (Some(tippetop::Error::Runtime { t, .. }), true) => assert_eq!(*t, 0.005),
            (None, false) => {}
            other => panic!("unexpected outcome {other:?}"),
        }
    }
}

/// Painlevé: with slip purely along +x and μ large enough that
/// m a h μ sin θ / A > 1 + m a² sin²θ / A, the θ̈–N system has no consistent
/// solution (docs/physics.md §4): the run stops at once and says so.
#[test]
fn painleve_case_is_reported() {
    let mut sc = Scenario::classical();
    let top = sc.top;
    let (m, a, ia) = (top.mass, top.offset, top.inertia_transverse);
    let th: f64 = 0.5;
    let (s, h) = (th.sin(), top.height(th));
    let k = m * a * h * s / ia;
    let mu_crit = (1.0 + m * a * a * s * s / ia) / k;
    for (mu, fails) in [(1.2 * mu_crit, true), (0.8 * mu_crit, false)] {
        sc.surface.friction = mu;
        sc.surface.law = FrictionLaw::CoulombSliding;
        sc.initial.theta = th;
        sc.initial.spin = 0.0;
        sc.initial.ux = 0.5;
        sc.solver.t_end = 1e-3;
        let tr = simulate(&sc).unwrap();
        match (&tr.error, fails) {
            (Some(tippetop::Error::Runtime { t, why }), true) => {
                assert_eq!(*t, 0.0);
                assert!(why.contains("Painleve"), "{why}");
            }
            (None, false) => {}
            other => panic!("mu = {mu}: {other:?}"),
        }
    }
}

/// J is conserved on the classical top under an applied-force schedule too.
#[test]
fn jellett_conserved_classical_with_forcing() {
    let mut sc = classical_smooth(1e-2);
    sc.solver.t_end = 2.0;
    sc.forcing = Forcing {
        windows: vec![
            ForceWindow {
                hx: 0.01,
                hy: -0.02,
                hz: 0.0,
                start: 0.1,
                stop: 0.7,
            },
            ForceWindow {
                hx: -0.005,
                hy: 0.01,
                hz: 0.0,
                start: 0.5,
                stop: f64::INFINITY,
            },
        ],
    };
    let tr = run(&sc);
    assert!(
        tr.summary.jellett_max_rel_drift <= 1e-10,
        "{:e}",
        tr.summary.jellett_max_rel_drift
    );
    assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
    assert!(tr.samples.iter().any(|s| s.work_applied != 0.0));
}
