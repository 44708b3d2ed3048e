//! `tippetop show`: print a scenario, resolved (a preset, a file and every
//! `--set` applied), as the TOML `tippetop run` would write into
//! `scenario.toml`, without running it.

use std::path::PathBuf;
use std::process::ExitCode;

use crate::scenario_load::input_error;

/// `tippetop show`.
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = "Examples:\n  \
                  tippetop show --preset classical\n  \
                  tippetop show --preset nano-physical --set thermal.temperature=77\n  \
                  tippetop show scenarios/nano.toml > mine.toml")]
pub struct ShowArgs {
    /// Scenario file (TOML); or give --preset.
    pub scenario: Option<PathBuf>,
    /// Start from a preset: "nano", "nano-physical" (C60 on graphene at 300 K), "nano-adhesive" (the same, deterministic) or "classical".
    #[arg(long)]
    pub preset: Option<String>,
    /// Override a scenario key, e.g. --set initial.spin=3e7 (repeatable).
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
}

/// Run `tippetop show`: the resolved scenario's TOML on stdout; bad input
/// is one line on stderr and exit code 2.
pub fn run(args: &ShowArgs) -> ExitCode {
    let sc = crate::scenario_load::from_args(
        args.scenario.as_deref(),
        args.preset.as_deref(),
        &args.set,
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
