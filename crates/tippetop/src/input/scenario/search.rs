//! A protocol search in the scenario (issue #16 item 5): the `[search]`
//! table of a bit scenario file (see [`crate::input::scenario::bit`]).
//!
//! ```toml
//! [search]
//! phase = "write"            # or "erase": the protocol searched; the other is kept
//! windows = 1                # K >= 1 actuator windows
//! actuator = "contact"       # the windows' kind: "contact" (the paper's H), "tip" or "magnetic"
//! # point = [0.0, 0.0, 3.905e-10]  # [m], "tip" only: the tip's body point (required)
//! # moment = 9.274e-24       # [A m^2], "magnetic" only: the top's moment along k (required)
//! magnitude = [0.0, 1e-21]   # bounds of each window's |H| or |F| [N], or |B| [T] ("magnetic")
//! angle = [-3.14159, 3.14159] # [rad]: "contact": H's direction in the (x, y) plane of the
//!                            # precessing frame; "tip": the horizontal lab-frame force's azimuth;
//!                            # "magnetic": B's polar angle from +Z in the lab X-Z plane
//! start = [0.0, 5e-5]        # [s] from the phase start
//! duration = [1e-6, 1e-4]    # [s]; a window ends at min(start + duration, phase)
//! weight = 0.0               # [s/J]: minimise time + weight × energy
//! margin = 0.0               # [rad]: success must hold in the target window shrunk by this
//! seed = 1                   # restarts' starting points (Philox)
//! budget = 200               # evaluations (runs) in all
//! perturbations = 20         # robustness: seeded ±5 % perturbations of the best protocol
//! ```
//!
//! Every bound is required (`--search` without them is bad input naming the
//! key). The search runs at T = 0 (deterministic runs).

use toml::{Table, Value};

use crate::Error;
use crate::input::Key;
use crate::input::reader::{Keys, check_keys, describe, parse_document, parse_set_value};

/// Which phase's protocol is searched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SearchPhase {
    /// The write (`[[write]]`, target `bit.one`).
    Write,
    /// The erase (`[[erase]]`, target `bit.zero`).
    Erase,
}

impl SearchPhase {
    /// `"write"` or `"erase"`: also the name of the window list.
    pub fn name(self) -> &'static str {
        match self {
            SearchPhase::Write => "write",
            SearchPhase::Erase => "erase",
        }
    }
}

/// The kind of window searched.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SearchActuator {
    /// The paper's force at the contact point (`kind = "contact"`): `hx`,
    /// `hy` from the magnitude and the angle in the precessing frame.
    Contact,
    /// A tip at a fixed body point \[m\] (`kind = "tip"`) pushing
    /// horizontally in the lab frame: force `|F| (cos φ, sin φ, 0)`.
    Tip {
        /// The body point \[m\] (origin at the centre of mass, z along k).
        point: [f64; 3],
    },
    /// A uniform magnetic field (`kind = "magnetic"`) on the top's moment
    /// along k: `B = |B| (sin a, 0, cos a)` in the lab frame (`a` the polar
    /// angle from +Z in the X–Z plane), a torque `μ k × B` and no force.
    Magnetic {
        /// The top's moment along k \[A m²\].
        moment: f64,
    },
}

/// The `[search]` table (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct SearchSpec {
    /// The phase searched.
    pub phase: SearchPhase,
    /// Number of actuator windows K.
    pub windows: usize,
    /// The windows' kind.
    pub actuator: SearchActuator,
    /// Bounds of each window's force magnitude \[N\].
    pub magnitude: [f64; 2],
    /// Bounds of the force's direction angle \[rad\].
    pub angle: [f64; 2],
    /// Bounds of each window's start from the phase start \[s\].
    pub start: [f64; 2],
    /// Bounds of each window's duration \[s\].
    pub duration: [f64; 2],
    /// Weight of the energy against the time \[s/J\].
    pub weight: f64,
    /// Margin inside the target window \[rad\].
    pub margin: f64,
    /// Seed of the restarts and of the perturbations.
    pub seed: u64,
    /// Evaluations (runs) in all.
    pub budget: usize,
    /// Number of ±5 % perturbations for the robustness figure.
    pub perturbations: usize,
}

/// Most windows a search may have.
pub const MAX_WINDOWS: usize = 8;
/// Largest `budget` (each evaluation is a run).
pub const MAX_BUDGET: usize = 100_000;
/// Largest `perturbations`.
pub const MAX_PERTURBATIONS: usize = 10_000;

const BOUNDS: &str = "[lo, hi], finite, lo <= hi";
const KEYS: Keys = &[
    Key::new("phase", "\"write\" or \"erase\""),
    Key::new("windows", "an integer, 1 <= windows <= 8"),
    Key::new("actuator", "\"contact\", \"tip\" or \"magnetic\""),
    Key::new(
        "point",
        "[x, y, z] [m], finite: the tip's body point, with actuator = \"tip\" only",
    ),
    Key::new(
        "moment",
        "a finite, non-zero moment [A m^2] along k, with actuator = \"magnetic\" only",
    ),
    Key::new(
        "magnitude",
        "[lo, hi] [N] (|B| [T] for \"magnetic\"), 0 <= lo <= hi, finite",
    ),
    Key::new("angle", "[lo, hi] [rad], finite, lo <= hi"),
    Key::new("start", "[lo, hi] [s], 0 <= lo <= hi < bit.phase"),
    Key::new("duration", "[lo, hi] [s], 0 < lo <= hi"),
    Key::new("weight", "a finite weight >= 0 [s/J]"),
    Key::new(
        "margin",
        "a finite angle >= 0 [rad], less than half the target window",
    ),
    Key::new("seed", "an integer >= 0"),
    Key::new("budget", "an integer, 1 <= budget <= 100000"),
    Key::new("perturbations", "an integer, 0 <= perturbations <= 10000"),
];

/// The valid range of `search.KEY` (as listed in the keys table).
fn range_of_key(key: &str) -> &'static str {
    KEYS.iter().find(|k| k.name == key).map_or("", |k| k.range)
}

fn bounds(t: &Table, key: &str) -> Result<[f64; 2], Error> {
    let full = format!("search.{key}");
    let range = KEYS
        .iter()
        .find(|k| k.name == key)
        .map_or(BOUNDS, |k| k.range);
    let bad = |what: String| Error::invalid(&full, what, range.into());
    let v = t
        .get(key)
        .ok_or_else(|| bad("missing (--search needs every bound)".into()))?;
    let Value::Array(a) = v else {
        return Err(bad(format!("expected [lo, hi], found {}", describe(v))));
    };
    let num = |v: &Value| match v {
        Value::Float(f) => Some(*f),
        Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    match a.as_slice() {
        [lo, hi] => match (num(lo), num(hi)) {
            (Some(lo), Some(hi)) if lo.is_finite() && hi.is_finite() && lo <= hi => Ok([lo, hi]),
            _ => Err(bad(format!("{v} is not allowed"))),
        },
        _ => Err(bad(format!("{v}: expected two numbers"))),
    }
}

fn float(t: &Table, key: &str, default: f64) -> Result<f64, Error> {
    let range = KEYS.iter().find(|k| k.name == key).map_or("", |k| k.range);
    match t.get(key) {
        None => Ok(default),
        Some(Value::Float(f)) if f.is_finite() && *f >= 0.0 => Ok(*f),
        Some(Value::Integer(i)) if *i >= 0 => Ok(*i as f64),
        Some(v) => Err(Error::invalid(
            &format!("search.{key}"),
            format!("{} is not allowed", describe(v)),
            range.into(),
        )),
    }
}

fn integer(t: &Table, key: &str, default: i64, lo: i64, hi: i64) -> Result<i64, Error> {
    let range = KEYS.iter().find(|k| k.name == key).map_or("", |k| k.range);
    match t.get(key) {
        None => Ok(default),
        Some(Value::Integer(i)) if (lo..=hi).contains(i) => Ok(*i),
        Some(v) => Err(Error::invalid(
            &format!("search.{key}"),
            format!("{} is not allowed", describe(v)),
            range.into(),
        )),
    }
}

impl SearchSpec {
    /// Parse the `[search]` table; `phase_len` is `bit.phase` \[s\] and
    /// `target` the searched phase's target window \[rad\] (for the margin).
    pub fn parse(
        t: &Table,
        phase_len: f64,
        target_of: impl Fn(SearchPhase) -> [f64; 2],
    ) -> Result<Self, Error> {
        check_keys(t, "search", KEYS)?;
        let phase = match t.get("phase") {
            None => SearchPhase::Write,
            Some(Value::String(s)) if s == "write" => SearchPhase::Write,
            Some(Value::String(s)) if s == "erase" => SearchPhase::Erase,
            Some(v) => {
                return Err(Error::invalid(
                    "search.phase",
                    format!("{} is not allowed", describe(v)),
                    range_of_key("phase").into(),
                ));
            }
        };
        let actuator = match t.get("actuator") {
            None => SearchActuator::Contact,
            Some(Value::String(s)) if s == "contact" => SearchActuator::Contact,
            Some(Value::String(s)) if s == "tip" => {
                let range = KEYS
                    .iter()
                    .find(|k| k.name == "point")
                    .map_or("", |k| k.range);
                let bad = |what: String| Error::invalid("search.point", what, range.into());
                let v = t
                    .get("point")
                    .ok_or_else(|| bad("missing (required with actuator = \"tip\")".into()))?;
                let p: Vec<f64> = match v {
                    Value::Array(a) => a
                        .iter()
                        .filter_map(|x| match x {
                            Value::Float(f) => Some(*f),
                            Value::Integer(i) => Some(*i as f64),
                            _ => None,
                        })
                        .collect(),
                    _ => Vec::new(),
                };
                match (p.as_slice(), v.as_array().map(|a| a.len())) {
                    ([x, y, z], Some(3)) if p.iter().all(|c| c.is_finite()) => {
                        SearchActuator::Tip {
                            point: [*x, *y, *z],
                        }
                    }
                    _ => return Err(bad(format!("{v} is not allowed"))),
                }
            }
            Some(Value::String(s)) if s == "magnetic" => {
                let bad = |what: String| {
                    Error::invalid("search.moment", what, range_of_key("moment").into())
                };
                let moment = match t.get("moment") {
                    None => {
                        return Err(bad("missing (required with actuator = \"magnetic\")".into()));
                    }
                    Some(Value::Float(f)) if f.is_finite() && *f != 0.0 => *f,
                    Some(Value::Integer(i)) if *i != 0 => *i as f64,
                    Some(v) => return Err(bad(format!("{v} is not allowed"))),
                };
                SearchActuator::Magnetic { moment }
            }
            Some(v) => {
                return Err(Error::invalid(
                    "search.actuator",
                    format!("{} is not allowed", describe(v)),
                    range_of_key("actuator").into(),
                ));
            }
        };
        if t.contains_key("point") && !matches!(actuator, SearchActuator::Tip { .. }) {
            return Err(Error::invalid(
                "search.point",
                "given without actuator = \"tip\"".into(),
                "only with actuator = \"tip\"".into(),
            ));
        }
        if t.contains_key("moment") && !matches!(actuator, SearchActuator::Magnetic { .. }) {
            return Err(Error::invalid(
                "search.moment",
                "given without actuator = \"magnetic\"".into(),
                "only with actuator = \"magnetic\"".into(),
            ));
        }
        let windows = integer(t, "windows", 1, 1, MAX_WINDOWS as i64)? as usize;
        let magnitude = bounds(t, "magnitude")?;
        let angle = bounds(t, "angle")?;
        let start = bounds(t, "start")?;
        let duration = bounds(t, "duration")?;
        if magnitude[0] < 0.0 {
            return Err(Error::invalid(
                "search.magnitude",
                format!("{magnitude:?} is not allowed"),
                range_of_key("magnitude").into(),
            ));
        }
        if start[0] < 0.0 || start[1] >= phase_len {
            return Err(Error::invalid(
                "search.start",
                format!("{start:?} is not allowed with bit.phase = {phase_len}"),
                range_of_key("start").into(),
            ));
        }
        if duration[0] <= 0.0 {
            return Err(Error::invalid(
                "search.duration",
                format!("{duration:?} is not allowed"),
                range_of_key("duration").into(),
            ));
        }
        let weight = float(t, "weight", 0.0)?;
        let margin = float(t, "margin", 0.0)?;
        let w = target_of(phase);
        if 2.0 * margin >= w[1] - w[0] {
            return Err(Error::invalid(
                "search.margin",
                format!("{margin} leaves nothing of the target window {w:?}"),
                range_of_key("margin").into(),
            ));
        }
        let seed = integer(t, "seed", 1, 0, i64::MAX)? as u64;
        let budget = integer(t, "budget", 200, 1, MAX_BUDGET as i64)? as usize;
        if budget < 4 * windows + 1 {
            return Err(Error::invalid(
                "search.budget",
                format!(
                    "{budget} runs cannot start a simplex over {} parameters",
                    4 * windows
                ),
                format!("at least 4 windows + 1 = {} runs", 4 * windows + 1),
            ));
        }
        let perturbations = integer(t, "perturbations", 20, 0, MAX_PERTURBATIONS as i64)? as usize;
        Ok(SearchSpec {
            phase,
            windows,
            actuator,
            magnitude,
            angle,
            start,
            duration,
            weight,
            margin,
            seed,
            budget,
            perturbations,
        })
    }

    /// Lower and upper bounds of the parameter vector: per window
    /// (magnitude \[N\], angle \[rad\], start \[s\], duration \[s\]).
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let mut lo = Vec::with_capacity(4 * self.windows);
        let mut hi = Vec::with_capacity(4 * self.windows);
        for _ in 0..self.windows {
            for b in [self.magnitude, self.angle, self.start, self.duration] {
                lo.push(b[0]);
                hi.push(b[1]);
            }
        }
        (lo, hi)
    }
}

/// Split a bit scenario document into the document without `[search]` and
/// the `[search]` table (`None` if absent).
pub fn split(mut doc: Table) -> Result<(Table, Option<Table>), Error> {
    match doc.remove("search") {
        None => Ok((doc, None)),
        Some(Value::Table(t)) => Ok((doc, Some(t))),
        Some(v) => Err(Error::invalid(
            "search",
            format!("expected a table, found {}", describe(&v)),
            "a [search] section".into(),
        )),
    }
}

/// Parse a scenario file's text (`None`: an empty document); a syntax
/// error is one line naming `scenario`.
pub fn document(text: Option<&str>) -> Result<Table, Error> {
    text.map_or_else(|| Ok(Table::new()), parse_document)
}

/// Apply `KEY=VALUE` overrides (values read as `--set` reads them) to a
/// document by dotted table path, for `tippetop bit --search` (window
/// lists are not reachable this way: an error names the key).
pub fn apply_sets(doc: &mut Table, sets: &[String]) -> Result<(), Error> {
    for s in sets {
        let Some((key, val)) = s.split_once('=') else {
            return Err(Error::invalid(
                "--set",
                format!("{s:?} has no '='"),
                "KEY=VALUE".into(),
            ));
        };
        let key = key.trim();
        let value = parse_set_value(key, val.trim())?;
        let parts: Vec<&str> = key.split('.').collect();
        if parts
            .iter()
            .any(|p| p.is_empty() || p.parse::<usize>().is_ok())
        {
            return Err(Error::invalid(
                key,
                "with --search, --set reaches table keys only".into(),
                "edit the window lists in the file".into(),
            ));
        }
        let mut t = &mut *doc;
        for p in &parts[..parts.len() - 1] {
            let e = t
                .entry(p.to_string())
                .or_insert_with(|| Value::Table(Table::new()));
            let Value::Table(inner) = e else {
                return Err(Error::invalid(
                    key,
                    format!("{p} is not a table"),
                    "a table key".into(),
                ));
            };
            t = inner;
        }
        t.insert(parts[parts.len() - 1].to_string(), value);
    }
    Ok(())
}
