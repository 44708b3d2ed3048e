//! The regime ratios against hand computations for both presets (the
//! numbers below were computed by hand from the presets' parameters and
//! k_B = 1.380649e-23 J/K, ħ = 1.054571817e-34 J s, τ = 9.1 ps; they agree
//! with the rounded figures of shared/research/nano-physics.md §1.1 and §2:
//! H/mg 8.5 per component, E_rot/kT 6e-20, ω/ω_th 3.5e-10, L/ħ 5e-8).

use tippetop::Scenario;
use tippetop::analysis::regime::{lines, max_applied_force, of_run, regime};

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-4 * b.abs()
}

/// Nano preset: m = 1.196e-24 kg, R = 3.55e-10 m, A = (2/3) m R²,
/// C = A/2 = 5.0242e-44 kg m², ω0 = 100 rad/s, μ = 0.13, g = 9.8 m/s²,
/// H = (1e-22, 1e-22) N from t = 0 (|H| = 1.41421e-22 N), t_end = 1e-4 s.
#[test]
fn nano_preset_by_hand() {
    let sc = Scenario::nano();
    assert!(close(max_applied_force(&sc), 1.414214e-22));
    let r = regime(&sc, Some(300.0)).unwrap();
    assert_eq!(r.adhesion_over_weight, None);
    // |H|/(m g) = 1.41421e-22 / 1.17208e-23.
    assert!(close(r.applied_over_weight.unwrap(), 12.06585));
    // |H|/(μ m g) = 12.06585 / 0.13.
    assert!(close(r.applied_over_friction_capacity.unwrap(), 92.81419));
    // ½ C ω0² / kT = 2.51210e-40 J / 4.14195e-21 J.
    assert!(close(r.rotational_energy_over_kt.unwrap(), 6.065018e-20));
    // ω0 / √(kT/C) = 100 / 2.87125e11.
    assert!(close(r.spin_over_thermal_spin.unwrap(), 3.482820e-10));
    // C ω0/ħ = 5.02420e-42 / 1.05457e-34.
    assert!(close(r.angular_momentum_over_hbar, 4.764205e-8));
    // 1e-4 s / 9.1e-12 s.
    assert!(close(
        r.window_over_orientation_correlation_time.unwrap(),
        1.098901e7
    ));
    let table = lines(&sc, &r);
    let verdict = |k: &str| &table.iter().find(|l| l.key == k).unwrap().verdict;
    assert!(verdict("applied_over_weight").contains("lift-off"));
    assert!(verdict("applied_over_friction_capacity").contains("slides"));
    assert!(verdict("angular_momentum_over_hbar").contains("questionable"));
    assert!(verdict("rotational_energy_over_kT").contains("buries"));
    assert!(verdict("adhesion_over_weight").contains("tippetop adhesion"));
    let classical = Scenario::classical();
    let table = lines(&classical, &regime(&classical, None).unwrap());
    let verdict = |k: &str| &table.iter().find(|l| l.key == k).unwrap().verdict;
    assert!(!verdict("adhesion_over_weight").contains("C60"));
    assert_eq!(verdict("applied_over_weight"), "no applied force");
    assert!(verdict("angular_momentum_over_hbar").contains("fine"));
}

/// Classical preset: m = 0.015 kg, C = 0.4 m R² = 1.35e-6 kg m², ω0 = 100
/// rad/s, no applied force, t_end = 10 s.
#[test]
fn classical_preset_by_hand() {
    let sc = Scenario::classical();
    let r = regime(&sc, Some(300.0)).unwrap();
    assert_eq!(r.applied_over_weight, Some(0.0));
    assert_eq!(r.applied_over_friction_capacity, Some(0.0));
    assert!(close(r.rotational_energy_over_kt.unwrap(), 1.629668e18));
    assert!(close(r.spin_over_thermal_spin.unwrap(), 1.805363e9));
    assert!(close(r.angular_momentum_over_hbar, 1.280140e30));
    assert!(close(
        r.window_over_orientation_correlation_time.unwrap(),
        1.098901e12
    ));
}

/// Without a temperature (or at T = 0) the thermal ratios are undefined;
/// the others stay. A bad temperature names itself.
#[test]
fn thermal_ratios_need_a_temperature() {
    let sc = Scenario::nano();
    for t in [None, Some(0.0)] {
        let r = regime(&sc, t).unwrap();
        assert_eq!(r.rotational_energy_over_kt, None);
        assert_eq!(r.spin_over_thermal_spin, None);
        assert_eq!(r.window_over_orientation_correlation_time, None);
        assert!(r.applied_over_weight.is_some());
    }
    for bad in [-1.0, f64::NAN, f64::INFINITY, 1e6] {
        let e = regime(&sc, Some(bad)).unwrap_err();
        assert!(e.to_string().starts_with("temperature: "), "{e}");
    }
}

/// The largest applied force follows the schedule exactly: windows that
/// add, and a window that starts after t_end does not count.
#[test]
fn max_applied_force_follows_the_schedule() {
    let sc = Scenario::load(
        Some("nano"),
        None,
        &[
            "force.0.hx=0".into(),
            "force.0.hy=1e-22".into(),
            "force.0.stop=5e-5".into(),
            "force.1.hx=3e-22".into(),
            "force.1.hy=0".into(),
            "force.1.start=2e-5".into(),
            "force.2.hx=1e-20".into(),
            "force.2.hy=0".into(),
            "force.2.start=2e-4".into(),
        ],
    )
    .unwrap();
    // On [2e-5, 5e-5): (3e-22, 1e-22), |H| = √10 e-22; the third window
    // starts after t_end = 1e-4 s.
    assert!(close(max_applied_force(&sc), 10f64.sqrt() * 1e-22));
}

/// Nano preset with the graphene adhesion of `tippetop adhesion`
/// (F_a = 5.9159e-10 N, E_b = 0.73 eV): F_a/(m g) = 5.9159e-10 / 1.17208e-23
/// = 5.04735e13 (nano-physics.md#kinematics: ~5e13), and the friction capacity
/// μ (m g + F_a) = 0.13 × 5.91590e-10 N = 7.69067e-11 N, so
/// |H| / capacity = 1.41421e-22 / 7.69067e-11 = 1.83889e-12.
#[test]
fn nano_preset_with_adhesion_by_hand() {
    let mut sc = Scenario::nano();
    sc.set_adhesion(tippetop::Adhesion {
        force: 5.9159e-10,
        energy: 0.73 * 1.602176634e-19,
    });
    let r = regime(&sc, None).unwrap();
    assert!(close(r.adhesion_over_weight.unwrap(), 5.04735e13));
    assert!(close(
        r.applied_over_friction_capacity.unwrap(),
        1.83889e-12
    ));
    let table = lines(&sc, &r);
    let verdict = |k: &str| &table.iter().find(|l| l.key == k).unwrap().verdict;
    assert!(verdict("adhesion_over_weight").contains("dominates the weight"));
}

/// A run's regime is at its own temperature: `nano-physical` (300 K) has
/// the thermal ratios at 300 K, the deterministic presets none.
#[test]
fn a_runs_regime_is_at_its_own_temperature() {
    let hot = Scenario::nano_physical();
    assert_eq!(hot.thermal.temperature, 300.0);
    assert_eq!(of_run(&hot), regime(&hot, Some(300.0)).unwrap());
    assert!(close(
        of_run(&hot).rotational_energy_over_kt.unwrap(),
        6.065018e-20
    ));
    for sc in [Scenario::nano(), Scenario::classical()] {
        let r = of_run(&sc);
        assert_eq!(r.temperature, None);
        assert_eq!(r, regime(&sc, None).unwrap());
    }
}
