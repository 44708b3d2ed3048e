//! Closed forms and exact statements every model must reproduce: steady
//! precession, the nutation frequency, the inverted top's n_Z, the Painlevé
//! case, N jumping below zero at a force switch, the poles θ = 0 and θ = π.

use crate::spec::*;
use tippetop::{ContactMode, ForceWindow, Forcing, FrictionLaw, ModelKind, Scenario};

/// The reduced model's Euler angles are singular at the poles: it refuses
/// θ = 0 and θ = π and its Ω equation divides by sin θ.
const REDUCED_POLE: Filter = cannot(
    Reduced,
    "Euler angles are singular at θ = 0 and π (the Ω equation divides by sin θ)",
);

/// Steady free precession of a sphere (a = 0, μ = 0, H = 0):
/// Ω0 = C ω0/(A cos θ0) makes θ̈ = 0; θ, Ω, ω stay constant to ~rtol.
#[test]
fn steady_free_precession_sphere() {
    each_model(&[], |m| {
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
        let tr = run(&sc, m);
        for s in &tr.samples {
            assert!((s.theta - 0.5).abs() <= 1e-9, "theta drifted: {}", s.theta);
            assert!(
                (s.precession - sc.initial.precession).abs() <= 1e-9 * sc.initial.precession,
                "t = {}: Omega {}",
                s.t,
                s.precession
            );
            assert!((s.spin - 100.0).abs() <= 1e-9 * 100.0, "t = {}", s.t);
        }
    });
}

/// Small nutation about a steady precession on a frictionless plane: the
/// period matches the Routhian linearisation (docs/physics.md#closed-forms), an
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
    // Fast-top limit C ω/A is the right order (independent sanity check).
    assert!((nu / (ic * w / ia) - 1.0).abs() < 0.3);

    let mut sc = Scenario::classical();
    sc.surface.friction = 0.0;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = th0 + 1e-5;
    sc.initial.spin = w;
    sc.initial.precession = om;
    let period = 2.0 * std::f64::consts::PI / nu;
    sc.solver.t_end = 20.0 * period;
    sc.solver.samples = 20001;
    each_model(&[], |model| {
        let tr = run(&sc, model);
        // Times of maxima of θ from the samples' upward-to-downward θ̇ sign
        // change, refined linearly in θ̇.
        let mut tmax = Vec::new();
        for w2 in tr.samples.windows(2) {
            if w2[0].theta_dot > 0.0 && w2[1].theta_dot <= 0.0 {
                let f = w2[0].theta_dot / (w2[0].theta_dot - w2[1].theta_dot);
                tmax.push(w2[0].t + f * (w2[1].t - w2[0].t));
            }
        }
        assert!(tmax.len() >= 18, "found {} maxima", tmax.len());
        let measured = (tmax[tmax.len() - 1] - tmax[0]) / (tmax.len() - 1) as f64;
        // Amplitude 1e-5 rad: nonlinear period shift O(1e-10); linear
        // interpolation of θ̇ on 1000 samples per period: O(1e-6) relative
        // per crossing.
        assert!(
            (measured - period).abs() <= 1e-5 * period,
            "measured {measured}, Routhian {period}"
        );
    });
}

/// The classical top inverts with the regularised law (ε = 1e-2 m/s), and late
/// in the run n_Z approaches ω0 (R cos θ0 − a)/(R + a) within the bound that
/// θ's distance from π allows (docs/physics.md#invariants).
#[test]
fn classical_inverts_regularized_and_nz_limit() {
    each_model(&[], |m| {
        let sc = classical_smooth(1e-2);
        let tr = run(&sc, m);
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
        assert_eq!(
            times(&tr, "theta_above_half_pi").len(),
            1,
            "{:?}",
            tr.events
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
    });
}

/// The Painlevé scenario of [`painleve_case_is_reported`] with friction
/// `factor` μ_crit: slip 0.5 m/s purely along +x at θ = 0.5, no spin, 1 ms.
fn painleve_scenario(factor: f64) -> Scenario {
    let mut sc = Scenario::classical();
    let top = sc.top;
    let (m, a, ia) = (top.mass, top.offset, top.inertia_transverse);
    let th: f64 = 0.5;
    let (s, h) = (th.sin(), top.height(th));
    let k = m * a * h * s / ia;
    let mu_crit = (1.0 + m * a * a * s * s / ia) / k;
    sc.surface.friction = factor * mu_crit;
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.initial.theta = th;
    sc.initial.spin = 0.0;
    sc.initial.ux = 0.5;
    sc.solver.t_end = 1e-3;
    sc
}

/// Below μ_crit (0.8 μ_crit) the run completes. It is expensive in every
/// model: the slip reaches zero at ≈ 0.45 ms and the sliding-only law then
/// crawls along |v| ≈ 1e-8 m/s without tripping the chatter detector
/// (reduced: 2.13M accepted + 2.71M rejected steps, 2.6 s in the test
/// profile; vector 1.19M + 3.09M, 2.4 s; rigid 1.56M + 1.98M, 5.3 s). The
/// rigid run alone would cost more than the whole suite gained by merging
/// the test binaries, so it runs with `--ignored`.
const PAINLEVE_SUBCRITICAL_COST: Filter = too_slow(
    Rigid,
    "the sub-critical Painlevé run crawls at zero slip: 1.56M steps + 1.98M rejected, 5.3 s",
);

/// Painlevé: with slip purely along +x and μ large enough that
/// m a h μ sin θ / A > 1 + m a² sin²θ / A, the θ̈–N system has no consistent
/// solution (docs/physics.md#normal-force): the run stops at once and says so
/// (1.2 μ_crit). Below μ_crit (0.8 μ_crit) the run completes.
#[test]
fn painleve_case_is_reported() {
    each_model(&[], |model| {
        let tr = simulate_as(&painleve_scenario(1.2), model);
        match &tr.error {
            Some(tippetop::Error::Runtime { t, why, .. }) => {
                assert_eq!(*t, 0.0);
                assert!(why.contains("Painleve"), "{why}");
                assert_eq!(tr.summary.failure, Some("painleve"));
            }
            other => panic!("1.2 mu_crit: {other:?}"),
        }
    });
    each_model(&[PAINLEVE_SUBCRITICAL_COST], painleve_subcritical_completes);
}

fn painleve_subcritical_completes(model: ModelKind) {
    let tr = simulate_as(&painleve_scenario(0.8), model);
    assert!(tr.error.is_none(), "0.8 mu_crit: {:?}", tr.error);
}

/// The sub-critical half of [`painleve_case_is_reported`] on the models it
/// leaves out for cost ([`PAINLEVE_SUBCRITICAL_COST`]).
#[test]
#[ignore = "slow: the sub-critical Painlevé run crawls at zero slip (rigid: 5.3 s in the test profile)"]
fn painleve_subcritical_completes_slow_models() {
    painleve_subcritical_completes(Rigid);
}

/// A force switch that makes N jump below zero is reported at the switch
/// time (no event can see a jump) as `contact_lost`. With μ = 0, θ̇ = 0 and
/// Ω = 0: N (1 + m a² s²/A) = m g + m a s h H_x/A, so N < 0 exactly when
/// H_x < −g A/(a s h) (≈ −1.35 N for the classical top at θ = 0.5).
/// Under unilateral contact the on-plane models stop there with an error;
/// the rigid model, which can fly, lifts off there instead (`lift_off`).
#[test]
fn normal_force_jump_at_a_switch_is_reported() {
    each_model(&[], |m| {
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
            let tr = run(&sc, m);
            if lost {
                assert_eq!(tr.summary.contact_lost_at, Some(0.005), "{:?}", tr.events);
                assert_eq!(times(&tr, "contact_lost").first(), Some(&0.005));
                // The sign history alternates: the next crossing (if any)
                // is N returning above zero.
                let regained = times(&tr, "contact_regained");
                let lost_t = times(&tr, "contact_lost");
                assert!(regained.len() + 1 >= lost_t.len(), "{:?}", tr.events);
                if let Some(r) = regained.first() {
                    assert!(
                        *r > 0.005 && lost_t.get(1).is_none_or(|l| l > r),
                        "{:?}",
                        tr.events
                    );
                }
            } else {
                assert_eq!(tr.summary.contact_lost_at, None, "{:?}", tr.events);
                assert!(times(&tr, "contact_lost").is_empty());
            }
            sc.surface.contact = ContactMode::Unilateral;
            let tr = simulate_as(&sc, m);
            if m == Rigid {
                assert!(tr.error.is_none(), "{:?}", tr.error);
                let lo = times(&tr, "lift_off");
                if lost {
                    assert_eq!(lo.first(), Some(&0.005), "{:?}", tr.events);
                } else {
                    assert!(lo.is_empty(), "{:?}", tr.events);
                }
            } else {
                match (&tr.error, lost) {
                    (Some(e @ tippetop::Error::Runtime { t, .. }), true) => {
                        assert_eq!(*t, 0.005);
                        assert_eq!(e.failure(), Some(tippetop::Failure::LiftOff));
                    }
                    (None, false) => {}
                    other => panic!("unexpected outcome {other:?}"),
                }
            }
        }
    });
}

/// Started at θ = 0 exactly (spinning upright on the heavy end, with a
/// nutation rate of 1 rad/s): the run completes, θ leaves 0 (with sliding
/// friction the upright tippe top is unstable and starts to rise), J and the
/// energy balance hold. Exactly upright with no nutation it stays upright.
#[test]
fn starts_at_theta_zero() {
    each_model(&[REDUCED_POLE], |m| {
        let mut sc = classical_smooth(1e-2);
        sc.initial.theta = 0.0;
        sc.initial.theta_dot = 1.0;
        sc.solver.t_end = 2.0;
        let tr = run(&sc, m);
        let s0 = &tr.samples[0];
        assert_eq!(s0.theta, 0.0);
        assert!((s0.theta_dot - 1.0).abs() < 1e-12 && (s0.spin - 100.0).abs() < 1e-12);
        let thmax = tr.samples.iter().map(|s| s.theta).fold(0.0, f64::max);
        println!(
            "theta = 0 start: theta_max {thmax:.3e}, J drift {:.2e}",
            tr.summary.jellett_max_rel_drift
        );
        assert!(thmax > 1e-3, "theta never left 0");
        assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
        assert!(tr.summary.energy_balance_max_rel_error <= 1e-8);
        // Exactly upright, no nutation: stays upright (nothing breaks the symmetry).
        let mut up = sc.clone();
        up.initial.theta_dot = 0.0;
        let tr = run(&up, m);
        assert!(
            tr.samples
                .iter()
                .all(|s| s.theta == 0.0 && (s.spin - 100.0).abs() < 1e-9)
        );
    });
    // The reduced model refuses the pole.
    let mut sc = Scenario::classical();
    sc.initial.theta = 0.0;
    sc.solver.model = Reduced;
    assert!(tippetop::simulate(&sc).is_err(), "reduced accepts θ = 0");
}

/// Started at θ = π exactly (inverted): completes and holds J.
#[test]
fn starts_at_theta_pi() {
    each_model(&[REDUCED_POLE], |m| {
        let mut sc = classical_smooth(1e-2);
        sc.initial.theta = std::f64::consts::PI;
        sc.initial.theta_dot = 0.5;
        sc.solver.t_end = 2.0;
        let tr = run(&sc, m);
        println!("theta = pi start: theta_final {}", tr.summary.theta_final);
        assert!(tr.summary.jellett_max_rel_drift <= 1e-10);
    });
}

/// A frictionless top passing through θ = π: started at θ = π − 0.01 with a
/// nutation rate towards π (no spin, no precession: a planar rocking) large
/// enough to carry the axis over the pole: θ gets within 1e-6 of π and the
/// energy is conserved to 1e-10. (That the axis comes out on the other side
/// is checked on the rigid model's attitude in `rigid.rs`.)
#[test]
fn passes_through_theta_pi() {
    each_model(&[REDUCED_POLE], |m| {
        let mut sc = Scenario::classical();
        sc.surface.friction = 0.0;
        sc.surface.law = FrictionLaw::CoulombSliding;
        sc.initial.theta = std::f64::consts::PI - 0.01;
        sc.initial.theta_dot = 20.0;
        sc.initial.precession = 0.0;
        sc.initial.spin = 0.0;
        sc.solver.t_end = 0.01;
        sc.solver.samples = 1001;
        let tr = run(&sc, m);
        let gap = std::f64::consts::PI - tr.summary.theta_max;
        println!("through pi: pi - theta_max {gap:.2e}");
        assert!(gap <= 1e-6, "pi - theta_max = {gap:e}");
        let em = emax(&tr);
        let e0 = tr.summary.energy_initial;
        assert!(
            tr.samples
                .iter()
                .all(|s| (s.energy - e0).abs() <= 1e-10 * em)
        );
    });
}
