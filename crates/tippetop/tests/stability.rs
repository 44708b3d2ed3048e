//! Stability analysis (App. B): the axis-vector model against the reduced
//! model, the linearisation against analytic characteristic polynomials, the
//! sleeping-top threshold, and the classical top's verdicts.

use tippetop::{
    FrictionLaw, Scenario, Top,
    analysis::stability::{self, Physics, SmoothLaw, Verdict},
    model::reduced::{Reduced, TH},
};

fn classical_physics(mu: f64, eps: f64) -> Physics {
    Physics {
        top: Top::classical(),
        gravity: 9.8,
        mu,
        law: SmoothLaw::Regularized,
        eps,
    }
}

#[test]
fn axis_model_matches_reduced_model() {
    for (preset, eps) in [("classical", 0.02), ("nano", 1e-7)] {
        let mut sc = Scenario::preset(preset).unwrap();
        sc.surface.law = FrictionLaw::Regularized { eps };
        sc.forcing = tippetop::Forcing::none();
        // The axis model uses N with its sign (the paper's contact); states
        // with N < 0 are included on purpose.
        sc.surface.contact = tippetop::ContactMode::Paper;
        let m = Reduced::new(&sc);
        let (tu, vu) = (m.scales.time, m.scales.velocity());
        let ph = Physics {
            top: sc.top,
            gravity: sc.surface.gravity,
            mu: sc.surface.friction,
            law: SmoothLaw::Regularized,
            eps,
        };
        for (th, thd, om, w, ux, uy) in [
            (0.7, 3.0, 20.0, 90.0, 0.01, -0.02),
            (2.3, -1.0, -15.0, 60.0, -0.03, 0.005),
            (1.5, 0.5, 5.0, -40.0, 0.0, 0.0),
        ] {
            let f = 1.0 / tu;
            let ysi = [th, thd * f, om * f, w * f, ux * vu, uy * vu];
            let mut y = [0.0; 8];
            y[TH] = th;
            for i in 1..4 {
                y[i] = ysi[i] * tu;
            }
            y[4] = ysi[4] / vu;
            y[5] = ysi[5] / vu;
            let e = m.eval(&y).unwrap();
            let d = stability::axis_model_derivatives(&ph, ysi);
            let acc = 1.0 / (tu * tu);
            let checks = [
                (d.theta_ddot, e.dy[1] * acc),
                (d.precession_dot, e.dy[2] * acc),
                (d.spin_dot, e.dy[3] * acc),
                (d.ux_dot, e.dy[4] * vu / tu),
                (d.uy_dot, e.dy[5] * vu / tu),
                (d.normal, e.normal * m.scales.force()),
            ];
            let scale_acc = (w * f).powi(2).max(1.0 / tu / tu);
            for (i, (a, b)) in checks.iter().enumerate() {
                let sc_ = match i {
                    0..=2 => scale_acc,
                    3 | 4 => scale_acc * sc.top.radius,
                    _ => scale_acc * sc.top.radius * sc.top.mass,
                };
                assert!(
                    (a - b).abs() <= 1e-10 * sc_,
                    "{preset} component {i}: axis {a:e} reduced {b:e}"
                );
            }
        }
    }
}
