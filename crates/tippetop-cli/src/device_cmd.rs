//! `tippetop device`: can the nano tippe top be a memory bit? The numbers
//! come from [`tippetop::analysis::device`]; this writes them as
//! device.json and device.md (plain words) and prints the verdict.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use tippetop::analysis::device::{self, DeviceOptions, DeviceReport, Found, TEN_YEARS, Tally};

use crate::output::{OutDir, write_bytes_atomic};
use crate::scenario_load::input_error;

/// Long help of `tippetop device`.
pub const DEVICE_LONG_ABOUT: &str =
    "Answer, with numbers, whether the nano tippe top can be a memory bit
(issue #16; docs/physics.md §23.2). Computes, each by this run:
  - the paper's model (preset nano, T = 0) and the same top with adhesion (nano-adhesive):
    the paper's write and its reversal as the erase (100 us phases), the smallest |H| along the
    paper's direction that writes, the best write and erase found by a protocol search;
  - C60 on graphene (nano-physical: Langevin, adhesion, the 1.1 eV lying well of a 1 nm stem)
    at 4, 77 and 300 K, 0.5 ns phases: P(write) with the paper's force and with no force,
    P(erase), Wilson intervals; the smallest force whose every run writes; how long the standing
    state lasts (first passage out of zero); the lying state's retention from the Arrhenius fit
    of escape rates at three raised temperatures (extrapolated, and labelled so); the highest
    temperature with 10 years of retention.
Writes device.json and device.md into --out. Takes minutes (a progress line per stage);
--quick cuts every ensemble and search for a first look.";

/// `tippetop device`.
#[derive(Debug, Args)]
#[command(
    after_help = "Examples:\n  tippetop device --out out/device\n  tippetop device --quick --out out/device-quick"
)]
pub struct DeviceArgs {
    /// Output directory.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Runs per thermal ensemble, 2 to 10000 (default 32; --quick 8).
    #[arg(long, value_name = "N")]
    pub runs: Option<usize>,
    /// Runs per protocol search, 1 to 100000 (default 40; --quick 12).
    #[arg(long, value_name = "N")]
    pub budget: Option<usize>,
    /// Runs per raised temperature of the retention fit, 2 to 10000 (default 16; --quick 8).
    #[arg(long, value_name = "N")]
    pub retention_runs: Option<usize>,
    /// Smaller ensembles and searches for a first look.
    #[arg(long)]
    pub quick: bool,
    /// Number of threads, 1 to 1024 (default: one per core).
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}

fn g(v: f64) -> String {
    format!("{v:.3e}")
}

/// A time in seconds, or "> 1e300 s" past f64's range.
fn secs(v: f64) -> String {
    if v.is_finite() {
        g(v)
    } else {
        "> 1e300".into()
    }
}

fn opt(v: Option<f64>) -> String {
    v.map(g).unwrap_or_else(|| "-".into())
}

fn p(t: &Tally) -> String {
    format!(
        "{}/{} ({})",
        t.successes,
        t.runs,
        if t.ci95[0] == t.ci95[1] {
            "deterministic".to_string()
        } else {
            format!("Wilson 95 % [{:.2}, {:.2}]", t.ci95[0], t.ci95[1])
        }
    )
}

fn fails(t: &Tally) -> String {
    if t.failures.is_empty() {
        String::new()
    } else {
        let f: Vec<String> = t.failures.iter().map(|(m, n)| format!("{m} {n}")).collect();
        format!("; failures: {}", f.join(", "))
    }
}

fn found(f: &Option<Found>) -> String {
    found_as(f, "H")
}

/// A search's outcome in words; `sym` names the force (H: the paper's, F: a tip's).
fn found_as(f: &Option<Found>, sym: &str) -> String {
    match f {
        None => "no search".into(),
        Some(f) if f.found => {
            let w: Vec<String> = f
                .windows
                .iter()
                .map(|w| {
                    format!(
                        "|{sym}| = {} N at {:.2} rad from {} s for {} s",
                        g(w[0]),
                        w[1],
                        g(w[2]),
                        g(w[3])
                    )
                })
                .collect();
            format!(
                "found ({} runs): {}; switches in {} s, work {} J; {}/{} of ±5 % perturbations succeed",
                f.evaluations,
                w.join("; "),
                opt(f.time),
                opt(f.energy),
                f.robustness.0,
                f.robustness.1
            )
        }
        Some(f) => format!(
            "none found in {} runs: the closest stayed {:.3} rad outside the target (shrunk by 0.05 rad) over the hold",
            f.evaluations, f.distance
        ),
    }
}

fn markdown(r: &DeviceReport, opts: &DeviceOptions) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# Can the nano tippe top be a memory bit?\n");
    let _ = writeln!(
        s,
        "Computed by `tippetop device` ({} runs per thermal ensemble, {} per search, {} per retention temperature). \
         State 0 = standing, θ in [0, 0.5]; state 1 = lying, θ in [π/2 − 0.35, π/2 + 0.35]; a phase succeeds if θ \
         stays in the target over its last hold (docs/physics.md §23).\n",
        opts.runs, opts.budget, opts.retention_runs
    );
    // The answer, sentence by sentence from the numbers above.
    let _ = writeln!(s, "## Answer\n");
    let mut ans: Vec<String> = Vec::new();
    let det = |name: &str| r.deterministic.iter().find(|d| d.preset == name);
    let mut tip_sentence: Option<String> = None;
    if let Some(d) = det("nano") {
        let w = d.write.successes == d.write.runs;
        let e = d.erase.successes == d.erase.runs;
        let found_erase = d.search_erase.as_ref().is_some_and(|f| f.found);
        if let Some(f) = d.tip_erase.as_ref().filter(|f| f.found) {
            tip_sentence = Some(format!(
                " A tip pushing at the top does erase there ({}/{} of ±5 % perturbed copies work).",
                f.robustness.0, f.robustness.1
            ));
        }
        ans.push(format!(
            "In the paper's own model (T = 0) the paper's write {} and its reversed force {}{}.",
            if w { "works" } else { "fails" },
            if e { "erases" } else { "does not erase" },
            if e {
                String::new()
            } else if found_erase {
                "; the search found an erase protocol (below)".into()
            } else {
                format!(
                    "; a search of {} runs found no erase protocol either",
                    d.search_erase.as_ref().map_or(0, |f| f.evaluations)
                )
            }
        ));
    }
    if let Some(t) = tip_sentence.take() {
        ans.push(t.trim_start().to_string());
    }
    if let Some(d) = det("nano-adhesive") {
        let w = d.write.successes == d.write.runs;
        ans.push(format!(
            "With the van der Waals adhesion the paper neglects, its force {}{}.",
            if w { "still writes" } else { "does not write" },
            match d.min_write_force {
                Some(h) => format!(" (the smallest writing force is {} N)", g(h)),
                None => format!(
                    " (nor does any force along its direction up to {} N)",
                    g(device::DET_FORCE_MAX)
                ),
            }
        ));
    }
    let held: Vec<String> = r
        .thermal
        .iter()
        .map(|t| {
            format!(
                "at {} K {} of {} runs left state 0 within 1 ns{}",
                t.temperature,
                t.zero_left.0,
                t.zero_left.1,
                t.zero_escape
                    .map(|e| format!(" (mean time {} s)", g(e.mean_time)))
                    .unwrap_or_default()
            )
        })
        .collect();
    ans.push(format!("C60 on graphene: {}.", held.join("; ")));
    let free: Vec<String> = r
        .thermal
        .iter()
        .map(|t| {
            format!(
                "{}/{} at {} K",
                t.write_without_force.successes, t.write_without_force.runs, t.temperature
            )
        })
        .collect();
    ans.push(format!(
        "With no force at all the top \"writes\" (falls into the lying well) in {} runs.",
        free.join(", ")
    ));
    let ten = r
        .retention
        .t_ten_years
        .map(|(t, [lo, hi])| format!("{t:.0} K (95 %: {lo:.0}–{hi:.0} K; extrapolated)"))
        .unwrap_or_else(|| "no temperature (no fit)".into());
    ans.push(format!(
        "The lying state holds 10 years up to {ten}, thanks to the modelled stem well."
    ));
    let zero_holds = r.thermal.iter().any(|t| t.zero_left.0 * 2 < t.zero_left.1);
    let _ = writeln!(
        s,
        "**{}** {}\n",
        if zero_holds {
            "Partly."
        } else {
            "Not as the paper proposes: state 0 does not hold."
        },
        ans.join(" ")
    );
    if !zero_holds {
        let _ = writeln!(
            s,
            "What would have to change: a barrier for the standing state too (an orientation well at θ = 0 \
             deeper than ~40 k_B T at the operating temperature for years), and an actuator that reaches the \
             top (the paper's force at the contact point has no physical actuator, docs/physics.md §23).\n"
        );
    }
    let _ = writeln!(s, "## The deterministic models (T = 0)\n");
    for d in &r.deterministic {
        let _ = writeln!(s, "### Preset `{}`\n", d.preset);
        let _ = writeln!(
            s,
            "- The paper's write (H_x = H_y = 0.1 zN, 100 µs): {}, time {} s, work {} J{}.",
            p(&d.write),
            opt(d.write.time_median),
            opt(d.write.energy_median),
            fails(&d.write)
        );
        let _ = writeln!(
            s,
            "- The paper's reversal as the erase: {}{}.",
            p(&d.erase),
            fails(&d.erase)
        );
        let _ = writeln!(
            s,
            "- Smallest |H| along the paper's direction that writes (P >= 0.99 is success at T = 0): {}.",
            d.min_write_force
                .map(|h| format!(
                    "{} N ({:.3} times the paper's 1.41e-22 N)",
                    g(h),
                    h / (2f64.sqrt() * 1e-22)
                ))
                .unwrap_or_else(|| format!(
                    "none up to {} N (larger forces: runs of minutes each)",
                    g(device::DET_FORCE_MAX)
                ))
        );
        let _ = writeln!(s, "- Protocol search, write: {}.", found(&d.search_write));
        let _ = writeln!(
            s,
            "- Protocol search, erase (after the paper's write): {}.\n",
            found(&d.search_erase)
        );
        if d.tip_write.is_some() || d.tip_erase.is_some() {
            let _ = writeln!(
                s,
                "- A tip at the top (R + a above the centre of mass, horizontal lab-frame force), write: {}.",
                found_as(&d.tip_write, "F")
            );
            let _ = writeln!(
                s,
                "- The same tip, erase (after the paper's write): {}.\n",
                found_as(&d.tip_erase, "F")
            );
        }
    }
    let _ = writeln!(s, "## C60 on graphene (`nano-physical`), 0.5 ns phases\n");
    let _ = writeln!(
        s,
        "| T [K] | write, paper's force | write, no force | erase, reversal | smallest |H| writing every run | state 0 left within 1 ns | state 1 retention (extrapolated) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|");
    for t in &r.thermal {
        let minf = match &t.min_write_force {
            Some((h, tl)) => format!(
                "{} N ({}/{}; Wilson lower {:.2})",
                g(*h),
                tl.successes,
                tl.runs,
                tl.ci95[0]
            ),
            None => format!("none up to {} N", g(device::HOT_FORCE_MAX)),
        };
        let ret = t
            .one_retention
            .map(|e| {
                let yrs = e.mean_time / (TEN_YEARS / 10.0);
                format!(
                    "{} s = {:.2e} yr (95 %: {}–{} s)",
                    secs(e.mean_time),
                    yrs,
                    secs(e.time_ci95[0]),
                    secs(e.time_ci95[1])
                )
            })
            .unwrap_or_else(|| "no fit".into());
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {}/{} | {} |",
            t.temperature,
            p(&t.write),
            p(&t.write_without_force),
            p(&t.erase),
            minf,
            t.zero_left.0,
            t.zero_left.1,
            ret
        );
    }
    let rt = &r.retention;
    let _ = writeln!(s, "\n## The lying state's retention\n");
    let _ = writeln!(
        s,
        "Escape out of state 1 from the well's bottom, measured at raised temperatures (first passages, \
         censored at 4 ns), fitted by ln k = ln ν − E/(k_B T) and extrapolated (docs/physics.md §22). The \
         potential's barrier to the window's edge is {} J = {:.3} eV.\n",
        g(rt.barrier_potential),
        rt.barrier_potential / 1.602176634e-19
    );
    for (pt, e) in &rt.points {
        let _ = writeln!(
            s,
            "- {:.0} K: {} passages in {} s at risk, k = {} 1/s (95 %: {}–{})",
            pt.temperature,
            e.passages,
            g(e.exposure),
            g(e.rate),
            g(e.ci95[0]),
            g(e.ci95[1])
        );
    }
    if let Some(f) = &rt.fit {
        let _ = writeln!(
            s,
            "\nFit: E = {:.3} ± {:.3} eV (the potential's {:.3} eV), ν = {} 1/s, χ² = {:.2} on {} dof. \
             Highest temperature with 10 years of retention: {ten}.",
            f.barrier_ev,
            f.barrier_se / 1.602176634e-19,
            rt.barrier_potential / 1.602176634e-19,
            g(f.ln_prefactor.exp()),
            f.chi2,
            f.dof
        );
    } else {
        let _ = writeln!(s, "\nNo fit (too few passages).");
    }
    s
}

/// Run `tippetop device`.
pub fn run(args: &DeviceArgs, quiet: bool) -> Result<ExitCode> {
    let d = DeviceOptions::default();
    let (runs, budget, rr) = if args.quick {
        (8, 12, 8)
    } else {
        (d.runs, d.budget, d.retention_runs)
    };
    let opts = DeviceOptions {
        runs: args.runs.unwrap_or(runs),
        budget: args.budget.unwrap_or(budget),
        retention_runs: args.retention_runs.unwrap_or(rr),
        threads: args.threads,
        ..d
    };
    for (key, v, hi) in [
        ("--runs", opts.runs, 10_000),
        ("--budget", opts.budget, 100_000),
        ("--retention-runs", opts.retention_runs, 10_000),
    ] {
        let lo = if key == "--budget" { 1 } else { 2 };
        if v < lo || v > hi {
            return Ok(input_error(format!(
                "{key}: {v} is not allowed ({lo} to {hi})"
            )));
        }
    }
    if let Err(e) = tippetop::analysis::sweep::threads(opts.threads) {
        return Ok(input_error(e));
    }
    let out = OutDir::open(&args.out)?;
    let started = std::time::Instant::now();
    let mut stage = |msg: &str| {
        if !quiet {
            eprintln!("[{:6.1} s] {msg}", started.elapsed().as_secs_f64());
        }
    };
    let report = match device::report(&opts, &mut stage) {
        Ok(r) => r,
        Err(e) => {
            out.abandon();
            anyhow::bail!("{e}");
        }
    };
    let stage_dir = out.stage().to_path_buf();
    let mut text = serde_json::to_string_pretty(&report)?;
    text.push('\n');
    write_bytes_atomic(&stage_dir.join("device.json"), text.as_bytes())?;
    let md = markdown(&report, &opts);
    write_bytes_atomic(&stage_dir.join("device.md"), md.as_bytes())?;
    out.commit(&["device.json"])?;
    if !quiet {
        if let Some(answer) = md
            .split("## Answer\n\n")
            .nth(1)
            .and_then(|s| s.split("\n\n").next())
        {
            println!("{answer}");
        }
        println!("wrote {}", args.out.display());
    }
    Ok(ExitCode::SUCCESS)
}
