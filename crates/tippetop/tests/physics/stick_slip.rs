// Included by tests/stick_slip_reduced.rs and tests/stick_slip_vector.rs, each with its own `MODEL`.
//
// Exact (set-valued) Coulomb friction: closed forms for sliding → rolling,
// rolling conserves energy, the stick limit, cost, invariants across switches.

use tippetop::{ForceWindow, Forcing, FrictionLaw, Scenario, Trajectory};

/// Run `sc` with this test crate's model (`MODEL`); panics if it fails.
fn run(sc: &Scenario) -> Trajectory {
    common::run_as(sc, MODEL)
}

use common::uniform_sphere as sphere;

/// Sliding sphere: |v_P| falls linearly at (7/2) μ g, so rolling starts at
/// t_r = 2 |v_P(0)| / (7 μ g) with centre-of-mass speed (2/7)|v_P(0)|.
#[test]
fn sliding_sphere_reaches_rolling_at_the_coulomb_time() {
    let (theta, spin, mu, g) = (0.5f64, 50.0, 0.2, 9.8);
    let sc = sphere(theta, spin, mu);
    let tr = run(&sc);
    let v0 = theta.sin() * sc.top.radius * spin;
    let t_roll = 2.0 * v0 / (7.0 * mu * g);
    let sticks: Vec<_> = tr.events.iter().filter(|e| e.kind == "stick").collect();
    assert_eq!(sticks.len(), 1, "events: {:?}", tr.events);
    let ts = sticks[0].t;
    assert!(
        (ts - t_roll).abs() <= 1e-8 * t_roll,
        "stick at {ts}, Coulomb predicts {t_roll}"
    );
    // Slip decreases linearly before, is zero after.
    for s in &tr.samples {
        if s.t < ts {
            let expect = v0 - 3.5 * mu * g * s.t;
            assert!(
                (s.slip - expect).abs() <= 1e-8 * v0,
                "t {}: slip {} vs {}",
                s.t,
                s.slip,
                expect
            );
            assert_eq!(s.rolling, 0);
        } else if s.t > ts {
            assert_eq!(s.rolling, 1);
            assert_eq!(s.slip, 0.0);
            let speed = s.ux.hypot(s.uy);
            assert!(
                (speed - 2.0 / 7.0 * v0).abs() <= 1e-8 * v0,
                "rolling speed {speed} vs {}",
                2.0 / 7.0 * v0
            );
        }
    }
    assert!((tr.summary.rolling_fraction - (0.4 - ts) / 0.4).abs() < 1e-9);
    // Cheap: smooth between events.
    assert!(
        tr.summary.rhs_evaluations < 10_000,
        "{} evaluations",
        tr.summary.rhs_evaluations
    );
}

/// Rolling without applied force does no work: energy constant, friction
/// work frozen (classical top after it sticks at ~0.047 s).
#[test]
fn rolling_dissipates_no_energy() {
    let tr = run(&Scenario::classical());
    let stick = tr
        .events
        .iter()
        .find(|e| e.kind == "stick")
        .expect("the classical top reaches rolling")
        .t;
    let rolling: Vec<_> = tr
        .samples
        .iter()
        .filter(|s| s.t > stick && s.rolling == 1)
        .collect();
    assert!(rolling.len() > 900);
    let e_ref = rolling[0].energy;
    let w_ref = rolling[0].work_friction;
    for s in &rolling {
        assert!(
            (s.energy - e_ref).abs() <= 1e-10 * e_ref,
            "t {}: dE {:e}",
            s.t,
            s.energy - e_ref
        );
        assert_eq!(s.work_friction, w_ref);
    }
    // J and the energy balance hold across the switch.
    assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
    assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
}

/// A sphere rolling freely needs no friction; an applied force at P then
/// needs friction |H| to keep P at rest. Just above μ m g rolling breaks at
/// once (at the switch time); just below, it does not.
#[test]
fn applied_force_step_breaks_rolling_only_above_mu_n() {
    for (factor, breaks) in [(1.01, true), (0.99, false)] {
        let mut sc = sphere(0.5, 50.0, 0.2);
        let (m, r) = (sc.top.mass, sc.top.radius);
        // Start rolling: u = rolling velocity (a = 0, θ̇ = 0, Ω = 0).
        sc.initial.uy = -(0.5f64).sin() * r * 50.0;
        let h = factor * 0.2 * m * 9.8;
        let t1 = 0.1;
        sc.forcing = Forcing {
            windows: vec![ForceWindow {
                hx: h * 0.6,
                hy: h * 0.8,
                hz: 0.0,
                start: t1,
                stop: f64::INFINITY,
            }],
        };
        let tr = run(&sc);
        assert_eq!(
            tr.events.iter().find(|e| e.kind == "stick").map(|e| e.t),
            Some(0.0)
        );
        let slip = tr.events.iter().find(|e| e.kind == "slip");
        if breaks {
            let t = slip.expect("rolling must break").t;
            assert_eq!(t, t1, "rolling broke at {t}, force switched at {t1}");
            assert!(tr.samples.last().unwrap().slip > 0.0);
        } else {
            assert!(slip.is_none(), "rolling broke: {:?}", tr.events);
            assert!(tr.samples.iter().all(|s| s.rolling == 1 && s.slip == 0.0));
        }
    }
}

/// J and the energy balance hold across every switch, on both presets, and
/// the exact law costs at most 10x the right-hand-side evaluations of the
/// regularised law (ε = 1e-3 m/s classical; the same ε/(R·rate) for nano).
#[test]
fn exact_law_invariants_and_cost_both_presets() {
    for (mut sc, eps) in [(Scenario::classical(), 1e-3), (Scenario::nano(), 1.2e-7)] {
        sc.surface.law = FrictionLaw::Coulomb;
        let exact = run(&sc);
        assert!(exact.summary.jellett_max_rel_drift <= 1e-10);
        assert!(exact.summary.energy_balance_max_rel_error <= 1e-8);
        let mut reg = sc.clone();
        reg.surface.law = FrictionLaw::Regularized { eps };
        let r = run(&reg);
        let ratio = exact.summary.rhs_evaluations as f64 / r.summary.rhs_evaluations as f64;
        assert!(ratio <= 10.0, "exact/regularised evaluations = {ratio}");
    }
}

/// Slow validation (run with `cargo test --workspace --release -- --ignored`):
/// with the regularised law the classical benchmark inverts at about 2 s,
/// 11 s and 100 s for ε = 1e-2, 1e-3, 1e-4 m/s (the figures an independent
/// implementation of App. A gave when the exact-friction issue was filed),
/// while under the exact law it rolls and never inverts.
#[test]
#[ignore = "slow: 150 s of simulated time at ε = 1e-4 (~25M RHS evaluations)"]
fn regularized_inversion_time_grows_like_inverse_eps_exact_never_inverts() {
    let mut base = Scenario::classical();
    base.solver.t_end = 150.0;
    base.solver.samples = 1501;
    let rows = tippetop::analysis::friction::eps_study(&base, &[1e-2, 1e-3, 1e-4]).unwrap();
    assert_eq!(rows[0].0.inversion_time, None, "exact law inverted");
    for ((row, _), expect) in rows[1..].iter().zip([2.0, 11.0, 100.0]) {
        let t = row.inversion_time.expect("regularised top inverts");
        assert!(
            (t / expect - 1.0).abs() < 0.25,
            "eps {:?}: inversion at {t} s, independent value ~{expect} s",
            row.eps
        );
    }
}
