//! Reproduce the paper: run every numerical result of Chan, Thamwattana &
//! Hill, collect the data of each figure and measure each quantitative
//! claim, with a verdict computed from stated criteria (never hard-coded).
//!
//! This crate is an application of the physics library `tippetop`, not part
//! of it: it knows the paper (its scenarios, figures, claims and constants);
//! the library knows tops. It does no I/O: the `tippetop reproduce` command
//! writes what [`reproduce`] returns.
//!
//! The shape follows the paper:
//! - [`runs`]: the table of runs, each a scenario file of `scenarios/`
//!   (embedded at build time) plus `--set` overrides listed in its settings,
//!   so a user can rerun any curve with `tippetop run scenarios/X.toml --set ...`;
//! - [`figures`]: one function per figure of the paper;
//! - [`claims`]: one function per claim, each with its criterion;
//! - [`sections`]: the report's extra sections (stick/slip, App. C against
//!   the numerics, and with `extended` the inversion maps, the ε study and
//!   the adhesion study);
//! - [`adhesion`]: the paper's nano scenarios rerun with van der Waals
//!   adhesion (extended mode);
//! - [`tube`]: the C60 inside carbon nanotubes, the paper's second
//!   setting (extended mode);
//! - [`report`]: the Markdown report.
//!
//! Three ways of computing each nano result are compared:
//! - **accurate** (`bilateral`): exact Coulomb friction, contact held with
//!   friction magnitude μ|N|, adaptive DOP853 at rtol 1e-10;
//! - **paper, accurate** (`paper`): the paper's literal law
//!   (`coulomb_sliding`, `contact = "paper"`: friction −μ N v/|v| with N's
//!   sign), adaptive at rtol 1e-10: what the paper's equations give;
//! - **paper's method** (`rk4/500`): the same equations with classical RK4 on
//!   500 steps over the window, the paper's numerics.

pub mod adhesion;
pub mod claims;
pub mod figures;
pub mod report;
pub mod runs;
pub mod sections;
pub mod tube;

use serde::Serialize;
use tippetop::{Error, Scenario, Trajectory};

pub use report::report_markdown;
pub use runs::SCENARIOS;
/// The paper's constants of App. C (also used by the library's asymptotics).
pub use tippetop::analysis::asymptotics::{PAPER_C1, PAPER_T_STAR, PAPER_U1, PAPER_U2};

/// The paper's retarding force H \[N\].
pub const PAPER_H: f64 = 1e-22;

/// One curve of a figure (SI units).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Curve {
    /// Column name in the figure's CSV and legend entry.
    pub name: String,
    /// Times \[s\].
    pub t: Vec<f64>,
    /// Values (unit in the figure's `y_label`).
    pub y: Vec<f64>,
    /// Drawn dashed (closed forms, the paper's method).
    pub dashed: bool,
}

/// The data of one figure of the paper.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Figure {
    /// Two-digit figure number, "02" … "15" (or a study's name, "eps_10s").
    pub id: String,
    /// Title, after the paper's caption.
    pub title: String,
    /// x-axis label (with unit, after `x_scale`).
    pub x_label: String,
    /// Factor from seconds to the x-axis unit (1e6 for µs); for a figure
    /// whose x is not a time, from its SI unit to the axis unit.
    pub x_scale: f64,
    /// Header of the CSV's first column (the curves' `t`, in SI units);
    /// empty: "t" (seconds).
    pub x_name: String,
    /// y-axis label with unit.
    pub y_label: String,
    /// The curves.
    pub curves: Vec<Curve>,
    /// Horizontal reference lines (value, label).
    pub hlines: Vec<(f64, String)>,
    /// Vertical marks (time \[s\], label): force switches and reversals.
    pub vlines: Vec<(f64, String)>,
    /// A fast oscillation (nutation): drawn as each curve's running mean
    /// with its running min–max band, so curves and laws can be compared.
    pub envelope: bool,
    /// What the figure shows and what we chose.
    pub note: String,
}

/// Verdict on one claim.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Verdict {
    /// Holds under the stated criterion.
    #[serde(rename = "reproduced")]
    Reproduced,
    /// Holds in part (in one setting, or qualitatively but not quantitatively).
    #[serde(rename = "partly")]
    Partly,
    /// Does not hold.
    #[serde(rename = "not reproduced")]
    NotReproduced,
}

impl Verdict {
    /// Text used in the report.
    pub fn as_str(&self) -> &'static str {
        match self {
            Verdict::Reproduced => "reproduced",
            Verdict::Partly => "partly",
            Verdict::NotReproduced => "not reproduced",
        }
    }

    /// The verdict of a claim tested in two settings: the common verdict if
    /// they agree, else partly.
    pub fn combine(a: Verdict, b: Verdict) -> Verdict {
        if a == b { a } else { Verdict::Partly }
    }

    /// Reproduced if `full`, else partly if `part`, else not reproduced.
    pub fn from_levels(full: bool, part: bool) -> Verdict {
        if full {
            Verdict::Reproduced
        } else if part {
            Verdict::Partly
        } else {
            Verdict::NotReproduced
        }
    }
}

/// One quantitative claim of the paper with what we measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Claim {
    /// Short stable identifier.
    pub id: String,
    /// The claim, as the paper makes it.
    pub claim: String,
    /// The paper's value or statement.
    pub paper_value: String,
    /// What we measured (numbers with units).
    pub measured: String,
    /// What we measured in one line for the report's table (at most 80
    /// characters, 3-4 significant figures with units).
    pub summary: String,
    /// Runs and settings used.
    pub settings: String,
    /// Verdict.
    pub verdict: Verdict,
    /// One sentence of why, including the criterion.
    pub why: String,
}

/// A run made for the reproduction.
#[derive(Debug, Clone)]
pub struct Run {
    /// Short name, e.g. "nano_bilateral".
    pub name: String,
    /// Scenario file and overrides.
    pub settings: String,
    /// The scenario actually run.
    pub scenario: Scenario,
    /// The result.
    pub trajectory: Trajectory,
}

/// A 2D map (heat map) with overlay curves, for the CLI to draw.
#[derive(Debug, Clone, PartialEq)]
pub struct MapData {
    /// File stem, e.g. "inversion_map_regularized".
    pub id: String,
    /// Title.
    pub title: String,
    /// x-axis label.
    pub x_label: String,
    /// y-axis label.
    pub y_label: String,
    /// Colour-bar label.
    pub z_label: String,
    /// Grid values along x.
    pub xs: Vec<f64>,
    /// Grid values along y.
    pub ys: Vec<f64>,
    /// `z[j][i]` at `(xs[i], ys[j])`; NaN for a failed case.
    pub z: Vec<Vec<f64>>,
    /// Overlay curves (x, y) in data coordinates.
    pub lines: Vec<(Vec<f64>, Vec<f64>)>,
    /// The sweep's CSV (one row per case).
    pub csv: String,
}

/// Everything `reproduce` produces (the CLI writes it to disk).
#[derive(Debug, Clone)]
pub struct Reproduction {
    /// Figures 02–15 except 05 (the drawing, see `snapshots`).
    pub figures: Vec<Figure>,
    /// Fig. 5: instants (t \[s\], θ \[rad\]) of the accurate nano run.
    pub snapshots: Vec<(f64, f64)>,
    /// Top geometry for the drawing: (R, a) \[m\].
    pub geometry: (f64, f64),
    /// The claims with verdicts.
    pub claims: Vec<Claim>,
    /// All runs.
    pub runs: Vec<Run>,
    /// Whether the short-window quick mode was used.
    pub quick: bool,
    /// Extra report sections (title, Markdown body).
    pub sections: Vec<(String, String)>,
    /// Heat maps (extended mode).
    pub maps: Vec<MapData>,
}

/// Options of [`reproduce`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Options {
    /// Shorten every window 10x (for tests; verdicts then are not meaningful).
    pub quick: bool,
    /// Also run the heavier studies (inversion maps, the ε study of the
    /// friction law, the adhesion study).
    pub extended: bool,
}

impl Options {
    /// The factor every window is scaled by: 0.1 in quick mode, else 1.
    pub fn time_factor(&self) -> f64 {
        if self.quick { 0.1 } else { 1.0 }
    }
}

/// Run everything and measure every claim. `progress` gets the name of each
/// run or study as it starts.
pub fn reproduce(opts: Options, progress: &mut dyn FnMut(&str)) -> Result<Reproduction, Error> {
    let runs = runs::Runs::execute(&runs::specs(), opts, progress)?;
    let app_c = figures::AppC::of(&runs, opts);
    let mut figures = figures::all(&runs, &app_c);
    let snapshots = figures::fig05_snapshots(&runs, opts);
    let claims = claims::all(&runs, opts, &app_c)?;
    let mut sections = sections::core(&runs, &app_c);
    let mut maps = Vec::new();
    if opts.extended {
        let ext = sections::extended(&runs, opts, progress)?;
        sections.extend(ext.sections);
        figures.extend(ext.figures);
        maps = ext.maps;
    }
    let nano = &runs.get(runs::NANO_BILATERAL).scenario;
    Ok(Reproduction {
        figures,
        snapshots,
        geometry: (nano.top.radius, nano.top.offset),
        claims,
        runs: runs.into_vec(),
        quick: opts.quick,
        sections,
        maps,
    })
}
