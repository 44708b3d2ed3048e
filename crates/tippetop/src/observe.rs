//! Derived quantities in SI units, written once from their definitions
//! (docs/physics.md#kinematics, §friction-laws) so that every model and every test uses the same
//! formulas.

use crate::Top;

/// Jellett's quantity `J = −L·r_OP = A Ω R sin²θ + C ω (R cos θ − a)` \[kg m³/s\].
///
/// `omega` is the spin `n·k`, `precession` is `Ω = φ̇`.
pub fn jellett(top: &Top, theta: f64, precession: f64, omega: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    top.inertia_transverse * precession * top.radius * s * s
        + top.inertia_axial * omega * (top.radius * c - top.offset)
}

/// Spin about the vertical, `n_Z = Ω sin²θ + ω cos θ` \[rad/s\].
pub fn vertical_spin(theta: f64, precession: f64, omega: f64) -> f64 {
    let (s, c) = theta.sin_cos();
    precession * s * s + omega * c
}

/// Total energy: translational `½ m |u|²`, rotational
/// `½ A (θ̇² + Ω² sin²θ) + ½ C ω²`, potential `m g h(θ)` \[J\].
#[allow(clippy::too_many_arguments)]
pub fn energy(
    top: &Top,
    gravity: f64,
    theta: f64,
    theta_dot: f64,
    precession: f64,
    omega: f64,
    u: [f64; 3],
) -> f64 {
    let s = theta.sin();
    let trans = 0.5 * top.mass * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    let rot =
        0.5 * top.inertia_transverse * (theta_dot * theta_dot + precession * precession * s * s)
            + 0.5 * top.inertia_axial * omega * omega;
    trans + rot + top.mass * gravity * top.height(theta)
}

/// Slip velocity of the contact point in the precessing frame, `v_P = u + n × r`
/// (horizontal components) \[m/s\].
pub fn slip_velocity(
    top: &Top,
    theta: f64,
    theta_dot: f64,
    precession: f64,
    omega: f64,
    ux: f64,
    uy: f64,
) -> [f64; 2] {
    let (s, c) = theta.sin_cos();
    let r = top.radius;
    [
        ux - top.height(theta) * theta_dot,
        uy + s * (r * (omega - precession * c) + top.offset * precession),
    ]
}

/// Quaternion product `a ⊗ b`, components `(w, x, y, z)`.
pub fn quat_mul(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The unit quaternion (body → lab) of the Euler angles: precession `φ`
/// about the lab `Z`, nutation `θ` about the precessing `ŷ`, spin `ψ` about
/// the body axis, `q = q_Z(φ) ⊗ q_Y(θ) ⊗ q_Z(ψ)` (docs/physics.md#position). The
/// axis is `k = (sin θ cos φ, sin θ sin φ, cos θ)`; `φ = ψ = 0` is the
/// initial attitude of every model.
pub fn attitude_from_euler(phi: f64, theta: f64, psi: f64) -> [f64; 4] {
    let (sp, cp) = (0.5 * phi).sin_cos();
    let (st, ct) = (0.5 * theta).sin_cos();
    let (ss, cs) = (0.5 * psi).sin_cos();
    quat_mul(
        quat_mul([cp, 0.0, 0.0, sp], [ct, 0.0, st, 0.0]),
        [cs, 0.0, 0.0, ss],
    )
}

/// The body's symmetry axis `e3` in the lab, `k = q e3 q*`, for a unit
/// quaternion `q` (body → lab).
pub fn axis_of(q: [f64; 4]) -> [f64; 3] {
    let [w, x, y, z] = q;
    [
        2.0 * (x * z + w * y),
        2.0 * (y * z - w * x),
        w * w - x * x - y * y + z * z,
    ]
}

/// The unit quaternion with axis exactly along `k` (normalised) nearest to
/// `q` (normalised): `q` turned by the smallest rotation that takes its axis
/// `q e3 q*` to `k`. The models whose dynamics integrate the axis `k` carry
/// a quaternion only for the rotation about it; this makes the output
/// attitude agree with `k` (and so with θ) to rounding.
pub fn attitude_with_axis(q: [f64; 4], k: [f64; 3]) -> [f64; 4] {
    let q = normalize4(q);
    let nk = (k[0] * k[0] + k[1] * k[1] + k[2] * k[2]).sqrt();
    let k = [k[0] / nk, k[1] / nk, k[2] / nk];
    let a = axis_of(q);
    let c = [
        a[1] * k[2] - a[2] * k[1],
        a[2] * k[0] - a[0] * k[2],
        a[0] * k[1] - a[1] * k[0],
    ];
    let r = normalize4([
        1.0 + a[0] * k[0] + a[1] * k[1] + a[2] * k[2],
        c[0],
        c[1],
        c[2],
    ]);
    normalize4(quat_mul(r, q))
}

/// `q / |q|`.
fn normalize4(q: [f64; 4]) -> [f64; 4] {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    [q[0] / n, q[1] / n, q[2] / n, q[3] / n]
}
