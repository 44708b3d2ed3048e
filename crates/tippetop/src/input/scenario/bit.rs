//! A memory bit in the scenario (issue #16): the two states as windows of
//! θ, and the write and erase protocols as lists of actuator windows.
//!
//! ```toml
//! preset = "nano"
//! [bit]
//! zero = [0.0, 0.5]            # [lo, hi] [rad], default: standing
//! one = [1.2208, 1.9208]       # [rad], default: lying, [pi/2 - 0.35, pi/2 + 0.35]
//! hold = 2e-5                  # [s], > 0: the state must be held this long
//! phase = 1e-4                 # [s], > hold: length of each phase
//! [[write]]                    # times from the start of the write phase
//! kind = "contact"             # default; or "tip", "magnetic" (below)
//! hx = 1e-22                   # [N], the paper's H (the force on the top is -H)
//! hy = 1e-22                   # [N]
//! hz = 0.0                     # [N], optional vertical load
//! start = 0.0                  # [s], default 0
//! stop = 1e-4                  # [s], start < stop <= phase, default phase
//! [[erase]]                    # times from the start of the erase phase
//! hx = -1e-22
//! hy = -1e-22
//! [[erase]]
//! kind = "tip"                 # a tip at a body point (docs/physics.md#actuators)
//! point = [0.0, 0.0, 7e-10]    # [m], body frame (origin the centre of mass, z along k)
//! force = [1e-22, 0.0, 0.0]    # [N], lab frame, the force on the top
//! [[erase]]
//! kind = "magnetic"            # a dipole mu k in a lab field (docs/physics.md#actuators)
//! moment = 9.2740100783e-24    # [A m^2] (one Bohr magneton)
//! field = [0.0, 0.0, 1.0]      # [T], uniform (default 0)
//! gradient = [[0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]]  # [T/m] (default 0)
//! ```
//!
//! The run lasts `2 × phase` (`solver.t_end` is replaced): write on
//! `[0, phase]`, then erase on `[phase, 2 phase]`, from wherever the write
//! left the top. A `"contact"` window is a `[[force]]` window (the paper's
//! force at the contact point, fixed in the precessing frame, which is
//! undefined at θ = 0: no physical actuator does that), at `[start, stop)`
//! for the write and `[phase + start, phase + stop)` for the erase; a
//! `"tip"` or `"magnetic"` window is a body actuator of the run
//! ([`Scenario::actuators`], physics/forces/actuators.rs), at the same times. The
//! scenario's own `[[force]]` list must be empty (a preset's list is
//! replaced by the protocol). `--set` reaches the new keys as `bit.KEY`,
//! `write.K.KEY` and `erase.K.KEY` (`K` equal to the number of windows
//! appends one). The initial θ must lie in `zero`, the two windows must be
//! disjoint, and the output rows (`solver.samples` over `2 × phase`) must
//! give at least [`MIN_ROWS_PER_HOLD`] rows per `hold`: success is judged
//! on the continuous solution (see [`crate::analysis::bit`]), but an
//! excursion within one integration step is not seen, and the adaptive
//! steppers' largest step is the row spacing; the rows also carry the
//! search's merit and the figures.

use toml::{Table, Value};

use crate::input::Key;
use crate::input::reader::{
    Keys, Section, check_keys, describe, parse_document, parse_set_value, range_of, render_keys,
    unknown_key,
};
use crate::physics::forces::{actuators, retarding, vertical_load};
use crate::{ActuatorWindow, BodyActuator, Error, ForceWindow, Forcing, Scenario};

/// Fewest output rows per `bit.hold` (the row spacing bounds the adaptive
/// steppers' step, within which an excursion out of a window and back is
/// not seen: so unseen excursions last less than a tenth of the hold).
pub const MIN_ROWS_PER_HOLD: f64 = 10.0;

/// The default `zero` window \[rad\]: standing.
pub const ZERO_DEFAULT: [f64; 2] = [0.0, 0.5];

/// The default `one` window \[rad\]: lying, `[π/2 − 0.35, π/2 + 0.35]`.
pub const ONE_DEFAULT: [f64; 2] = [
    std::f64::consts::FRAC_PI_2 - 0.35,
    std::f64::consts::FRAC_PI_2 + 0.35,
];

const STATE_RANGE: &str = "[lo, hi] [rad] with 0 <= lo < hi <= pi, zero and one disjoint";

const BIT_KEYS: Keys = &[
    Key::new("zero", STATE_RANGE),
    Key::new("one", STATE_RANGE),
    Key::new("hold", "a finite time > 0 [s]"),
    Key::new("phase", "a finite time > bit.hold [s]"),
];

/// A `[[write]]` or `[[erase]]` window's keys: the `[[force]]` window's
/// (input/forcing.rs, the terms' in physics/forces/), with start and stop
/// from the start of the phase.
const WINDOW_KEYS: Keys = &[
    crate::input::forcing::KIND,
    retarding::KEYS[0],
    retarding::KEYS[1],
    vertical_load::KEY,
    Key::new(
        "start",
        "a finite time >= 0 [s] from the start of the phase",
    ),
    Key::new(
        "stop",
        "a finite time, start < stop <= bit.phase [s] from the start of the phase; default bit.phase",
    ),
    actuators::KEYS[0],
    actuators::KEYS[1],
    actuators::KEYS[2],
    actuators::KEYS[3],
    actuators::KEYS[4],
];

/// The two states and the timing of a bit (the `[bit]` table).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bit {
    /// State 0: `[lo, hi]` of θ \[rad\].
    pub zero: [f64; 2],
    /// State 1: `[lo, hi]` of θ \[rad\].
    pub one: [f64; 2],
    /// How long θ must stay in the target window at the end of a phase \[s\].
    pub hold: f64,
    /// Length of each phase (write, erase) \[s\].
    pub phase: f64,
}

/// The kind of an actuator window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ActuatorKind {
    /// The paper's force `−H` at the contact point, fixed in the
    /// precessing frame (a `[[force]]` window; `hx`, `hy`, `hz`).
    Contact,
    /// A tip or a magnetic dipole (`kind = "tip"`, `"magnetic"`): a body
    /// actuator of the run (docs/physics.md#actuators); `hx`, `hy`, `hz` are 0.
    Body(BodyActuator),
}

impl ActuatorKind {
    /// The name in the scenario file.
    pub fn name(self) -> &'static str {
        match self {
            ActuatorKind::Contact => "contact",
            ActuatorKind::Body(b) => b.name(),
        }
    }
}

/// One window of a protocol (`[[write]]`, `[[erase]]`), times from the
/// start of its phase.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Actuator {
    /// What acts.
    pub kind: ActuatorKind,
    /// `H_x` \[N\] (the force on the top is `−H_x` along the precessing x).
    pub hx: f64,
    /// `H_y` \[N\].
    pub hy: f64,
    /// Vertical load \[N\], > 0 pushes onto the plane.
    pub hz: f64,
    /// Switch-on time from the phase start \[s\].
    pub start: f64,
    /// Switch-off time from the phase start \[s\].
    pub stop: f64,
}

impl Actuator {
    /// `|(h_x, h_y, h_z)|` \[N\] (0 for a body actuator).
    pub fn magnitude(&self) -> f64 {
        (self.hx * self.hx + self.hy * self.hy + self.hz * self.hz).sqrt()
    }

    /// The body actuator's window of the run, `offset` \[s\] the phase's
    /// start; `None` for a contact window.
    pub fn body_window(&self, offset: f64) -> Option<ActuatorWindow> {
        match self.kind {
            ActuatorKind::Contact => None,
            ActuatorKind::Body(actuator) => Some(ActuatorWindow {
                actuator,
                start: offset + self.start,
                stop: offset + self.stop,
            }),
        }
    }
}

/// A bit scenario: the run (write then erase) and what defines success.
#[derive(Debug, Clone, PartialEq)]
pub struct BitScenario {
    /// The run's scenario: `solver.t_end = 2 × phase`, the protocols as
    /// its `[[force]]` windows, `thermal.run` the first run's.
    pub scenario: Scenario,
    /// The states and timing.
    pub bit: Bit,
    /// The write protocol.
    pub write: Vec<Actuator>,
    /// The erase protocol.
    pub erase: Vec<Actuator>,
}

impl BitScenario {
    /// Load a bit scenario: `preset`, the TOML text and `--set`s as for
    /// [`Scenario::load`], plus the `[bit]`, `[[write]]`, `[[erase]]`
    /// tables and their `bit.KEY`, `write.K.KEY`, `erase.K.KEY` overrides.
    /// Errors name the key ([`Error::Invalid`]).
    pub fn load(
        preset: Option<&str>,
        toml_text: Option<&str>,
        sets: &[String],
    ) -> Result<BitScenario, Error> {
        let mut file = match toml_text {
            Some(text) => parse_document(text)?,
            None => Table::new(),
        };
        // A protocol search's table (`tippetop bit --search`,
        // `crate::input::scenario::search`) is not part of the bit itself.
        file.remove("search");
        let mut bit_table = match file.remove("bit") {
            None => Table::new(),
            Some(Value::Table(t)) => t,
            Some(v) => {
                return Err(Error::invalid(
                    "bit",
                    format!("expected a table, found {}", describe(&v)),
                    "a [bit] section".into(),
                ));
            }
        };
        check_keys(&bit_table, "bit", BIT_KEYS)?;
        let mut lists = [Vec::new(), Vec::new()];
        for (name, list) in ["write", "erase"].into_iter().zip(lists.iter_mut()) {
            match file.remove(name) {
                None => {}
                Some(Value::Array(a)) => {
                    for (k, w) in a.iter().enumerate() {
                        let Value::Table(t) = w else {
                            return Err(Error::invalid(
                                &format!("{name}.{k}"),
                                format!("expected a table, found {}", describe(w)),
                                format!("[[{name}]] sections, one per window"),
                            ));
                        };
                        check_keys(t, &format!("{name}.{k}"), WINDOW_KEYS)?;
                    }
                    *list = a;
                }
                Some(v) => {
                    return Err(Error::invalid(
                        name,
                        format!("expected an array of tables, found {}", describe(&v)),
                        format!("[[{name}]] sections, one per window"),
                    ));
                }
            }
        }
        if let Some(v) = file.get("force")
            && !matches!(v, Value::Array(a) if a.is_empty())
        {
            return Err(force_error("force"));
        }

        let mut rest = Vec::new();
        for set in sets {
            let key = set.split_once('=').map(|(k, _)| k.trim()).unwrap_or("");
            let head = key.split('.').next().unwrap_or("");
            match head {
                "bit" | "write" | "erase" => {
                    apply_bit_set(&mut bit_table, &mut lists, key, set)?;
                }
                "force" => return Err(force_error(key)),
                _ => rest.push(set.clone()),
            }
        }

        let bit = parse_bit(&bit_table)?;
        let [write_list, erase_list] = &lists;
        let write = parse_windows("write", write_list, bit.phase)?;
        let erase = parse_windows("erase", erase_list, bit.phase)?;

        // The run lasts two phases; the protocols replace any preset force.
        let t_end = 2.0 * bit.phase;
        rest.push(format!("solver.t_end={t_end:?}"));
        file.insert("force".into(), Value::Array(Vec::new()));
        // solver.t_end is 2 x bit.phase: its range errors are bit.phase's.
        let phase_key = |e: Error| match e {
            Error::Invalid { key, what, range } if key == "solver.t_end" => Error::invalid(
                "bit.phase",
                format!("2 x phase = {t_end:e} s as solver.t_end: {what}"),
                range,
            ),
            other => other,
        };
        let mut scenario = Scenario::load_table(preset, &file, &rest).map_err(phase_key)?;
        scenario.forcing = Forcing {
            windows: run_windows(&write, &erase, bit.phase),
        };
        scenario.actuators = run_actuators(&write, &erase, bit.phase);
        for (name, list, offset) in [("write", &write, 0.0), ("erase", &erase, bit.phase)] {
            for (k, a) in list.iter().enumerate() {
                if let Some(w) = a.body_window(offset) {
                    actuators::check_model(
                        &w.actuator,
                        &format!("{name}.{k}"),
                        scenario.solver.model,
                    )?;
                }
            }
        }
        scenario.validate().map_err(phase_key)?;

        let theta0 = scenario.initial.theta;
        if !(bit.zero[0] <= theta0 && theta0 <= bit.zero[1]) {
            return Err(Error::invalid(
                "initial.theta",
                format!(
                    "{theta0} [rad] is outside bit.zero = [{}, {}]",
                    bit.zero[0], bit.zero[1]
                ),
                "the initial state must lie in bit.zero".into(),
            ));
        }
        let spacing = t_end / (scenario.solver.samples.max(2) - 1) as f64;
        let rows = bit.hold / spacing;
        if rows < MIN_ROWS_PER_HOLD {
            return Err(Error::invalid(
                "solver.samples",
                format!(
                    "{} rows over 2 x bit.phase = {t_end:e} s give {rows:.3} rows per bit.hold = {:e} s",
                    scenario.solver.samples, bit.hold
                ),
                format!(
                    "samples >= 1 + {MIN_ROWS_PER_HOLD} x 2 x phase / hold = {}",
                    (1.0 + MIN_ROWS_PER_HOLD * t_end / bit.hold).ceil()
                ),
            ));
        }
        Ok(BitScenario {
            scenario,
            bit,
            write,
            erase,
        })
    }

    /// A complete TOML document for this bit scenario: the run's scenario
    /// without its `[[force]]` windows (every key explicit, as
    /// [`Scenario::to_toml_string`]), then `[bit]`, `[[write]]`, `[[erase]]`
    /// with every key. `BitScenario::load(None, Some(&text), &[])` gives the
    /// same bit scenario back.
    pub fn to_toml_string(&self) -> String {
        let mut plain = self.scenario.clone();
        plain.forcing = Forcing::none();
        plain.actuators.clear();
        let mut out = plain.to_toml_string();
        let b = &self.bit;
        let mut t = Table::new();
        let pair = |w: [f64; 2]| Value::Array(vec![Value::Float(w[0]), Value::Float(w[1])]);
        t.insert("zero".into(), pair(b.zero));
        t.insert("one".into(), pair(b.one));
        t.insert("hold".into(), Value::Float(b.hold));
        t.insert("phase".into(), Value::Float(b.phase));
        out.push_str("\n[bit]\n");
        render_keys(&mut out, &t, BIT_KEYS);
        for (name, list) in [("write", &self.write), ("erase", &self.erase)] {
            for a in list {
                let mut t = Table::new();
                t.insert("kind".into(), Value::String(a.kind.name().into()));
                match a.kind {
                    ActuatorKind::Contact => {
                        retarding::to_table([a.hx, a.hy], &mut t);
                        // Written even when 0 (a bit's windows show every key).
                        t.insert(vertical_load::KEY.name.into(), Value::Float(a.hz));
                    }
                    ActuatorKind::Body(b) => actuators::to_table(&b, &mut t),
                }
                t.insert("start".into(), Value::Float(a.start));
                t.insert("stop".into(), Value::Float(a.stop));
                out.push_str(&format!("\n[[{name}]]\n"));
                render_keys(&mut out, &t, WINDOW_KEYS);
            }
        }
        out
    }

    /// The scenario of run `k` of an ensemble: `thermal.run = r0 + k`, `r0`
    /// the scenario's own `thermal.run`.
    pub fn run_scenario(&self, k: u64) -> Scenario {
        let mut sc = self.scenario.clone();
        sc.thermal.run = self.scenario.thermal.run + k;
        sc
    }
}

/// The run's force windows: the write windows as given, the erase windows
/// shifted by one phase.
pub fn run_windows(write: &[Actuator], erase: &[Actuator], phase: f64) -> Vec<ForceWindow> {
    let window = |a: &Actuator, offset: f64| ForceWindow {
        hx: a.hx,
        hy: a.hy,
        hz: a.hz,
        start: offset + a.start,
        stop: offset + a.stop,
    };
    let contact = |a: &&Actuator| a.kind == ActuatorKind::Contact;
    write
        .iter()
        .filter(contact)
        .map(|a| window(a, 0.0))
        .chain(erase.iter().filter(contact).map(|a| window(a, phase)))
        .collect()
}

/// The run's body actuators (tips, magnets): the write windows as given,
/// the erase windows shifted by one phase.
pub fn run_actuators(write: &[Actuator], erase: &[Actuator], phase: f64) -> Vec<ActuatorWindow> {
    write
        .iter()
        .filter_map(|a| a.body_window(0.0))
        .chain(erase.iter().filter_map(|a| a.body_window(phase)))
        .collect()
}

fn force_error(key: &str) -> Error {
    Error::invalid(
        key,
        "not allowed with [bit]: the applied forces are the [[write]] and [[erase]] windows".into(),
        "no [[force]] windows in a bit scenario (force = [] is fine)".into(),
    )
}

/// Apply one `--set` of `bit.KEY`, `write.K.KEY` or `erase.K.KEY`.
fn apply_bit_set(
    bit: &mut Table,
    lists: &mut [Vec<Value>; 2],
    key: &str,
    set: &str,
) -> Result<(), Error> {
    let value = parse_set_value(
        key,
        set.split_once('=').map(|(_, v)| v.trim()).unwrap_or(""),
    )?;
    let parts: Vec<&str> = key.split('.').collect();
    match parts.as_slice() {
        ["bit", k] => {
            if !BIT_KEYS.iter().any(|key| key.name == *k) {
                return Err(unknown_key(key, BIT_KEYS));
            }
            bit.insert((*k).to_string(), value);
            Ok(())
        }
        [list @ ("write" | "erase"), idx, k] => {
            let windows = if *list == "write" {
                &mut lists[0]
            } else {
                &mut lists[1]
            };
            if idx.is_empty() || !idx.bytes().all(|b| b.is_ascii_digit()) {
                return Err(Error::invalid(
                    key,
                    format!("{idx:?} is not a window index"),
                    format!("{list}.K.KEY with K = 0, 1, ... (0-based)"),
                ));
            }
            if !WINDOW_KEYS.iter().any(|key| key.name == *k) {
                return Err(unknown_key(key, WINDOW_KEYS));
            }
            let n = windows.len();
            let kk = idx.parse::<usize>().unwrap_or(usize::MAX);
            if kk > n {
                return Err(Error::invalid(
                    key,
                    format!("there is no {list} window {idx} ({n} defined)"),
                    format!("K <= {n}: 0-based, K = {n} appends a new window"),
                ));
            }
            if kk == n {
                windows.push(Value::Table(Table::new()));
            }
            if let Value::Table(t) = &mut windows[kk] {
                t.insert((*k).to_string(), value);
            }
            Ok(())
        }
        ["bit", ..] => Err(Error::invalid(
            key,
            "not a key: expected bit.KEY".into(),
            "valid keys: zero, one, hold, phase".into(),
        )),
        _ => Err(Error::invalid(
            key,
            "protocol windows are set one key at a time".into(),
            format!(
                "{}.K.KEY with K = 0, 1, ... and KEY one of kind, hx, hy, hz, start, stop, point, force, moment, field, gradient",
                parts[0]
            ),
        )),
    }
}

fn parse_bit(t: &Table) -> Result<Bit, Error> {
    let s = Section {
        prefix: "bit".into(),
        keys: BIT_KEYS,
        table: Some(t),
    };
    if let Some(key) = ["hold", "phase"].into_iter().find(|k| s.get(k).is_none()) {
        return Err(Error::invalid(
            &s.full(key),
            "missing".into(),
            format!(
                "a bit needs [bit] with hold and phase; {}",
                range_of(BIT_KEYS, key)
            ),
        ));
    }
    let zero = s.f64s("zero", Some(ZERO_DEFAULT))?;
    let one = s.f64s("one", Some(ONE_DEFAULT))?;
    let hold = s.f64("hold", None)?;
    let phase = s.f64("phase", None)?;
    let pi = std::f64::consts::PI;
    for (name, w) in [("zero", zero), ("one", one)] {
        if !(0.0 <= w[0] && w[0] < w[1] && w[1] <= pi) {
            return Err(Error::invalid(
                &format!("bit.{name}"),
                format!("[{}, {}] is not a window", w[0], w[1]),
                STATE_RANGE.into(),
            ));
        }
    }
    if !(one[0] > zero[1] || zero[0] > one[1]) {
        return Err(Error::invalid(
            "bit.one",
            format!(
                "[{}, {}] overlaps bit.zero = [{}, {}]",
                one[0], one[1], zero[0], zero[1]
            ),
            STATE_RANGE.into(),
        ));
    }
    if hold <= 0.0 {
        return Err(Error::invalid(
            "bit.hold",
            format!("{} is not allowed", crate::human::exact(hold)),
            range_of(BIT_KEYS, "hold").into(),
        ));
    }
    if phase <= hold {
        return Err(Error::invalid(
            "bit.phase",
            format!("{phase} is not longer than bit.hold = {hold}"),
            range_of(BIT_KEYS, "phase").into(),
        ));
    }
    Ok(Bit {
        zero,
        one,
        hold,
        phase,
    })
}

fn parse_windows(name: &str, list: &[Value], phase: f64) -> Result<Vec<Actuator>, Error> {
    let mut out = Vec::new();
    for (k, w) in list.iter().enumerate() {
        let s = Section {
            prefix: format!("{name}.{k}"),
            keys: WINDOW_KEYS,
            table: w.as_table(),
        };
        let kind = match crate::input::forcing::parse_actuator(&s)? {
            None => ActuatorKind::Contact,
            Some(b) => ActuatorKind::Body(b),
        };
        let [hx, hy] = retarding::parse(&s)?;
        let a = Actuator {
            kind,
            hx,
            hy,
            hz: vertical_load::parse(&s)?,
            start: s.f64("start", Some(0.0))?,
            stop: s.f64("stop", Some(phase))?,
        };
        if a.start < 0.0 {
            return Err(Error::invalid(
                &s.full("start"),
                format!("{} is not allowed", crate::human::exact(a.start)),
                range_of(WINDOW_KEYS, "start").into(),
            ));
        }
        if a.stop <= a.start || a.stop > phase {
            return Err(Error::invalid(
                &s.full("stop"),
                format!(
                    "{} with start = {} and bit.phase = {phase}",
                    a.stop, a.start
                ),
                range_of(WINDOW_KEYS, "stop").into(),
            ));
        }
        out.push(a);
    }
    Ok(out)
}
