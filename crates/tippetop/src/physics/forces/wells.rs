//! Orientation wells, the `[[well]]` entries (docs/physics.md#wells): each a
//! Gaussian well in the nutation angle θ, `theta` θ_i \[rad\], `depth` d_i
//! \[J\], `width` w_i \[rad\], with the potential
//!
//! ```text
//! U(θ) = −Σ_i d_i exp(−(θ − θ_i)²/(2 w_i²))
//! ```
//!
//! (a stem adhering when the top lies, a corrugation barrier). It acts as a
//! pure torque (a couple: no force, so the centre of mass and the contact
//! force see it only through the motion) about the horizontal axis `ŷ`
//! normal to the symmetry axis `k`, the axis about which θ turns
//! (`ŷ = Z × x̂`, `x̂` the horizontal direction of the tilt, so that
//! `∂k/∂θ = ŷ × k`):
//!
//! ```text
//! τ = τ_y ŷ,   τ_y = −U′(θ) = −Σ_i d_i (θ − θ_i)/w_i² exp(−(θ − θ_i)²/(2 w_i²))
//! ```
//!
//! equivalently `τ = U′(θ) (k × Z)/sin θ`; `τ_y > 0` turns `k` towards larger
//! θ, so the torque drives θ down the potential (`τ·n = τ_y θ̇ = −dU/dt`).
//!
//! - Closure: `ŷ ⊥ k`, so the torque's angular acceleration is `τ/A`; it
//!   enters exactly as the gyroscopic term does, `G ← G + τ_y` in the Euler
//!   angles (`A θ̈ = G + τ_y − a s N − h F_x`), so `Q` gains `a s τ_y/A`
//!   (with `D(σ)` unchanged); the vector and rigid models add `τ/A` to the
//!   torque-free angular acceleration `ẇ₀`, which the closure and the
//!   rolling constraint read (`Q` gains `−a (τ/A)·e`, `e = k × Z`, the same
//!   `a s τ_y/A`). The Ω and ω equations do not change (`τ·Z = τ·k = 0`).
//! - Jellett's J = `−L·r`, `r = a k − R Z`: `dJ/dt` gains `−τ·r = 0`
//!   (`τ ⊥ k`, `τ ⊥ Z`): conserved.
//! - Energy: a potential; the energy includes `U(θ)`, so `E − E0 = W_f + W_a`
//!   holds with the same `W_f`, `W_a`.
//! - Poles: `ŷ` is undefined at θ = 0 and π, and `U′` need not vanish there
//!   (`U′(0) = −Σ d_i θ_i/w_i² exp(−θ_i²/(2w_i²)) <= 0`, `U′(π) >= 0`: each pole
//!   is a conical peak of `U` unless a well is centred on it). The torque is
//!   bounded (`|τ| = |U′|`) and points away from the pole along the current
//!   tilt; at exactly `sin θ = 0` its direction is undefined and the models
//!   apply none (a peak's tip: an equilibrium, unstable). `U` is continuous,
//!   so the energy balance holds through the pole; the reduced model stops
//!   near it anyway (docs/physics.md#failures).

use super::{Applied, Energy, ForceTerm, Kind, Properties};

pub use crate::input::well::{
    DEPTH_RANGE, OVERLAP_WIDTHS, THETA_RANGE, WIDTH_RANGE, Well, validate,
};

/// `U(θ) = −Σ d_i exp(−(θ − θ_i)²/(2 w_i²))` (units of the depths).
#[inline]
pub fn potential(wells: &[Well], theta: f64) -> f64 {
    wells
        .iter()
        .map(|w| {
            let x = (theta - w.theta) / w.width;
            -w.depth * (-0.5 * x * x).exp()
        })
        .sum()
}

/// `e + U(θ)`; `e` itself without wells (bit for bit): what the models'
/// energies add.
#[inline]
pub fn with_potential(wells: &[Well], e: f64, theta: f64) -> f64 {
    if wells.is_empty() {
        e
    } else {
        e + potential(wells, theta)
    }
}

/// `τ_y = −U′(θ) = −Σ d_i (θ − θ_i)/w_i² exp(−(θ − θ_i)²/(2 w_i²))`: the
/// torque about `ŷ` (units of the depths).
#[inline]
pub fn torque(wells: &[Well], theta: f64) -> f64 {
    wells
        .iter()
        .map(|w| {
            let x = (theta - w.theta) / w.width;
            -w.depth * x / w.width * (-0.5 * x * x).exp()
        })
        .sum()
}

/// `base + τ_y(θ)`, the wells' torque about `ŷ` added to `base` (the
/// reduced model's gyroscopic term of `A θ̈`); `base` itself without wells
/// (bit for bit). The lab-vector models take [`torque_world`]
/// (through [`crate::physics::body::WellsTorque`]).
#[inline(always)]
pub fn with_torque(wells: &[Well], base: f64, theta: f64) -> f64 {
    if wells.is_empty() {
        base
    } else {
        base + torque(wells, theta)
    }
}

/// The torque `τ_y ŷ` in the space frame for the (not necessarily unit)
/// axis `k`: `ŷ = (−k_y, k_x, 0)/|k_h|`, θ = atan2(|k_h|, k_Z); zero where
/// `k_h = 0` (the pole: direction undefined, module doc). `|k_h|` is a
/// plain square root (|k| ≈ 1 in every model: nothing to overflow; it
/// underflows to 0 only for `|k_h| < 1e-154`, then the torque is 0; since
/// 66 instructions less than `hypot` per call). θ and the
/// Gaussians use glibc's `atan2` and `exp`: fdlibm's versions in
/// `detmath` took fewer instructions but more time, their divisions being
/// on the critical path (docs/performance.md#langevin-step).
#[inline]
pub fn torque_world(wells: &[Well], k: [f64; 3]) -> [f64; 3] {
    let kh = (k[0] * k[0] + k[1] * k[1]).sqrt();
    if kh == 0.0 {
        return [0.0; 3];
    }
    let ty = torque(wells, kh.atan2(k[2])) / kh;
    [-k[1] * ty, k[0] * ty, 0.0]
}

/// The wells of a scenario, one force term.
#[derive(Debug, Clone)]
pub struct Wells {
    wells: Vec<Well>,
}

impl Wells {
    /// The term of the scenario's `[[well]]` entries.
    pub fn of(wells: &[Well]) -> Self {
        Wells {
            wells: wells.to_vec(),
        }
    }
}

impl ForceTerm for Wells {
    fn name(&self) -> &'static str {
        "orientation wells (well.K.theta, well.K.depth, well.K.width)"
    }
    fn kind(&self) -> Kind {
        Kind::Torque
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "a torque -U'(theta) about y (perpendicular to k and Z): G += tau_y, Q += a s tau_y/A (docs/physics.md#wells)",
            conserves_jellett: true,
            energy: Energy::Potential,
        }
    }
    fn add_to(&self, _t: f64, acc: &mut Applied) {
        acc.wells.extend_from_slice(&self.wells);
    }
}
