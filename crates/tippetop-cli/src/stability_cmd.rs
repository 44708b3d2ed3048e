//! `tippetop stability`: the steady motions of a scenario, their eigenvalues
//! and verdicts, the frozen-spin analysis when a force is applied, and the
//! paper's App. B (B1–B4) beside them. See `tippetop::analysis::stability`.

use std::process::ExitCode;

use tippetop::{
    Scenario,
    analysis::stability::{self, Linearisation, Options, SmoothLaw, StabilityReport},
};

/// Smooth friction law for the linearisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum LawArg {
    /// μ N v/√(|v|² + ε²)
    Regularized,
    /// μ N v/ε
    Viscous,
}

/// Stability of the steady motions (θ = 0, π/2, π) beside the paper's App. B.
#[derive(Debug, Clone, clap::Args)]
#[command(after_help = "Examples:\n  \
    tippetop stability --preset classical\n  \
    tippetop stability --preset nano --no-run --json > stability.json\n  \
    tippetop stability scenarios/fig07_classical.toml --law viscous --eps 1e-3\n  \
    tippetop stability --preset classical --spin 200 --tol 1e-8\n\n\
Output (stdout; a table, or JSON with --json): for each steady motion (upright at theta = 0,\n\
inverted at theta = pi, the relative equilibrium at theta = pi/2) its theta*, Omega*, omega*, the eigenvalues of the\n\
linearisation with the smooth friction law and with mu = 0, and a verdict (stable, unstable,\n\
marginal); without --no-run the late-time state of the scenario's run; with an applied force the\n\
frozen-spin analysis; and the paper's App. B (B1-B4) against the full analysis. Progress and\n\
errors go to stderr; nothing is written to disk.\n\n\
Exit codes: 0 done; 2 bad input (scenario key, --spin, --eps or --tol out of range, a friction\n\
law the linearisation does not have (Coulomb-Contensou over a disc), --law the other smooth law\n\
than the scenario's without --eps; one line `error: KEY: what (valid range)`, nothing computed);\n\
3 the analysis or the run failed part-way (e.g. an eigenvalue iteration did not converge);\n\
1 other errors.")]
#[command(
    mut_arg("scenario", |a| a.help("Scenario file (TOML); or give --preset")),
    mut_arg("sets", |a| a.help("Override a scenario key, e.g. --set surface.friction=0 (repeatable)")),
)]
pub struct StabilityArgs {
    /// The scenario: file, preset, overrides.
    #[command(flatten)]
    pub source: crate::common::args::ScenarioArgs,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
    /// Smooth friction law used for the linearisation (Coulomb is not
    /// differentiable at zero slip); default: the scenario's law if it is
    /// regularized or viscous, else regularized. The other smooth law than
    /// the scenario's needs --eps (the scenario's ε is its own law's).
    #[arg(long, value_enum)]
    pub law: Option<LawArg>,
    /// Regularisation speed ε [m/s], 1e-100 <= eps <= 1e100; default: the
    /// scenario's, else 1e-3 R max(|ω0|, √(g/R)).
    #[arg(long, allow_negative_numbers = true)]
    pub eps: Option<f64>,
    /// Spin about the vertical at θ = 0 and π [rad/s], |spin| <= 1e100;
    /// default: the spin with the scenario's Jellett J.
    #[arg(long, allow_negative_numbers = true)]
    pub spin: Option<f64>,
    /// Relative tolerance of the verdicts: tol = TOL · max|λ|; 0 <= TOL < 1.
    #[arg(long, default_value_t = 1e-10, allow_negative_numbers = true)]
    pub tol: f64,
    /// Do not run the scenario (no late-time state).
    #[arg(long)]
    pub no_run: bool,
}

fn load(args: &StabilityArgs) -> Result<Scenario, tippetop::Error> {
    crate::scenario_load::from_args(
        args.source.scenario.as_deref(),
        args.source.preset.as_deref(),
        &args.source.sets,
    )
}

/// Run `tippetop stability`. Exit code 0, 2 for bad input, 3 for a failure
/// while computing.
pub fn run(args: &StabilityArgs, quiet: bool) -> anyhow::Result<ExitCode> {
    let opts = Options {
        law: args.law.map(|l| match l {
            LawArg::Regularized => SmoothLaw::Regularized,
            LawArg::Viscous => SmoothLaw::Viscous,
        }),
        eps: args.eps,
        spin: args.spin,
        tol_rel: args.tol,
        run: !args.no_run,
        ..Default::default()
    };
    // Every input (options, then the scenario) before any work or output.
    let sc = match opts
        .validate()
        .and_then(|()| load(args))
        .and_then(|sc| stability::supports(&sc).map(|()| sc))
        .and_then(|sc| stability::law_and_eps(&sc, &opts).map(|_| sc))
    {
        Ok(sc) => sc,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(2));
        }
    };
    if !quiet && opts.run {
        eprintln!("running the scenario for its late-time state ...");
    }
    let rep = match stability::analyse(&sc, &opts) {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return Ok(ExitCode::from(if e.is_input() { 2 } else { 3 }));
        }
    };
    if args.json {
        crate::output::print_json(&rep)?;
    } else {
        print!("{}", table(&rep, Some(&sc)));
    }
    Ok(ExitCode::SUCCESS)
}

/// Which friction law each part used, and, where the run's late state is a
/// steady motion the linearisation calls unstable, why they disagree
/// (issue 29: "upright: unstable", then "Late-time state: upright").
fn laws(r: &StabilityReport, sc: &Scenario) -> Option<String> {
    use tippetop::input::surface::FrictionLaw;
    let late = r.late.as_ref()?;
    let run_law = sc.surface.law;
    let mut s = format!(
        "Friction laws: the linearisation uses the {} law (ε = {} m/s); the run uses the scenario's {} law.\n",
        r.law.name(),
        h(r.eps),
        run_law.name()
    );
    let sticks = matches!(
        run_law,
        FrictionLaw::Coulomb | FrictionLaw::CoulombSliding | FrictionLaw::Contensou { .. }
    );
    let steady = r
        .steady
        .iter()
        .find(|m| m.name.starts_with(late.class.as_str()));
    if let Some(m) = steady.filter(|m| sticks && m.with_friction.verdict.as_str() == "unstable") {
        s += &format!(
            "They disagree about the {} state only through that law: the smooth law always slides a little, and that slip is what destabilises it (max Re λ = {} 1/s); exact Coulomb friction lets the contact stick, and a rolling contact does no work, so the run stays {}. With surface.friction_law = \"regularized\" the run leaves it too.\n",
            late.class,
            h(m.with_friction.max_re),
            late.class
        );
    }
    Some(s)
}

/// A number for people: 4 significant figures (`tippetop::human`).
fn h(x: f64) -> String {
    tippetop::human::sig(x, 4)
}

fn eigs(l: &Linearisation) -> String {
    l.eigenvalues
        .iter()
        .map(|e| {
            if e.im == 0.0 {
                h(e.re)
            } else {
                tippetop::human::complex(e.re, e.im)
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// The human-readable report; with the scenario, which friction law each
/// part used and why their verdicts differ ([`laws`]).
pub fn table(r: &StabilityReport, sc: Option<&Scenario>) -> String {
    let mut s = String::new();
    s += &format!(
        "Steady motions with H = 0, linearised with the {} friction law (ε = {} m/s, μ = {}), g = {} m/s²\n",
        r.law.name(),
        h(r.eps),
        r.mu,
        r.gravity
    );
    s += &format!(
        "Verdict: stable if every Re λ < −tol, unstable if some Re λ > tol, else marginal; tol = {} · max|λ|. Structural zeros (Jellett's J, rotation about Z) removed.\n",
        tippetop::human::sig(r.tol_rel, 1)
    );
    s += &format!(
        "Jellett J (initial) = {} kg m³/s; sleeping-top threshold ω_c = 2√(A m g a)/C = {} rad/s\n\n",
        h(r.jellett),
        h(r.sleeping_threshold)
    );
    s += &format!(
        "{:<48} {:>8} {:>12} {:>12} {:>10} {:>12} {:>10}\n",
        "steady motion", "θ*", "Ω* [rad/s]", "ω* [rad/s]", "friction", "max Re λ", "μ = 0"
    );
    for m in &r.steady {
        let l = &m.with_friction;
        s += &format!(
            "{:<48} {:>8.4} {:>12} {:>12} {:>10} {:>12} {:>10}\n",
            m.name,
            l.theta,
            h(l.precession),
            h(l.spin),
            l.verdict.as_str(),
            h(l.max_re),
            m.frictionless.verdict.as_str()
        );
        s += &format!("    ({})\n", m.how);
        s += &format!("    λ [1/s], friction: {}\n", eigs(l));
        s += &format!("    λ [1/s], μ = 0:    {}\n", eigs(&m.frictionless));
    }
    let inv = &r.inversion;
    s += "\nFull inversion (friction conserves J and dissipates energy: a top whose slip always costs energy ends at the least energy V_J(θ) = J²/(2D(θ)) + m g (R − a cos θ) at its J, docs/physics.md#stability):\n";
    match inv.threshold_at_pi {
        Some(nc) => {
            s += &format!(
                "  θ = π is a minimum of V_J iff the spin about the vertical there exceeds n_c = (R + a)√(m g a/(R[C(R + a) − A R])) = {} rad/s; this scenario's J gives {} rad/s there ({})\n",
                h(nc),
                h(inv.spin_at_pi.abs()),
                if inv.spin_at_pi.abs() > nc {
                    "above"
                } else {
                    "below"
                }
            );
        }
        None => {
            s += "  θ = π is never a minimum of V_J: C (R + a) <= A R (outside the inversion window A/C < 1 + a/R)\n"
        }
    }
    match inv.threshold_at_0 {
        Some(nu) => {
            s += &format!(
                "  θ = 0 stays a minimum of V_J (a top near upright stays there) while the spin about the vertical there is below n_up = (R − a)√(m g a/(R[A R − C(R − a)])) = {} rad/s\n",
                h(nu)
            );
        }
        None => {
            s += "  θ = 0 is a minimum of V_J at every spin: A R <= C (R − a) (outside the inversion window A/C > 1 − a/R)\n"
        }
    }
    if let Some(w) = inv.initial_spin_threshold {
        s += &format!(
            "  from the scenario's θ₀ with Ω₀ = 0: initial spin above {} rad/s (the energy alone, E₀ >= V_J(π), asks only {} rad/s)\n",
            h(w),
            h(inv.energy_bound)
        );
    }
    s += &format!(
        "  least energy at this scenario's J: θ = {} rad\n",
        h(inv.final_theta)
    );
    if let Some(l) = &r.late {
        s += &format!(
            "\nLate-time state of the run ({} s to {} s, status {}): {} — θ = {:.4} ± {:.4} rad (θ − π/2 = {:+.4}), Ω = {} rad/s, ω = {} rad/s (end {}), u = ({}, {}) m/s\n",
            h(l.t_from),
            h(l.t_to),
            l.status,
            l.class,
            l.theta_mean,
            l.theta_amplitude,
            l.theta_mean - std::f64::consts::FRAC_PI_2,
            h(l.precession_mean),
            h(l.spin_mean),
            h(l.spin_final),
            h(l.u_mean[0]),
            h(l.u_mean[1])
        );
    }
    if let Some(text) = sc.and_then(|sc| laws(r, sc)) {
        s += &text;
    }
    if !r.frozen.is_empty() {
        s += "\nApplied force H ≠ 0: nothing is steady. Frozen-spin (quasi-static) analysis, not a true equilibrium:\n";
        for f in &r.frozen {
            let x = &f.result;
            match x.theta_quasi {
                Some(tq) => {
                    s += &format!(
                        "  {:<46} {:<24} θ_q = {:.5} Ω = {} ω = {}: λ = {} → {}\n",
                        f.name,
                        format!("{:?}", x.variant),
                        tq,
                        h(x.precession),
                        h(x.spin),
                        x.eigenvalues
                            .iter()
                            .map(|e| tippetop::human::complex(e.re, e.im))
                            .collect::<Vec<_>>()
                            .join(", "),
                        x.verdict.map(|v| v.as_str()).unwrap_or("-")
                    )
                }
                None => {
                    s += &format!(
                        "  {:<46} {:<24} {}\n",
                        f.name,
                        format!("{:?}", x.variant),
                        x.note
                    )
                }
            }
        }
    }
    s += "\nThe paper's App. B against the full analysis:\n";
    for p in &r.paper {
        s += &format!("{}  {}\n", p.id, p.configuration);
        s += &format!("    paper:   {}\n", p.paper);
        s += &format!("    full:    {}\n", p.full);
        s += &format!("    agree:   {}\n", p.agree);
        s += &format!("    dropped: {}\n", p.dropped);
    }
    s
}
