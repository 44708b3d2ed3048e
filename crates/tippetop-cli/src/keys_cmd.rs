//! `tippetop keys [TABLE]`: every scenario key with its unit, default,
//! valid range and a one-line doc, from the keys' own definitions
//! ([`tippetop::input`]; the force plug-ins' tables included). `--markdown`
//! writes docs/keys.md's text.

use std::process::ExitCode;

use crate::scenario_load::input_error;

/// The command that regenerates docs/keys.md.
pub const REGENERATE: &str = "tippetop keys --markdown > docs/keys.md";

/// Every scenario key: unit, default, range and what it is (docs/keys.md).
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = "Examples:\n  \
                  tippetop keys surface\n  \
                  tippetop keys\n  \
                  tippetop keys --markdown > docs/keys.md")]
pub struct KeysArgs {
    /// One table (top, surface, adhesion, force, well, initial, solver, thermal, or a force plug-in's such as wind); all when omitted.
    pub table: Option<String>,
    /// Print docs/keys.md (Markdown tables of every key) instead of the listing.
    #[arg(long)]
    pub markdown: bool,
}

/// Run `tippetop keys`: the listing (or Markdown) on stdout; an unknown
/// table is one line on stderr and exit code 2.
pub fn run(args: &KeysArgs) -> ExitCode {
    let all = tippetop::input::scenario::key_tables();
    let tables = match &args.table {
        None => all,
        Some(name) => match all.iter().find(|t| t.name == name.as_str()) {
            Some(t) => vec![*t],
            None => {
                let names: Vec<&str> = all.iter().map(|t| t.name).collect();
                return input_error(format!(
                    "keys: unknown table {name:?} (valid tables: {})",
                    names.join(", ")
                ));
            }
        },
    };
    if args.markdown {
        print!("{}", tippetop::input::markdown(&tables, REGENERATE));
    } else {
        print!("{}", tippetop::input::listing(&tables));
    }
    ExitCode::SUCCESS
}
