//! The adhesion study of `reproduce --extended` (issue #14 item 4): the
//! paper's nano scenarios rerun with van der Waals adhesion on, and what
//! becomes of the paper's story (lying down, spin reversal, standing up
//! again, the App. D pulses, staying on the surface).
//!
//! The adhesion is C60 on one graphene sheet from the continuum
//! Lennard-Jones helper (`physics::adhesion`, docs/physics.md#adhesion-c60), the
//! values the `nano-adhesive` preset carries. Four settings per scenario:
//! exact Coulomb friction with the paper's μ = 0.13 and with the preset's
//! superlubric μ, each on the vector model (bilateral contact, as the
//! scenario files) and on the rigid body with unilateral contact (the top
//! may leave the surface). The runs without adhesion are the run table's
//! bilateral runs (reduced model: the same physics as the vector model).
//! Two control runs (one per μ, vector, the reversal scenario's window with
//! every force set to zero) measure how much the applied force changes θ.
//!
//! Every verdict is computed from the measures with the criterion stated
//! beside it in the report.

use std::f64::consts::FRAC_PI_2;

use tippetop::physics::adhesion::{Adhesion, EV};
use tippetop::{Error, Scenario, Trajectory};

use crate::figures::{curve, theta_lines};
use crate::runs::{self, NANO_BILATERAL, REVERSAL_BILATERAL, RunSpec, Runs, STEP1, STEP8};
use crate::{Figure, Options, Run, Verdict};

const US: f64 = 1e6;

/// The paper's friction coefficient (Sec. 1, eq. 1.3, after Heo et al.).
pub const PAPER_MU: f64 = 0.13;

/// A nano scenario of the paper, rerun with adhesion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Case {
    /// Short label ("constant", "reversal", "pulse 8 µs", "pulse 1 µs").
    pub label: &'static str,
    /// Figure id (file stem `fig{id}`).
    pub fig: &'static str,
    /// Scenario file of `scenarios/`.
    pub file: &'static str,
    /// The run table's bilateral run of the same file (no adhesion).
    pub baseline: &'static str,
}

/// The paper's nano scenarios: constant force (Figs. 2–4), force reversed
/// at 100 µs (Fig. 6), the App. D pulses of 8 µs and 1 µs (Figs. 12–15).
pub const CASES: [Case; 4] = [
    Case {
        label: "constant force",
        fig: "adhesion_constant",
        file: "nano.toml",
        baseline: NANO_BILATERAL,
    },
    Case {
        label: "force reversed",
        fig: "adhesion_reversal",
        file: "fig06_reversal.toml",
        baseline: REVERSAL_BILATERAL,
    },
    Case {
        label: "pulse 8 µs",
        fig: "adhesion_pulse8us",
        file: "fig12_step_8us.toml",
        baseline: STEP8[0],
    },
    Case {
        label: "pulse 1 µs",
        fig: "adhesion_pulse1us",
        file: "fig14_step_1us.toml",
        baseline: STEP1[0],
    },
];

/// One way of running a case with adhesion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Setting {
    /// Label in the report.
    pub label: &'static str,
    /// Part of the run names.
    pub key: &'static str,
    /// Friction coefficient (exact Coulomb law).
    pub mu: f64,
    /// `solver.model`.
    pub model: &'static str,
    /// Unilateral contact (the top may leave the surface).
    pub unilateral: bool,
}

/// The four settings: paper μ and superlubric μ, vector (bilateral) and
/// rigid (unilateral).
pub fn settings() -> [Setting; 4] {
    let sl = superlubric_mu();
    [
        Setting {
            label: "μ = 0.13 (vector)",
            key: "mu0.13_vector",
            mu: PAPER_MU,
            model: "vector",
            unilateral: false,
        },
        Setting {
            label: "superlubric (vector)",
            key: "superlubric_vector",
            mu: sl,
            model: "vector",
            unilateral: false,
        },
        Setting {
            label: "μ = 0.13 (rigid unilateral)",
            key: "mu0.13_rigid_unilateral",
            mu: PAPER_MU,
            model: "rigid",
            unilateral: true,
        },
        Setting {
            label: "superlubric (rigid unilateral)",
            key: "superlubric_rigid_unilateral",
            mu: sl,
            model: "rigid",
            unilateral: true,
        },
    ]
}

/// The superlubric μ of the `nano-adhesive` preset.
pub fn superlubric_mu() -> f64 {
    Scenario::nano_adhesive().surface.friction
}

/// (F_a \[N\], E_b \[J\]) of C60 on graphene from the continuum LJ helper.
pub fn graphene_adhesion() -> Result<(f64, f64), Error> {
    let b = Adhesion::c60_on_graphene().binding()?;
    Ok((b.pull_off_force, b.energy))
}

/// What the study measures of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct Measures {
    /// "completed" or the failure.
    pub status: String,
    /// Largest θ \[rad\].
    pub theta_max: f64,
    /// First time θ > π/2 \[s\].
    pub first_above_half_pi: Option<f64>,
    /// θ at the end \[rad\].
    pub theta_final: f64,
    /// (mean θ, half-range) over the second half of the window \[rad\].
    pub lying_second_half: (f64, f64),
    /// First sample with ω < 0 \[s\].
    pub spin_reversed_at: Option<f64>,
    /// ω at the end \[rad/s\].
    pub omega_final: f64,
    /// Fraction of the window spent rolling.
    pub rolling_fraction: f64,
    /// First stick event \[s\].
    pub stick_at: Option<f64>,
    /// Smallest contact reaction N_c \[N\] (`pull_off_margin_min`; without
    /// adhesion the smallest N of the samples).
    pub n_min: f64,
    /// Where contact is lost (N < 0) \[s\].
    pub contact_lost_at: Option<f64>,
    /// Work of the applied force at the end \[J\].
    pub work_applied: f64,
    /// Largest |W_a| over the run \[J\].
    pub work_applied_max_abs: f64,
    /// Work of friction at the end \[J\] (<= 0).
    pub work_friction: f64,
    /// The work the applied force would do on a point sliding along the
    /// contact point's track: max|H| × the track's length \[J\].
    pub work_scale: f64,
    /// Largest |θ − θ(H = 0)| on the common samples \[rad\] (adhesion runs).
    pub force_effect: Option<f64>,
}

/// Length of the contact point's track on the plane \[m\].
pub fn contact_track_length(tr: &Trajectory) -> f64 {
    tr.samples
        .windows(2)
        .map(|w| (w[1].xp - w[0].xp).hypot(w[1].yp - w[0].yp))
        .sum()
}

/// Largest |θ_a − θ_b| over the samples of `a` and `b` at the same time.
pub fn theta_diff(a: &Trajectory, b: &Trajectory) -> f64 {
    a.samples
        .iter()
        .zip(&b.samples)
        .filter(|(x, y)| (x.t - y.t).abs() <= 1e-9 * x.t.abs().max(y.t.abs()))
        .map(|(x, y)| (x.theta - y.theta).abs())
        .fold(0.0, f64::max)
}

impl Measures {
    /// The measures of `run`; `control` is the same setting with H = 0.
    pub fn of(run: &Run, control: Option<&Trajectory>) -> Measures {
        let tr = &run.trajectory;
        let su = &tr.summary;
        let t_end = tr.samples.last().map_or(0.0, |s| s.t);
        let last = tr.samples.last();
        let n_min = su.pull_off_margin_min.unwrap_or_else(|| {
            tr.samples
                .iter()
                .map(|s| s.normal)
                .fold(f64::INFINITY, f64::min)
        });
        Measures {
            status: runs::status(tr),
            theta_max: su.theta_max,
            first_above_half_pi: su.first_time_theta_above_half_pi,
            theta_final: su.theta_final,
            lying_second_half: runs::lying(tr, 0.5 * t_end, t_end),
            spin_reversed_at: tr.samples.iter().find(|s| s.spin < 0.0).map(|s| s.t),
            omega_final: su.omega_final,
            rolling_fraction: su.rolling_fraction,
            stick_at: tr.events.iter().find(|e| e.kind == "stick").map(|e| e.t),
            n_min,
            contact_lost_at: su.contact_lost_at,
            work_applied: last.map_or(f64::NAN, |s| s.work_applied),
            work_applied_max_abs: tr
                .samples
                .iter()
                .map(|s| s.work_applied.abs())
                .fold(0.0, f64::max),
            work_friction: last.map_or(f64::NAN, |s| s.work_friction),
            work_scale: tippetop::analysis::regime::max_applied_force(&run.scenario)
                * contact_track_length(tr),
            force_effect: control.map(|c| theta_diff(tr, c)),
        }
    }

    /// Lies down: over the second half the mean θ is within 0.25 rad of
    /// π/2 (it oscillates about the lying state: the "partly" level of
    /// claim `nano_lies_down_50us`).
    pub fn lies_down(&self) -> bool {
        (self.lying_second_half.0 - FRAC_PI_2).abs() <= 0.25
    }

    /// Lies down stably: over the second half mean θ within 0.1 rad of π/2
    /// and half-range ≤ 0.15 rad (claims `nano_lies_down_50us`,
    /// `step_1us_no_stable_lying`).
    pub fn lies_stably(&self) -> bool {
        let (mean, amp) = self.lying_second_half;
        (mean - FRAC_PI_2).abs() <= 0.1 && amp <= 0.15
    }
}

/// One adhesion run and its measures.
#[derive(Debug, Clone)]
pub struct Row {
    /// Index into [`CASES`].
    pub case: usize,
    /// Index into [`settings`].
    pub setting: usize,
    /// The run.
    pub run: Run,
    /// Its measures.
    pub m: Measures,
}

/// A verdict on one claim of the paper under adhesion.
#[derive(Debug, Clone, PartialEq)]
pub struct ClaimUnderAdhesion {
    /// The claim (short).
    pub claim: String,
    /// The criterion, stated.
    pub criterion: String,
    /// Without adhesion (the run table's bilateral run).
    pub without: String,
    /// With adhesion, per setting.
    pub with: String,
    /// Whether the claim holds without adhesion (the same criterion).
    pub holds_without: bool,
    /// Holds in every adhesion setting: Reproduced; in some: Partly; in
    /// none: NotReproduced.
    pub verdict: Verdict,
    /// One sentence in plain words.
    pub plain: String,
}

/// The study's results.
#[derive(Debug, Clone)]
pub struct Study {
    /// F_a \[N\].
    pub force: f64,
    /// E_b \[J\].
    pub energy: f64,
    /// m g of the nano top \[N\].
    pub weight: f64,
    /// The paper's max |H| \[N\].
    pub applied: f64,
    /// Per case, the measures of the run without adhesion.
    pub baseline: Vec<Measures>,
    /// The adhesion runs (case-major).
    pub rows: Vec<Row>,
    /// The controls with H = 0 (one per setting with its μ, vector).
    pub controls: Vec<Run>,
    /// The verdicts per claim.
    pub claims: Vec<ClaimUnderAdhesion>,
    /// The expectation check: every Coulomb (μ = 0.13) run rolls
    /// (rolling fraction ≥ 0.999) with |W_a| ≤ 1e-12 max|H| L_P.
    pub rolling_no_work: bool,
}

/// Tolerance of "the applied force does no work": |W_a| ≤ this × max|H|
/// × (track length of the contact point).
pub const NO_WORK_REL: f64 = 1e-12;

fn spec_of(case: &Case, s: &Setting, fa: f64, eb: f64, zero_force: bool) -> RunSpec {
    let mut sets = vec![
        format!("adhesion.force={fa:e}"),
        format!("adhesion.energy={eb:e}"),
        format!("surface.friction={:e}", s.mu),
        format!("solver.model=\"{}\"", s.model),
    ];
    if s.unilateral {
        sets.push("surface.contact=\"unilateral\"".into());
    }
    if zero_force {
        for k in 0..2 {
            sets.push(format!("force.{k}.hx=0"));
            sets.push(format!("force.{k}.hy=0"));
        }
    }
    let name = format!(
        "adhesion_{}_{}{}",
        case.fig.trim_start_matches("adhesion_"),
        s.key,
        if zero_force { "_H0" } else { "" }
    );
    RunSpec {
        name,
        file: case.file,
        sets,
        rk4: false,
    }
}

fn execute(spec: &RunSpec, opts: Options, progress: &mut dyn FnMut(&str)) -> Result<Run, Error> {
    let (scenario, settings) = runs::load(spec, opts)?;
    progress(&spec.name);
    let trajectory = tippetop::simulate(&scenario)?;
    Ok(Run {
        name: spec.name.clone(),
        settings,
        scenario,
        trajectory,
    })
}

/// Run the study. `runs` must hold the baseline runs of [`CASES`].
pub fn study(runs: &Runs, opts: Options, progress: &mut dyn FnMut(&str)) -> Result<Study, Error> {
    let (fa, eb) = graphene_adhesion()?;
    let sets = settings();
    // Controls: the reversal file (the longest window) with every force 0,
    // on the vector model, one per μ.
    let mut controls = Vec::new();
    for s in sets.iter().filter(|s| s.model == "vector") {
        controls.push(execute(
            &spec_of(&CASES[1], s, fa, eb, true),
            opts,
            progress,
        )?);
    }
    let control_of = |s: &Setting| -> Option<&Trajectory> {
        controls
            .iter()
            .find(|c| s.model == "vector" && c.scenario.surface.friction == s.mu)
            .map(|c| &c.trajectory)
    };
    let mut rows = Vec::new();
    for (ci, case) in CASES.iter().enumerate() {
        for (si, s) in sets.iter().enumerate() {
            let run = execute(&spec_of(case, s, fa, eb, false), opts, progress)?;
            let m = Measures::of(&run, control_of(s));
            rows.push(Row {
                case: ci,
                setting: si,
                run,
                m,
            });
        }
    }
    let baseline: Vec<Measures> = CASES
        .iter()
        .map(|c| Measures::of(runs.get(c.baseline), None))
        .collect();
    let nano = &runs.get(NANO_BILATERAL).scenario;
    let weight = nano.top.mass * nano.surface.gravity;
    let applied = tippetop::analysis::regime::max_applied_force(nano);
    let rolling_no_work = rows
        .iter()
        .filter(|r| sets[r.setting].mu == PAPER_MU)
        .all(|r| {
            r.m.rolling_fraction >= 0.999
                && r.m.work_applied_max_abs <= NO_WORK_REL * r.m.work_scale
        });
    let mut st = Study {
        force: fa,
        energy: eb,
        weight,
        applied,
        baseline,
        rows,
        controls,
        claims: Vec::new(),
        rolling_no_work,
    };
    st.claims = claims(&st, runs);
    Ok(st)
}

fn fmt_t(t: Option<f64>) -> String {
    t.map_or("never".into(), |t| format!("{:.3} µs", t * US))
}

impl Study {
    /// The rows of case `ci`, in settings order.
    pub fn case_rows(&self, ci: usize) -> impl Iterator<Item = &Row> {
        self.rows.iter().filter(move |r| r.case == ci)
    }

    /// The section's end: the paper's claims under adhesion (a short table,
    /// then each in words), the figures and the adhesion runs.
    fn claims_and_runs(&self) -> String {
        let mut b = String::new();
        b.push_str("\n**The paper's claims under adhesion** (\"holds\" if the criterion holds in all four adhesion settings, \"partly\" in some, \"fails\" in none):\n\n| claim | no adhesion | under adhesion |\n|---|---|---|\n");
        for c in &self.claims {
            b.push_str(&format!(
                "| {} | {} | **{}** |\n",
                crate::report::clip(&c.claim, 80).replace('|', "\\|"),
                if c.holds_without { "holds" } else { "fails" },
                word(c.verdict),
            ));
        }
        b.push('\n');
        for c in &self.claims {
            b.push_str(&format!(
                "- **{}** ({}): {} Criterion: {}. No adhesion: {}. With adhesion: {}.\n",
                c.claim,
                word(c.verdict),
                c.plain,
                c.criterion.trim_end_matches('.'),
                c.without.trim_end_matches('.'),
                c.with.trim_end_matches('.'),
            ));
        }
        b.push_str("\nFigures: ");
        b.push_str(
            &CASES
                .iter()
                .map(|c| c.fig)
                .chain(["adhesion_zoom"])
                .map(|f| format!("[fig{f}](fig{f}.png)"))
                .collect::<Vec<_>>()
                .join(", "),
        );
        b.push_str(" (θ(t) with and without adhesion; the zoom: with and without the applied force). Adhesion runs:\n\n| run | steps | J drift |\n|---|---|---|\n");
        let runs: Vec<&crate::Run> = self
            .rows
            .iter()
            .map(|r| &r.run)
            .chain(&self.controls)
            .collect();
        for r in &runs {
            let su = &r.trajectory.summary;
            b.push_str(&format!(
                "| {} | {} | {} |\n",
                r.name,
                su.steps,
                tippetop::human::sig(su.jellett_max_rel_drift, 2)
            ));
        }
        b.push_str("\nTheir settings:\n\n");
        for r in &runs {
            b.push_str(&format!("- {}: `{}`\n", r.name, r.settings));
        }
        b
    }

    /// The Markdown section (title, body).
    pub fn section(&self) -> (String, String) {
        let sets = settings();
        let mut b = String::new();
        b.push_str(&format!(
            "The paper presses the C60 onto the graphene with its weight m g = {:.3e} N. Van der Waals adhesion adds a pull-off force \
             F_a = {:.4e} N and a binding energy E_b = {:.4e} J ({:.3} eV) (C60 on one graphene sheet, continuum Lennard-Jones, \
             `physics::adhesion`, docs/physics.md#adhesion-c60; the `nano-adhesive` preset's values): F_a/(m g) = {:.2e}, F_a/max|H| = {:.2e}. \
             With adhesion the contact reaction is N_c = F_a + N (docs/physics.md#adhesion), and the friction it can hold, μ N_c, is \
             {:.2e} |H| at the paper's μ = {PAPER_MU} and {:.2e} |H| at the superlubric μ = {:e} (the preset's). \
             Each of the paper's nano scenarios is rerun with adhesion under exact Coulomb friction (`coulomb`) in four settings: \
             μ = 0.13 and superlubric μ, each on the vector model (bilateral contact, as the scenario files) and on the rigid body \
             with `contact = \"unilateral\"` (the top may leave the surface). \"no adhesion\" is the run table's bilateral run of \
             the same file (reduced model). Control: the same settings with every force set to zero (vector model), \
             to measure what the applied force changes.\n\n",
            self.weight,
            self.force,
            self.energy,
            self.energy / EV,
            self.force / self.weight,
            self.force / self.applied,
            PAPER_MU * (self.force + self.weight) / self.applied,
            sets[1].mu * (self.force + self.weight) / self.applied,
            sets[1].mu,
        ));
        b.push_str(&self.in_short());
        b.push_str(
            "Columns: θ_max; first time θ > π/2; mean θ ± half-range over the second half of the window; first time ω < 0 and ω at the end; \
             fraction of the window rolling and the time of the first stick; N_min = the smallest contact reaction (`pull_off_margin_min` \
             with adhesion, shown as N_min/F_a − 1; without adhesion the smallest N) and the first time N < 0 (lift-off under unilateral \
             contact); W_a = work of the applied force at the end, and its largest |W_a| over the run against W_ref = max|H| × (length \
             of the contact point's track), the work the force would do at a point sliding along that track; W_f = work of friction; \
             Δθ(H) = max |θ − θ with H = 0| (what the applied force changes).\n\n",
        );
        b.push_str("| scenario | setting | status | θ_max [rad] | first θ > π/2 | θ 2nd half | ω < 0 from | ω(end) [rad/s] | rolling | first stick [s] | N_min | N < 0 at | W_a [J] | max\\|W_a\\|/W_ref | W_f [J] | Δθ(H) [rad] |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for (ci, case) in CASES.iter().enumerate() {
            let mut line = |setting: &str, m: &Measures, adh: bool| {
                b.push_str(&format!(
                    "| {} | {} | {} | {:.4} | {} | {:.3} ± {:.3} | {} | {:.4e} | {:.1}% | {} | {} | {} | {:.2e} | {:.1e} | {:.2e} | {} |\n",
                    case.label,
                    setting,
                    crate::report::clip(&m.status, 80).replace('|', "/"),
                    m.theta_max,
                    fmt_t(m.first_above_half_pi),
                    m.lying_second_half.0,
                    m.lying_second_half.1,
                    fmt_t(m.spin_reversed_at),
                    m.omega_final,
                    100.0 * m.rolling_fraction,
                    m.stick_at.map_or("never".into(), |t| format!("{t:.1e}")),
                    if adh {
                        format!("F_a {:+.1e}", m.n_min / self.force - 1.0)
                    } else {
                        format!("{:.2e} N", m.n_min)
                    },
                    fmt_t(m.contact_lost_at),
                    m.work_applied,
                    m.work_applied_max_abs / m.work_scale,
                    m.work_friction,
                    m.force_effect.map_or("–".into(), |d| format!("{d:.1e}")),
                ));
            };
            line("no adhesion", &self.baseline[ci], false);
            for r in self.case_rows(ci) {
                line(sets[r.setting].label, &r.m, true);
            }
        }
        // The expectation.
        let coulomb: Vec<&Row> = self
            .rows
            .iter()
            .filter(|r| sets[r.setting].mu == PAPER_MU)
            .collect();
        let fold = |f: &dyn Fn(&Row) -> f64, init: f64, g: fn(f64, f64) -> f64| {
            coulomb.iter().map(|r| f(r)).fold(init, g)
        };
        let roll_min = fold(&|r| r.m.rolling_fraction, f64::INFINITY, f64::min);
        let wa_rel = fold(
            &|r| r.m.work_applied_max_abs / r.m.work_scale,
            0.0,
            f64::max,
        );
        let wa_abs = fold(&|r| r.m.work_applied_max_abs, 0.0, f64::max);
        let nc_dev = self
            .rows
            .iter()
            .map(|r| (r.m.n_min - self.force).abs())
            .fold(0.0, f64::max);
        let base_wa = self
            .baseline
            .iter()
            .map(|m| m.work_applied.abs())
            .fold(0.0, f64::max);
        b.push_str(&format!(
            "\n**Expectation: under Coulomb friction with N ≈ F_a the contact sticks and rolls, and a force at a rolling contact point \
             does no work.** Criterion: every μ = 0.13 run rolls for ≥ 99.9% of the window and max|W_a| ≤ {NO_WORK_REL:e} W_ref. \
             Measured over the {} runs: rolling fraction ≥ {:.4}, max|W_a| = {:.2e} J, max|W_a|/W_ref = {:.1e}; the reaction stays \
             within {:.2e} N = {:.2} m g of F_a in every adhesion run. Without adhesion the same force does up to |W_a| = {:.2e} J. \
             **{}**\n",
            coulomb.len(),
            roll_min,
            wa_abs,
            wa_rel,
            nc_dev,
            nc_dev / self.weight,
            base_wa,
            if self.rolling_no_work {
                "Confirmed."
            } else {
                "Not confirmed."
            }
        ));
        b.push_str(&self.claims_and_runs());
        (
            "Adhesion: what van der Waals binding does to the paper's story".into(),
            b,
        )
    }

    /// One paragraph of what the study found, from the measures.
    pub fn in_short(&self) -> String {
        let stick = self
            .rows
            .iter()
            .filter_map(|r| r.m.stick_at)
            .fold(0.0, f64::max);
        let rolling = self
            .rows
            .iter()
            .map(|r| r.m.rolling_fraction)
            .fold(1.0, f64::min);
        let effect = self
            .rows
            .iter()
            .filter_map(|r| r.m.force_effect)
            .fold(0.0, f64::max);
        let theta_max = self.rows.iter().map(|r| r.m.theta_max).fold(0.0, f64::max);
        let all_stick = self.rows.iter().all(|r| r.m.stick_at.is_some());
        let mut s = format!(
            "**In short.** With adhesion the contact {} and the top rolls for at least {:.1}% of every window, in every setting (both μ, \
             both models). The applied force then changes θ by at most {effect:.1e} rad (against the same run with no force), and θ \
             stays at or below {theta_max:.3} rad. ",
            if all_stick {
                format!("sticks within {stick:.1e} s")
            } else {
                "does not always stick".to_string()
            },
            100.0 * rolling
        );
        let v: Vec<String> = self
            .claims
            .iter()
            .map(|c| format!("{}: {}", c.claim, word(c.verdict)))
            .collect();
        s.push_str(&format!(
            "The paper's claims under adhesion: {}.\n\n",
            v.join("; ")
        ));
        s
    }

    /// θ(t) per case: without adhesion, and with it at both μ (vector) and
    /// μ = 0.13 on the rigid body with unilateral contact.
    pub fn figures(&self, runs: &Runs) -> Vec<Figure> {
        let sets = settings();
        let mut figs: Vec<Figure> = CASES
            .iter()
            .enumerate()
            .map(|(ci, case)| {
                let mut curves = vec![curve(
                    "no adhesion (bilateral; run table)",
                    runs.tr(case.baseline),
                    |s| s.theta,
                    false,
                )];
                for r in self.case_rows(ci).filter(|r| r.setting != 3) {
                    curves.push(curve(
                        &format!("adhesion {}", sets[r.setting].label),
                        &r.run.trajectory,
                        |s| s.theta,
                        r.setting == 2,
                    ));
                }
                Figure {
                    id: case.fig.into(),
                    title: format!(
                        "Adhesion study, {}: θ with and without C60/graphene adhesion",
                        case.label
                    ),
                    x_label: "t [µs]".into(),
                    x_scale: US,
                    y_label: "θ [rad]".into(),
                    curves,
                    hlines: theta_lines(),
                    note: format!(
                        "scenarios/{} without adhesion (the run table's bilateral run) and with F_a = {:.3e} N, E_b = {:.3e} J \
                         under exact Coulomb friction (dashed: rigid body, unilateral contact). With adhesion the curves lie on each other.",
                        case.file, self.force, self.energy
                    ),
                    ..Default::default()
                }
            })
            .collect();
        // Zoom on the reversal case: with the force (forward, then
        // reversed) and without any force.
        let mut curves: Vec<_> = self
            .case_rows(1)
            .filter(|r| r.setting != 3)
            .map(|r| {
                curve(
                    &format!("H forward then reversed; {}", sets[r.setting].label),
                    &r.run.trajectory,
                    |s| s.theta,
                    false,
                )
            })
            .collect();
        for c in &self.controls {
            curves.push(curve(
                &format!("H = 0; μ = {:e} (vector)", c.scenario.surface.friction),
                &c.trajectory,
                |s| s.theta,
                true,
            ));
        }
        figs.push(Figure {
            id: "adhesion_zoom".into(),
            title: "Adhesion study: θ with the force reversed at 100 µs and with no force at all".into(),
            x_label: "t [µs]".into(),
            x_scale: US,
            y_label: "θ [rad]".into(),
            curves,
            hlines: vec![],
            note: "scenarios/fig06_reversal.toml with adhesion, and the same with every force set to 0 (dashed): the curves coincide (the table's Δθ(H)); the top rolls, and θ oscillates between its start 0.1 rad and ~0 without ever lying down.".into(),
            ..Default::default()
        });
        figs
    }
}

/// The word for a verdict under adhesion.
pub fn word(v: Verdict) -> &'static str {
    match v {
        Verdict::Reproduced => "holds",
        Verdict::Partly => "partly",
        Verdict::NotReproduced => "fails",
    }
}

fn with_word(text: String, holds: bool) -> String {
    format!("{text} ({})", if holds { "holds" } else { "fails" })
}

fn verdict_of(study: &Study, ci: usize, f: &dyn Fn(&Measures) -> bool) -> Verdict {
    let n = study.case_rows(ci).count();
    let k = study.case_rows(ci).filter(|r| f(&r.m)).count();
    Verdict::from_levels(k == n, k > 0)
}

fn per_setting(study: &Study, ci: usize, f: &dyn Fn(&Measures) -> String) -> String {
    let sets = settings();
    study
        .case_rows(ci)
        .map(|r| format!("{}: {}", sets[r.setting].label, f(&r.m)))
        .collect::<Vec<_>>()
        .join("; ")
}

fn claims(st: &Study, runs: &Runs) -> Vec<ClaimUnderAdhesion> {
    vec![
        claim_lies_down(st),
        claim_spin_reversal(st),
        claim_retraction(st, runs),
        claim_pulse_8us(st, runs),
        claim_pulse_1us(st),
        claim_on_surface(st),
    ]
}

/// θ in words: its maximum, its first passage above π/2 and its mean ±
/// half-range over the second half.
fn lying_words(m: &Measures) -> String {
    format!(
        "θ_max {:.3}, first θ > π/2 {}, θ 2nd half {:.3} ± {:.3}",
        m.theta_max,
        fmt_t(m.first_above_half_pi),
        m.lying_second_half.0,
        m.lying_second_half.1
    )
}

/// The largest change of θ the force makes in the runs of case `ci` [rad].
fn max_effect(st: &Study, ci: usize) -> f64 {
    st.case_rows(ci)
        .filter_map(|r| r.m.force_effect)
        .fold(0.0, f64::max)
}

/// Claim 1. Lying down.
fn claim_lies_down(st: &Study) -> ClaimUnderAdhesion {
    let v = verdict_of(st, 0, &Measures::lies_down);
    ClaimUnderAdhesion {
        claim: "The nano top lies down (θ → π/2) within ~50 µs (constant force)".into(),
        criterion: "over the second half the mean θ is within 0.25 rad of π/2 (it oscillates about lying; the partly level of claim nano_lies_down_50us)".into(),
        without: with_word(lying_words(&st.baseline[0]), st.baseline[0].lies_down()),
        with: per_setting(st, 0, &lying_words),
        holds_without: st.baseline[0].lies_down(),
        verdict: v,
        plain: format!(
            "With adhesion the top {}: θ never exceeds {:.3} rad (it starts at {:.3}), it rolls for {:.1}% of the window or more, and the force changes θ by at most {:.1e} rad.",
            if v == Verdict::NotReproduced { "never lies down" } else { "still lies down in some settings" },
            st.case_rows(0).map(|r| r.m.theta_max).fold(0.0, f64::max),
            st.rows[0].run.scenario.initial.theta,
            100.0 * st.case_rows(0).map(|r| r.m.rolling_fraction).fold(1.0, f64::min),
            max_effect(st, 0)
        ),
    }
}

/// Claim 2. Spin reversal.
fn claim_spin_reversal(st: &Study) -> ClaimUnderAdhesion {
    let rev = |m: &Measures| m.spin_reversed_at.is_some();
    let v = verdict_of(st, 0, &rev);
    let spin = |m: &Measures| {
        format!(
            "ω < 0 from {}, ω(end) {:.3e} rad/s",
            fmt_t(m.spin_reversed_at),
            m.omega_final
        )
    };
    ClaimUnderAdhesion {
        claim: "The spin ω reverses and grows to ~3e7 rad/s (constant force)".into(),
        criterion: "ω < 0 at some sample".into(),
        without: with_word(spin(&st.baseline[0]), rev(&st.baseline[0])),
        with: per_setting(st, 0, &spin),
        holds_without: rev(&st.baseline[0]),
        verdict: v,
        plain: format!(
            "With adhesion the spin {}; ω ends between {:.2} and {:.2} rad/s (from 100).",
            if v == Verdict::NotReproduced {
                "never reverses"
            } else {
                "reverses"
            },
            st.case_rows(0)
                .map(|r| r.m.omega_final)
                .fold(f64::INFINITY, f64::min),
            st.case_rows(0)
                .map(|r| r.m.omega_final)
                .fold(f64::NEG_INFINITY, f64::max)
        ),
    }
}

/// Claim 3. Retraction: the reversed force stands the top up.
fn claim_retraction(st: &Study, runs: &Runs) -> ClaimUnderAdhesion {
    let t_rev = runs.get(REVERSAL_BILATERAL).scenario.forcing.windows[0].stop;
    let retract = |tr: &Trajectory| {
        let before = runs::lying(tr, 0.5 * t_rev, t_rev).0;
        let after = runs::window(tr, t_rev, f64::INFINITY, |s| s.theta).0;
        (before, after)
    };
    let stands = |(before, after): (f64, f64)| (before - FRAC_PI_2).abs() <= 0.25 && after < 0.5;
    let fmt_r = |(before, after): (f64, f64)| {
        format!("mean θ before the reversal {before:.3}, min θ after it {after:.3}")
    };
    let rows1: Vec<&Row> = st.case_rows(1).collect();
    let k = rows1
        .iter()
        .filter(|r| stands(retract(&r.run.trajectory)))
        .count();
    let v = Verdict::from_levels(k == rows1.len(), k > 0);
    let base_tr = runs.tr(REVERSAL_BILATERAL);
    ClaimUnderAdhesion {
        claim: "While lying, the reversed force stands the top up again (force reversed)".into(),
        criterion: format!(
            "it lay down before the reversal at {:.0} µs (mean θ over [{:.0}, {:.0}] µs within 0.25 rad of π/2) and θ comes back below 0.5 rad after it (the partly level of claim reversal_stands_up)",
            t_rev * US,
            0.5 * t_rev * US,
            t_rev * US
        ),
        without: with_word(fmt_r(retract(base_tr)), stands(retract(base_tr))),
        with: rows1
            .iter()
            .map(|r| {
                format!(
                    "{}: {}",
                    settings()[r.setting].label,
                    fmt_r(retract(&r.run.trajectory))
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        holds_without: stands(retract(base_tr)),
        verdict: v,
        plain: format!(
            "With adhesion there is nothing to stand up from: the top never lies down, and θ(t) with the force forward then reversed differs from θ(t) with no force by at most {:.1e} rad.",
            max_effect(st, 1)
        ),
    }
}

/// Claim 4. App. D, 8 µs pulse.
fn claim_pulse_8us(st: &Study, runs: &Runs) -> ClaimUnderAdhesion {
    let q = st.rows[0].run.scenario.solver.t_end / 1e-4;
    let theta_21 = |tr: &Trajectory| runs::window(tr, 8e-6 * q, 2e-5 * q, |s| s.theta).1;
    let rows2: Vec<&Row> = st.case_rows(2).collect();
    let ok8 = |tr: &Trajectory, m: &Measures| {
        theta_21(tr) > FRAC_PI_2 && (m.lying_second_half.0 - FRAC_PI_2).abs() <= 0.3
    };
    let k = rows2
        .iter()
        .filter(|r| ok8(&r.run.trajectory, &r.m))
        .count();
    ClaimUnderAdhesion {
        claim: "App. D: an 8 µs pulse lays the top down (θ peaks at ~2.1 after the switch-off, then oscillates about π/2)".into(),
        criterion: "max θ on [8, 20] µs above π/2 and the mean θ over the second half within 0.3 rad of π/2 (the partly level of claim step_8us_theta_2_1)".into(),
        without: with_word(
            format!(
                "max θ on [8, 20] µs {:.3}, mean θ 2nd half {:.3}",
                theta_21(runs.tr(STEP8[0])),
                st.baseline[2].lying_second_half.0
            ),
            ok8(runs.tr(STEP8[0]), &st.baseline[2]),
        ),
        with: rows2
            .iter()
            .map(|r| format!("{}: {:.3}, {:.3}", settings()[r.setting].label, theta_21(&r.run.trajectory), r.m.lying_second_half.0))
            .collect::<Vec<_>>()
            .join("; "),
        holds_without: ok8(runs.tr(STEP8[0]), &st.baseline[2]),
        verdict: Verdict::from_levels(k == rows2.len(), k > 0),
        plain: format!(
            "With adhesion the pulse does nothing visible: θ stays below {:.3} rad and differs from the no-force run by at most {:.1e} rad.",
            rows2.iter().map(|r| r.m.theta_max).fold(0.0, f64::max),
            max_effect(st, 2)
        ),
    }
}

/// Claim 5. App. D, 1 µs pulse.
fn claim_pulse_1us(st: &Study) -> ClaimUnderAdhesion {
    let not_lying = |m: &Measures| !m.lies_stably();
    let v = verdict_of(st, 3, &not_lying);
    ClaimUnderAdhesion {
        claim: "App. D: a 1 µs pulse does not make the top lie down stably".into(),
        criterion: "not lying: mean θ over the second half not within 0.1 rad of π/2 with half-range ≤ 0.15 rad (as claim step_1us_no_stable_lying)".into(),
        without: with_word(lying_words(&st.baseline[3]), not_lying(&st.baseline[3])),
        with: per_setting(st, 3, &lying_words),
        holds_without: not_lying(&st.baseline[3]),
        verdict: v,
        plain: format!(
            "Holds trivially with adhesion: the top does not lie down after any force; θ_max {:.3} rad, the pulse changes θ by at most {:.1e} rad.",
            st.case_rows(3).map(|r| r.m.theta_max).fold(0.0, f64::max),
            max_effect(st, 3)
        ),
    }
}

/// Claim 6. Staying on the surface.
fn claim_on_surface(st: &Study) -> ClaimUnderAdhesion {
    let on = |m: &Measures| m.contact_lost_at.is_none() && m.n_min > 0.0;
    let all_on = st.rows.iter().filter(|r| on(&r.m)).count();
    let base_on = st.baseline.iter().filter(|m| on(m)).count();
    let first_off = st
        .baseline
        .iter()
        .filter_map(|m| m.contact_lost_at)
        .fold(f64::INFINITY, f64::min);
    ClaimUnderAdhesion {
        claim: "Implicit: the top stays on the surface (all four scenarios)".into(),
        criterion: "N (N_c with adhesion) > 0 in every sample and no lift-off (unilateral runs: the rigid body would fly)".into(),
        without: with_word(
            format!(
                "{base_on} of {} runs stay on; N < 0 first at {:.3} µs",
                st.baseline.len(),
                first_off * US
            ),
            base_on == st.baseline.len(),
        ),
        with: format!(
            "{all_on} of {} runs stay on; smallest N_c = {:.4e} N (F_a {:+.1e})",
            st.rows.len(),
            st.rows.iter().map(|r| r.m.n_min).fold(f64::INFINITY, f64::min),
            st.rows.iter().map(|r| r.m.n_min).fold(f64::INFINITY, f64::min) / st.force - 1.0
        ),
        holds_without: base_on == st.baseline.len(),
        verdict: Verdict::from_levels(all_on == st.rows.len(), all_on > 0),
        plain: if all_on == st.rows.len() {
            format!(
                "With adhesion the top never lifts off: the reaction stays within {:.2} m g of F_a, and F_a is {:.1e} times max|H|.",
                st.rows.iter().map(|r| (r.m.n_min - st.force).abs()).fold(0.0, f64::max) / st.weight,
                st.force / st.applied
            )
        } else {
            format!("With adhesion {} of {} runs still lose contact.", st.rows.len() - all_on, st.rows.len())
        },
    }
}
