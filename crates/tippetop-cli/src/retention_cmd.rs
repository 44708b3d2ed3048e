//! `tippetop retention`: the Arrhenius extrapolation of escape rates
//! measured by ensembles with a first-passage criterion
//! (`tippetop ensemble --first-passage ...`) at raised temperatures, to a
//! target temperature ([`tippetop::analysis::retention`]).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use tippetop::analysis::retention::{RatePoint, fit_arrhenius};

use crate::output::write_bytes_atomic;

/// Long help of `tippetop retention`.
pub const RETENTION_LONG_ABOUT: &str = "How long a state holds at a target temperature, from \
    escape rates measured where escapes are fast enough to simulate. Each DIR is the output of \
    `tippetop ensemble --first-passage SPEC` (the runs stop when they leave the state); its \
    summary.json holds the temperature and the escape rate k = passages / time at risk (the \
    maximum-likelihood rate of a Poisson escape with censored runs; standard error of ln k: \
    1/sqrt(passages)). The rates are fitted by ln k = ln nu - E/(k_B T) (weights 1/se^2; \
    with more than two temperatures the covariance is scaled by chi2/dof when that exceeds 1) \
    and extrapolated to --temperature: the predicted rate and mean retention time 1/k with \
    their 95 % intervals, and the fitted barrier E (compare it with the potential's: Kramers' \
    prefactor depends on T as a power, which the fit does not model; the interval is \
    statistical only). With --out DIR, writes DIR/retention.json.\n\n\
    Exit codes: 0 ok, 2 bad input (one line naming the key), 1 unreadable files.";

/// Arguments of `tippetop retention`.
#[derive(Debug, Clone, clap::Args)]
#[command(
    after_help = "Example (escape from the lying well of nano-physical):\n  \
    for T in 2000 2500 3000; do\n    \
    tippetop ensemble --preset nano-physical --set thermal.temperature=$T --runs 200 \\\n      \
    --first-passage 'theta<1.07,theta>2.07' --out out/esc$T\n  \
    done\n  \
    tippetop retention out/esc2000 out/esc2500 out/esc3000 --temperature 300"
)]
pub struct RetentionArgs {
    /// Ensemble output directories (each with summary.json), two or more
    /// temperatures.
    #[arg(value_name = "DIR", required = true)]
    pub dirs: Vec<PathBuf>,
    /// Target temperature [K] (> 0).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub temperature: f64,
    /// Write retention.json into this directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

use crate::scenario_load::input_error;

/// Run `tippetop retention`.
pub fn run(args: &RetentionArgs, quiet: bool) -> Result<ExitCode> {
    if !(args.temperature > 0.0 && args.temperature.is_finite()) {
        return Ok(input_error(format!(
            "--temperature: {} is not allowed (a finite temperature > 0 [K])",
            args.temperature
        )));
    }
    let mut points = Vec::new();
    for dir in &args.dirs {
        let path = dir.join("summary.json");
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("reading {}", path.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).with_context(|| format!("parsing {}", path.display()))?;
        let Some(t) = v.get("temperature").and_then(|x| x.as_f64()) else {
            return Ok(input_error(format!(
                "{}: no temperature (an ensemble's summary.json of a Langevin or Brownian run)",
                path.display()
            )));
        };
        let rate = &v["first_passage"]["escape_rate"];
        let (Some(k), Some(se)) = (rate["rate"].as_f64(), rate["ln_rate_se"].as_f64()) else {
            return Ok(input_error(format!(
                "{}: no escape rate (no run passed: run longer, at a higher temperature, or with --first-passage)",
                path.display()
            )));
        };
        points.push(RatePoint {
            temperature: t,
            rate: k,
            ln_rate_se: se,
        });
    }
    let fit = match fit_arrhenius(&points) {
        Ok(f) => f,
        Err(e) => return Ok(input_error(e.to_string())),
    };
    let at = fit.extrapolate(args.temperature);
    if !quiet {
        for p in &points {
            println!(
                "T = {:>8.2} K   k = {:.4e} 1/s (ln k ± {:.3})",
                p.temperature, p.rate, p.ln_rate_se
            );
        }
        println!(
            "barrier        E = {:.4e} J = {:.4} eV ± {:.4} eV (fit; chi2 {:.3}, dof {})",
            fit.barrier,
            fit.barrier_ev,
            fit.barrier_se / 1.602176634e-19,
            fit.chi2,
            fit.dof
        );
        println!(
            "at {} K       k = {:.4e} 1/s (95 % CI {:.4e} .. {:.4e})",
            args.temperature, at.rate, at.rate_ci95[0], at.rate_ci95[1]
        );
        println!(
            "retention     1/k = {:.4e} s (95 % CI {:.4e} .. {:.4e} s)",
            at.mean_time, at.time_ci95[0], at.time_ci95[1]
        );
    }
    if let Some(out) = &args.out {
        std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
        let json = serde_json::json!({
            "fit": fit,
            "target": at,
            "sources": args.dirs.iter().map(|d| d.display().to_string()).collect::<Vec<_>>(),
        });
        let mut text = serde_json::to_string_pretty(&json)?;
        text.push('\n');
        write_bytes_atomic(&out.join("retention.json"), text.as_bytes())?;
    }
    Ok(ExitCode::SUCCESS)
}
