//! Convergence of the simulated physics: RK4's order, the adaptive
//! method's error following rtol, the stiff method against the adaptive one,
//! the kink of μ|N| where the bilateral normal force changes sign.

use crate::spec::*;
use tippetop::{FrictionLaw, Method, ModelKind, Scenario, Trajectory};

/// The classical top over 0..0.04 s with the sliding law (before the first
/// zero slip, ~0.05 s, so the law is smooth there), two samples.
fn classical_short() -> Scenario {
    let mut sc = Scenario::classical();
    sc.surface.law = FrictionLaw::CoulombSliding;
    sc.solver.t_end = 0.04;
    sc.solver.samples = 2;
    sc
}

/// RK4 converges at order 4 on the classical top: halving the step divides
/// the error against an rtol-1e-13 reference by 13..19.
#[test]
fn rk4_order_four_classical() {
    each_model(&[], |m| {
        let sc = classical_short();
        let mut reference = sc.clone();
        reference.solver.rtol = 1e-13;
        let yref = *run(&reference, m).samples.last().unwrap();
        let mut errs = Vec::new();
        for steps in [200, 400, 800] {
            let mut s = sc.clone();
            s.solver.method = Method::Rk4;
            s.solver.steps = steps;
            let y = *run(&s, m).samples.last().unwrap();
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
    });
}

/// The adaptive method's error follows its rtol (at most 100 rtol, falling
/// from 1e-6 to 1e-10), and at tight settings RK4 and the adaptive method
/// agree to 1e-8 relative.
#[test]
fn adaptive_error_follows_rtol_and_agrees_with_rk4() {
    each_model(&[], |m| {
        let sc = classical_short();
        let mut reference = sc.clone();
        reference.solver.rtol = 1e-13;
        let yref = *run(&reference, m).samples.last().unwrap();
        let mut prev = f64::INFINITY;
        for rtol in [1e-6, 1e-8, 1e-10] {
            let mut s = sc.clone();
            s.solver.rtol = rtol;
            let y = *run(&s, m).samples.last().unwrap();
            let e = (y.theta - yref.theta)
                .abs()
                .max((y.spin - yref.spin).abs() / 100.0);
            assert!(e <= 100.0 * rtol, "rtol {rtol:e}: error {e:e}");
            assert!(e < prev, "rtol {rtol:e}: error {e:e} not below {prev:e}");
            prev = e;
        }
        let mut s = sc.clone();
        s.solver.method = Method::Rk4;
        s.solver.steps = 20000;
        let y = *run(&s, m).samples.last().unwrap();
        for (a, b, scale) in [
            (y.theta, yref.theta, 1.0),
            (y.spin, yref.spin, 100.0),
            (y.precession, yref.precession, 100.0),
        ] {
            assert!((a - b).abs() <= 1e-8 * scale, "{a} vs {b}");
        }
    });
}

/// `solver.method = "stiff"` (Rodas4P) on the classical preset with the
/// regularised law, ε = 1e-3 m/s, rtol 1e-10, 10 s: θ and ω agree with
/// DOP853 at every sample to 1e-6 of their largest values (reduced model:
/// 4.1e-8 and 5.8e-8: the two solve the same equations, each to its global
/// error); the energy balance closes to 1e-8.
///
/// Jellett's J holds to 1e-10 of C max|ω| R. Its drift is a global error
/// like any other: DOP853 meets the bar at rtol 1e-10 (8.0e-11, reduced);
/// Rodas4P, order 4 with a global error of ~6.7 tol on y'' = -y
/// (`tests/integrate`), drifts 1.3e-10 there, so the stiff run for the J
/// check uses rtol 1e-11 (the bar is not widened; the solver is run tighter).
#[test]
fn stiff_matches_adaptive_regularized() {
    let run_with = |m: ModelKind, method: Method, rtol: f64| -> Trajectory {
        let mut sc = classical_smooth(1e-3);
        sc.solver.method = method;
        sc.solver.rtol = rtol;
        let tr = run(&sc, m);
        let s = &tr.summary;
        println!(
            "{method:?} rtol {rtol:.0e}: {} steps, {} rejected, {} evals, theta_final {:.12}, \
             omega_final {:.12}, J drift {:.2e}, energy balance {:.2e}",
            s.steps,
            s.rejected_steps,
            s.rhs_evaluations,
            s.theta_final,
            s.omega_final,
            s.jellett_max_rel_drift,
            s.energy_balance_max_rel_error
        );
        tr
    };
    each_model(&[], |m| {
        let ad = run_with(m, Method::Adaptive, 1e-10);
        let st = run_with(m, Method::Stiff, 1e-10);
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
        println!(
            "max |Δθ| / max|θ| = {:.2e}, max |Δω| / max|ω| = {:.2e}",
            d_th / th_max,
            d_om / om_max
        );
        assert!(d_th <= 1e-6 * th_max, "theta: {d_th:e} vs {th_max}");
        assert!(d_om <= 1e-6 * om_max, "omega: {d_om:e} vs {om_max}");
        let s = &run_with(m, Method::Stiff, 1e-11).summary;
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
    });
}

/// Within a segment the models' right-hand sides do not depend on `t` (the
/// applied force is latched in `begin_segment`), so the stiff solver's
/// finite difference in `t` is exactly zero for them (module doc of
/// `integrate/rosenbrock.rs`). Checked with a force window switching at
/// t = 5 ms: the latched value holds whatever `t` is passed. (Needs the
/// models' types: the public `simulate` API has no access to a right-hand
/// side.)
#[test]
fn model_rhs_is_autonomous_within_a_segment() {
    use tippetop::integrate::OdeSystem;
    use tippetop::model::{reduced::Reduced as R, rigid::Rigid as G, vector::Vector as V};
    use tippetop::{ForceWindow, Forcing};
    let mut sc = classical_smooth(1e-3);
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
    fn check<S: OdeSystem<N>, const N: usize>(name: &str, mut m: S, y: [f64; N])
    where
        S::Error: std::fmt::Debug,
    {
        m.begin_segment(0.0, &y);
        let mut d0 = [0.0; N];
        m.rhs(0.0, &y, &mut d0).unwrap();
        for t in [0.0, 1e-4, 0.3, 7.0, 1e3] {
            let mut d = [0.0; N];
            m.rhs(t, &y, &mut d).unwrap();
            assert_eq!(d, d0, "{name}, t = {t}");
        }
    }
    let m = R::new(&sc);
    let y = m.scale_state(&sc.initial);
    check("reduced", m, y);
    let m = V::new(&sc);
    let y = m.scale_state(&sc.initial);
    check("vector", m, y);
    let m = G::new(&sc);
    let y = m.scale_state(&sc.initial);
    check("rigid", m, y);
}

/// The nano preset with `model` at `rtol` (its default exact law).
fn nano(model: ModelKind, rtol: f64) -> Trajectory {
    let mut sc = Scenario::nano();
    sc.solver.rtol = rtol;
    run(&sc, model)
}

fn max_theta_diff(a: &Trajectory, b: &Trajectory) -> f64 {
    assert_eq!(a.samples.len(), b.samples.len());
    a.samples
        .iter()
        .zip(&b.samples)
        .map(|(x, y)| (x.theta - y.theta).abs())
        .fold(0.0, f64::max)
}

/// The sign changes of N a run reports: (`contact_lost`, `contact_regained`).
fn crossings(tr: &Trajectory) -> (usize, usize) {
    (
        times(tr, "contact_lost").len(),
        times(tr, "contact_regained").len(),
    )
}

/// The kink of the friction μ|N| where the bilateral normal force changes
/// sign (docs/physics.md#normal-force): the drivers latch the branch of the closure,
/// stop at N = 0 and restart on the other branch from a step of the method,
/// so no step straddles the kink. The nano preset crosses N = 0 275 times
/// in 100 µs.
///
/// Two independent formulations (Euler angles and vector form) at rtol
/// 1e-13 give the same θ(t) to 1e-10 rad over the whole run and the same
/// `contact_lost` / `contact_regained` events; each model at the preset's
/// rtol 1e-10 is within 1e-7 rad in θ and 1e-6 of the scale in N of the
/// reference, with the same events. With the kink inside steps (friction
/// μ|N| evaluated on the consistent branch at every stage, no stop at N = 0)
/// the two references differed by 7.9e-9 rad and the rtol-1e-10 runs by
/// 8.1e-7 (Euler angles) and 1.3e-6 rad (vector form): a step across a kink
/// loses the method's order, whatever the tolerance. The rigid model without
/// the latched branch was 1.0e-6 rad and 8.1e-6 off; with it 3.4e-8 rad and
/// 2.6e-7 (the vector form: 2.6e-8 rad and 2.1e-7).
#[test]
fn nano_converges_through_the_normal_force_sign_changes() {
    let ref_r = nano(Reduced, 1e-13);
    let ref_v = nano(Vector, 1e-13);
    let d_ref = max_theta_diff(&ref_r, &ref_v);
    println!("references differ by {d_ref:.2e} rad");
    assert!(d_ref <= 1e-10, "references differ by {d_ref:e} rad");
    assert_eq!(crossings(&ref_r), crossings(&ref_v));
    let (lost, regained) = crossings(&ref_r);
    assert!(lost + regained > 200, "{lost} + {regained} sign changes");
    let n_scale = ref_r
        .samples
        .iter()
        .map(|s| s.normal.abs())
        .fold(0.0, f64::max);
    each_model(&[], |m| {
        let tr = nano(m, 1e-10);
        let d = max_theta_diff(&tr, &ref_r);
        let d_n = tr
            .samples
            .iter()
            .zip(&ref_r.samples)
            .map(|(a, b)| (a.normal - b.normal).abs())
            .fold(0.0, f64::max)
            / n_scale;
        println!("at rtol 1e-10: theta {d:.2e} rad, N {d_n:.2e} of its scale");
        assert!(d <= 1e-7, "θ off by {d:e} rad");
        assert!(d_n <= 1e-6, "N differs by {d_n:e} of its scale");
        assert_eq!(crossings(&tr), crossings(&ref_r));
    });
}

/// No step straddles a kink: with the branch latched DOP853 rejects few
/// attempts on nano at rtol 1e-10. Measured: 10 % with the Euler angles,
/// whose 1/sin θ adds its own; 0.4 % in vector form; rigid 10 of 2 582
/// (0.39 %; 36 % before the latched branch, 5.9 % with the latched branch
/// and the body-frame state, docs/physics.md#rigid-model). Evaluating μ|N| on the
/// consistent branch at every stage rejected 35 % and 36 % of the attempts
/// (Euler angles, vector form): every crossing cost a cascade of rejections.
/// The bound is each model's own measured share with margin (issue #13's
/// bar for the rigid model is 5 %).
#[test]
fn no_step_straddles_a_normal_force_kink() {
    each_model(&[], |m| {
        let bound = match m {
            Reduced => 0.2,
            Vector | Rigid => 0.02,
        };
        let s = nano(m, 1e-10).summary;
        let frac = s.rejected_steps as f64 / (s.steps + s.rejected_steps) as f64;
        println!(
            "{} of {} attempts rejected",
            s.rejected_steps,
            s.steps + s.rejected_steps
        );
        assert!(frac < bound, "{frac:.3} of the attempts rejected");
    });
}

/// The regularised classical top (ε = 1e-3 m/s, slip relaxing at
/// ≈ 2 950 s⁻¹) holds DOP853 at its stability limit; with the stability cap
/// (`vector::DOP853_STABILITY_CAP`) under 2 % of the attempts are rejected
/// (measured: 32 of 4 317); without it 27 % were (1 647 of 6 027), and the
/// step count stays near the limit `10 s · 2 950 s⁻¹ / 6.1` ≈ 4 800.
#[test]
fn stability_limited_run_without_rejection_cascades() {
    let only_vector = "the DOP853 stability cap is the vector model's step-control hint";
    let filters = [cannot(Reduced, only_vector), cannot(Rigid, only_vector)];
    each_model(&filters, |m| {
        let mut sc = classical_smooth(1e-3);
        sc.solver.rtol = 1e-8;
        let s = run(&sc, m).summary;
        let attempts = s.steps + s.rejected_steps;
        println!("{} steps, {} rejected", s.steps, s.rejected_steps);
        assert!(s.rejected_steps * 50 < attempts, "{s:?}");
        assert!((3_500..6_000).contains(&s.steps), "{} steps", s.steps);
    });
}
