//! The table of runs the reproduction makes, and the measurements the
//! figures and claims take of them.
//!
//! Every run is a scenario file of `scenarios/` plus `--set` overrides and
//! always the paper's own equations (`solver.model = "reduced"`, the
//! Euler-angle model), whatever the library's default model is. The
//! settings string of each run is the command line that reproduces it.

use tippetop::analysis::asymptotics::interp;
use tippetop::{Error, Sample, Scenario, Trajectory, simulate};

use crate::{Options, Run};

/// Scenario files, embedded so the binary needs nothing on disk.
pub const SCENARIOS: [(&str, &str); 5] = [
    ("nano.toml", include_str!("../../../scenarios/nano.toml")),
    (
        "fig06_reversal.toml",
        include_str!("../../../scenarios/fig06_reversal.toml"),
    ),
    (
        "fig07_classical.toml",
        include_str!("../../../scenarios/fig07_classical.toml"),
    ),
    (
        "fig12_step_8us.toml",
        include_str!("../../../scenarios/fig12_step_8us.toml"),
    ),
    (
        "fig14_step_1us.toml",
        include_str!("../../../scenarios/fig14_step_1us.toml"),
    ),
];

/// The overrides that make a scenario the paper's literal contact law.
pub const PAPER_SETS: [&str; 2] = [
    "surface.friction_law=\"coulomb_sliding\"",
    "surface.contact=\"paper\"",
];

// Run names used by the figures and claims.
/// Nano, constant force, bilateral contact, exact Coulomb (accurate).
pub const NANO_BILATERAL: &str = "nano_bilateral";
/// As [`NANO_BILATERAL`] with g = 0.
pub const NANO_BILATERAL_G0: &str = "nano_bilateral_g0";
/// As [`NANO_BILATERAL`] with g = 100 m/s².
pub const NANO_BILATERAL_G100: &str = "nano_bilateral_g100";
/// Nano, the paper's contact law, solved accurately.
pub const NANO_PAPER: &str = "nano_paper";
/// As [`NANO_PAPER`] with g = 0.
pub const NANO_PAPER_G0: &str = "nano_paper_g0";
/// As [`NANO_PAPER`] with g = 100 m/s².
pub const NANO_PAPER_G100: &str = "nano_paper_g100";
/// Nano, the paper's contact law with the paper's RK4 on 500 steps.
pub const NANO_PAPER_RK4: &str = "nano_paper_rk4_500";
/// The C/A ratios of the study of the claim "C/A does not matter".
pub const C_OVER_A: [f64; 3] = [0.2, 0.5, 0.8];
/// Force reversed at 100 µs, bilateral.
pub const REVERSAL_BILATERAL: &str = "reversal_bilateral";
/// Force reversed, paper contact.
pub const REVERSAL_PAPER: &str = "reversal_paper";
/// Force reversed, paper contact, RK4/500.
pub const REVERSAL_PAPER_RK4: &str = "reversal_paper_rk4_500";
/// Classical top, exact Coulomb friction.
pub const CLASSICAL_EXACT: &str = "classical_exact_coulomb";
/// Classical top, regularised friction with ε = 1e-2 m/s.
pub const CLASSICAL_REGULARIZED: &str = "classical_regularized_1e-2";
/// Classical top, Coulomb–Contensou friction over a Hertz contact disc of
/// radius 0.3 mm (docs/physics.md#contensou).
pub const CLASSICAL_CONTENSOU: &str = "classical_contensou_0.3mm";
/// Classical top, sliding Coulomb, RK4/500.
pub const CLASSICAL_RK4: &str = "classical_sliding_rk4_500";
/// App. D, force off at 8 µs: bilateral, paper contact, RK4/500.
pub const STEP8: [&str; 3] = [
    "step8us_bilateral",
    "step8us_paper",
    "step8us_paper_rk4_500",
];
/// App. D, force off at 1 µs: bilateral, paper contact, RK4/500.
pub const STEP1: [&str; 3] = [
    "step1us_bilateral",
    "step1us_paper",
    "step1us_paper_rk4_500",
];

/// The name of the C/A study's run for `ratio`.
pub fn c_over_a_name(ratio: f64) -> String {
    format!("nano_bilateral_C_over_A_{ratio}")
}

/// One run of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// Short name.
    pub name: String,
    /// Scenario file of `scenarios/`.
    pub file: &'static str,
    /// `--set` overrides after the file.
    pub sets: Vec<String>,
    /// The paper's method: RK4 on 500 steps, 501 samples.
    pub rk4: bool,
}

fn spec(name: &str, file: &'static str, sets: &[&str], rk4: bool) -> RunSpec {
    RunSpec {
        name: name.to_string(),
        file,
        sets: sets.iter().map(|s| s.to_string()).collect(),
        rk4,
    }
}

/// Every run, in the order of the report's run table.
pub fn specs() -> Vec<RunSpec> {
    let (nano, rev, cl) = ("nano.toml", "fig06_reversal.toml", "fig07_classical.toml");
    let (s8, s1) = ("fig12_step_8us.toml", "fig14_step_1us.toml");
    let p = PAPER_SETS;
    let mut v = vec![
        spec(NANO_BILATERAL, nano, &[], false),
        spec(NANO_BILATERAL_G0, nano, &["surface.gravity=0"], false),
        spec(NANO_BILATERAL_G100, nano, &["surface.gravity=100"], false),
        spec(NANO_PAPER, nano, &p, false),
        spec(
            NANO_PAPER_G0,
            nano,
            &[p[0], p[1], "surface.gravity=0"],
            false,
        ),
        spec(
            NANO_PAPER_G100,
            nano,
            &[p[0], p[1], "surface.gravity=100"],
            false,
        ),
        spec(NANO_PAPER_RK4, nano, &p, true),
    ];
    // A of the nano preset: 2/3 m r² of a C60 shell (m = 1.196e-24 kg,
    // r = 3.55e-10 m); C = ratio · A.
    let a_val = 2.0 / 3.0 * 1.196e-24 * 3.55e-10f64.powi(2);
    for ratio in C_OVER_A {
        let set = format!("top.inertia_axial={:e}", ratio * a_val);
        v.push(spec(&c_over_a_name(ratio), nano, &[&set], false));
    }
    v.extend([
        spec(REVERSAL_BILATERAL, rev, &[], false),
        spec(REVERSAL_PAPER, rev, &p, false),
        spec(REVERSAL_PAPER_RK4, rev, &p, true),
        spec(CLASSICAL_EXACT, cl, &[], false),
        spec(
            CLASSICAL_REGULARIZED,
            cl,
            &[
                "surface.friction_law=\"regularized\"",
                "surface.friction_eps=1e-2",
            ],
            false,
        ),
        spec(
            CLASSICAL_CONTENSOU,
            cl,
            &[
                "surface.friction_law=\"contensou\"",
                "surface.contact_radius=3e-4",
            ],
            false,
        ),
        spec(
            CLASSICAL_RK4,
            cl,
            &["surface.friction_law=\"coulomb_sliding\""],
            true,
        ),
        spec(STEP8[0], s8, &[], false),
        spec(STEP8[1], s8, &p, false),
        spec(STEP8[2], s8, &p, true),
        spec(STEP1[0], s1, &[], false),
        spec(STEP1[1], s1, &p, false),
        spec(STEP1[2], s1, &p, true),
    ]);
    v
}

/// The text of an embedded scenario file.
pub fn scenario_text(name: &str) -> Option<&'static str> {
    SCENARIOS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// The scenario of `spec` and its settings string (the command line that
/// reproduces it).
pub fn load(spec: &RunSpec, opts: Options) -> Result<(Scenario, String), Error> {
    let mut all: Vec<String> = vec!["solver.model=\"reduced\"".into()];
    all.extend(spec.sets.iter().cloned());
    if spec.rk4 {
        all.push("solver.method=\"rk4\"".into());
        all.push("solver.steps=500".into());
        all.push("solver.samples=501".into());
    }
    let text = scenario_text(spec.file).ok_or_else(|| {
        Error::invalid(
            "scenario",
            format!("{} is not an embedded scenario", spec.file),
            "one of scenarios/*.toml".into(),
        )
    })?;
    let mut sc = Scenario::load(None, Some(text), &all)?;
    if opts.quick {
        sc.solver.t_end /= 10.0;
        for w in &mut sc.forcing.windows {
            w.start /= 10.0;
            w.stop /= 10.0;
        }
        all.push(format!(
            "(quick: windows / 10, t_end = {:e})",
            sc.solver.t_end
        ));
    }
    let settings = format!("scenarios/{} --set {}", spec.file, all.join(" --set "));
    Ok((sc, settings))
}

/// The runs made, looked up by name.
#[derive(Debug, Clone)]
pub struct Runs(Vec<Run>);

impl Runs {
    /// Run every spec in order; `progress` gets each name as it starts.
    pub fn execute(
        specs: &[RunSpec],
        opts: Options,
        progress: &mut dyn FnMut(&str),
    ) -> Result<Runs, Error> {
        let mut runs = Vec::with_capacity(specs.len());
        for s in specs {
            let (scenario, settings) = load(s, opts)?;
            progress(&s.name);
            let trajectory = simulate(&scenario)?;
            runs.push(Run {
                name: s.name.clone(),
                settings,
                scenario,
                trajectory,
            });
        }
        Ok(Runs(runs))
    }

    /// The run called `name`. Panics if the table has no such run: the
    /// names are this crate's constants, and the tests run every lookup.
    pub fn get(&self, name: &str) -> &Run {
        self.0
            .iter()
            .find(|r| r.name == name)
            .unwrap_or_else(|| panic!("no run {name} in the reproduction's table"))
    }

    /// The trajectory of the run called `name`.
    pub fn tr(&self, name: &str) -> &Trajectory {
        &self.get(name).trajectory
    }

    /// The settings string of the run called `name`.
    pub fn settings(&self, name: &str) -> &str {
        &self.get(name).settings
    }

    /// `t_end` of the run called `name` \[s\].
    pub fn t_end(&self, name: &str) -> f64 {
        self.get(name).scenario.solver.t_end
    }

    /// Every run, in table order.
    pub fn all(&self) -> &[Run] {
        &self.0
    }

    /// The runs, in table order.
    pub fn into_vec(self) -> Vec<Run> {
        self.0
    }
}

/// (min, max, mean) of `f` over samples with t in \[t0, t1\]; NaN if none.
pub fn window(tr: &Trajectory, t0: f64, t1: f64, f: impl Fn(&Sample) -> f64) -> (f64, f64, f64) {
    let v: Vec<f64> = tr
        .samples
        .iter()
        .filter(|s| s.t >= t0 && s.t <= t1)
        .map(f)
        .collect();
    if v.is_empty() {
        return (f64::NAN, f64::NAN, f64::NAN);
    }
    let mn = v.iter().copied().fold(f64::INFINITY, f64::min);
    let mx = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    (mn, mx, v.iter().sum::<f64>() / v.len() as f64)
}

/// Value of `f` at time `t` \[s\] by linear interpolation between samples.
pub fn at(tr: &Trajectory, t: f64, f: impl Fn(&Sample) -> f64) -> f64 {
    interp(&tr.samples, t, f)
}

/// Max |a − b| over common sample indices (same grids assumed).
pub fn max_diff(a: &Trajectory, b: &Trajectory, f: impl Fn(&Sample) -> f64) -> f64 {
    a.samples
        .iter()
        .zip(&b.samples)
        .map(|(x, y)| (f(x) - f(y)).abs())
        .fold(0.0, f64::max)
}

/// "completed", or "FAILED at t = … s: why" without the state dump.
pub fn status(tr: &Trajectory) -> String {
    match &tr.error {
        None => "completed".into(),
        Some(Error::Runtime { t, why, .. }) => {
            // The first clause: the report's table of runs has the whole
            // message (`failure`).
            let short = why.split(": ").next().unwrap_or(why);
            let short = short.split("; ").next().unwrap_or(short);
            format!("failed at t = {} s: {short}", tippetop::human::s4(*t))
        }
        Some(e) => format!("failed: {e}"),
    }
}

/// A failed run's whole message (without the state dump), or None.
pub fn failure(tr: &Trajectory) -> Option<String> {
    match &tr.error {
        None => None,
        Some(Error::Runtime { t, why, .. }) => {
            let why = why.split("; state:").next().unwrap_or(why);
            Some(format!("at t = {} s: {why}", tippetop::human::s4(*t)))
        }
        Some(e) => Some(e.to_string()),
    }
}

/// The lying state over \[t0, t1\]: (mean θ, half-range of θ) \[rad\].
pub fn lying(tr: &Trajectory, t0: f64, t1: f64) -> (f64, f64) {
    let (mn, mx, mean) = window(tr, t0, t1, |s| s.theta);
    (mean, 0.5 * (mx - mn))
}

/// A time in µs with three decimals, or "never".
pub fn us_or_never(t: Option<f64>) -> String {
    t.map(|t| format!("{:.3}", t * 1e6))
        .unwrap_or("never".into())
}
