//! The initial state (`[initial]`): Euler angles and rates, or lab-frame vectors.

use toml::Table;

use crate::Error;
use crate::input::Key;
use crate::input::field::{Bounds, Num};
use crate::input::reader::{Keys, Section};

/// The table's name.
const TABLE: &str = "initial";

/// Initial state of the reduced model (SI units, radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Initial {
    /// Nutation angle θ \[rad\], the tilt of the symmetry axis from the vertical.
    pub theta: f64,
    /// θ̇ \[rad/s\].
    pub theta_dot: f64,
    /// Precession rate Ω = φ̇ \[rad/s\].
    pub precession: f64,
    /// Spin ω = n·k, the angular-velocity component along the symmetry axis \[rad/s\].
    pub spin: f64,
    /// Centre-of-mass velocity along the precessing x axis \[m/s\].
    pub ux: f64,
    /// Centre-of-mass velocity along the precessing y axis \[m/s\].
    pub uy: f64,
    /// Heading φ₀ \[rad\]: the angle from the lab X axis to the horizontal
    /// direction the symmetry axis tilts towards at t = 0 (the precessing
    /// frame's x). The dynamics do not depend on it (the plane is isotropic);
    /// the position and attitude columns are turned by it. Default 0.
    pub heading: f64,
}

impl Initial {
    /// The paper's initial state: θ = 0.1, θ̇ = 0, Ω = 0, ω = 100 rad/s, u = 0.
    pub fn paper() -> Self {
        Initial {
            theta: 0.1,
            theta_dot: 0.0,
            precession: 0.0,
            spin: 100.0,
            ux: 0.0,
            uy: 0.0,
            heading: 0.0,
        }
    }

    /// The initial state from lab-frame vectors (Z up): the symmetry axis
    /// `axis` (any nonzero length; it is normalised), the angular velocity
    /// `angular_velocity` \[rad/s\] and the horizontal centre-of-mass
    /// velocity `velocity` \[m/s\] (the vertical one follows from the
    /// contact). With `k` the unit axis, `s = |k_h|`, `c = k_Z`:
    /// θ = atan2(s, c), the heading φ₀ = atan2(k_Y, k_X), ω = n·k,
    /// θ̇ = n·ŷ, Ω = (n_Z − ω c)/s² (x̂ = k_h/s, ŷ = Z × x̂; the inverse of
    /// `n = (ω − Ω c) s x̂ + θ̇ ŷ + (Ω s² + ω c) Z`), u = (v·x̂, v·ŷ).
    /// With the axis vertical (s = 0) the heading is chosen so that the
    /// horizontal angular velocity lies along ŷ (θ̇ = |n_h|, Ω = 0, ω = n·k).
    /// `Err` names the offending vector.
    pub fn from_lab(
        axis: [f64; 3],
        angular_velocity: [f64; 3],
        velocity: [f64; 2],
    ) -> Result<Self, Error> {
        let finite = |name: &str, v: &[f64]| -> Result<(), Error> {
            if v.iter().all(|x| x.is_finite()) {
                Ok(())
            } else {
                Err(Error::invalid(
                    name,
                    format!("{v:?} is not allowed"),
                    "finite components".into(),
                ))
            }
        };
        finite("initial.axis", &axis)?;
        finite("initial.angular_velocity", &angular_velocity)?;
        finite("initial.velocity", &velocity)?;
        let len = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
        if !(len > 0.0 && len.is_finite()) {
            return Err(Error::invalid(
                "initial.axis",
                format!("{axis:?} has no direction"),
                "a nonzero vector [x, y, z] (it is normalised)".into(),
            ));
        }
        let k = [axis[0] / len, axis[1] / len, axis[2] / len];
        let n = angular_velocity;
        let s = k[0].hypot(k[1]);
        let c = k[2];
        let spin = n[0] * k[0] + n[1] * k[1] + n[2] * k[2];
        let (heading, theta_dot, precession) = if s > 0.0 {
            let yh = [-k[1] / s, k[0] / s];
            (
                k[1].atan2(k[0]),
                n[0] * yh[0] + n[1] * yh[1],
                (n[2] - spin * c) / (s * s),
            )
        } else {
            let nh = n[0].hypot(n[1]);
            // ŷ along n_h: x̂ = ŷ × Z = (ŷ_Y, −ŷ_X).
            let heading = if nh > 0.0 { (-n[0]).atan2(n[1]) } else { 0.0 };
            (heading, nh, 0.0)
        };
        let (sh, ch) = heading.sin_cos();
        let (xh, yh) = ([ch, sh], [-sh, ch]);
        Ok(Initial {
            theta: s.atan2(c),
            theta_dot,
            precession,
            spin,
            ux: velocity[0] * xh[0] + velocity[1] * xh[1],
            uy: velocity[0] * yh[0] + velocity[1] * yh[1],
            heading,
        })
    }

    /// The lab-frame vectors of this state: the unit symmetry axis, the
    /// angular velocity \[rad/s\] and the horizontal centre-of-mass velocity
    /// \[m/s\] (the inverse of [`Initial::from_lab`]).
    pub fn to_lab(&self) -> ([f64; 3], [f64; 3], [f64; 2]) {
        let (s, c) = self.theta.sin_cos();
        let (sh, ch) = self.heading.sin_cos();
        let (xh, yh) = ([ch, sh, 0.0], [-sh, ch, 0.0]);
        let (w, om, thd) = (self.spin, self.precession, self.theta_dot);
        let nx = (w - om * c) * s;
        let nz = om * s * s + w * c;
        let k = [s * xh[0], s * xh[1], c];
        let n = [nx * xh[0] + thd * yh[0], nx * xh[1] + thd * yh[1], nz];
        let v = [
            self.ux * xh[0] + self.uy * yh[0],
            self.ux * xh[1] + self.uy * yh[1],
        ];
        (k, n, v)
    }

    /// Check finiteness (and θ in (0, π) if `reduced`).
    pub fn validate(&self, reduced: bool) -> Result<(), Error> {
        for k in NUMS {
            k.check(TABLE, self)?;
        }
        if reduced
            && !(self.theta > 0.0
                && self.theta < std::f64::consts::PI
                && self.theta.sin() >= SIN_GUARD)
        {
            return Err(Error::invalid(
                "initial.theta",
                format!("{} is outside the reduced model's range", self.theta),
                "0 < theta < pi [rad] with sin(theta) >= 1e-8 (the reduced model's pole guard); use model = \"vector\" (the default) or \"rigid\" for theta = 0 or pi".into(),
            ));
        }
        if !reduced && !(0.0..=std::f64::consts::PI).contains(&self.theta) {
            return Err(Error::invalid(
                "initial.theta",
                format!("{} is out of range", self.theta),
                "0 <= theta <= pi [rad]".into(),
            ));
        }
        Ok(())
    }
}

/// |sin θ| below which the reduced (Euler-angle) equations are declared
/// singular: the pole guard of `model::reduced`, also the bound an initial
/// θ of that model is checked against.
pub const SIN_GUARD: f64 = 1e-8;

// ---------------------------------------------------------------------------
// The `[initial]` keys: defined once, read, written.

/// The range a failed finiteness check states.
const FINITE: &str = "a finite number";

/// `initial.theta`.
pub const THETA: Num<Initial> = Num {
    key: Key::doc(
        "theta",
        "0 < theta < pi [rad]; 0 <= theta <= pi with model = \"vector\" (the default) or \"rigid\"",
        "required",
        "the axis's tilt from the vertical",
    ),
    default: None,
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.theta,
    set: |i, v| i.theta = v,
};

/// `initial.theta_dot`.
pub const THETA_DOT: Num<Initial> = Num {
    key: Key::doc("theta_dot", "a finite number [rad/s]", "0", "d theta/dt"),
    default: Some(0.0),
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.theta_dot,
    set: |i, v| i.theta_dot = v,
};

/// `initial.precession`.
pub const PRECESSION: Num<Initial> = Num {
    key: Key::doc(
        "precession",
        "a finite number [rad/s]",
        "0",
        "Omega, the precession rate",
    ),
    default: Some(0.0),
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.precession,
    set: |i, v| i.precession = v,
};

/// `initial.spin`.
pub const SPIN: Num<Initial> = Num {
    key: Key::doc(
        "spin",
        "a finite number [rad/s]",
        "required",
        "omega, the spin rate",
    ),
    default: None,
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.spin,
    set: |i, v| i.spin = v,
};

/// `initial.ux`.
pub const UX: Num<Initial> = Num {
    key: Key::doc(
        "ux",
        "a finite number [m/s]",
        "0",
        "centre-of-mass velocity, precessing frame x",
    ),
    default: Some(0.0),
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.ux,
    set: |i, v| i.ux = v,
};

/// `initial.uy`.
pub const UY: Num<Initial> = Num {
    key: Key::doc(
        "uy",
        "a finite number [m/s]",
        "0",
        "centre-of-mass velocity, precessing frame y",
    ),
    default: Some(0.0),
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.uy,
    set: |i, v| i.uy = v,
};

/// `initial.heading`.
pub const HEADING: Num<Initial> = Num {
    key: Key::doc(
        "heading",
        "a finite angle [rad] from the lab X axis (default 0)",
        "0",
        "the precessing frame's initial heading",
    ),
    default: Some(0.0),
    bounds: Bounds::Finite,
    check_range: Some(FINITE),
    get: |i| i.heading,
    set: |i, v| i.heading = v,
};

/// The number keys of `[initial]`, the Euler-angle form, in document
/// order: read, written, checked (finite; `theta`'s range depends on the
/// model, [`Initial::validate`]) and listed from their definitions.
pub const NUMS: [Num<Initial>; 7] = [THETA, THETA_DOT, PRECESSION, SPIN, UX, UY, HEADING];

/// Every `[initial]` key, in document order (`tippetop keys initial`): the
/// Euler-angle form, then the lab-frame form.
pub const KEYS: Keys = &[
    THETA.key,
    THETA_DOT.key,
    PRECESSION.key,
    SPIN.key,
    UX.key,
    UY.key,
    HEADING.key,
    Key::doc(
        "axis",
        "[x, y, z], the symmetry axis in the lab frame (Z up; nonzero, normalised); with angular_velocity and velocity, instead of theta ... heading",
        "",
        "lab-frame initial state: the symmetry axis",
    ),
    Key::doc(
        "angular_velocity",
        "[x, y, z] [rad/s], lab frame (default [0, 0, 0]; with axis)",
        "[0, 0, 0]",
        "lab-frame initial state: the angular velocity",
    ),
    Key::doc(
        "velocity",
        "[x, y] [m/s], horizontal centre-of-mass velocity, lab frame (default [0, 0]; with axis)",
        "[0, 0]",
        "lab-frame initial state: the centre of mass's velocity",
    ),
];

/// The `[initial]` table: Euler angles and rates, or lab-frame vectors
/// (types, required keys and defaults; no range checks:
/// [`Initial::validate`]).
pub(crate) fn parse(s: &Section, has_preset: bool) -> Result<Initial, Error> {
    let initial = if s.get("axis").is_some() {
        Initial::from_lab(
            s.f64s("axis", None)?,
            s.f64s("angular_velocity", Some([0.0; 3]))?,
            s.f64s("velocity", Some([0.0; 2]))?,
        )?
    } else if let Some(l) = ["angular_velocity", "velocity"]
        .into_iter()
        .find(|l| s.get(l).is_some())
    {
        return Err(Error::invalid(
            &format!("initial.{l}"),
            "given without initial.axis".into(),
            "the lab-frame initial state is axis (required), angular_velocity, velocity".into(),
        ));
    } else {
        let mut i = Initial::paper();
        for k in NUMS {
            k.read(s, has_preset, &mut i)?;
        }
        i
    };
    Ok(initial)
}

/// The `[initial]` table of `i`, the Euler-angle form (`heading` only
/// when set).
pub(crate) fn to_table(i: &Initial) -> Table {
    let mut initial = Table::new();
    for k in NUMS {
        if k.key.name != HEADING.key.name || i.heading != 0.0 {
            k.write(i, &mut initial);
        }
    }
    initial
}
