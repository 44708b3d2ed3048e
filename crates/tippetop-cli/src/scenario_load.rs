//! Loading the scenario for `run`: preset, scenario file and `--set`
//! overrides, resolved and validated by the library.

use tippetop::{Error, Scenario};

/// Resolve the scenario: `preset` as the base, the TOML text of a scenario
/// file over it, then the `TABLE.KEY=VALUE` overrides. Validated.
pub fn load(
    preset: Option<&str>,
    toml_text: Option<&str>,
    sets: &[String],
) -> Result<Scenario, Error> {
    Scenario::load(preset, toml_text, sets)
}

/// The resolved scenario as TOML text (written to `scenario.toml` and into
/// `summary.json`).
pub fn to_toml(scenario: &Scenario) -> String {
    scenario.to_toml_string()
}
