//! The surface: gravity, friction law and what a negative normal force means.
//!
//! Every friction law here is written as `F_f = −N f(v_P)` (or `−|N| f(v_P)`
//! under [`ContactMode::Bilateral`]), where `v_P` is the horizontal slip
//! velocity of the contact point and `f` is a vector with `|f| <= μ`:
//!
//! | law | `f(v)` |
//! |---|---|
//! | [`FrictionLaw::CoulombSliding`] | `μ v/|v|`, and `0` at exactly `v = 0` |
//! | [`FrictionLaw::Regularized`] | `μ v/sqrt(|v|² + ε²)` |
//! | [`FrictionLaw::Viscous`] | `μ v/ε` (the small-slip limit of the regularised law; unbounded) |
//! | [`FrictionLaw::Coulomb`] | exact set-valued Coulomb: sliding as above, rolling when the needed friction is within the cone |
//! | [`FrictionLaw::Contensou`] | Coulomb's law integrated over a contact disc of radius `r_c` (docs/physics.md#contensou): `μ f(d) v/|v|` with a drilling torque about the normal, `d = |v|/(r_c |n_Z|)`; at `r_c = 0` the exact point law |

use std::f64::consts::PI;

use toml::{Table, Value};

use crate::Error;
use crate::input::Key;
use crate::input::field::{Bounds, Num};
use crate::input::reader::{Keys, Section, name_of};

/// The table's name.
const TABLE: &str = "surface";

/// Pressure distribution over the contact disc of Coulomb–Contensou
/// friction (docs/physics.md#contensou; the law is `physics::contensou`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pressure {
    /// Hertz: `p ∝ √(1 − ρ²)` (the elastic sphere on a plane; default).
    Hertz,
    /// Uniform: `p` constant (a flat rigid face, the Contensou/Farkas disc).
    Uniform,
}

impl Pressure {
    /// Scenario name (`surface.contact_pressure`).
    pub fn name(&self) -> &'static str {
        match self {
            Pressure::Hertz => "hertz",
            Pressure::Uniform => "uniform",
        }
    }

    /// The drilling torque at zero slip over `μ N r_c`: `⟨ρ⟩` =
    /// 2/3 (uniform), 3π/16 (Hertz). It is also the stick bound of the
    /// torque with no force.
    pub fn zero_slip_torque(&self) -> f64 {
        match self {
            Pressure::Uniform => 2.0 / 3.0,
            Pressure::Hertz => 3.0 * PI / 16.0,
        }
    }

    /// The small-slip slope `f'(0)`: `f ≈ f'(0) d`, `f'(0) = ½ ⟨1/ρ⟩` =
    /// 1 (uniform), 3π/8 (Hertz).
    pub fn small_slip_slope(&self) -> f64 {
        match self {
            Pressure::Uniform => 1.0,
            Pressure::Hertz => 3.0 * PI / 8.0,
        }
    }

    /// `⟨ρ²⟩` = 1/2 (uniform), 2/5 (Hertz): the large-slip tails are
    /// `1 − f ≈ ⟨ρ²⟩/(4 d²)` and `m ≈ ⟨ρ²⟩/(2 d)`.
    pub fn second_moment(&self) -> f64 {
        match self {
            Pressure::Uniform => 0.5,
            Pressure::Hertz => 0.4,
        }
    }
}

/// Friction law at the contact point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FrictionLaw {
    /// Exact (set-valued) Coulomb friction with stick/slip switching.
    Coulomb,
    /// The paper's `μ N v/|v|`, sliding only; `f = 0` at exactly zero slip.
    CoulombSliding,
    /// `μ N v/sqrt(|v|² + ε²)`, `eps` in m/s.
    Regularized {
        /// Regularisation speed ε \[m/s\].
        eps: f64,
    },
    /// `μ N v/ε`, `eps` in m/s.
    Viscous {
        /// Slip speed ε \[m/s\] at which the force reaches `μ N`.
        eps: f64,
    },
    /// Coulomb–Contensou friction over a contact disc (docs/physics.md
    /// §contensou): the sliding force and the drilling torque about the contact
    /// normal, coupled. `radius = 0` is the exact point law
    /// ([`FrictionLaw::Coulomb`]), bit for bit.
    Contensou {
        /// Contact radius `r_c` \[m\] (scaled inside the models).
        radius: f64,
        /// Pressure distribution over the disc.
        pressure: Pressure,
        /// The smooth Padé form instead of the exact integral.
        pade: bool,
    },
}

/// The speed `|v| + r_c |n_Z|` (scaled: units of the initial `R × rate`,
/// docs/physics.md#scaling) at which a run under Coulomb–Contensou friction
/// declares sliding and spinning both stopped (§contensou).
pub const CONTENSOU_STICK_SPEED: f64 = 1e-7;

/// Valid range of `surface.contact_radius`, as the error messages state it.
pub const CONTACT_RADIUS_RANGE: &str =
    "0 <= contact_radius <= 0.1 * top.radius [m] (a contact patch much smaller than the sphere)";

impl FrictionLaw {
    /// Scenario name of the law.
    pub fn name(&self) -> &'static str {
        match self {
            FrictionLaw::Coulomb => "coulomb",
            FrictionLaw::CoulombSliding => "coulomb_sliding",
            FrictionLaw::Regularized { .. } => "regularized",
            FrictionLaw::Viscous { .. } => "viscous",
            FrictionLaw::Contensou { pade: false, .. } => "contensou",
            FrictionLaw::Contensou { pade: true, .. } => "contensou_pade",
        }
    }

    /// The contact radius and pressure of a Contensou law.
    pub fn contensou(&self) -> Option<(f64, Pressure, bool)> {
        match *self {
            FrictionLaw::Contensou {
                radius,
                pressure,
                pade,
            } => Some((radius, pressure, pade)),
            _ => None,
        }
    }

    /// The regularisation speed, if the law has one \[m/s\].
    pub fn eps(&self) -> Option<f64> {
        match self {
            FrictionLaw::Regularized { eps } | FrictionLaw::Viscous { eps } => Some(*eps),
            _ => None,
        }
    }
}

/// A sliding friction law, the one interface every model uses: the friction
/// force on the top is `−N f(v)` for slip velocity `v`, with `|f| <= μ`
/// for the Coulomb laws (the viscous law is unbounded). Stick/slip (the
/// exact law) is not a function of `v` alone: the models handle it as a
/// mode on top of this (docs/physics.md#coulomb).
pub trait SlidingLaw {
    /// `f(v)` for friction coefficient `mu` and slip `v` (same speed unit as
    /// the law's ε). The Coulomb laws give `μ v/|v|`, and 0 at exactly `v = 0`.
    fn coefficient(&self, mu: f64, v: [f64; 2]) -> [f64; 2];
}

impl SlidingLaw for FrictionLaw {
    // Inlined into the models' right-hand sides, where it sits on the
    // critical path: one division per law (`k = μ/|v|`, then products)
    // instead of one per component. Always: as a plain `#[inline]` it
    // stayed a call (~26 instructions of call overhead per evaluation).
    #[inline(always)]
    fn coefficient(&self, mu: f64, v: [f64; 2]) -> [f64; 2] {
        match *self {
            FrictionLaw::Coulomb | FrictionLaw::CoulombSliding | FrictionLaw::Contensou { .. } => {
                // |v| as sqrt(v_x² + v_y²) while the sum of squares is a
                // normal number (no overflow or underflow: within an ulp of
                // `hypot`) and μ/|v| cannot overflow (|v| >= 1.4e-154 there);
                // otherwise `hypot` and the division per component, so tiny
                // slips keep their direction and huge ones do not overflow.
                let r2 = v[0] * v[0] + v[1] * v[1];
                if (f64::MIN_POSITIVE..f64::INFINITY).contains(&r2) && mu < 1e150 {
                    let k = mu / r2.sqrt();
                    return [k * v[0], k * v[1]];
                }
                let n = v[0].hypot(v[1]);
                if n > 0.0 {
                    [mu * v[0] / n, mu * v[1] / n]
                } else {
                    [0.0, 0.0]
                }
            }
            FrictionLaw::Regularized { eps } => {
                let k = mu / (v[0] * v[0] + v[1] * v[1] + eps * eps).sqrt();
                [k * v[0], k * v[1]]
            }
            FrictionLaw::Viscous { eps } => [mu * v[0] / eps, mu * v[1] / eps],
        }
    }
}

impl FrictionLaw {
    /// The same law with its ε divided by `speed_unit` (for scaled models).
    pub fn scaled(&self, speed_unit: f64) -> FrictionLaw {
        match *self {
            FrictionLaw::Regularized { eps } => FrictionLaw::Regularized {
                eps: eps / speed_unit,
            },
            FrictionLaw::Viscous { eps } => FrictionLaw::Viscous {
                eps: eps / speed_unit,
            },
            other => other,
        }
    }
}

/// What the model does when the normal force `N` would become negative.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ContactMode {
    /// The top is held on the plane; friction has magnitude `μ|N|` and always
    /// opposes the slip. The default.
    Bilateral,
    /// Held on the plane, and the paper's formula `−μ N v/|v|` is used with
    /// `N`'s sign (pushes along the slip when `N < 0`).
    Paper,
    /// The top may leave the plane: the reduced model stops with an error at
    /// lift-off; the rigid model flies.
    Unilateral,
}

impl ContactMode {
    /// Scenario name of the mode.
    pub fn name(&self) -> &'static str {
        match self {
            ContactMode::Bilateral => "bilateral",
            ContactMode::Paper => "paper",
            ContactMode::Unilateral => "unilateral",
        }
    }
}

/// The surface's shape (`surface.shape`; docs/physics.md#tube-dynamics).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Shape {
    /// The horizontal plane `z = 0` (the default).
    #[default]
    Plane,
    /// The inside of a horizontal cylinder (rigid model only): axis along
    /// lab X through `(y, z) = (0, radius)`, so that its lowest line is
    /// `z = 0`; the top starts with its contact point turned by `angle`
    /// about the axis from the lowest line (towards +y for `angle > 0`).
    Tube {
        /// The tube's radius `b` \[m\] (`surface.tube_radius`), `> top.radius`.
        radius: f64,
        /// The initial angle of the contact point about the tube's axis,
        /// from the lowest line \[rad\] (`surface.tube_angle`), `|angle| < π/2`.
        angle: f64,
    },
}

impl Shape {
    /// Scenario name (`surface.shape`).
    pub fn name(&self) -> &'static str {
        match self {
            Shape::Plane => "plane",
            Shape::Tube { .. } => "tube",
        }
    }

    /// The tube's `(radius [m], initial angle [rad])`, `None` on the plane.
    pub fn tube(&self) -> Option<(f64, f64)> {
        match *self {
            Shape::Tube { radius, angle } => Some((radius, angle)),
            Shape::Plane => None,
        }
    }
}

/// Valid range of `surface.tube_radius`, as the error messages state it.
pub const TUBE_RADIUS_RANGE: &str = "a finite radius > top.radius [m] (the inside of the tube must hold the contact sphere), required with shape = \"tube\"";
/// Valid range of `surface.tube_angle`, as the error messages state it.
pub const TUBE_ANGLE_RANGE: &str = "a finite angle with |tube_angle| < pi/2 [rad] (below the tube's axis), only with shape = \"tube\"";

/// The plane the top spins on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Surface {
    /// Gravitational acceleration `g` \[m/s²\], `>= 0`.
    pub gravity: f64,
    /// Friction coefficient `μ` (dimensionless), `>= 0`.
    pub friction: f64,
    /// Friction law.
    pub law: FrictionLaw,
    /// Contact mode.
    pub contact: ContactMode,
    /// Normal coefficient of restitution at touchdown (rigid model, unilateral contact), in \[0, 1\].
    pub restitution: f64,
    /// The plane (default) or the inside of a tube.
    pub shape: Shape,
}

impl Surface {
    /// The keys' defaults: gravity 9.8 m/s², exact Coulomb friction with
    /// `friction` 0 (required in a scenario), bilateral contact, no
    /// restitution, the plane.
    pub fn defaults() -> Surface {
        let mut s = Surface {
            gravity: 0.0,
            friction: 0.0,
            law: FrictionLaw::Coulomb,
            contact: ContactMode::Bilateral,
            restitution: 0.0,
            shape: Shape::Plane,
        };
        for k in NUMS {
            (k.set)(&mut s, k.default.unwrap_or(0.0));
        }
        s
    }

    /// Check physical ranges (the number keys first, [`NUMS`], then the
    /// law's parameters and the rules between keys); the error names the
    /// scenario key.
    pub fn validate(&self) -> Result<(), Error> {
        for k in NUMS {
            k.check(TABLE, self)?;
        }
        if let Some(eps) = self.law.eps() {
            if !eps.is_finite() || eps <= 0.0 {
                return Err(Error::invalid(
                    "surface.friction_eps",
                    format!("{} is not allowed", crate::human::exact(eps)),
                    "a finite speed > 0 [m/s]".into(),
                ));
            }
        }
        if let Some((r, _, _)) = self.law.contensou() {
            if !r.is_finite() || r < 0.0 {
                return Err(Error::invalid(
                    "surface.contact_radius",
                    format!("{} is not allowed", crate::human::exact(r)),
                    CONTACT_RADIUS_RANGE.into(),
                ));
            }
            if self.contact == ContactMode::Paper {
                return Err(Error::invalid(
                    "surface.friction_law",
                    format!(
                        "\"{}\" cannot be combined with contact = \"paper\"",
                        self.law.name()
                    ),
                    "use \"coulomb_sliding\", \"regularized\" or \"viscous\" with contact = \"paper\""
                        .into(),
                ));
            }
        }
        if let Some((b, angle)) = self.shape.tube() {
            if !b.is_finite() || b <= 0.0 {
                return Err(Error::invalid(
                    "surface.tube_radius",
                    format!("{} is not allowed", crate::human::exact(b)),
                    TUBE_RADIUS_RANGE.into(),
                ));
            }
            if !angle.is_finite() || angle.abs() >= 0.5 * PI {
                return Err(Error::invalid(
                    "surface.tube_angle",
                    format!("{} is not allowed", crate::human::exact(angle)),
                    TUBE_ANGLE_RANGE.into(),
                ));
            }
        }
        if self.law == FrictionLaw::Coulomb && self.contact == ContactMode::Paper {
            return Err(Error::invalid(
                "surface.friction_law",
                "\"coulomb\" (exact stick/slip) cannot be combined with contact = \"paper\"".into(),
                "use \"coulomb_sliding\", \"regularized\" or \"viscous\" with contact = \"paper\""
                    .into(),
            ));
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// The `[surface]` keys: defined once, read, written.

/// `surface.gravity`.
pub const GRAVITY: Num<Surface> = Num {
    key: Key::doc("gravity", "a finite number >= 0 [m/s^2]", "9.8", "g"),
    default: Some(9.8),
    bounds: Bounds::AtLeast(0.0),
    check_range: Some("a finite number >= 0"),
    get: |s| s.gravity,
    set: |s, v| s.gravity = v,
};

/// `surface.friction`.
pub const FRICTION: Num<Surface> = Num {
    key: Key::doc(
        "friction",
        "a finite number >= 0",
        "required",
        "mu, the friction coefficient",
    ),
    default: None,
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |s| s.friction,
    set: |s, v| s.friction = v,
};

/// `surface.restitution`.
pub const RESTITUTION: Num<Surface> = Num {
    key: Key::doc(
        "restitution",
        "0 <= restitution <= 1",
        "0",
        "coefficient of restitution at touchdown (rigid model)",
    ),
    default: Some(0.0),
    bounds: Bounds::Within(0.0, 1.0),
    check_range: None,
    get: |s| s.restitution,
    set: |s, v| s.restitution = v,
};

/// The number keys of `[surface]` with a field of their own: read,
/// written and checked from their definitions.
pub const NUMS: [Num<Surface>; 3] = [GRAVITY, FRICTION, RESTITUTION];

/// Every `[surface]` key, in document order (`tippetop keys surface`).
pub const KEYS: Keys = &[
    GRAVITY.key,
    FRICTION.key,
    Key::doc(
        "friction_law",
        "\"coulomb\", \"coulomb_sliding\", \"regularized\", \"viscous\", \"contensou\" or \"contensou_pade\"",
        "\"coulomb\"",
        "the friction law (docs/physics.md#contensou)",
    ),
    Key::doc(
        "contact_radius",
        CONTACT_RADIUS_RANGE,
        "required with contensou*",
        "r_c, the contact patch's radius",
    ),
    Key::doc(
        "contact_pressure",
        "\"hertz\" (default) or \"uniform\", only with friction_law = \"contensou\" or \"contensou_pade\"",
        "\"hertz\"",
        "the pressure over the contact patch",
    ),
    Key::doc(
        "friction_eps",
        "a finite speed > 0 [m/s], only with friction_law = \"regularized\" or \"viscous\"",
        "required with regularized/viscous",
        "the regularisation speed",
    ),
    Key::doc(
        "contact",
        "\"bilateral\", \"paper\" or \"unilateral\"",
        "\"bilateral\"",
        "the contact model (held on the plane, the paper's law, or free to lift off)",
    ),
    RESTITUTION.key,
    Key::doc(
        "shape",
        "\"plane\" or \"tube\" (the inside of a horizontal cylinder, axis along x; solver.model = \"rigid\" only)",
        "\"plane\"",
        "the surface (docs/physics.md#tube-dynamics)",
    ),
    Key::doc(
        "tube_radius",
        TUBE_RADIUS_RANGE,
        "required with shape = \"tube\"",
        "b, the tube's inner radius (its lowest line is z = 0)",
    ),
    Key::doc(
        "tube_angle",
        TUBE_ANGLE_RANGE,
        "0",
        "the initial contact point's angle about the tube's axis from the lowest line (> 0 towards +y); the initial state is given in the frame of the local tangent plane",
    ),
];

const LAWS: &[(&str, LawName)] = &[
    ("coulomb", LawName::Coulomb),
    ("coulomb_sliding", LawName::CoulombSliding),
    ("regularized", LawName::Regularized),
    ("viscous", LawName::Viscous),
    ("contensou", LawName::Contensou),
    ("contensou_pade", LawName::ContensouPade),
];

const PRESSURES: &[(&str, Pressure)] =
    &[("hertz", Pressure::Hertz), ("uniform", Pressure::Uniform)];

const CONTACTS: &[(&str, ContactMode)] = &[
    ("bilateral", ContactMode::Bilateral),
    ("paper", ContactMode::Paper),
    ("unilateral", ContactMode::Unilateral),
];

/// Friction law without its parameter.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LawName {
    Coulomb,
    CoulombSliding,
    Regularized,
    Viscous,
    Contensou,
    ContensouPade,
}

/// The `[surface]` table with its friction law's parameters (types,
/// required keys and defaults, the keys each law or shape takes; no range
/// checks: [`Surface::validate`]): the number keys ([`NUMS`]) first, then
/// the law with its parameters, the contact and the shape.
pub(crate) fn parse(s: &Section, has_preset: bool, eps_explicit: bool) -> Result<Surface, Error> {
    let mut surface = Surface::defaults();
    for k in NUMS {
        k.read(s, has_preset, &mut surface)?;
    }
    let law_name = s.name("friction_law", LAWS, LawName::Coulomb)?;
    let uses_eps = matches!(law_name, LawName::Regularized | LawName::Viscous);
    let law_str = name_of(LAWS, law_name);
    let eps = if uses_eps {
        match s.get("friction_eps") {
            None => {
                return Err(Error::invalid(
                    "surface.friction_eps",
                    "missing".into(),
                    format!("required with friction_law = \"{law_str}\": a speed > 0 [m/s]"),
                ));
            }
            Some(_) => s.f64("friction_eps", None)?,
        }
    } else {
        if eps_explicit && s.get("friction_eps").is_some() {
            return Err(Error::invalid(
                "surface.friction_eps",
                format!("given with friction_law = \"{law_str}\", which does not use it"),
                "only with friction_law = \"regularized\" or \"viscous\"".into(),
            ));
        }
        0.0
    };
    let contensou = matches!(law_name, LawName::Contensou | LawName::ContensouPade);
    let (radius, pressure) = if contensou {
        let radius = match s.get("contact_radius") {
            None => {
                return Err(Error::invalid(
                    "surface.contact_radius",
                    "missing".into(),
                    format!(
                        "required with friction_law = \"{law_str}\": {}",
                        CONTACT_RADIUS_RANGE
                    ),
                ));
            }
            Some(_) => s.f64("contact_radius", None)?,
        };
        (
            radius,
            s.name("contact_pressure", PRESSURES, Pressure::Hertz)?,
        )
    } else {
        for key in ["contact_radius", "contact_pressure"] {
            if s.get(key).is_some() {
                return Err(Error::invalid(
                    &format!("surface.{key}"),
                    format!("given with friction_law = \"{law_str}\", which does not use it"),
                    "only with friction_law = \"contensou\" or \"contensou_pade\"".into(),
                ));
            }
        }
        (0.0, Pressure::Hertz)
    };
    let law = match law_name {
        LawName::Contensou | LawName::ContensouPade => FrictionLaw::Contensou {
            radius,
            pressure,
            pade: law_name == LawName::ContensouPade,
        },
        LawName::Coulomb => FrictionLaw::Coulomb,
        LawName::CoulombSliding => FrictionLaw::CoulombSliding,
        LawName::Regularized => FrictionLaw::Regularized { eps },
        LawName::Viscous => FrictionLaw::Viscous { eps },
    };
    surface.law = law;
    surface.contact = s.name("contact", CONTACTS, ContactMode::Bilateral)?;
    surface.shape = shape_of(s)?;
    Ok(surface)
}

/// `surface.shape` with the tube's radius and initial angle.
fn shape_of(s: &Section) -> Result<Shape, Error> {
    let tube = s.name("shape", SHAPES, false)?;
    if !tube {
        for key in ["tube_radius", "tube_angle"] {
            if s.get(key).is_some() {
                return Err(Error::invalid(
                    &format!("surface.{key}"),
                    "given with shape = \"plane\", which does not use it".into(),
                    "only with shape = \"tube\"".into(),
                ));
            }
        }
        return Ok(Shape::Plane);
    }
    if s.get("tube_radius").is_none() {
        return Err(Error::invalid(
            "surface.tube_radius",
            "missing".into(),
            TUBE_RADIUS_RANGE.into(),
        ));
    }
    Ok(Shape::Tube {
        radius: s.f64("tube_radius", None)?,
        angle: s.f64("tube_angle", Some(0.0))?,
    })
}

/// `surface.shape`'s names (true: the tube).
const SHAPES: &[(&str, bool)] = &[("plane", false), ("tube", true)];

/// The `[surface]` table of `s` (the friction law's parameters only when
/// used, the tube's keys only for the tube).
pub(crate) fn to_table(s: &Surface) -> Table {
    let mut surface = Table::new();
    for k in NUMS {
        k.write(s, &mut surface);
    }
    surface.insert("friction_law".into(), Value::String(s.law.name().into()));
    if let Some(eps) = s.law.eps() {
        surface.insert("friction_eps".into(), Value::Float(eps));
    }
    if let Some((radius, pressure, _)) = s.law.contensou() {
        surface.insert("contact_radius".into(), Value::Float(radius));
        surface.insert(
            "contact_pressure".into(),
            Value::String(pressure.name().into()),
        );
    }
    surface.insert("contact".into(), Value::String(s.contact.name().into()));
    // Written only for the tube, so the plane's scenarios keep their text.
    if let Some((radius, angle)) = s.shape.tube() {
        surface.insert("shape".into(), Value::String(s.shape.name().into()));
        surface.insert("tube_radius".into(), Value::Float(radius));
        surface.insert("tube_angle".into(), Value::Float(angle));
    }
    surface
}
