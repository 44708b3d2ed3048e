//! The initial state from lab-frame vectors (`initial.axis`,
//! `initial.angular_velocity`, `initial.velocity`) and the heading
//! (`initial.heading`): the conversion against its inverse and closed-form
//! cases, and the isotropy of the plane: a run turned by a heading about Z
//! is the same run, its positions and attitudes turned (every model).

use super::spec::{each_model, run};
use tippetop::{Initial, ModelKind, Scenario};

/// `from_lab(to_lab(i)) == i` to rounding over a spread of states (θ away
/// from the poles, where the heading is defined by the axis).
#[test]
fn lab_vectors_round_trip() {
    let mut x: u64 = 0x2545_F491_4F6C_DD1D;
    let mut rnd = || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    for _ in 0..1000 {
        let i = Initial {
            theta: 0.05 + 3.0 * rnd(),
            theta_dot: 10.0 * (rnd() - 0.5),
            precession: 10.0 * (rnd() - 0.5),
            spin: 200.0 * (rnd() - 0.5),
            ux: rnd() - 0.5,
            uy: rnd() - 0.5,
            heading: 6.0 * (rnd() - 0.5),
        };
        let (k, n, v) = i.to_lab();
        let j = Initial::from_lab(k, n, v).expect("valid");
        // Each value is a few roundings of sums of products of magnitude
        // up to |ω| + |Ω| + |θ̇| (the angular velocity) or |u|: 1e-13 of
        // that scale; the heading to 1e-13 rad, wrapped.
        let rate = i.spin.abs() + i.precession.abs() + i.theta_dot.abs();
        let speed = i.ux.abs() + i.uy.abs();
        assert!((j.theta - i.theta).abs() <= 1e-14, "{i:?} -> {j:?}");
        let dh = (j.heading - i.heading).rem_euclid(std::f64::consts::TAU);
        assert!(
            dh.min(std::f64::consts::TAU - dh) <= 1e-13,
            "{i:?} -> {j:?}"
        );
        for (a, b, scale) in [
            (j.theta_dot, i.theta_dot, rate),
            (j.spin, i.spin, rate),
            // Ω = (n_Z − ω c)/s²: the division by s² (s >= sin 0.05)
            // amplifies the rounding by up to 1/s² ≈ 400.
            (j.precession, i.precession, 400.0 * rate),
            (j.ux, i.ux, speed),
            (j.uy, i.uy, speed),
        ] {
            assert!((a - b).abs() <= 1e-13 * scale, "{i:?} -> {j:?}");
        }
    }
}

/// Closed forms: the axis tilted towards +Y is heading π/2; the vertical
/// axis takes the heading that puts the horizontal angular velocity along
/// ŷ (θ̇ = |n_h|, Ω = 0, ω = n_Z); the axis is normalised.
#[test]
fn lab_vectors_closed_forms() {
    let i = Initial::from_lab([0.0, 2.0, 2.0], [0.0, 0.0, 10.0], [1.0, 0.0]).unwrap();
    assert!((i.theta - std::f64::consts::FRAC_PI_4).abs() <= 1e-15);
    assert!((i.heading - std::f64::consts::FRAC_PI_2).abs() <= 1e-15);
    // ω = n·k = 10 cos 45°; Ω = (n_Z − ω c)/s² = (10 − 5)/0.5 = 10.
    assert!((i.spin - 10.0 * 0.5f64.sqrt()).abs() <= 1e-14);
    assert!((i.precession - 10.0).abs() <= 1e-13);
    assert!(i.theta_dot.abs() <= 1e-15);
    // v = X: along −ŷ (ŷ = Z × x̂ = −X for x̂ = Y).
    assert!(i.ux.abs() <= 1e-16 && (i.uy + 1.0).abs() <= 1e-15, "{i:?}");
    let p = Initial::from_lab([0.0, 0.0, 3.0], [0.3, 0.4, 100.0], [0.0, 0.0]).unwrap();
    assert_eq!(p.theta, 0.0);
    assert!((p.theta_dot - 0.5).abs() <= 1e-15);
    assert_eq!(p.spin, 100.0);
    assert_eq!(p.precession, 0.0);
    // ŷ = n_h/|n_h| = (0.6, 0.8): x̂ = (0.8, −0.6), heading atan2(−0.6, 0.8).
    assert!((p.heading - (-0.6f64).atan2(0.8)).abs() <= 1e-15);
    for bad in [[0.0; 3], [f64::NAN, 0.0, 1.0]] {
        let e = Initial::from_lab(bad, [0.0; 3], [0.0; 2]).unwrap_err();
        assert!(e.to_string().starts_with("initial.axis: "), "{e}");
    }
}

/// The scenario keys: the lab form replaces the preset's Euler-angle form;
/// a file that mixes them, an Euler key after a lab key, and
/// `angular_velocity` or `velocity` without `axis` are errors naming the key.
#[test]
fn lab_form_scenario_keys() {
    let sc = Scenario::load(
        Some("classical"),
        None,
        &[
            "initial.axis=[0.0, 0.479425538604203, 0.8775825618903728]".into(),
            "initial.angular_velocity=[0, 0, 100]".into(),
        ],
    )
    .expect("valid");
    assert!((sc.initial.theta - 0.5).abs() <= 1e-15);
    assert!((sc.initial.heading - std::f64::consts::FRAC_PI_2).abs() <= 1e-15);
    let err = |toml: Option<&str>, sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        Scenario::load(Some("classical"), toml, &sets)
            .expect_err("invalid")
            .to_string()
    };
    let e = err(Some("[initial]\ntheta = 0.5\naxis = [0, 0, 1]\n"), &[]);
    assert!(
        e.starts_with("initial.theta: cannot be combined with initial.axis"),
        "{e}"
    );
    let e = err(None, &["initial.axis=[0,0,1]", "initial.spin=5"]);
    assert!(
        e.starts_with("initial.spin: cannot be combined with initial.axis"),
        "{e}"
    );
    let e = err(None, &["initial.velocity=[1, 0]"]);
    assert!(
        e.starts_with("initial.velocity: given without initial.axis"),
        "{e}"
    );
    let e = err(None, &["initial.axis=[0, 0]"]);
    assert!(
        e.starts_with("initial.axis: expected an array of 3 numbers"),
        "{e}"
    );
    let e = err(None, &["initial.axis=[0, 0, 0]"]);
    assert!(e.starts_with("initial.axis: "), "{e}");
    // The resolved scenario (scenario.toml) is the Euler form with the
    // heading, and reads back to the same state.
    let back = Scenario::from_toml_str(&sc.to_toml_string()).expect("round trip");
    assert_eq!(back.initial, sc.initial);
}

/// A run turned by a heading about Z is the same run (the plane is
/// isotropic and the applied force lives in the precessing frame): every
/// column up to `rolling` agrees, and the positions, contact points and
/// attitudes are the unturned ones turned by the heading. The reduced model
/// carries the heading only in its φ quadrature, so its first 17 columns
/// are bit-identical. The vector and rigid models start from turned
/// vectors, and DOP853 weighs each component by its own size, which is not
/// invariant under a rotation: the step sequences differ, so the two runs
/// agree to their integration error at rtol 1e-10, not to rounding
/// (measured: positions 3e-9 of the scale on the classical top). Bar: 1e-7
/// of each quantity's scale, inside the 1e-6 of the models' cross-checks;
/// θ within 2e-7 rad: each run is within 1e-7 rad of the rtol-1e-13
/// reference on nano (`convergence::nano_converges_through_the_normal_force_sign_changes`),
/// so two of them are within 2e-7.
#[test]
fn a_turned_run_is_the_same_run() {
    let alpha = 0.7f64;
    let (sa, ca) = alpha.sin_cos();
    let (ha_s, ha_c) = (0.5 * alpha).sin_cos();
    for (name, base) in [
        ("classical 1 s", classical_1s()),
        ("nano", Scenario::nano()),
    ] {
        each_model(&[], |m| {
            let mut turned = base.clone();
            turned.initial.heading = alpha;
            let a = run(&base, m);
            let b = run(&turned, m);
            assert_eq!(a.samples.len(), b.samples.len());
            let scale = |f: fn(&tippetop::Sample) -> f64| {
                a.samples.iter().map(|s| f(s).abs()).fold(0.0, f64::max)
            };
            let (xs, ws) = (
                scale(|s| s.x.hypot(s.y)).max(base.top.radius),
                scale(|s| s.spin),
            );
            for (p, q) in a.samples.iter().zip(&b.samples) {
                if m == ModelKind::Reduced {
                    assert_eq!(
                        (
                            p.theta,
                            p.theta_dot,
                            p.precession,
                            p.spin,
                            p.ux,
                            p.uy,
                            p.normal
                        ),
                        (
                            q.theta,
                            q.theta_dot,
                            q.precession,
                            q.spin,
                            q.ux,
                            q.uy,
                            q.normal
                        ),
                        "{name}"
                    );
                }
                assert!(
                    (p.theta - q.theta).abs() <= 2e-7,
                    "{name}: theta at {}: {:e}",
                    p.t,
                    (p.theta - q.theta).abs()
                );
                assert!(
                    (p.spin - q.spin).abs() <= 1e-7 * ws,
                    "{name}: spin at {}",
                    p.t
                );
                // Turned positions and contact points.
                for ((x0, y0), (x1, y1)) in [((p.x, p.y), (q.x, q.y)), ((p.xp, p.yp), (q.xp, q.yp))]
                {
                    let (xr, yr) = (ca * x0 - sa * y0, sa * x0 + ca * y0);
                    assert!(
                        (xr - x1).hypot(yr - y1) <= 1e-7 * xs,
                        "{name}: position at {}: {:?} vs {:?}",
                        p.t,
                        (xr, yr),
                        (x1, y1)
                    );
                }
                // q_Z(α) ⊗ q.
                let qr = [
                    ha_c * p.qw - ha_s * p.qz,
                    ha_c * p.qx - ha_s * p.qy,
                    ha_c * p.qy + ha_s * p.qx,
                    ha_c * p.qz + ha_s * p.qw,
                ];
                let d = (qr[0] - q.qw).abs()
                    + (qr[1] - q.qx).abs()
                    + (qr[2] - q.qy).abs()
                    + (qr[3] - q.qz).abs();
                // The same rotation as ±q.
                let e = (qr[0] + q.qw).abs()
                    + (qr[1] + q.qx).abs()
                    + (qr[2] + q.qy).abs()
                    + (qr[3] + q.qz).abs();
                assert!(d.min(e) <= 1e-7, "{name}: attitude at {}", p.t);
            }
        });
    }
}

fn classical_1s() -> Scenario {
    let mut sc = Scenario::classical();
    sc.solver.t_end = 1.0;
    sc.solver.samples = 101;
    sc
}
