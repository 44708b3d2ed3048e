//! `tippetop retention`: the Arrhenius extrapolation of escape rates
//! measured by ensembles with a first-passage criterion
//! (`tippetop ensemble --first-passage ...`) at raised temperatures, to a
//! target temperature ([`tippetop::analysis::retention`]).

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{Context, Result};
use tippetop::analysis::retention::{RatePoint, check_temperature, fit_arrhenius};
use tippetop::human::s4;

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
    The values read are checked: temperatures 1e-3 to 1e5 K (--temperature too), rates 1e-300 \
    to 1e300 1/s, 0 < ln_rate_se <= 1; the extrapolation must be finite in f64.\n\n\
    Exit codes: 0 ok, 2 bad input (one line naming the file and the field, or the option), 1 \
    I/O failures writing --out.";

/// Retention time at a temperature, from ensembles' escape rates (Arrhenius).
#[derive(Debug, Clone, clap::Args)]
#[command(long_about = RETENTION_LONG_ABOUT)]
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
    /// Target temperature [K] (1e-3 to 1e5).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub temperature: f64,
    /// Write retention.json into this directory (created if missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
}

use crate::scenario_load::input_error;

/// The fields of an ensemble's `summary.json` that `retention` reads: the
/// field of [`RatePoint`] and its path in the file.
const FIELDS: [(&str, &str); 3] = [
    ("temperature", "temperature"),
    ("rate", "first_passage.escape_rate.rate"),
    ("ln_rate_se", "first_passage.escape_rate.ln_rate_se"),
];

/// The escape rate of one ensemble directory, checked: `Err` is the
/// one-line message naming the file and the field.
fn read_point(dir: &std::path::Path) -> std::result::Result<RatePoint, String> {
    let path = dir.join("summary.json");
    let file = path.display();
    let what = "an ensemble's summary.json, written by tippetop ensemble --first-passage";
    let text = crate::scenario_load::read_small(&path, what)?;
    let v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| format!("{file}: not JSON: {e} ({what})"))?;
    let number = |path_in: &str| -> std::result::Result<Option<f64>, String> {
        let mut x = &v;
        for part in path_in.split('.') {
            x = &x[part];
        }
        match x {
            serde_json::Value::Null => Ok(None),
            serde_json::Value::Number(n) => Ok(n.as_f64()),
            other => Err(format!(
                "{file}: {path_in}: {other} is not a number ({what})"
            )),
        }
    };
    let Some(temperature) = number("temperature")? else {
        return Err(format!(
            "{file}: temperature: missing (an ensemble's summary.json of a Langevin or Brownian run)"
        ));
    };
    let (Some(rate), Some(ln_rate_se)) = (
        number("first_passage.escape_rate.rate")?,
        number("first_passage.escape_rate.ln_rate_se")?,
    ) else {
        return Err(format!(
            "{file}: first_passage.escape_rate: missing (no run passed: run longer, at a higher temperature, or with --first-passage)"
        ));
    };
    let p = RatePoint {
        temperature,
        rate,
        ln_rate_se,
    };
    p.check().map_err(|e| match e {
        tippetop::Error::Invalid { key, what, range } => {
            let field = FIELDS
                .iter()
                .find(|f| f.0 == key)
                .map_or(key.as_str(), |f| f.1);
            format!("{file}: {field}: {what} ({range})")
        }
        other => format!("{file}: {other}"),
    })?;
    Ok(p)
}

/// Run `tippetop retention`. Bad input (a target temperature out of range,
/// a directory without a valid escape rate, values out of range, fewer than
/// two temperatures): one line naming the file and the field, exit code 2.
pub fn run(args: &RetentionArgs, quiet: bool) -> Result<ExitCode> {
    if let Err(e) = check_temperature("--temperature", args.temperature) {
        return Ok(input_error(e));
    }
    let mut points = Vec::new();
    for dir in &args.dirs {
        match read_point(dir) {
            Ok(p) => points.push(p),
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    if !points
        .iter()
        .any(|p| p.temperature != points[0].temperature)
    {
        return Ok(input_error(format!(
            "DIR: {} escape rate(s), all at {} K (ensembles at two or more distinct temperatures)",
            points.len(),
            points[0].temperature
        )));
    }
    let fit = match fit_arrhenius(&points) {
        Ok(f) => f,
        Err(e) => return Ok(input_error(format!("DIR: {e}"))),
    };
    let at = match fit.extrapolate_checked("--temperature", args.temperature) {
        Ok(at) => at,
        Err(e) => return Ok(input_error(e)),
    };
    if !quiet {
        for p in &points {
            println!(
                "T = {:>8.2} K   k = {} 1/s (ln k ± {:.3})",
                p.temperature,
                s4(p.rate),
                p.ln_rate_se
            );
        }
        println!(
            "barrier        E = {} J = {:.4} eV ± {:.4} eV (fit; chi2 {:.3}, dof {})",
            s4(fit.barrier),
            fit.barrier_ev,
            fit.barrier_se / 1.602176634e-19,
            fit.chi2,
            fit.dof
        );
        println!(
            "at {} K       k = {} 1/s (95 % CI {} .. {})",
            args.temperature,
            s4(at.rate),
            s4(at.rate_ci95[0]),
            s4(at.rate_ci95[1])
        );
        println!(
            "retention     1/k = {} s (95 % CI {} .. {} s)",
            s4(at.mean_time),
            s4(at.time_ci95[0]),
            s4(at.time_ci95[1])
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
