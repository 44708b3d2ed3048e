//! `tippetop show`: print a scenario, resolved (a preset, a file and every
//! `--set` applied), as the TOML `tippetop run` would write into
//! `scenario.toml`, without running it.

use std::process::ExitCode;

use crate::scenario_load::input_error;

/// Print a scenario resolved (preset, file, every --set) as TOML.
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = "Examples:\n  \
                  tippetop show --preset classical\n  \
                  tippetop show --preset nano-physical --set thermal.temperature=77\n  \
                  tippetop show scenarios/nano.toml > mine.toml")]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML); or give --preset")),
    mut_arg("preset", |a| a.help("Start from a preset: \"nano\", \"nano-physical\" (C60 on graphene at 300 K), \"nano-adhesive\" (the same, deterministic) or \"classical\"")),
    mut_arg("sets", |a| a.help("Override a scenario key, e.g. --set initial.spin=3e7 (repeatable)")),
)]
pub struct ShowArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,
}

/// Run `tippetop show`: the resolved scenario's TOML on stdout; bad input
/// is one line on stderr and exit code 2.
pub fn run(args: &ShowArgs) -> ExitCode {
    let sc = crate::scenario_load::from_args(
        args.source.scenario.as_deref(),
        args.source.preset.as_deref(),
        &args.source.sets,
    )
    .and_then(|sc| sc.validate().map(|()| sc));
    match sc {
        Ok(sc) => {
            print!("{}", sc.to_toml_string());
            ExitCode::SUCCESS
        }
        Err(e) => input_error(e),
    }
}
