//! Command-line arguments (clap derive).

use clap::{Parser, Subcommand};

pub use crate::reproduce::ReproduceArgs;
pub use crate::run::RunArgs;

/// Top-level command line.
#[derive(Debug, Parser)]
#[command(
    name = "tippetop",
    version,
    about = "Simulate tippe tops: the classical toy and the C60 nano tippe top",
    long_about = "Simulate tippe-top dynamics (a spinning sphere with an offset centre of \
                  mass that turns itself upside down), from the 15 g toy to the C60 \
                  \"nano tippe top\", and reproduce the paper's results.",
    after_help = "Examples:\n  \
                  tippetop run --preset nano --out out/nano\n  \
                  tippetop run my-top.toml --set surface.friction=0.2 --out out/mine\n  \
                  tippetop reproduce --out out\n  \
                  tippetop animate out/nano   (then open out/nano/viewer.html in a browser)\n\n\
                  Exit codes: 0 ok, 1 other failure (e.g. I/O), 2 bad input, 3 the run failed."
)]
pub struct Cli {
    /// Print nothing but errors (no progress, no summary).
    #[arg(long, short, global = true)]
    pub quiet: bool,

    /// Let this command replace the output another subcommand wrote into
    /// --out (its files are removed). Without it, that is refused (exit 2)
    /// and nothing is touched. Refused by the commands that write no files
    /// (stability, adhesion, regime, show, keys).
    #[arg(long, global = true)]
    pub force: bool,

    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands. Their arguments are built only for the subcommand
/// typed (`defer`): building all fifteen was more than half of a run's
/// start-up in user space (docs/performance.md, "The speed gate"). A
/// subcommand's one-line description is set twice, here (read before it
/// is built: `tippetop --help`'s list) and as its argument struct's doc
/// comment (applied when it is built, over this one), kept equal by a
/// test; its long description (`long_about`) only on the struct, so that
/// a run does not copy the other fourteen.
#[derive(Debug, Subcommand)]
#[command(defer = true)]
pub enum Command {
    /// Run one scenario and write its trajectory, summary and plots.
    Run(RunArgs),
    /// Reproduce the nano tippe-top paper's figures and numbers.
    Reproduce(ReproduceArgs),
    /// Run a parameter sweep (a grid of scenarios) on all cores.
    Sweep(crate::sweep_cmd::SweepArgs),
    /// Run a Langevin scenario N times (an ensemble) and write statistics.
    Ensemble(crate::ensemble_cmd::EnsembleArgs),
    /// Join the outputs of a sweep's (an ensemble's, a bit's, a splitting's) shards.
    Merge(crate::common::args::MergeArgs),
    /// Stability of the steady motions (θ = 0, π/2, π) beside the paper's App. B.
    Stability(crate::stability_cmd::StabilityArgs),
    /// Van der Waals adhesion of a fullerene on graphene or graphite (E_b, F_a).
    Adhesion(crate::adhesion_cmd::AdhesionArgs),
    /// The regime a scenario is in: weight, adhesion, friction and thermal ratios.
    Regime(crate::regime_cmd::RegimeArgs),
    /// Retention time at a temperature, from ensembles' escape rates (Arrhenius).
    Retention(crate::retention_cmd::RetentionArgs),
    /// A memory bit: write and erase protocols, success probabilities, switching times.
    Bit(crate::bit_args::BitArgs),
    /// Can the nano tippe top be a memory bit? A report with numbers (minutes).
    Device(crate::device_cmd::DeviceArgs),
    /// Rare events: P(target before reset) or a mean first-passage time (exact 1D, direct, splitting).
    Rare(Box<crate::rare_cmd::RareArgs>),
    /// Animate a run: DIR/animation.gif and DIR/viewer.html (a 3D view in the browser).
    Animate(crate::animate::AnimateArgs),
    /// Print a scenario resolved (preset, file, every --set) as TOML.
    Show(crate::show_cmd::ShowArgs),
    /// Every scenario key: unit, default, range and what it is (docs/keys.md).
    Keys(crate::keys_cmd::KeysArgs),
}

/// Help pages start with the usage line, then the description and the
/// options (clap puts the usage after a long description).
const HELP_TEMPLATE: &str =
    "{usage-heading} {usage}\n\n{about-with-newline}\n{all-args}{after-help}";

/// The command line's definition ([`Cli`]) with every help page starting
/// with its usage line.
pub fn command() -> clap::Command {
    use clap::CommandFactory;
    fn usage_first(c: clap::Command) -> clap::Command {
        let names: Vec<String> = c
            .get_subcommands()
            .map(|s| s.get_name().to_string())
            .collect();
        let mut c = c.help_template(HELP_TEMPLATE);
        for n in names {
            c = c.mut_subcommand(n, usage_first);
        }
        c
    }
    usage_first(Cli::command())
}

impl Command {
    /// Whether the subcommand writes files (it has an output directory):
    /// `--force` means something only for these.
    pub fn writes_files(&self) -> bool {
        !matches!(
            self,
            Command::Stability(_)
                | Command::Adhesion(_)
                | Command::Regime(_)
                | Command::Show(_)
                | Command::Keys(_)
        )
    }

    /// `--force` given to a subcommand that writes no files: the one-line
    /// message of the refusal (exit 2), else `None`.
    pub fn force_refused(&self, force: bool) -> Option<String> {
        (force && !self.writes_files()).then(|| {
            format!(
                "--force: `tippetop {}` writes no files, so there is no output for --force to replace (leave it out)",
                self.name()
            )
        })
    }

    /// The subcommand's name, as typed (`run`, `sweep`, ...).
    pub fn name(&self) -> &'static str {
        match self {
            Command::Run(_) => "run",
            Command::Reproduce(_) => "reproduce",
            Command::Sweep(_) => "sweep",
            Command::Ensemble(_) => "ensemble",
            Command::Merge(_) => "merge",
            Command::Stability(_) => "stability",
            Command::Adhesion(_) => "adhesion",
            Command::Regime(_) => "regime",
            Command::Retention(_) => "retention",
            Command::Animate(_) => "animate",
            Command::Bit(_) => "bit",
            Command::Device(_) => "device",
            Command::Rare(_) => "rare",
            Command::Show(_) => "show",
            Command::Keys(_) => "keys",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;
    use std::path::PathBuf;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    /// Each subcommand's one-line description is the same before its
    /// deferred arguments are built (the variant's doc, what `tippetop
    /// --help` lists) and after (its argument struct's doc comment, what
    /// `tippetop SUB --help` prints); its long description is set only when
    /// it is built.
    #[test]
    fn deferred_subcommands_keep_their_descriptions() {
        let described = |c: &clap::Command| -> Vec<(String, String)> {
            c.get_subcommands()
                .map(|s| {
                    let about = s.get_about().map(|t| t.to_string()).unwrap_or_default();
                    (s.get_name().to_string(), about)
                })
                .collect()
        };
        let before = Cli::command();
        assert!(
            before
                .find_subcommand("run")
                .is_some_and(|s| s.get_arguments().next().is_none()),
            "the subcommands' arguments are not deferred"
        );
        let mut built = Cli::command();
        built.build();
        assert!(
            built
                .find_subcommand("run")
                .is_some_and(|s| s.get_arguments().next().is_some())
        );
        assert!(
            before
                .get_subcommands()
                .all(|s| s.get_long_about().is_none())
        );
        assert!(
            built
                .find_subcommand("run")
                .is_some_and(|s| s.get_long_about().is_some())
        );
        let (before, after) = (described(&before), described(&built));
        assert_eq!(before.len(), 15);
        for (b, a) in before.iter().zip(&after) {
            assert_eq!(b, a, "subcommand {}: description changed when built", b.0);
            assert!(!b.1.is_empty(), "subcommand {} has no description", b.0);
        }
    }

    #[test]
    fn plot_flags_last_wins() {
        let parse = |a: &[&str]| match Cli::try_parse_from(a).unwrap().command {
            Command::Run(r) => r.plots(),
            _ => unreachable!(),
        };
        assert!(parse(&["tippetop", "run", "--preset", "nano"]));
        assert!(!parse(&[
            "tippetop",
            "run",
            "--preset",
            "nano",
            "--no-plot"
        ]));
        assert!(parse(&[
            "tippetop",
            "run",
            "--preset",
            "nano",
            "--no-plot",
            "--plot"
        ]));
        assert!(!parse(&[
            "tippetop",
            "run",
            "--preset",
            "nano",
            "--plot",
            "--no-plot"
        ]));
    }

    #[test]
    fn quiet_is_global_and_source_required() {
        assert!(
            Cli::try_parse_from(["tippetop", "run", "--preset", "nano", "--quiet"])
                .unwrap()
                .quiet
        );
        assert!(
            Cli::try_parse_from(["tippetop", "-q", "reproduce"])
                .unwrap()
                .quiet
        );
        assert!(
            Cli::try_parse_from(["tippetop", "reproduce", "--quiet"])
                .unwrap()
                .quiet
        );
        assert!(Cli::try_parse_from(["tippetop", "run", "--out", "x"]).is_err());
        let c = Cli::try_parse_from([
            "tippetop", "run", "a.toml", "--preset", "nano", "--set", "a.b=1", "--set", "c.d=2",
        ])
        .unwrap();
        match c.command {
            Command::Run(r) => {
                assert_eq!(r.source.sets, ["a.b=1", "c.d=2"]);
                assert_eq!(r.out, PathBuf::from("out/run"));
            }
            _ => unreachable!(),
        }
    }
}
