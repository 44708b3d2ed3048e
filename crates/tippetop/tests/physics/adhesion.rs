//! Van der Waals adhesion, the `[adhesion]` table (docs/physics.md#adhesion), run
//! over every model: the slip-to-roll time of a sphere against the closed
//! form with the load `F_a`, Jellett's J and the energy balance with
//! adhesion, and lift-off under unilateral contact exactly where a pull at
//! the contact point exceeds `F_a + m g` (reduced/vector: the run stops
//! there; rigid: it flies, and the separation costs `E_b`, checked against
//! the gap potential's closed form). Every tolerance is justified next to
//! its assertion; no expected value comes from the code's output.

use super::spec::{self, each_model, run as run_as, uniform_sphere};
use tippetop::{Adhesion, ContactMode, Error, ForceWindow, Forcing, ModelKind, Scenario};

/// Adhesion with pull-off force `factor · m g` and the decay length
/// `E_b/F_a = decay · R` of the flight potential.
fn adhesion(sc: &Scenario, factor: f64, decay: f64) -> Adhesion {
    let force = factor * sc.top.mass * sc.surface.gravity;
    Adhesion {
        force,
        energy: force * decay * sc.top.radius,
    }
}

/// One window of a vertical load `hz` \[N\] at the contact point on
/// `[start, stop)`.
fn load(hz: f64, start: f64, stop: f64) -> Forcing {
    Forcing {
        windows: vec![ForceWindow {
            hx: 0.0,
            hy: 0.0,
            hz,
            start,
            stop,
        }],
    }
}

/// A sliding uniform sphere under the exact Coulomb law with adhesion: the
/// contact reaction is `N_c = m g + F_a` (a = 0: `Q = m g`, `D = 1`), the
/// friction `μ N_c` brings the slip to zero at
/// `t_r = 2 v0 / (7 μ (g + F_a/m))`, and the sphere then rolls at
/// `(2/7) v0` whatever `F_a` (the load passes through `P`).
/// `pull_off_margin_min` is `m g + F_a`.
#[test]
fn sliding_sphere_rolls_at_the_adhesive_coulomb_time() {
    let (theta, spin, mu) = (0.5f64, 50.0, 0.2);
    each_model(&[], |model| {
        for factor in [3.0, 1e3] {
            let mut sc = uniform_sphere(theta, spin, mu);
            sc.set_adhesion(adhesion(&sc, factor, 0.1));
            let (m, g) = (sc.top.mass, sc.surface.gravity);
            let fa = sc.adhesion().force;
            let tr = run_as(&sc, model);
            let v0 = theta.sin() * sc.top.radius * spin;
            let geff = g + fa / m;
            let t_roll = 2.0 * v0 / (7.0 * mu * geff);
            let sticks = spec::times(&tr, "stick");
            assert_eq!(sticks.len(), 1, "{model:?}: events {:?}", tr.events);
            let ts = sticks[0];
            println!(
                "{model:?} F_a = {factor} m g: stick at {ts:e}, closed form {t_roll:e}, rel {:.1e}",
                (ts - t_roll).abs() / t_roll
            );
            // The bar of the loaded sliding-sphere test (physics/forces.rs):
            // the slip-zero event is located on the dense output to the
            // step's accuracy. Without F_a in the friction t_r would be off
            // by the factor 1 + F_a/(m g) = 4 or 1001.
            assert!(
                (ts - t_roll).abs() <= 1e-8 * t_roll,
                "{model:?} F_a = {factor} m g: stick at {ts}, closed form {t_roll}"
            );
            let want = m * g + fa;
            for s in &tr.samples {
                // N_c = m g + F_a: one or two roundings sliding, a 3x3
                // solve of O(1) entries rolling (the bar of forces.rs).
                assert!(
                    (s.normal - want).abs() <= 1e-13 * want,
                    "{model:?} t {}: N {} vs {want}",
                    s.t,
                    s.normal
                );
                if s.t > ts {
                    assert_eq!(s.rolling, 1, "{model:?} t {}", s.t);
                    let speed = s.ux.hypot(s.uy);
                    // Rolling holds the speed to the integration error.
                    assert!(
                        (speed - 2.0 / 7.0 * v0).abs() <= 1e-8 * v0,
                        "{model:?}: rolling speed {speed} vs {}",
                        2.0 / 7.0 * v0
                    );
                }
            }
            let margin = tr.summary.pull_off_margin_min.expect("adhesion on");
            assert!(
                (margin - want).abs() <= 1e-13 * want,
                "{model:?}: pull_off_margin_min {margin} vs {want}"
            );
        }
    });
}

/// Without adhesion `pull_off_margin_min` is null.
#[test]
fn pull_off_margin_is_null_without_adhesion() {
    each_model(&[], |model| {
        let tr = run_as(&uniform_sphere(0.5, 50.0, 0.2), model);
        assert_eq!(tr.summary.pull_off_margin_min, None, "{model:?}");
    });
}

/// Jellett's J is conserved and `E − E0 = W_f + W_a` holds with adhesion
/// (it does no work in contact): the classical top (exact law, sliding then
/// rolling) with `F_a = 5 m g`, and the nano preset (the paper's H) with
/// `F_a = 100 m g`, both at rtol 1e-10.
#[test]
fn jellett_and_energy_balance_hold_with_adhesion() {
    each_model(&[], |model| {
        let mut sc = Scenario::classical();
        sc.solver.t_end = 2.0;
        sc.solver.samples = 201;
        sc.set_adhesion(adhesion(&sc, 5.0, 0.1));
        let tr = run_as(&sc, model);
        let s = &tr.summary;
        let rolling = tr.samples.iter().filter(|s| s.rolling == 1).count();
        println!(
            "classical {model:?} F_a = 5 m g: J drift {:.1e}, energy balance {:.1e}, {rolling} rolling samples",
            s.jellett_max_rel_drift, s.energy_balance_max_rel_error
        );
        // The bars of the invariant tests without adhesion
        // (physics/invariants.rs, physics/forces.rs) at rtol 1e-10.
        assert!(s.jellett_max_rel_drift <= 1e-10, "{model:?} classical J");
        assert!(
            s.energy_balance_max_rel_error <= 1e-8,
            "{model:?} classical energy"
        );
        // Both phases are exercised (the stick time shrinks by 1 + F_a/(m g)).
        assert!(rolling > 0 && rolling < tr.samples.len(), "{model:?}");

        let mut sc = Scenario::nano();
        sc.set_adhesion(adhesion(&sc, 100.0, 0.5));
        let tr = run_as(&sc, model);
        let s = &tr.summary;
        println!(
            "nano {model:?} F_a = 100 m g: J drift {:.1e}, energy balance {:.1e}, margin {:?}",
            s.jellett_max_rel_drift, s.energy_balance_max_rel_error, s.pull_off_margin_min
        );
        assert!(s.jellett_max_rel_drift <= 1e-10, "{model:?} nano J");
        assert!(
            s.energy_balance_max_rel_error <= 1e-8,
            "{model:?} nano energy"
        );
        // F_a = 100 m g dwarfs H = 8.5 m g: the contact holds throughout.
        assert!(
            s.pull_off_margin_min.expect("adhesion on") > 0.0,
            "{model:?}"
        );
    });
}

/// Under unilateral contact a pull `h_z = −P` at the contact point of a
/// sphere (`N_c = m g + F_a − P`) lifts it off exactly when `P > F_a + m g`:
/// at `P = 0.99 (F_a + m g)` the contact holds (the smallest `N_c` is
/// `0.01 (F_a + m g)`), at `P = 1.01 (F_a + m g)` it leaves at the pull's
/// start `t1`. The reduced and vector models stop there with the time; the
/// rigid model flies.
#[test]
fn a_pull_lifts_off_exactly_beyond_pull_off_plus_weight() {
    let t1 = 0.1;
    each_model(&[], |model| {
        for (k, lifts) in [(0.99, false), (1.01, true)] {
            let mut sc = uniform_sphere(0.5, 50.0, 0.2);
            sc.surface.contact = ContactMode::Unilateral;
            sc.set_adhesion(adhesion(&sc, 2.0, 0.1));
            let hold = sc.top.mass * sc.surface.gravity + sc.adhesion().force;
            sc.forcing = load(-k * hold, t1, 0.2);
            let tr = spec::simulate_as(&sc, model);
            let lift = spec::times(&tr, "lift_off");
            println!(
                "{model:?} P = {k} (F_a + m g): error {:?}, lift-offs {lift:?}, margin {:?}",
                tr.error, tr.summary.pull_off_margin_min
            );
            if !lifts {
                assert!(tr.error.is_none(), "{model:?}: {:?}", tr.error);
                assert!(lift.is_empty(), "{model:?}: {:?}", tr.events);
                let margin = tr.summary.pull_off_margin_min.expect("adhesion on");
                // N_c = (1 − k)(F_a + m g) while pulled: a few roundings of
                // the O(1) scaled force (1e-13 of F_a + m g, as above).
                assert!(
                    (margin - (1.0 - k) * hold).abs() <= 1e-13 * hold,
                    "{model:?}: margin {margin} vs {}",
                    (1.0 - k) * hold
                );
                continue;
            }
            match model {
                ModelKind::Rigid => {
                    assert!(tr.error.is_none(), "{model:?}: {:?}", tr.error);
                    // The jump of N_c below zero at the switch is seen at
                    // the switch time itself.
                    assert_eq!(lift.first(), Some(&t1), "{model:?}: {:?}", tr.events);
                }
                _ => match &tr.error {
                    Some(Error::Runtime { t, why, kind }) => {
                        assert_eq!(*t, t1, "{model:?}: stopped at {t}: {why}");
                        assert_eq!(*kind, tippetop::Failure::LiftOff, "{model:?}");
                        assert!(why.contains("lift-off"), "{model:?}: {why}");
                    }
                    other => panic!("{model:?}: expected a lift-off stop, got {other:?}"),
                },
            }
        }
    });
}

/// In flight the adhesion is the gap potential `U(z) = −E_b exp(−F_a z/E_b)`
/// (rigid model): a sphere pulled off by `P = 1.5 (F_a + m g)` rises with
/// `½ m v_z² = (P − m g) z − E_b (1 − exp(−F_a z/E_b))`, so once `z ≫
/// E_b/F_a` the separation has cost exactly `E_b`. The height is measured by
/// the pull's work (`z = W_a/P` for `a = 0`, where `v_Pz = v_z`); the energy
/// balance (with the potential in the energy) holds through the flight and
/// the landing.
#[test]
fn rigid_separation_costs_the_binding_energy() {
    let mut sc = uniform_sphere(0.5, 50.0, 0.2);
    sc.solver.model = ModelKind::Rigid;
    sc.surface.contact = ContactMode::Unilateral;
    sc.set_adhesion(adhesion(&sc, 2.0, 0.1));
    let (m, g) = (sc.top.mass, sc.surface.gravity);
    let (fa, eb) = (sc.adhesion().force, sc.adhesion().energy);
    let p = 1.5 * (fa + m * g);
    let (t1, tau) = (0.1, 0.05);
    sc.forcing = load(-p, t1, t1 + tau);
    sc.solver.samples = 4001;
    let tr = run_as(&sc, ModelKind::Rigid);
    assert_eq!(spec::times(&tr, "lift_off").first(), Some(&t1));
    let mut worst = 0.0f64;
    let mut zmax = 0.0f64;
    for s in tr.samples.iter().filter(|s| s.t > t1 && s.t < t1 + tau) {
        let z = s.work_applied / p;
        zmax = zmax.max(z);
        let want = (p - m * g) * z + eb * (-fa * z / eb).exp_m1();
        let got = 0.5 * m * s.uz * s.uz;
        worst = worst.max((got - want).abs() / (p * z).max(f64::MIN_POSITIVE));
    }
    let s = &tr.summary;
    println!(
        "rigid pull-off: max |½ m v_z² − closed form| = {worst:.1e} of P z, z_max = {:.1} E_b/F_a, energy balance {:.1e}, J drift {:.1e}",
        zmax * fa / eb,
        s.energy_balance_max_rel_error,
        s.jellett_max_rel_drift
    );
    // The separation is complete within the window: z reaches many decay
    // lengths, so the potential's E_b is fully paid.
    assert!(zmax * fa / eb > 10.0, "z_max {zmax}");
    // The flight is integrated to rtol 1e-10 and W_a is its quadrature:
    // 1e-8 of the pull's work is 100x rtol. Without the potential the
    // kinetic energy would be off by E_b = 0.1 F_a R, i.e. by more than 2 %
    // of P z at the end of the window.
    assert!(worst <= 1e-8, "vertical energy off by {worst:e} of P z");
    // The energy includes U: the balance holds through lift-off, flight
    // and touchdown at the bar of the pull test without adhesion.
    assert!(s.energy_balance_max_rel_error <= 1e-8);
    assert!(s.jellett_max_rel_drift <= 1e-10);
}

/// The `nano-adhesive` preset (graphene adhesion, superlubric μ = 1e-3)
/// runs in every model with J and the energy balance at the usual nano
/// bars, and the contact reaction stays `F_a` up to the motion's own part,
/// which is of the order of the weight and the paper's H (8.5 m g per
/// component): `|N_c − F_a| <= 100 m g` (the adhesion is 5e13 m g).
#[test]
fn nano_adhesive_preset_holds_its_contact() {
    each_model(&[], |model| {
        let sc = Scenario::nano_adhesive();
        let tr = run_as(&sc, model);
        let s = &tr.summary;
        let w = sc.top.mass * sc.surface.gravity;
        let margin = s.pull_off_margin_min.expect("adhesion on");
        println!(
            "{model:?} nano-adhesive: J drift {:.1e}, energy balance {:.1e}, F_a − min N_c = {:.2} m g, rolling {}",
            s.jellett_max_rel_drift,
            s.energy_balance_max_rel_error,
            (sc.adhesion().force - margin) / w,
            s.rolling_fraction
        );
        assert!(s.jellett_max_rel_drift <= 1e-10, "{model:?}");
        assert!(s.energy_balance_max_rel_error <= 1e-8, "{model:?}");
        for r in &tr.samples {
            assert!(
                (r.normal - sc.adhesion().force).abs() <= 100.0 * w,
                "{model:?} t {}: N {}",
                r.t,
                r.normal
            );
        }
        // The slip (~R ω0 sin θ0 = 3.5e-9 m/s) dies at μ (g + F_a/m) ~ 5e11
        // m/s²: the top sticks within ~1e-20 s and rolls the whole window
        // (the friction capacity μ F_a is 4e12 |H|).
        assert!(
            s.rolling_fraction >= 1.0 - 1e-6,
            "{model:?}: {}",
            s.rolling_fraction
        );
        // Rolling, neither the friction nor H does work, so the energy
        // stays E0 ≈ ½ C ω0² = 2.5e-40 J; standing up to θ > π/2 would
        // raise the centre of mass by a (1 + cos θ0) and cost ~m g a =
        // 4e-34 J. No inversion.
        assert_eq!(s.first_time_theta_above_half_pi, None, "{model:?}");
    });
}
