//! Loading the scenario for `run`: preset, scenario file and `--set`
//! overrides, resolved and validated by the library.
//!
//! TEMP until scenario lands: `tippetop::Scenario::load` and
//! `Scenario::to_toml_string` are being written in the library; until then
//! [`load`] takes the preset only, and [`to_toml`] writes a placeholder.

use tippetop::{Error, Scenario};

/// Resolve the scenario: `preset` as the base, the TOML text of a scenario
/// file over it, then the `TABLE.KEY=VALUE` overrides. Validated.
pub fn load(
    preset: Option<&str>,
    toml_text: Option<&str>,
    sets: &[String],
) -> Result<Scenario, Error> {
    // TEMP until scenario lands: replace the body with
    // `Scenario::load(preset, toml_text, sets)`.
    if toml_text.is_some() {
        return Err(Error::invalid(
            "scenario",
            "scenario files are not supported by this build yet".into(),
            "use --preset nano|classical".into(),
        ));
    }
    if !sets.is_empty() {
        eprintln!("warning: --set is ignored by this build (scenario parsing not yet available)");
    }
    let sc = Scenario::preset(preset.unwrap_or("nano"))?;
    sc.validate()?;
    Ok(sc)
}

/// The resolved scenario as TOML text (written to `scenario.toml` and into
/// `summary.json`).
pub fn to_toml(scenario: &Scenario) -> String {
    // TEMP until scenario lands: replace with `scenario.to_toml_string()`.
    let mut s = String::from(
        "# TEMP: scenario serialization is not available in this build yet.\n\
         # The resolved scenario, for the record:\n",
    );
    for line in format!("{scenario:#?}").lines() {
        s.push_str("# ");
        s.push_str(line);
        s.push('\n');
    }
    s
}
