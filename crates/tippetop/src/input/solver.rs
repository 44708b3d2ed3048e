//! The solver settings (`[solver]`): the method, the model, tolerances,
//! samples and the step limit, with their bounds.

use toml::{Table, Value};

use crate::input::Key;
use crate::input::field::{Bounds, Num};
use crate::input::reader::{Keys, Section, name_of, to_i64};
use crate::{Error, Sample};

/// The table's name.
const TABLE: &str = "solver";

/// Integration method: what the user asks for (`solver.method`). Each
/// runs one algorithm, an `integrate::Stepper` named after it: `adaptive`
/// DOP853, `rk4` RK4, `stiff` Rodas4P, `langevin` and `brownian` the
/// Langevin engine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Adaptive Dormand–Prince 8(5,3) with 7th-order dense output.
    Adaptive,
    /// Classical fixed-step RK4 (the paper's method).
    Rk4,
    /// Linearly implicit Rosenbrock method Rodas4P (L-stable, order 4,
    /// numerical Jacobian), for the stiff regularised friction law near
    /// rolling (time scale `ε / (μ g)`).
    Stiff,
    /// Langevin dynamics with the fixed step `solver.dt`: the exact
    /// Ornstein–Uhlenbeck step of the damping and its noise around an RK4
    /// step of the deterministic forces (a symmetric splitting, weak order
    /// 2; docs/physics.md#langevin). Vector or rigid model, no Coulomb
    /// friction.
    Langevin,
    /// The overdamped limit of the Langevin dynamics (Brownian motion of
    /// the axis and the centre with the same damping and forces), fixed step
    /// `solver.dt`, Euler–Maruyama (weak order 1; docs/physics.md#langevin): for
    /// windows of microseconds and more, where the Langevin step would need
    /// 1e10 steps.
    Brownian,
}

impl Method {
    /// Whether the method is one of the thermal ones (`"langevin"`,
    /// `"brownian"`): fixed step `solver.dt`, `[thermal]`, noise.
    pub fn is_stochastic(self) -> bool {
        matches!(self, Method::Langevin | Method::Brownian)
    }
}

/// Which equations of motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelKind {
    /// The paper's Euler-angle model (App. A).
    Reduced,
    /// Full 3D rigid body with a unit quaternion.
    Rigid,
    /// The reduced model's physics (the sphere stays on the plane) written
    /// with the symmetry-axis vector, the angular velocity and the
    /// centre-of-mass velocity in the space frame: no Euler angles, so no
    /// pole singularity and no trigonometry (docs/physics.md#vector-model).
    Vector,
}

/// The valid range of `solver.max_steps`.
pub(crate) const MAX_STEPS_RANGE: &str =
    "an integer, 1 <= max_steps <= 1000000000; default 20000000, 2000000 with method = \"stiff\"";

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverSettings {
    /// Integration method.
    pub method: Method,
    /// End time \[s\].
    pub t_end: f64,
    /// Number of RK4 steps over `[0, t_end]` (RK4 only); a multiple of
    /// `samples - 1`, which is its default.
    pub steps: usize,
    /// Relative tolerance (adaptive and stiff); the absolute tolerance is the same
    /// number in the scaled units (lengths by R, masses by m, see docs/physics.md).
    pub rtol: f64,
    /// Output rows, evenly spaced on `[0, t_end]`.
    pub samples: usize,
    /// Which model.
    pub model: ModelKind,
    /// Largest number of accepted steps of the run (`solver.max_steps`);
    /// `None` for the method's default, [`max_steps_for`].
    /// A run that reaches it stops with a run-time error.
    pub max_steps: Option<u64>,
    /// The fixed step \[s\] of `method = "langevin"` or `"brownian"` (`solver.dt`; the run
    /// takes [`crate::input::thermal::langevin_steps`] equal steps); `None` otherwise.
    pub dt: Option<f64>,
}

impl SolverSettings {
    /// Defaults: adaptive, rtol 1e-10, 1001 samples, 1000 steps (`samples -
    /// 1`, so that `method = "rk4"` alone is valid), the vector model (the
    /// Euler-angle physics without the pole; `reduced`, the paper's own
    /// form, is what `reproduce` runs), the method's step limit.
    pub fn new(t_end: f64) -> Self {
        SolverSettings {
            method: Method::Adaptive,
            t_end,
            steps: 1000,
            rtol: 1e-10,
            samples: 1001,
            model: ModelKind::Vector,
            max_steps: None,
            dt: None,
        }
    }

    /// The run's step limit: `max_steps`, or the method's default
    /// ([`max_steps_for`]).
    pub fn step_limit(&self) -> u64 {
        self.max_steps.unwrap_or_else(|| max_steps_for(self.method))
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<(), Error> {
        T_END.check(TABLE, self)?;
        if self.samples < 2 || self.samples > MAX_SAMPLES {
            return Err(Error::invalid(
                "solver.samples",
                format!(
                    "{} is too {}",
                    self.samples,
                    if self.samples < 2 { "few" } else { "many" }
                ),
                format!(
                    "an integer, 2 <= samples <= {}: each row keeps {} bytes in memory",
                    MAX_SAMPLES, BYTES_PER_SAMPLE
                ),
            ));
        }
        RTOL.check(TABLE, self)?;
        if let Some(n) = self.max_steps {
            if !(1..=STEP_LIMIT_MAX).contains(&n) {
                return Err(Error::invalid(
                    "solver.max_steps",
                    format!("{n} is not allowed"),
                    MAX_STEPS_RANGE.into(),
                ));
            }
        }
        if self.method == Method::Rk4 {
            if self.steps as u64 > self.step_limit() {
                return Err(Error::invalid(
                    "solver.steps",
                    format!(
                        "{} exceeds the step limit {}",
                        self.steps,
                        self.step_limit()
                    ),
                    "steps <= solver.max_steps (default 20000000), a multiple of samples - 1"
                        .into(),
                ));
            }
            if self.steps == 0 {
                return Err(Error::invalid(
                    "solver.steps",
                    "0 steps".into(),
                    "an integer >= 1, a multiple of samples - 1".into(),
                ));
            }
            if self.steps % (self.samples - 1) != 0 {
                return Err(Error::invalid(
                    "solver.steps",
                    format!(
                        "{} is not a multiple of samples - 1 = {}",
                        self.steps,
                        self.samples - 1
                    ),
                    "a multiple of samples - 1 (method = \"rk4\")".into(),
                ));
            }
        }
        Ok(())
    }
}

// ---------------------------------------------------------------------------
// Bounds of the solver settings (see `limits` for the checks of a whole run).

/// The default step limit of a run (accepted steps over all its integration
/// segments) for the explicit methods; a run that reaches its limit stops
/// with a run-time error (exit code 3). Measured (release build, one core of a shared
/// 2-core machine, classical preset with `initial.spin = 1e8`, which needs
/// far more steps): 20 million DOP853 steps take 39 s (reduced model), 46 s
/// (vector), 47 s (rigid), with memory flat at 6 to 21 MB; so a run that
/// cannot make progress stops within about a minute. The stiff method gets
/// a tenth ([`max_steps_for`]). `solver.max_steps` lowers or raises it, up
/// to [`STEP_LIMIT_MAX`].
pub const MAX_STEPS: u64 = 20_000_000;

/// Largest `solver.max_steps`: fifty times the default, about 40 minutes
/// of one core for DOP853 at the rate measured for [`MAX_STEPS`] (memory
/// does not grow with the steps), for a long run that advances at a steady
/// rate. Below 2⁴⁰, the bits of a random stream's step counter.
pub const STEP_LIMIT_MAX: u64 = 1_000_000_000;

/// Largest number of output rows (`solver.samples`). One row takes
/// [`BYTES_PER_SAMPLE`] (224) bytes in memory (and about 440 bytes of CSV),
/// so 5 000 000 rows need 1.12 GB while the run is kept in memory (and a
/// 2.2 GB trajectory.csv): within [`crate::limits::MEMORY_BUDGET`]. A
/// command that runs several runs at once (sweep, ensemble, bit) runs no
/// more of them at once than fit in that bound
/// ([`crate::limits::fit_threads`]); an ensemble keeps histograms at every
/// sample time and has its own, lower limit
/// (`analysis::ensemble::MAX_SAMPLES`).
pub const MAX_SAMPLES: usize = 5_000_000;

/// Memory of one output row while its run is kept \[bytes\]: the row itself
/// (a [`Sample`]: 25 `f64` and a `u8`, 208 bytes), its sample time and, in a
/// stochastic run, the integral of N over its interval (8 bytes each): 224.
pub const BYTES_PER_SAMPLE: u64 = (std::mem::size_of::<Sample>() + 16) as u64;

/// The default step limit of a run with `method`: [`MAX_STEPS`] for the
/// explicit methods; a tenth of it for the stiff method (Rodas4P), whose
/// steps cost up to about ten DOP853 steps each (a numerical Jacobian, an LU
/// decomposition and five stages): 2 million of them took 4 s (nano preset,
/// `force.0.hy = 1e-12`) to 12 s (rigid model, classical, spin 1e8).
pub fn max_steps_for(method: Method) -> u64 {
    match method {
        Method::Stiff => MAX_STEPS / 10,
        Method::Adaptive | Method::Rk4 | Method::Langevin | Method::Brownian => MAX_STEPS,
    }
}

// ---------------------------------------------------------------------------
// The `[solver]` keys: defined once, read, written.

/// `solver.t_end`.
pub const T_END: Num<SolverSettings> = Num {
    key: Key::doc(
        "t_end",
        "a finite time > 0 [s]",
        "required",
        "the run's duration",
    ),
    default: None,
    bounds: Bounds::Above(0.0),
    check_range: None,
    get: |s| s.t_end,
    set: |s, v| s.t_end = v,
};

/// `solver.rtol`.
pub const RTOL: Num<SolverSettings> = Num {
    key: Key::doc(
        "rtol",
        "1e-14 <= rtol <= 1e-2",
        "1e-10",
        "relative tolerance (adaptive, stiff)",
    ),
    default: Some(1e-10),
    bounds: Bounds::Within(1e-14, 1e-2),
    check_range: None,
    get: |s| s.rtol,
    set: |s, v| s.rtol = v,
};

/// Every `[solver]` key, in document order (`tippetop keys solver`).
pub const KEYS: Keys = &[
    Key::doc(
        "method",
        "\"adaptive\", \"rk4\", \"stiff\", \"langevin\" or \"brownian\"",
        "\"adaptive\"",
        "the integrator",
    ),
    T_END.key,
    Key::doc(
        "steps",
        "an integer >= 1, a multiple of samples - 1 (method = \"rk4\"); default samples - 1",
        "samples - 1",
        "RK4's step count",
    ),
    RTOL.key,
    Key::doc(
        "samples",
        "an integer, 2 <= samples <= 5000000",
        "1001",
        "output rows, evenly spaced from 0 to t_end",
    ),
    Key::doc(
        "model",
        "\"reduced\", \"vector\" or \"rigid\"",
        "\"vector\"",
        "the equations of motion (docs/physics.md)",
    ),
    Key::doc(
        "max_steps",
        MAX_STEPS_RANGE,
        "20000000 (2000000 with stiff)",
        "step limit of the run",
    ),
    Key::doc(
        "dt",
        "a finite time > 0 [s], the fixed step of method = \"langevin\" or \"brownian\" (only there)",
        "",
        "the Langevin or Brownian step",
    ),
];

/// `solver.method`'s names.
pub(crate) const METHODS: &[(&str, Method)] = &[
    ("adaptive", Method::Adaptive),
    ("rk4", Method::Rk4),
    ("stiff", Method::Stiff),
    ("langevin", Method::Langevin),
    ("brownian", Method::Brownian),
];

/// `solver.model`'s names.
pub(crate) const MODELS: &[(&str, ModelKind)] = &[
    ("reduced", ModelKind::Reduced),
    ("rigid", ModelKind::Rigid),
    ("vector", ModelKind::Vector),
];

/// The `[solver]` table (types, required keys and defaults, in document
/// order; no range checks: [`SolverSettings::validate`]).
pub(crate) fn parse(s: &Section, has_preset: bool) -> Result<SolverSettings, Error> {
    let method = s.name("method", METHODS, Method::Adaptive)?;
    let mut d = SolverSettings::new(0.0);
    T_END.read(s, has_preset, &mut d)?;
    let samples = s.usize("samples", d.samples)?;
    let steps = s.usize("steps", samples.saturating_sub(1))?;
    RTOL.read(s, has_preset, &mut d)?;
    let solver = SolverSettings {
        method,
        steps,
        samples,
        model: s.name("model", MODELS, d.model)?,
        max_steps: match s.get("max_steps") {
            None => None,
            Some(_) => Some(s.usize("max_steps", 0)? as u64),
        },
        dt: match s.get("dt") {
            None => None,
            Some(_) => Some(s.f64("dt", None)?),
        },
        ..d
    };
    Ok(solver)
}

/// The `[solver]` table of `so` (`steps`, `max_steps`, `dt` only when set).
pub(crate) fn to_table(so: &SolverSettings) -> Table {
    let mut solver = Table::new();
    solver.insert(
        "method".into(),
        Value::String(name_of(METHODS, so.method).into()),
    );
    T_END.write(so, &mut solver);
    // `steps` defaults to `samples - 1`: written only when it differs,
    // so that changing `samples` (or `method`) alone keeps RK4 valid.
    if so.steps != so.samples.wrapping_sub(1) {
        solver.insert("steps".into(), Value::Integer(to_i64(so.steps)));
    }
    RTOL.write(so, &mut solver);
    solver.insert("samples".into(), Value::Integer(to_i64(so.samples)));
    solver.insert(
        "model".into(),
        Value::String(name_of(MODELS, so.model).into()),
    );
    if let Some(n) = so.max_steps {
        solver.insert("max_steps".into(), Value::Integer(to_i64(n as usize)));
    }
    if let Some(dt) = so.dt {
        solver.insert("dt".into(), Value::Float(dt));
    }
    solver
}
