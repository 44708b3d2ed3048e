//! Errors: bad input (names the offending scenario key and the valid range)
//! and run-time failures (say when and why).

/// Everything that can go wrong in tippetop's library.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum Error {
    /// Bad input: `key` is the scenario key (e.g. `top.offset`, `force.0.stop`).
    #[error("{key}: {what} ({range})")]
    Invalid {
        /// Scenario key, `table.key`.
        key: String,
        /// What is wrong.
        what: String,
        /// The valid range.
        range: String,
    },
    /// A run that failed while integrating; `t` is the time of failure \[s\].
    /// The state there is the last row of the run's output (the summary's
    /// `*_final` values, [`crate::Simulation::state`]).
    #[error("at t = {} s: {why}", crate::human::s4(*t))]
    Runtime {
        /// Simulated time of the failure \[s\].
        t: f64,
        /// What kind of failure.
        kind: Failure,
        /// What went wrong, with the state where useful.
        why: String,
    },
}

/// The kinds of run-time failure ([`Error::Runtime`]), for programs that
/// react to them (the message says the same in words).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Failure {
    /// The normal force has no or two consistent solutions with friction
    /// (Painlevé paradox), in the equations of motion or at an impact.
    Painleve,
    /// The Euler-angle (reduced) model reached its pole θ = 0 or π.
    Pole,
    /// The sliding-only Coulomb law chatters at zero slip.
    Chattering,
    /// The fixed-step RK4 solution became unstable (energy balance lost).
    Unstable,
    /// The state became NaN or infinite.
    NonFinite,
    /// The state blew up: the symmetry axis, a unit vector up to the
    /// integration error, drifted far off unit length (or became NaN), so
    /// the integration diverged and the state is no motion of the top.
    BlowUp,
    /// A value of the output overflows f64 in SI units.
    OutputOverflow,
    /// The step limit (`solver.max_steps`) was reached.
    StepLimit,
    /// The adaptive step size underflowed.
    StepUnderflow,
    /// The top would leave the plane, which the on-plane models cannot follow.
    LiftOff,
    /// Too many stick/slip switches, or lift-offs and touchdowns.
    SwitchLimit,
    /// A numerical method of an analysis did not converge.
    Numerics,
    /// The motion reached a state the model does not follow (a stem the
    /// model cannot follow, docs/physics.md#stem; the Coulomb–Contensou
    /// stick, which it once named, is modelled, §contensou).
    NotModelled,
}

impl Failure {
    /// The kind as a short name (`"painleve"`, `"step_limit"`, ...), as in
    /// `summary.json`'s `failure`.
    pub fn as_str(self) -> &'static str {
        match self {
            Failure::Painleve => "painleve",
            Failure::Pole => "pole",
            Failure::Chattering => "chattering",
            Failure::Unstable => "unstable",
            Failure::NonFinite => "non_finite",
            Failure::BlowUp => "blow_up",
            Failure::OutputOverflow => "output_overflow",
            Failure::StepLimit => "step_limit",
            Failure::StepUnderflow => "step_underflow",
            Failure::LiftOff => "lift_off",
            Failure::SwitchLimit => "switch_limit",
            Failure::Numerics => "numerics",
            Failure::NotModelled => "not_modelled",
        }
    }
}

impl Error {
    /// A bad-input error for `key`.
    pub fn invalid(key: &str, what: String, range: String) -> Self {
        Error::Invalid {
            key: key.to_string(),
            what,
            range,
        }
    }

    /// A run-time error of `kind` at time `t` \[s\].
    pub fn runtime(t: f64, kind: Failure, why: impl Into<String>) -> Self {
        Error::Runtime {
            t,
            kind,
            why: why.into(),
        }
    }

    /// The kind of a run-time failure (`None` for bad input).
    pub fn failure(&self) -> Option<Failure> {
        match self {
            Error::Runtime { kind, .. } => Some(*kind),
            Error::Invalid { .. } => None,
        }
    }

    /// True for bad input (CLI exit code 2), false for run-time failures (exit code 3).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Invalid { .. })
    }
}

/// A number for a message: plain for ordinary magnitudes (`0.0015`,
/// `3.5e-10` as `0.00000000035` is not written), else `1e308` style.
pub(crate) fn num(x: f64) -> String {
    if x == 0.0 || (1e-4..1e15).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
