//! Arguments shared by several subcommands.

use std::path::PathBuf;

use clap::Args;

/// `tippetop merge` (every kind of shard's merge reads them; see
/// [`crate::merge_cmd`]).
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
                  tippetop merge shards/1 shards/2 shards/3 shards/4 --out result\n  \
                  tippetop merge shards/* --out result")]
pub struct MergeArgs {
    /// Shard output directories (each with sweep.csv and shard.json).
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,

    /// Output directory (created if missing; locked while merge writes; the
    /// previous command's files in it are replaced or removed).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
}

/// Where a scenario comes from: `[SCENARIO.toml] [--preset NAME] [--set
/// TABLE.KEY=VALUE ...]`, the preset first, the file over it, then each
/// `--set` in order. Flattened into every command that reads a scenario;
/// a command words an argument's help for itself with `mut_arg`.
#[derive(Debug, Clone, Args)]
pub struct ScenarioArgs {
    /// Scenario file (TOML).
    #[arg(value_name = "SCENARIO.toml")]
    pub scenario: Option<PathBuf>,

    /// Start from a built-in scenario ("nano", "nano-physical", "nano-adhesive", "classical").
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,

    /// Override one scenario value, e.g. `--set top.offset=0.002`; repeatable,
    /// applied in order after the file.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub sets: Vec<String>,
}

/// `--threads`, for the commands that run on all cores.
#[derive(Debug, Clone, Copy, Args)]
pub struct ThreadsArg {
    /// Number of threads, 1 to 1024 (default: one per core).
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}
