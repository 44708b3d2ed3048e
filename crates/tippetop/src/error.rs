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
    #[error("at t = {t:e} s: {why}")]
    Runtime {
        /// Simulated time of the failure \[s\].
        t: f64,
        /// What went wrong, with the state where useful.
        why: String,
    },
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

    /// A run-time error at time `t` \[s\].
    pub fn runtime(t: f64, why: impl Into<String>) -> Self {
        Error::Runtime { t, why: why.into() }
    }

    /// True for bad input (CLI exit code 2), false for run-time failures (exit code 3).
    pub fn is_input(&self) -> bool {
        matches!(self, Error::Invalid { .. })
    }
}
