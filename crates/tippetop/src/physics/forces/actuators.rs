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
//! refuses these kinds, [`check_model`]):
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

//!
//! # Keys
//!
//! Their keys in a window of `[[force]]`, `[[write]]` or `[[erase]]`
//! ([`KEYS`]; `kind`, `start`, `stop` are the schedule's, input/forcing.rs)
//! are read ([`parse`]), checked ([`BodyActuator::validate`],
//! [`check_model`]) and written ([`to_table`]) here:
//!
//! ```toml
//! [[force]]
//! kind = "tip"                 # default "contact" (hx, hy, hz)
//! point = [0.0, 0.0, 1e-9]     # [m], body frame: origin at the centre of mass, z along k
//! force = [1e-22, 0.0, 0.0]    # [N], lab frame (Z up), the force on the top
//! start = 0.0
//! stop = 1e-5
//! [[force]]
//! kind = "magnetic"
//! moment = 9.2740100783e-24    # [A m^2] along k: one Bohr magneton
//! field = [0.0, 0.0, 1.0]      # [T], uniform, lab frame (default 0)
//! gradient = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]  # [T/m], G_ij = dB_i/dx_j (default 0)
//! ```
//!
//! A key of another kind (`point` in a contact window, `hx` in a tip
//! window, ...) is an error naming it (the schedule's `kind` check);
//! `point`, `force` and `moment` are required by their kind.

use toml::{Table, Value};

use super::{Applied, Energy, ForceTerm, Kind, Properties, Window};
use crate::Error;
use crate::input::Key;
use crate::input::reader::Section;
use crate::input::solver::ModelKind;

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
    windows: Vec<Window<BodyActuator>>,
    name: &'static str,
}

impl Actuators {
    /// The windows of `kind` (`"tip"` or `"magnetic"`) among `windows`
    /// (the schedule's, in its order); `None` if there are none.
    pub fn of(windows: impl IntoIterator<Item = Window<BodyActuator>>, kind: &str) -> Option<Self> {
        let w: Vec<Window<BodyActuator>> = windows
            .into_iter()
            .filter(|w| w.value.name() == kind)
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
            acc.body.add(&w.value);
        }
    }
}

/// One Bohr magneton \[A m²\] (J/T), CODATA 2018: a moment of `n` μ_B is
/// `moment = n × BOHR_MAGNETON` (docs/physics.md#actuators).
pub const BOHR_MAGNETON: f64 = 9.2740100783e-24;

/// A body actuator (docs/physics.md#actuators): what a `[[force]]`,
/// `[[write]]` or `[[erase]]` window of `kind = "tip"` or `"magnetic"`
/// applies. Lab frame: `X, Y` horizontal, `Z` up. Body frame: origin at the
/// centre of mass, `z` along the symmetry axis `k`, `x, y` the body's
/// material axes (the attitude quaternion's, docs/physics.md#position).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BodyActuator {
    /// A tip: the force `force` \[N\] (lab frame, the force on the top)
    /// at the body point `point` \[m\] (body frame). It adds `force` to the
    /// centre of mass and the torque `ρ × force` about it, `ρ` the point in
    /// the lab frame; its power is `force·v_point`.
    Tip {
        /// The point of application \[m\], body frame.
        point: [f64; 3],
        /// The force on the top \[N\], lab frame.
        force: [f64; 3],
    },
    /// A magnetic dipole `μ k` (moment along the symmetry axis) in the lab
    /// field `B(x) = field + gradient · x`: the torque `μ k × field` and the
    /// force `F_j = μ k_i G_ij` at the centre of mass (`G_ij = ∂B_i/∂x_j`,
    /// the gradient's torque `μ k × G x` is neglected, docs/physics.md#actuators).
    /// Its work is integrated (`W_a`).
    Magnetic {
        /// `μ` \[A m²\] along `k` ([`BOHR_MAGNETON`] per μ_B).
        moment: f64,
        /// Uniform field `B` \[T\], lab frame.
        field: [f64; 3],
        /// `G_ij = ∂B_i/∂x_j` \[T/m\], lab frame, row `i`.
        gradient: [[f64; 3]; 3],
    },
}

impl BodyActuator {
    /// The kind's name in the scenario file (`"tip"`, `"magnetic"`).
    pub fn name(&self) -> &'static str {
        match self {
            BodyActuator::Tip { .. } => "tip",
            BodyActuator::Magnetic { .. } => "magnetic",
        }
    }

    /// True if it never applies anything (a zero force, or a zero moment or
    /// field and gradient).
    pub fn is_zero(&self) -> bool {
        match self {
            BodyActuator::Tip { force, .. } => force.iter().all(|&f| f == 0.0),
            BodyActuator::Magnetic {
                moment,
                field,
                gradient,
            } => {
                *moment == 0.0
                    || (field.iter().all(|&b| b == 0.0)
                        && gradient.iter().flatten().all(|&g| g == 0.0))
            }
        }
    }

    /// True for a tip whose point is off the symmetry axis (`point.x` or
    /// `point.y` nonzero): its lever arm turns with the spin, so the
    /// dynamics need the full attitude.
    pub fn off_axis(&self) -> bool {
        matches!(self, BodyActuator::Tip { point, .. } if point[0] != 0.0 || point[1] != 0.0)
    }

    /// The rates \[1/s\] it sets for a top of mass `m` \[kg\], radius `r`
    /// \[m\], transverse inertia `a` \[kg m²\]: a tip `sqrt(|F| / (m R))` (as
    /// the contact force's) and `sqrt(|F| |point| / A)`; a magnet
    /// `sqrt(|μ| |B| / A)` and `sqrt(|μ| |G| / (m R))` (`|G|` the
    /// Frobenius norm). The largest is the actuator's time-unit rate.
    pub fn rate(&self, m: f64, r: f64, a: f64) -> f64 {
        let norm = |v: &[f64; 3]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
        match self {
            BodyActuator::Tip { point, force } => {
                let f = norm(force);
                (f / (m * r)).sqrt().max((f * norm(point) / a).sqrt())
            }
            BodyActuator::Magnetic {
                moment,
                field,
                gradient,
            } => {
                let g = gradient.iter().flatten().map(|x| x * x).sum::<f64>().sqrt();
                (moment.abs() * norm(field) / a)
                    .sqrt()
                    .max((moment.abs() * g / (m * r)).sqrt())
            }
        }
    }

    /// Check the values; errors name `{prefix}.KEY` (the keys of the
    /// scenario file).
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        let finite = |key: &str, vs: &[f64], what: &str| -> Result<(), Error> {
            match vs.iter().find(|v| !v.is_finite()) {
                Some(v) => Err(Error::invalid(
                    &format!("{prefix}.{key}"),
                    format!("{} is not allowed", crate::human::exact(*v)),
                    what.into(),
                )),
                None => Ok(()),
            }
        };
        match self {
            BodyActuator::Tip { point, force } => {
                finite("point", point, TIP_POINT_RANGE)?;
                finite("force", force, TIP_FORCE_RANGE)
            }
            BodyActuator::Magnetic {
                moment,
                field,
                gradient,
            } => {
                finite("moment", &[*moment], MAGNETIC_MOMENT_RANGE)?;
                finite("field", field, MAGNETIC_FIELD_RANGE)?;
                let flat: Vec<f64> = gradient.iter().flatten().copied().collect();
                finite("gradient", &flat, MAGNETIC_GRADIENT_RANGE)
            }
        }
    }
}

/// The valid range of a tip's `point`.
pub const TIP_POINT_RANGE: &str = "[x, y, z] [m], finite, body frame (origin at the centre of mass, z along the symmetry axis); kind = \"tip\"";
/// The valid range of a tip's `force`.
pub const TIP_FORCE_RANGE: &str =
    "[x, y, z] [N], finite, lab frame (Z up), the force on the top; kind = \"tip\"";
/// The valid range of a magnet's `moment`.
pub const MAGNETIC_MOMENT_RANGE: &str = "a finite moment [A m^2] along the symmetry axis (1 Bohr magneton = 9.2740100783e-24 A m^2); kind = \"magnetic\"";
/// The valid range of a magnet's `field`.
pub const MAGNETIC_FIELD_RANGE: &str =
    "[x, y, z] [T], finite, uniform, lab frame; kind = \"magnetic\" (default [0, 0, 0])";
/// The valid range of a magnet's `gradient`.
pub const MAGNETIC_GRADIENT_RANGE: &str = "[[dBx/dx, dBx/dy, dBx/dz], [dBy/dx, ...], [dBz/dx, ...]] [T/m], a finite 3x3 array, lab frame; kind = \"magnetic\" (default zero)";

/// The body actuators' keys with their ranges (`kind` is the caller's).
pub const KEYS: [Key; 5] = [
    Key::doc(
        "point",
        TIP_POINT_RANGE,
        "required by tip",
        "the tip's point on the body",
    ),
    Key::doc(
        "force",
        TIP_FORCE_RANGE,
        "required by tip",
        "the tip's force on the top",
    ),
    Key::doc(
        "moment",
        MAGNETIC_MOMENT_RANGE,
        "required by magnetic",
        "the magnetic moment along the axis",
    ),
    Key::doc(
        "field",
        MAGNETIC_FIELD_RANGE,
        "[0, 0, 0]",
        "the uniform field B0",
    ),
    Key::doc(
        "gradient",
        MAGNETIC_GRADIENT_RANGE,
        "zero",
        "the field's gradient G",
    ),
];

/// The body actuator of a window of `kind` (`"tip"` or `"magnetic"`,
/// whose keys the schedule has checked belong to it): each required key
/// first (`point`, `force`; `moment`), then the values (types only;
/// [`BodyActuator::validate`] checks them).
pub(crate) fn parse(kind: &str, s: &Section) -> Result<BodyActuator, Error> {
    let required = |key: &str| -> Result<(), Error> {
        match s.get(key) {
            Some(_) => Ok(()),
            None => Err(Error::invalid(
                &s.full(key),
                "missing".into(),
                format!("required with kind = \"{kind}\": {}", range(key)),
            )),
        }
    };
    if kind == "tip" {
        required("point")?;
        required("force")?;
        Ok(BodyActuator::Tip {
            point: s.f64s("point", None)?,
            force: s.f64s("force", None)?,
        })
    } else {
        required("moment")?;
        Ok(BodyActuator::Magnetic {
            moment: s.f64("moment", None)?,
            field: s.f64s("field", Some([0.0; 3]))?,
            gradient: gradient(s)?,
        })
    }
}

/// The keys a window of `kind` (`"tip"`, `"magnetic"`) takes besides the
/// schedule's.
pub const fn own_keys(kind: &str) -> &'static [&'static str] {
    match kind.as_bytes() {
        b"tip" => &["point", "force"],
        _ => &["moment", "field", "gradient"],
    }
}

fn range(key: &str) -> &'static str {
    KEYS.iter()
        .find(|k| k.name == key)
        .map(|k| k.range)
        .unwrap_or("")
}

/// `gradient`: a 3x3 array of finite numbers (default zero).
fn gradient(s: &Section) -> Result<[[f64; 3]; 3], Error> {
    let Some(v) = s.get("gradient") else {
        return Ok([[0.0; 3]; 3]);
    };
    let bad = || s.wrong_type("gradient", "a 3x3 array of numbers", v);
    let Value::Array(rows) = v else {
        return Err(bad());
    };
    if rows.len() != 3 {
        return Err(bad());
    }
    let mut g = [[0.0; 3]; 3];
    for (gi, row) in g.iter_mut().zip(rows) {
        let Value::Array(row) = row else {
            return Err(bad());
        };
        if row.len() != 3 {
            return Err(bad());
        }
        for (gij, x) in gi.iter_mut().zip(row) {
            *gij = match x {
                Value::Float(f) => *f,
                Value::Integer(i) => *i as f64,
                _ => return Err(bad()),
            };
            if !gij.is_finite() {
                return Err(Error::invalid(
                    &s.full("gradient"),
                    format!("{gij} is not allowed"),
                    MAGNETIC_GRADIENT_RANGE.into(),
                ));
            }
        }
    }
    Ok(g)
}

/// The TOML keys of a body actuator (with `kind`), for rendering.
pub(crate) fn to_table(a: &BodyActuator, t: &mut Table) {
    let arr = |v: &[f64; 3]| Value::Array(v.iter().map(|x| Value::Float(*x)).collect());
    t.insert("kind".into(), Value::String(a.name().into()));
    match a {
        BodyActuator::Tip { point, force } => {
            t.insert("point".into(), arr(point));
            t.insert("force".into(), arr(force));
        }
        BodyActuator::Magnetic {
            moment,
            field,
            gradient,
        } => {
            t.insert("moment".into(), Value::Float(*moment));
            t.insert("field".into(), arr(field));
            t.insert(
                "gradient".into(),
                Value::Array(gradient.iter().map(arr).collect()),
            );
        }
    }
}

/// What the models cannot apply: the reduced model none of the body
/// actuators, the vector model a tip off the symmetry axis (its dynamics
/// read only the axis `k`, not the spin angle). Errors name `{prefix}.KEY`.
pub fn check_model(a: &BodyActuator, prefix: &str, model: ModelKind) -> Result<(), Error> {
    let kind = a.name();
    match model {
        ModelKind::Reduced => Err(Error::invalid(
            &format!("{prefix}.kind"),
            format!("\"{kind}\" is not available in model = \"reduced\""),
            "kind = \"tip\" and \"magnetic\" need model = \"vector\" (the default) or \"rigid\""
                .into(),
        )),
        ModelKind::Vector if a.off_axis() => Err(Error::invalid(
            &format!("{prefix}.point"),
            "is off the symmetry axis, which model = \"vector\" cannot apply (its dynamics read only the axis k, not the spin angle)".into(),
            "point = [0, 0, z] with model = \"vector\"; any point with model = \"rigid\"".into(),
        )),
        _ => Ok(()),
    }
}
