//! `tippetop regime`: the dimensionless ratios that say which physics a
//! scenario's regime needs (`tippetop::analysis::regime`), as a table with
//! a verdict per line or as JSON.

use std::process::ExitCode;

use tippetop::{Scenario, analysis::regime};

/// Long help of `tippetop regime`.
pub const REGIME_LONG_ABOUT: &str = "The regime a scenario is in: dimensionless ratios from \
    its parameters and initial state, each with a verdict. adhesion_over_weight F_a/(m g) \
    (F_a from the [adhesion] table; null without adhesion); applied_over_weight max|H|/(m g); \
    applied_over_friction_capacity max|H|/(mu (m g + F_a)); and with --temperature T: \
    rotational_energy_over_kT (1/2 C omega0^2 / kT), spin_over_thermal_spin (|omega0| / \
    sqrt(kT/C)), window_over_orientation_correlation_time (t_end / 9.1 ps, the C60 \
    orientation correlation time near room temperature); always angular_momentum_over_hbar \
    (C |omega0| / hbar; below 10 classical rotation is questionable). summary.json of every \
    run carries the same object at the run's own temperature (thermal entries null without \
    one). docs/physics.md#regime has the \
    constants and sources.\n\n\
    Exit codes: 0 ok, 2 bad input (one line naming the key and its range).";

/// The regime a scenario is in: weight, adhesion, friction and thermal ratios.
#[derive(Debug, Clone, clap::Args)]
#[command(long_about = REGIME_LONG_ABOUT)]
#[command(after_help = "Examples:\n  \
                  tippetop regime --preset nano --temperature 300\n  \
                  tippetop regime scenarios/nano.toml --temperature 4 --json\n  \
                  tippetop regime --preset classical")]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML); or give --preset")),
    mut_arg("sets", |a| a.help("Override a scenario key, e.g. --set initial.spin=3e7 (repeatable)")),
)]
pub struct RegimeArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,
    /// Temperature for the thermal ratios [K], 0 to 1e5 (default: the
    /// scenario's thermal.temperature if it has one).
    #[arg(long, allow_negative_numbers = true)]
    pub temperature: Option<f64>,
    /// Print JSON.
    #[arg(long)]
    pub json: bool,
}

fn load(args: &RegimeArgs) -> Result<Scenario, tippetop::Error> {
    let sc = crate::scenario_load::from_args(
        args.source.scenario.as_deref(),
        args.source.preset.as_deref(),
        &args.source.sets,
    )?;
    sc.validate()?;
    Ok(sc)
}

/// Run `tippetop regime`: exit 0, or 2 with one line for bad input.
pub fn run(args: &RegimeArgs) -> anyhow::Result<ExitCode> {
    let rep = load(args).and_then(|sc| {
        // Without --temperature, a scenario with a temperature (a Langevin
        // or Brownian run) gives its own.
        let r = match args.temperature {
            Some(t) => regime::regime(&sc, Some(t)),
            None => Ok(regime::of_run(&sc)),
        }
        .map_err(|e| match e {
            tippetop::Error::Invalid { key, what, range } if key == "temperature" => {
                tippetop::Error::Invalid {
                    key: "--temperature".into(),
                    what,
                    range,
                }
            }
            other => other,
        })?;
        Ok((sc, r))
    });
    let (sc, rep) = match rep {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(2));
        }
    };
    if args.json {
        crate::output::print_json(&rep)?;
        return Ok(ExitCode::SUCCESS);
    }
    match rep.temperature {
        Some(t) => println!("regime at T = {t} K"),
        None => println!("regime without temperature (--temperature K for the thermal ratios)"),
    }
    for l in regime::lines(&sc, &rep) {
        let v = match l.value {
            Some(v) => tippetop::human::sig(v, 4),
            None => "null".into(),
        };
        println!("{:<42} {:>10}  {}", l.key, v, l.verdict);
    }
    Ok(ExitCode::SUCCESS)
}
