//! The `tippetop` command line: run scenarios and reproduce the nano
//! tippe-top paper.
//!
//! Exit codes: 0 ok; 1 other failures (I/O, plotting); 2 bad input (one
//! line `error: KEY: WHAT (RANGE)` on stderr, nothing written; a command
//! line clap cannot parse is one line too, `error: WHAT (see tippetop SUB
//! --help)`); 3 the run failed part-way (results up to the failure
//! written, `error: ...` on stderr).

use std::process::ExitCode;

use clap::{CommandFactory, FromArgMatches};
use tippetop_cli::cli::{Cli, Command};
use tippetop_cli::{
    adhesion_cmd, animate, bit_cmd, device_cmd, ensemble_cmd, keys_cmd, merge_cmd, rare_cmd,
    regime_cmd, reproduce, retention_cmd, run, show_cmd, stability_cmd, sweep_cmd,
};

fn main() -> ExitCode {
    // Behave like a Unix filter when the reader goes away (`tippetop ... | head`):
    // die quietly on SIGPIPE instead of panicking on a failed print.
    #[cfg(unix)]
    // SAFETY: setting a signal disposition to the default at start-up, before
    // any thread exists.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // The plain definition parses; the one whose help pages start with
    // their usage line (`cli::command`, ~0.2 M instructions to build, a
    // third of a run's start-up) only renders a help page.
    let matches = match Cli::command().try_get_matches() {
        Err(e) if is_help(&e) => tippetop_cli::cli::command().try_get_matches(),
        other => other,
    };
    let cli = match matches.and_then(|m| Cli::from_arg_matches(&m)) {
        Ok(cli) => cli,
        Err(e) => return usage_error(&e),
    };
    // Fault injection for the end-to-end tests of the rule "finite or
    // failed" (tippetop::testing): every output row from this time on [s]
    // gets qw = NaN.
    if let Some(at) = std::env::var("TIPPETOP_TEST_NAN_ROW_AT")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
    {
        tippetop::testing::plant_nan_row(Some(at));
    }
    if let Some(msg) = cli.command.force_refused(cli.force) {
        eprintln!("error: {msg}");
        return ExitCode::from(2);
    }
    tippetop_cli::output::set_invocation(cli.command.name(), cli.force);
    let result = match &cli.command {
        Command::Run(args) => run::run(args, cli.quiet).map(|()| ExitCode::SUCCESS),
        Command::Reproduce(args) => reproduce::run(args, cli.quiet).map(|()| ExitCode::SUCCESS),
        Command::Sweep(args) => sweep_cmd::sweep(args, cli.quiet),
        Command::Ensemble(args) => ensemble_cmd::ensemble(args, cli.quiet),
        Command::Merge(args) => merge_cmd::run(args, cli.quiet),
        Command::Stability(args) => stability_cmd::run(args, cli.quiet),
        Command::Adhesion(args) => adhesion_cmd::run(args),
        Command::Regime(args) => regime_cmd::run(args),
        Command::Retention(args) => retention_cmd::run(args, cli.quiet),
        Command::Animate(args) => animate::run(args, cli.quiet),
        Command::Bit(args) => bit_cmd::run(args, cli.quiet),
        Command::Device(args) => device_cmd::run(args, cli.quiet),
        Command::Rare(args) => rare_cmd::run(args, cli.quiet),
        Command::Show(args) => Ok(show_cmd::run(args)),
        Command::Keys(args) => Ok(keys_cmd::run(args)),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            let (code, msg) = classify(&e);
            eprintln!("error: {msg}");
            ExitCode::from(code)
        }
    }
}

/// A command line clap cannot parse: one line `error: WHAT[; tip: ...]
/// (see tippetop SUB --help)` on stderr, exit code 2, as every other bad
/// input. `--help`, `--version` (and the help a bare `tippetop` prints)
/// are clap's own, on stdout with exit code 0 (stderr, 2 for the bare
/// command).
fn usage_error(e: &clap::Error) -> ExitCode {
    if is_help(e) || e.kind() == clap::error::ErrorKind::DisplayVersion {
        e.exit();
    }
    let names: Vec<String> = Cli::command()
        .get_subcommands()
        .map(|c| c.get_name().to_string())
        .collect();
    let sub = std::env::args()
        .skip(1)
        .find(|a| names.contains(a))
        .map(|s| format!("tippetop {s} --help"))
        .unwrap_or_else(|| "tippetop --help".into());
    eprintln!(
        "error: {} (see {sub})",
        usage_message(&e.render().to_string())
    );
    ExitCode::from(2)
}

/// True if clap's "error" is a help page to print.
fn is_help(e: &clap::Error) -> bool {
    use clap::error::ErrorKind;
    matches!(
        e.kind(),
        ErrorKind::DisplayHelp | ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand
    )
}

/// The message of a clap error as one line: its `error:` line and its
/// `tip:` lines, without the usage and the pointer to `--help`.
fn usage_message(rendered: &str) -> String {
    let mut parts = Vec::new();
    for line in rendered.lines().map(str::trim) {
        if let Some(m) = line.strip_prefix("error:") {
            parts.push(m.trim().to_string());
        } else if line.starts_with("tip:") {
            parts.push(line.to_string());
        } else if line.starts_with("Usage:") || line.starts_with("For more information") {
            break;
        }
    }
    one_line(&parts.join("; "))
}

/// Exit code and one-line message for an error: 2 for bad input, 3 for a
/// run-time failure of the simulation, 1 for anything else.
fn classify(e: &anyhow::Error) -> (u8, String) {
    let (code, msg) = match e.downcast_ref::<tippetop::Error>() {
        Some(te) if te.is_input() => (2, te.to_string()),
        Some(te) => (3, format!("run failed {te}")),
        None => (1, format!("{e:#}")),
    };
    (code, one_line(&msg))
}

/// Collapse any line breaks so the message is exactly one line.
fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;
    use anyhow::Context;

    #[test]
    fn exit_codes() {
        let input = tippetop::Error::invalid(
            "top.radius",
            "-1 is not allowed".into(),
            "a finite number > 0".into(),
        );
        let (code, msg) = classify(&input.clone().into());
        assert_eq!(
            (code, msg.as_str()),
            (2, "top.radius: -1 is not allowed (a finite number > 0)")
        );
        // Context does not hide the library error.
        let wrapped = Err::<(), _>(input).context("loading").unwrap_err();
        assert_eq!(classify(&wrapped).0, 2);
        let rt = tippetop::Error::runtime(
            1.5e-3,
            tippetop::Failure::StepUnderflow,
            "step size underflow",
        );
        let (code, msg) = classify(&rt.into());
        assert_eq!(code, 3);
        assert!(msg.starts_with("run failed at t = "), "{msg}");
        let other = anyhow::anyhow!("disk full\nreally");
        assert_eq!(classify(&other), (1, "disk full really".to_string()));
    }
}
