//! Arguments shared by several subcommands.

use std::path::PathBuf;

use clap::Args;

/// Long help of `tippetop merge`.
pub const MERGE_LONG_ABOUT: &str = "Join the output directories of the shards of one sweep (tippetop sweep \
                  --shard K/N) into --out: sweep.csv, byte for byte the file a one-shot run \
                  of the sweep writes, and shard.json. The shards may come in any order and \
                  from different layouts (e.g. 1/2 with 3/4 and 4/4); merge checks that \
                  they belong to the same sweep and cover every case exactly once, that \
                  each file matches the checksum its shard.json records (an edited or \
                  damaged shard is refused) and that each row is a row of its case. On any \
                  mismatch or gap it exits with code 2 and writes nothing; so does an --out \
                  that is one of the shard directories. Plots as for a \
                  whole sweep (see tippetop sweep --help). --out is locked and updated as a \
                  unit as for tippetop sweep (another command writing into it exits with \
                  code 1). A shard directory that a sweep is still writing into (its lock \
                  is held) is not read: merge exits with code 1 (\"DIR is in use by \
                  another tippetop process (pid N); wait until it ends\"). The shards of an \
                  ensemble (tippetop ensemble --shard K/N; told apart by their shard.json) \
                  merge the same way: ensemble.csv rows joined in run order, histograms.csv \
                  counts added, quantiles.csv, summary.json and the fan chart recomputed: \
                  the bytes of a one-shot run. So do the shards of a bit design map \
                  (tippetop bit --vary ... --shard K/N: bitmap.csv joined, plots redrawn) and \
                  of a bit ensemble (tippetop bit --runs N --shard K/M: runs.csv joined, \
                  bit.json, bit.md and the figure recomputed), and of a splitting (tippetop \
                  rare --method ams --shard K/M: the replicas joined, rare.json, rare.md and \
                  levels.png of the unsharded run, the same bytes apart from wall_seconds).";

/// Join the outputs of a sweep's (an ensemble's, a bit's, a splitting's) shards.
#[derive(Debug, Args)]
#[command(long_about = MERGE_LONG_ABOUT)]
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

    /// A built-in scenario to start from (help: every preset).
    #[arg(long, value_name = "NAME", help = tippetop::input::scenario::preset_help())]
    pub preset: Option<String>,

    /// Override one scenario value, e.g. `--set top.offset=0.002` or `--set
    /// surface.friction_law=contensou` (a name needs no quotes); repeatable,
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
