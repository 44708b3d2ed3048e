//! `solver.method = "stiff"` (Rodas4P) on the classical preset with the
//! regularised friction law: the same solution as DOP853, Jellett's J
//! conserved, the energy balance closed.

use tippetop::{FrictionLaw, Method, Scenario, Trajectory, simulate};

fn run(method: Method, eps: f64, rtol: f64, t_end: f64) -> Trajectory {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Regularized { eps };
    sc.solver.method = method;
    sc.solver.rtol = rtol;
    sc.solver.t_end = t_end;
    let tr = simulate(&sc).expect("valid scenario");
    assert!(tr.error.is_none(), "{method:?}: run failed: {:?}", tr.error);
    let s = &tr.summary;
    eprintln!(
        "{method:?} eps {eps:.0e} rtol {rtol:.0e}: {} steps, {} rejected, {} evals, \
         theta_final {:.12}, omega_final {:.12}, J drift {:.2e}, \
         energy balance {:.2e}",
        s.steps,
        s.rejected_steps,
        s.rhs_evaluations,
        s.theta_final,
        s.omega_final,
        s.jellett_max_rel_drift,
        s.energy_balance_max_rel_error
    );
    tr
}

/// ε = 1e-3 m/s, rtol 1e-10, 10 s: θ and ω agree with DOP853 at every
/// sample to 1e-6 of their largest values (observed 4.1e-8 and 5.8e-8: the
/// two solve the same equations, each to its global error); the energy
/// balance closes to 1e-8 (observed 1.1e-10).
///
/// Jellett's J holds to the same bar as for the reduced model's presets,
/// 1e-10 of C max|ω| R. Its drift is a global error like any other: DOP853
/// meets the bar at rtol 1e-10 (8.0e-11); Rodas4P, order 4 with a global
/// error of ~6.7 tol on y'' = -y (`integrate_rosenbrock`), drifts 1.3e-10
/// there, so the stiff run for the J check uses rtol 1e-11 (the bar is
/// not widened; the solver is run tighter).
#[test]
fn stiff_matches_adaptive_regularized() {
    let ad = run(Method::Adaptive, 1e-3, 1e-10, 10.0);
    let st = run(Method::Stiff, 1e-3, 1e-10, 10.0);
    assert_eq!(ad.samples.len(), st.samples.len());
    let th_max = ad.samples.iter().map(|s| s.theta.abs()).fold(0.0, f64::max);
    let om_max = ad.samples.iter().map(|s| s.spin.abs()).fold(0.0, f64::max);
    let mut d_th: f64 = 0.0;
    let mut d_om: f64 = 0.0;
    for (a, b) in ad.samples.iter().zip(&st.samples) {
        assert_eq!(a.t, b.t);
        d_th = d_th.max((a.theta - b.theta).abs());
        d_om = d_om.max((a.spin - b.spin).abs());
    }
    eprintln!(
        "max |Δθ| / max|θ| = {:.2e}, max |Δω| / max|ω| = {:.2e}",
        d_th / th_max,
        d_om / om_max
    );
    assert!(d_th <= 1e-6 * th_max, "theta: {d_th:e} vs {th_max}");
    assert!(d_om <= 1e-6 * om_max, "omega: {d_om:e} vs {om_max}");
    let s = &run(Method::Stiff, 1e-3, 1e-11, 10.0).summary;
    assert!(
        s.jellett_max_rel_drift <= 1e-10,
        "J {:e}",
        s.jellett_max_rel_drift
    );
    assert!(
        s.energy_balance_max_rel_error <= 1e-8,
        "energy {:e}",
        s.energy_balance_max_rel_error
    );
}

/// Within a segment the models' right-hand sides do not depend on `t` (the
/// applied force is latched in `begin_segment`), so the stiff solver's
/// finite difference in `t` is exactly zero for them (module doc of
/// `integrate/rosenbrock.rs`). Checked with a force window switching at
/// t = 5 ms: the latched value holds whatever `t` is passed.
#[test]
fn model_rhs_is_autonomous_within_a_segment() {
    use tippetop::integrate::OdeSystem;
    use tippetop::model::{reduced::Reduced, rigid::Rigid};
    use tippetop::{ForceWindow, Forcing};
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::Regularized { eps: 1e-3 };
    sc.initial.ux = 0.01;
    sc.forcing = Forcing {
        windows: vec![ForceWindow {
            hx: 1e-3,
            hy: -2e-3,
            hz: 0.0,
            start: 0.0,
            stop: 5e-3,
        }],
    };
    sc.validate().unwrap();
    let ts = [0.0, 1e-4, 0.3, 7.0, 1e3];

    let mut m = Reduced::new(&sc);
    let y = m.scale_state(&sc.initial);
    m.begin_segment(0.0, &y);
    let mut d0 = [0.0; 8];
    m.rhs(0.0, &y, &mut d0).unwrap();
    for t in ts {
        let mut d = [0.0; 8];
        m.rhs(t, &y, &mut d).unwrap();
        assert_eq!(d, d0, "reduced, t = {t}");
    }

    let mut m = Rigid::new(&sc);
    let y = m.scale_state(&sc.initial);
    m.begin_segment(0.0, &y);
    let mut d0 = [0.0; tippetop::model::rigid::DIM];
    m.rhs(0.0, &y, &mut d0).unwrap();
    for t in ts {
        let mut d = [0.0; tippetop::model::rigid::DIM];
        m.rhs(t, &y, &mut d).unwrap();
        assert_eq!(d, d0, "rigid, t = {t}");
    }
}
