//! The body: an axisymmetric sphere whose centre of mass is offset from its
//! geometric centre along the symmetry axis.
//!
//! Conventions (see `docs/physics.md`): the symmetry axis `k` points from the
//! centre of mass `O` towards the geometric centre `C`, so `C = O + a k`, and
//! the height of the centre of mass above the plane is `h(θ) = R − a cos θ`.
//! `θ = 0` is "standing up" (centre of mass lowest), `θ = π` is inverted.

use toml::{Table, Value};

use crate::Error;
use crate::error::num;
use crate::input::Key;
use crate::input::field::{Bounds, Num};
use crate::input::reader::{Keys, Section};

/// Geometry and mass properties of the top. SI units throughout.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Top {
    /// Sphere radius `R` \[m\].
    pub radius: f64,
    /// Distance `a` from the geometric centre to the centre of mass \[m\], `0 <= a < R`.
    pub offset: f64,
    /// Mass `m` \[kg\].
    pub mass: f64,
    /// Transverse principal moment `A` about the centre of mass \[kg m²\].
    pub inertia_transverse: f64,
    /// Axial principal moment `C` about the centre of mass \[kg m²\].
    pub inertia_axial: f64,
    /// The stem (`top.stem_radius`, `top.stem_distance`), if any: a second
    /// contact sphere on the symmetry axis (docs/physics.md#stem).
    pub stem: Option<Stem>,
}

/// The stem of a tippe top: a second sphere of radius `r2` whose centre is
/// on the symmetry axis at `S = O + d2 k`, on the same side of the centre of
/// mass `O` as the main sphere's centre `C = O + a k` (the stem points up
/// when the top stands on its heavy end). docs/physics.md#stem.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Stem {
    /// Radius `r2` of the stem's end sphere \[m\], `0 < r2 < R`.
    pub radius: f64,
    /// Distance `d2` from the centre of mass to the stem sphere's centre
    /// along `k` \[m\], `d2 − a > R − r2`.
    pub distance: f64,
}

/// Valid range of `top.stem_radius`.
pub const STEM_RADIUS_RANGE: &str =
    "0 < stem_radius < radius [m], given together with stem_distance (both absent: no stem)";
/// Valid range of `top.stem_distance`.
pub const STEM_DISTANCE_RANGE: &str = "stem_distance - offset > radius - stem_radius [m] (else the stem never touches), given together with stem_radius";

impl Top {
    /// The paper's C60 nano top (Sec. 3): R = 3.55 Å, a = 0.1 R,
    /// m = 1.196e-24 kg, A = (2/3) m R², C = A/2.
    pub fn nano() -> Self {
        let radius = 3.55e-10;
        let mass = 1.196e-24;
        let a = 2.0 / 3.0 * mass * radius * radius;
        Top {
            radius,
            // a = 0.1 R = 0.355 Å, with its digits (`0.1 * radius` rounds
            // to 3.5500000000000007e-11).
            offset: 3.55e-11,
            mass,
            inertia_transverse: a,
            inertia_axial: 0.5 * a,
            stem: None,
        }
    }

    /// The paper's classical benchmark (end of App. A): R = 0.015 m,
    /// a = 0.1 R, m = 0.015 kg, A = C = (2/5) m R².
    pub fn classical() -> Self {
        let radius = 0.015;
        let mass = 0.015;
        // A = C = (2/5) M R² = 1.35e-6 kg m², written with the digits the
        // paper's values give it: `0.4 * mass * radius * radius` rounds to
        // 1.3499999999999998e-6, one ulp below, which every resolved
        // scenario file would then show (tests/preset_digits.rs checks both).
        let i = 1.35e-6;
        Top {
            radius,
            offset: 0.1 * radius,
            mass,
            inertia_transverse: i,
            inertia_axial: i,
            stem: None,
        }
    }

    /// Height of the centre of mass above the plane, `h(θ) = R − a cos θ` \[m\].
    pub fn height(&self, theta: f64) -> f64 {
        self.radius - self.offset * theta.cos()
    }

    /// Check the physical ranges; the error names the scenario key.
    pub fn validate(&self) -> Result<(), Error> {
        let t = self;
        for k in [RADIUS, MASS, INERTIA_TRANSVERSE, INERTIA_AXIAL] {
            k.check("top", t)?;
        }
        if !t.offset.is_finite() || t.offset < 0.0 || t.offset >= t.radius {
            return Err(Error::invalid(
                "top.offset",
                format!("{} is out of range", num(t.offset)),
                format!("0 <= offset < radius = {}", num(t.radius)),
            ));
        }
        if t.inertia_axial > 2.0 * t.inertia_transverse {
            return Err(Error::invalid(
                "top.inertia_axial",
                format!(
                    "C = {} exceeds 2A = {} (no rigid body has that)",
                    t.inertia_axial,
                    2.0 * t.inertia_transverse
                ),
                "0 < inertia_axial <= 2 * inertia_transverse".to_string(),
            ));
        }
        if let Some(st) = t.stem {
            if !st.radius.is_finite() || st.radius <= 0.0 || st.radius >= t.radius {
                return Err(Error::invalid(
                    "top.stem_radius",
                    format!("{} is out of range", num(st.radius)),
                    format!("0 < stem_radius < radius = {}", num(t.radius)),
                ));
            }
            if !st.distance.is_finite() || st.distance - t.offset <= t.radius - st.radius {
                return Err(Error::invalid(
                    "top.stem_distance",
                    format!(
                        "{} is out of range (the stem sphere lies inside the main sphere: it never touches the plane)",
                        num(st.distance)
                    ),
                    format!(
                        "stem_distance > offset + radius - stem_radius = {} [m]",
                        num(t.offset + t.radius - st.radius)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `cos θ_td = −(R − r2)/(d2 − a)`: the stem touches the plane while the
    /// main sphere rests on it at `θ_td` (docs/physics.md#stem); `None`
    /// without a stem.
    pub fn stem_touchdown_cos(&self) -> Option<f64> {
        self.stem
            .map(|st| -(self.radius - st.radius) / (st.distance - self.offset))
    }
}

// ---------------------------------------------------------------------------
// The `[top]` keys: defined once, read, written.

/// The range the checks of `radius`, `mass` and the inertias state.
const POSITIVE: &str = "a finite number > 0";

/// `top.radius`.
pub const RADIUS: Num<Top> = Num {
    key: Key::doc(
        "radius",
        "a finite length > 0 [m]",
        "required",
        "R, the sphere's radius",
    ),
    default: None,
    bounds: Bounds::Above(0.0),
    check_range: Some(POSITIVE),
    get: |t| t.radius,
    set: |t, v| t.radius = v,
};

/// `top.offset`.
pub const OFFSET: Num<Top> = Num {
    key: Key::doc(
        "offset",
        "0 <= offset < radius [m]",
        "required",
        "a, from the sphere's centre to the centre of mass",
    ),
    default: None,
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |t| t.offset,
    set: |t, v| t.offset = v,
};

/// `top.mass`.
pub const MASS: Num<Top> = Num {
    key: Key::doc(
        "mass",
        "a finite mass > 0 [kg]",
        "required",
        "m, the top's mass",
    ),
    default: None,
    bounds: Bounds::Above(0.0),
    check_range: Some(POSITIVE),
    get: |t| t.mass,
    set: |t, v| t.mass = v,
};

/// `top.inertia_transverse`.
pub const INERTIA_TRANSVERSE: Num<Top> = Num {
    key: Key::doc(
        "inertia_transverse",
        "a finite moment > 0 [kg m^2]",
        "required",
        "A, moment of inertia about a transverse axis through the centre of mass",
    ),
    default: None,
    bounds: Bounds::Above(0.0),
    check_range: Some(POSITIVE),
    get: |t| t.inertia_transverse,
    set: |t, v| t.inertia_transverse = v,
};

/// `top.inertia_axial`.
pub const INERTIA_AXIAL: Num<Top> = Num {
    key: Key::doc(
        "inertia_axial",
        "0 < inertia_axial <= 2 * inertia_transverse [kg m^2]",
        "required",
        "C, moment of inertia about the symmetry axis",
    ),
    default: None,
    bounds: Bounds::Above(0.0),
    check_range: Some(POSITIVE),
    get: |t| t.inertia_axial,
    set: |t, v| t.inertia_axial = v,
};

/// The number keys of `[top]`, in document order: read, written and
/// listed from their definitions. Their ranges are checked in
/// [`Top::validate`] (`offset` against `radius`, `inertia_axial` against
/// `2 inertia_transverse`: rules between two keys).
pub const NUMS: [Num<Top>; 5] = [RADIUS, OFFSET, MASS, INERTIA_TRANSVERSE, INERTIA_AXIAL];

/// Every `[top]` key, in document order (`tippetop keys top`).
pub const KEYS: Keys = &[
    RADIUS.key,
    OFFSET.key,
    MASS.key,
    INERTIA_TRANSVERSE.key,
    INERTIA_AXIAL.key,
    Key::doc(
        "stem_radius",
        STEM_RADIUS_RANGE,
        "no stem",
        "r2, the stem's end sphere (rigid model; docs/physics.md#stem)",
    ),
    Key::doc(
        "stem_distance",
        STEM_DISTANCE_RANGE,
        "no stem",
        "d2, centre of mass to the stem sphere's centre, along the axis",
    ),
];

/// The `[top]` table (types and required keys, in document order; the
/// stem: both keys or neither; no range checks: [`Top::validate`]).
pub(crate) fn parse(s: &Section, has_preset: bool) -> Result<Top, Error> {
    let mut top = Top {
        radius: 0.0,
        offset: 0.0,
        mass: 0.0,
        inertia_transverse: 0.0,
        inertia_axial: 0.0,
        stem: None,
    };
    for k in NUMS {
        k.read(s, has_preset, &mut top)?;
    }
    // The stem (§stem): both keys or neither.
    let top = match (s.get("stem_radius"), s.get("stem_distance")) {
        (None, None) => top,
        (Some(_), Some(_)) => Top {
            stem: Some(Stem {
                radius: s.f64("stem_radius", None)?,
                distance: s.f64("stem_distance", None)?,
            }),
            ..top
        },
        (Some(_), None) => {
            return Err(Error::invalid(
                "top.stem_distance",
                "missing (top.stem_radius is given)".into(),
                STEM_DISTANCE_RANGE.into(),
            ));
        }
        (None, Some(_)) => {
            return Err(Error::invalid(
                "top.stem_radius",
                "missing (top.stem_distance is given)".into(),
                STEM_RADIUS_RANGE.into(),
            ));
        }
    };
    Ok(top)
}

/// The `[top]` table of `t` (the stem's keys only with a stem).
pub(crate) fn to_table(t: &Top) -> Table {
    let mut top = Table::new();
    for k in NUMS {
        k.write(t, &mut top);
    }
    if let Some(st) = t.stem {
        top.insert("stem_radius".into(), Value::Float(st.radius));
        top.insert("stem_distance".into(), Value::Float(st.distance));
    }
    top
}
