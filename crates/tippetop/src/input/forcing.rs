//! The `[[force]]` schedule: windows in time, each of one kind (`kind =
//! "contact"`, the default: the paper's force `H` and a vertical load at
//! the contact point; `"tip"`, `"magnetic"`: a body actuator). What is the
//! schedule's is here: the windows ([`ForceWindow`], [`ActuatorWindow`]),
//! their times (`start`, `stop`, [`check_times`]), the `kind` that picks the
//! window's keys, the list of a window's keys ([`KEYS`]) and the order of
//! the windows. What a window applies is its term's, in its file with its
//! keys, their parse, checks and rendering: `hx`, `hy` in
//! physics/forces/retarding.rs, `hz` in vertical_load.rs, the actuators'
//! keys in actuators.rs.
//!
//! Following the paper's eq. (1.3), the total retarding force is
//! `F = −μ N v_P/|v_P| − (H_x, H_y)`: the window values `(hx, hy)` are the
//! paper's `H`, and the force on the top is `−H`. Components are in the
//! precessing frame: `x` horizontal towards the tilt of the symmetry axis,
//! `y = Z × x`. `hz` is a vertical load at the same point, positive
//! pushing the top onto the plane (the force on the top is `−hz Z`,
//! docs/physics.md#vertical-load).

use toml::{Table, Value};

use crate::Error;
use crate::input::Key;
use crate::input::reader::Section;
use crate::input::solver::ModelKind;
use crate::physics::forces::{actuators, retarding, vertical_load};

pub use crate::physics::forces::actuators::{
    BOHR_MAGNETON, BodyActuator, MAGNETIC_FIELD_RANGE, MAGNETIC_GRADIENT_RANGE,
    MAGNETIC_MOMENT_RANGE, TIP_FORCE_RANGE, TIP_POINT_RANGE,
};

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

    /// Check each window; errors name `force.K.key` (0-based K): its
    /// values (finite: [`retarding::check`], [`vertical_load::check`]),
    /// then its times ([`check_times`]). The run limits
    /// (`scenario::limits::check_run`) also need the time unit they set,
    /// `sqrt(|(H_x, H_y, h_z)| / (m R))`, finite.
    pub fn validate(&self) -> Result<(), Error> {
        for (k, w) in self.windows.iter().enumerate() {
            let prefix = format!("force.{k}");
            retarding::check(&prefix, [w.hx, w.hy])?;
            vertical_load::check(&prefix, w.hz)?;
            check_times(&prefix, w.start, w.stop)?;
        }
        Ok(())
    }
}

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

    /// Check the values ([`BodyActuator::validate`]) and the times
    /// ([`check_times`]); errors name `{prefix}.KEY`.
    pub fn validate(&self, prefix: &str) -> Result<(), Error> {
        self.actuator.validate(prefix)?;
        check_times(prefix, self.start, self.stop)
    }
}

/// Check a window's times: `start` finite and `>= 0`, `stop > start`
/// (`f64::INFINITY`: never); errors name `{prefix}.start`, `{prefix}.stop`.
pub fn check_times(prefix: &str, start: f64, stop: f64) -> Result<(), Error> {
    if !start.is_finite() || start < 0.0 {
        return Err(Error::invalid(
            &format!("{prefix}.start"),
            format!("{} is not allowed", crate::human::exact(start)),
            START.range.into(),
        ));
    }
    if stop.is_nan() || stop <= start {
        return Err(Error::invalid(
            &format!("{prefix}.stop"),
            format!("{stop} is not after start = {start}"),
            "stop > start [s], or omit stop for never".into(),
        ));
    }
    Ok(())
}

/// The valid values of `kind`.
pub const KIND_RANGE: &str = "\"contact\" (hx, hy, hz: the paper's force at the contact point), \"tip\" (point, force) or \"magnetic\" (moment, field, gradient)";

/// A window's `kind`.
pub const KIND: Key = Key::doc(
    "kind",
    KIND_RANGE,
    "\"contact\"",
    "the window's force: at the contact point, a tip or a magnet",
);

/// A window's `start`.
pub const START: Key = Key::doc(
    "start",
    "a finite time >= 0 [s]",
    "0",
    "when the window starts",
);

/// A window's `stop`.
pub const STOP: Key = Key::doc(
    "stop",
    "a finite time > start [s], or omit stop for never",
    "never",
    "when the window stops",
);

/// Every key of a `[[force]]` window, in document order: the schedule's
/// `kind`, `start`, `stop` and each kind's own (retarding `hx`, `hy`,
/// vertical load `hz`, the actuators').
pub const KEYS: [Key; 11] = [
    KIND,
    retarding::KEYS[0],
    retarding::KEYS[1],
    vertical_load::KEY,
    START,
    STOP,
    actuators::KEYS[0],
    actuators::KEYS[1],
    actuators::KEYS[2],
    actuators::KEYS[3],
    actuators::KEYS[4],
];

/// The keys of a contact window (`kind = "contact"`).
const CONTACT_KEYS: [&str; 3] = [
    retarding::KEYS[0].name,
    retarding::KEYS[1].name,
    vertical_load::KEY.name,
];

/// A window's `kind` (`"contact"` when absent); a key of another kind is
/// an error naming it.
fn kind_of(s: &Section) -> Result<&'static str, Error> {
    let kind = match s.get("kind") {
        None => "contact",
        Some(Value::String(v)) => match v.as_str() {
            "contact" => "contact",
            "tip" => "tip",
            "magnetic" => "magnetic",
            _ => {
                return Err(Error::invalid(
                    &s.full("kind"),
                    format!("unknown value {v:?}"),
                    KIND_RANGE.into(),
                ));
            }
        },
        Some(v) => return Err(s.wrong_type("kind", "a string", v)),
    };
    let own: &[&str] = match kind {
        "contact" => &CONTACT_KEYS,
        _ => actuators::own_keys(kind),
    };
    let others = CONTACT_KEYS
        .iter()
        .chain(actuators::KEYS.iter().map(|k| &k.name));
    if let Some(k) = others
        .filter(|k| !own.contains(k))
        .find(|k| s.get(k).is_some())
    {
        return Err(Error::invalid(
            &s.full(k),
            format!("not a key of kind = \"{kind}\""),
            format!("{kind} windows take {}", own.join(", ")),
        ));
    }
    Ok(kind)
}

/// A window's kind and its actuator: `None` for `"contact"` (or no
/// `kind`), else the body actuator its keys give (types only). Keys of
/// another kind are errors naming them. The `[[write]]` and `[[erase]]`
/// windows of a bit read theirs with it too.
pub(crate) fn parse_actuator(s: &Section) -> Result<Option<BodyActuator>, Error> {
    match kind_of(s)? {
        "contact" => Ok(None),
        kind => actuators::parse(kind, s).map(Some),
    }
}

/// The `[[force]]` windows of `list` (a document's): contact windows and
/// body actuators, each in the order given. Types and defaults; an
/// actuator window is checked at once ([`ActuatorWindow::validate`], and
/// [`actuators::check_model`] against `model()`, the document's
/// `solver.model`, read only then).
pub(crate) fn parse(
    list: &[Value],
    model: impl Fn() -> Result<ModelKind, Error>,
) -> Result<(Forcing, Vec<ActuatorWindow>), Error> {
    let mut windows = Vec::new();
    let mut actuators = Vec::new();
    for (k, w) in list.iter().enumerate() {
        let s = Section {
            prefix: format!("force.{k}"),
            keys: &KEYS,
            table: w.as_table(),
        };
        if let Some(a) = parse_actuator(&s)? {
            let w = ActuatorWindow {
                actuator: a,
                start: s.f64("start", Some(0.0))?,
                stop: s.f64("stop", Some(f64::INFINITY))?,
            };
            w.validate(&s.prefix)?;
            actuators::check_model(&w.actuator, &s.prefix, model()?)?;
            actuators.push(w);
            continue;
        }
        let [hx, hy] = retarding::parse(&s)?;
        windows.push(ForceWindow {
            hx,
            hy,
            hz: vertical_load::parse(&s)?,
            start: s.f64("start", Some(0.0))?,
            stop: s.f64("stop", Some(f64::INFINITY))?,
        });
    }
    Ok((Forcing { windows }, actuators))
}

/// The `[[force]]` list of a schedule as TOML tables: the contact windows,
/// then the body actuators (a window that never stops has no `stop`).
pub(crate) fn to_list(forcing: &Forcing, actuators: &[ActuatorWindow]) -> Vec<Value> {
    let times = |t: &mut Table, start: f64, stop: f64| {
        t.insert(START.name.into(), Value::Float(start));
        if stop != f64::INFINITY {
            t.insert(STOP.name.into(), Value::Float(stop));
        }
    };
    forcing
        .windows
        .iter()
        .map(|w| {
            let mut t = Table::new();
            retarding::to_table([w.hx, w.hy], &mut t);
            vertical_load::to_table(w.hz, &mut t);
            times(&mut t, w.start, w.stop);
            Value::Table(t)
        })
        .chain(actuators.iter().map(|w| {
            let mut t = Table::new();
            actuators::to_table(&w.actuator, &mut t);
            times(&mut t, w.start, w.stop);
            Value::Table(t)
        }))
        .collect()
}
