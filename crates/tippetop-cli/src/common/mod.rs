//! Helpers the subcommands share. Nothing here names a subcommand's
//! module: the subcommands depend on `common`, never the other way round
//! (the architecture test in `crates/tippetop/tests/architecture.rs`
//! checks that no two files depend on each other).
//!
//! - [`args`]: arguments several subcommands take (flattened into their
//!   argument structs with `#[command(flatten)]`), and `merge`'s, which
//!   every kind of shard's merge reads;
//! - [`grid`]: the shards of grid commands (`sweep`, `bit --vary`, the
//!   ensembles): streaming rows with `--resume`, `shard.json`;
//! - [`time_unit`], [`same_dir`].

use std::path::Path;

pub mod args;
pub mod grid;

/// A time axis in readable units: the factor to multiply seconds by, and the
/// unit's name (s, ms, µs, ns).
pub fn time_unit(t_max: f64) -> (f64, &'static str) {
    let t = t_max.abs();
    if t >= 1.0 || !t.is_finite() || t == 0.0 {
        (1.0, "s")
    } else if t >= 1e-3 {
        (1e3, "ms")
    } else if t >= 1e-6 {
        (1e6, "µs")
    } else {
        (1e9, "ns")
    }
}

/// Whether `a` and `b` name the same existing directory.
pub fn same_dir(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
