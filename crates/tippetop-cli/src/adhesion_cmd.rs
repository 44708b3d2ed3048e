//! `tippetop adhesion`: the van der Waals binding of a fullerene on graphene
//! or graphite in the continuum Lennard-Jones approximation
//! (`tippetop::physics::adhesion`): binding energy, equilibrium height,
//! pull-off force, stiffness, and how they compare with the weight.

use std::process::ExitCode;

use serde::Serialize;
use tippetop::physics::adhesion::{ANGSTROM, Adhesion, EV, LjConstants, Shell, Substrate};

/// Long help of `tippetop adhesion`.
pub const ADHESION_LONG_ABOUT: &str = "The van der Waals adhesion of a fullerene cage on \
    graphene or graphite, from continuum Lennard-Jones integrals (the atoms smeared over the \
    cage and the sheets): the binding energy E_b, the equilibrium height, the pull-off force \
    F_a (the largest attraction a pull must overcome), the normal stiffness and the vertical \
    vibration frequency, and F_a against the weight m g.\n\n\
    Defaults: C60 (R = 3.55 Å, 60 atoms, m = 1.196e-24 kg) on one graphene sheet (0.3818 \
    atoms/Å², 3.35 Å between sheets), carbon-carbon constants A = 17.4 eV Å^6, B = 29.0e3 \
    eV Å^12 (Girifalco, Hodak & Lee 2000, by mixing rules; quoted, not checked against the \
    paper). The result for graphite (0.88 eV) lies within the published theory values \
    0.76-0.96 eV; desorption experiments give an apparent 1.3-1.5 eV. docs/physics.md#adhesion-c60 \
    has the derivation and the sources.\n\n\
    Exit codes: 0 ok, 2 bad input (one line naming the option and its range).";

/// The substrate under the cage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SubstrateArg {
    /// One graphene sheet.
    Graphene,
    /// A stack of graphene sheets (--layers, default 30: the bulk to 1e-4).
    Graphite,
}

/// Arguments of `tippetop adhesion`.
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = "Examples:\n  \
                  tippetop adhesion\n  \
                  tippetop adhesion --substrate graphite\n  \
                  tippetop adhesion --substrate graphite --layers 5 --json\n  \
                  tippetop adhesion --lj-a 2.97e-78 --lj-b 4.65e-135   # C6 = 18.54 eV Å^6 (Lu et al.)")]
pub struct AdhesionArgs {
    /// What the cage sits on.
    #[arg(long, value_enum, default_value = "graphene")]
    pub substrate: SubstrateArg,
    /// Number of sheets with --substrate graphite (1 to 100000).
    #[arg(long, default_value_t = 30)]
    pub layers: u32,
    /// Cage radius R (atom centres) [m].
    #[arg(long, default_value_t = Shell::C60.radius)]
    pub radius: f64,
    /// Atoms on the cage.
    #[arg(long, default_value_t = Shell::C60.atoms)]
    pub atoms: f64,
    /// Mass of the body, for F_a/(m g) and the vibration frequency [kg].
    #[arg(long, default_value_t = 1.196e-24)]
    pub mass: f64,
    /// Gravity for F_a/(m g) [m/s^2].
    #[arg(long, default_value_t = 9.8)]
    pub gravity: f64,
    /// Carbon-carbon attraction constant A of Φ = −A/r^6 + B/r^12 [J m^6]
    /// (default 17.4 eV Å^6).
    #[arg(long = "lj-a", default_value_t = LjConstants::C60_GRAPHENE.a)]
    pub lj_a: f64,
    /// Carbon-carbon repulsion constant B [J m^12] (default 29.0e3 eV Å^12).
    #[arg(long = "lj-b", default_value_t = LjConstants::C60_GRAPHENE.b)]
    pub lj_b: f64,
    /// Print JSON (SI units).
    #[arg(long)]
    pub json: bool,
}

/// What `tippetop adhesion --json` prints (SI).
#[derive(Debug, Clone, Serialize)]
pub struct AdhesionReport {
    /// "graphene" or "graphite".
    pub substrate: &'static str,
    /// Sheets.
    pub layers: u32,
    /// Cage radius \[m\].
    pub radius: f64,
    /// Atoms on the cage.
    pub atoms: f64,
    /// A \[J m⁶\].
    pub lj_a: f64,
    /// B \[J m¹²\].
    pub lj_b: f64,
    /// Binding energy E_b \[J\].
    pub binding_energy: f64,
    /// E_b \[eV\].
    pub binding_energy_ev: f64,
    /// Equilibrium height of the centre above the top sheet \[m\].
    pub height: f64,
    /// Gap cage–sheet at equilibrium \[m\].
    pub gap: f64,
    /// Pull-off force F_a \[N\].
    pub pull_off_force: f64,
    /// Height of the largest attraction \[m\].
    pub pull_off_height: f64,
    /// Normal stiffness \[N/m\].
    pub stiffness: f64,
    /// Vertical vibration frequency √(k/m)/(2π) \[Hz\].
    pub vertical_frequency: f64,
    /// Mass \[kg\].
    pub mass: f64,
    /// Gravity \[m/s²\].
    pub gravity: f64,
    /// F_a/(m g); null with g = 0.
    pub pull_off_over_weight: Option<f64>,
}

/// Check the options that the library does not (mass, gravity).
fn check(args: &AdhesionArgs) -> Result<(), tippetop::Error> {
    if !(1e-30..=1e3).contains(&args.mass) {
        return Err(tippetop::Error::invalid(
            "--mass",
            format!("{:e} is not allowed", args.mass),
            "1e-30 to 1e3 kg".into(),
        ));
    }
    if !(0.0..=1e3).contains(&args.gravity) {
        return Err(tippetop::Error::invalid(
            "--gravity",
            format!("{:e} is not allowed", args.gravity),
            "0 to 1e3 m/s^2".into(),
        ));
    }
    Ok(())
}

/// The report for `args`, or the bad-input error.
pub fn report(args: &AdhesionArgs) -> Result<AdhesionReport, tippetop::Error> {
    check(args)?;
    let (name, layers) = match args.substrate {
        SubstrateArg::Graphene => ("graphene", 1),
        SubstrateArg::Graphite => ("graphite", args.layers),
    };
    let ad = Adhesion {
        shell: Shell {
            radius: args.radius,
            atoms: args.atoms,
        },
        substrate: Substrate::graphite(layers),
        lj: LjConstants {
            a: args.lj_a,
            b: args.lj_b,
        },
    };
    // The library names its parameters (`lj_a`); the user typed `--lj-a`.
    let b = ad.binding().map_err(|e| match e {
        tippetop::Error::Invalid { key, what, range } => tippetop::Error::Invalid {
            key: format!("--{}", key.replace('_', "-")),
            what,
            range,
        },
        other => other,
    })?;
    let weight = args.mass * args.gravity;
    Ok(AdhesionReport {
        substrate: name,
        layers,
        radius: args.radius,
        atoms: args.atoms,
        lj_a: args.lj_a,
        lj_b: args.lj_b,
        binding_energy: b.energy,
        binding_energy_ev: b.energy / EV,
        height: b.height,
        gap: b.gap,
        pull_off_force: b.pull_off_force,
        pull_off_height: b.pull_off_height,
        stiffness: b.stiffness,
        vertical_frequency: (b.stiffness / args.mass).sqrt() / std::f64::consts::TAU,
        mass: args.mass,
        gravity: args.gravity,
        pull_off_over_weight: (weight > 0.0).then(|| b.pull_off_force / weight),
    })
}

/// Run `tippetop adhesion`: exit 0, or 2 with one line for bad input.
pub fn run(args: &AdhesionArgs) -> anyhow::Result<ExitCode> {
    let rep = match report(args) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(2));
        }
    };
    if args.json {
        crate::output::print_json(&rep)?;
    } else {
        print!("{}", table(&rep));
    }
    Ok(ExitCode::SUCCESS)
}

fn table(r: &AdhesionReport) -> String {
    let ev6 = EV * ANGSTROM.powi(6);
    let ev12 = EV * ANGSTROM.powi(12);
    let on = if r.layers == 1 {
        "one graphene sheet".to_string()
    } else {
        format!("graphite ({} sheets 3.35 Å apart)", r.layers)
    };
    let weight = match r.pull_off_over_weight {
        Some(x) => format!("{x:.2e}"),
        None => "undefined (g = 0)".into(),
    };
    format!(
        "cage of {} atoms, R = {:.4} Å, on {on}; A = {:.4} eV Å^6, B = {:.4e} eV Å^12\n\
         binding energy E_b    {:.4} eV = {:.4e} J\n\
         equilibrium height    {:.4} Å (gap {:.4} Å)\n\
         pull-off force F_a    {:.4e} N at height {:.4} Å\n\
         normal stiffness      {:.4} N/m (vertical vibration {:.3e} Hz for m = {:e} kg)\n\
         F_a / (m g)           {weight} (g = {} m/s^2)\n",
        r.atoms,
        r.radius / ANGSTROM,
        r.lj_a / ev6,
        r.lj_b / ev12,
        r.binding_energy_ev,
        r.binding_energy,
        r.height / ANGSTROM,
        r.gap / ANGSTROM,
        r.pull_off_force,
        r.pull_off_height / ANGSTROM,
        r.stiffness,
        r.vertical_frequency,
        r.mass,
        r.gravity
    )
}
