//! The applied forces at the contact point, as a schedule of windows in
//! time (the `[[force]]` tables): the data that the force terms of
//! [`crate::physics::forces`] read.
//!
//! Following the paper's eq. (1.3), the total retarding force is
//! `F = −μ N v_P/|v_P| − (H_x, H_y)`: the window values `(hx, hy)` are the
//! paper's `H`, and the force on the top is `−H`. Components are in the
//! precessing frame: `x` horizontal towards the tilt of the symmetry axis,
//! `y = Z × x`. `hz` is a vertical load at the same point, positive
//! pushing the top onto the plane (the force on the top is `−hz Z`,
//! docs/physics.md#vertical-load).

use crate::Error;

/// One window: `(hx, hy, hz)` acts on `[start, stop)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceWindow {
    /// `H_x` \[N\] (the force on the top is `−H_x` along x).
    pub hx: f64,
    /// `H_y` \[N\].
    pub hy: f64,
    /// Vertical load `h_z` at the contact point \[N\], positive pushing
    /// the top onto the plane (the force on the top is `−h_z Z`).
    pub hz: f64,
    /// Switch-on time \[s\], `>= 0`.
    pub start: f64,
    /// Switch-off time \[s\], `> start`; `f64::INFINITY` for never.
    pub stop: f64,
}

/// A schedule of force windows; overlapping windows add.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Forcing {
    /// The windows, in the order given.
    pub windows: Vec<ForceWindow>,
}

impl Forcing {
    /// No applied force.
    pub fn none() -> Self {
        Forcing::default()
    }

    /// A constant `(hx, hy)` from t = 0 on \[N\].
    pub fn constant(hx: f64, hy: f64) -> Self {
        Forcing {
            windows: vec![ForceWindow {
                hx,
                hy,
                hz: 0.0,
                start: 0.0,
                stop: f64::INFINITY,
            }],
        }
    }

    /// `(H_x, H_y)` at time `t` \[N\]: the sum over windows with `start <= t < stop`.
    pub fn at(&self, t: f64) -> (f64, f64) {
        let mut h = (0.0, 0.0);
        for w in &self.windows {
            if w.start <= t && t < w.stop {
                h.0 += w.hx;
                h.1 += w.hy;
            }
        }
        h
    }

    /// The vertical load `h_z` at time `t` \[N\]: the sum over windows with
    /// `start <= t < stop` (`+0` when none applies).
    pub fn load_at(&self, t: f64) -> f64 {
        let mut hz = 0.0;
        for w in &self.windows {
            if w.start <= t && t < w.stop {
                hz += w.hz;
            }
        }
        hz
    }

    /// All switch times (window starts and finite stops), sorted, deduplicated \[s\].
    pub fn switch_times(&self) -> Vec<f64> {
        let mut v: Vec<f64> = self
            .windows
            .iter()
            .flat_map(|w| [w.start, w.stop])
            .filter(|t| t.is_finite())
            .collect();
        v.sort_by(f64::total_cmp);
        v.dedup();
        v
    }

    /// True if no window ever applies a non-zero force.
    pub fn is_zero(&self) -> bool {
        self.windows
            .iter()
            .all(|w| w.hx == 0.0 && w.hy == 0.0 && w.hz == 0.0)
    }

    /// True if some window applies a vertical load `h_z != 0`.
    pub fn has_load(&self) -> bool {
        self.windows.iter().any(|w| w.hz != 0.0)
    }

    /// Largest |H| (horizontal, the paper's force) any combination of
    /// windows can reach (upper bound) \[N\].
    pub fn max_magnitude(&self) -> f64 {
        let sx: f64 = self.windows.iter().map(|w| w.hx.abs()).sum();
        let sy: f64 = self.windows.iter().map(|w| w.hy.abs()).sum();
        sx.hypot(sy)
    }

    /// Largest `|(H_x, H_y, h_z)|` any combination of windows can reach
    /// (upper bound) \[N\]: [`Forcing::max_magnitude`] when no window has a
    /// vertical load (`hypot(x, 0) = |x|` exactly).
    pub fn max_contact_force(&self) -> f64 {
        let sz: f64 = self.windows.iter().map(|w| w.hz.abs()).sum();
        self.max_magnitude().hypot(sz)
    }

    /// Check each window; errors name `force.K.key` (0-based K). Forces
    /// must be finite here; the run limits
    /// (`scenario::limits::check_run`) also need the time unit they set,
    /// `sqrt(|(H_x, H_y, h_z)| / (m R))`, finite.
    pub fn validate(&self) -> Result<(), Error> {
        for (k, w) in self.windows.iter().enumerate() {
            for (name, v) in [("hx", w.hx), ("hy", w.hy), ("hz", w.hz)] {
                if !v.is_finite() {
                    return Err(Error::invalid(
                        &format!("force.{k}.{name}"),
                        format!("{} is not allowed", crate::human::exact(v)),
                        "a finite force [N]".into(),
                    ));
                }
            }
            if !w.start.is_finite() || w.start < 0.0 {
                return Err(Error::invalid(
                    &format!("force.{k}.start"),
                    format!("{} is not allowed", crate::human::exact(w.start)),
                    "a finite time >= 0 [s]".into(),
                ));
            }
            if w.stop.is_nan() || w.stop <= w.start {
                return Err(Error::invalid(
                    &format!("force.{k}.stop"),
                    format!("{} is not after start = {}", w.stop, w.start),
                    "stop > start [s], or omit stop for never".into(),
                ));
            }
        }
        Ok(())
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

/// A body actuator acting on `[start, stop)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ActuatorWindow {
    /// What acts.
    pub actuator: BodyActuator,
    /// Switch-on time \[s\], `>= 0`.
    pub start: f64,
    /// Switch-off time \[s\], `> start`; `f64::INFINITY` for never.
    pub stop: f64,
}

impl ActuatorWindow {
    /// True if it acts at `t` \[s\].
    pub fn active(&self, t: f64) -> bool {
        self.start <= t && t < self.stop
    }

    /// Check the values and the times; errors name `{prefix}.KEY`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        self.actuator.validate(prefix)?;
        if !self.start.is_finite() || self.start < 0.0 {
            return Err(Error::invalid(
                &format!("{prefix}.start"),
                format!("{} is not allowed", crate::human::exact(self.start)),
                "a finite time >= 0 [s]".into(),
            ));
        }
        if self.stop.is_nan() || self.stop <= self.start {
            return Err(Error::invalid(
                &format!("{prefix}.stop"),
                format!("{} is not after start = {}", self.stop, self.start),
                "stop > start [s], or omit stop for never".into(),
            ));
        }
        Ok(())
    }
}
