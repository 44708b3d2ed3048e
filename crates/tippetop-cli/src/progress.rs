//! Progress display on stderr with `indicatif`: hidden when stderr is not a
//! terminal or with `--quiet`, so logs and pipes stay clean.

use std::io::IsTerminal;
use std::time::Duration;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use tippetop::human;

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
/// [`tippetop::simulate_with_progress`]: a bar on a terminal (with the
/// simulated time); without one (a log, a batch job) a line every
/// [`LOG_EVERY_SECONDS`] seconds on stderr, `simulating: 1.2 % (t = 12.3 ms
/// of 1.00 s; 2.27 ms of run time per second, 7 min 15 s left at that
/// rate)`, so a long run shows it is alive and when it will end; nothing
/// with `--quiet`.
///
/// It also says, once per decade, when the run is running away, from the
/// state at every report (so the same run warns at the same place whatever
/// the machine): the spin has grown by decades since the first report, or
/// the mean step size has fallen by decades ([`tippetop::RunawayWatch`]); and,
/// from the wall clock, when the run advances ten times (a hundred, ...)
/// slower than over its first interval ([`slowdown_warning`]).
pub struct RunProgress {
    bar: ProgressBar,
    log: Option<LogSink>,
    every: Duration,
    t_end: f64,
    last_line: std::time::Instant,
    /// (wall time, fraction) at the last measured interval.
    last: (std::time::Instant, f64),
    /// Simulated seconds per wall second over the first interval.
    first_rate: Option<f64>,
    /// Decades of slow-down already reported.
    warned_decades: i32,
    /// The state's watch: the first report and the decades already said.
    runaway: tippetop::RunawayWatch,
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
        // A hidden bar draws nothing: its template is not parsed (~40 000
        // instructions, a tenth of a short run's start-up).
        if !quiet {
            bar.set_style(
                ProgressStyle::with_template(
                    "simulating [{bar:40}] {percent:>3} % {msg} [{elapsed} < {eta}]",
                )
                .expect("valid template")
                .progress_chars("=> "),
            );
        }
        let now = std::time::Instant::now();
        RunProgress {
            bar,
            log,
            every,
            t_end,
            last_line: now,
            last: (now, 0.0),
            first_rate: None,
            warned_decades: 0,
            runaway: tippetop::RunawayWatch::default(),
        }
    }

    /// The run has reached `p` (its fraction done, time, steps and spin).
    pub fn update(&mut self, p: &tippetop::Progress) {
        let fraction = p.fraction;
        self.bar.set_position((fraction * 1000.0) as u64);
        if let Some(w) = self.runaway.check(p) {
            self.say(&w);
        }
        let now = std::time::Instant::now();
        let wall = now.duration_since(self.last.0).as_secs_f64();
        if wall < self.every.as_secs_f64().max(1e-9) && !self.every.is_zero() {
            return;
        }
        // Simulated seconds per wall second over this interval.
        let rate = (fraction - self.last.1) * self.t_end / wall.max(1e-9);
        self.last = (now, fraction);
        self.bar.set_message(format!(
            "t = {} of {}",
            human::si(fraction * self.t_end, "s", 3),
            human::si(self.t_end, "s", 3)
        ));
        let first = *self.first_rate.get_or_insert(rate);
        let warning =
            slowdown_warning(first, rate, &mut self.warned_decades, fraction * self.t_end);
        if let Some(log) = &mut self.log {
            if self.last_line.elapsed() >= self.every || self.every.is_zero() {
                self.last_line = now;
                log(&log_line(fraction, self.t_end, rate));
            }
        }
        if let Some(w) = warning {
            self.say(&w);
        }
    }

    /// A warning line: in the log, or above the bar.
    fn say(&mut self, line: &str) {
        match &mut self.log {
            Some(log) => log(line),
            None => self.bar.println(line),
        }
    }

    /// Remove the bar.
    pub fn finish(self) {
        self.bar.finish_and_clear();
    }
}

/// The warning, once per decade, when the run's time advances 10^n times
/// slower than at first (`rate` against `first` \[s of run time / s\]).
fn slowdown_warning(first: f64, rate: f64, warned: &mut i32, t: f64) -> Option<String> {
    if !(first > 0.0 && rate.is_finite()) {
        return None;
    }
    let decades = if rate > 0.0 {
        (first / rate).log10().floor() as i32
    } else {
        *warned + 1
    };
    if decades <= *warned || decades < 1 {
        return None;
    }
    *warned = decades;
    let factor = format!("{:.0}", 10f64.powi(decades));
    Some(format!(
        "warning: at t = {} the run advances {factor}x slower than at its start ({} of run time per second, was {}): \
         its step size is falling by decades, as when the state runs away (a spin or a stiffness growing \
         without bound); it stops at solver.max_steps if it does not recover",
        human::si(t, "s", 3),
        human::si(rate, "s", 3),
        human::si(first, "s", 3)
    ))
}

/// The progress line for a log: `simulating: 43.0 % (t = 4.30 s of 10.0 s;
/// 1.20 s of run time per second, 4 s left at that rate)`.
pub fn log_line(fraction: f64, t_end: f64, rate: f64) -> String {
    let pct = 100.0 * fraction;
    let left = if rate > 0.0 {
        format!(
            "{} left at that rate",
            human::duration((1.0 - fraction) * t_end / rate)
        )
    } else {
        "no progress in this interval".into()
    };
    format!(
        "simulating: {} % (t = {} of {}; {} of run time per second, {left})",
        if pct < 10.0 {
            format!("{pct:.1}")
        } else {
            format!("{pct:.0}")
        },
        human::si(fraction * t_end, "s", 3),
        human::si(t_end, "s", 3),
        human::si(rate, "s", 3),
    )
}

#[cfg(test)]
mod tests {
    use std::{cell::RefCell, rc::Rc, time::Duration};

    /// Without a terminal the run logs a line per interval (here: every
    /// update), with the percentage, the simulated time, the rate and what
    /// is left; when the rate falls by a decade it warns, once per decade.
    #[test]
    fn run_progress_logs_lines_and_warns_of_a_slowdown() {
        let at = |fraction: f64| tippetop::Progress {
            fraction,
            t: 2.0 * fraction,
            steps: (fraction * 4.0) as u64 * 1000,
            spin: 100.0,
        };
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
        p.update(&at(0.25));
        p.update(&at(0.5));
        p.finish();
        let l = lines.borrow();
        assert_eq!(l.len(), 2, "{l:?}");
        assert!(
            l[0].starts_with("simulating: 25 % (t = 500 ms of 2.00 s; "),
            "{}",
            l[0]
        );
        assert!(
            l[1].starts_with("simulating: 50 % (t = 1.00 s of 2.00 s; "),
            "{}",
            l[1]
        );
        assert!(l[1].contains("of run time per second") && l[1].contains("left at that rate"));
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
        p.update(&at(0.5));
        assert!(lines.borrow().is_empty());
    }

    #[test]
    fn slowdown_warns_once_per_decade() {
        let mut warned = 0;
        assert!(super::slowdown_warning(1.0, 0.5, &mut warned, 1.0).is_none());
        let w = super::slowdown_warning(1.0, 0.09, &mut warned, 1.0).unwrap();
        assert!(
            w.starts_with("warning: at t = 1.00 s the run advances 10x slower"),
            "{w}"
        );
        assert!(super::slowdown_warning(1.0, 0.05, &mut warned, 2.0).is_none());
        let w = super::slowdown_warning(1.0, 0.001, &mut warned, 3.0).unwrap();
        assert!(w.contains("1000x slower"), "{w}");
        assert!(super::slowdown_warning(1.0, 0.0, &mut warned, 3.0).is_some());
    }

    /// [`super::RunProgress`] warns from the state at the report where the
    /// spin has grown tenfold since the first report, whatever the wall
    /// clock (no log line is due: the interval is an hour).
    #[test]
    fn run_progress_warns_of_a_runaway_from_the_state() {
        let lines = Rc::new(RefCell::new(Vec::<String>::new()));
        let sink = lines.clone();
        let mut p = super::RunProgress::with_log(
            true,
            1.0,
            Some(Box::new(move |l: &str| {
                sink.borrow_mut().push(l.to_string())
            })),
            Duration::from_secs(3600),
        );
        let report = |k: u64, spin: f64| tippetop::Progress {
            fraction: k as f64 * 1e-3,
            t: k as f64 * 1e-3,
            steps: k * 1000,
            spin,
        };
        p.update(&report(1, 1e7));
        p.update(&report(2, 5e7));
        assert!(lines.borrow().is_empty());
        p.update(&report(3, -1.1e8));
        assert_eq!(lines.borrow().len(), 1);
        assert!(
            lines.borrow()[0].contains("has grown 10x"),
            "{:?}",
            lines.borrow()
        );
        p.update(&report(4, 2e8));
        assert_eq!(lines.borrow().len(), 1);
    }

    #[test]
    fn log_line_reads_well() {
        assert_eq!(
            super::log_line(0.43, 10.0, 1.2),
            "simulating: 43 % (t = 4.30 s of 10.0 s; 1.20 s of run time per second, 5 s left at that rate)"
        );
        assert_eq!(
            super::log_line(0.012, 1.0, 2.27e-3),
            "simulating: 1.2 % (t = 12.0 ms of 1.00 s; 2.27 ms of run time per second, 7 min 15 s left at that rate)"
        );
    }
}
