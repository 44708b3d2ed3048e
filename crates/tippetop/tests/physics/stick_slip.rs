//! Exact (set-valued) Coulomb friction: closed forms for sliding → rolling,
//! rolling dissipates nothing, the stick limit under an applied force, cost,
//! invariants across switches, chattering of the sliding-only law.

use crate::spec::*;
use tippetop::{ForceWindow, Forcing, FrictionLaw, Scenario};

/// Sliding sphere (θ0 = 0.5, ω0 = 50 about the tilted axis, μ = 0.2):
/// |v_P| falls linearly at (7/2) μ g, so rolling starts at
/// t_r = 2 |v_P(0)| / (7 μ g) with centre-of-mass speed (2/7)|v_P(0)|; one
/// `stick` event, no `slip`.
#[test]
fn sliding_sphere_reaches_rolling_at_the_coulomb_time() {
    each_model(&[], |m| {
        let (theta, spin, mu, g) = (0.5f64, 50.0, 0.2, 9.8);
        let sc = uniform_sphere(theta, spin, mu);
        let tr = run(&sc, m);
        let v0 = theta.sin() * sc.top.radius * spin;
        let t_roll = 2.0 * v0 / (7.0 * mu * g);
        let sticks = times(&tr, "stick");
        assert_eq!(sticks.len(), 1, "events: {:?}", tr.events);
        assert!(times(&tr, "slip").is_empty(), "events: {:?}", tr.events);
        let ts = sticks[0];
        println!(
            "sphere: stick at {ts}, closed form {t_roll}, rel {:.1e}, {} rhs",
            (ts - t_roll).abs() / t_roll,
            tr.summary.rhs_evaluations
        );
        // 1e-8 is the requirement; measured 1e-14 (rigid). Without the smooth
        // continuation of μ v/|v| through zero slip the rigid model's event
        // was found only to ≈ 3e-11, which the 1e-12 bound catches.
        assert!(
            (ts - t_roll).abs() <= 1e-12 * t_roll,
            "stick at {ts}, Coulomb predicts {t_roll}"
        );
        // Slip decreases linearly before, is zero after.
        let mut worst_roll = 0.0f64;
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
                worst_roll = worst_roll.max((speed - 2.0 / 7.0 * v0).abs() / v0);
            }
        }
        println!("rolling speed: max deviation from 2/7 |v0| = {worst_roll:.1e} |v0|");
        assert!(
            worst_roll <= 1e-8,
            "rolling speed off by {worst_roll:e} |v0|"
        );
        assert!((tr.summary.rolling_fraction - (0.4 - ts) / 0.4).abs() < 1e-9);
        // Cheap: smooth between events.
        assert!(
            tr.summary.rhs_evaluations < 10_000,
            "{} evaluations",
            tr.summary.rhs_evaluations
        );
    });
}

/// A sphere started exactly at θ = 0 (axis vertical), spinning about the
/// vertical with ω0 and about the horizontal y axis with θ̇0, its centre
/// moving with (u_x, u_y).
///
/// Derivation: at θ = 0, n = (0, θ̇0, ω0), r = −R Z, so the slip is
/// v_P = u + n × r = (u_x − R θ̇0, u_y, 0): the vertical spin does not slip.
/// For a = 0 the contact matrix on horizontal forces is
/// K F = F/m − r × (r × F)/I = (1/m + R²/I) F = 7/(2m) F and ṙ = 0, so
/// under sliding friction F = −μ m g v̂ the slip obeys v̇_P = −(7/2) μ g v̂:
/// it keeps its direction and falls linearly, rolling starts at
/// t_r = 2|v_P(0)|/(7 μ g). Meanwhile v̇ = −μ g v̂, so the centre's velocity
/// when rolling starts is u0 − (2/7) v_P(0), constant afterwards (a free
/// rolling sphere needs no friction). The friction torque r × F is
/// horizontal and the inertia isotropic, so n_Z = ω0 throughout.
#[test]
fn sphere_from_theta_zero_sticks_at_the_coulomb_time() {
    let reduced = cannot(Reduced, "Euler angles are singular at θ = 0");
    each_model(&[reduced], |m| {
        let (mu, g) = (0.2, 9.8);
        let sc = sphere_from_theta_zero(mu);
        let r = sc.top.radius;
        let (thd0, ux0, uy0) = (10.0, 0.5, 0.3);
        let tr = run(&sc, m);
        let v0 = [ux0 - r * thd0, uy0];
        let v0n = f64::hypot(v0[0], v0[1]);
        let t_roll = 2.0 * v0n / (7.0 * mu * g);
        let sticks = times(&tr, "stick");
        assert_eq!(sticks.len(), 1, "events: {:?}", tr.events);
        let ts = sticks[0];
        println!(
            "sphere from theta = 0: stick at {ts}, closed form {t_roll}, rel {:.1e}",
            (ts - t_roll).abs() / t_roll
        );
        assert!((ts - t_roll).abs() <= 1e-12 * t_roll);
        // Centre velocity once rolling, in world axes: the outputs u_x, u_y
        // are in the precessing frame (x̂ along the tilt), so compare the speed.
        let u_roll = [ux0 - 2.0 / 7.0 * v0[0], uy0 - 2.0 / 7.0 * v0[1]];
        let speed_roll = u_roll[0].hypot(u_roll[1]);
        let (mut worst_slip, mut worst_speed, mut worst_nz) = (0.0f64, 0.0f64, 0.0f64);
        for s in &tr.samples {
            // n_Z = Ω sin²θ + ω cos θ (Ω is reported 0 at θ = 0 exactly).
            let nz = s.precession * s.theta.sin().powi(2) + s.spin * s.theta.cos();
            worst_nz = worst_nz.max((nz - 50.0).abs() / 50.0);
            if s.t < ts {
                assert_eq!(s.rolling, 0);
                worst_slip = worst_slip.max((s.slip - (v0n - 3.5 * mu * g * s.t)).abs() / v0n);
            } else if s.t > ts {
                assert_eq!(s.rolling, 1);
                assert_eq!(s.slip, 0.0);
                worst_speed = worst_speed.max((s.ux.hypot(s.uy) - speed_roll).abs() / speed_roll);
            }
        }
        println!(
            "  slip {worst_slip:.1e} |v0|, rolling speed {worst_speed:.1e}, n_Z {worst_nz:.1e} (relative)"
        );
        assert!(worst_slip <= 1e-8, "slip off the line by {worst_slip:e}");
        assert!(worst_speed <= 1e-8, "rolling speed off by {worst_speed:e}");
        assert!(worst_nz <= 1e-8, "n_Z changed by {worst_nz:e}");
        // It did leave θ = 0 (the horizontal rotation tips the body axis).
        assert!(tr.samples.last().unwrap().theta > 0.1);
    });
}

/// The scenario of [`sphere_from_theta_zero_sticks_at_the_coulomb_time`]:
/// θ0 = 0, ω0 = 50, θ̇0 = 10, (u_x, u_y) = (0.5, 0.3).
pub fn sphere_from_theta_zero(mu: f64) -> Scenario {
    let mut sc = uniform_sphere(0.0, 50.0, mu);
    sc.initial.theta_dot = 10.0;
    sc.initial.ux = 0.5;
    sc.initial.uy = 0.3;
    sc
}

/// Rolling without applied force does no work: after the `stick` of the
/// classical top (≈ 0.047 s) the energy is constant to 1e-10, the friction
/// work frozen, the slip zero; J and the energy balance hold across the
/// switch.
#[test]
fn rolling_dissipates_no_energy() {
    each_model(&[], |m| {
        let tr = run(&Scenario::classical(), m);
        let stick = *times(&tr, "stick")
            .first()
            .expect("the classical top reaches rolling");
        let rolling: Vec<_> = tr
            .samples
            .iter()
            .filter(|s| s.t > stick && s.rolling == 1)
            .collect();
        assert!(rolling.len() > 900, "{} rolling samples", rolling.len());
        let e_ref = rolling[0].energy;
        let w_ref = rolling[0].work_friction;
        let mut worst = 0.0f64;
        for s in &rolling {
            worst = worst.max((s.energy - e_ref).abs() / e_ref);
            assert_eq!(s.work_friction, w_ref, "t {}", s.t);
            assert_eq!(s.slip, 0.0, "t {}", s.t);
        }
        println!(
            "rolling: max |E - E(stick)|/E = {worst:.1e}, J drift {:.2e}",
            tr.summary.jellett_max_rel_drift
        );
        assert!(worst <= 1e-10, "energy drift while rolling {worst:e}");
        assert!(
            tr.summary.jellett_max_rel_drift <= 1e-10,
            "J drift {:e}",
            tr.summary.jellett_max_rel_drift
        );
        assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
    });
}

/// A sphere rolling freely needs no friction; an applied force H at P then
/// needs friction |H| to keep P at rest (H drops out of the motion). Just
/// above μ m g rolling breaks at once (a `slip` at the switch time); just
/// below, it does not and the sphere rolls on unchanged.
#[test]
fn applied_force_step_breaks_rolling_only_above_mu_n() {
    each_model(&[], |m| {
        for (factor, breaks) in [(1.01, true), (0.99, false)] {
            let mut sc = uniform_sphere(0.5, 50.0, 0.2);
            let (mass, r) = (sc.top.mass, sc.top.radius);
            // Start rolling: u = rolling velocity (a = 0, θ̇ = 0, Ω = 0).
            sc.initial.uy = -(0.5f64).sin() * r * 50.0;
            let h = factor * 0.2 * mass * 9.8;
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
            let tr = run(&sc, m);
            assert_eq!(times(&tr, "stick").first().copied(), Some(0.0));
            let slip = times(&tr, "slip");
            let s0 = &tr.samples[0];
            if breaks {
                assert_eq!(slip, vec![t1], "events {:?}", tr.events);
                assert!(tr.samples.last().unwrap().slip > 0.0);
                // Before the switch it rolled with no friction: nothing changed.
                for s in tr.samples.iter().filter(|s| s.t < t1) {
                    assert_eq!(s.rolling, 1);
                    assert!((s.uy - s0.uy).abs() <= 1e-10 * s0.uy.abs(), "t {}", s.t);
                }
            } else {
                assert!(slip.is_empty(), "rolling broke: {:?}", tr.events);
                assert!(tr.samples.iter().all(|s| s.rolling == 1 && s.slip == 0.0));
                // H drops out of the motion: the sphere rolls on unchanged.
                let worst = tr
                    .samples
                    .iter()
                    .map(|s| (s.uy - s0.uy).abs().max(s.ux.abs()) / s0.uy.abs())
                    .fold(0.0, f64::max);
                assert!(worst <= 1e-10, "rolling velocity changed by {worst:e}");
            }
        }
    });
}

/// J and the energy balance hold across every switch, on both presets, and
/// the exact law costs at most 10x the right-hand-side evaluations of the
/// regularised law (ε = 1e-3 m/s classical; the same ε/(R·rate) for nano).
#[test]
fn exact_law_invariants_and_cost_both_presets() {
    each_model(&[], |m| {
        for (name, mut sc, eps) in [
            ("classical", Scenario::classical(), 1e-3),
            ("nano", Scenario::nano(), 1.2e-7),
        ] {
            sc.surface.law = FrictionLaw::Coulomb;
            let exact = run(&sc, m);
            let d = exact.summary.jellett_max_rel_drift;
            assert!(d <= 1e-10, "{name}: J drift {d:e}");
            assert!(exact.summary.energy_balance_max_rel_error <= 1e-8, "{name}");
            let mut reg = sc.clone();
            reg.surface.law = FrictionLaw::Regularized { eps };
            let r = run(&reg, m);
            let ratio = exact.summary.rhs_evaluations as f64 / r.summary.rhs_evaluations as f64;
            assert!(
                ratio <= 10.0,
                "{name}: exact/regularised evaluations = {ratio}"
            );
        }
    });
}

/// Before the first zero slip the exact "coulomb" law is the sliding law
/// μ v/|v| itself (its continuation through zero only acts past a zero):
/// the classical top over 0..0.04 s gives bit-identical samples with
/// "coulomb" and "coulomb_sliding", no events and no notes.
#[test]
fn coulomb_equals_sliding_before_first_zero_slip() {
    each_model(&[], |m| {
        let mut sc = Scenario::classical();
        sc.solver.t_end = 0.04;
        let tr = run(&sc, m);
        assert!(tr.events.is_empty(), "events: {:?}", tr.events);
        let mut sliding = sc.clone();
        sliding.surface.law = FrictionLaw::CoulombSliding;
        let tr2 = run(&sliding, m);
        assert!(tr2.events.is_empty());
        assert_eq!(tr.samples, tr2.samples);
        assert!(tr.samples.iter().all(|s| s.rolling == 0 && s.slip > 0.0));
    });
}

/// The sliding-only law chatters at zero slip: the classical run stops with
/// the chattering error (the same message in every model) after
/// CHATTER_REVERSALS slip reversals instead of grinding on.
#[test]
fn coulomb_sliding_chatter_detected() {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::CoulombSliding;
    let cut = |m: &str| m.split("; state").next().unwrap().to_string();
    let strip_time = |m: String| m.split_once(": ").map(|x| x.1.to_string()).unwrap_or(m);
    let reference = simulate_as(&sc, Reduced)
        .error
        .expect("reduced chatters")
        .to_string();
    each_model(&[], |m| {
        let tr = simulate_as(&sc, m);
        let err = tr.error.as_ref().expect("chattering must stop the run");
        let msg = err.to_string();
        println!(
            "chatter: {msg}\n  at t = {} after {} steps",
            tr.summary.t_end, tr.summary.steps
        );
        assert!(
            msg.contains("the sliding-only Coulomb law chatters"),
            "{msg}"
        );
        assert!(msg.contains("use friction_law = \"coulomb\""), "{msg}");
        assert_eq!(err.failure(), Some(tippetop::Failure::Chattering));
        assert_eq!(tr.summary.failure, Some("chattering"));
        assert!(tr.summary.steps < 100_000, "{} steps", tr.summary.steps);
        assert!(tr.summary.steps > 0);
        assert_eq!(strip_time(cut(&msg)), strip_time(cut(&reference)));
    });
}

/// Slow validation (run with `cargo test --workspace --release -- --ignored`):
/// with the regularised law the classical benchmark inverts at about 2 s,
/// 11 s and 100 s for ε = 1e-2, 1e-3, 1e-4 m/s (the figures an independent
/// implementation of App. A gave when the exact-friction issue was filed),
/// while under the exact law it rolls and never inverts.
#[test]
#[ignore = "slow: 150 s of simulated time at ε = 1e-4 (~25M RHS evaluations)"]
fn regularized_inversion_time_grows_like_inverse_eps_exact_never_inverts() {
    each_model(&[], |m| {
        let mut base = Scenario::classical();
        base.solver.model = m;
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
    });
}
