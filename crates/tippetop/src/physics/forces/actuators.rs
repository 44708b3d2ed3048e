//! The body actuators (docs/physics.md#actuators): a tip pushing at a body point
//! and a magnetic dipole along the symmetry axis in a lab field, the
//! `[[force]]`, `[[write]]` and `[[erase]]` windows of `kind = "tip"` and
//! `kind = "magnetic"`. Both are [`Kind::BodyPoint`] terms: each applies a
//! *wrench*, a force `F` at the centre of mass `O` and a torque `τ` about
//! it (lab frame), summed over the windows in effect as one [`BodyLoad`].
//!
//! - Tip at the body point `p` (body frame: origin `O`, `z` along `k`,
//!   `x, y` the material axes) with the lab force `F_tip`: `ρ = p_x e₁ +
//!   p_y e₂ + p_z k` (lab), `F = F_tip`, `τ = ρ × F_tip`.
//! - Magnet: moment `μ k` in `B(x) = B₀ + G x`: `τ = μ k × B₀`,
//!   `F_j = μ k_i G_ij` (the force `∇(μ k·B)` at `O`); the torque of the
//!   gradient's field at `O`, `μ k × G x_O`, is neglected (the field is
//!   `B₀` over the top's excursion; with `B₀ = 0` the axis stays put).
//!
//! How the models apply the wrench (vector and rigid; the reduced model
//! refuses these kinds, `scenario::actuator::check_model`):
//!
//! - the free accelerations gain it: `v̇ += F/m`, `ẇ₀ += I⁻¹ τ` (`ẇ₀` the
//!   angular acceleration without the contact force), so the normal-force
//!   closure `N D(σ) = Q` (§normal-force, §rigid-model) gets `Q −= F_Z/m + a (I⁻¹τ)·e` with
//!   `D(σ)` unchanged (`e = k × Z`: `Q` is minus the gap's acceleration
//!   without the contact force), and the rolling constraint's right-hand
//!   side `b = g Z − ẇ₀ × r − a w × k̇` gets `−F/m` and the new `ẇ₀`;
//!   in flight (rigid) the wrench simply adds to Newton's and Euler's
//!   equations. For a force at `P` (`ρ = r`) this is the contact-point
//!   force's own closure `Q + a H·w` (tests/physics/actuators.rs compares
//!   the two paths).
//! - Jellett's `J = −L·r`: `dJ/dt = −τ·r` (the contact force's torque is
//!   normal to `r`, and `L·k̇ = 0`). Conserved for a tip whose line passes
//!   through `P` (`ρ − r ∥ F`) and for a field along `Z`; not in general.
//! - Energy: no potential; the power `F·v_O + τ·w` (the tip's
//!   `F·v_point`; the magnet's `μ d(k·B₀)/dt + F·v_O`) is integrated in
//!   `W_a`, rolling or not, so `E − E0 = W_f + W_a` with `E` the kinetic
//!   and gravitational energy (and the wells' and adhesion's potentials).

use super::{Applied, Energy, ForceTerm, Kind, Properties};
use crate::input::forcing::{ActuatorWindow, BodyActuator};

/// A 3-vector.
pub type V3 = [f64; 3];

/// The sum of the body actuators in effect (lab frame; SI in
/// [`Applied::body`], scaled by force unit `F_u` and length unit `R` when
/// latched, [`BodyLoad::scaled`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BodyLoad {
    /// `Σ F_tip` \[N\].
    pub force: V3,
    /// `Σ p_c F_tip` for the body coordinate `c = x, y, z` (row `c`) \[N m\]:
    /// the tips' torque is `e₁ × M_x + e₂ × M_y + k × M_z`.
    pub moments: [V3; 3],
    /// `Σ μ B₀` \[N m\]: the torque is `k × Σ μ B₀`.
    pub mu_field: V3,
    /// `Σ μ G` \[N\] (row `i`: `∂B_i/∂x_j`): the force is `F_j = k_i (Σ μ G)_ij`.
    pub mu_gradient: [V3; 3],
}

impl BodyLoad {
    /// True if it applies nothing (the models then skip it: bit for bit
    /// the runs without actuators).
    #[inline(always)]
    pub fn is_zero(&self) -> bool {
        *self == BodyLoad::default()
    }

    /// True if some tip is off the symmetry axis (its torque needs the
    /// body's material axes `e₁, e₂`).
    #[inline(always)]
    pub fn off_axis(&self) -> bool {
        self.moments[0] != [0.0; 3] || self.moments[1] != [0.0; 3]
    }

    /// Add one actuator (SI).
    pub fn add(&mut self, a: &BodyActuator) {
        match a {
            BodyActuator::Tip { point, force } => {
                for (i, f) in force.iter().enumerate() {
                    self.force[i] += f;
                    for (m, p) in self.moments.iter_mut().zip(point) {
                        m[i] += p * f;
                    }
                }
            }
            BodyActuator::Magnetic {
                moment,
                field,
                gradient,
            } => {
                for (i, (b, g)) in field.iter().zip(gradient).enumerate() {
                    self.mu_field[i] += moment * b;
                    for (acc, gij) in self.mu_gradient[i].iter_mut().zip(g) {
                        *acc += moment * gij;
                    }
                }
            }
        }
    }

    /// The load in scaled units: forces by `force_unit` \[N\], torques and
    /// moments by `force_unit × length_unit`.
    pub fn scaled(&self, force_unit: f64, length_unit: f64) -> BodyLoad {
        let torque_unit = force_unit * length_unit;
        let s = |v: V3, u: f64| [v[0] / u, v[1] / u, v[2] / u];
        BodyLoad {
            force: s(self.force, force_unit),
            moments: self.moments.map(|m| s(m, torque_unit)),
            mu_field: s(self.mu_field, torque_unit),
            mu_gradient: self.mu_gradient.map(|g| s(g, force_unit)),
        }
    }

    /// The wrench `(F, τ)` for the axis `k` and, for tips off the axis, the
    /// body's material axes `axes() = (e₁, e₂)` (called only then).
    #[inline]
    pub fn wrench(&self, k: V3, axes: impl FnOnce() -> (V3, V3)) -> (V3, V3) {
        let g = &self.mu_gradient;
        let mut f = self.force;
        for (j, fj) in f.iter_mut().enumerate() {
            *fj += k[0] * g[0][j] + k[1] * g[1][j] + k[2] * g[2][j];
        }
        let mut tau = cross(k, add(self.moments[2], self.mu_field));
        if self.off_axis() {
            let (e1, e2) = axes();
            tau = add(
                tau,
                add(cross(e1, self.moments[0]), cross(e2, self.moments[1])),
            );
        }
        (f, tau)
    }
}

#[inline(always)]
fn cross(a: V3, b: V3) -> V3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

#[inline(always)]
fn add(a: V3, b: V3) -> V3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// The body's material axes `(e₁, e₂)` from an attitude quaternion `q`
/// (`w, x, y, z`; body → lab, not necessarily unit) made orthonormal to the
/// integrated axis `k` (Gram–Schmidt: `e₁` the lab image of the body `x`
/// less its `k` part, `e₂ = k × e₁`).
pub fn material_axes(q: [f64; 4], k: V3) -> (V3, V3) {
    let [w, x, y, z] = q;
    let n2 = w * w + x * x + y * y + z * z;
    let ex = [
        (w * w + x * x - y * y - z * z) / n2,
        2.0 * (x * y + w * z) / n2,
        2.0 * (x * z - w * y) / n2,
    ];
    let kk = k[0] * k[0] + k[1] * k[1] + k[2] * k[2];
    let c = (ex[0] * k[0] + ex[1] * k[1] + ex[2] * k[2]) / kk;
    let e = [ex[0] - c * k[0], ex[1] - c * k[1], ex[2] - c * k[2]];
    let ne = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
    let e1 = [e[0] / ne, e[1] / ne, e[2] / ne];
    let nk = kk.sqrt();
    let e2 = cross([k[0] / nk, k[1] / nk, k[2] / nk], e1);
    (e1, e2)
}

/// The body actuators of a scenario (tips and magnets), one term per kind.
#[derive(Debug, Clone)]
pub struct Actuators {
    windows: Vec<ActuatorWindow>,
    name: &'static str,
}

impl Actuators {
    /// The windows of `kind` (`"tip"` or `"magnetic"`) among `windows`;
    /// `None` if there are none.
    pub fn of(windows: &[ActuatorWindow], kind: &str) -> Option<Self> {
        let w: Vec<ActuatorWindow> = windows
            .iter()
            .filter(|w| w.actuator.name() == kind)
            .copied()
            .collect();
        let name = if kind == "tip" {
            "tip (force.K.point, force.K.force)"
        } else {
            "magnetic dipole (force.K.moment, force.K.field, force.K.gradient)"
        };
        (!w.is_empty()).then_some(Actuators { windows: w, name })
    }
}

impl ForceTerm for Actuators {
    fn name(&self) -> &'static str {
        self.name
    }
    fn kind(&self) -> Kind {
        Kind::BodyPoint
    }
    fn properties(&self) -> Properties {
        Properties {
            closure: "a wrench: v' += F/m, w0' += I^-1 tau, so Q -= F_Z/m + a (I^-1 tau).e and the rolling b -= F/m (docs/physics.md#actuators)",
            conserves_jellett: false,
            energy: Energy::Integrated,
        }
    }
    fn add_to(&self, t: f64, acc: &mut Applied) {
        for w in self.windows.iter().filter(|w| w.active(t)) {
            acc.body.add(&w.actuator);
        }
    }
}
