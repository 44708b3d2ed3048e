//! The `tippetop` command line.
//!
//! TEMP wiring of `sweep` and `merge` on the sweep branch, for its CLI tests;
//! the real main.rs (run, reproduce, ...) lives on the cli branch.

use std::process::ExitCode;

use clap::{Parser, Subcommand};

mod sweep_cmd;

/// Top-level command line.
#[derive(Debug, Parser)]
#[command(name = "tippetop", version, about = "Simulate tippe tops")]
struct Cli {
    /// Print nothing but errors (no progress, no summary).
    #[arg(long, short, global = true)]
    quiet: bool,

    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run a parameter sweep (a grid of scenarios) on all cores.
    Sweep(sweep_cmd::SweepArgs),
    /// Join the outputs of a sweep's shards.
    Merge(sweep_cmd::MergeArgs),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Sweep(args) => sweep_cmd::sweep(args, cli.quiet),
        Command::Merge(args) => sweep_cmd::merge(args, cli.quiet),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!(
                "error: {}",
                format!("{e:#}")
                    .split_whitespace()
                    .collect::<Vec<_>>()
                    .join(" ")
            );
            ExitCode::FAILURE
        }
    }
}
