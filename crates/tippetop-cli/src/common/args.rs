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
