//! Where the top is (docs/physics.md#position): the centre-of-mass position
//! `x, y, z`, the attitude quaternion `qw, qx, qy, qz` (body → lab) and the
//! contact point `xp, yp`, in every model. The closed forms and the
//! conventions (lab frame, initial heading, `k = q e3 q*`) are written here
//! from their definitions, not from the library's helpers.

use crate::spec::*;
use tippetop::{Sample, Scenario};

/// `k = q e3 q*` for a unit quaternion `(w, x, y, z)`.
fn axis(s: &Sample) -> [f64; 3] {
    let (w, x, y, z) = (s.qw, s.qx, s.qy, s.qz);
    [
        2.0 * (x * z + w * y),
        2.0 * (y * z - w * x),
        w * w - x * x - y * y + z * z,
    ]
}

fn quat(s: &Sample) -> [f64; 4] {
    [s.qw, s.qx, s.qy, s.qz]
}

/// Distance between two attitudes, `min |q1 ∓ q2|` (q and −q are the same
/// rotation).
fn qdist(a: [f64; 4], b: [f64; 4]) -> f64 {
    let d = |sgn: f64| {
        (0..4)
            .map(|i| (a[i] - sgn * b[i]).powi(2))
            .sum::<f64>()
            .sqrt()
    };
    d(1.0).min(d(-1.0))
}

/// The classical preset, exact Coulomb law, 1 s (slides, sticks at
/// ≈ 0.047 s, rolls), at rtol 1e-12 as the cross-checks.
fn classical_1s() -> Scenario {
    let mut sc = Scenario::classical();
    sc.solver.t_end = 1.0;
    sc.solver.rtol = 1e-12;
    sc
}

/// At every sample of the classical top (1 s) and of the nano preset: the
/// quaternion is unit, its axis has `k_Z = cos θ`, the height is the
/// contact's `R − a cos θ`, the contact point is `(x, y) + a (k_X, k_Y)`;
/// at t = 0 the top is at the origin with `q = (cos θ/2, 0, sin θ/2, 0)`.
/// Tolerances are rounding budgets (every one of these holds exactly in
/// exact arithmetic, in every model): |q| to 4 ulp (a normalised
/// quaternion, or products of half-angle sines and cosines); k_Z to 1e-14
/// (two quaternion products and a normalisation, a few ulp each, on O(1)
/// numbers); z to 1e-14 of R, the contact point to 1e-14 of the larger of
/// R and |x|, |y|.
#[test]
fn attitude_is_unit_and_agrees_with_theta() {
    each_model(&[], |m| {
        for (name, sc) in [("classical", classical_1s()), ("nano", Scenario::nano())] {
            let tr = run(&sc, m);
            let (r, a) = (sc.top.radius, sc.top.offset);
            let s0 = &tr.samples[0];
            let th0 = sc.initial.theta;
            assert_eq!((s0.x, s0.y), (0.0, 0.0), "{name}: start at the origin");
            let q0 = [(0.5 * th0).cos(), 0.0, (0.5 * th0).sin(), 0.0];
            assert!(qdist(quat(s0), q0) <= 4e-16, "{name}: q(0) {:?}", quat(s0));
            let (mut wn, mut wk, mut wz, mut wp) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
            for s in &tr.samples {
                let n = quat(s).iter().map(|v| v * v).sum::<f64>().sqrt();
                wn = wn.max((n - 1.0).abs());
                let k = axis(s);
                wk = wk.max((k[2] - s.theta.cos()).abs());
                wz = wz.max((s.z - (r - a * s.theta.cos())).abs() / r);
                // Rounding of the sum x + a k_X is relative to the larger
                // of its terms (the nano top travels many radii).
                let big = r.max(s.x.abs()).max(s.y.abs());
                wp = wp
                    .max(((s.xp - s.x - a * k[0]).abs()).max((s.yp - s.y - a * k[1]).abs()) / big);
            }
            println!(
                "[{m:?}] {name}: | |q| - 1 | {wn:.1e}, |k_Z - cos θ| {wk:.1e}, z {wz:.1e}, contact point {wp:.1e}"
            );
            assert!(wn <= 4.0 * f64::EPSILON, "{name}: |q| off by {wn:e}");
            assert!(wk <= 1e-14, "{name}: k_Z vs cos θ off by {wk:e}");
            assert!(wz <= 1e-14, "{name}: z vs R − a cos θ off by {wz:e}");
            assert!(wp <= 1e-14, "{name}: contact point off by {wp:e}");
        }
    });
}

/// A uniform sphere (a = 0) with its axis tilted by θ0 = 0.5 towards +X,
/// spinning at ω0 = 50 rad/s about it, set down at rest (μ = 0.2, exact
/// law). The contact point slips along +Y at `v0 = R ω0 sin θ0`; friction
/// `μ m g` along −Y accelerates the centre until the slip vanishes at
/// `t_s = 2 v0 / (7 μ g)`; then it rolls on at `−μ g t_s`. So
/// `x = 0`, `y = −½ μ g t²` (t ≤ t_s), `y = −½ μ g t_s² − μ g t_s (t − t_s)`
/// after, `z = R`, and the contact point traces the same line (`a = 0`).
/// The position is the integral of a velocity computed to rtol 1e-10 over
/// 0.4 s: bound 1e-8 of the distance covered (`|y(0.4 s)|`), far above
/// the integration error and far below any error of the law (a wrong
/// heading, frame or scale is O(1)).
#[test]
fn sphere_slides_then_rolls_along_the_closed_form_line() {
    each_model(&[], |m| {
        let (theta, spin, mu) = (0.5f64, 50.0, 0.2);
        let sc = uniform_sphere(theta, spin, mu);
        let g = sc.surface.gravity;
        let r = sc.top.radius;
        let tr = run(&sc, m);
        let v0 = r * spin * theta.sin();
        let ts = 2.0 * v0 / (7.0 * mu * g);
        let y_of = |t: f64| {
            if t <= ts {
                -0.5 * mu * g * t * t
            } else {
                -0.5 * mu * g * ts * ts - mu * g * ts * (t - ts)
            }
        };
        let scale = y_of(sc.solver.t_end).abs();
        let mut worst = 0.0f64;
        for s in &tr.samples {
            let e = [
                s.x.abs(),
                (s.y - y_of(s.t)).abs(),
                (s.z - r).abs(),
                (s.xp - s.x).abs(),
                (s.yp - s.y).abs(),
            ];
            let e = e.into_iter().fold(0.0, f64::max) / scale;
            worst = worst.max(e);
        }
        println!(
            "[{m:?}] sphere: distance {scale:.4e} m, worst deviation from the closed form {worst:.1e} of it"
        );
        assert!(worst <= 1e-8, "position off the closed form by {worst:e}");
    });
}

/// Position and attitude against the Euler-angle model on the classical
/// top (1 s, exact law, rtol 1e-12; slides then rolls), to the 1e-6 of the
/// scale the other cross-checks use (`crosscheck.rs`): x, y of the largest
/// horizontal distance, z of R, the quaternion as a rotation (|q1 ∓ q2|; the
/// spin phase has turned by ≈ 180 rad, so this also checks the spin angle's
/// quadrature).
#[test]
fn position_and_attitude_agree_with_euler_angles() {
    let sc = classical_1s();
    let red = run(&sc, Reduced);
    each_model(
        &[cannot(Reduced, "it is the reference of the cross-check")],
        |m| {
            let other = run(&sc, m);
            let r = sc.top.radius;
            let dist = red
                .samples
                .iter()
                .map(|s| s.x.hypot(s.y))
                .fold(0.0, f64::max);
            let (mut dx, mut dz, mut dq) = (0.0f64, 0.0f64, 0.0f64);
            for (a, b) in red.samples.iter().zip(&other.samples) {
                assert_eq!(a.t, b.t);
                dx = dx.max((a.x - b.x).abs().max((a.y - b.y).abs()) / dist);
                dx = dx.max((a.xp - b.xp).abs().max((a.yp - b.yp).abs()) / dist);
                dz = dz.max((a.z - b.z).abs() / r);
                dq = dq.max(qdist(quat(a), quat(b)));
            }
            println!(
                "[{m:?}] classical 1 s vs reduced: distance {dist:.3e} m; x, y, contact {dx:.1e}, z {dz:.1e}, q {dq:.1e}"
            );
            assert!(dx <= 1e-6, "x, y deviate by {dx:e} of {dist:e} m");
            assert!(dz <= 1e-6, "z deviates by {dz:e} of R");
            assert!(dq <= 1e-6, "attitude deviates by {dq:e}");
        },
    );
}

/// The sampled position is the integral of the velocity columns: over two
/// sample intervals, `x_{i+1} − x_{i−1}` equals Simpson's rule on the lab
/// velocity `u_x x̂ + u_y ŷ`, with the precessing frame's `x̂` the heading of
/// the quaternion's axis, `ŷ = Z × x̂`. Classical top, regularised law
/// (smooth: no stick/slip switch inside an interval), 0.2 s, Δt = 1e-4 s.
/// Simpson's error is `Δt⁵ |v''''| / 90` per double interval, relative
/// `(ω Δt)⁴ / 180 ≈ 5e-9` at the top's fastest rate ω ≈ 300 rad/s; bound
/// 1e-7 of the distance a sample interval pair covers at the largest speed.
#[test]
fn position_follows_the_velocity_columns() {
    each_model(&[], |m| {
        let mut sc = classical_smooth(1e-2);
        sc.solver.t_end = 0.2;
        sc.solver.samples = 2001;
        sc.solver.rtol = 1e-12;
        let tr = run(&sc, m);
        let v = |s: &Sample| {
            let k = axis(s);
            let h = k[0].hypot(k[1]);
            let (cx, cy) = (k[0] / h, k[1] / h);
            [s.ux * cx - s.uy * cy, s.ux * cy + s.uy * cx]
        };
        let vmax = tr
            .samples
            .iter()
            .map(|s| s.ux.hypot(s.uy))
            .fold(0.0, f64::max);
        let mut worst = 0.0f64;
        for w in tr.samples.windows(3) {
            let dt = w[2].t - w[0].t;
            let (v0, v1, v2) = (v(&w[0]), v(&w[1]), v(&w[2]));
            for c in 0..2 {
                let simpson = dt / 6.0 * (v0[c] + 4.0 * v1[c] + v2[c]);
                let dpos = if c == 0 {
                    w[2].x - w[0].x
                } else {
                    w[2].y - w[0].y
                };
                worst = worst.max((dpos - simpson).abs() / (vmax * dt));
            }
        }
        println!("[{m:?}] position vs Simpson of the velocity: {worst:.1e} of v_max Δt");
        assert!(worst <= 1e-7, "position vs velocity off by {worst:e}");
    });
}

/// A sleeping top (θ = 0, the classical top spinning at ω = 1e6 rad/s
/// about the vertical, which it keeps exactly: no slip, no torque) turns
/// about `Z` by `ω t`: `q = (cos ωt/2, 0, 0, sin ωt/2)`. At t = 2 s that
/// is 2e6 rad. Bound: 1e-9 rad on the angle (`|q1 ∓ q2| ≈ angle/2`), a few
/// ulps of 2e6 rad (the closed form's own `ω t` is one rounding of 2.3e-10
/// rad); the quaternion unit to 4 ulp. Issue 26: the vector model's
/// attitude quadrature overflowed here (NaN from 0.02 s, the run failed).
/// The rigid model integrates `q` under error control (8.9e6 steps, ~40 s
/// in release; its phase is off by 2.4e-6 rad at 2 s, rtol 1e-10): it runs
/// in the ignored test below with its own bound.
#[test]
fn sleeping_top_turns_by_spin_times_t() {
    each_model(
        &[
            cannot(Reduced, "θ = 0 is the Euler angles' pole"),
            too_slow(
                Rigid,
                "8.9e6 steps: sleeping_top_turns_by_spin_times_t_rigid",
            ),
        ],
        |m| sleeping_top(m, 1e-9),
    );
}

/// [`sleeping_top_turns_by_spin_times_t`] on the rigid model, whose
/// quaternion is under DOP853's error control at rtol 1e-10 (measured phase
/// error 2.4e-6 rad after 2e6 rad, 1.2e-12 of it): bound 1e-5 rad.
/// `cargo test --release -p tippetop --test physics -- --ignored sleeping_top`.
#[test]
#[ignore]
fn sleeping_top_turns_by_spin_times_t_rigid() {
    sleeping_top(Rigid, 1e-5);
}

fn sleeping_top(m: tippetop::ModelKind, bound: f64) {
    let mut sc = Scenario::classical();
    let spin = 1e6;
    sc.initial.theta = 0.0;
    sc.initial.spin = spin;
    sc.solver.t_end = 2.0;
    let tr = run(&sc, m);
    assert_eq!(tr.samples.len(), sc.solver.samples);
    let (mut wa, mut wn) = (0.0f64, 0.0f64);
    for s in &tr.samples {
        let (sn, cs) = (0.5 * spin * s.t).sin_cos();
        wa = wa.max(2.0 * qdist(quat(s), [cs, 0.0, 0.0, sn]));
        let n = quat(s).iter().map(|v| v * v).sum::<f64>().sqrt();
        wn = wn.max((n - 1.0).abs());
    }
    println!(
        "[{m:?}] sleeping top, 1e6 rad/s for 2 s: angle off ω t by {wa:.2e} rad, | |q| - 1 | {wn:.1e}"
    );
    assert!(wa <= bound, "attitude off the closed form by {wa:e} rad");
    assert!(wn <= 4.0 * f64::EPSILON, "|q| off by {wn:e}");
}

/// Issue 26's reproducer: the classical top at θ0 = 0.1 spinning at 1e6
/// rad/s for 2 s (2e6 rad). The vector model's quaternion was NaN in 236
/// of the 1001 rows from 1.53 s on while the run said `ok`. Now every row
/// is finite with |q| = 1 to 4 ulp, and the attitude agrees with the
/// reduced model's (Euler angles: `ψ` a plain quadrature of
/// `ω − Ω cos θ`, `q` from `φ, θ, ψ`), an independent formulation, to
/// 2e-7 rad at every row: the reduced model's own `ψ` moves by 7.3e-8 rad
/// between rtol 1e-10 and 1e-12 (its sum of 3e5 steps at 2e6 rad), the two
/// agree to 4.3e-8 (1e-13 of the angle turned; a lost step of the spin
/// phase is O(1) rad). (The rigid model, whose `q` is under error control,
/// is 1.5e-6 rad off its own rtol 1e-12 run at 2 s: too coarse a reference.)
#[test]
fn fast_top_attitude_is_finite_and_agrees_with_euler_angles() {
    let mut sc = Scenario::classical();
    sc.initial.spin = 1e6;
    sc.solver.t_end = 2.0;
    let (vec, red) = std::thread::scope(|s| {
        let v = s.spawn(|| run(&sc, Vector));
        let r = s.spawn(|| run(&sc, Reduced));
        (v.join().unwrap(), r.join().unwrap())
    });
    assert_eq!(vec.samples.len(), sc.solver.samples);
    let (mut wa, mut wn) = (0.0f64, 0.0f64);
    for (v, r) in vec.samples.iter().zip(&red.samples) {
        assert!(v.is_finite(), "a row is not finite: {v:?}");
        let n = quat(v).iter().map(|x| x * x).sum::<f64>().sqrt();
        wn = wn.max((n - 1.0).abs());
        wa = wa.max(2.0 * qdist(quat(v), quat(r)));
    }
    let last = vec.samples.last().unwrap();
    println!(
        "fast top, 1e6 rad/s for 2 s: vector vs reduced attitude {wa:.2e} rad (max over rows), | |q| - 1 | {wn:.1e}; q(2 s) = {:?}",
        quat(last)
    );
    assert!(wn <= 4.0 * f64::EPSILON, "|q| off by {wn:e}");
    assert!(wa <= 2e-7, "attitude off the reduced model's by {wa:e} rad");
}
