//! Derived quantities in SI units, written once from their definitions
//! (docs/physics.md §2, §5) so that every model and every test uses the same
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
