//! Temperature and damping, the scenario's `[thermal]` table: the data,
//! its validation (the cross-key rules and the step-size rule of
//! `solver.method = "langevin"` are `scenario::langevin`'s)
//! (the physics and the integrator: docs/physics.md#langevin,
//! `integrate::langevin` and `model::vector`'s thermostat).
//!
//! A Langevin run adds to the deterministic forces, each with its matching
//! white noise (fluctuation–dissipation at temperature `T`):
//!
//! - a force `−m γ_t v` on the centre of mass (`v` its 3D velocity, the
//!   vertical part included: on the plane it follows from the tilt rate);
//! - a torque `−γ_r I ω` (`I` the inertia tensor about the centre of mass,
//!   `ω` the angular velocity: every rotational mode relaxes at `γ_r`);
//! - optionally a viscous slip law at the contact, a force `−c v_P` at the
//!   contact point (`v_P` the horizontal slip velocity).
//!
//! The noise is generated in the constrained coordinates of the top on the
//! plane (its exact Ornstein–Uhlenbeck step, docs/physics.md#langevin), so the
//! velocities have the Maxwell distribution of the constrained top.

use toml::{Table, Value};

use crate::Error;
use crate::input::Key;
use crate::input::field::{Bounds, Num};
use crate::input::reader::{Keys, Section};

/// The table's name.
const TABLE: &str = "thermal";

/// Boltzmann's constant \[J/K\] (exact since the 2019 SI).
pub const BOLTZMANN: f64 = 1.380649e-23;

/// Largest product of the step and the fastest rate of a Langevin run
/// ([`step_rates`]): `dt · rate <= 0.02` (about 300 steps per period of the
/// fastest oscillation, 50 steps per relaxation time). The splitting's
/// error is second order in this product (docs/physics.md#langevin, the weak
/// order measured in tests/physics/thermal.rs).
pub const MAX_STEP_RATE: f64 = 0.02;

/// Largest product of the step and the fastest rate of a Brownian run
/// ([`crate::input::scenario::langevin::brownian_rates`]): `dt · rate <= 0.002`,
/// so the rms angle of one step, `sqrt(2 D_r dt)`, is at most 0.063 rad
/// (Euler–Maruyama is weak order 1: its bias is proportional to this
/// product; measured in tests/physics/thermal.rs).
pub const MAX_BROWNIAN_STEP_RATE: f64 = 0.002;

/// The largest [`crate::input::scenario::langevin::contact_ratio`] of a Brownian
/// run (the contact damping's rates over the bath's own): the mobility
/// `Γ⁻¹` comes from a Cholesky factor of `Γ`, whose relative error grows as
/// its condition number (up to about this ratio) times the rounding unit
/// 1.1e-16: at 1e8 the mobility keeps ~8 digits.
pub const MAX_BROWNIAN_CONTACT_RATIO: f64 = 1e8;

/// Valid range of `thermal.temperature`.
pub const TEMPERATURE_RANGE: &str =
    "a finite temperature >= 0 [K] (> 0 needs solver.method = \"langevin\")";
/// Valid range of `thermal.damping_translational`.
pub const DAMPING_T_RANGE: &str = "a finite rate >= 0 [1/s] (> 0 at temperature > 0)";
/// Valid range of `thermal.damping_rotational`.
pub const DAMPING_R_RANGE: &str = "a finite rate >= 0 [1/s] (> 0 at temperature > 0)";
/// Valid range of `thermal.damping_contact`.
pub const DAMPING_C_RANGE: &str =
    "a finite coefficient >= 0 [N s/m] (a viscous slip law at the contact; default 0)";
/// Valid range of `thermal.seed`.
pub const SEED_RANGE: &str =
    "an integer >= 0, required at temperature > 0 (the random stream's key)";
/// Valid range of `thermal.run`.
pub const RUN_RANGE: &str =
    "an integer, 0 <= run < 4294967296 (the run's index in the random stream; default 0)";

/// Largest `thermal.run` + 1: the stream's counter holds a 32-bit run index.
pub const MAX_RUNS: u64 = 1 << 32;

/// Largest number of runs of one ensemble (`tippetop ensemble --runs`,
/// `tippetop bit --runs`, per point of `bit --vary`, Python's
/// `ensemble`): 1 000 000. What an ensemble keeps per run (the passage
/// times of its Kaplan–Meier estimate, a bit's run results, Python's
/// arrays, the rows a merge or `--resume` reads back) stays within the
/// memory bound ([`crate::limits::MEMORY_BUDGET`]).
pub const MAX_ENSEMBLE_RUNS: usize = 1_000_000;

/// The `[thermal]` table (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Thermal {
    /// Temperature T \[K\].
    pub temperature: f64,
    /// γ_t \[1/s\]: the force `−m γ_t v` on the centre of mass.
    pub damping_translational: f64,
    /// γ_r \[1/s\]: the torque `−γ_r I ω`.
    pub damping_rotational: f64,
    /// c \[N s/m\]: the force `−c v_P` at the contact point.
    pub damping_contact: f64,
    /// Key of the random stream (required at `T > 0`).
    pub seed: Option<u64>,
    /// Index of this run in the stream (`thermal.run`; an ensemble's run K).
    pub run: u64,
}

impl Thermal {
    /// No temperature, no damping.
    pub const NONE: Thermal = Thermal {
        temperature: 0.0,
        damping_translational: 0.0,
        damping_rotational: 0.0,
        damping_contact: 0.0,
        seed: None,
        run: 0,
    };

    /// Whether any key differs from [`Thermal::NONE`] (the table is then
    /// written out and needs `solver.method = "langevin"`).
    pub fn is_set(&self) -> bool {
        *self != Self::NONE
    }

    /// Whether the run is stochastic (`T > 0`).
    pub fn is_hot(&self) -> bool {
        self.temperature > 0.0
    }

    /// Whether any damping is on.
    pub fn damps(&self) -> bool {
        self.damping_translational > 0.0
            || self.damping_rotational > 0.0
            || self.damping_contact > 0.0
    }

    /// kT \[J\].
    pub fn kt(&self) -> f64 {
        BOLTZMANN * self.temperature
    }

    /// Check each key's own range (the cross-key rules are
    /// [`crate::input::scenario::langevin::check`]'s).
    pub fn validate(&self) -> Result<(), Error> {
        for k in NUMS {
            k.check(TABLE, self)?;
        }
        if self.run >= MAX_RUNS {
            return Err(Error::invalid(
                "thermal.run",
                format!("{} is not allowed", self.run),
                RUN_RANGE.into(),
            ));
        }
        Ok(())
    }
}

impl Default for Thermal {
    fn default() -> Self {
        Self::NONE
    }
}

/// Number of equal steps of a Langevin run: `n = ceil(t_end/dt − 1e-9)`
/// (at least 1), each of `t_end / n`; the `1e-9` keeps a `t_end` that is a
/// whole number of `dt` up to rounding at that number.
pub fn langevin_steps(t_end: f64, dt: f64) -> u64 {
    let n = (t_end / dt - 1e-9).ceil();
    if n.is_finite() && n >= 1.0 {
        n.min(u64::MAX as f64) as u64
    } else {
        1
    }
}

// ---------------------------------------------------------------------------
// The `[thermal]` keys: defined once, read, written.

/// `thermal.temperature`.
pub const TEMPERATURE: Num<Thermal> = Num {
    key: Key::doc(
        "temperature",
        TEMPERATURE_RANGE,
        "0",
        "T (docs/physics.md#langevin)",
    ),
    default: Some(0.0),
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |t| t.temperature,
    set: |t, v| t.temperature = v,
};

/// `thermal.damping_translational`.
pub const DAMPING_TRANSLATIONAL: Num<Thermal> = Num {
    key: Key::doc(
        "damping_translational",
        DAMPING_T_RANGE,
        "0",
        "gamma_t: force -m gamma_t v on the centre of mass",
    ),
    default: Some(0.0),
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |t| t.damping_translational,
    set: |t, v| t.damping_translational = v,
};

/// `thermal.damping_rotational`.
pub const DAMPING_ROTATIONAL: Num<Thermal> = Num {
    key: Key::doc(
        "damping_rotational",
        DAMPING_R_RANGE,
        "0",
        "gamma_r: torque -gamma_r I w",
    ),
    default: Some(0.0),
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |t| t.damping_rotational,
    set: |t, v| t.damping_rotational = v,
};

/// `thermal.damping_contact`.
pub const DAMPING_CONTACT: Num<Thermal> = Num {
    key: Key::doc(
        "damping_contact",
        DAMPING_C_RANGE,
        "0",
        "c: force -c v_P at the contact point",
    ),
    default: Some(0.0),
    bounds: Bounds::AtLeast(0.0),
    check_range: None,
    get: |t| t.damping_contact,
    set: |t, v| t.damping_contact = v,
};

/// The number keys of `[thermal]`, in document order: read, written,
/// checked and listed from their definitions (`seed` and `run`, whole
/// numbers, are read and written in [`parse`] and [`to_table`]).
pub const NUMS: [Num<Thermal>; 4] = [
    TEMPERATURE,
    DAMPING_TRANSLATIONAL,
    DAMPING_ROTATIONAL,
    DAMPING_CONTACT,
];

/// Every `[thermal]` key, in document order (`tippetop keys thermal`).
pub const KEYS: Keys = &[
    TEMPERATURE.key,
    DAMPING_TRANSLATIONAL.key,
    DAMPING_ROTATIONAL.key,
    DAMPING_CONTACT.key,
    Key::doc(
        "seed",
        SEED_RANGE,
        "required at T > 0",
        "key of the random stream",
    ),
    Key::doc("run", RUN_RANGE, "0", "index of this run in the stream"),
];

/// The `[thermal]` table (types and defaults, in document order; no
/// range checks: [`Thermal::validate`]).
pub(crate) fn parse(s: &Section) -> Result<Thermal, Error> {
    let mut th = Thermal::NONE;
    for k in NUMS {
        k.read(s, false, &mut th)?;
    }
    th.seed = match s.get("seed") {
        None => None,
        Some(_) => Some(s.usize("seed", 0)? as u64),
    };
    th.run = s.usize("run", 0)? as u64;
    Ok(th)
}

/// The `[thermal]` table of `th` (`seed` only when given).
pub(crate) fn to_table(th: &Thermal) -> Table {
    let mut t = Table::new();
    for k in NUMS {
        k.write(th, &mut t);
    }
    if let Some(seed) = th.seed {
        t.insert("seed".into(), Value::Integer(seed as i64));
    }
    t.insert("run".into(), Value::Integer(th.run as i64));
    t
}
