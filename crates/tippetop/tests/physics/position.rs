//! Where the top is (docs/physics.md §19): the centre-of-mass position
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
