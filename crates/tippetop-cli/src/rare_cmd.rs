//! `tippetop rare`: a rare-event question about a scenario (issue 27):
//! the probability of reaching a target before a reset, or the mean
//! first-passage time to a target, by the exact one-dimensional answer or
//! a plain ensemble ([`tippetop::analysis::rare`]); writes rare.json and
//! rare.md.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Result;
use clap::{ArgGroup, Args};
use tippetop::analysis::rare::ams::{Ams, Hooks, Replica, Settings};
use tippetop::analysis::rare::exact::{Edge, Exact, Positive, Quantity};
use tippetop::analysis::rare::problem::{
    self, AmsPart, DEFAULT_REPLICAS, Problem, RareMethod, Report,
};
use tippetop::analysis::rare::step_check::{self as rare_step, Checked};
use tippetop::analysis::sweep::ShardInfo;

use crate::output::{OutDir, write_bytes_atomic};
use crate::partial::{check_checksum, checksum};
use crate::scenario_load::input_error;

/// Long help of `tippetop rare`.
pub const RARE_LONG_ABOUT: &str =
    "A rare-event question about a stochastic scenario (solver.method = \
\"langevin\" or \"brownian\" at thermal.temperature > 0), from its initial state:
  with --reset (or --horizon): p = P(target before reset [and before the horizon T]);
  without: the mean first-passage time to the target [s].
COND is the grammar of `ensemble --first-passage`: COLUMN>VALUE or COLUMN<VALUE over trajectory.csv
columns (SI units), several joined by ',' (any of them), e.g. 'theta<1.07,theta>2.07'.

Methods:
  exact   the exact answer where theta is a one-dimensional diffusion: the Brownian mode on the
          plane (wells, gravity, adhesion, contact damping, a constant H_x; conditions on theta
          only; no horizon). Mean first-passage time and splitting probability by quadrature in
          log space (barriers of hundreds of kT; a value past 1e308 is given by its logarithm).
          Anywhere else it refuses with the reason (exit 2). docs/physics.md#rare-exact.
  direct  a plain ensemble of --replicas runs (run K is the scenario with thermal.run = r0 + K),
          each until the target or the reset holds at the end of a step (a tie goes to the
          target), or the horizon, or --max-steps steps (censored): solver.t_end and
          solver.samples do not cut a run short. p with the Wilson 95 % interval (censored or
          failed runs widen it upwards); the mean time with mean +- t(0.975, n-1) s/sqrt(n) (with
          censored runs: a lower bound, the interval open above).
  ams     adaptive multilevel splitting (generalised AMS, Brehier et al. 2016; docs/physics.md
          §ams) on the full stochastic dynamics (Langevin or Brownian, any model and force):
          --replicas M independent replicas (default 20) of --particles n (default 100); each
          level kills the --kill k lowest paths (by their maximum of the coordinate) and
          branches survivors. Every path is watched at every step and runs until the target,
          the reset, the horizon or --max-steps steps from its root (default 1e7; a path cut
          there counts as a miss, reported as truncated). Probability: the replicas' mean with
          Student's t 95 % interval; no particle at the target: estimate 0 with the upper bound
          1 - 0.05^(1/(nM)). Without --reset: the mean first-passage time by the flux relation
          tau = T1 + C (1/p - 1) + S (a direct run per replica collects --crossings crossings
          of the interface coordinate > Z_S, within --direct-steps; a pilot run of
          --pilot-steps places the basin and the interface unless --basin/--interface give
          them). --max-trajectories bounds a replica's paths (a replica that needs more: exit
          code 3, the replicas in replicas.json). The coordinate (--coordinate) only changes
          the variance, never the mean.
          --shard K/N runs the K-th of N blocks of the replicas (replicas.json, rare_shard.json,
          shard.json); tippetop merge DIR... joins them into the files of the unsharded run.

Step check (direct and ams; on by default, --no-step-check turns it off): the same question is
answered again at solver.dt/2 (an independent seed: thermal.seed + 0x9E3779B97F4A7C15, wrapping;
every budget counted in steps doubled, within its range), at about twice the first answer's cost.
The step error is the change of the answer when the step is halved (ams mean time: the relative
change |ln tau(dt/2) - ln tau(dt)|), against the 95 % half-width of the answer at solver.dt (on
the same scale): below it the answer is converged in the step (dt_converged: true); else the
console and rare.md say NOT converged, and the answer is not to be quoted without a smaller
solver.dt. The answer written is the one at solver.dt; the one at dt/2 is beside it. Sharded
splittings (--shard, merge) run no check. docs/physics.md#step-check.

Writes into --out:
  rare.json  quantity (\"probability\" or \"mean_first_passage_time\"), estimate, ci95 [lo, hi]
             (null where unknown or past f64), ln_estimate, method, replicas, trajectories, steps,
             wall_seconds, exact (the exact answer where it applies: value and its log for the
             continuous path, watched: the same for a path watched every solver.dt, the theta
             window; else exact_unavailable, the reason), the conditions, the budgets, the
             tallies of a direct ensemble, the scenario
             dt_converged (true/false; null unchecked) and step_check (scale, at_dt and
             at_half_dt: dt, estimate, ci95; step_error, statistical, converged; the refined
             run's trajectories and steps), or step_unchecked (why)
  rare.md    the answer in words, 4 significant figures, and the step check
  levels.png, levels.svg  (ams) each replica's levels against the estimated probability of
             passing them, with the estimate and the exact value
  rare.json with ams: an \"ams\" object (coordinate, particles, kill, standard_error, interval,
             extinct, iterations, truncated, failed, replica_estimates, flux: the flux relation's
             parts)
The files are the same bytes for any --threads or --shard layout, apart from wall_seconds. Bad input (a condition
that holds at the start, --method exact where it is not exact, budgets out of range) exits with
code 2 and writes nothing; runs that fail part-way are counted, the files written, and the
command exits with code 3.";

/// Rare events: P(target before reset) or a mean first-passage time (exact 1D, direct, splitting).
#[derive(Debug, Args)]
#[command(long_about = RARE_LONG_ABOUT)]
#[command(
    group(ArgGroup::new("source").required(true).multiple(true).args(["scenario", "preset"])),
    after_help = "Examples:\n  \
                  tippetop rare --preset nano-physical --set solver.method=brownian --set solver.dt=2e-16 \\\n    \
                  --set initial.theta=1.5707963267948966 --target 'theta<1.22,theta>1.92' \\\n    \
                  --method exact --out out/rare\n  \
                  tippetop rare scenarios/thermal.toml --target 'theta>1.2' --reset 'theta<0.05' \\\n    \
                  --method direct --replicas 2000 --out out/rare\n  \
                  tippetop rare scenarios/thermal.toml --target 'theta>2.5' --reset 'theta<0.05' \\\n    \
                  --method ams --coordinate theta --replicas 20 --out out/rare-ams\n  \
                  tippetop rare --preset nano-physical --set solver.dt=2e-15 \\\n    \
                  --set initial.theta=1.5707963267948966 --target 'theta<1.2208,theta>1.9208' \\\n    \
                  --method ams --out out/lying"
)]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML): a Langevin or Brownian run at temperature > 0")),
    mut_arg("sets", |a| a.help("Override one scenario value, e.g. `--set thermal.temperature=77`; repeatable, applied in order after the file")),
)]
pub struct RareArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,

    /// The target condition (the `--first-passage` grammar), e.g.
    /// `theta<1.22,theta>1.92`.
    #[arg(long, value_name = "COND")]
    pub target: String,

    /// The reset condition: with it, the probability of the target before
    /// the reset.
    #[arg(long, value_name = "COND")]
    pub reset: Option<String>,

    /// exact, direct or ams (default direct).
    #[arg(long, value_name = "METHOD", default_value = "direct")]
    pub method: String,

    /// Independent runs of the direct method (>= 1; default 1000), or
    /// independent replicas of the splitting (>= 2; default 20).
    #[arg(long, value_name = "N")]
    pub replicas: Option<usize>,

    /// ams: the reaction coordinate, whose levels split the paths: a
    /// trajectory.csv column (theta, omega, ...), -COLUMN, |COLUMN-C| (e.g.
    /// '|theta-1.5708|', C in SI units) or tilt_energy [J]. Default: theta
    /// oriented towards the target ('theta>b': theta; 'theta<a': -theta;
    /// both: |theta-c| from the window's middle c, or tilt_energy in the
    /// Langevin mode); theta for a target on other columns.
    #[arg(long, value_name = "XI", allow_hyphen_values = true)]
    pub coordinate: Option<String>,

    /// ams: particles per replica, 2 to 30000 (default 100).
    #[arg(long, value_name = "N")]
    pub particles: Option<usize>,

    /// ams: particles killed per iteration, 1 to particles - 1 (default 1).
    #[arg(long, value_name = "K")]
    pub kill: Option<usize>,

    /// ams: most paths one replica may run, particles to 16777200 (default
    /// 100000); a replica that needs more has no estimate (exit code 3).
    #[arg(long, value_name = "N")]
    pub max_trajectories: Option<u64>,

    /// ams, mean first-passage time: interface crossings a replica's direct
    /// run collects as starting states, 1 to 100000 (default 100).
    #[arg(long, value_name = "N")]
    pub crossings: Option<usize>,

    /// ams, mean first-passage time: step budget of a replica's direct run,
    /// 1 to 10000000 (default 10000000).
    #[arg(long, value_name = "N")]
    pub direct_steps: Option<u64>,

    /// ams, mean first-passage time: steps of the pilot run that places the
    /// basin and the interface, 1000 to 10000000 (default 100000).
    #[arg(long, value_name = "N")]
    pub pilot_steps: Option<u64>,

    /// ams, mean first-passage time: the basin, coordinate <= Z_A (default:
    /// the pilot run's median of the coordinate).
    #[arg(long, value_name = "Z_A", allow_negative_numbers = true)]
    pub basin: Option<f64>,

    /// ams, mean first-passage time: the interface, coordinate > Z_S
    /// (default: the pilot run's 90 % quantile).
    #[arg(long, value_name = "Z_S", allow_negative_numbers = true)]
    pub interface: Option<f64>,

    /// ams: run only the K-th of N blocks of the replicas and write
    /// replicas.json, rare_shard.json and shard.json (join the shards with
    /// tippetop merge: the files of the unsharded run).
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,

    /// Horizon T [s]: p = P(target before reset and before T).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub horizon: Option<f64>,

    /// Step budget of one trajectory, 1 to 20000000 (default 1000000); ams:
    /// of one path counted from its root, 1 to 10000000 (default 10000000).
    #[arg(long, value_name = "N")]
    pub max_steps: Option<u64>,

    /// Skip the step check (the answer again at solver.dt/2 with an
    /// independent seed, about twice the main run's cost): the outputs then
    /// say the step is unchecked.
    #[arg(long)]
    pub no_step_check: bool,

    /// Output directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,

    /// `--threads`.
    #[command(flatten)]
    pub cores: crate::common::args::ThreadsArg,
}

/// A positive value with 4 significant figures from its logarithm (so
/// values past f64 print too: `3.162e+431`).
pub fn fmt_positive(p: Positive) -> String {
    if p.value.is_finite() && p.value > 0.0 && p.value >= 1e-300 {
        return format!("{:.4}", Sig(p.value));
    }
    if p.ln == f64::NEG_INFINITY {
        return "0".into();
    }
    let l10 = p.ln / std::f64::consts::LN_10;
    let mut e = l10.floor();
    let mut m = 10f64.powf(l10 - e);
    if format!("{m:.3}") == "10.000" {
        m = 1.0;
        e += 1.0;
    }
    format!("{m:.3}e{}{}", if e >= 0.0 { "+" } else { "" }, e as i64)
}

/// 4 significant figures: fixed for 1e-3 <= |v| < 1e4, scientific beyond.
struct Sig(f64);

impl std::fmt::Display for Sig {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let v = self.0;
        if !v.is_finite() {
            return write!(f, "{v}");
        }
        let a = v.abs();
        if v == 0.0 {
            write!(f, "0")
        } else if (1e-3..1e4).contains(&a) {
            let digits = (3 - a.log10().floor() as i32).max(0) as usize;
            write!(f, "{v:.digits$}")
        } else {
            write!(f, "{v:.3e}")
        }
    }
}

fn s4(v: f64) -> String {
    format!("{}", Sig(v))
}

/// What is estimated, in words.
fn question(p: &Problem) -> String {
    match p.quantity() {
        Quantity::Probability => {
            let mut s = format!("P({}", p.target);
            if let Some(r) = &p.reset {
                let _ = write!(s, " before {r}");
            }
            if let Some(t) = p.horizon {
                let _ = write!(s, " within {} s", s4(t));
            }
            s.push(')');
            s
        }
        Quantity::MeanFirstPassageTime => format!("mean first-passage time to {}", p.target),
    }
}

fn with_unit(v: f64, q: Quantity) -> String {
    match q {
        Quantity::Probability => s4(v),
        Quantity::MeanFirstPassageTime => format!("{} s", s4(v)),
    }
}

fn interval(ci: [f64; 2], q: Quantity) -> String {
    let hi = if ci[1].is_finite() {
        with_unit(ci[1], q)
    } else {
        "unknown (censored runs)".into()
    };
    format!("{} .. {hi}", with_unit(ci[0], q))
}

/// An exact answer for people: a probability, or a time in seconds (one
/// beyond any time scale in words: rare.json has its logarithm).
fn exact_value(p: Positive, q: Quantity) -> String {
    match q {
        Quantity::Probability => fmt_positive(p),
        Quantity::MeanFirstPassageTime
            if tippetop::human::beyond_any_time_scale(p.ln / std::f64::consts::LN_10) =>
        {
            tippetop::human::BEYOND_ANY_TIME_SCALE.into()
        }
        Quantity::MeanFirstPassageTime => format!("{} s", fmt_positive(p)),
    }
}

fn exact_words(e: &Exact, q: Quantity) -> String {
    let mut s = exact_value(e.value, q);
    // Two times beyond any time scale are one answer.
    let beyond = |t: &str| t == tippetop::human::BEYOND_ANY_TIME_SCALE;
    if let Some(w) = e
        .watched
        .filter(|w| !(beyond(&s) && beyond(&exact_value(*w, q))))
    {
        let _ = write!(
            s,
            " (watched at every step of solver.dt: {})",
            exact_value(w, q)
        );
    }
    s
}

/// The console's summary lines.
fn summary_lines(p: &Problem, r: &Report, wall: f64) -> Vec<String> {
    let q = r.quantity;
    let mut lines = Vec::new();
    match r.method {
        RareMethod::Exact => {
            let e = r.exact.as_ref().expect("the exact method has its answer");
            lines.push(format!(
                "{} = {} (exact, 1D)",
                question(p),
                exact_words(e, q)
            ));
        }
        _ => {
            let bound = r
                .tally
                .as_ref()
                .is_some_and(|t| q == Quantity::MeanFirstPassageTime && t.censored > 0)
                || r.ams
                    .as_ref()
                    .is_some_and(|a| a.estimate.interval == "bound");
            lines.push(format!(
                "{} = {}{} (95 % CI {}), {}: {} trajectories, {} steps, {:.1} s",
                question(p),
                if bound { ">= " } else { "" },
                with_unit(r.estimate, q),
                interval(r.ci95, q),
                r.method.name(),
                r.trajectories,
                r.steps,
                wall
            ));
            if let Some(a) = &r.ams {
                lines.push(ams_line(a, q));
            }
            match &r.exact {
                Some(e) => lines.push(format!("exact (1D): {}", exact_words(e, q))),
                None => lines.push(format!(
                    "exact (1D): not applicable ({})",
                    r.exact_unavailable.clone().unwrap_or_default()
                )),
            }
        }
    }
    lines
}

fn markdown(p: &Problem, r: &Report, wall: f64) -> String {
    let q = r.quantity;
    let mut s = String::new();
    let _ = writeln!(s, "# Rare event: {}\n", question(p));
    let _ = writeln!(
        s,
        "From the scenario's initial state (theta = {} rad), T = {} K, seed {}.\n",
        s4(p.scenario.initial.theta),
        s4(p.scenario.thermal.temperature),
        p.scenario.thermal.seed.unwrap_or(0)
    );
    match r.method {
        RareMethod::Exact => {
            let e = r.exact.as_ref().expect("exact");
            let _ = writeln!(
                s,
                "**Exact (one-dimensional θ diffusion): {}**\n",
                exact_words(e, q)
            );
        }
        _ => {
            let t = r.tally.clone().unwrap_or_default();
            let _ = writeln!(
                s,
                "**{}: {} (95 % interval {})**\n",
                r.method.name(),
                with_unit(r.estimate, q),
                interval(r.ci95, q)
            );
            if let Some(a) = &r.ams {
                let _ = writeln!(s, "{}\n", ams_paragraph(p, r, a, wall));
            } else {
                let _ = writeln!(
                    s,
                    "{} trajectories, {} steps in {:.1} s: {} met the target, {} the reset, {} reached the horizon, {} used their whole budget of {} steps, {} failed.\n",
                    r.trajectories,
                    r.steps,
                    wall,
                    t.target,
                    t.reset,
                    t.horizon,
                    t.censored,
                    p.max_steps,
                    t.failed
                );
            }
            match &r.exact {
                Some(e) => {
                    let _ = writeln!(
                        s,
                        "Exact (one-dimensional θ diffusion): {}.\n",
                        exact_words(e, q)
                    );
                }
                None => {
                    let _ = writeln!(
                        s,
                        "No exact answer here: {}.\n",
                        r.exact_unavailable.clone().unwrap_or_default()
                    );
                }
            }
        }
    }
    if let Some(e) = &r.exact {
        let edge = |e: Option<Edge>, pole: &str| match e {
            Some(e) => format!(
                "{} rad ({})",
                s4(e.theta),
                if e.target { "target" } else { "reset" }
            ),
            None => format!("none (the pole {pole}, reflecting)"),
        };
        let _ = writeln!(
            s,
            "θ window: lower edge {}, upper edge {}.",
            edge(e.lower, "0"),
            edge(e.upper, "π")
        );
    }
    s
}

/// The unit of a coordinate, for the figure's axis.
fn coordinate_unit(xi: &str) -> &'static str {
    let name = xi.trim_start_matches(['-', '|']);
    let name = name.split(['-', '|']).next().unwrap_or("");
    match name {
        "t" => "s",
        "theta" => "rad",
        "theta_dot" | "Omega" | "omega" => "rad/s",
        "N" => "N",
        "slip" | "hx" | "hy" => "m/s",
        "energy" | "work_friction" | "work_applied" | "tilt_energy" => "J",
        "x" | "y" | "z" | "xp" | "yp" => "m",
        "J" => "kg m²/s",
        _ => "1",
    }
}

/// The splitting in one console line.
fn ams_line(a: &AmsPart, q: Quantity) -> String {
    let e = &a.estimate;
    let s = &a.settings;
    let mut l = format!(
        "splitting on {}: {} replicas of {} particles (kill {}), {} levels, standard error {}",
        a.coordinate,
        e.replicas,
        e.particles,
        s.kill,
        e.iterations,
        if e.standard_error.is_finite() {
            with_unit(e.standard_error, q)
        } else {
            "unbounded".into()
        }
    );
    if e.extinct {
        l.push_str("; no particle met the target: the estimate is a bound");
    }
    if e.truncated > 0 {
        let _ = write!(l, "; {} paths cut by --max-steps", e.truncated);
    }
    if e.failed > 0 {
        let _ = write!(l, "; {} paths failed", e.failed);
    }
    l
}

/// The splitting in words, for rare.md.
fn ams_paragraph(p: &Problem, r: &Report, a: &AmsPart, wall: f64) -> String {
    let e = &a.estimate;
    let s = &a.settings;
    let q = r.quantity;
    let mut t = format!(
        "Adaptive multilevel splitting (generalised AMS, Bréhier et al. 2016; docs/physics.md#ams) \
         on the coordinate `{}`: {} independent replicas of {} particles, at least {} killed per \
         level; {} levels, {} trajectories, {} steps in {:.1} s. ",
        a.coordinate, e.replicas, e.particles, s.kill, e.iterations, r.trajectories, r.steps, wall
    );
    let _ = write!(
        t,
        "Standard error {} ({}). ",
        if e.standard_error.is_finite() {
            with_unit(e.standard_error, q)
        } else {
            "unbounded".into()
        },
        match e.interval {
            "student_t" => "the 95 % interval is the replicas' mean ± Student's t standard errors",
            "rule_of_three" =>
                "no particle of any replica met the target: the estimate is 0 and the interval's upper end is 1 − 0.05^(1/(particles × replicas))",
            "lognormal_delta" =>
                "flux relation, delta method over the replicas, log-normal 95 % interval",
            "bound" => "no particle met the target: the time is bounded below only",
            other => other,
        }
    );
    if let Some(f) = &e.flux {
        let unit = coordinate_unit(&a.coordinate);
        let _ = write!(
            t,
            "Flux relation τ = T₁ + C (1/p − 1) + S: basin {} ≤ {} {unit}, interface {} > {} {unit}; p = {} \
             (P(target before the basin) from a crossing), T₁ = {} s, C = {} s, S = {}; escape rate {} 1/s. ",
            a.coordinate,
            s4(f.basin),
            a.coordinate,
            s4(f.interface),
            s4(f.probability),
            s4(f.first_crossing_time),
            s4(f.cycle_time),
            f.transit_time
                .map(|x| format!("{} s", s4(x)))
                .unwrap_or_else(|| "unknown".into()),
            s4(f.rate)
        );
    }
    if e.truncated > 0 {
        let _ = write!(
            t,
            "{} paths were cut by the step budget ({} steps from their root): the estimate is of the event within that budget. ",
            e.truncated, p.max_steps
        );
    }
    if e.failed > 0 {
        let _ = write!(
            t,
            "{} paths failed (first: {}). ",
            e.failed,
            e.first_failure.clone().unwrap_or_default()
        );
    }
    t.push_str("\n\n![splitting levels](levels.png)\n\nThe figure: each replica's levels Z_j of the coordinate against the estimated probability that a path's maximum of the coordinate passes them, Π(1 − K/n) (one curve per replica).");
    t.trim_end().to_string()
}

/// `levels.png`/`.svg` in `dir`: each replica's staircase (level, estimated
/// P(max ξ > level)), with the estimate and the exact value as lines; the
/// legend where the staircases (falling to the right) leave room.
fn levels_figure(dir: &Path, r: &Report, a: &AmsPart) -> Result<()> {
    use crate::plot::{PlotOpts, Series, line_plot};
    let mut series = Vec::new();
    let mut lo = 1.0f64;
    let (mut x0, mut x1) = (f64::INFINITY, f64::NEG_INFINITY);
    for (i, rep) in a.replicas.iter().enumerate() {
        let (xs, ys): (Vec<f64>, Vec<f64>) = rep
            .levels
            .iter()
            .filter(|l| l[0].is_finite() && l[0] > f64::MIN && l[1] > f64::MIN)
            .map(|l| (l[0], 10f64.powf(l[1])))
            .unzip();
        for &x in &xs {
            x0 = x0.min(x);
            x1 = x1.max(x);
        }
        if let Some(m) = ys.iter().copied().reduce(f64::min) {
            lo = lo.min(m);
        }
        let name = if i == 0 {
            format!("replicas ({}), one staircase each", a.replicas.len())
        } else {
            String::new()
        };
        series.push(Series::new(name, xs, ys).color((31, 119, 180)).width(1));
    }
    if x0 >= x1 {
        (x0, x1) = (0.0, 1.0);
    }
    let p_final = match &a.estimate.flux {
        Some(f) => f.probability,
        None => r.estimate,
    };
    if p_final > 0.0 {
        let what = match &a.estimate.flux {
            Some(_) => "p, from the interface to the target,",
            None => "estimate",
        };
        series.push(
            Series::new(
                format!("{what} {}", s4(p_final)),
                vec![x0, x1],
                vec![p_final; 2],
            )
            .color((0, 0, 0))
            .dashed(),
        );
        lo = lo.min(p_final);
    }
    if r.quantity == Quantity::Probability {
        if let Some(w) = r.exact.and_then(|e| e.watched) {
            if w.value > 0.0 && w.value.is_finite() {
                series.push(
                    Series::new(
                        format!("exact (1D, watched every step) {}", s4(w.value)),
                        vec![x0, x1],
                        vec![w.value; 2],
                    )
                    .color((214, 39, 40))
                    .dashed(),
                );
                lo = lo.min(w.value);
            }
        }
    }
    let unit = coordinate_unit(&a.coordinate);
    let y_label = match &a.estimate.flux {
        Some(_) => "P(max ξ > level | crossing) [1]",
        None => "P(max ξ > level) [1]",
    };
    let opts = PlotOpts {
        log_y: true,
        y_range: Some((lo / 10.0, 1.5)),
        ..PlotOpts::default()
    };
    line_plot(
        &dir.join("levels"),
        &format!("Splitting levels: {} replicas", a.replicas.len()),
        &format!("level of ξ = {} [{unit}]", a.coordinate),
        y_label,
        &series,
        &opts,
    )
}

/// What defines a splitting's output (`--method ams`): the scenario's
/// sources and every option that changes a figure. A shard records it in
/// `rare_shard.json`; `tippetop merge` rebuilds the question from it.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct AmsInputs {
    /// `--preset`.
    pub preset: Option<String>,
    /// The scenario file's text.
    pub toml_text: Option<String>,
    /// `--set`, in order.
    pub sets: Vec<String>,
    /// `--target`.
    pub target: String,
    /// `--reset`.
    pub reset: Option<String>,
    /// `--horizon` \[s\].
    pub horizon: Option<f64>,
    /// `--max-steps`.
    pub max_steps: Option<u64>,
    /// `--coordinate`.
    pub coordinate: Option<String>,
    /// `--replicas`.
    pub replicas: Option<usize>,
    /// `--particles`.
    pub particles: Option<usize>,
    /// `--kill`.
    pub kill: Option<usize>,
    /// `--max-trajectories`.
    pub max_trajectories: Option<u64>,
    /// `--crossings`.
    pub crossings: Option<usize>,
    /// `--direct-steps`.
    pub direct_steps: Option<u64>,
    /// `--pilot-steps`.
    pub pilot_steps: Option<u64>,
    /// `--basin`.
    pub basin: Option<f64>,
    /// `--interface`.
    pub interface: Option<f64>,
}

impl AmsInputs {
    fn of(args: &RareArgs, toml_text: Option<String>) -> AmsInputs {
        AmsInputs {
            preset: args.source.preset.clone(),
            toml_text,
            sets: args.source.sets.clone(),
            target: args.target.clone(),
            reset: args.reset.clone(),
            horizon: args.horizon,
            max_steps: args.max_steps,
            coordinate: args.coordinate.clone(),
            replicas: args.replicas,
            particles: args.particles,
            kill: args.kill,
            max_trajectories: args.max_trajectories,
            crossings: args.crossings,
            direct_steps: args.direct_steps,
            pilot_steps: args.pilot_steps,
            basin: args.basin,
            interface: args.interface,
        }
    }

    /// The question and its splitting (the checks of [`Problem::new`] and
    /// [`problem::ams_for`]; runs the pilot run of a mean first-passage
    /// time).
    fn setup(&self) -> Result<(Problem, Ams), tippetop::Error> {
        let scenario = tippetop::Scenario::load(
            self.preset.as_deref(),
            self.toml_text.as_deref(),
            &self.sets,
        )?;
        let prob = Problem::for_ams(
            scenario,
            &self.target,
            self.reset.as_deref(),
            self.horizon,
            self.max_steps,
        )?;
        let ams = problem::ams_for(&prob, self.coordinate.as_deref(), self.settings())?;
        Ok((prob, ams))
    }

    /// The splitting's settings: the options given, the defaults for the
    /// rest (the question's step budget is [`problem::ams_for`]'s).
    fn settings(&self) -> Settings {
        let d = Settings::default();
        Settings {
            replicas: self.replicas.unwrap_or(d.replicas),
            particles: self.particles.unwrap_or(d.particles),
            kill: self.kill.unwrap_or(d.kill),
            max_trajectories: self.max_trajectories.unwrap_or(d.max_trajectories),
            crossings: self.crossings.unwrap_or(d.crossings),
            direct_steps: self.direct_steps.unwrap_or(d.direct_steps),
            pilot_steps: self.pilot_steps.unwrap_or(d.pilot_steps),
            basin: self.basin,
            interface: self.interface,
            ..d
        }
    }

    /// The fingerprint of the splitting, for its shards.
    fn fingerprint(&self) -> String {
        let grid = tippetop::analysis::sweep::Sweep {
            preset: self.preset.clone(),
            toml_text: self.toml_text.clone(),
            sets: self.sets.clone(),
            axes: Vec::new(),
        };
        let options = serde_json::to_string(self).unwrap_or_default();
        grid.fingerprint_of("tippetop rare 1", &[("options", options)])
    }
}

/// The step check's line of the console and rare.md.
fn check_line(checked: &Checked, q: Quantity) -> String {
    match checked {
        Checked::Done { check, .. } => check.words(&|v| with_unit(v, q)),
        Checked::Off(why) => format!("step unchecked ({why})"),
    }
}

/// The options of the splitting that other methods refuse.
fn ams_only(args: &RareArgs) -> Option<&'static str> {
    [
        (args.coordinate.is_some(), "--coordinate"),
        (args.particles.is_some(), "--particles"),
        (args.kill.is_some(), "--kill"),
        (args.max_trajectories.is_some(), "--max-trajectories"),
        (args.crossings.is_some(), "--crossings"),
        (args.direct_steps.is_some(), "--direct-steps"),
        (args.pilot_steps.is_some(), "--pilot-steps"),
        (args.basin.is_some(), "--basin"),
        (args.interface.is_some(), "--interface"),
        (args.shard.is_some(), "--shard"),
    ]
    .into_iter()
    .find(|(given, _)| *given)
    .map(|(_, key)| key)
}

/// Run `tippetop rare`. Bad input: one line and exit code 2 (returned as
/// `Ok`), nothing written; `Err` for I/O failures.
pub fn run(args: &RareArgs, quiet: bool) -> Result<ExitCode> {
    let started = std::time::Instant::now();
    let toml_text = match crate::scenario_load::read_text(args.source.scenario.as_deref()) {
        Ok(t) => t,
        Err(code) => return Ok(code),
    };
    let method = match RareMethod::parse(&args.method) {
        Ok(m) => m,
        Err(e) => return Ok(input_error(e)),
    };
    if let Err(e) = tippetop::analysis::sweep::threads(args.cores.threads) {
        return Ok(input_error(e));
    }
    if method != RareMethod::Ams {
        if let Some(key) = ams_only(args) {
            return Ok(input_error(format!(
                "{key}: given with --method {} (an option of --method ams)",
                method.name()
            )));
        }
    } else {
        return run_ams(args, AmsInputs::of(args, toml_text), started, quiet);
    }
    let scenario = match tippetop::Scenario::load(
        args.source.preset.as_deref(),
        toml_text.as_deref(),
        &args.source.sets,
    ) {
        Ok(s) => s,
        Err(e) => return Ok(input_error(e)),
    };
    let prob = match Problem::new(
        scenario,
        &args.target,
        args.reset.as_deref(),
        args.horizon,
        args.max_steps,
    ) {
        Ok(p) => p,
        Err(e) => return Ok(input_error(e)),
    };
    let replicas = args.replicas.unwrap_or(DEFAULT_REPLICAS);
    let report = match method {
        RareMethod::Ams => unreachable!("handled above"),
        RareMethod::Exact => {
            if args.replicas.is_some() {
                return Ok(input_error(
                    "--replicas: given with --method exact (which runs no trajectory)",
                ));
            }
            match problem::by_exact(&prob) {
                Ok(r) => r,
                Err(e) if e.is_input() => return Ok(input_error(e)),
                Err(e) => return Err(e.into()),
            }
        }
        RareMethod::Direct => {
            if replicas == 0 || replicas as u64 > tippetop::input::thermal::MAX_RUNS {
                return Ok(input_error(format!(
                    "--replicas: {replicas} is not allowed (N >= 1, the run indices below 4294967296)"
                )));
            }
            let out = OutDir::open(&args.out)?;
            let pb = crate::progress::bar(quiet, replicas as u64, "rare (direct)");
            let r = problem::by_direct(&prob, replicas, args.cores.threads, &mut |done| {
                pb.set_position(done as u64);
                true
            });
            pb.finish_and_clear();
            let r = r.and_then(|r| {
                if args.no_step_check {
                    return Ok((r, Checked::Off("--no-step-check".into())));
                }
                let fine = rare_step::refined_problem(&prob, RareMethod::Direct)?;
                let pb = crate::progress::bar(
                    quiet,
                    replicas as u64,
                    "rare (direct) step check at dt/2",
                );
                let f = problem::by_direct(&fine, replicas, args.cores.threads, &mut |done| {
                    pb.set_position(done as u64);
                    true
                });
                pb.finish_and_clear();
                let c = Checked::of(&prob, &r, &f?);
                Ok((r, c))
            });
            match r {
                Ok((r, c)) => return finish(&args.out, &prob, &r, &c, out, started, quiet),
                Err(e) => {
                    out.abandon();
                    if e.is_input() {
                        return Ok(input_error(e));
                    }
                    return Err(e.into());
                }
            }
        }
    };
    let out = OutDir::open(&args.out)?;
    let checked = Checked::Off(rare_step::EXACT_UNCHECKED.into());
    finish(&args.out, &prob, &report, &checked, out, started, quiet)
}

/// File of a shard's replicas.
const REPLICAS_JSON: &str = "replicas.json";
/// File of a shard's inputs.
const INPUTS_JSON: &str = "rare_shard.json";

/// A replica as a shard writes it: a level at `-inf` (a particle that met
/// the reset at once) becomes `f64::MIN`, which JSON can hold (the picture
/// leaves both out).
fn storable(mut r: Replica) -> Replica {
    for l in &mut r.levels {
        if !l[0].is_finite() {
            l[0] = f64::MIN;
        }
        if !l[1].is_finite() {
            l[1] = f64::MIN;
        }
    }
    r
}

/// `--method ams`: the replicas (all, or a shard's), then the report (or
/// the shard's files).
fn run_ams(
    args: &RareArgs,
    inputs: AmsInputs,
    started: std::time::Instant,
    quiet: bool,
) -> Result<ExitCode> {
    let shard = match args
        .shard
        .as_deref()
        .map(tippetop::analysis::sweep::Shard::parse)
        .transpose()
    {
        Ok(s) => s,
        Err(e) => return Ok(input_error(e)),
    };
    let setup = if quiet {
        inputs.setup()
    } else {
        let sp = crate::progress::spinner(quiet, "rare (ams): checking the question");
        let r = inputs.setup();
        sp.finish_and_clear();
        r
    };
    let (prob, ams) = match setup {
        Ok(x) => x,
        Err(e) if e.is_input() => return Ok(input_error(e)),
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(3));
        }
    };
    let m = ams.settings().replicas;
    let range = match shard {
        None => 0..m,
        Some(sh) => match tippetop::analysis::sweep::shard_range(m, sh) {
            Ok(r) => r,
            Err(e) => {
                return Ok(input_error(
                    e.to_string()
                        .replace("a sweep of", "a splitting of")
                        .replace("cases", "replicas")
                        .replace("case", "replica"),
                ));
            }
        },
    };
    // The particles of the replicas running at once, and the records of
    // all, within the memory bound: checked before anything is written.
    let asked = match tippetop::analysis::sweep::threads(args.cores.threads) {
        Ok(t) => t,
        Err(e) => return Ok(input_error(e)),
    };
    match ams.threads_within_memory(asked) {
        Ok(t) => {
            crate::scenario_load::note_threads(quiet, asked.min(m), t);
        }
        Err(e) => return Ok(input_error(e)),
    }
    let out = OutDir::open(&args.out)?;
    let replicas = match replicas_of(
        &ams,
        range.clone(),
        args.cores.threads,
        quiet,
        "rare (ams) replicas",
    ) {
        Ok(r) => r,
        Err(e) => {
            out.abandon();
            return Ok(input_error(e));
        }
    };
    if let Some(sh) = shard {
        return write_shard(out, &args.out, &inputs, sh, m, range, &replicas, quiet);
    }
    let report = match problem::by_ams(&prob, &ams, replicas.clone()) {
        Ok(r) => r,
        Err(e) if e.is_input() => {
            out.abandon();
            return Ok(input_error(e));
        }
        Err(e) => return partial_replicas(out, &args.out, &replicas, &e),
    };
    let checked = if args.no_step_check {
        Checked::Off("--no-step-check".into())
    } else {
        match refined_ams(&inputs, &prob, &report, args.cores.threads, quiet) {
            Ok(c) => c,
            Err(e) => {
                out.abandon();
                return Ok(input_error(e));
            }
        }
    };
    finish(&args.out, &prob, &report, &checked, out, started, quiet)
}

/// The step check of a splitting: the same splitting at `solver.dt / 2`
/// ([`rare_step::refined_ams`]), all its replicas, compared with `report`
/// (the answer to `prob`).
fn refined_ams(
    inputs: &AmsInputs,
    prob: &Problem,
    report: &Report,
    threads: Option<usize>,
    quiet: bool,
) -> Result<Checked, tippetop::Error> {
    let fine = rare_step::refined_ams(prob, inputs.coordinate.as_deref(), &inputs.settings())?;
    let m = fine.1.settings().replicas;
    let reps = replicas_of(
        &fine.1,
        0..m,
        threads,
        quiet,
        "rare (ams) step check at dt/2",
    )?;
    Checked::of_ams(prob, report, &fine, reps)
}

/// Run the replicas `range` of `ams` with a progress bar labelled `label`
/// (on a terminal it counts the steps run meanwhile).
fn replicas_of(
    ams: &Ams,
    range: std::ops::Range<usize>,
    threads: Option<usize>,
    quiet: bool,
    label: &str,
) -> Result<Vec<Replica>, tippetop::Error> {
    let pb = crate::progress::bar(quiet, range.len() as u64, label);
    let len = range.len() as f64;
    let progress = |f: f64| pb.set_position((f * len).round() as u64);
    // A replica of many particles runs for minutes: the bar says how many
    // steps have run meanwhile.
    let steps = std::sync::atomic::AtomicU64::new(0);
    let ticking = std::sync::atomic::AtomicBool::new(true);
    let hooks = Hooks {
        progress: Some(&progress),
        cancel: None,
        steps: Some(&steps),
    };
    let mut replicas = Vec::with_capacity(range.len());
    let ran = std::thread::scope(|sc| {
        if crate::progress::visible(quiet) {
            sc.spawn(|| {
                while ticking.load(std::sync::atomic::Ordering::Relaxed) {
                    let n = steps.load(std::sync::atomic::Ordering::Relaxed);
                    pb.set_message(format!(
                        "{label}, {} steps",
                        tippetop::human::sig(n as f64, 3)
                    ));
                    std::thread::sleep(std::time::Duration::from_millis(250));
                }
            });
        }
        let ran = ams.run(range.clone(), threads, hooks, &mut |r| {
            replicas.push(storable(r));
            true
        });
        ticking.store(false, std::sync::atomic::Ordering::Relaxed);
        ran
    });
    pb.finish_and_clear();
    ran.map(|_| replicas)
}

/// A splitting that did not finish (a replica out of budget): the
/// replicas (partial output) in replicas.json, the error, exit code 3.
fn partial_replicas(
    out: OutDir,
    dir: &Path,
    replicas: &[Replica],
    e: &tippetop::Error,
) -> Result<ExitCode> {
    let mut text = serde_json::to_string_pretty(&serde_json::json!({ "replicas": replicas }))?;
    text.push('\n');
    write_bytes_atomic(&out.stage().join(REPLICAS_JSON), text.as_bytes())?;
    out.commit(&[REPLICAS_JSON])?;
    eprintln!(
        "error: {e} (the replicas are in {})",
        dir.join(REPLICAS_JSON).display()
    );
    Ok(ExitCode::from(3))
}

/// A shard of a splitting: replicas.json (its replicas),
/// rare_shard.json (the inputs), shard.json (what it covers, checksums).
#[allow(clippy::too_many_arguments)]
fn write_shard(
    out: OutDir,
    dir: &Path,
    inputs: &AmsInputs,
    sh: tippetop::analysis::sweep::Shard,
    total: usize,
    range: std::ops::Range<usize>,
    replicas: &[Replica],
    quiet: bool,
) -> Result<ExitCode> {
    let info = ShardInfo {
        fingerprint: inputs.fingerprint(),
        k: sh.k,
        n: sh.n,
        total_cases: total,
        first_index: range.start,
        end_index: range.end,
        axes: Vec::new(),
        checksums: Default::default(),
    };
    let mut reps = serde_json::to_string_pretty(&serde_json::json!({ "replicas": replicas }))?;
    reps.push('\n');
    let mut inp = serde_json::to_string_pretty(inputs)?;
    inp.push('\n');
    let stage = out.stage().to_path_buf();
    write_bytes_atomic(&stage.join(REPLICAS_JSON), reps.as_bytes())?;
    write_bytes_atomic(&stage.join(INPUTS_JSON), inp.as_bytes())?;
    crate::common::grid::write_info(
        &stage,
        &info,
        &[
            (REPLICAS_JSON, checksum(reps.as_bytes())),
            (INPUTS_JSON, checksum(inp.as_bytes())),
        ],
    )?;
    out.commit(&["shard.json"])?;
    if !quiet {
        println!(
            "shard {}/{}: replicas {}..{} of {total} -> {}",
            sh.k,
            sh.n,
            range.start,
            range.end,
            dir.join(REPLICAS_JSON).display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Whether `dir` holds a shard of a splitting (`rare_shard.json` beside
/// `shard.json`), for `tippetop merge`.
pub fn is_rare_shard_dir(dir: &Path) -> bool {
    dir.join(INPUTS_JSON).is_file() && dir.join("shard.json").is_file()
}

#[derive(serde::Deserialize)]
struct ReplicasFile {
    replicas: Vec<Replica>,
}

/// `tippetop merge` of the shards of one splitting: rare.json, rare.md and
/// the levels' figure of the unsharded run (the same bytes apart from
/// wall_seconds, here the merge's time).
pub fn merge(args: &crate::common::args::MergeArgs, quiet: bool) -> Result<ExitCode> {
    let started = std::time::Instant::now();
    let what = "a directory written by tippetop rare --method ams --shard, with shard.json, \
                rare_shard.json and replicas.json";
    let mut shards: Vec<(ShardInfo, Vec<Replica>, AmsInputs)> = Vec::new();
    for dir in &args.dirs {
        let _reading = crate::output::read_lock(dir)?;
        let got = (|| {
            let small = |name: &str| crate::scenario_load::read_small(&dir.join(name), what);
            let info: ShardInfo = serde_json::from_str(&small("shard.json")?)
                .map_err(|e| format!("{}: {e} ({what})", dir.join("shard.json").display()))?;
            let (reps, inp) = (small(REPLICAS_JSON)?, small(INPUTS_JSON)?);
            check_checksum(&info.checksums, dir, REPLICAS_JSON, reps.as_bytes())?;
            check_checksum(&info.checksums, dir, INPUTS_JSON, inp.as_bytes())?;
            let reps: ReplicasFile = serde_json::from_str(&reps)
                .map_err(|e| format!("{}: {e} ({what})", dir.join(REPLICAS_JSON).display()))?;
            let inp: AmsInputs = serde_json::from_str(&inp)
                .map_err(|e| format!("{}: {e} ({what})", dir.join(INPUTS_JSON).display()))?;
            Ok::<_, String>((info, reps.replicas, inp))
        })();
        match got {
            Ok(s) => shards.push(s),
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    let (first, _, inputs) = &shards[0];
    for (i, (info, reps, inp)) in shards.iter().enumerate() {
        if inp != inputs
            || info.fingerprint != first.fingerprint
            || info.fingerprint != inp.fingerprint()
        {
            return Ok(input_error(format!(
                "merge: {} is a shard of another splitting than {} (all shards from one tippetop \
                 rare --method ams: same scenario, --set and options)",
                args.dirs[i].display(),
                args.dirs[0].display()
            )));
        }
        let indices: Vec<usize> = reps.iter().map(|r| r.index).collect();
        let want: Vec<usize> = (info.first_index..info.end_index).collect();
        if indices != want || info.total_cases != first.total_cases {
            return Ok(input_error(format!(
                "merge: {}: replicas.json does not hold the replicas {}..{} its shard.json names \
                 ({what})",
                args.dirs[i].display(),
                info.first_index,
                info.end_index
            )));
        }
    }
    let mut order: Vec<&(ShardInfo, Vec<Replica>, AmsInputs)> = shards.iter().collect();
    order.sort_by_key(|s| (s.0.first_index, s.0.end_index));
    let mut replicas: Vec<Replica> = Vec::new();
    for (info, reps, _) in order {
        if info.first_index != replicas.len() {
            return Ok(input_error(format!(
                "merge: replicas {}..{} of {} are {} (shards that cover every replica exactly once)",
                replicas.len().min(info.first_index),
                replicas.len().max(info.first_index),
                first.total_cases,
                if info.first_index > replicas.len() {
                    "missing"
                } else {
                    "in two shards"
                }
            )));
        }
        replicas.extend(reps.iter().cloned());
    }
    if replicas.len() != first.total_cases {
        return Ok(input_error(format!(
            "merge: replicas {}..{} are missing (shards that cover every replica exactly once)",
            replicas.len(),
            first.total_cases
        )));
    }
    let (prob, ams) = match inputs.setup() {
        Ok(x) => x,
        Err(e) => return Ok(input_error(format!("merge: {e}"))),
    };
    if ams.settings().replicas != replicas.len() {
        return Ok(input_error(format!(
            "merge: {} replicas for a splitting of {} ({what})",
            replicas.len(),
            ams.settings().replicas
        )));
    }
    let out = OutDir::open(&args.out)?;
    let checked = Checked::Off(
        "a merge of shards: run the splitting with --set solver.dt=DT/2 and compare".into(),
    );
    match problem::by_ams(&prob, &ams, replicas.clone()) {
        Ok(r) => finish(&args.out, &prob, &r, &checked, out, started, quiet),
        Err(e) if e.is_input() => {
            out.abandon();
            Ok(input_error(e))
        }
        Err(e) => partial_replicas(out, &args.out, &replicas, &e),
    }
}

/// Write rare.json and rare.md, print the summary; exit code 3 if runs
/// failed.
fn finish(
    dir: &Path,
    prob: &Problem,
    report: &Report,
    checked: &Checked,
    out: OutDir,
    started: std::time::Instant,
    quiet: bool,
) -> Result<ExitCode> {
    let wall = started.elapsed().as_secs_f64();
    let stage = out.stage().to_path_buf();
    let doc = checked.document(report.document(prob, wall));
    let mut text = serde_json::to_string_pretty(&doc)?;
    text.push('\n');
    write_bytes_atomic(&stage.join("rare.json"), text.as_bytes())?;
    let mut md = markdown(prob, report, wall);
    let _ = writeln!(md, "\n{}.", check_line(checked, report.quantity));
    write_bytes_atomic(&stage.join("rare.md"), md.as_bytes())?;
    if let Some(a) = &report.ams {
        levels_figure(&stage, report, a)?;
    }
    out.commit(&["rare.json"])?;
    if !quiet {
        for l in summary_lines(prob, report, wall) {
            println!("{l}");
        }
        println!("{}", check_line(checked, report.quantity));
        println!("wrote {}", dir.display());
    }
    if let Some(t) = &report.tally {
        if t.failed > 0 {
            eprintln!(
                "error: {} of {} runs failed (first: {})",
                t.failed,
                t.runs(),
                t.first_error.clone().unwrap_or_default()
            );
            return Ok(ExitCode::from(3));
        }
    }
    if let Some(a) = &report.ams {
        if a.estimate.failed > 0 {
            eprintln!(
                "error: {} paths failed (first: {}); the estimate counts them as not reaching the target",
                a.estimate.failed,
                a.estimate.first_failure.clone().unwrap_or_default()
            );
            return Ok(ExitCode::from(3));
        }
    }
    Ok(ExitCode::SUCCESS)
}
