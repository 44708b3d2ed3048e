//! Loading the scenario of a command: preset, scenario file and `--set`
//! overrides, resolved and validated by the library; the one-line bad-input
//! message every command prints.

use std::path::Path;
use std::process::ExitCode;

use tippetop::{Error, Scenario};

/// Bad input of a command: `error: ...` on one line (whitespace collapsed)
/// on stderr; the exit code 2 to return.
pub fn input_error(e: impl std::fmt::Display) -> ExitCode {
    let msg = e.to_string();
    eprintln!(
        "error: {}",
        msg.split_whitespace().collect::<Vec<_>>().join(" ")
    );
    ExitCode::from(2)
}

/// The text of an optional scenario file (at most
/// [`tippetop::limits::MAX_FILE_BYTES`]); `Err` (after the one-line
/// message, [`input_error`]) with exit code 2 if it cannot be read or is
/// too large.
pub fn read_text(path: Option<&Path>) -> Result<Option<String>, ExitCode> {
    match path {
        None => Ok(None),
        Some(path) => tippetop::limits::read_file(path)
            .map(Some)
            .map_err(input_error),
    }
}

/// The thread count a command runs with: `fit` (what fits in the memory
/// bound, [`tippetop::limits::fit_threads`]) out of `asked`, with a note on
/// stderr (unless `quiet`) when that is fewer. The output does not depend
/// on the thread count.
pub fn note_threads(quiet: bool, asked: usize, fit: usize) -> usize {
    if fit < asked && !quiet {
        eprintln!(
            "note: running {fit} at once, not {asked}: more would need more than the memory \
             bound of {} (the output is the same)",
            tippetop::limits::fmt_bytes(tippetop::limits::MEMORY_BUDGET)
        );
    }
    fit
}

/// The text of a small input file (a shard's `shard.json`, a `bit.toml`,
/// an ensemble's `summary.json`), at most
/// [`tippetop::limits::MAX_FILE_BYTES`]; `Err` is the one-line message
/// naming the file, with `what` (the file expected, in words).
pub fn read_small(path: &Path, what: &str) -> Result<String, String> {
    tippetop::limits::read_file(path).map_err(|e| match e {
        Error::Invalid {
            key,
            what: w,
            range,
        } => format!("{key}: {w} ({range}; {what})"),
        other => other.to_string(),
    })
}

/// Resolve the scenario: `preset` as the base, the TOML text of a scenario
/// file over it, then the `TABLE.KEY=VALUE` overrides. Validated.
pub fn load(
    preset: Option<&str>,
    toml_text: Option<&str>,
    sets: &[String],
) -> Result<Scenario, Error> {
    Scenario::load(preset, toml_text, sets)
}

/// The scenario of a command that takes `[SCENARIO.toml] [--preset NAME]
/// [--set KEY=VALUE ...]` (`stability`, `regime`): the file read (an
/// unreadable file is bad input for the key `scenario`), then [`load`]. At
/// least one of the file and the preset is required.
pub fn from_args(
    scenario: Option<&std::path::Path>,
    preset: Option<&str>,
    sets: &[String],
) -> Result<Scenario, Error> {
    let text = match scenario {
        Some(p) => Some(tippetop::limits::read_file(p)?),
        None => None,
    };
    if text.is_none() && preset.is_none() {
        return Err(Error::invalid(
            "scenario",
            "no scenario given".into(),
            "a SCENARIO.toml argument or --preset nano|classical".into(),
        ));
    }
    load(preset, text.as_deref(), sets)
}

/// The resolved scenario as TOML text (written to `scenario.toml` and into
/// `summary.json`).
pub fn to_toml(scenario: &Scenario) -> String {
    scenario.to_toml_string()
}
