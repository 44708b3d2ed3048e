//! `tippetop reproduce`: regenerate the figures and numbers of the nano
//! tippe-top paper into `--out`. Not yet implemented.

use anyhow::{Result, bail};

use crate::ReproduceArgs;

/// Reproduce the paper's results into `args.out` (`args.extended` adds the
/// extra studies). `quiet` silences everything but errors.
pub fn run(args: &ReproduceArgs, quiet: bool) -> Result<()> {
    let _ = (&args.out, args.extended, quiet);
    bail!("reproduce: not yet implemented")
}
