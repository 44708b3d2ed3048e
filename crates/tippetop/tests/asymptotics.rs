//! App. C: the asymptotic laws, their fit, and the paper's algebra for v(t).

use tippetop::{
    Sample, Scenario,
    analysis::asymptotics::{self as asy, LyingParams, UxyConstants},
    simulate,
};

fn sample(t: f64, omega: f64, precession: f64, ux: f64, uy: f64) -> Sample {
    Sample {
        t,
        theta: std::f64::consts::FRAC_PI_2,
        theta_dot: 0.0,
        precession,
        spin: omega,
        ux,
        uy,
        uz: 0.0,
        normal: 0.0,
        slip: 0.0,
        jellett: 0.0,
        energy: 0.0,
        work_friction: 0.0,
        work_applied: 0.0,
        hx: 0.0,
        hy: 0.0,
        rolling: 0,
        x: 0.0,
        y: 0.0,
        z: 0.0,
        qw: 1.0,
        qx: 0.0,
        qy: 0.0,
        qz: 0.0,
        xp: 0.0,
        yp: 0.0,
    }
}

fn nano_params() -> LyingParams {
    LyingParams::of(&Scenario::nano(), 0.0)
}

#[test]
fn synthetic_closed_form_is_recovered_exactly() {
    let p = nano_params();
    let c1 = -1.234567e6;
    let k = UxyConstants {
        t_star: 5e-5,
        u1: 1e-6,
        u2: -3e-3,
        c1,
    };
    let samples: Vec<Sample> = (0..=1000)
        .map(|i| {
            let t = 1e-4 * i as f64 / 1000.0;
            let (ux, uy) = asy::uxy(&p, &k, t);
            sample(
                t,
                asy::omega_c2(&p, c1, t),
                asy::precession_c3(&p, c1, t),
                ux,
                uy,
            )
        })
        .collect();
    let fit = asy::fit_c1(&samples, &p, 5e-5, 1e-4);
    assert!(
        (fit.c1 - c1).abs() <= 1e-12 * c1.abs(),
        "c1 {} vs {c1}",
        fit.c1
    );
    assert!((fit.slope_free / p.slope() - 1.0).abs() < 1e-9);
    let rep = asy::analyse(&samples, &p, 5e-5, 1e-4, 5e-5);
    for e in [
        rep.c2_fitted,
        rep.c3_fitted,
        rep.ux_numerics,
        rep.uy_numerics,
    ] {
        assert!(e.rel < 1e-9, "{e:?}");
        assert_eq!(e.undefined, 0);
    }
}

#[test]
fn paper_closed_form_for_v_solves_its_ode() {
    // v̇ + i R H v/(c1 C − R H t) = −(H/m)(1 + i), integrated with RK4,
    // against the paper's closed form (paper's constants).
    let p = nano_params();
    let k = UxyConstants::paper();
    let (r, h, m) = (p.radius, p.h, p.mass);
    let f = |t: f64, v: (f64, f64)| -> (f64, f64) {
        let kk = r * h / p.d(k.c1, t);
        // −i kk v − (H/m)(1 + i)
        (kk * v.1 - h / m, -kk * v.0 - h / m)
    };
    let (t0, t1) = (k.t_star, 1e-4);
    let n = 20000;
    let dt = (t1 - t0) / n as f64;
    let mut v = (k.u1, k.u2);
    let mut t = t0;
    let mut max_err: f64 = 0.0;
    let mut max_v: f64 = 0.0;
    for _ in 0..n {
        let k1 = f(t, v);
        let k2 = f(t + dt / 2.0, (v.0 + dt / 2.0 * k1.0, v.1 + dt / 2.0 * k1.1));
        let k3 = f(t + dt / 2.0, (v.0 + dt / 2.0 * k2.0, v.1 + dt / 2.0 * k2.1));
        let k4 = f(t + dt, (v.0 + dt * k3.0, v.1 + dt * k3.1));
        v.0 += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
        v.1 += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
        t += dt;
        let (ux, uy) = asy::uxy(&p, &k, t);
        max_err = max_err.max((ux - v.0).abs()).max((uy - v.1).abs());
        max_v = max_v.max(v.0.hypot(v.1));
    }
    eprintln!("closed form vs RK4: max |error| {max_err:e} m/s, max |v| {max_v:e} m/s");
    assert!(
        max_err <= 1e-8 * max_v,
        "max err {max_err:e} vs |v| {max_v:e}"
    );
    // Also across a window that contains the pole of (C3) with a small c1:
    // the closed form is NaN there, and the law is only asserted on one side.
    let kpole = UxyConstants { c1: 1e6, ..k };
    let tp = asy::c3_pole_time(&p, kpole.c1);
    assert!(tp > 0.0 && tp < k.t_star);
    assert!(asy::uxy(&p, &kpole, 0.5 * tp).0.is_nan());
}

#[test]
fn nano_paper_run_lying_laws() {
    let sets: Vec<String> = [
        "surface.contact=\"paper\"",
        "surface.friction_law=\"coulomb_sliding\"",
    ]
    .iter()
    .map(|s| s.to_string())
    .collect();
    let sc = Scenario::load(Some("nano"), None, &sets).unwrap();
    let tr = simulate(&sc).unwrap();
    assert!(tr.error.is_none(), "{:?}", tr.error);
    let p = LyingParams::of(&sc, 0.0);
    let t_end = sc.solver.t_end;
    let rep = asy::analyse(&tr.samples, &p, 0.5 * t_end, t_end, asy::PAPER_T_STAR);
    eprintln!(
        "fit: c1 = {:.6e}, free slope = {:.6e} ({:.4} x -RH/C = {:.6e}); theta - pi/2 = {:+.4} +- {:.4}",
        rep.fit.c1,
        rep.fit.slope_free,
        rep.slope_ratio,
        rep.fit.slope_theory,
        rep.theta_offset,
        rep.theta_amplitude
    );
    eprintln!(
        "errors: C2 fit {:.3e} paper {:.3e}; C3 fit {:.3e} paper {:.3e}; ux num {:.3e} paper {:.3e}; uy num {:.3e} paper {:.3e}; poles {:.4e} {:.4e}",
        rep.c2_fitted.rel,
        rep.c2_paper.rel,
        rep.c3_fitted.rel,
        rep.c3_paper.rel,
        rep.ux_numerics.rel,
        rep.ux_paper.rel,
        rep.uy_numerics.rel,
        rep.uy_paper.rel,
        rep.c3_pole_fitted,
        rep.c3_pole_paper
    );
    for t in &rep.text {
        eprintln!("{t}");
    }
    // The free slope is close to −R H/C: within 10 % (1.065 at rtol 1e-10;
    // the neglected friction, μ⟨|N|⟩/H ≈ 0.1–0.3, makes it steeper).
    assert!(
        (rep.slope_ratio - 1.0).abs() < 0.1,
        "slope ratio {}",
        rep.slope_ratio
    );
    assert!(rep.friction_over_drive > 0.01);
    // The top lies below π/2 (towards arccos(a/R)), not at π/2.
    assert!(rep.theta_offset < -0.05 && rep.theta_offset > -0.15);
    // u closed form with u1, u2 from the numerics equals the numerics at t*.
    let k = rep.uxy_numerics;
    let (ux, uy) = asy::uxy(&p, &k, k.t_star);
    assert!(
        (ux - k.u1).abs() <= 1e-12 * k.u1.abs().max(1e-30),
        "{ux} vs {}",
        k.u1
    );
    assert!((uy - k.u2).abs() <= 1e-12 * k.u2.abs(), "{uy} vs {}", k.u2);
    assert_eq!(k.u1, asy::interp(&tr.samples, k.t_star, |s| s.ux));
    // (C2) with the fitted c1 is good to a few per cent over the window.
    assert!(rep.c2_fitted.rel < 0.05, "{:?}", rep.c2_fitted);
}
