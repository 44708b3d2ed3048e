//! `tippetop merge`: joins the output directories of the shards of one
//! sweep, ensemble, bit design map, bit ensemble or splitting. Each kind
//! of shard is registered in [`TARGETS`] with the test that tells its
//! directories and its merge; the subcommands' modules know nothing of
//! this one.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;

use crate::common::args::MergeArgs;
use crate::common::same_dir;
use crate::scenario_load::input_error;
use crate::{bit_cmd, bitmap_cmd, ensemble_cmd, rare_cmd, sweep_cmd};

/// Long help of `tippetop merge` (set on the subcommand in `cli.rs`).
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

/// A kind of shard directory `tippetop merge` joins.
pub struct Target {
    /// The subcommand that writes such shards.
    pub writer: &'static str,
    /// Whether a directory is such a shard (the first input decides).
    pub is_shard: fn(&Path) -> bool,
    /// Its merge (bad input: exit code 2 returned as `Ok`).
    pub merge: fn(&MergeArgs, bool) -> Result<ExitCode>,
}

/// The kinds of shard, asked in this order; the last, a sweep's, takes
/// whatever the others did not claim (its messages say what a sweep's
/// shard lacks).
pub const TARGETS: &[Target] = &[
    Target {
        writer: "ensemble",
        is_shard: ensemble_cmd::is_ensemble_dir,
        merge: ensemble_cmd::merge,
    },
    Target {
        writer: "bit --vary",
        is_shard: bitmap_cmd::is_bitmap_dir,
        merge: bitmap_cmd::merge,
    },
    Target {
        writer: "rare",
        is_shard: rare_cmd::is_rare_shard_dir,
        merge: rare_cmd::merge,
    },
    Target {
        writer: "bit",
        is_shard: bit_cmd::is_bit_shard_dir,
        merge: bit_cmd::merge,
    },
    Target {
        writer: "sweep",
        is_shard: |_| true,
        merge: sweep_cmd::merge,
    },
];

/// Run `tippetop merge`. Bad input (an --out that cannot be written or is
/// one of the shards, and whatever the shards' merge refuses): one line
/// on stderr and exit code 2 (returned as `Ok`), nothing written; `Err`
/// for I/O failures while writing.
pub fn run(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    if let Err(e) = crate::output::check_out_dir(&args.out) {
        return Ok(input_error(e));
    }
    // --out must not be one of the inputs: the merge would replace the
    // shard it reads.
    if let Some(d) = args.dirs.iter().find(|d| same_dir(d, &args.out)) {
        return Ok(input_error(format!(
            "--out: {} is {}, one of the shard directories merge reads (a directory that is \
             not one of them)",
            args.out.display(),
            d.display()
        )));
    }
    let sweep = &TARGETS[TARGETS.len() - 1];
    let target = args
        .dirs
        .first()
        .and_then(|d| TARGETS.iter().find(|t| (t.is_shard)(d)))
        .unwrap_or(sweep);
    (target.merge)(args, quiet)
}
