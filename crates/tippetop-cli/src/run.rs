//! `tippetop run`: resolve a scenario, simulate it, write the results.
//!
//! Order matters for the exit-code contract: everything that can be bad
//! input is checked before `--out` is touched (exit code 2, nothing
//! written); then the output directory is created, locked and checked
//! ([`OutDir::open`], exit code 1 if it cannot be written or is in use), so
//! an unwritable `--out` is found before the simulation, not after it; the
//! results are staged and committed as a unit.

use std::fs;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Result;
use clap::{ArgGroup, Args};
use tippetop::{Error, Scenario, Trajectory};

use crate::common::time_unit;
use crate::output::{
    Columns, OutDir, SummaryDoc, summary_with_status, write_bytes_atomic, write_json_pretty,
    write_trajectory_csv_columns,
};
use crate::plot::{self, Panel, PlotOpts, RefLine, Series, VLine};
use crate::{progress, scenario_load};

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
                 contact point: its drift measures the integration error; not
                 conserved by the physics under friction_law = \"contensou\", whose
                 contact patch's drilling torque changes J, nor in a heat bath)
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

--no-pose leaves out the pose's nine columns, x .. yp, and the vector and reduced models then do
not integrate them (docs/performance.md#pose).

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

/// Run one scenario and write its trajectory, summary and plots.
#[derive(Debug, Args)]
#[command(long_about = RUN_LONG_ABOUT)]
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
#[command()]
pub struct RunArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,

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

    /// Do not compute the pose: trajectory.csv without its columns x, y, z,
    /// qw, qx, qy, qz, xp, yp (the first 17 columns only). The vector model
    /// (the default) then integrates 10 state components instead of 17, the
    /// reduced model 8 instead of 14 (not the attitude and position, which
    /// nothing else reads): every other column, summary.json and the plots
    /// are the same bits, in 10-20 % fewer instructions
    /// (docs/performance.md#pose). The rigid model computes the pose anyway
    /// (only the columns are left out).
    #[arg(long)]
    pub no_pose: bool,
}

impl RunArgs {
    /// Whether to write plots (`--plot` unless `--no-plot` came last).
    pub fn plots(&self) -> bool {
        !self.no_plot
    }
}

/// Run `tippetop run`. Errors: a [`tippetop::Error`] that `is_input()` for
/// bad input (nothing written), a run-time [`tippetop::Error`] if the run
/// failed part-way (results up to the failure written), anything else for
/// I/O and plotting failures.
pub fn run(args: &RunArgs, quiet: bool) -> Result<()> {
    // 1. Everything that can be bad input, before touching --out.
    let toml_text = match &args.source.scenario {
        Some(path) => Some(tippetop::limits::read_file(path)?),
        None => None,
    };
    for s in &args.source.sets {
        check_set_syntax(s)?;
    }
    let scenario = scenario_load::load(
        args.source.preset.as_deref(),
        toml_text.as_deref(),
        &args.source.sets,
    )?;
    scenario.validate()?;
    check_out_dir(&args.out)?;

    // 2. The output directory: created, locked and checked before computing.
    let out = OutDir::open(&args.out)?;

    // 3. The run.
    let mut prog = progress::RunProgress::new(quiet, scenario.solver.t_end);
    let start = Instant::now();
    let result = tippetop::simulate_with_pose(&scenario, !args.no_pose, &mut |p| prog.update(p));
    let wall_seconds = start.elapsed().as_secs_f64();
    prog.finish();
    let traj = match result {
        Ok(t) => t,
        Err(e) => {
            // Bad input found by the library: nothing written.
            out.abandon();
            return Err(e.into());
        }
    };

    // 4. Results (also for a run that failed part-way), staged, then
    // committed: summary.json last, the previous run's other files removed.
    let toml = scenario_load::to_toml(&scenario);
    let stage = out.stage().to_path_buf();
    let columns = if args.no_pose {
        Columns::WithoutPose
    } else {
        Columns::All
    };
    let mut written = write_data_columns(&stage, &scenario, &toml, &traj, wall_seconds, columns)?;
    let mut plots = Vec::new();
    let mut plot_error = None;
    if args.plots() {
        match write_plots(&stage, &scenario, &traj) {
            Ok(p) => plots = p,
            Err(e) => {
                // The data are good: commit them without any plot (no half
                // set), then report the plots' failure.
                for stem in PLOT_STEMS {
                    for ext in ["png", "svg"] {
                        let _ = fs::remove_file(stage.join(format!("{stem}.{ext}")));
                    }
                }
                plot_error = Some(e);
            }
        }
    }
    out.commit(&["summary.json"])?;
    if let Some(e) = plot_error {
        if traj.error.is_none() {
            return Err(e.context("plots not written (the data files are)"));
        }
        // A failed run's error is the one that matters; still say why the
        // plots are missing.
        eprintln!("warning: plots not written: {e:#}");
    }
    let rebase = |p: &PathBuf| match p.file_name() {
        Some(n) => args.out.join(n),
        None => p.clone(),
    };
    written = written.iter().map(rebase).collect();
    let plots: Vec<PathBuf> = plots.iter().map(rebase).collect();
    if !quiet {
        print!(
            "{}",
            human_summary(&traj, &scenario, wall_seconds, &args.out, &written, &plots)
        );
    }
    match &traj.error {
        Some(e) => Err(e.clone().into()),
        None => Ok(()),
    }
}

/// `--set` must look like `KEY=VALUE` (the library checks the key and value).
fn check_set_syntax(s: &str) -> Result<(), Error> {
    match s.split_once('=') {
        Some((k, _)) if !k.trim().is_empty() => Ok(()),
        _ => Err(Error::invalid(
            "set",
            format!("\"{s}\" is not TABLE.KEY=VALUE"),
            "e.g. --set top.offset=0.002".into(),
        )),
    }
}

/// `--out` must be a directory or not exist yet.
fn check_out_dir(out: &Path) -> Result<(), Error> {
    if out.exists() && !out.is_dir() {
        return Err(Error::invalid(
            "--out",
            format!("{} exists and is not a directory", out.display()),
            "a directory, created if missing".into(),
        ));
    }
    Ok(())
}

/// Write `trajectory.csv`, `scenario.toml` and `summary.json` into `dir`
/// (which must exist); returns the paths written. `summary.json` is last, so
/// its presence means the data files are complete.
pub fn write_data(
    dir: &Path,
    scenario: &Scenario,
    scenario_toml: &str,
    traj: &Trajectory,
    wall_seconds: f64,
) -> Result<Vec<PathBuf>> {
    write_data_columns(
        dir,
        scenario,
        scenario_toml,
        traj,
        wall_seconds,
        Columns::All,
    )
}

/// [`write_data`] with `trajectory.csv`'s `columns` (`run --no-pose`).
pub fn write_data_columns(
    dir: &Path,
    scenario: &Scenario,
    scenario_toml: &str,
    traj: &Trajectory,
    wall_seconds: f64,
    columns: Columns,
) -> Result<Vec<PathBuf>> {
    let csv = dir.join("trajectory.csv");
    write_trajectory_csv_columns(&csv, traj, columns)?;
    let toml = dir.join("scenario.toml");
    write_bytes_atomic(&toml, scenario_toml.as_bytes())?;
    let summary = summary_with_status(traj);
    let doc = SummaryDoc::new(&summary, &traj.events, scenario_toml, wall_seconds);
    // The regime at the run's own temperature (the thermal ratios are null
    // without one).
    let doc = doc.with_regime(tippetop::analysis::regime::of_run(scenario));
    let json = dir.join("summary.json");
    write_json_pretty(&json, &doc)?;
    Ok(vec![csv, json, toml])
}

/// The stems of the plots [`write_plots`] writes.
pub const PLOT_STEMS: [&str; 3] = ["theta", "spin", "diagnostics"];

/// The standard plots of a run, as `STEM.png` + `STEM.svg` in `dir`:
/// `theta` (θ with π/2 and π marked), `spin` (ω and Ω), `diagnostics`
/// (N, slip, Jellett drift, energy balance). Returns the stems.
pub fn write_plots(dir: &Path, scenario: &Scenario, traj: &Trajectory) -> Result<Vec<PathBuf>> {
    let s = &traj.samples;
    if s.is_empty() {
        return Ok(Vec::new());
    }
    // The requested span (a failed run stops short of its end, visibly).
    let t_last = s.last().map_or(0.0, |x| x.t);
    let t_end = if scenario.solver.t_end.is_finite() && scenario.solver.t_end > t_last {
        scenario.solver.t_end
    } else {
        t_last
    };
    let (k, unit) = time_unit(t_end);
    let t: Vec<f64> = s.iter().map(|x| x.t * k).collect();
    let col = |f: fn(&tippetop::Sample) -> f64| s.iter().map(f).collect::<Vec<f64>>();
    let x_label = format!("t [{unit}]");
    let x_range = Some((0.0, t_end * k));
    // The applied force's switches, marked on the time plots.
    let switches: Vec<VLine> = scenario
        .switch_times()
        .into_iter()
        .filter(|&ts| ts > 0.0 && ts < t_end)
        .map(|ts| VLine::new(ts * k, "force switch"))
        .collect();
    let failed = traj.error.is_some();
    let suffix = if failed { " (run failed)" } else { "" };

    let mut stems = Vec::new();

    let stem = dir.join("theta");
    let pi = std::f64::consts::PI;
    plot::line_plot(
        &stem,
        &format!("Nutation angle θ(t){suffix}"),
        &x_label,
        "θ [rad]",
        &[Series::new("θ", t.clone(), col(|x| x.theta))],
        &PlotOpts {
            hlines: vec![RefLine::new(pi / 2.0, "π/2"), RefLine::new(pi, "π")],
            x_range,
            vlines: switches.clone(),
            ..PlotOpts::default()
        },
    )?;
    stems.push(stem);

    let stem = dir.join("spin");
    plot::line_plot(
        &stem,
        &format!("Spin ω and precession Ω{suffix}"),
        &x_label,
        "rate [rad/s]",
        &[
            Series::new("spin ω", t.clone(), col(|x| x.spin)),
            // Ω nutates fast: its running mean and min-max band over 1/100
            // of the run, so that ω stays visible beside it.
            Series::envelope(
                "precession Ω (running mean, min–max band)",
                &t,
                &col(|x| x.precession),
                500,
                t_end * k / 100.0,
            ),
        ],
        &PlotOpts {
            hlines: vec![RefLine {
                y: 0.0,
                label: None,
            }],
            x_range,
            vlines: switches,
            ..PlotOpts::default()
        },
    )?;
    stems.push(stem);

    // Jellett drift normalised as in the summary: (J − J0) / (C max|ω| R).
    let j0 = s[0].jellett;
    let max_spin = s.iter().map(|x| x.spin.abs()).fold(0.0, f64::max);
    let j_scale = scenario.top.inertia_axial * max_spin * scenario.top.radius;
    let j_scale = if j_scale > 0.0 && j_scale.is_finite() {
        j_scale
    } else {
        1.0
    };
    let e0 = s[0].energy;
    let e_scale = s.iter().map(|x| x.energy.abs()).fold(0.0, f64::max);
    let e_scale = if e_scale > 0.0 && e_scale.is_finite() {
        e_scale
    } else {
        1.0
    };
    let panels = vec![
        Panel::new(
            "normal force N [N]",
            vec![Series::new("N", t.clone(), col(|x| x.normal))],
        ),
        Panel::new(
            "slip speed |v_P| [m/s]",
            vec![Series::new("slip", t.clone(), col(|x| x.slip))],
        ),
        Panel::new(
            "(J − J₀)/(C max|ω| R)",
            vec![Series::new(
                "Jellett drift",
                t.clone(),
                s.iter().map(|x| (x.jellett - j0) / j_scale).collect(),
            )],
        ),
        Panel::new(
            "(E − E₀ − W)/max|E|",
            vec![Series::new(
                "energy balance",
                t.clone(),
                s.iter()
                    .map(|x| (x.energy - e0 - x.work_friction - x.work_applied) / e_scale)
                    .collect(),
            )],
        ),
    ];
    let stem = dir.join("diagnostics");
    plot::multi_panel(
        &stem,
        &format!("Contact and conservation diagnostics{suffix}"),
        &x_label,
        &panels,
        &PlotOpts {
            size: (1000, 1100),
            x_range,
            ..PlotOpts::default()
        },
    )?;
    stems.push(stem);
    Ok(stems)
}

/// True when the run's top can leave the plane (the rigid model with
/// unilateral contact): its summary's `contact_lost_at` is then the first
/// lift-off and `negative_normal_fraction` the fraction of time in flight.
pub fn flies(sc: &tippetop::Scenario) -> bool {
    sc.solver.model == tippetop::ModelKind::Rigid
        && sc.surface.contact == tippetop::ContactMode::Unilateral
}

/// `fraction` of a run of `span` seconds for people: `97.6% of the time`;
/// a share that rounds to 100 % but is not all of it is given by the time
/// left over instead (`all but 47.1 ms of the 200 s`).
fn share(fraction: f64, span: f64) -> String {
    let pct = crate::plot::format_value(100.0 * fraction);
    if pct == "100" && fraction < 1.0 {
        format!(
            "all but {} of the {} s",
            tippetop::human::si((1.0 - fraction) * span, "s", 3),
            crate::plot::format_value(span)
        )
    } else {
        format!("{pct}% of the time")
    }
}

/// A top of a toy's size (radius 1 mm or more) on the plane: the scale at
/// which a top that rolls under exact Coulomb friction inverts once the
/// friction acts over its contact patch (Coulomb-Contensou,
/// docs/physics.md#contensou), as real tops do.
pub fn toy_on_plane(sc: &Scenario) -> bool {
    sc.surface.shape == tippetop::input::surface::Shape::Plane && sc.top.radius >= 1e-3
}

/// The contact radius the hint for a rolling toy suggests [m]: 0.3 mm (the
/// classical top's patch, R / 50 for R = 15 mm, that inverts it), R / 50
/// for a smaller top (the largest patch allowed is R / 10).
pub fn suggested_contact_radius(sc: &Scenario) -> f64 {
    (sc.top.radius / 50.0).min(3e-4)
}

/// Why a top that rolled (exact Coulomb friction) and never rose above
/// π/2 did not, and what makes it rise: for a toy on the plane its contact
/// patch (Coulomb-Contensou friction), else the paper's slip law.
fn no_rise_hint(sc: &Scenario) -> String {
    let why = "             a rolling contact does no work, so friction cannot raise the top \
               (docs/physics.md#coulomb)";
    if toy_on_plane(sc) && sc.surface.law == tippetop::FrictionLaw::Coulomb {
        let rc = suggested_contact_radius(sc);
        format!(
            "{why};\n             a real top slides on its contact patch and inverts: \
             --set surface.friction_law=contensou --set surface.contact_radius={} \
             (a patch of radius {}, docs/physics.md#contensou)\n",
            tippetop::human::exact(rc),
            tippetop::human::si(rc, "m", 3)
        )
    } else {
        format!("{why}; the paper's slip law: surface.friction_law = \"regularized\"\n")
    }
}

/// The short human summary printed at the end of a run of `scenario`
/// (without `--quiet`).
pub fn human_summary(
    traj: &Trajectory,
    scenario: &Scenario,
    wall_seconds: f64,
    out: &Path,
    written: &[PathBuf],
    plots: &[PathBuf],
) -> String {
    use crate::plot::format_value as v;
    let flies = flies(scenario);
    let s = summary_with_status(traj);
    let mut o = String::new();
    let status = if traj.error.is_some() {
        format!("FAILED: {}", s.status)
    } else {
        s.status.clone()
    };
    o.push_str(&format!(
        "status:      {status}\n\
         time:        0 .. {} s, {} samples, {} steps ({} rejected)\n",
        v(s.t_end),
        traj.samples.len(),
        s.steps,
        s.rejected_steps
    ));
    let theta0 = traj.samples.first().map_or(f64::NAN, |x| x.theta);
    o.push_str(&format!(
        "theta:       {} -> {} rad (max {} rad)",
        v(theta0),
        v(s.theta_final),
        v(s.theta_max)
    ));
    match s.first_time_theta_above_half_pi {
        Some(t) => o.push_str(&format!(", above π/2 from t = {} s\n", v(t))),
        None => o.push_str(", never above π/2\n"),
    }
    // The contact's story (exact Coulomb): when it stuck, how long it
    // rolled, and, for a top that rolled and never rose, why.
    if s.rolling_fraction > 0.0 {
        let stuck = traj.events.iter().find(|e| e.kind == "stick").map(|e| e.t);
        o.push_str(&format!(
            "friction:    rolls without slipping {}{}\n",
            share(s.rolling_fraction, s.t_end),
            stuck.map_or(String::new(), |t| format!(
                " (sticks first at t = {} s)",
                v(t)
            )),
        ));
        if s.first_time_theta_above_half_pi.is_none() && s.rolling_fraction >= 0.5 {
            o.push_str(&no_rise_hint(scenario));
        }
    }
    // A stochastic run (it has interval-averaged N): the bath's torques
    // change J, so its drift is not an accuracy figure; nor under
    // Coulomb-Contensou friction, whose drilling torque changes J.
    let j_note = if s.normal_intervals.is_some() {
        " (not conserved: the heat bath's torques)"
    } else if matches!(
        scenario.surface.law,
        tippetop::FrictionLaw::Contensou { .. }
    ) {
        " (not conserved: the contact patch's drilling torque, docs/physics.md#contensou; \
         not an integration error)"
    } else if s.stem.is_some_and(|st| st.first_stem_contact_at.is_some()) {
        " (the touching sphere's -L·r: it jumps where the stem and the main sphere take over from each other)"
    } else {
        ""
    };
    o.push_str(&format!(
        "spin:        omega_final {} rad/s, Omega_final {} rad/s\n\
         Jellett J:   J0 = {} kg m³/s, max relative drift {}{j_note}\n\
         energy:      {} -> {} J, max balance error {}\n",
        v(s.omega_final),
        v(s.precession_final),
        v(s.jellett_initial),
        v(s.jellett_max_rel_drift),
        v(s.energy_initial),
        v(s.energy_final),
        v(s.energy_balance_max_rel_error),
    ));
    if let Some(t) = s.contact_lost_at {
        o.push_str(&if flies {
            format!(
                "contact:     lifts off first at t = {} s, in flight {}\n",
                v(t),
                share(s.negative_normal_fraction, s.t_end)
            )
        } else {
            format!(
                "contact:     N < 0 first at t = {} s ({})\n",
                v(t),
                share(s.negative_normal_fraction, s.t_end)
            )
        });
    }
    if let Some(st) = &s.stem {
        match st.first_stem_contact_at {
            Some(t) => o.push_str(&format!(
                "stem:        lands first at t = {} s, on the plane {}\n",
                v(t),
                share(st.stem_contact_fraction, s.t_end)
            )),
            None => o.push_str("stem:        never touches the plane\n"),
        }
    }
    if let Some(ni) = &s.normal_intervals {
        o.push_str(&format!(
            "contact:     N averaged over each output interval ({} intervals): min {} N, max {} N, negative in {}% of them\n",
            ni.intervals,
            v(ni.mean_min),
            v(ni.mean_max),
            v(100.0 * ni.negative_fraction)
        ));
    }
    o.push_str(&format!(
        "wall time:   {}\n",
        crate::output::fmt_duration(wall_seconds)
    ));
    let name = |p: &PathBuf| {
        p.file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default()
    };
    let mut files: Vec<String> = written.iter().map(name).collect();
    files.extend(plots.iter().map(|p| format!("{}.{{png,svg}}", name(p))));
    o.push_str(&format!(
        "wrote:       {}/ {}\n",
        out.display(),
        files.join(" ")
    ));
    o
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::tests::fake_trajectory;

    #[test]
    fn time_units() {
        assert_eq!(time_unit(10.0), (1.0, "s"));
        assert_eq!(time_unit(0.05), (1e3, "ms"));
        assert_eq!(time_unit(1e-4), (1e6, "µs"));
        assert_eq!(time_unit(3e-8), (1e9, "ns"));
    }

    #[test]
    fn set_and_out_checks() {
        assert!(check_set_syntax("top.radius=0.01").is_ok());
        for bad in ["top.radius", "=3", ""] {
            let e = check_set_syntax(bad).unwrap_err();
            assert!(e.is_input());
            assert!(e.to_string().starts_with("set: "), "{e}");
        }
        let dir = tempfile::tempdir().unwrap();
        let f = dir.path().join("file");
        fs::write(&f, "x").unwrap();
        assert!(check_out_dir(&f).unwrap_err().is_input());
        assert!(check_out_dir(dir.path()).is_ok());
        assert!(check_out_dir(&dir.path().join("new")).is_ok());
    }

    /// The whole output of a (fake) nano run: data files, plots, summary.
    #[test]
    fn writes_all_outputs_for_fake_runs() {
        for failed in [false, true] {
            let dir = tempfile::tempdir().unwrap();
            let sc = Scenario::nano();
            let traj = fake_trajectory(1001, 1e-4, failed);
            let toml = scenario_load::to_toml(&sc);
            let written = write_data(dir.path(), &sc, &toml, &traj, 0.5).unwrap();
            let plots = write_plots(dir.path(), &sc, &traj).unwrap();
            let stems: Vec<String> = plots
                .iter()
                .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
                .collect();
            assert_eq!(
                stems, PLOT_STEMS,
                "PLOT_STEMS lists what write_plots writes"
            );
            let mut names: Vec<String> = fs::read_dir(dir.path())
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect();
            names.sort();
            assert_eq!(
                names,
                [
                    "diagnostics.png",
                    "diagnostics.svg",
                    "scenario.toml",
                    "spin.png",
                    "spin.svg",
                    "summary.json",
                    "theta.png",
                    "theta.svg",
                    "trajectory.csv"
                ]
            );
            let json: serde_json::Value =
                serde_json::from_str(&fs::read_to_string(dir.path().join("summary.json")).unwrap())
                    .unwrap();
            assert_eq!(json["scenario"], toml.as_str());
            assert_eq!(json["wall_seconds"], 0.5);
            if failed {
                assert!(
                    json["status"]
                        .as_str()
                        .unwrap()
                        .contains("step size underflow")
                );
            } else {
                assert_eq!(json["status"], "ok");
            }
            let text = human_summary(&traj, &sc, 0.5, dir.path(), &written, &plots);
            assert!(text.contains("theta:") && text.contains("wall time:"));
            assert!(text.contains("theta.{png,svg}"));
            assert_eq!(text.contains("FAILED"), failed);
        }
    }

    /// Renders the sample plots into `$TIPPETOP_PLOT_PREVIEW` for a visual
    /// check: `TIPPETOP_PLOT_PREVIEW=/tmp/p cargo test -p tippetop-cli preview -- --ignored`.
    /// Without the variable it does nothing, so that the documented slow
    /// validation run (`cargo test --workspace --release -- --ignored`) does
    /// not fail on this tool.
    #[test]
    #[ignore = "writes preview images for a human to look at"]
    fn preview() {
        let Ok(dir) = std::env::var("TIPPETOP_PLOT_PREVIEW") else {
            eprintln!("TIPPETOP_PLOT_PREVIEW not set: no preview written");
            return;
        };
        let dir = PathBuf::from(dir);
        fs::create_dir_all(&dir).unwrap();
        let sc = Scenario::nano();
        write_plots(&dir, &sc, &fake_trajectory(1001, 1e-4, false)).unwrap();
    }
}
