//! The body: an axisymmetric sphere whose centre of mass is offset from its
//! geometric centre along the symmetry axis.
//!
//! Conventions (see `docs/physics.md`): the symmetry axis `k` points from the
//! centre of mass `O` towards the geometric centre `C`, so `C = O + a k`, and
//! the height of the centre of mass above the plane is `h(θ) = R − a cos θ`.
//! `θ = 0` is "standing up" (centre of mass lowest), `θ = π` is inverted.

use crate::Error;
use crate::error::num;

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
        finite_positive("top.radius", t.radius)?;
        finite_positive("top.mass", t.mass)?;
        finite_positive("top.inertia_transverse", t.inertia_transverse)?;
        finite_positive("top.inertia_axial", t.inertia_axial)?;
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

pub(crate) fn finite_positive(key: &str, v: f64) -> Result<(), Error> {
    if !v.is_finite() || v <= 0.0 {
        return Err(Error::invalid(
            key,
            format!("{} is not allowed", crate::human::exact(v)),
            "a finite number > 0".to_string(),
        ));
    }
    Ok(())
}
