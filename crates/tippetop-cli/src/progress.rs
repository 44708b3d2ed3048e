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

/// Seconds between two progress lines on a stderr that is not a terminal.
pub const LOG_EVERY_SECONDS: u64 = 10;

/// Where the log lines of [`RunProgress`] go.
type LogSink = Box<dyn FnMut(&str)>;

/// Progress of one simulation, fed by
/// [`tippetop::simulate_with_progress`]: a bar on a terminal; without one
/// (a log, a batch job) a line `simulating: 43 % (t = 4.3 s of 10 s)` on
/// stderr every [`LOG_EVERY_SECONDS`] seconds, so a long run shows it is
/// alive; nothing with `--quiet`.
pub struct RunProgress {
    bar: ProgressBar,
    log: Option<LogSink>,
    every: Duration,
    t_end: f64,
    last_line: std::time::Instant,
}

impl RunProgress {
    /// Progress of a run to `t_end` \[s\].
    pub fn new(quiet: bool, t_end: f64) -> Self {
        let log: Option<LogSink> = if !quiet && !std::io::stderr().is_terminal() {
            Some(Box::new(|line: &str| eprintln!("{line}")))
        } else {
            None
        };
        Self::with_log(quiet, t_end, log, Duration::from_secs(LOG_EVERY_SECONDS))
    }

    /// As [`RunProgress::new`], with the log lines sent to `log` (if any)
    /// at most once per `every`.
    fn with_log(quiet: bool, t_end: f64, log: Option<LogSink>, every: Duration) -> Self {
        let bar = ProgressBar::with_draw_target(Some(1000), target(quiet));
        bar.set_style(
            ProgressStyle::with_template(
                "simulating [{bar:40}] {percent:>3} % [{elapsed} < {eta}]",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        RunProgress {
            bar,
            log,
            every,
            t_end,
            last_line: std::time::Instant::now(),
        }
    }

    /// The run has done `fraction` (in `[0, 1]`) of its time span.
    pub fn update(&mut self, fraction: f64) {
        self.bar.set_position((fraction * 1000.0) as u64);
        if let Some(log) = &mut self.log {
            if self.last_line.elapsed() >= self.every {
                self.last_line = std::time::Instant::now();
                log(&log_line(fraction, self.t_end));
            }
        }
    }

    /// Remove the bar.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

/// The progress line for a log: `simulating: 43 % (t = 4.3 s of 10 s)`.
pub fn log_line(fraction: f64, t_end: f64) -> String {
    format!(
        "simulating: {:.0} % (t = {:.4e} s of {t_end} s)",
        100.0 * fraction,
        fraction * t_end
    )
}

#[cfg(test)]
mod tests {
    use std::{cell::RefCell, rc::Rc, time::Duration};

    /// Without a terminal the run logs a line per interval (here: every
    /// update), with the percentage and the simulated time.
    #[test]
    fn run_progress_logs_lines() {
        let lines = Rc::new(RefCell::new(Vec::<String>::new()));
        let sink = lines.clone();
        let mut p = super::RunProgress::with_log(
            true,
            2.0,
            Some(Box::new(move |l: &str| {
                sink.borrow_mut().push(l.to_string())
            })),
            Duration::ZERO,
        );
        p.update(0.25);
        p.update(0.5);
        p.finish();
        assert_eq!(
            *lines.borrow(),
            [
                "simulating: 25 % (t = 5.0000e-1 s of 2 s)",
                "simulating: 50 % (t = 1.0000e0 s of 2 s)"
            ]
        );
        // A long interval: nothing yet.
        let lines = Rc::new(RefCell::new(Vec::<String>::new()));
        let sink = lines.clone();
        let mut p = super::RunProgress::with_log(
            true,
            2.0,
            Some(Box::new(move |l: &str| {
                sink.borrow_mut().push(l.to_string())
            })),
            Duration::from_secs(3600),
        );
        p.update(0.5);
        assert!(lines.borrow().is_empty());
    }

    #[test]
    fn log_line_reads_well() {
        assert_eq!(
            super::log_line(0.43, 10.0),
            "simulating: 43 % (t = 4.3000e0 s of 10 s)"
        );
    }
}
