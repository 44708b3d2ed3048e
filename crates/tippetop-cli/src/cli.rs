//! Command-line arguments (clap derive).

use std::path::PathBuf;

use clap::{ArgGroup, Args, Parser, Subcommand};

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
    /// and nothing is touched.
    #[arg(long, global = true)]
    pub force: bool,

    /// What to do.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run one scenario and write its trajectory, summary and plots.
    #[command(long_about = crate::cli::RUN_LONG_ABOUT)]
    Run(RunArgs),
    /// Reproduce the nano tippe-top paper's figures and numbers.
    #[command(
        long_about = "Reproduce the nano tippe-top paper's figures and numbers: runs \
                            the paper's scenarios (scenarios/*.toml, embedded) three ways (accurate \
                            with bilateral contact and exact Coulomb friction; the paper's literal \
                            law solved accurately; the paper's RK4 on 500 steps) and writes into \
                            --out: figNN.png/.svg/.csv for figures 02-15, report.md (every claim \
                            of the paper beside what we measured, with a verdict and why) and \
                            claims.json. --out is created, locked and checked before the runs \
                            (another tippetop command writing into it exits with code 1); the \
                            files are moved in together at the end, report.md last, and the \
                            files of the previous command into it that this one did not write \
                            (e.g. the ε-study figures of an earlier --extended) are removed."
    )]
    Reproduce(ReproduceArgs),
    /// Run a parameter sweep (a grid of scenarios) on all cores.
    #[command(long_about = crate::sweep_cmd::SWEEP_LONG_ABOUT)]
    Sweep(crate::sweep_cmd::SweepArgs),
    /// Run a Langevin scenario N times (an ensemble) and write statistics.
    #[command(long_about = crate::ensemble_cmd::ENSEMBLE_LONG_ABOUT)]
    Ensemble(crate::ensemble_cmd::EnsembleArgs),
    /// Join the outputs of a sweep's (an ensemble's, a bit's, a splitting's) shards.
    #[command(long_about = crate::sweep_cmd::MERGE_LONG_ABOUT)]
    Merge(crate::sweep_cmd::MergeArgs),
    /// Stability of the steady motions (θ = 0, π/2, π) beside the paper's App. B.
    Stability(crate::stability_cmd::StabilityArgs),
    /// Van der Waals adhesion of a fullerene on graphene or graphite (E_b, F_a).
    #[command(long_about = crate::adhesion_cmd::ADHESION_LONG_ABOUT)]
    Adhesion(crate::adhesion_cmd::AdhesionArgs),
    /// The regime a scenario is in: weight, adhesion, friction and thermal ratios.
    #[command(long_about = crate::regime_cmd::REGIME_LONG_ABOUT)]
    Regime(crate::regime_cmd::RegimeArgs),
    /// Retention time at a temperature, from ensembles' escape rates (Arrhenius).
    #[command(long_about = crate::retention_cmd::RETENTION_LONG_ABOUT)]
    Retention(crate::retention_cmd::RetentionArgs),
    /// A memory bit: write and erase protocols, success probabilities, switching times.
    #[command(long_about = crate::bit_cmd::BIT_LONG_ABOUT)]
    Bit(crate::bit_cmd::BitArgs),
    /// Can the nano tippe top be a memory bit? A report with numbers (minutes).
    #[command(long_about = crate::device_cmd::DEVICE_LONG_ABOUT)]
    Device(crate::device_cmd::DeviceArgs),
    /// Rare events: P(target before reset) or a mean first-passage time (exact 1D, direct, splitting).
    #[command(long_about = crate::rare_cmd::RARE_LONG_ABOUT)]
    Rare(Box<crate::rare_cmd::RareArgs>),
    /// Animate a run: DIR/animation.gif and DIR/viewer.html (a 3D view in the browser).
    #[command(long_about = crate::animate::ANIMATE_LONG_ABOUT)]
    Animate(crate::animate::AnimateArgs),
    /// Print a scenario resolved (preset, file, every --set) as TOML.
    Show(crate::show_cmd::ShowArgs),
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
        }
    }
}

/// Long help of `tippetop run`: the files, every `trajectory.csv` column
/// with its unit, the output directory's lock and manifest.
pub const RUN_LONG_ABOUT: &str = "Run one scenario and write into --out:
  trajectory.csv   one row per sample, the columns below
  summary.json     scalar results, events, wall time and the scenario
  scenario.toml    the resolved scenario, to run it again
  theta, spin, diagnostics (.png and .svg)   plots, unless --no-plot

trajectory.csv columns (SI units; angles in rad; frames in docs/physics.md):
  t              time [s]
  theta          nutation angle θ between the symmetry axis and the vertical [rad]
                 (0: standing on the heavy end, centre of mass lowest; pi: inverted)
  theta_dot      dθ/dt [rad/s]
  Omega          precession rate Ω = dφ/dt: how fast the direction of the axis's tilt
                 turns about the vertical (the precessing frame's rate) [rad/s]
  omega          spin ω, the angular velocity along the symmetry axis [rad/s]
  ux, uy         centre-of-mass velocity in the precessing frame: x horizontal towards
                 the tilt of the axis, y = Z × x [m/s]
  uz             centre-of-mass velocity, vertical [m/s]
  N              normal force of the plane on the top [N] (negative: the plane would
                 have to pull, i.e. a real top would lose contact)
  slip           slip speed |v_P| of the contact point on the plane [m/s]
  J              Jellett's quantity J = A Ω R sin²θ + C ω (R cos θ − a) [kg m³/s], with
                 A, C the moments of inertia (transverse, axial), R the radius, a the
                 offset of the centre of mass (conserved for any force at the
                 contact point: its drift measures the integration error)
  energy         total energy: translational + rotational kinetic + m g h, h the height
                 of the centre of mass above the plane [J]
  work_friction  work done by friction since t = 0 [J] (<= 0)
  work_applied   work done by the applied force since t = 0 [J]; energy - energy(0)
                 = work_friction + work_applied up to the integration error
  hx, hy         applied force H = (H_x, H_y) in effect, precessing frame [N] (a
                 retarding force: the force on the top at the contact point is -H)
  rolling        1 while rolling (exact Coulomb friction: slip held at zero) or stuck
                 (Coulomb-Contensou friction: slip and spin about the vertical held at
                 zero), else 0
  x, y           centre-of-mass position on the plane, lab frame [m]: Z up, the plane
                 at Z = 0, the origin below the centre of mass at t = 0, X the initial
                 heading (the axis tilts towards +X at t = 0)
  z              centre-of-mass height above the plane [m] (R − a cos θ in contact)
  qw, qx, qy, qz  attitude, unit quaternion body → lab (scalar first; the symmetry
                 axis is the body's third axis, k = q e3 q*; q = (cos θ/2, 0, sin θ/2, 0)
                 at t = 0) [1]
  xp, yp         contact point on the plane, lab frame [m]: the sphere's lowest point,
                 (x, y) + a (k_X, k_Y)

The scenario is the preset (if given), then the scenario file over it, then each --set in
order. Bad input exits with code 2 and touches nothing; a run that fails part-way writes what
it computed and exits with code 3.

The output directory: created if missing and checked (and locked, see below) before the
simulation starts, so an unwritable --out fails at once with code 1. While a run writes into
it, DIR/.tippetop.lock holds a lock: any other tippetop command writing into the same directory
exits at once with code 1 (\"DIR is in use by another tippetop process (pid N)\"); it does
not wait. The files are written aside and moved in together at the end, summary.json last;
then the files of the previous command into DIR (listed in DIR/.tippetop-manifest) that this
run did not write are removed, e.g. the plots after a --no-plot run. Files the tool did not
write are never touched. (The lock uses flock(2), on Unix; on a file system without locks the
command goes on with a warning.) The lock file is removed at the end, also on Ctrl-C (SIGINT),
SIGTERM or SIGHUP, with the files written aside; one left by a killed process is taken over.
Files in DIR are never written through a symbolic link: a link where the lock or a partial
file goes is bad input (exit code 2), and a link where a result goes is replaced, its target
left alone.";

/// `tippetop run`.
#[derive(Debug, Args)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop run --preset nano --out out/nano\n  \
                  tippetop run --preset classical --set solver.t_end=20 --no-plot --out out/long\n  \
                  tippetop run --preset classical --set solver.model=reduced --no-plot --out out/paper\n  \
                  tippetop run scenarios/my-top.toml --out out/mine\n\n\
                  Models (solver.model): \"vector\" (default) the physics of the paper's equations written\n\
                  without Euler angles: no singularity at theta = 0 or pi, 1.3-3.6x faster; \"reduced\" the\n\
                  paper's Euler-angle equations themselves (what reproduce runs; theta must stay in (0, pi));\n\
                  \"rigid\" full 3D body with flight and impacts (contact = \"unilateral\")."
)]
pub struct RunArgs {
    /// Scenario file (TOML).
    #[arg(value_name = "SCENARIO.toml")]
    pub scenario: Option<PathBuf>,

    /// Start from a built-in scenario: "nano" (C60, the paper's Sec. 3),
    /// "nano-physical" (the same C60 on graphene at 300 K: van der Waals
    /// adhesion, a stem's lying well, Langevin damping and noise, 1 ns,
    /// docs/physics.md#langevin), "nano-adhesive" (the same without temperature:
    /// adhesion and superlubric Coulomb friction, §adhesion) or "classical" (the
    /// 15 g toy of the paper's App. A).
    #[arg(long, value_name = "NAME")]
    pub preset: Option<String>,

    /// Override one scenario value, e.g. `--set top.offset=0.002`; repeatable,
    /// applied in order after the file.
    #[arg(long = "set", value_name = "TABLE.KEY=VALUE")]
    pub sets: Vec<String>,

    /// Output directory (created if missing; locked while the run writes;
    /// the previous run's files in it are replaced or removed; another
    /// subcommand's output there is refused unless --force). The default
    /// is run's own, beside `reproduce`'s `out/`.
    #[arg(long, value_name = "DIR", default_value = "out/run")]
    pub out: PathBuf,

    /// Write plots (the default).
    #[arg(long, overrides_with = "no_plot")]
    pub plot: bool,

    /// Do not write plots.
    #[arg(long, overrides_with = "plot")]
    pub no_plot: bool,
}

impl RunArgs {
    /// Whether to write plots (`--plot` unless `--no-plot` came last).
    pub fn plots(&self) -> bool {
        !self.no_plot
    }
}

/// `tippetop reproduce`.
#[derive(Debug, Args)]
#[command(after_help = "Examples:\n  \
                        tippetop reproduce --out out\n  \
                        tippetop reproduce --extended --quiet --out out/full")]
pub struct ReproduceArgs {
    /// Output directory for figures, data and the report (locked while
    /// writing; the previous command's files in it are replaced or removed).
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,

    /// Also run the extended studies beyond the paper (slower): the ε study
    /// of the friction law over 10 s and 150 s, the classical inversion
    /// maps, and the adhesion study (the nano scenarios with C60/graphene
    /// van der Waals adhesion).
    #[arg(long)]
    pub extended: bool,

    /// Shorten every window 10x: a smoke test of the pipeline (the verdicts
    /// are then meaningless and the report says so).
    #[arg(long)]
    pub quick: bool,
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn clap_definition_is_consistent() {
        Cli::command().debug_assert();
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
                assert_eq!(r.sets, ["a.b=1", "c.d=2"]);
                assert_eq!(r.out, PathBuf::from("out/run"));
            }
            _ => unreachable!(),
        }
    }
}
