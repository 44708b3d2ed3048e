//! The `tippetop` command line as a library: argument definitions, the
//! subcommands, and the output helpers (CSV/JSON writers, plots, progress)
//! that `reproduce` and sweeps build on. The binary is `src/main.rs`.

#![warn(missing_docs)]

pub mod adhesion_cmd;
pub mod animate;
pub mod bit_args;
pub mod bit_cmd;
pub mod bitmap_cmd;
pub mod cli;
pub mod common;
pub mod device_cmd;
pub mod ensemble_cmd;
pub mod keys_cmd;
pub mod merge_cmd;
pub mod output;
pub mod partial;
pub mod plot;
pub mod progress;
pub mod rare_cmd;
pub mod regime_cmd;
pub mod reproduce;
pub mod retention_cmd;
pub mod run;
pub mod scenario_load;
pub mod search_cmd;
pub mod show_cmd;
pub mod stability_cmd;
pub mod sweep_cmd;

pub use cli::{Cli, Command, ReproduceArgs, RunArgs};
