//! `tippetop reproduce`: regenerate every numerical result of the nano
//! tippe-top paper into `--out`: for each figure NN, `figNN.png`,
//! `figNN.svg` and `figNN.csv` (first column t in seconds, one column per
//! curve), plus `report.md` (each claim beside what we measured, with a
//! verdict) and `claims.json`. The physics and the verdicts are computed by
//! the `tippetop-paper` crate; this module only writes them.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::Args;
use tippetop_paper::{self as paper, Figure, Options, Reproduction};

use crate::output::{OutDir, write_bytes_atomic, write_json_pretty, write_series_csv};
use crate::plot::{Panel, PlotOpts, RefLine, Series, VLine, line_plot, multi_panel};
use crate::progress;

/// Long help of `tippetop reproduce`.
pub const REPRODUCE_LONG_ABOUT: &str = "Reproduce the nano tippe-top paper's figures and numbers: runs \
                            the paper's scenarios (scenarios/*.toml, embedded) three ways (accurate \
                            with bilateral contact and exact Coulomb friction; the paper's literal \
                            law solved accurately; the paper's RK4 on 500 steps) and writes into \
                            --out: figNN.png/.svg/.csv for figures 02-15, report.md (every claim \
                            of the paper beside what we measured, with a verdict and why) and \
                            claims.json. --out is created, locked and checked before the runs \
                            (another tippetop command writing into it exits with code 1); the \
                            files are moved in together at the end, report.md last, and the \
                            files of the previous command into it that this one did not write \
                            (e.g. the ε-study figures of an earlier --extended) are removed.";

/// Reproduce the nano tippe-top paper's figures and numbers.
#[derive(Debug, Args)]
#[command(long_about = REPRODUCE_LONG_ABOUT)]
#[command(after_help = "Examples:\n  \
                        tippetop reproduce --out out\n  \
                        tippetop reproduce --extended --quiet --out out/full")]
pub struct ReproduceArgs {
    /// Output directory for figures, data and the report (locked while
    /// writing; the previous command's files in it are replaced or removed).
    #[arg(long, value_name = "DIR", default_value = "out")]
    pub out: PathBuf,

    /// Also run the extended studies beyond the paper (slower): the ε study
    /// of the friction law over 10 s and 150 s, the classical inversion
    /// maps, the adhesion study (the nano scenarios with C60/graphene
    /// van der Waals adhesion) and the C60 inside carbon nanotubes (the
    /// section "Inside a nanotube", figtube_energy).
    #[arg(long)]
    pub extended: bool,

    /// Shorten every window 10x: a smoke test of the pipeline (the verdicts
    /// are then meaningless and the report says so).
    #[arg(long)]
    pub quick: bool,
}

/// Reproduce the paper's results into `args.out` (`args.extended` adds the
/// ε study of the friction law, the inversion maps, the adhesion study and
/// the nanotube section).
/// `quiet` silences everything but errors.
pub fn run(args: &ReproduceArgs, quiet: bool) -> Result<()> {
    if args.out.exists() && !args.out.is_dir() {
        return Err(tippetop::Error::invalid(
            "--out",
            format!("{} exists and is not a directory", args.out.display()),
            "a directory, created if missing".into(),
        )
        .into());
    }
    // Created, locked and checked before the (long) computation; the files
    // are staged and committed as a unit (report.md last), and figures of a
    // previous reproduce that this one does not write are removed.
    let out = OutDir::open(&args.out)?;
    let t0 = std::time::Instant::now();
    let pb = progress::spinner(quiet, "running the paper's scenarios");
    let rep = match paper::reproduce(
        Options {
            quick: args.quick,
            extended: args.extended,
        },
        &mut |name| pb.set_message(format!("running {name}")),
    ) {
        Ok(r) => r,
        Err(e) => {
            pb.finish_and_clear();
            out.abandon();
            return Err(e.into());
        }
    };
    pb.set_message("writing figures");
    write_all(out.stage(), &rep)?;
    out.commit(&["report.md"])?;
    pb.finish_and_clear();
    if !quiet {
        let count = |v: paper::Verdict| rep.claims.iter().filter(|c| c.verdict == v).count();
        println!(
            "reproduced the paper in {}: {} figures, {} claims ({} reproduced, {} partly, {} not reproduced)",
            crate::output::fmt_duration(t0.elapsed().as_secs_f64()),
            rep.figures.len() + 1,
            rep.claims.len(),
            count(paper::Verdict::Reproduced),
            count(paper::Verdict::Partly),
            count(paper::Verdict::NotReproduced)
        );
        for c in &rep.claims {
            println!("  {:<16} {}", c.verdict.as_str(), c.id);
        }
        println!("report: {}", args.out.join("report.md").display());
    }
    Ok(())
}

/// Write every file of a reproduction into `dir`.
pub fn write_all(dir: &Path, rep: &Reproduction) -> Result<()> {
    for f in &rep.figures {
        write_figure(dir, f)?;
    }
    write_fig05(dir, rep)?;
    for m in &rep.maps {
        write_bytes_atomic(&dir.join(format!("{}.csv", m.id)), m.csv.as_bytes())?;
        crate::plot::heatmap(
            &dir.join(&m.id),
            &m.title,
            &m.x_label,
            &m.y_label,
            &m.z_label,
            &m.xs,
            &m.ys,
            &m.z,
            &crate::plot::HeatmapOpts {
                z_range: Some((0.0, std::f64::consts::PI)),
                lines: m.lines.clone(),
                ..Default::default()
            },
        )?;
    }
    write_json_pretty(&dir.join("claims.json"), &rep.claims)?;
    write_bytes_atomic(
        &dir.join("report.md"),
        paper::report_markdown(rep).as_bytes(),
    )?;
    Ok(())
}

/// figNN.csv on the union of the curves' time grids (empty field where a
/// curve has no value), and the PNG/SVG plot.
fn write_figure(dir: &Path, f: &Figure) -> Result<()> {
    let mut grid: BTreeMap<u64, usize> = BTreeMap::new();
    for c in &f.curves {
        for &t in &c.t {
            // t >= 0, so the bit pattern orders like the value.
            grid.insert(t.to_bits(), 0);
        }
    }
    for (i, v) in grid.values_mut().enumerate() {
        *v = i;
    }
    let ts: Vec<f64> = grid.keys().map(|&b| f64::from_bits(b)).collect();
    let mut cols: Vec<Vec<f64>> = vec![ts.clone()];
    for c in &f.curves {
        let mut col = vec![f64::NAN; ts.len()];
        for (t, y) in c.t.iter().zip(&c.y) {
            col[grid[&t.to_bits()]] = *y;
        }
        cols.push(col);
    }
    let mut headers = vec![if f.x_name.is_empty() {
        "t".to_string()
    } else {
        f.x_name.clone()
    }];
    headers.extend(f.curves.iter().map(|c| c.name.clone()));
    let h: Vec<&str> = headers.iter().map(|s| s.as_str()).collect();
    let c: Vec<&[f64]> = cols.iter().map(|v| v.as_slice()).collect();
    write_series_csv(&dir.join(format!("fig{}.csv", f.id)), &h, &c)?;

    if f.id == "02" {
        return write_fig02(dir, f);
    }
    let span = f
        .curves
        .iter()
        .filter_map(|c| c.t.last().copied())
        .fold(0.0, f64::max)
        * f.x_scale;
    let series: Vec<Series> = f
        .curves
        .iter()
        .map(|c| {
            let xs: Vec<f64> = c.t.iter().map(|t| t * f.x_scale).collect();
            // A nutating curve: its running mean with its min-max band over
            // 1/100 of the figure's span. The closed forms (dashed) are
            // smooth: drawn as they are, so the legend shows no band for them.
            let s = if f.envelope && !c.dashed {
                Series::envelope(c.name.clone(), &xs, &c.y, 400, span / 100.0)
            } else {
                Series::new(c.name.clone(), xs, c.y.clone())
            };
            if c.dashed { s.dashed() } else { s }
        })
        .collect();
    let opts = PlotOpts {
        hlines: f
            .hlines
            .iter()
            .map(|(y, l)| RefLine::new(*y, l.clone()))
            .collect(),
        vlines: vlines(f),
        ..Default::default()
    };
    if f.id == "09" {
        return write_fig09(dir, f, series, opts, span);
    }
    line_plot(
        &dir.join(format!("fig{}", f.id)),
        &f.title,
        &f.x_label,
        &f.y_label,
        &series,
        &opts,
    )
}

/// The figure's force switches as vertical marks, in its x unit.
fn vlines(f: &Figure) -> Vec<VLine> {
    f.vlines
        .iter()
        .map(|(t, l)| VLine::new(t * f.x_scale, l.clone()))
        .collect()
}

/// Fig. 2, readable: five oscillating θ(t) overlap, so `fig02.png` draws
/// each curve's running mean and min–max band over a sliding window of
/// 1/40 of the run (the curves themselves are in fig02.csv), one curve a
/// panel on the same axes (five translucent bands on one panel blend into
/// one colour), each beside the g = 9.8 bilateral mean in grey; and
/// `fig02_zoom.png` the curves themselves over the first 10 µs, where they
/// part.
fn write_fig02(dir: &Path, f: &Figure) -> Result<()> {
    let t_end = f
        .curves
        .iter()
        .filter_map(|c| c.t.last().copied())
        .fold(0.0, f64::max);
    // Each curve as its running mean with its running min-max band over
    // 2.5 µs (1/40 of the window, a few nutation periods once the top
    // lies), sliding: no zigzag from fixed bins.
    let window = t_end * f.x_scale / 40.0;
    let series: Vec<Series> = f
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let color = crate::plot::PALETTE[i % crate::plot::PALETTE.len()];
            let xs: Vec<f64> = c.t.iter().map(|t| t * f.x_scale).collect();
            let s = Series::envelope(c.name.clone(), &xs, &c.y, 450, window).color(color);
            if c.dashed { s.dashed() } else { s }
        })
        .collect();
    let hlines: Vec<RefLine> = f
        .hlines
        .iter()
        .map(|(y, l)| RefLine::new(*y, l.clone()))
        .collect();
    // The reference every panel shows: the g = 9.8 bilateral run's mean.
    let reference = f
        .curves
        .iter()
        .position(|c| c.name.starts_with("g=9.8") && c.name.contains("bilateral"));
    let y_range = Some((0.0, 1.05 * std::f64::consts::PI));
    let panels: Vec<Panel> = series
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let mut curves = Vec::new();
            let mut label = format!("θ [rad], {}", s.name);
            if let Some(r) = reference.filter(|&r| r != i) {
                let mut mean = Series::new("", series[r].xs.clone(), series[r].ys.clone())
                    .color((90, 90, 90))
                    .width(1);
                mean.band = None;
                curves.push(mean);
                label.push_str(&format!(" (grey: the mean of {})", series[r].name));
            }
            curves.push(s.clone());
            Panel {
                y_label: label,
                series: curves,
                opts: PlotOpts {
                    hlines: hlines.clone(),
                    y_range,
                    ..Default::default()
                },
            }
        })
        .collect();
    multi_panel(
        &dir.join("fig02"),
        "Fig. 2: θ, running mean and min–max band over 2.5 µs, g = 0, 9.8, 100 m/s²",
        &f.x_label,
        &panels,
        &PlotOpts {
            size: (1000, 1250),
            ..Default::default()
        },
    )?;
    let zoom_end = 10e-6;
    let zoom: Vec<Series> = f
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let (xs, ys): (Vec<f64>, Vec<f64>) =
                c.t.iter()
                    .zip(&c.y)
                    .filter(|(t, _)| **t <= zoom_end)
                    .map(|(t, y)| (t * f.x_scale, *y))
                    .unzip();
            let s = Series::new(c.name.clone(), xs, ys)
                .color(crate::plot::PALETTE[i % crate::plot::PALETTE.len()]);
            if c.dashed { s.dashed() } else { s }
        })
        .collect();
    let opts = PlotOpts {
        hlines,
        x_range: Some((0.0, zoom_end * f.x_scale)),
        ..Default::default()
    };
    line_plot(
        &dir.join("fig02_zoom"),
        &format!("{}: the first 10 µs", f.title),
        &f.x_label,
        &f.y_label,
        &zoom,
        &opts,
    )
}

/// Fig. 9, readable: Ω nutates with an amplitude some hundred times the
/// (C3) laws' values, so under the bands the laws sit near 0. Two panels
/// on the same time axis: the top one as the other nutating figures (each
/// numerical curve's running mean and min–max band over 1/100 of the
/// window, the laws as they are), the bottom one zoomed on the laws: its
/// Ω range is the laws' over the second half of the window (where they
/// are compared, the report's error figures), the numerics' running means
/// there over 1/5 of the window (tens of nutation periods) without bands,
/// and 0, so each law can be seen against its curve's mean. Each curve has the same colour in both panels.
fn write_fig09(
    dir: &Path,
    f: &Figure,
    series: Vec<Series>,
    opts: PlotOpts,
    span: f64,
) -> Result<()> {
    let colour = |i: usize| crate::plot::PALETTE[i % crate::plot::PALETTE.len()];
    let series: Vec<Series> = series
        .into_iter()
        .enumerate()
        .map(|(i, s)| s.color(colour(i)))
        .collect();
    // The numerics as running means over a fifth of the window (many
    // nutation periods: what is left of the nutation in them is ~ its
    // amplitude times period/window, the scale the laws are judged on).
    let zoom: Vec<Series> = f
        .curves
        .iter()
        .enumerate()
        .map(|(i, c)| {
            let xs: Vec<f64> = c.t.iter().map(|t| t * f.x_scale).collect();
            let s = if c.dashed {
                Series::new(c.name.clone(), xs, c.y.clone()).dashed()
            } else {
                let mut m = Series::envelope(c.name.clone(), &xs, &c.y, 200, span / 5.0);
                m.band = None;
                m
            };
            s.color(colour(i))
        })
        .collect();
    // The zoom's Ω range: the laws and the means over the second half,
    // and 0.
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for s in &zoom {
        for (x, y) in s.xs.iter().zip(&s.ys) {
            if *x >= span / 2.0 && y.is_finite() {
                lo = lo.min(*y);
                hi = hi.max(*y);
            }
        }
    }
    let pad = 0.1 * (hi - lo);
    let top = Panel {
        y_label: f.y_label.clone(),
        series,
        opts: opts.clone(),
    };
    let bottom = Panel {
        y_label: format!(
            "{}, zoomed: means over {} µs",
            f.y_label,
            tippetop::human::sig(span / 5.0, 3)
        ),
        series: zoom,
        opts: PlotOpts {
            y_range: (pad > 0.0).then_some((lo - pad, hi + pad)),
            legend: crate::plot::Legend::None,
            ..opts.clone()
        },
    };
    multi_panel(
        &dir.join(format!("fig{}", f.id)),
        &format!("{}; below: zoomed on the laws", f.title),
        &f.x_label,
        &[top, bottom],
        &PlotOpts {
            size: (1000, 900),
            ..Default::default()
        },
    )
}

/// Fig. 5: the top drawn at several instants (sphere, symmetry axis, centre
/// of mass), side by side, in units of Å.
fn write_fig05(dir: &Path, rep: &Reproduction) -> Result<()> {
    let (r, a) = rep.geometry;
    let unit = 1e-10; // Å
    let (rr, aa) = (r / unit, a / unit);
    let spacing = 3.0 * rr;
    let mut series = Vec::new();
    for (i, &(t, theta)) in rep.snapshots.iter().enumerate() {
        let x0 = i as f64 * spacing;
        let (s, c) = theta.sin_cos();
        let centre = (x0, rr);
        let circle = |rad: f64, cx: f64, cy: f64| -> (Vec<f64>, Vec<f64>) {
            (0..=120)
                .map(|j| {
                    let p = j as f64 / 120.0 * std::f64::consts::TAU;
                    (cx + rad * p.cos(), cy + rad * p.sin())
                })
                .unzip()
        };
        let (xs, ys) = circle(rr, centre.0, centre.1);
        let color = crate::plot::PALETTE[i % crate::plot::PALETTE.len()];
        series.push(
            Series::new(format!("t = {:.3} µs, θ = {:.2}", t * 1e6, theta), xs, ys).color(color),
        );
        // Symmetry axis k through the centre; the centre of mass O = C − a k.
        let k = (s, c);
        series.push(
            Series::new(
                "",
                vec![centre.0 - 1.3 * rr * k.0, centre.0 + 1.3 * rr * k.0],
                vec![centre.1 - 1.3 * rr * k.1, centre.1 + 1.3 * rr * k.1],
            )
            .color(color),
        );
        let o = (centre.0 - aa * k.0, centre.1 - aa * k.1);
        let (xs, ys) = circle(0.12 * rr, o.0, o.1);
        series.push(Series::new("", xs, ys).color((0, 0, 0)));
        // The heavy end: the sphere's surface within 35° of −k (the side
        // of the centre of mass), drawn thick.
        let pole = (-k.1).atan2(-k.0);
        let (xs, ys): (Vec<f64>, Vec<f64>) = (0..=30)
            .map(|j| {
                let p = pole + (j as f64 / 30.0 - 0.5) * 70f64.to_radians();
                (centre.0 + rr * p.cos(), centre.1 + rr * p.sin())
            })
            .unzip();
        let name = if i == 0 {
            "heavy end (side of the centre of mass)"
        } else {
            ""
        };
        series.push(Series::new(name, xs, ys).color((0, 0, 0)).width(6));
    }
    let n = rep.snapshots.len() as f64;
    let x_range = (-1.5 * rr, (n - 1.0) * spacing + 1.5 * rr);
    let size = (1500u32, 480u32);
    // Equal scales in x and z: the y range's top follows the plotting
    // area's aspect (computed by the plot from its layout, per backend).
    let opts = PlotOpts {
        size,
        x_range: Some(x_range),
        y_range: Some((-0.3 * rr, 3.0 * rr)),
        equal_aspect: true,
        hlines: vec![RefLine::new(0.0, "plane")],
        ..Default::default()
    };
    line_plot(
        &dir.join("fig05"),
        "Fig. 5: precession of the nano tippe top (accurate run; black circle: centre of mass; thick arc: heavy end)",
        "x [Å] (instants side by side)",
        "z [Å]",
        &series,
        &opts,
    )?;
    let ts: Vec<f64> = rep.snapshots.iter().map(|s| s.0).collect();
    let th: Vec<f64> = rep.snapshots.iter().map(|s| s.1).collect();
    write_series_csv(&dir.join("fig05.csv"), &["t", "theta"], &[&ts, &th])
}
