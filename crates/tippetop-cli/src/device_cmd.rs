//! `tippetop device`: can the nano tippe top be a memory bit? The numbers
//! come from [`tippetop::analysis::device`]; this writes them as
//! device.json and device.md (plain words) and prints the verdict.

use std::fmt::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Result;
use clap::Args;
use tippetop::analysis::desorption::DesorptionRate;
use tippetop::analysis::device::{self, DeviceOptions, DeviceReport, Found, Tally};
use tippetop::analysis::device_rare::{self as dr, BigTime, LyingRetention, Measured, Sizes};
use tippetop::analysis::retention::Extrapolation;
use tippetop::human::{BEYOND_ANY_TIME_SCALE, YEAR, beyond_any_time_scale};

use crate::output::{OutDir, write_bytes_atomic};
use crate::scenario_load::input_error;

/// Long help of `tippetop device`.
pub const DEVICE_LONG_ABOUT: &str =
    "Answer, with numbers, whether the nano tippe top can be a memory bit
(docs/physics.md#device). Computes, each by this run:
  - the paper's model (preset nano, T = 0) and the same top with adhesion (nano-adhesive):
    the paper's write and its reversal as the erase (100 us phases), the smallest |H| along the
    paper's direction that writes, the best write and erase found by a protocol search;
  - C60 on graphene (nano-physical: Langevin, adhesion, the 1.1 eV lying well of a 1 nm stem)
    at 4, 77 and 300 K, 0.5 ns phases: P(write) with the paper's force and with no force,
    P(erase), Wilson intervals; the smallest force whose every run writes; how long the standing
    state lasts (first passage out of zero); the lying state's retention from the Arrhenius fit
    of escape rates at three raised temperatures (extrapolated, and labelled so); the highest
    temperature with 10 years of retention (the cross-check);
  - computed directly (docs/physics.md#device-rare): the lying state's retention at 4, 77
    and 300 K by splitting, beside transition-state theory's lower bound and the overdamped
    twin's exact answer (4 K: beyond any sampler, said so); the write error rates at 300 K of
    the paper's write and the search's best; the smallest well depth for 10 years at 300 K and
    77 K, and that design's write (force, shortest time with an error rate <= 1e-9).
    The rare events step at dt * rate <= 0.009 (at most 2 fs), and the 300 K residence is
    checked in the step: the same splitting at dt/2, converged when the change is below its
    95 % half-width (device.json dt_converged and step_check; --no-step-check skips it;
    docs/physics.md#step-check).
Writes device.json and device.md into --out. Takes minutes (5 min 37 s on 2 cores, 647 CPU-s, at the default sizes, 2026-12-07; a progress
line per stage); --quick cuts every ensemble, search and splitting (and leaves out the splitting
at 77 K and at the design depths) for a first look (46 CPU-s, release build, 2026-11-28).";

/// Can the nano tippe top be a memory bit? A report with numbers (minutes).
#[derive(Debug, Args)]
#[command(long_about = DEVICE_LONG_ABOUT)]
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
    /// Skip the step check of the 300 K lying residence (the splitting
    /// again at dt/2, about twice its cost): device.md then says the step
    /// is unchecked.
    #[arg(long)]
    pub no_step_check: bool,
    /// Number of threads, 1 to 1024 (default: one per core).
    #[arg(long, value_name = "T")]
    pub threads: Option<usize>,
}

/// `v` with 4 significant figures (`tippetop::human`: plain between 1e-3
/// and 1e4, else `1.234e-22`; `0` for zero).
fn g(v: f64) -> String {
    tippetop::human::sig(v, 4)
}

/// A duration in readable units: ps … s, hours, days, years (beyond
/// 10⁴ years as `1.234 × 10^32 years`, as [`big`] writes times beyond f64;
/// beyond 10^100 years in words, [`BEYOND_ANY_TIME_SCALE`]).
fn dur(s: f64) -> String {
    if !s.is_finite() {
        // Not reached: the report's times are finite or come through
        // [`big`] with their logarithm.
        return "not finite".into();
    }
    let (x, u) = if s < 1e-9 {
        (s * 1e12, "ps")
    } else if s < 1e-6 {
        (s * 1e9, "ns")
    } else if s < 1e-3 {
        (s * 1e6, "µs")
    } else if s < 1.0 {
        (s * 1e3, "ms")
    } else if s < 3600.0 {
        (s, "s")
    } else if s < 86400.0 {
        (s / 3600.0, "h")
    } else if s < YEAR {
        (s / 86400.0, "days")
    } else if s < 1e4 * YEAR {
        (s / YEAR, "years")
    } else {
        return years_pow10(s.log10());
    };
    format!("{} {u}", g(x))
}

/// `10^log10_seconds` seconds as `1.234 × 10^32 years`, or
/// [`BEYOND_ANY_TIME_SCALE`] past 10^100 years.
fn years_pow10(log10_seconds: f64) -> String {
    if beyond_any_time_scale(log10_seconds) {
        return BEYOND_ANY_TIME_SCALE.into();
    }
    let y = log10_seconds - YEAR.log10();
    let mut e = y.floor();
    let mut m = 10f64.powf(y - e);
    if format!("{m:.3}") == "10.000" {
        (m, e) = (1.0, e + 1.0);
    }
    format!("{m:.3} × 10^{e:.0} years")
}

/// A time that may exceed f64.
fn big(t: &BigTime) -> String {
    match t.seconds {
        Some(s) => dur(s),
        None => years_pow10(t.log10_seconds),
    }
}

/// An extrapolated mean retention `1/k` (finite text however far the
/// extrapolation reaches) and the same with its 95 % interval: the ends
/// beyond any time scale said once, in words.
fn extrapolated(e: &Extrapolation) -> (String, String) {
    let at = |z: f64| BigTime::from_ln(-(e.ln_rate + z * e.ln_rate_se));
    let (mid, lo, hi) = (at(0.0), at(1.96), at(-1.96));
    let far = |t: &BigTime| beyond_any_time_scale(t.log10_seconds);
    let with_interval = match (far(&lo), far(&mid), far(&hi)) {
        (true, _, _) => format!("{BEYOND_ANY_TIME_SCALE}, all of its 95 % interval"),
        (false, true, _) => format!("{BEYOND_ANY_TIME_SCALE}; 95 % from {}", big(&lo)),
        (false, false, true) => {
            format!("{} (95 %: {} – beyond any time scale)", big(&mid), big(&lo))
        }
        _ => format!("{} (95 %: {} – {})", big(&mid), big(&lo), big(&hi)),
    };
    (big(&mid), with_interval)
}

/// A transition-state bound in words: `at least 8.447 × 10^15 years`, or
/// past 10^100 years that the state lasts beyond any time scale.
fn at_least(tst: &BigTime) -> String {
    if beyond_any_time_scale(tst.log10_seconds) {
        "no escape: it lasts beyond any time scale (its transition-state bound, a lower one, is over 10^100 years)"
            .into()
    } else {
        format!("at least {} (transition-state bound)", big(tst))
    }
}

/// A splitting estimate of a time, with its interval.
fn ams_time(m: &Measured) -> String {
    format!(
        "{} (95 %: {} – {})",
        dur(m.estimate),
        dur(m.ci95[0]),
        dur(m.ci95[1])
    )
}

/// A splitting estimate of a probability, with its interval.
fn ams_p(m: &Measured) -> String {
    if m.extinct {
        format!("0 (no path reached it; 95 % upper bound {})", g(m.ci95[1]))
    } else {
        format!(
            "{} (95 %: {} – {})",
            g(m.estimate),
            g(m.ci95[0]),
            g(m.ci95[1])
        )
    }
}

fn ev(j: f64) -> String {
    format!("{} eV", g(j / dr::EV))
}

/// Why a retention was not measured, in words.
fn not_measured(l: &LyingRetention) -> String {
    match l.not_measured {
        Some("beyond_reach") => format!("beyond any sampler's reach ({} kT)", g(l.barrier_kt)),
        _ => "not measured (--quick)".into(),
    }
}

/// The step check of a measured residence, in words: "converged in the
/// step: at dt/2 = 1.000e-15 s it is ... (a change of 7.029 %, below the
/// 95 % half-width 46.09 %)", NOT converged, or unchecked.
fn step_words(l: &LyingRetention) -> String {
    let Some(m) = &l.ams else {
        return String::new();
    };
    let Some(c) = &l.step_check else {
        let why = if m.estimate > 0.0 {
            "--no-step-check"
        } else {
            "no estimate to compare"
        };
        return format!("step unchecked at dt = {} s ({why})", g(l.dt));
    };
    let pct = |x: Option<f64>| {
        x.map_or("undefined".into(), |v| {
            format!("{} %", g(100.0 * v.exp_m1()))
        })
    };
    format!(
        "{} in the step: at dt = {} s, and at dt/2 {} (a change of {} against its 95 % half-width {})",
        if c.converged {
            "converged"
        } else {
            "NOT converged"
        },
        g(l.dt),
        dur(c.at_half_dt.estimate),
        pct(c.step_error),
        pct(c.statistical)
    )
}

/// One sentence on the lying state's retention at one temperature.
fn lying_words(l: &LyingRetention) -> String {
    match &l.ams {
        Some(m) => format!(
            "at {} K it lasts {} by splitting (barrier {} kT{})",
            l.temperature,
            ams_time(m),
            g(l.barrier_kt),
            match l.dt_converged {
                Some(true) => "; converged in dt",
                Some(false) => "; NOT converged in dt",
                None => "",
            }
        ),
        None if l.not_measured == Some("beyond_reach") => format!(
            "at {} K the barrier is {} kT, beyond any sampler's reach; {}",
            l.temperature,
            g(l.barrier_kt),
            at_least(&l.tst)
        ),
        None => format!(
            "at {} K (not measured by this run) {}",
            l.temperature,
            at_least(&l.tst)
        ),
    }
}

/// `v` with its unit, or `–` (no unit) when there is none.
fn opt_unit(v: Option<f64>, unit: &str) -> String {
    v.map(|x| format!("{} {unit}", g(x)))
        .unwrap_or_else(|| "–".into())
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
                "found ({} runs): {}; switches in {}, work {}; {}/{} of ±5 % perturbations succeed",
                f.evaluations,
                w.join("; "),
                opt_unit(f.time, "s"),
                opt_unit(f.energy, "J"),
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
         stays in the target over its last hold (docs/physics.md#bit).\n",
        opts.runs, opts.budget, opts.retention_runs
    );
    answer_section(&mut s, r);
    deterministic_section(&mut s, r);
    thermal_section(&mut s, r);
    rare_section(&mut s, r);
    retention_section(&mut s, r);
    s
}

/// The highest temperature with 10 years of retention, in words (the
/// Arrhenius extrapolation).
fn ten_years_words(r: &DeviceReport) -> String {
    r.retention
        .t_ten_years
        .map(|(t, [lo, hi])| format!("{t:.0} K (95 %: {lo:.0}–{hi:.0} K; extrapolated)"))
        .unwrap_or_else(|| "no temperature (no fit)".into())
}

/// The report's answer in words, paragraph by paragraph (the paper's
/// model; the standing state; the lying state and the writes; the
/// design), each sentence from the numbers below it.
fn answer_paragraphs(r: &DeviceReport) -> Vec<String> {
    let ten = ten_years_words(r);
    let mut paragraphs: Vec<String> = Vec::new();
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
    paragraphs.push(std::mem::take(&mut ans).join(" "));
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
    paragraphs.push(std::mem::take(&mut ans).join(" "));
    let rare = &r.rare;
    let lying: Vec<String> = rare.lying.iter().rev().map(lying_words).collect();
    ans.push(format!(
        "The lying state (the stem's 1.1 eV well), computed directly: {}.",
        lying.join("; ")
    ));
    paragraphs.push(std::mem::take(&mut ans).join(" "));
    if let Some(p) = losses_paragraph(rare) {
        paragraphs.push(p);
    }
    for w in &rare.writes {
        ans.push(format!(
            "At 300 K {} fails with probability {} (95 %: {} – {}), {}.",
            write_name(w),
            g(w.rate),
            g(w.ci95[0]),
            g(w.ci95[1]),
            write_limit(w)
        ));
    }
    paragraphs.push(std::mem::take(&mut ans).join(" "));
    ans.extend(design_sentences(rare));
    ans.push(format!(
        "(Cross-check, extrapolated: the Arrhenius fit gives 10 years up to {ten}.)"
    ));
    paragraphs.push(ans.join(" "));
    paragraphs.retain(|p| !p.is_empty());
    paragraphs
}

/// The paragraph that counts every way the bit is lost (orientation and
/// desorption), or `None` where the report has no loss figures.
fn losses_paragraph(rare: &device::Rare) -> Option<String> {
    let losses: Vec<String> = rare
        .losses
        .iter()
        .rev()
        .map(|l| {
            format!(
                "at {} K the molecule stays {} before it desorbs, and the bit lasts {}, limited by {}",
                l.temperature,
                residence_ci(&l.desorption),
                big(&l.lifetime),
                loss_name(l.limited_by)
            )
        })
        .collect();
    (!losses.is_empty()).then(|| {
        format!(
            "Every way the bit is lost, counted together (the molecule's {} binding to graphene): {}.",
            ev(rare.losses[0].desorption.well.binding),
            losses.join("; ")
        )
    })
}

/// The design sentences: the well depth and binding for 10 years, and the
/// 300 K design's write without a force.
fn design_sentences(rare: &device::Rare) -> Vec<String> {
    let mut ans = Vec::new();
    for d in &rare.designs {
        if let Some(depth) = d.depth {
            ans.push(format!(
                "For 10 years at {} K the well must be {} deep{}, and the molecule must be bound to its substrate by {}.",
                d.temperature,
                ev(depth),
                d.check
                    .as_ref()
                    .and_then(|c| c.ams.as_ref())
                    .map(|m| format!(" (splitting at that depth: {})", ams_time(m)))
                    .unwrap_or_default(),
                binding_words(d.binding)
            ));
        }
    }
    if let Some(w) = &rare.design_write {
        ans.push(match (w.write_time, &w.check) {
            (Some(t), Some(c)) => format!(
                "That 300 K design writes with no force at all (the standing state has no barrier) in {} with an error rate of {} (95 % upper {}).",
                dur(t + c.hold),
                g(c.rate),
                g(c.ci95[1])
            ),
            _ => format!(
                "That 300 K design writes with no force, but no write time within {} reached an error rate of {}.",
                dur(w.horizon),
                g(dr::ERROR_TARGET)
            ),
        });
    }
    ans
}

/// A write of the report in a sentence: the search's best write with
/// where it comes from.
fn write_name(w: &dr::WriteError) -> String {
    if w.label == "the search's best write" {
        format!(
            "the search's best write (found on the paper's model at T = 0; its force held over the whole {} phase)",
            dur(w.phase)
        )
    } else {
        w.label.clone()
    }
}

/// What sets a write's error rate, in words.
fn write_limit(w: &dr::WriteError) -> &'static str {
    if w.hold_escape > w.late.ci95[1] {
        "set by the lying state's own escape during the hold"
    } else {
        "set by the fall arriving late"
    }
}

/// A rate with its 95 % interval: `3.008e-8 (6.415e-9 – 1.411e-7)`.
/// A desorption residence `1/k` with its 95 % interval `[1/hi, 1/lo]`, or
/// its power of ten beyond f64.
fn residence_ci(d: &DesorptionRate) -> String {
    match d.residence {
        Some(t) if d.ci95[0] > 0.0 => format!(
            "{} (95 %: {} – {})",
            dur(t),
            dur(1.0 / d.ci95[1]),
            dur(1.0 / d.ci95[0])
        ),
        _ => big(&BigTime::from_ln(-d.ln_rate)),
    }
}

/// The design's binding for the molecule, in words.
fn binding_words(b: Option<f64>) -> String {
    match b {
        Some(e) => format!(
            "at least {} (C60 on one graphene sheet: {}; TST bound)",
            ev(e),
            ev(tippetop::physics::adhesion::Adhesion::c60_on_graphene()
                .binding()
                .map_or(f64::NAN, |b| b.energy))
        ),
        None => "more than 100 eV".into(),
    }
}

/// What limits the bit, in words.
fn loss_name(limited_by: &str) -> &'static str {
    if limited_by == "desorption" {
        "the molecule's desorption"
    } else {
        "the lying state's escape over the stem's well"
    }
}

fn rate_ci(rate: f64, ci: [f64; 2]) -> String {
    format!("{} ({} – {})", g(rate), g(ci[0]), g(ci[1]))
}

/// The answer's table: each state's retention (95 %) and what limits it,
/// each write's error rate at 300 K, and the design.
fn answer_table(r: &DeviceReport) -> String {
    let mut t =
        String::from("| | retention or error rate (95 %) | what limits it |\n|---|---|---|\n");
    let mut row = |what: String, value: String, limit: String| {
        let _ = writeln!(t, "| {what} | {value} | {limit} |");
    };
    for th in &r.thermal {
        let (left, runs) = th.zero_left;
        let value = match &th.zero_escape {
            Some(e) => format!(
                "{} (95 %: {} – {}); {left} of {runs} runs left it within 1 ns",
                dur(e.mean_time),
                dur(1.0 / e.ci95[1]),
                dur(1.0 / e.ci95[0])
            ),
            None => format!("{left} of {runs} runs left it within 1 ns"),
        };
        row(
            format!("state 0 (standing), {} K", th.temperature),
            value,
            format!(
                "no barrier: with no force the top falls to lying in {}/{} runs",
                th.write_without_force.successes, th.write_without_force.runs
            ),
        );
    }
    for l in r.rare.lying.iter().rev() {
        let value = match &l.ams {
            Some(m) if l.step_check.is_some() || l.temperature >= 300.0 => {
                format!("{} by splitting; {}", ams_time(m), step_words(l))
            }
            Some(m) => format!("{} by splitting", ams_time(m)),
            None if beyond_any_time_scale(l.tst.log10_seconds) => {
                "beyond any time scale (its transition-state lower bound: over 10^100 years)".into()
            }
            None => format!("at least {} (transition-state bound)", big(&l.tst)),
        };
        let limit = format!(
            "escape over the stem's well: {} = {} kT{}",
            ev(l.barrier),
            g(l.barrier_kt),
            match l.not_measured {
                Some("beyond_reach") => ", beyond any sampler's reach",
                Some(_) => " (not measured by this run)",
                None => "",
            }
        );
        row(
            format!("state 1 (lying), {} K", l.temperature),
            value,
            limit,
        );
    }
    for l in r.rare.losses.iter().rev() {
        let d = &l.desorption;
        row(
            format!("the molecule on graphene, {} K", l.temperature),
            format!("{} before it desorbs", residence_ci(d)),
            format!(
                "desorption: binding {} = {} kT",
                ev(d.well.binding),
                g(d.well.binding_kt)
            ),
        );
        row(
            format!("the bit, {} K", l.temperature),
            format!("lifetime {}", big(&l.lifetime)),
            format!("limited by {}", loss_name(l.limited_by)),
        );
    }
    for w in &r.rare.writes {
        row(
            format!("{}, 300 K, {} phase", w.label, dur(w.phase)),
            format!("write error rate {}", rate_ci(w.rate, w.ci95)),
            write_limit(w).trim_start_matches("set by ").to_string(),
        );
    }
    for d in &r.rare.designs {
        let Some(depth) = d.depth else {
            row(
                format!("the design at {} K", d.temperature),
                "no well up to 100 eV keeps 10 years".into(),
                "–".into(),
            );
            continue;
        };
        let check = d
            .check
            .as_ref()
            .and_then(|c| c.ams.as_ref())
            .map(|m| format!("; splitting there: {}", ams_time(m)))
            .unwrap_or_default();
        row(
            format!("the design at {} K: a {} well", d.temperature, ev(depth)),
            format!("10 years (transition-state bound, a lower one){check}"),
            d.check.as_ref().map_or_else(
                || "escape over the deeper well".into(),
                |c| format!("escape over the deeper well: {} kT", g(c.barrier_kt)),
            ),
        );
    }
    if let Some(w) = &r.rare.design_write {
        let (value, limit) = match (w.write_time, &w.check) {
            (Some(t), Some(c)) => (
                format!(
                    "write error rate {} in {} with no force",
                    rate_ci(c.rate, c.ci95),
                    dur(t + c.hold)
                ),
                write_limit(c).trim_start_matches("set by ").to_string(),
            ),
            _ => (
                format!(
                    "no write time within {} reaches an error rate of {}",
                    dur(w.horizon),
                    g(dr::ERROR_TARGET)
                ),
                "the fall arriving late".into(),
            ),
        };
        row("the design's write, 300 K".into(), value, limit);
    }
    t
}

/// "## Answer": the verdict, the table of [`answer_table`], then the words
/// of [`answer_paragraphs`].
fn answer_section(s: &mut String, r: &DeviceReport) {
    let _ = writeln!(s, "## Answer\n");
    let zero_holds = r.thermal.iter().any(|t| t.zero_left.0 * 2 < t.zero_left.1);
    let _ = writeln!(
        s,
        "**{}**\n",
        if zero_holds {
            "Partly."
        } else {
            "Not as the paper proposes: state 0 does not hold."
        }
    );
    let _ = writeln!(s, "{}", answer_table(r));
    for p in answer_paragraphs(r) {
        let _ = writeln!(s, "{p}\n");
    }
    if !zero_holds {
        let _ = writeln!(
            s,
            "What would have to change: a barrier for the standing state too (an orientation well at θ = 0 \
             deeper than ~40 k_B T at the operating temperature for years), and an actuator that reaches the \
             top (the paper's force at the contact point has no physical actuator, docs/physics.md#bit).\n"
        );
    }
}

/// "## The deterministic models (T = 0)".
fn deterministic_section(s: &mut String, r: &DeviceReport) {
    let _ = writeln!(s, "## The deterministic models (T = 0)\n");
    for d in &r.deterministic {
        let _ = writeln!(s, "### Preset `{}`\n", d.preset);
        let _ = writeln!(
            s,
            "- The paper's write (H_x = H_y = 0.1 zN, 100 µs): {}, time {}, work {}{}.",
            p(&d.write),
            opt_unit(d.write.time_median, "s"),
            opt_unit(d.write.energy_median, "J"),
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
}

/// "## C60 on graphene": the table of the thermal runs.
fn thermal_section(s: &mut String, r: &DeviceReport) {
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
            .map(|e| extrapolated(&e).1)
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
}

/// "## Cross-check": the lying state's retention extrapolated.
fn retention_section(s: &mut String, r: &DeviceReport) {
    let ten = ten_years_words(r);
    let rt = &r.retention;
    let _ = writeln!(
        s,
        "\n## Cross-check: the lying state's retention extrapolated (Arrhenius)\n"
    );
    let _ = writeln!(
        s,
        "Escape out of state 1 from the well's bottom, measured at raised temperatures (first passages, \
         censored at 4 ns), fitted by ln k = ln ν − E/(k_B T) and extrapolated (docs/physics.md#retention). The \
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
}

/// "## Every way the bit is lost": desorption beside the lying state's
/// escape, and the bit's lifetime.
fn losses_section(s: &mut String, r: &DeviceReport) {
    let _ = writeln!(s, "\n## Every way the bit is lost\n");
    let _ = writeln!(
        s,
        "The bit is lost when the lying state escapes over the stem's well (above) or when the molecule leaves the \
         surface. Desorption is computed on the height coordinate (docs/physics.md#desorption): the C60's centre in \
         the continuum Lennard-Jones well of one graphene sheet, Langevin with the preset's translational damping; it \
         has desorbed where the binding has fallen to kT. Its rate is κ k_TST: k_TST the flux out of the well by \
         quadrature (an upper bound), κ the fraction of those crossings that are not recrossings, counted over paths \
         (Wilson 95 %). Beside it the two limits it tends to: strong damping (the Smoluchowski equation, exact) and \
         weak damping (Mel'nikov–Meshkov); in between (here) the rate lies below both. The lifetime is 1/(escape rate + desorption rate), the escape from the \
         splitting where it measured, else from TST's bound.\n"
    );
    let _ = writeln!(
        s,
        "| T [K] | binding | desorption rate (95 %) | residence | TST | κ (95 %) | strong / weak damping limits | step check | bit lifetime | limited by |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|---|---|");
    for l in r.rare.losses.iter().rev() {
        let d = &l.desorption;
        let c = &d.count;
        let step = match &d.step_check {
            Some(k) => format!(
                "{} at dt/2 = {} s: {}",
                rate_s(k.at_half_dt.estimate),
                g(k.at_half_dt.dt),
                if k.converged {
                    "converged"
                } else {
                    "NOT converged"
                }
            ),
            None => "unchecked".into(),
        };
        let _ = writeln!(
            s,
            "| {} | {} = {} kT | {} ({} – {}) | {} | {} | {} ({} – {}), {} of {} paths | {} / {} | {} | {} | {} |",
            l.temperature,
            ev(d.well.binding),
            g(d.well.binding_kt),
            rate_s(d.rate),
            rate_s(d.ci95[0]),
            rate_s(d.ci95[1]),
            residence_ci(d),
            rate_s(d.tst_rate),
            g(c.transmission),
            g(c.transmission_ci95[0]),
            g(c.transmission_ci95[1]),
            c.captured,
            c.paths,
            rate_s(d.overdamped_rate),
            rate_s(d.underdamped_rate),
            step,
            big(&l.lifetime),
            loss_name(l.limited_by)
        );
    }
    let _ = writeln!(
        s,
        "\nThe damping of the height is the preset's γ_t = {} 1/s (γ/ω₀ = {} at 300 K, ω₀ the well's frequency); \
         the molecule's stay is set by the binding, and by the damping through κ only.",
        r.rare
            .losses
            .first()
            .map_or_else(|| "-".into(), |l| g(l.desorption.damping)),
        r.rare
            .losses
            .iter()
            .find(|l| l.temperature == 300.0)
            .map_or_else(|| "-".into(), |l| g(l.desorption.damping_over_frequency))
    );
}

/// A rate \[1/s\] with its unit.
fn rate_s(k: f64) -> String {
    format!("{} 1/s", g(k))
}

/// The rare events, computed directly.
fn rare_section(s: &mut String, r: &DeviceReport) {
    let rare = &r.rare;
    let _ = writeln!(s, "\n## The lying state's retention, computed directly\n");
    let _ = writeln!(
        s,
        "Mean residence in state 1 (θ in π/2 ± 0.35) from the well's bottom, Langevin, by adaptive multilevel \
         splitting (docs/physics.md#ams: the flux relation, replicas' 95 % interval). Beside it, two closed answers: \
         transition-state theory (TST), a lower bound of the residence (every escape crosses an edge; docs/physics.md \
         §device-rare), and the exact mean exit time of the overdamped twin (the same top and frictions in the Brownian mode, \
         an exact 1D diffusion; faster than the Langevin top, which is not overdamped here). A barrier above {} kT is \
         beyond any sampler's reach and is said so.\n",
        dr::REACH_KT
    );
    let _ = writeln!(
        s,
        "| T [K] | barrier | splitting (Langevin) | TST lower bound | overdamped twin, exact | Arrhenius (extrapolated) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for l in &rare.lying {
        let arr = r
            .thermal
            .iter()
            .find(|t| t.temperature == l.temperature)
            .and_then(|t| t.one_retention)
            .map(|e| extrapolated(&e).0)
            .unwrap_or_else(|| "-".into());
        let ams = match &l.ams {
            Some(m) => format!(
                "{} ({} paths, {} steps of {} s)",
                ams_time(m),
                m.trajectories,
                tippetop::human::sig(m.steps as f64, 3),
                g(l.dt)
            ),
            None => not_measured(l),
        };
        let _ = writeln!(
            s,
            "| {} | {} = {} kT | {} | {} | {} | {} |",
            l.temperature,
            ev(l.barrier),
            g(l.barrier_kt),
            ams,
            big(&l.tst),
            big(&l.overdamped_exact),
            arr
        );
    }
    losses_section(s, r);
    let _ = writeln!(s, "\n## Write error rates at 300 K\n");
    let _ = writeln!(
        s,
        "A write fails if θ is outside state 1 at any step of the hold (stricter than the bit's rows). Its rate is at \
         most P_late + P_hold: P_late, the fall not yet past θ = {} rad by {} before the hold (splitting on the time; \
         measured at {} at the latest, a bound for later times since it only decreases), and P_hold = 1 − exp(−hold/τ), \
         the settled top leaving during the hold (τ the residence above).\n",
        g(dr::SETTLE),
        dur(dr::RELAX),
        dur(device::WRITE_HORIZON)
    );
    let _ = writeln!(
        s,
        "| write | force (H_x, H_y) | phase, hold | P_late | P_hold | error rate (95 %) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    let write_row = |s: &mut String, w: &dr::WriteError| {
        let _ = writeln!(
            s,
            "| {} | ({}, {}) N | {}, {} | {}{} | {} | {} ({} – {}) |",
            w.label,
            g(w.force[0]),
            g(w.force[1]),
            dur(w.phase),
            dur(w.hold),
            if w.late_bound { "≤ " } else { "" },
            ams_p(&w.late),
            g(w.hold_escape),
            g(w.rate),
            g(w.ci95[0]),
            g(w.ci95[1])
        );
    };
    for w in &rare.writes {
        write_row(s, w);
    }
    let _ = writeln!(s, "\n## The design: a well deep enough for 10 years\n");
    let _ = writeln!(
        s,
        "The smallest depth of the stem's well (its binding) whose TST residence, a lower bound, is 10 years: \
         sufficient (bisection to 1e-6; the overdamped twin's exact answer beside it), checked by splitting at that depth.\n"
    );
    let _ = writeln!(
        s,
        "| T [K] | depth (TST bound) | depth (overdamped twin) | barrier at that depth | splitting there | binding that keeps the molecule (TST bound) |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|");
    for d in &rare.designs {
        let check = d.check.as_ref();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} | {} |",
            d.temperature,
            d.depth
                .map(ev)
                .unwrap_or_else(|| "none up to 100 eV".into()),
            d.depth_overdamped
                .map(ev)
                .unwrap_or_else(|| "none up to 100 eV".into()),
            check
                .map(|c| format!("{} kT", g(c.barrier_kt)))
                .unwrap_or_else(|| "-".into()),
            check
                .and_then(|c| c.ams.as_ref())
                .map(ams_time)
                .unwrap_or_else(|| check.map(not_measured).unwrap_or_else(|| "-".into())),
            d.binding
                .map(ev)
                .unwrap_or_else(|| "none up to 100 eV".into())
        );
    }
    if let Some(w) = &rare.design_write {
        let _ = writeln!(
            s,
            "\nThe 300 K design's write: the smallest force is **{} N** (the standing state has no barrier: the top \
             falls into the lying well by itself). The shortest write time with an error rate ≤ {} is {} (the replicas' \
             survival curve of the fall reaches the target less P_hold at {}, plus {} to settle, plus the hold).",
            w.force,
            g(dr::ERROR_TARGET),
            w.write_time
                .zip(w.check.as_ref())
                .map(|(t, c)| format!("**{}**", dur(t + c.hold)))
                .unwrap_or_else(|| format!("not reached within {}", dur(w.horizon))),
            w.arrival.map(dur).unwrap_or_else(|| "-".into()),
            dur(dr::RELAX)
        );
        if let Some(c) = &w.check {
            let _ = writeln!(s, "\nChecked by a fresh splitting run at that time:\n");
            let _ = writeln!(
                s,
                "| write | force (H_x, H_y) | phase, hold | P_late | P_hold | error rate (95 %) |"
            );
            let _ = writeln!(s, "|---|---|---|---|---|---|");
            write_row(s, c);
        }
    }
}

/// Run `tippetop device`.
pub fn run(args: &DeviceArgs, quiet: bool) -> Result<ExitCode> {
    let d = DeviceOptions::default();
    let (runs, budget, rr) = if args.quick {
        (8, 12, 8)
    } else {
        (d.runs, d.budget, d.retention_runs)
    };
    let small = Sizes {
        replicas: 4,
        particles: 20,
    };
    let opts = DeviceOptions {
        runs: args.runs.unwrap_or(runs),
        budget: args.budget.unwrap_or(budget),
        retention_runs: args.retention_runs.unwrap_or(rr),
        threads: args.threads,
        rare_retention: if args.quick { small } else { d.rare_retention },
        step_check: !args.no_step_check,
        rare_deep: if args.quick { None } else { d.rare_deep },
        desorption_paths: if args.quick {
            2_000
        } else {
            d.desorption_paths
        },
        rare_write: if args.quick {
            Sizes {
                replicas: 3,
                particles: 10,
            }
        } else {
            d.rare_write
        },
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
        // The verdict and the answer's table; the words are in device.md.
        if let Some(answer) = md.split("## Answer\n\n").nth(1) {
            for block in answer.split("\n\n").take(2) {
                println!("{}\n", block.trim_end());
            }
        }
        println!(
            "the answer in words: {}",
            args.out.join("device.md").display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn long_times_read_as_powers_of_ten_of_years() {
        // 1e4 years is where the power form starts.
        assert_eq!(dur(1e4 * YEAR), "1.000 × 10^4 years");
        assert_eq!(dur(9999.0 * YEAR), "9999 years");
        // A mantissa that rounds to 10 carries into the exponent.
        assert_eq!(years_pow10((9.9996e5 * YEAR).log10()), "1.000 × 10^6 years");
        assert_eq!(dur(3.3e-3), "3.300 ms");
        assert_eq!(dur(8.447e15 * YEAR), "8.447 × 10^15 years");
        // Past 10^100 years, within f64 or beyond it (from the
        // logarithm): words, no digits.
        assert_eq!(dur(1e102 * YEAR), BEYOND_ANY_TIME_SCALE);
        let t =
            BigTime::from_ln((3.74f64.log10() + 664.0 + YEAR.log10()) * std::f64::consts::LN_10);
        assert!(t.seconds.is_none());
        assert_eq!(big(&t), BEYOND_ANY_TIME_SCALE);
        assert!(at_least(&t).starts_with("no escape: it lasts beyond any time scale"));
        let t = BigTime::from_ln((8.447e15 * YEAR).ln());
        assert_eq!(
            at_least(&t),
            "at least 8.447 × 10^15 years (transition-state bound)"
        );
    }

    fn extrapolation(ln_rate: f64, ln_rate_se: f64) -> Extrapolation {
        Extrapolation {
            temperature: 4.0,
            rate: 0.0,
            ln_rate,
            rate_ci95: [0.0, 0.0],
            ln_rate_se,
            mean_time: f64::INFINITY,
            time_ci95: [f64::INFINITY; 2],
        }
    }

    #[test]
    fn extrapolations_beyond_f64_are_finite_text() {
        let years = |ln_s: f64| {
            let y = ln_s / std::f64::consts::LN_10 - YEAR.log10();
            format!("{:.3} × 10^{} years", 10f64.powf(y - y.floor()), y.floor())
        };
        // ln k = −100 ± 10: 1/k = e^100 s = 8.5 × 10^35 years, and its
        // interval e^(100 ∓ 19.6): powers of ten.
        let (m, both) = extrapolated(&extrapolation(-100.0, 10.0));
        assert_eq!(m, years(100.0));
        assert_eq!(
            both,
            format!(
                "{} (95 %: {} – {})",
                years(100.0),
                years(80.4),
                years(119.6)
            )
        );
        // ln k = −2000: 1/k = e^2000 s = 10^868.6 s, beyond f64 and beyond
        // any time scale, its whole interval too.
        let (m, both) = extrapolated(&extrapolation(-2000.0, 10.0));
        assert_eq!(m, BEYOND_ANY_TIME_SCALE);
        assert_eq!(
            both,
            format!("{BEYOND_ANY_TIME_SCALE}, all of its 95 % interval")
        );
        // Only the upper end past 10^100 years (e^258.8 s = 10^104.9
        // years; e^200 s = 10^79.4 years).
        let (_, both) = extrapolated(&extrapolation(-200.0, 30.0));
        assert_eq!(
            both,
            format!(
                "{} (95 %: {} – beyond any time scale)",
                years(200.0),
                years(141.2)
            )
        );
    }
}
