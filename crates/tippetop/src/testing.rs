//! Fault injection for tests of the run's post-conditions (not for use in
//! programs). The driver promises that a run is *finite or failed*: a
//! completed run has no output row with a value that is not a finite
//! number, and a run whose row is not finite fails (`non_finite`) at that
//! row, keeping the rows before it. No input is known to break that
//! promise today (the fuzz harnesses look for one), so the check is tested
//! by planting a NaN: [`plant_nan_row`] makes the driver write NaN into the
//! `qw` column (`J` in a run without the pose, whose `qw` is not computed:
//! `simulate_with_pose`) of every output row at or after a time, in every run of the
//! process from then on (sweeps, ensembles and bit runs included). The
//! `tippetop` binary sets it from the environment variable
//! `TIPPETOP_TEST_NAN_ROW_AT` (seconds) for its end-to-end tests.

use std::sync::atomic::{AtomicU64, Ordering};

use crate::Sample;

/// A fixed sequence of numbers in [0, 1) for the tests (xorshift64, the
/// top 53 bits): the same numbers on every machine, from `seed` (not 0).
#[cfg(test)]
pub(crate) fn uniform_sequence(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// The planted time's bits (seconds); NaN's bits: nothing planted.
static NAN_ROW_AT: AtomicU64 = AtomicU64::new(f64::NAN.to_bits());

/// From now on, every output row at `t >= at` \[s\] of every run in this
/// process gets `qw = NaN`; `None` stops it. For tests only (it is
/// process-wide: a test that uses it should be alone in its binary).
pub fn plant_nan_row(at: Option<f64>) {
    NAN_ROW_AT.store(at.unwrap_or(f64::NAN).to_bits(), Ordering::Relaxed);
}

/// The row as the driver records it: `row` itself unless a NaN is planted
/// at or before its time.
#[inline]
pub(crate) fn planted(mut row: Sample) -> Sample {
    let at = f64::from_bits(NAN_ROW_AT.load(Ordering::Relaxed));
    if row.t >= at {
        // A row without the pose (its `qw` NaN already, not computed:
        // `simulate::simulate_with_pose`) gets it in `J`.
        if row.qw.is_nan() {
            row.jellett = f64::NAN;
        } else {
            row.qw = f64::NAN;
        }
    }
    row
}
