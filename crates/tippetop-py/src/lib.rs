//! Python bindings of tippetop: the module `tippetop` (built by maturin,
//! see `pyproject.toml`). Scenarios as the CLI resolves them (preset, file,
//! `--set`), runs with the GIL released, trajectories as numpy float64
//! arrays, and the steppable `Simulation`.
//!
//! Errors: bad input raises `ValueError` with the CLI's line without its
//! `error: ` prefix; a panic inside the library raises `RuntimeError` (never
//! pyo3's `PanicException`, a `BaseException` that `except Exception`
//! misses).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex, MutexGuard, TryLockError};
use std::time::{Duration, Instant};

use numpy::PyArray1;
use pyo3::exceptions::{PyAttributeError, PyKeyError, PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyMapping, PyString, PyTuple};
use serde::Serialize;
use tippetop::analysis;
use tippetop::analysis::sweep::{Axis, Sweep, Table};
use tippetop::trajectory::COLUMNS;
use tippetop::{EventRecord, Summary};

/// Most cases of a sweep in Python (`sweep`), whose result is kept in
/// memory (about 200 bytes a case, and the arrays): 1 000 000, within the
/// library's memory bound (`tippetop::limits::MEMORY_BUDGET`). The CLI's
/// `tippetop sweep` streams its rows to disk and takes 1e9.
const MAX_SWEEP_CASES: usize = 1_000_000;

/// Why the step is unchecked when the caller turned the check off
/// (`step_unchecked` of `ensemble` and `rare`), as the CLI's
/// `--no-step-check` says `"--no-step-check"`.
const STEP_CHECK_OFF: &str = "step_check=False";

/// A library error as a Python exception: bad input is `ValueError`
/// (`"<key>: <what> (<range>)"`), a run-time failure `RuntimeError`.
/// The message is on one line, as the CLI prints it (line breaks, e.g. in
/// a TOML parse error, become spaces).
fn to_py_err(e: tippetop::Error) -> PyErr {
    let msg = one_line(&e.to_string());
    if e.is_input() {
        PyValueError::new_err(msg)
    } else {
        PyRuntimeError::new_err(msg)
    }
}

/// `s` with every run of white space (line breaks included) collapsed to
/// one space: the CLI's one-line error messages.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A user's text (a key) as a message quotes it: each control character
/// (a line break, a tab, NUL) a space, nothing trimmed, so the message
/// stays on one line and still shows the key's spaces.
fn flat(s: &str) -> String {
    s.chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect()
}

/// Run `f`, turning a panic into a `RuntimeError`.
fn guarded<T>(f: impl FnOnce() -> T) -> PyResult<T> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| {
        let msg = p
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| p.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "unknown panic".into());
        PyRuntimeError::new_err(format!("internal error in tippetop (a bug): {msg}"))
    })
}

/// A float as TOML text that parses back to exactly `x` (Rust's shortest
/// round-trip digits; `nan`, `inf`, `-inf` for the rest, which the scenario
/// checks then reject by name).
fn toml_float(x: f64) -> String {
    if x.is_nan() {
        "nan".into()
    } else if x.is_infinite() {
        if x > 0.0 { "inf".into() } else { "-inf".into() }
    } else {
        format!("{x:?}")
    }
}

/// `repr(v)` for a message: at most 60 characters, on one line; the type's
/// name where repr fails (a list a million levels deep has none).
fn short_repr(v: &Bound<'_, PyAny>) -> String {
    match v.repr() {
        Ok(r) => {
            let r = one_line(&r.to_string());
            match r.char_indices().nth(60) {
                Some((i, _)) => format!("{}...", &r[..i]),
                None => r,
            }
        }
        Err(_) => format!(
            "a {}",
            v.get_type()
                .name()
                .map(|n| n.to_string())
                .unwrap_or_default()
        ),
    }
}

/// Most values in a list given for a scenario key: each takes at least
/// two bytes of TOML, and a scenario's text is at most
/// `tippetop::limits::MAX_FILE_BYTES` (16 MiB). Checked before the list is
/// read (a numpy array's `tolist()` would cost ~30 bytes a value).
const MAX_LIST_VALUES: usize = (tippetop::limits::MAX_FILE_BYTES / 2) as usize;

/// A Python value as the text after `=` of a `--set KEY=VALUE`: bool →
/// `true`/`false`, int → its digits, float (and numpy scalars) → exact
/// shortest digits, str → as given (as on the command line: TOML if it
/// parses as TOML, else the string), list/tuple/array → `[a, b, c]`.
/// Errors name `key`.
fn set_value_text(key: &str, v: &Bound<'_, PyAny>) -> PyResult<String> {
    set_value_text_at(key, v, 0)
}

/// Deepest nesting of lists in a value: a scenario's arrays are flat or
/// hold tables; a list that holds itself (or a million levels of lists)
/// must not exhaust the stack.
const MAX_VALUE_DEPTH: usize = 32;

/// [`set_value_text`] of a value `depth` lists deep.
fn set_value_text_at(key: &str, v: &Bound<'_, PyAny>, depth: usize) -> PyResult<String> {
    if v.is_instance_of::<PyBool>() {
        return Ok(if v.extract::<bool>()? {
            "true"
        } else {
            "false"
        }
        .into());
    }
    if v.is_instance_of::<PyString>() {
        return v.extract::<String>();
    }
    if v.is_instance_of::<PyFloat>() {
        return Ok(toml_float(v.extract::<f64>()?));
    }
    if let Ok(i) = v.extract::<i64>() {
        return Ok(i.to_string());
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(toml_float(x));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() || v.hasattr("tolist")? {
        if depth >= MAX_VALUE_DEPTH {
            return Err(PyValueError::new_err(format!(
                "{}: lists nested more than {MAX_VALUE_DEPTH} deep (a number, bool, str or list \
                 of numbers)",
                flat(key)
            )));
        }
        if let Ok(n) = v.len() {
            if n > MAX_LIST_VALUES {
                return Err(PyValueError::new_err(format!(
                    "{}: a list of {n} values (at most {MAX_LIST_VALUES}: a scenario's text is \
                     at most 16 MiB)",
                    flat(key)
                )));
            }
        }
        let items = if v.hasattr("tolist")? {
            v.call_method0("tolist")?
        } else {
            v.clone()
        };
        let mut parts = Vec::new();
        for item in items.try_iter()? {
            parts.push(set_value_text_at(key, &item?, depth + 1)?);
        }
        return Ok(format!("[{}]", parts.join(", ")));
    }
    Err(PyTypeError::new_err(format!(
        "{}: cannot use a value of type {} in a scenario (a number, bool, str or list of \
         numbers)",
        flat(key),
        v.get_type().name()?
    )))
}

/// An integer argument `name` of a function: an int or an integer that
/// says so (`__index__`: numpy's integers). TypeError for anything else (a
/// bool, a float, a str, None), ValueError (with `range`) if it is out of
/// `i64` (Python's own OverflowError would be neither).
fn int_arg(v: &Bound<'_, PyAny>, name: &str, range: &str) -> PyResult<i64> {
    let not_int = || -> PyResult<PyErr> {
        Ok(PyTypeError::new_err(format!(
            "{name}: expected an int, got {} ({range})",
            v.get_type().name()?
        )))
    };
    if v.is_instance_of::<PyBool>() {
        return Err(not_int()?);
    }
    let v = if v.is_instance_of::<PyInt>() {
        v.clone()
    } else {
        // numpy's bool refuses `__index__` itself.
        match v.py().import("operator")?.call_method1("index", (v,)) {
            Ok(i) if !i.is_instance_of::<PyBool>() => i,
            _ => return Err(not_int()?),
        }
    };
    v.extract::<i64>().map_err(|_| {
        PyValueError::new_err(format!(
            "{name}: {} is out of range ({range})",
            v.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    })
}

/// An optional integer argument (`None`: not given) that is a count from
/// 0 up, as [`int_arg`]; a negative one is refused with `range`.
fn count_arg(v: Option<&Bound<'_, PyAny>>, name: &str, range: &str) -> PyResult<Option<u64>> {
    let Some(v) = v.filter(|v| !v.is_none()) else {
        return Ok(None);
    };
    let n = int_arg(v, name, range)?;
    u64::try_from(n)
        .map(Some)
        .map_err(|_| PyValueError::new_err(format!("{name}: {n} is not allowed ({range})")))
}

/// A float argument `name`: a number (int, float, numpy scalar; not a
/// bool, a str or an array), TypeError naming it and `what` it is
/// otherwise. NaN and infinities pass: the library refuses them by name.
fn float_arg(v: &Bound<'_, PyAny>, name: &str, what: &str) -> PyResult<f64> {
    let type_name = v.get_type().name()?.to_string();
    let array = v.hasattr("ndim")? && v.getattr("ndim")?.extract::<i64>().is_ok_and(|d| d != 0);
    let boolean = v.is_instance_of::<PyBool>() || type_name == "bool_" || type_name == "bool";
    if array || boolean || v.is_instance_of::<PyString>() {
        return Err(PyTypeError::new_err(format!(
            "{name}: expected a number, got {type_name} ({what})"
        )));
    }
    v.extract::<f64>().map_err(|_| {
        PyTypeError::new_err(format!(
            "{name}: expected a number, got {type_name} ({what})"
        ))
    })
}

/// An optional float argument (`None`: not given), as [`float_arg`].
fn opt_float_arg(v: Option<&Bound<'_, PyAny>>, name: &str, what: &str) -> PyResult<Option<f64>> {
    v.filter(|v| !v.is_none())
        .map(|v| float_arg(v, name, what))
        .transpose()
}

/// The `threads` argument: `None` (one per core) or an int from 1 to
/// 1024 (the CLI's `--threads`).
fn threads_arg(threads: Option<&Bound<'_, PyAny>>) -> PyResult<usize> {
    let range = format!(
        "1 to {} threads; more threads than cores only add overhead",
        analysis::sweep::MAX_THREADS
    );
    let t =
        match threads {
            None => None,
            Some(t) if t.is_none() => None,
            Some(t) => {
                let n = int_arg(t, "--threads", &range)?;
                Some(usize::try_from(n).map_err(|_| {
                    PyValueError::new_err(format!("--threads: {n} threads ({range})"))
                })?)
            }
        };
    analysis::sweep::threads(t).map_err(to_py_err)
}

/// Ask Python whether a signal (Ctrl-C) came in, at most every 0.1 s (the
/// GIL taken for a moment): `false` (and the exception kept in
/// `interrupted`) to stop. For the `keep_going` callbacks of the long
/// calls that run with the GIL released.
fn signals_checker<'a>(interrupted: &'a mut Option<PyErr>) -> impl FnMut() -> bool + 'a {
    let mut last = Instant::now();
    move || signals_ok(&mut last, interrupted)
}

/// False (with the error in `interrupted`) when Python has a signal
/// pending (Ctrl-C), asked at most every 0.1 s since `last`.
fn signals_ok(last: &mut Instant, interrupted: &mut Option<PyErr>) -> bool {
    if last.elapsed().as_secs_f64() < 0.1 {
        return true;
    }
    *last = Instant::now();
    match Python::attach(|py| py.check_signals()) {
        Ok(()) => true,
        Err(e) => {
            *interrupted = Some(e);
            false
        }
    }
}

/// Run `work` on a thread of its own, inside
/// `tippetop::simulate::stoppable(stop)` and with the GIL released, while
/// this thread asks Python every 50 ms whether a signal came in (Ctrl-C;
/// Python runs its handlers on the main thread only, and `work` may wait
/// seconds between two results of an analysis): then `stop` is set, which
/// ends the runs in progress within a few thousand steps and the analysis
/// at its next result (`work`'s sinks and hooks look at `stop` too), and
/// the signal's exception (KeyboardInterrupt) is returned once `work` has
/// returned. A panic in `work` is a RuntimeError.
fn interruptible<R: Send>(
    py: Python<'_>,
    stop: &Arc<AtomicBool>,
    work: impl FnOnce() -> R + Send,
) -> PyResult<R> {
    let mut interrupted: Option<PyErr> = None;
    let out = py.detach(|| {
        std::thread::scope(|scope| {
            let waiter = std::thread::current();
            let worker = scope.spawn(move || {
                let r = guarded(|| tippetop::simulate::stoppable(stop, work));
                waiter.unpark();
                r
            });
            while !worker.is_finished() {
                std::thread::park_timeout(Duration::from_millis(50));
                if interrupted.is_none() && !worker.is_finished() {
                    if let Err(e) = Python::attach(|py| py.check_signals()) {
                        interrupted = Some(e);
                        stop.store(true, Ordering::Relaxed);
                    }
                }
            }
            worker.join().unwrap_or_else(|_| {
                Err(PyRuntimeError::new_err(
                    "internal error in tippetop (a bug): a worker thread panicked",
                ))
            })
        })
    });
    match interrupted {
        Some(e) => Err(e),
        None => out,
    }
}

/// Issue `message` as a Python `RuntimeWarning` at the caller's line (an
/// `Err` when the warnings filter turns it into an error).
fn warn_runtime(py: Python<'_>, message: &str) -> PyResult<()> {
    let text = std::ffi::CString::new(message.replace('\0', " ")).expect("no NUL left");
    PyErr::warn(
        py,
        &py.get_type::<pyo3::exceptions::PyRuntimeWarning>(),
        &text,
        1,
    )
}

/// A TOML value as a Python object.
fn toml_to_py<'py>(py: Python<'py>, v: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        toml::Value::Float(x) => x.into_pyobject(py)?.into_any(),
        toml::Value::Integer(i) => i.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(b) => PyBool::new(py, *b).to_owned().into_any(),
        toml::Value::String(s) => s.into_pyobject(py)?.into_any(),
        toml::Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| toml_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        toml::Value::Table(t) => {
            let d = PyDict::new(py);
            for (k, x) in t {
                d.set_item(k, toml_to_py(py, x)?)?;
            }
            d.into_any()
        }
        toml::Value::Datetime(d) => d.to_string().into_pyobject(py)?.into_any(),
    })
}

/// A tippe-top scenario: the top, the surface, forces, initial state and
/// solver settings (SI units; see `to_toml()` for every key). Immutable:
/// `set` returns a new scenario.
#[pyclass(module = "tippetop", frozen)]
struct Scenario {
    /// How it was made, as the CLI's arguments: `--preset`, the file's
    /// text, the `--set`s in order (so `set` has exactly the CLI's rules).
    preset: Option<String>,
    toml: Option<String>,
    sets: Vec<String>,
    sc: tippetop::Scenario,
}

impl Scenario {
    fn load(preset: Option<String>, toml: Option<String>, sets: Vec<String>) -> PyResult<Self> {
        let sc = guarded(|| tippetop::Scenario::load(preset.as_deref(), toml.as_deref(), &sets))?
            .map_err(to_py_err)?;
        Ok(Scenario {
            preset,
            toml,
            sets,
            sc,
        })
    }
}

#[pymethods]
impl Scenario {
    /// A built-in scenario: `"nano"` (the C60 nano tippe top of the paper),
    /// `"nano-physical"` (C60 on graphene at 300 K, a Langevin run),
    /// `"nano-md"` (the same with the damping from molecular dynamics),
    /// `"nano-adhesive"` (the same without temperature) or `"classical"`
    /// (the 15 g toy).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        Scenario::load(Some(name.to_string()), None, Vec::new())
    }

    /// A scenario from a TOML file (the CLI's `tippetop run FILE`; the file
    /// may name a `preset` to start from). ValueError naming the file if it
    /// cannot be read or is larger than 16 MiB.
    #[staticmethod]
    fn from_file(path: std::path::PathBuf) -> PyResult<Self> {
        let text = tippetop::limits::read_file(&path).map_err(to_py_err)?;
        Scenario::load(None, Some(text), Vec::new())
    }

    /// A scenario from TOML text (the format of scenario files).
    #[staticmethod]
    fn from_toml(text: String) -> PyResult<Self> {
        Scenario::load(None, Some(text), Vec::new())
    }

    /// A new scenario with `key` (`"table.key"`, e.g. `"surface.friction"`,
    /// `"force.0.hx"`) set to `value`: the CLI's `--set key=value`, same
    /// keys and checks (ValueError naming the key). Floats are passed with
    /// the digits that give back exactly the same float.
    fn set(&self, key: &str, value: &Bound<'_, PyAny>) -> PyResult<Self> {
        let mut sets = self.sets.clone();
        sets.push(format!("{key}={}", set_value_text(key, value)?));
        Scenario::load(self.preset.clone(), self.toml.clone(), sets)
    }

    /// A new scenario with every `key: value` of `values` (a dict, in its
    /// order) set at once: the CLI's `--set k1=v1 --set k2=v2 ...`, checked
    /// together, for keys that depend on each other (e.g.
    /// `{"surface.friction_law": "regularized", "surface.friction_eps":
    /// 1e-2}` [m/s], which `set` one at a time rejects). Values as in `set`.
    /// TypeError if `values` is not a mapping or a key is not a str.
    fn set_many(&self, values: &Bound<'_, PyAny>) -> PyResult<Self> {
        let Ok(map) = values.cast::<PyMapping>() else {
            return Err(PyTypeError::new_err(format!(
                "set_many: expected a dict of key: value (a mapping), got {}",
                values.get_type().name()?
            )));
        };
        let mut sets = self.sets.clone();
        for item in map.items()?.try_iter()? {
            let (key, value): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item?.extract()?;
            let Ok(key) = key.extract::<String>() else {
                return Err(PyTypeError::new_err(format!(
                    "set_many: the keys are scenario keys (str, e.g. \"top.offset\"), got {}",
                    key.get_type().name()?
                )));
            };
            sets.push(format!("{key}={}", set_value_text(&key, &value)?));
        }
        Scenario::load(self.preset.clone(), self.toml.clone(), sets)
    }

    /// The value of `key` (`"top.radius"`, `"force.0.hx"`, ...) as
    /// `to_toml()` writes it.
    fn get<'py>(&self, py: Python<'py>, key: &str) -> PyResult<Bound<'py, PyAny>> {
        let doc: toml::Table = toml::from_str(&self.sc.to_toml_string())
            .map_err(|e| PyRuntimeError::new_err(format!("internal error: {e}")))?;
        let mut v: Option<&toml::Value> = None;
        for part in key.split('.') {
            v = match v {
                None => doc.get(part),
                Some(toml::Value::Table(t)) => t.get(part),
                Some(toml::Value::Array(a)) => part.parse::<usize>().ok().and_then(|i| a.get(i)),
                Some(_) => None,
            };
            if v.is_none() {
                break;
            }
        }
        match v {
            Some(v) => toml_to_py(py, v),
            None => Err(PyValueError::new_err(format!(
                "{}: not a key of this scenario (the keys of Scenario.to_toml(), as table.key)",
                flat(key)
            ))),
        }
    }

    /// The complete scenario as TOML (every key explicit; floats exact):
    /// what the CLI writes to `scenario.toml`.
    fn to_toml(&self) -> PyResult<String> {
        guarded(|| self.sc.to_toml_string())
    }

    /// True if `other` is a Scenario with exactly the same values.
    fn __eq__(&self, other: &Bound<'_, PyAny>) -> bool {
        other
            .cast::<Scenario>()
            .map(|o| o.get().sc == self.sc)
            .unwrap_or(false)
    }

    /// A Python expression that makes this scenario again:
    /// `tippetop.Scenario.preset('nano').set_many({'surface.friction':
    /// '0.2'})` (each value as the text it was set with, which `set_many`
    /// takes back unchanged), `tippetop.Scenario.from_toml('...')` for one
    /// read from TOML (a file's text inlined); a key set twice: the
    /// complete TOML.
    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let lit = |s: &str| -> PyResult<String> { Ok(PyString::new(py, s).repr()?.to_string()) };
        let pairs: Vec<(&str, &str)> = self
            .sets
            .iter()
            .map(|set| set.split_once('=').unwrap_or((set.as_str(), "")))
            .collect();
        let mut keys: Vec<&str> = pairs.iter().map(|p| p.0).collect();
        keys.sort_unstable();
        keys.dedup();
        if keys.len() < pairs.len() {
            let toml = guarded(|| self.sc.to_toml_string())?;
            return Ok(format!("tippetop.Scenario.from_toml({})", lit(&toml)?));
        }
        let mut out = match (&self.preset, &self.toml) {
            (_, Some(t)) => format!("tippetop.Scenario.from_toml({})", lit(t)?),
            (Some(p), None) => format!("tippetop.Scenario.preset({})", lit(p)?),
            (None, None) => {
                let toml = guarded(|| self.sc.to_toml_string())?;
                format!("tippetop.Scenario.from_toml({})", lit(&toml)?)
            }
        };
        if !pairs.is_empty() {
            let items = pairs
                .iter()
                .map(|(k, v)| Ok(format!("{}: {}", lit(k)?, lit(v)?)))
                .collect::<PyResult<Vec<_>>>()?;
            out.push_str(&format!(".set_many({{{}}})", items.join(", ")));
        }
        Ok(out)
    }
}

/// `summary.json` of the CLI (crates/tippetop-cli/src/output.rs
/// `SummaryDoc`): the library's summary flattened, the wall time, the
/// resolved scenario's TOML, the events, the regime.
#[derive(Serialize)]
struct SummaryDoc<'a> {
    #[serde(flatten)]
    summary: &'a Summary,
    wall_seconds: f64,
    scenario: &'a str,
    events: &'a [EventRecord],
    regime: Option<tippetop::analysis::regime::Regime>,
}

/// The summary dict of `traj` (the keys of the CLI's summary.json).
fn summary_dict<'py>(
    py: Python<'py>,
    sc: &tippetop::Scenario,
    traj: &tippetop::Trajectory,
    wall_seconds: f64,
) -> PyResult<Bound<'py, PyAny>> {
    let mut summary = traj.summary.clone();
    if let Some(e) = &traj.error {
        if summary.status.is_empty() || summary.status == "ok" {
            summary.status = e.to_string();
        }
    }
    let toml = sc.to_toml_string();
    let doc = SummaryDoc {
        summary: &summary,
        wall_seconds,
        scenario: &toml,
        events: &traj.events,
        regime: tippetop::analysis::regime::regime(sc, None).ok(),
    };
    let text = serde_json::to_string(&doc)
        .map_err(|e| PyRuntimeError::new_err(format!("internal error: {e}")))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// `None`, or `{"time": t [s], "kind": "painleve" | ..., "message": ...}`
/// for a run that failed part-way.
fn error_obj<'py>(py: Python<'py>, e: Option<&tippetop::Error>) -> PyResult<Bound<'py, PyAny>> {
    match e {
        None => Ok(py.None().into_bound(py)),
        Some(e) => {
            let d = PyDict::new(py);
            match e {
                tippetop::Error::Runtime { t, kind, .. } => {
                    d.set_item("time", *t)?;
                    d.set_item("kind", kind.as_str())?;
                }
                tippetop::Error::Invalid { key, .. } => {
                    d.set_item("time", py.None())?;
                    d.set_item("kind", format!("invalid:{key}"))?;
                }
            }
            d.set_item("message", e.to_string())?;
            Ok(d.into_any())
        }
    }
}

/// The result of a run: one numpy float64 array per trajectory.csv column
/// (`tr.t`, `tr.theta`, `tr["Omega"]`, ...; `tr.columns` lists them), one
/// element per sample; `tr.summary` (summary.json as a dict) and
/// `tr.error`. Columns (SI units): t [s], theta [rad], theta_dot [rad/s],
/// Omega (precession) [rad/s], omega (spin) [rad/s], ux, uy, uz [m/s],
/// N [N], slip [m/s], J [kg m^3/s], energy, work_friction, work_applied
/// [J], hx, hy [N], rolling [0 or 1], x, y, z [m], qw, qx, qy, qz [1],
/// xp, yp [m] (definitions: `tippetop run --help`); a run with
/// `pose=False` has the columns up to `rolling` only.
#[pyclass(module = "tippetop", frozen)]
struct Trajectory {
    arrays: Py<PyDict>,
    summary: Py<PyAny>,
    error: Py<PyAny>,
    len: usize,
    /// The columns held: the first `ncols` of `COLUMNS` (all, or all but
    /// the pose's with `pose=False`).
    ncols: usize,
}

impl Trajectory {
    fn new(
        py: Python<'_>,
        sc: &tippetop::Scenario,
        traj: tippetop::Trajectory,
        wall_seconds: f64,
    ) -> PyResult<Self> {
        Self::with_columns(py, sc, traj, wall_seconds, COLUMNS.len())
    }

    /// [`Trajectory::new`] with the first `ncols` columns of `COLUMNS`.
    fn with_columns(
        py: Python<'_>,
        sc: &tippetop::Scenario,
        traj: tippetop::Trajectory,
        wall_seconds: f64,
        ncols: usize,
    ) -> PyResult<Self> {
        let n = traj.samples.len();
        // The rows as arrays a block at a time, then each column of the
        // block appended to the Vec its numpy array takes over (no copy): a
        // tight loop per column instead of 26 pushes per row, with a
        // bounded buffer (a copy of every row cost 1 GB at the 5e6-sample
        // limit).
        const BLOCK: usize = 512;
        let mut cols: Vec<Vec<f64>> = (0..ncols).map(|_| Vec::with_capacity(n)).collect();
        let mut rows: Vec<[f64; COLUMNS.len()]> = Vec::with_capacity(BLOCK.min(n));
        for block in traj.samples.chunks(BLOCK) {
            rows.clear();
            rows.extend(block.iter().map(|s| s.values()));
            for (i, c) in cols.iter_mut().enumerate() {
                c.extend(rows.iter().map(|r| r[i]));
            }
        }
        let arrays = PyDict::new(py);
        for (name, c) in COLUMNS[..ncols].iter().zip(cols) {
            arrays.set_item(*name, PyArray1::from_vec(py, c))?;
        }
        Ok(Trajectory {
            arrays: arrays.unbind(),
            summary: summary_dict(py, sc, &traj, wall_seconds)?.unbind(),
            error: error_obj(py, traj.error.as_ref())?.unbind(),
            len: n,
            ncols,
        })
    }
}

#[pymethods]
impl Trajectory {
    /// The column names, in trajectory.csv order (`COLUMNS`).
    #[getter]
    fn columns(&self) -> Vec<&'static str> {
        COLUMNS[..self.ncols].to_vec()
    }

    /// summary.json of the CLI as a dict: `theta_final` [rad],
    /// `omega_final` [rad/s], `steps`, `status`, `events`, `scenario`
    /// (TOML), `wall_seconds` [s], ...
    #[getter]
    fn summary(&self, py: Python<'_>) -> Py<PyAny> {
        self.summary.clone_ref(py)
    }

    /// `None`, or for a run that failed part-way a dict `time` [s], `kind`
    /// (`"painleve"`, `"step_limit"`, ...), `message`; the arrays then hold
    /// the samples up to the failure.
    #[getter]
    fn error(&self, py: Python<'_>) -> Py<PyAny> {
        self.error.clone_ref(py)
    }

    /// All columns as a new dict of arrays, in column order.
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        self.arrays.bind(py).copy()
    }

    /// The columns as a pandas DataFrame (needs pandas).
    fn to_pandas<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let pd = py.import("pandas")?;
        pd.call_method1("DataFrame", (self.arrays.bind(py),))
    }

    /// The column `name` (KeyError if there is none).
    fn __getitem__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.arrays.bind(py).get_item(name)?.ok_or_else(|| {
            PyKeyError::new_err(format!(
                "{name:?}: not a column (columns: {})",
                COLUMNS[..self.ncols].join(", ")
            ))
        })
    }

    /// The column `name` (AttributeError if there is none).
    fn __getattr__<'py>(&self, py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
        self.arrays.bind(py).get_item(name)?.ok_or_else(|| {
            PyAttributeError::new_err(format!(
                "'Trajectory' has no attribute {name:?} (columns: {})",
                COLUMNS[..self.ncols].join(", ")
            ))
        })
    }

    /// True if `name` is a column.
    fn __contains__(&self, name: &str) -> bool {
        COLUMNS[..self.ncols].contains(&name)
    }

    /// The number of samples (rows).
    fn __len__(&self) -> usize {
        self.len
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let status = self
            .summary
            .bind(py)
            .get_item("status")
            .and_then(|s| s.extract::<String>())
            .unwrap_or_default();
        Ok(format!(
            "tippetop.Trajectory({} samples, {} columns, status {status:?})",
            self.len, self.ncols
        ))
    }
}

/// Run `scenario` to `solver.t_end` [s] (the CLI's `tippetop run`), with
/// the GIL released: bit for bit the CLI's trajectory.csv and summary.json.
/// Bad input raises ValueError; a run that fails part-way returns its
/// partial trajectory with `error` set. `pose=False` (`tippetop run
/// --no-pose`): the pose is not computed and its columns (x, y, z, qw, qx,
/// qy, qz, xp, yp) are left out; the vector model then integrates 10 state
/// components instead of 17 (the reduced model 8 instead of 14), every
/// other column and the summary the same bits.
#[pyfunction]
#[pyo3(signature = (scenario, pose = true))]
fn run(py: Python<'_>, scenario: &Scenario, pose: bool) -> PyResult<Trajectory> {
    let sc = &scenario.sc;
    // The resumable driver to t_end (the same run as `simulate`, bit for
    // bit), asking about Ctrl-C every few thousand steps, and pausing every
    // PROGRESS_EVERY steps (a pause never changes a step) to watch the
    // state as the CLI does: a run that runs away says so, as a
    // RuntimeWarning, before it fails.
    let mut interrupted: Option<PyErr> = None;
    let (traj, wall) = py.detach(|| {
        guarded(|| {
            let start = Instant::now();
            let r = tippetop::Simulation::with_pose(sc, pose).and_then(|mut sim| {
                let mut watch = tippetop::RunawayWatch::default();
                // One clock for the signal checks across the pauses (a
                // stretch between two pauses may be shorter than 0.1 s).
                let mut last = Instant::now();
                loop {
                    let mut asked = 0u64;
                    let done = sim.integrate_to_while(sc.solver.t_end, &mut || {
                        asked += 1;
                        asked * tippetop::simulate::CHECK_EVERY < tippetop::simulate::PROGRESS_EVERY
                            && signals_ok(&mut last, &mut interrupted)
                    })?;
                    if done || interrupted.is_some() {
                        return Ok(done.then(|| sim.into_trajectory()));
                    }
                    if let Some(w) = watch.check(&sim.progress()) {
                        if let Err(e) = Python::attach(|py| warn_runtime(py, &w)) {
                            // The warnings filter made it an error.
                            interrupted = Some(e);
                            return Ok(None);
                        }
                    }
                }
            });
            (r, start.elapsed().as_secs_f64())
        })
    })?;
    if let Some(e) = interrupted {
        return Err(e);
    }
    let traj = traj
        .map_err(to_py_err)?
        .ok_or_else(|| PyRuntimeError::new_err("internal error: the run stopped early"))?;
    let ncols = if pose {
        COLUMNS.len()
    } else {
        COLUMNS.len() - tippetop::trajectory::POSE_COLUMNS.len()
    };
    Trajectory::with_columns(py, sc, traj, wall, ncols)
}

/// The axis of `vary[key]`: a tuple `(lo, hi, n)` or `(lo, hi, n, "log")`
/// is the CLI's `--vary KEY=LO:HI:N[:log]` (parsed by the library's
/// `Axis::parse`, so with the CLI's checks and messages); anything else
/// iterable (a list, a numpy array) is the values as given.
fn vary_axis(key: &str, spec: &Bound<'_, PyAny>) -> PyResult<Axis> {
    if key.contains('=') || key.trim().is_empty() {
        return Err(PyValueError::new_err(format!(
            "{}: not a scenario key (table.key as in Scenario.set, e.g. top.offset)",
            flat(key)
        )));
    }
    // The key as messages show it (on one line); the library gets it as
    // given.
    let shown = flat(key);
    if spec.is_instance_of::<PyTuple>() {
        let mut parts = Vec::new();
        for item in spec.try_iter()? {
            let item = item?;
            let text = set_value_text(key, &item)?;
            if text.contains(':') {
                // One element must not pass for several of FROM:TO:N.
                return Err(PyValueError::new_err(format!(
                    "{shown}: {} in (lo, hi, n) is not a number ((lo, hi, n) or (lo, hi, n, \"log\"))",
                    short_repr(&item)
                )));
            }
            parts.push(text);
        }
        return Axis::parse(&format!("{key}={}", parts.join(":"))).map_err(to_py_err);
    }
    if spec.is_instance_of::<PyString>() {
        return Err(PyValueError::new_err(format!(
            "{shown}: {} is not a grid or values (a tuple (lo, hi, n) or (lo, hi, n, \"log\"), \
             or a list or array of numbers)",
            short_repr(spec)
        )));
    }
    let too_many = |n: String| {
        PyValueError::new_err(format!(
            "{shown}: {n} values (at most {MAX_SWEEP_CASES} cases in Python, whose result is kept \
             in memory)"
        ))
    };
    if let Ok(n) = spec.len() {
        if n > MAX_SWEEP_CASES {
            return Err(too_many(n.to_string()));
        }
    }
    let items = if spec.hasattr("tolist")? {
        spec.call_method0("tolist")?
    } else {
        spec.clone()
    };
    let Ok(iter) = items.try_iter() else {
        return Err(PyValueError::new_err(format!(
            "{shown}: a value of type {} is not a grid or values (a tuple (lo, hi, n) or \
             (lo, hi, n, \"log\"), or a list or array of numbers)",
            spec.get_type().name()?
        )));
    };
    let mut values = Vec::new();
    for (i, item) in iter.enumerate() {
        if i == MAX_SWEEP_CASES {
            return Err(too_many(format!("more than {MAX_SWEEP_CASES}")));
        }
        let item = item?;
        match item.extract::<f64>() {
            Ok(v) if !item.is_instance_of::<PyString>() => values.push(v),
            _ => {
                return Err(PyValueError::new_err(format!(
                    "{shown}: value {i} ({}) is not a number (finite numbers)",
                    short_repr(&item)
                )));
            }
        }
    }
    Axis::of_values(key, values).map_err(to_py_err)
}

/// Run a grid of scenarios (the CLI's `tippetop sweep`) on `threads`
/// threads (1 to 1024; default one per core) with the GIL released.
///
/// `vary` maps scenario keys (as in `Scenario.set`) to values in the key's
/// SI unit: a tuple `(lo, hi, n)` or `(lo, hi, n, "log")` is the CLI's
/// `--vary KEY=LO:HI:N[:log]`, a list or numpy array is taken as given. The
/// cases are the grid over all keys, the first varying slowest.
///
/// Returns a dict of numpy arrays, one per `sweep.csv` column in its order:
/// the varied keys, then `theta_final`, `theta_max` [rad], `omega_final`,
/// `Omega_final` [rad/s], `first_time_theta_above_half_pi`,
/// `contact_lost_at` [s], `negative_normal_fraction`, `rolling_fraction`,
/// `J_max_rel_drift` [1], `energy_final` [J], `steps`, `rhs_evaluations`
/// (counts), all float64, NaN where the CSV field is empty; then `status`
/// (str: `"ok"` or the case's error; a failing case does not stop the
/// sweep). Bit for bit the CLI's `sweep.csv`, whatever `threads`. Bad input
/// raises ValueError naming the key; `threads` is an int (TypeError for
/// another type, ValueError out of range); at most 1 000 000 cases (the
/// result is kept in memory); Ctrl-C stops the sweep.
#[pyfunction]
#[pyo3(signature = (scenario, vary, threads = None))]
fn sweep<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    vary: &Bound<'py, PyAny>,
    threads: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let Ok(vary) = vary.cast::<PyMapping>() else {
        return Err(PyTypeError::new_err(format!(
            "vary: expected a dict of key: grid or values (a mapping), got {}",
            vary.get_type().name()?
        )));
    };
    let mut axes = Vec::new();
    for item in vary.items()?.try_iter()? {
        let (k, v): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item?.extract()?;
        let key: String = k.extract().map_err(|_| {
            PyTypeError::new_err("the keys of vary are scenario keys (str, e.g. \"top.offset\")")
        })?;
        axes.push(vary_axis(&key, &v)?);
    }
    if axes.is_empty() {
        return Err(PyValueError::new_err(
            "vary: no keys given (one or more, e.g. {\"top.offset\": (3e-4, 6e-3, 20)})",
        ));
    }
    // The Python bound first (the library's is the CLI's, 1e9 cases).
    let total = axes.iter().try_fold(1usize, |a, x| a.checked_mul(x.n));
    if total.is_none_or(|t| t > MAX_SWEEP_CASES) {
        let sizes: Vec<String> = axes.iter().map(|a| a.n.to_string()).collect();
        return Err(PyValueError::new_err(format!(
            "vary: {} cases (at most {MAX_SWEEP_CASES} in Python, whose result is kept in \
             memory; the CLI's tippetop sweep streams up to 1000000000)",
            sizes.join(" x ")
        )));
    }
    let threads = threads_arg(threads.as_ref())?;
    let sw = Sweep {
        preset: scenario.preset.clone(),
        toml_text: scenario.toml.clone(),
        sets: scenario.sets.clone(),
        axes,
    };
    guarded(|| sw.validate())?.map_err(to_py_err)?;
    let threads = guarded(|| sw.threads_within_memory(threads))?.map_err(to_py_err)?;

    // The rows, with the GIL released, kept as the table's columns (not
    // the rows themselves); Ctrl-C stops the sweep (`interruptible`).
    let mut table = Table::from_rows(&sw.axes, &[]);
    let stop = Arc::new(AtomicBool::new(false));
    let run = interruptible(py, &stop, || {
        sw.run_streaming(0..sw.total(), Some(threads), &mut |row| {
            let one = Table::from_rows(&sw.axes, std::slice::from_ref(&row));
            table.values.extend(one.values);
            table.fields.extend(one.fields);
            table.status.extend(one.status);
            !stop.load(Ordering::Relaxed)
        })
    })?;
    if !run.map_err(|e| PyRuntimeError::new_err(one_line(&e.to_string())))? {
        return Err(PyRuntimeError::new_err("sweep: stopped before its end"));
    }

    let out = PyDict::new(py);
    for key in &table.keys {
        let col = table.column(key).unwrap_or_default();
        out.set_item(key, PyArray1::from_vec(py, col))?;
    }
    for name in analysis::sweep::FIELDS {
        let col = table.column(name).unwrap_or_default();
        out.set_item(name, PyArray1::from_vec(py, col))?;
    }
    let status = PyList::new(py, &table.status)?;
    out.set_item(
        "status",
        py.import("numpy")?.call_method1("array", (status,))?,
    )?;
    Ok(out)
}

/// Run a Langevin (or Brownian) scenario `runs` times with independent
/// noise: run K is the scenario with `thermal.run = r0 + K` (`r0` its own
/// `thermal.run`), so `tt.run(sc.set("thermal.run", r0 + K))` replays it.
/// `first_passage` is the CLI's `--first-passage` (e.g.
/// `"theta<1.07,theta>2.07"`: each run stops at its first output row where
/// it holds). The GIL is released; Ctrl-C stops the ensemble.
///
/// Returns a dict of numpy arrays, one per `ensemble.csv` column in its
/// order (`run`, `seed`, then `<col>_final` for every trajectory column in
/// its SI unit, `theta_max`, `theta_min` [rad], `N_min` [N],
/// `negative_normal_fraction`, `first_passage_time` [s], `censored`,
/// `t_reached` [s]; float64, NaN where empty), `status` (str), and
/// `summary`: the ensemble's statistics as in `summary.json` (means with
/// 95 % intervals of the final θ, ω, Ω, energy; first passages with the
/// Kaplan–Meier median and the escape rate). Bit for bit the CLI's
/// `ensemble.csv`, whatever `threads`. Bad input raises ValueError naming
/// the key; `runs` (1 to 1 000 000) and `threads` (1 to 1024) are ints:
/// TypeError for another type, ValueError out of range. Fewer runs run at
/// once than `threads` when more would need more than 3 GiB.
///
/// `step_check` (default True) is the CLI's step check
/// (docs/physics.md#step-check): the same runs again on the scenario at
/// `solver.dt / 2` (the step limit doubled, an independent seed:
/// `thermal.seed + 0x9E3779B97F4A7C15`), about twice the ensemble's cost
/// again, and every statistic with a 95 % interval compared. `summary`
/// then carries summary.json's step-check keys, the same figures as the
/// CLI's for the same inputs: `dt_converged` (True: every statistic's
/// change is below its 95 % half-width; False: one or more is not, a step
/// error resolved: use a smaller `solver.dt`; None: unchecked),
/// `step_check` (by statistic, `theta_final`, `omega_final`,
/// `Omega_final`, `energy_final`, `first_passage.mean_observed`,
/// `first_passage.censored_fraction`, `first_passage.escape_rate`: `scale`
/// `"linear"` or `"log"`, `at_dt` and `at_half_dt` each `{dt [s],
/// estimate, ci95}` in the statistic's unit, `step_error` the change
/// (that unit; on the log scale `|ln ratio|` [1]), `statistical` its 95 %
/// half-width (the same), `family`, `converged`; None unchecked) and
/// `step_unchecked` (why not, absent when checked: `"step_check=False"`,
/// one run, fewer than 2 ok runs). A scenario whose `solver.dt / 2`
/// version is invalid raises ValueError naming the key.
#[pyfunction]
#[pyo3(signature = (scenario, runs, threads = None, first_passage = None, step_check = true))]
fn ensemble<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    runs: Bound<'py, PyAny>,
    threads: Option<Bound<'py, PyAny>>,
    first_passage: Option<String>,
    step_check: bool,
) -> PyResult<Bound<'py, PyDict>> {
    use tippetop::analysis::ensemble as ens;
    use tippetop::analysis::ensemble::step_check::{self as ens_step, Plan};
    let range = format!(
        "1 <= runs <= {}, with the run indices below 4294967296",
        tippetop::input::thermal::MAX_ENSEMBLE_RUNS
    );
    let n = int_arg(&runs, "--runs", &range)?;
    let runs = usize::try_from(n)
        .map_err(|_| PyValueError::new_err(format!("--runs: {n} runs ({range})")))?;
    let threads = threads_arg(threads.as_ref())?;
    let exit = first_passage
        .as_deref()
        .map(ens::Exit::parse)
        .transpose()
        .map_err(to_py_err)?;
    let e = guarded(|| {
        ens::Ensemble::new(
            scenario.preset.clone(),
            scenario.toml.clone(),
            scenario.sets.clone(),
            runs,
        )
    })?
    .map_err(to_py_err)?
    .with_exit(exit);
    let threads = e.threads_within_memory(threads).map_err(to_py_err)?;
    // Planned before anything runs, as the CLI does: a refined scenario
    // that is invalid is refused at once.
    let plan = if step_check {
        ens_step::plan(&e, analysis::sweep::Shard::ALL, STEP_CHECK_OFF).map_err(to_py_err)?
    } else {
        Plan::Off(STEP_CHECK_OFF.into())
    };

    // Each row goes into the columns and the statistics as it comes (no
    // row is kept).
    let header = ens::csv_header();
    let names: Vec<&str> = header.trim_end().split(',').collect();
    let mut acc = ens::StatsAcc::default();
    let mut cols: Vec<Vec<f64>> = vec![Vec::with_capacity(runs); names.len()];
    let mut status = Vec::with_capacity(runs);
    let mut bad_row: Option<PyErr> = None;
    let stop = Arc::new(AtomicBool::new(false));
    let done = interruptible(py, &stop, || {
        e.run_streaming(0..runs, Some(threads), &mut |row| {
            let line = ens::csv_row(&row);
            let line = line.trim_end();
            let Some(r) = ens::parse_row(line) else {
                bad_row = Some(PyRuntimeError::new_err(
                    "internal: an ensemble row did not parse",
                ));
                return false;
            };
            acc.push(&r);
            for (c, name) in cols.iter_mut().zip(&names) {
                c.push(match *name {
                    "run" => r.run as f64,
                    "seed" => r.seed as f64,
                    "status" => f64::NAN,
                    n => r.get(n).unwrap_or(f64::NAN),
                });
            }
            status.push(r.status);
            !stop.load(Ordering::Relaxed)
        })
    })?;
    if let Some(err) = bad_row {
        return Err(err);
    }
    if !done.map_err(|err| PyRuntimeError::new_err(one_line(&err.to_string())))? {
        return Err(PyRuntimeError::new_err("ensemble: stopped before its end"));
    }

    let out = PyDict::new(py);
    for (c, name) in cols.into_iter().zip(&names) {
        if *name == "status" {
            let st = PyList::new(py, &status)?;
            out.set_item("status", py.import("numpy")?.call_method1("array", (st,))?)?;
        } else {
            out.set_item(*name, PyArray1::from_vec(py, c))?;
        }
    }
    let stats = acc.finish();
    let step = ensemble_step(py, &stop, &e, &stats, &plan, threads)?;
    // summary.json's statistics, then its step-check fields.
    #[derive(Serialize)]
    struct EnsembleSummary<'a> {
        #[serde(flatten)]
        stats: &'a ens::EnsembleStats,
        #[serde(flatten)]
        step: ens_step::Fields<'a>,
    }
    let summary = serde_json::to_string(&EnsembleSummary {
        stats: &stats,
        step: step.fields(),
    })
    .map_err(|err| PyRuntimeError::new_err(err.to_string()))?;
    out.set_item(
        "summary",
        py.import("json")?.call_method1("loads", (summary,))?,
    )?;
    Ok(out)
}

/// The step check of `ensemble` (`e`, its statistics `stats`) by `plan`:
/// the refined ensemble's runs on `threads` threads, the GIL released,
/// Ctrl-C stopping them (`interruptible`), compared with `stats`.
fn ensemble_step(
    py: Python<'_>,
    stop: &Arc<AtomicBool>,
    e: &tippetop::analysis::ensemble::Ensemble,
    stats: &tippetop::analysis::ensemble::EnsembleStats,
    plan: &tippetop::analysis::ensemble::step_check::Plan,
    threads: usize,
) -> PyResult<tippetop::analysis::ensemble::step_check::Outcome> {
    use tippetop::analysis::ensemble::step_check::{self as ens_step, Outcome, Plan, Refined};
    let fine = match plan {
        Plan::Off(why) => return Ok(Outcome::Off(why.clone())),
        Plan::Run(fine) => fine,
    };
    let fine_stats = interruptible(py, stop, || {
        ens_step::refined_stats(fine, Some(threads), &mut || !stop.load(Ordering::Relaxed))
    })?
    .map_err(|err| PyRuntimeError::new_err(one_line(&format!("step check: {err}"))))?
    .ok_or_else(|| PyRuntimeError::new_err("ensemble: stopped before its end"))?;
    Ok(Outcome::Done(Refined::new(e, stats, fine, &fine_stats)))
}

/// A rare-event question about a stochastic scenario (the CLI's `tippetop
/// rare`): with `reset` (or `horizon` [s]) `P(target before reset [and
/// before horizon])`, else the mean first-passage time to `target` [s].
/// `target` and `reset` use the `--first-passage` grammar (e.g.
/// `"theta<1.22,theta>1.92"`). `method`: `"exact"` (the one-dimensional
/// answer where θ is exactly a 1D diffusion: the Brownian mode on the
/// plane; else ValueError with the reason), `"direct"` (`replicas` runs,
/// default 1000, each until the target or the reset holds at a step's end,
/// or `max_steps` steps, default 1e6) or `"ams"` (adaptive multilevel
/// splitting: `replicas` independent replicas, default 20, of `particles`,
/// default 100, killing `kill` per level, default 1, on the reaction
/// `coordinate`, default θ towards the target (the CLI's `--coordinate`
/// grammar: a column, `-COLUMN`, `|COLUMN-C|` or `tilt_energy`); budgets
/// `max_trajectories` per replica (default 1e5) and `max_steps` per path
/// (default 1e7); without `reset`, the mean first-passage time by the flux
/// relation with `crossings`, `direct_steps`, `pilot_steps`, `basin`,
/// `interface` as the CLI's options; a replica out of budget raises
/// RuntimeError). The GIL is released; Ctrl-C stops the run.
///
/// Returns rare.json as a dict (the same figures, bit for bit, apart from
/// `wall_seconds`): `quantity`, `unit`, `estimate`, `ln_estimate`, `ci95`,
/// `method`, `replicas`, `trajectories`, `steps`, `wall_seconds`, `exact`
/// (dict or None; `exact_unavailable` says why), the conditions, budgets,
/// `tally` of a direct ensemble, `ams` of the splitting (coordinate,
/// sizes, `standard_error`, `interval`, `extinct`, `replica_estimates`,
/// `flux`), `seed`, `first_run`, `temperature`, `scenario`. Numbers past f64 or unknown (an interval open above) are
/// None. Bad input raises ValueError naming the option.
///
/// `step_check` (default True, methods `"direct"` and `"ams"`) is the
/// CLI's step check (docs/physics.md#step-check): the same question at
/// `solver.dt / 2` (an independent seed, `thermal.seed +
/// 0x9E3779B97F4A7C15`; every budget counted in steps doubled), about
/// twice the cost, compared with the answer at `solver.dt` (the one
/// returned). The dict then carries rare.json's step-check keys, the same
/// figures as the CLI's for the same inputs: `dt_converged` (True: the
/// change is below its 95 % half-width; False: it is not, a step error
/// resolved: use a smaller `solver.dt`; None: unchecked), `step_check`
/// (`scale` `"linear"`, or `"log"` for the splitting's mean time;
/// `at_dt` and `at_half_dt` each `{dt [s], estimate, ci95}` in the
/// answer's unit; `step_error` the change (that unit; on the log scale
/// `|ln ratio|` [1]); `statistical` its 95 % half-width (the same);
/// `family`; `converged`; `refined_trajectories`, `refined_steps`,
/// `refined_seed_offset`; None unchecked) and `step_unchecked` (why not,
/// absent when checked: `"step_check=False"`; the exact method, which has
/// no step, whatever `step_check`; a refined splitting without an answer).
#[pyfunction]
#[pyo3(signature = (scenario, target, reset = None, method = "direct", replicas = None, horizon = None, max_steps = None, threads = None, coordinate = None, particles = None, kill = None, max_trajectories = None, crossings = None, direct_steps = None, pilot_steps = None, basin = None, interface = None, step_check = true))]
#[allow(clippy::too_many_arguments)]
fn rare<'py>(
    py: Python<'py>,
    scenario: &Scenario,
    target: &str,
    reset: Option<&str>,
    method: &str,
    replicas: Option<Bound<'py, PyAny>>,
    horizon: Option<Bound<'py, PyAny>>,
    max_steps: Option<Bound<'py, PyAny>>,
    threads: Option<Bound<'py, PyAny>>,
    coordinate: Option<&str>,
    particles: Option<Bound<'py, PyAny>>,
    kill: Option<Bound<'py, PyAny>>,
    max_trajectories: Option<Bound<'py, PyAny>>,
    crossings: Option<Bound<'py, PyAny>>,
    direct_steps: Option<Bound<'py, PyAny>>,
    pilot_steps: Option<Bound<'py, PyAny>>,
    basin: Option<Bound<'py, PyAny>>,
    interface: Option<Bound<'py, PyAny>>,
    step_check: bool,
) -> PyResult<Bound<'py, PyAny>> {
    use tippetop::analysis::rare::ams::{MAX_PARTICLES, MAX_REPLICAS};
    use tippetop::analysis::rare::problem::{self, DEFAULT_REPLICAS, Problem, RareMethod};
    use tippetop::analysis::rare::step_check::{Checked, EXACT_UNCHECKED};
    let started = Instant::now();
    let method = RareMethod::parse(method).map_err(to_py_err)?;
    let replicas_range = match method {
        RareMethod::Ams => format!("2 <= M <= {MAX_REPLICAS}"),
        _ => "N >= 1, with the run indices below 4294967296".to_string(),
    };
    let replicas = count_arg(replicas.as_ref(), "--replicas", &replicas_range)?;
    let max_steps = count_arg(
        max_steps.as_ref(),
        "--max-steps",
        "1 to 20000000 steps per trajectory",
    )?;
    let horizon = opt_float_arg(horizon.as_ref(), "--horizon", "a finite time > 0 [s]")?;
    let threads = threads_arg(threads.as_ref())?;
    let sc = scenario.sc.clone();
    let (target, reset) = (target.to_string(), reset.map(str::to_string));
    let level = "a finite level of the coordinate";
    let o = AmsOptions {
        replicas,
        particles: count_arg(
            particles.as_ref(),
            "--particles",
            &format!("2 <= n <= {MAX_PARTICLES}"),
        )?,
        kill: count_arg(kill.as_ref(), "--kill", "1 <= k < n (--particles)")?,
        max_trajectories: count_arg(
            max_trajectories.as_ref(),
            "--max-trajectories",
            "n (--particles) <= N <= 16777200 per replica",
        )?,
        crossings: count_arg(
            crossings.as_ref(),
            "--crossings",
            "1 <= crossings <= 100000",
        )?,
        direct_steps: count_arg(
            direct_steps.as_ref(),
            "--direct-steps",
            "1 <= steps <= 10000000",
        )?,
        pilot_steps: count_arg(
            pilot_steps.as_ref(),
            "--pilot-steps",
            "1000 <= steps <= 10000000",
        )?,
        basin: opt_float_arg(basin.as_ref(), "--basin", level)?,
        interface: opt_float_arg(interface.as_ref(), "--interface", level)?,
        coordinate,
    };
    if method != RareMethod::Ams {
        let given = [
            (o.coordinate.is_some(), "--coordinate"),
            (o.particles.is_some(), "--particles"),
            (o.kill.is_some(), "--kill"),
            (o.max_trajectories.is_some(), "--max-trajectories"),
            (o.crossings.is_some(), "--crossings"),
            (o.direct_steps.is_some(), "--direct-steps"),
            (o.pilot_steps.is_some(), "--pilot-steps"),
            (o.basin.is_some(), "--basin"),
            (o.interface.is_some(), "--interface"),
        ];
        if let Some((_, key)) = given.iter().find(|g| g.0) {
            return Err(PyValueError::new_err(format!(
                "{key}: given with --method {} (an option of --method ams)",
                method.name()
            )));
        }
    }
    let prob = guarded(|| match method {
        RareMethod::Ams => Problem::for_ams(sc, &target, reset.as_deref(), horizon, max_steps),
        _ => Problem::new(sc, &target, reset.as_deref(), horizon, max_steps),
    })?
    .map_err(to_py_err)?;
    let (report, checked) = match method {
        RareMethod::Ams => rare_ams(py, &prob, o, threads, step_check)?,
        RareMethod::Exact => {
            if replicas.is_some() {
                return Err(PyValueError::new_err(
                    "--replicas: given with --method exact (which runs no trajectory)",
                ));
            }
            let report = py
                .detach(|| guarded(|| problem::by_exact(&prob)))?
                .map_err(to_py_err)?;
            (report, Checked::Off(EXACT_UNCHECKED.into()))
        }
        RareMethod::Direct => {
            // Past usize only where usize is 32 bits; by_direct names the
            // bound.
            let n = replicas.map_or(Ok(DEFAULT_REPLICAS), |r| {
                usize::try_from(r).map_err(|_| {
                    PyValueError::new_err(format!("--replicas: {r} ({replicas_range})"))
                })
            })?;
            rare_direct(py, &prob, n, threads, step_check)?
        }
    };
    let doc = checked.document(report.document(&prob, started.elapsed().as_secs_f64()));
    let text = serde_json::to_string(&doc).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
    py.import("json")?.call_method1("loads", (text,))
}

/// The options of `rare(method="ams")` as given (None: the default).
struct AmsOptions<'a> {
    replicas: Option<u64>,
    particles: Option<u64>,
    kill: Option<u64>,
    max_trajectories: Option<u64>,
    crossings: Option<u64>,
    direct_steps: Option<u64>,
    pilot_steps: Option<u64>,
    basin: Option<f64>,
    interface: Option<f64>,
    coordinate: Option<&'a str>,
}

/// A count as a `usize` setting: saturated where `usize` is narrower (the
/// settings' checks then refuse it by name).
fn size(v: u64) -> usize {
    usize::try_from(v).unwrap_or(usize::MAX)
}

/// `rare(method="ams")`: the splitting (its pilot run included) and its
/// replicas on `threads` threads, the GIL released; Ctrl-C sets the
/// splitting's cancel flag (`interruptible`). With `step_check`, the same
/// splitting at `solver.dt / 2` too, and the comparison.
fn rare_ams(
    py: Python<'_>,
    prob: &tippetop::analysis::rare::problem::Problem,
    o: AmsOptions<'_>,
    threads: usize,
    step_check: bool,
) -> PyResult<(
    tippetop::analysis::rare::problem::Report,
    tippetop::analysis::rare::step_check::Checked,
)> {
    use tippetop::analysis::rare::ams::Settings;
    use tippetop::analysis::rare::problem;
    use tippetop::analysis::rare::step_check::{self as rare_step, Checked};
    let d = Settings::default();
    let settings = Settings {
        replicas: o.replicas.map_or(d.replicas, size),
        particles: o.particles.map_or(d.particles, size),
        kill: o.kill.map_or(d.kill, size),
        max_trajectories: o.max_trajectories.unwrap_or(d.max_trajectories),
        crossings: o.crossings.map_or(d.crossings, size),
        direct_steps: o.direct_steps.unwrap_or(d.direct_steps),
        pilot_steps: o.pilot_steps.unwrap_or(d.pilot_steps),
        basin: o.basin,
        interface: o.interface,
        ..d
    };
    let coordinate = o.coordinate.map(str::to_string);
    let stop = Arc::new(AtomicBool::new(false));
    let ams = interruptible(py, &stop, || {
        problem::ams_for(prob, coordinate.as_deref(), settings.clone())
    })?
    .map_err(to_py_err)?;
    // The particles of the replicas running at once within the memory
    // bound (the splitting runs fewer at once, as the CLI does): refused
    // here, before anything runs, when not even one fits.
    ams.threads_within_memory(threads).map_err(to_py_err)?;
    let reps = ams_replicas(py, &stop, &ams, threads)?;
    let report = py
        .detach(|| guarded(|| problem::by_ams(prob, &ams, reps)))?
        .map_err(to_py_err)?;
    if !step_check {
        return Ok((report, Checked::Off(STEP_CHECK_OFF.into())));
    }
    let fine = interruptible(py, &stop, || {
        rare_step::refined_ams(prob, coordinate.as_deref(), &settings)
    })?
    .map_err(to_py_err)?;
    let reps = ams_replicas(py, &stop, &fine.1, threads)?;
    let checked = py
        .detach(|| guarded(|| Checked::of_ams(prob, &report, &fine, reps)))?
        .map_err(to_py_err)?;
    Ok((report, checked))
}

/// All the replicas of `ams` on `threads` threads, in replica order, the
/// GIL released; Ctrl-C (`stop`) cancels them.
fn ams_replicas(
    py: Python<'_>,
    stop: &Arc<AtomicBool>,
    ams: &tippetop::analysis::rare::ams::Ams,
    threads: usize,
) -> PyResult<Vec<tippetop::analysis::rare::ams::Replica>> {
    use tippetop::analysis::rare::ams::Hooks;
    let m = ams.settings().replicas;
    let mut reps = Vec::new();
    let ran = interruptible(py, stop, || {
        let hooks = Hooks {
            progress: None,
            cancel: Some(&**stop),
            steps: None,
        };
        ams.run(0..m, Some(threads), hooks, &mut |r| {
            reps.push(r);
            !stop.load(Ordering::Relaxed)
        })
    })?;
    if !ran.map_err(to_py_err)? {
        return Err(PyRuntimeError::new_err("rare: stopped before its end"));
    }
    Ok(reps)
}

/// `rare(method="direct")`: `n` runs on `threads` threads, the GIL
/// released; Ctrl-C stops them (`interruptible`). With `step_check`, the
/// same runs of the question at `solver.dt / 2` too, and the comparison.
fn rare_direct(
    py: Python<'_>,
    prob: &tippetop::analysis::rare::problem::Problem,
    n: usize,
    threads: usize,
    step_check: bool,
) -> PyResult<(
    tippetop::analysis::rare::problem::Report,
    tippetop::analysis::rare::step_check::Checked,
)> {
    use tippetop::analysis::rare::problem::{self, Problem, RareMethod};
    use tippetop::analysis::rare::step_check::{self as rare_step, Checked};
    let stop = Arc::new(AtomicBool::new(false));
    let run = |p: &Problem| {
        interruptible(py, &stop, || {
            problem::by_direct(p, n, Some(threads), &mut |_| !stop.load(Ordering::Relaxed))
        })?
        .map_err(to_py_err)
    };
    let report = run(prob)?;
    if !step_check {
        return Ok((report, Checked::Off(STEP_CHECK_OFF.into())));
    }
    let fine =
        guarded(|| rare_step::refined_problem(prob, RareMethod::Direct))?.map_err(to_py_err)?;
    let checked = Checked::of(prob, &report, &run(&fine)?);
    Ok((report, checked))
}

/// A copy of a `Simulation` at one instant (`Simulation.snapshot()`),
/// exact to the bit; `Simulation.restore` goes back to it.
#[pyclass(module = "tippetop", frozen)]
struct Snapshot {
    /// Not `Sync` by itself (the models cache evaluations in cells); locked
    /// only briefly, with the GIL held.
    inner: Mutex<tippetop::Snapshot>,
    wall: f64,
    /// [`fingerprint`] of the scenario of the simulation it was taken
    /// from: `restore` refuses it in a simulation of another scenario.
    fingerprint: String,
    /// That scenario, to name what differs when it is refused.
    scenario: Arc<tippetop::Scenario>,
}

/// The first key (`table.key`, in `to_toml()`'s order) whose value
/// differs between scenarios `a` and `b`, with both values as TOML text
/// (`absent` where one has no such key).
fn first_difference(
    a: &tippetop::Scenario,
    b: &tippetop::Scenario,
) -> Option<(String, String, String)> {
    fn parse(sc: &tippetop::Scenario) -> toml::Value {
        toml::from_str::<toml::Table>(&sc.to_toml_string())
            .map(toml::Value::Table)
            .unwrap_or_else(|e| toml::Value::String(e.to_string()))
    }
    fn text(v: Option<&toml::Value>) -> String {
        match v {
            None => "absent".into(),
            Some(toml::Value::Float(x)) => toml_float(*x),
            Some(v) => one_line(&v.to_string()),
        }
    }
    fn walk(
        key: &str,
        a: Option<&toml::Value>,
        b: Option<&toml::Value>,
    ) -> Option<(String, String, String)> {
        use toml::Value::{Array, Table};
        let join = |k: &str| {
            if key.is_empty() {
                k.to_string()
            } else {
                format!("{key}.{k}")
            }
        };
        match (a, b) {
            (Some(Table(x)), Some(Table(y))) => {
                let mut keys: Vec<&String> = x.keys().collect();
                keys.extend(y.keys().filter(|k| !x.contains_key(*k)));
                keys.into_iter()
                    .find_map(|k| walk(&join(k), x.get(k), y.get(k)))
            }
            (Some(Array(x)), Some(Array(y))) => (0..x.len().max(y.len()))
                .find_map(|i| walk(&join(&i.to_string()), x.get(i), y.get(i))),
            (x, y) if x == y => None,
            (x, y) => Some((key.to_string(), text(x), text(y))),
        }
    }
    walk("", Some(&parse(a)), Some(&parse(b)))
}

/// A 16-hex-digit hash (FNV-1a) of the resolved scenario (its complete
/// TOML, every key explicit): what a snapshot belongs to.
fn fingerprint(sc: &tippetop::Scenario) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in sc.to_toml_string().as_bytes() {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// The state of a `Simulation` behind its lock.
struct SimState {
    /// `None` after an internal error left the run unusable.
    sim: Option<tippetop::Simulation>,
    /// Seconds spent integrating so far.
    wall: f64,
}

/// A run you can step, inspect, copy and continue: `integrate_to(t)`
/// (seconds) integrates until the run has passed `t` without ever
/// shortening a step, so stepping in pieces gives the same trajectory, bit
/// for bit, as `run`; `state` is the state at `time`.
#[pyclass(module = "tippetop", frozen)]
struct Simulation {
    sc: Arc<tippetop::Scenario>,
    /// [`fingerprint`] of `sc`.
    fingerprint: String,
    /// Taken with `try_lock` only: a thread that waited for it while
    /// holding the GIL would deadlock with `integrate_to`, which holds it
    /// with the GIL released.
    state: Mutex<SimState>,
}

impl Simulation {
    fn lock(&self) -> PyResult<MutexGuard<'_, SimState>> {
        self.state.try_lock().map_err(|e| match e {
            TryLockError::WouldBlock => PyRuntimeError::new_err(
                "the simulation is busy (integrate_to is running in another thread)",
            ),
            TryLockError::Poisoned(_) => PyRuntimeError::new_err("the simulation is unusable"),
        })
    }

    fn with<T>(&self, f: impl FnOnce(&mut tippetop::Simulation) -> T) -> PyResult<T> {
        let mut g = self.lock()?;
        match g.sim.as_mut() {
            Some(s) => Ok(f(s)),
            None => Err(unusable()),
        }
    }
}

fn unusable() -> PyErr {
    PyRuntimeError::new_err("the simulation is unusable after an internal error")
}

#[pymethods]
impl Simulation {
    /// A run of `scenario` at `t = 0` (ValueError for bad input).
    #[new]
    fn new(scenario: &Scenario) -> PyResult<Self> {
        let sim = guarded(|| tippetop::Simulation::new(&scenario.sc))?.map_err(to_py_err)?;
        Ok(Simulation {
            sc: Arc::new(scenario.sc.clone()),
            fingerprint: fingerprint(&scenario.sc),
            state: Mutex::new(SimState {
                sim: Some(sim),
                wall: 0.0,
            }),
        })
    }

    /// Integrate until the run has passed `t` [s] (or ended, or failed: see
    /// `error`), with the GIL released. ValueError if `t` is before the last
    /// time integrated to or after `solver.t_end`. Ctrl-C raises
    /// KeyboardInterrupt within a second; the run then stands at its last
    /// step (`time`) and goes on from there, bit for bit, with the next call.
    fn integrate_to(&self, py: Python<'_>, t: &Bound<'_, PyAny>) -> PyResult<()> {
        let t = float_arg(
            t,
            "t",
            "a time [s], from the last time integrated to up to solver.t_end",
        )?;
        let mut g = self.lock()?;
        let st = &mut *g;
        let Some(sim) = st.sim.as_mut() else {
            return Err(unusable());
        };
        let start = Instant::now();
        let mut interrupted: Option<PyErr> = None;
        let r = py.detach(|| {
            guarded(|| sim.integrate_to_while(t, &mut signals_checker(&mut interrupted)))
        });
        st.wall += start.elapsed().as_secs_f64();
        match r {
            // Interrupted: the run stands at its last accepted step
            // (`time`), and can go on from there.
            Ok(r) => match (r.map_err(to_py_err)?, interrupted) {
                (false, Some(e)) => Err(e),
                _ => Ok(()),
            },
            Err(e) => {
                st.sim = None;
                Err(e)
            }
        }
    }

    /// The time [s] `state` refers to: the last time integrated to (earlier
    /// if the run failed before it).
    #[getter]
    fn time(&self) -> PyResult<f64> {
        self.with(|s| s.time())
    }

    /// The state at `time` as a dict: one trajectory.csv row (SI units).
    #[getter]
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let row = self.with(|s| guarded(|| s.state()))??;
        let d = PyDict::new(py);
        for (name, v) in COLUMNS.iter().zip(row.values()) {
            d.set_item(*name, v)?;
        }
        Ok(d)
    }

    /// `None`, or the failure that ended the run (as `Trajectory.error`).
    #[getter]
    fn error(&self, py: Python<'_>) -> PyResult<Py<PyAny>> {
        let e = self.with(|s| s.error().cloned())?;
        Ok(error_obj(py, e.as_ref())?.unbind())
    }

    /// True once the run has reached `solver.t_end` or failed.
    #[getter]
    fn is_finished(&self) -> PyResult<bool> {
        self.with(|s| s.is_finished())
    }

    /// A copy of the whole run as it stands (exact floats).
    fn snapshot(&self) -> PyResult<Snapshot> {
        let g = self.lock()?;
        let sim = g.sim.as_ref().ok_or_else(unusable)?;
        Ok(Snapshot {
            inner: Mutex::new(sim.snapshot()),
            wall: g.wall,
            fingerprint: self.fingerprint.clone(),
            scenario: self.sc.clone(),
        })
    }

    /// Go back to `snapshot` (it replaces the run entirely). ValueError if
    /// the snapshot was taken from a simulation of another scenario (its
    /// fingerprint, a hash of the resolved scenario, differs), naming the
    /// first key that differs and both values.
    fn restore(&self, snapshot: &Snapshot) -> PyResult<()> {
        if snapshot.fingerprint != self.fingerprint {
            let what = match first_difference(&snapshot.scenario, &self.sc) {
                Some((key, theirs, ours)) => {
                    format!("{key} is {theirs} there, {ours} in this simulation's")
                }
                None => format!(
                    "fingerprint {}, this simulation's {}",
                    snapshot.fingerprint, self.fingerprint
                ),
            };
            return Err(PyValueError::new_err(format!(
                "snapshot: taken from a simulation of another scenario ({what}) (a snapshot of \
                 a simulation of this scenario)"
            )));
        }
        let snap = snapshot
            .inner
            .lock()
            .map_err(|_| PyRuntimeError::new_err("the snapshot is unusable"))?;
        let mut g = self.lock()?;
        match g.sim.as_mut() {
            Some(s) => s.restore(&snap),
            None => {
                let mut s = tippetop::Simulation::new(&self.sc).map_err(to_py_err)?;
                s.restore(&snap);
                g.sim = Some(s);
            }
        }
        g.wall = snapshot.wall;
        Ok(())
    }

    /// The run so far as a `Trajectory` (samples up to the last accepted
    /// step, summary, error); after `integrate_to(t_end)` it equals
    /// `run(scenario)`. The simulation itself is left as it is (it is
    /// copied), so it can go on.
    // The name of the Rust API (and the issue); in Python it copies.
    #[allow(clippy::wrong_self_convention)]
    fn into_trajectory(&self, py: Python<'_>) -> PyResult<Trajectory> {
        let (snap, wall) = {
            let g = self.lock()?;
            (g.sim.as_ref().ok_or_else(unusable)?.snapshot(), g.wall)
        };
        let sc = &self.sc;
        // One copy of the run (the snapshot), turned into the trajectory.
        let traj = py.detach(move || guarded(move || snap.into_trajectory()))?;
        Trajectory::new(py, sc, traj, wall)
    }

    fn __repr__(&self) -> PyResult<String> {
        let (t, done) = self.with(|s| (s.time(), s.is_finished()))?;
        Ok(format!(
            "tippetop.Simulation(time={}, finished={})",
            toml_float(t),
            if done { "True" } else { "False" }
        ))
    }
}

/// tippetop: tippe-top dynamics (the classical toy to the C60 nano tippe
/// top) from Python. `Scenario.preset("nano")`, `run(sc)` → `Trajectory`
/// of numpy float64 arrays (SI units, radians), `sweep(sc, vary=...)` → a
/// dict of arrays (one row per case), `Simulation(sc)` to step a run. Bad
/// input raises ValueError with the CLI's line (`key: what (range)`).
#[pymodule]
#[pyo3(name = "tippetop")]
fn tippetop_py(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Scenario>()?;
    m.add_class::<Trajectory>()?;
    m.add_class::<Simulation>()?;
    m.add_class::<Snapshot>()?;
    m.add_function(wrap_pyfunction!(run, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(ensemble, m)?)?;
    m.add_function(wrap_pyfunction!(rare, m)?)?;
    m.add("COLUMNS", COLUMNS.to_vec())?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
