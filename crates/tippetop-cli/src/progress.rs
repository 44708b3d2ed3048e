//! Progress display on stderr with `indicatif`: hidden when stderr is not a
//! terminal or with `--quiet`, so logs and pipes stay clean.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// True when progress should be drawn: not `quiet` and stderr is a terminal.
pub fn visible(quiet: bool) -> bool {
    !quiet && std::io::stderr().is_terminal()
}

/// A ticking spinner with `message` (for work without a progress callback).
/// Call `finish_and_clear()` when done.
pub fn spinner(quiet: bool, message: impl Into<String>) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(None, target(quiet));
    pb.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .expect("valid template")
            .tick_chars("⠋⠙⠹⠸⠼⠴⠦⠧⠇⠏ "),
    );
    pb.set_message(message.into());
    if visible(quiet) {
        pb.enable_steady_tick(Duration::from_millis(100));
    }
    pb
}

/// A bar over `len` units of work with `message` (e.g. runs of a sweep).
pub fn bar(quiet: bool, len: u64, message: impl Into<String>) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(len), target(quiet));
    pb.set_style(
        ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} [{elapsed} < {eta}]")
            .expect("valid template")
            .progress_chars("=> "),
    );
    pb.set_message(message.into());
    pb
}

fn target(quiet: bool) -> ProgressDrawTarget {
    if visible(quiet) {
        ProgressDrawTarget::stderr()
    } else {
        ProgressDrawTarget::hidden()
    }
}
