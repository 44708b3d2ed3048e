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
//! docs/physics.md §17).

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
                        format!("{v} is not allowed"),
                        "a finite force [N]".into(),
                    ));
                }
            }
            if !w.start.is_finite() || w.start < 0.0 {
                return Err(Error::invalid(
                    &format!("force.{k}.start"),
                    format!("{} is not allowed", w.start),
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
