//! `tippetop adhesion`: the van der Waals binding of a fullerene on graphene
//! or graphite in the continuum Lennard-Jones approximation
//! (`tippetop::physics::adhesion`): binding energy, equilibrium height,
//! pull-off force, stiffness, and how they compare with the weight; with
//! `--substrate nanotube` the cage inside a single-walled tube
//! (`tippetop::physics::nanotube`): where it sits, its binding and suction
//! energies, its radial stiffness and pull-off force.

use std::process::ExitCode;

use serde::Serialize;
use tippetop::human::s4;
use tippetop::physics::adhesion::{ANGSTROM, Adhesion, EV, LjConstants, Shell, Substrate};
use tippetop::physics::nanotube::{Nanotube, chirality_radius, off_axis_radius};

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
    --substrate nanotube puts the cage inside an infinitely long single-walled tube (radius \
    --tube-radius, or --chirality N,M with b = a_CC sqrt(3(N^2+NM+M^2))/(2 pi), a_CC = 1.42 Å; \
    the wall has graphene's density): the energy against the cage's offset from the axis, the \
    equilibrium on the axis or against the wall, the binding energy, the radial stiffness, the \
    pull-off force towards the axis (off the axis only), the suction energy (entering along the \
    axis from free space) and the tube radius at which the cage leaves the axis. A tube must be \
    wider than R + the sheet's equilibrium gap. docs/physics.md#nanotube.\n\n\
    Exit codes: 0 ok, 2 bad input (one line naming the option and its range).";

/// The substrate under the cage.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SubstrateArg {
    /// One graphene sheet.
    Graphene,
    /// A stack of graphene sheets (--layers, default 30: the bulk to 1e-4).
    Graphite,
    /// Inside a single-walled carbon nanotube (--tube-radius or --chirality).
    Nanotube,
}

/// Van der Waals adhesion of a fullerene on graphene or graphite (E_b, F_a).
#[derive(Debug, Clone, clap::Args)]
#[command(long_about = ADHESION_LONG_ABOUT)]
#[command(after_help = "Examples:\n  \
                  tippetop adhesion\n  \
                  tippetop adhesion --substrate graphite\n  \
                  tippetop adhesion --substrate graphite --layers 5 --json\n  \
                  tippetop adhesion --substrate nanotube --chirality 10,10\n  \
                  tippetop adhesion --substrate nanotube --tube-radius 6.78e-10 --json\n  \
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
    /// Radius b of the tube's wall (atom centres) with --substrate nanotube
    /// [m]: above R + the sheet's equilibrium gap (6.509e-10 m for C60), up
    /// to 1e-6 m.
    #[arg(long = "tube-radius")]
    pub tube_radius: Option<f64>,
    /// The tube's chiral indices N,M with --substrate nanotube (0 <= M <= N,
    /// 1 <= N <= 5000); b = a_CC sqrt(3(N^2+NM+M^2))/(2 pi).
    #[arg(long)]
    pub chirality: Option<String>,
    /// Print JSON (SI units).
    #[arg(long)]
    pub json: bool,
}

/// What `tippetop adhesion --json` prints (SI).
#[derive(Debug, Clone, Serialize)]
pub struct AdhesionReport {
    /// "graphene", "graphite" or "nanotube".
    pub substrate: &'static str,
    /// Sheets (1 for a tube).
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
    /// Equilibrium height of the centre above the top sheet; in a tube the
    /// centre's distance from the nearest wall \[m\].
    pub height: f64,
    /// Gap cage–sheet (cage–wall) at equilibrium \[m\].
    pub gap: f64,
    /// Pull-off force F_a \[N\]; in a tube the largest force back to the
    /// wall on the way to the axis; null with the cage on the axis.
    pub pull_off_force: Option<f64>,
    /// Height (distance from the wall) of the largest attraction \[m\];
    /// null with the cage on the axis.
    pub pull_off_height: Option<f64>,
    /// Normal (in a tube: radial) stiffness \[N/m\].
    pub stiffness: f64,
    /// Vertical (in a tube: radial) vibration frequency √(k/m)/(2π) \[Hz\].
    pub vertical_frequency: f64,
    /// Mass \[kg\].
    pub mass: f64,
    /// Gravity \[m/s²\].
    pub gravity: f64,
    /// F_a/(m g); null with g = 0 or on a tube's axis.
    pub pull_off_over_weight: Option<f64>,
    /// The tube's fields (`--substrate nanotube` only), at the top level
    /// of the JSON.
    #[serde(flatten)]
    pub tube: Option<Tube>,
}

/// The fields only a tube has.
#[derive(Debug, Clone, Serialize)]
pub struct Tube {
    /// The cage centre's distance from the axis at equilibrium \[m\] (0.0
    /// on the axis).
    pub offset: f64,
    /// Whether the cage sits on the axis.
    pub on_axis: bool,
    /// The wall's radius b \[m\].
    pub tube_radius: f64,
    /// With --chirality: `[N, M]`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chirality: Option<[u32; 2]>,
    /// Suction energy −U(0), entering along the axis from free space \[J\].
    pub suction_energy: f64,
    /// The suction energy \[eV\].
    pub suction_energy_ev: f64,
    /// The tube radius at which the cage leaves the axis \[m\] (None: not
    /// found up to b = 1e-6 m).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub off_axis_radius: Option<f64>,
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
    if args.substrate != SubstrateArg::Nanotube {
        for (set, opt) in [
            (args.tube_radius.is_some(), "--tube-radius"),
            (args.chirality.is_some(), "--chirality"),
        ] {
            if set {
                return Err(tippetop::Error::invalid(
                    opt,
                    "is a tube option".into(),
                    "only with --substrate nanotube".into(),
                ));
            }
        }
    }
    Ok(())
}

/// The largest chiral index N accepted (b = 339 Å for (5000, 5000)).
const MAX_CHIRAL: u32 = 5000;

/// `N,M` with `0 <= M <= N`, `1 <= N <= 5000`.
fn parse_chirality(text: &str) -> Result<[u32; 2], tippetop::Error> {
    let bad = || {
        tippetop::Error::invalid(
            "--chirality",
            format!("{text:?} is not allowed"),
            format!("two integers N,M with 0 <= M <= N and 1 <= N <= {MAX_CHIRAL}"),
        )
    };
    let (n, m) = text.split_once(',').ok_or_else(bad)?;
    let n: u32 = n.trim().parse().map_err(|_| bad())?;
    let m: u32 = m.trim().parse().map_err(|_| bad())?;
    if !(1..=MAX_CHIRAL).contains(&n) || m > n {
        return Err(bad());
    }
    Ok([n, m])
}

/// The library names its parameters (`lj_a`); the user typed `--lj-a`.
fn as_option(e: tippetop::Error) -> tippetop::Error {
    match e {
        tippetop::Error::Invalid { key, what, range } => tippetop::Error::Invalid {
            key: format!("--{}", key.replace('_', "-")),
            what,
            range,
        },
        other => other,
    }
}

/// The report for `args`, or the bad-input error.
pub fn report(args: &AdhesionArgs) -> Result<AdhesionReport, tippetop::Error> {
    check(args)?;
    let (name, layers) = match args.substrate {
        SubstrateArg::Graphene => ("graphene", 1),
        SubstrateArg::Graphite => ("graphite", args.layers),
        SubstrateArg::Nanotube => return tube_report(args),
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
    let b = ad.binding().map_err(as_option)?;
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
        pull_off_force: Some(b.pull_off_force),
        pull_off_height: Some(b.pull_off_height),
        stiffness: b.stiffness,
        vertical_frequency: (b.stiffness / args.mass).sqrt() / std::f64::consts::TAU,
        mass: args.mass,
        gravity: args.gravity,
        pull_off_over_weight: (weight > 0.0).then(|| b.pull_off_force / weight),
        tube: None,
    })
}

/// The report of `--substrate nanotube`.
fn tube_report(args: &AdhesionArgs) -> Result<AdhesionReport, tippetop::Error> {
    let (radius, chirality, opt) = match (args.tube_radius, &args.chirality) {
        (Some(_), Some(_)) => {
            return Err(tippetop::Error::invalid(
                "--chirality",
                "given with --tube-radius".into(),
                "one of --tube-radius B or --chirality N,M".into(),
            ));
        }
        (Some(b), None) => (b, None, "--tube-radius"),
        (None, Some(c)) => {
            let [n, m] = parse_chirality(c)?;
            (chirality_radius(n, m), Some([n, m]), "--chirality")
        }
        (None, None) => {
            return Err(tippetop::Error::invalid(
                "--tube-radius",
                "missing with --substrate nanotube".into(),
                "--tube-radius B [m] (above R + gap, up to 1e-6) or --chirality N,M".into(),
            ));
        }
    };
    let tube = Nanotube {
        shell: Shell {
            radius: args.radius,
            atoms: args.atoms,
        },
        radius,
        density: Substrate::graphene_density(),
        lj: LjConstants {
            a: args.lj_a,
            b: args.lj_b,
        },
    };
    // The sheet's parameters first (their own options), then the radius.
    tube.sheet().validate().map_err(as_option)?;
    let named = |e: tippetop::Error| match e {
        tippetop::Error::Invalid { key, what, range } if key == "tube_radius" => {
            let what = match chirality {
                Some([n, m]) => format!("({n},{m}) gives b = {what}"),
                None => what,
            };
            tippetop::Error::Invalid {
                key: opt.into(),
                what,
                range,
            }
        }
        other => as_option(other),
    };
    let b = tube.binding().map_err(named)?;
    let leaves = off_axis_radius(&tube).ok();
    let weight = args.mass * args.gravity;
    Ok(AdhesionReport {
        substrate: "nanotube",
        layers: 1,
        radius: args.radius,
        atoms: args.atoms,
        lj_a: args.lj_a,
        lj_b: args.lj_b,
        binding_energy: b.energy,
        binding_energy_ev: b.energy / EV,
        height: b.wall_distance,
        gap: b.gap,
        pull_off_force: b.pull_off_force,
        pull_off_height: b.pull_off_wall_distance,
        stiffness: b.stiffness,
        vertical_frequency: (b.stiffness / args.mass).sqrt() / std::f64::consts::TAU,
        mass: args.mass,
        gravity: args.gravity,
        pull_off_over_weight: b
            .pull_off_force
            .filter(|_| weight > 0.0)
            .map(|f| f / weight),
        tube: Some(Tube {
            offset: b.offset,
            on_axis: b.on_axis,
            tube_radius: radius,
            chirality,
            suction_energy: b.suction_energy,
            suction_energy_ev: b.suction_energy / EV,
            off_axis_radius: leaves,
        }),
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
    } else if let Some(tube) = &rep.tube {
        print!("{}", tube_table(&rep, tube));
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
        r.pull_off_force.unwrap_or(f64::NAN),
        r.pull_off_height.unwrap_or(f64::NAN) / ANGSTROM,
        r.stiffness,
        r.vertical_frequency,
        r.mass,
        r.gravity
    )
}

/// The console text of `--substrate nanotube` (4 significant figures).
fn tube_table(r: &AdhesionReport, t: &Tube) -> String {
    let ev6 = EV * ANGSTROM.powi(6);
    let ev12 = EV * ANGSTROM.powi(12);
    let a = |x: f64| format!("{} Å", s4(x / ANGSTROM));
    let b = t.tube_radius;
    let tube = match t.chirality {
        Some([n, m]) => format!("a ({n},{m}) tube, b = {}", a(b)),
        None => format!("a tube of b = {}", a(b)),
    };
    let on_axis = t.on_axis;
    let offset = t.offset;
    let where_ = if on_axis {
        format!(
            "on the axis; wall gap {} all round: the cage touches nothing",
            a(r.gap)
        )
    } else {
        format!(
            "off the axis by {}, wall gap {} (centre {} from the wall): it rests against the wall",
            a(offset),
            a(r.gap),
            a(r.height)
        )
    };
    let pull = match (r.pull_off_force, r.pull_off_height) {
        (Some(f), Some(h)) => format!(
            "{} nN towards the axis, largest at {} from the wall",
            s4(f * 1e9),
            a(h)
        ),
        _ => "none: on the axis no wall holds the cage".into(),
    };
    let weight = match r.pull_off_over_weight {
        Some(x) => s4(x),
        None if on_axis => "undefined (on the axis)".into(),
        None => "undefined (g = 0)".into(),
    };
    let leaves = match t.off_axis_radius {
        Some(x) => format!("in tubes wider than b = {}", a(x)),
        None => "not found up to b = 1e-6 m".into(),
    };
    format!(
        "cage of {} atoms, R = {}, in {tube} (graphene's density); A = {} eV Å^6, B = {} eV Å^12\n\
         equilibrium           {where_}\n\
         binding energy E_b    {} eV = {} J\n\
         suction energy        {} eV (entering along the axis from free space)\n\
         radial stiffness      {} N/m (radial vibration {} Hz for m = {} kg)\n\
         pull-off force F_a    {pull}\n\
         F_a / (m g)           {weight} (g = {} m/s^2)\n\
         the cage leaves the axis {leaves}\n",
        r.atoms,
        a(r.radius),
        s4(r.lj_a / ev6),
        s4(r.lj_b / ev12),
        s4(r.binding_energy_ev),
        s4(r.binding_energy),
        s4(t.suction_energy_ev),
        s4(r.stiffness),
        s4(r.vertical_frequency),
        s4(r.mass),
        s4(r.gravity),
    )
}
