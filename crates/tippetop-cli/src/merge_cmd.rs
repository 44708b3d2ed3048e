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
