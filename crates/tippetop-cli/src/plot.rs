//! Plots: line plots, stacked panels sharing x, and heat maps, each written
//! as both `STEM.png` and `STEM.svg` (atomically, see [`crate::output`]).
//!
//! Text is drawn with DejaVu Sans, embedded in the binary
//! (`assets/DejaVuSans.ttf`, licence in `assets/DejaVuSans-LICENSE.txt`) and
//! registered with plotters' `ab_glyph` font table: no system fonts or
//! fontconfig at build or run time.
//!
//! Bitmap backends draw rotated text badly (plotters issue #655), so in the
//! PNG the y-axis label is written unrotated in a line above the axis; the
//! SVG has the usual rotated label beside the axis.
//!
//! Axis ticks use powers of ten when |v| < 1e-3 or |v| >= 1e4 (see
//! [`format_tick`]: `1.2×10⁻²⁴`, `3×10⁷`, as a reader writes them).

use std::io::Write;
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{Result, anyhow, bail};
use plotters::coord::Shift;
use plotters::coord::ranged1d::{AsRangedCoord, Ranged, ValueFormatter};
use plotters::coord::types::RangedCoordf64;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::output::write_atomic;

/// DejaVu Sans, embedded (see the module docs).
static FONT_BYTES: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// The font family name the embedded font is registered under.
const FAMILY: &str = "sans-serif";

/// Register the embedded font with plotters (once per process).
pub(crate) fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| {
        plotters::style::register_font(FAMILY, FontStyle::Normal, FONT_BYTES).is_ok()
    });
    if ok {
        Ok(())
    } else {
        bail!("the embedded DejaVu Sans font could not be loaded")
    }
}

/// The embedded font at `size` [px], black.
pub(crate) fn font(size: f64) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// Default figure size in pixels (PNG; the SVG uses the same size in px).
pub const DEFAULT_SIZE: (u32, u32) = (1000, 650);

/// A qualitative palette (Tableau 10), used for series without a colour.
pub const PALETTE: [(u8, u8, u8); 10] = [
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (214, 39, 40),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (188, 189, 34),
    (23, 190, 207),
];

/// How one curve is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineStyle {
    /// RGB colour; `None` takes the next colour of [`PALETTE`].
    pub color: Option<(u8, u8, u8)>,
    /// Line width in pixels.
    pub width: u32,
    /// Dashed instead of solid.
    pub dashed: bool,
}

impl Default for LineStyle {
    fn default() -> Self {
        LineStyle {
            color: None,
            width: 2,
            dashed: false,
        }
    }
}

/// One named curve. Points with a non-finite coordinate (or y <= 0 on a
/// log axis) are gaps: the line is broken there.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend entry (empty: not in the legend).
    pub name: String,
    /// x values (same length as `ys`).
    pub xs: Vec<f64>,
    /// y values.
    pub ys: Vec<f64>,
    /// Colour, width, dashes.
    pub style: LineStyle,
    /// A band `(lo, hi)` at the same `xs`, shaded in the series' colour
    /// under its line (an envelope; see [`Series::envelope`]).
    pub band: Option<(Vec<f64>, Vec<f64>)>,
}

impl Series {
    /// A solid curve in the next palette colour.
    pub fn new(name: impl Into<String>, xs: Vec<f64>, ys: Vec<f64>) -> Self {
        Series {
            name: name.into(),
            xs,
            ys,
            style: LineStyle::default(),
            band: None,
        }
    }

    /// A fast oscillation drawn so that it can be read: its running mean as
    /// the line and its running min–max as a shaded band, each over a
    /// sliding window of `window` x units centred on `points` equally spaced
    /// x values (the window slides, so the band does not zigzag with how
    /// the periods fall into fixed bins). Non-finite samples are skipped;
    /// a grid point with none in its window is a gap.
    pub fn envelope(
        name: impl Into<String>,
        xs: &[f64],
        ys: &[f64],
        points: usize,
        window: f64,
    ) -> Self {
        let e = running_envelope(xs, ys, points, window);
        let mut s = Series::new(name, e.0, e.1);
        s.band = Some((e.2, e.3));
        s
    }

    /// Set the colour.
    pub fn color(mut self, rgb: (u8, u8, u8)) -> Self {
        self.style.color = Some(rgb);
        self
    }

    /// Draw dashed.
    pub fn dashed(mut self) -> Self {
        self.style.dashed = true;
        self
    }

    /// Set the line width in pixels.
    pub fn width(mut self, px: u32) -> Self {
        self.style.width = px;
        self
    }
}

/// A horizontal reference line (thin, dashed, grey) with an optional label.
#[derive(Debug, Clone, PartialEq)]
pub struct RefLine {
    /// Where \[y units\].
    pub y: f64,
    /// Text written right of the plot, level with the line, e.g. `"π/2"`.
    pub label: Option<String>,
}

impl RefLine {
    /// A reference line at `y` labelled `label`.
    pub fn new(y: f64, label: impl Into<String>) -> Self {
        RefLine {
            y,
            label: Some(label.into()),
        }
    }
}

/// Where the legend goes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Legend {
    /// In a strip above the plot area, outside the data (wrapping onto
    /// more rows when the entries do not fit in one): never over a curve.
    /// A panel with a single named curve gets none (its y label names it).
    #[default]
    Above,
    /// Upper right corner of the plot area.
    UpperRight,
    /// Upper left.
    UpperLeft,
    /// Lower right.
    LowerRight,
    /// Lower left.
    LowerLeft,
    /// Middle right.
    MiddleRight,
    /// No legend.
    None,
}

/// A vertical mark at `x` (a force switch, a reversal, a phase boundary):
/// a dashed dark line with its label written at the top of the plot area.
#[derive(Debug, Clone, PartialEq)]
pub struct VLine {
    /// Where \[x units\].
    pub x: f64,
    /// Text beside the line's top, e.g. `"force reversed"`.
    pub label: String,
}

impl VLine {
    /// A mark at `x` labelled `label`.
    pub fn new(x: f64, label: impl Into<String>) -> Self {
        VLine {
            x,
            label: label.into(),
        }
    }
}

/// A shaded window `[x0, x1]` (a hold, a force pulse) with its label at the
/// top left of the window.
#[derive(Debug, Clone, PartialEq)]
pub struct Span {
    /// Start \[x units\].
    pub x0: f64,
    /// End \[x units\].
    pub x1: f64,
    /// Text at the top of the window (may be empty).
    pub label: String,
}

/// Options of a line plot (or of one panel of [`multi_panel`], which takes
/// `size` and `x_range` from the figure's options instead).
#[derive(Debug, Clone, PartialEq)]
pub struct PlotOpts {
    /// Figure size in pixels.
    pub size: (u32, u32),
    /// Logarithmic y axis (points with y <= 0 are left out).
    pub log_y: bool,
    /// Horizontal reference lines (always inside the y range).
    pub hlines: Vec<RefLine>,
    /// Fixed x range; `None`: the data's extent.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None`: the data's extent plus 5 %.
    pub y_range: Option<(f64, f64)>,
    /// Legend position.
    pub legend: Legend,
    /// Vertical marks (force switches, reversals, phase boundaries).
    pub vlines: Vec<VLine>,
    /// Shaded windows (holds, pulses), drawn under the curves.
    pub spans: Vec<Span>,
    /// Equal scales on x and y (a circle is drawn as a circle): the y
    /// range keeps its lower end and is extended or cut to the plotting
    /// area's aspect, computed from the layout of each backend.
    pub equal_aspect: bool,
}

impl Default for PlotOpts {
    fn default() -> Self {
        PlotOpts {
            size: DEFAULT_SIZE,
            log_y: false,
            hlines: Vec::new(),
            x_range: None,
            y_range: None,
            legend: Legend::Above,
            vlines: Vec::new(),
            spans: Vec::new(),
            equal_aspect: false,
        }
    }
}

/// One panel of a [`multi_panel`] figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Panel {
    /// y-axis label with units, e.g. `"N [N]"`.
    pub y_label: String,
    /// The curves.
    pub series: Vec<Series>,
    /// `log_y`, `hlines`, `y_range`, `legend`, `vlines`, `spans` of this
    /// panel (`size` and `x_range` are the figure's).
    pub opts: PlotOpts,
}

impl Panel {
    /// A panel with default options.
    pub fn new(y_label: impl Into<String>, series: Vec<Series>) -> Self {
        Panel {
            y_label: y_label.into(),
            series,
            opts: PlotOpts::default(),
        }
    }
}

/// Options of a [`heatmap`].
#[derive(Debug, Clone, PartialEq)]
pub struct HeatmapOpts {
    /// Figure size in pixels.
    pub size: (u32, u32),
    /// Logarithmic colour scale (values <= 0 drawn as missing).
    pub log_z: bool,
    /// Fixed colour range; `None`: the finite data's extent.
    pub z_range: Option<(f64, f64)>,
    /// Curves drawn over the map, in data coordinates (x, y): white lines,
    /// mapped onto the cell grid by interpolating between grid values.
    pub lines: Vec<(Vec<f64>, Vec<f64>)>,
}

impl Default for HeatmapOpts {
    fn default() -> Self {
        HeatmapOpts {
            size: DEFAULT_SIZE,
            log_z: false,
            z_range: None,
            lines: Vec::new(),
        }
    }
}

/// `STEM.png` and `STEM.svg` for `stem`.
pub fn output_paths(stem: &Path) -> (PathBuf, PathBuf) {
    let name = stem
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    (
        stem.with_file_name(format!("{name}.png")),
        stem.with_file_name(format!("{name}.svg")),
    )
}

/// A line plot written to `STEM.png` and `STEM.svg`: `series` against a
/// common x axis, with a legend (series with a non-empty name), axis labels
/// (give units, e.g. `"t [µs]"`), optional reference lines and log-y.
pub fn line_plot(
    stem: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    opts: &PlotOpts,
) -> Result<()> {
    let panel = Panel {
        y_label: y_label.to_string(),
        series: series.to_vec(),
        opts: opts.clone(),
    };
    multi_panel(stem, title, x_label, std::slice::from_ref(&panel), opts)
}

/// Panels stacked vertically, sharing the x axis (labelled once, at the
/// bottom), written to `STEM.png` and `STEM.svg`. `fig.size` and
/// `fig.x_range` apply to the whole figure; each panel has its own y options.
pub fn multi_panel(
    stem: &Path,
    title: &str,
    x_label: &str,
    panels: &[Panel],
    fig: &PlotOpts,
) -> Result<()> {
    if panels.is_empty() {
        bail!("{}: no panels to plot", stem.display());
    }
    for p in panels {
        for s in &p.series {
            if s.xs.len() != s.ys.len() {
                bail!(
                    "{}: series {:?} has {} x values and {} y values",
                    stem.display(),
                    s.name,
                    s.xs.len(),
                    s.ys.len()
                );
            }
        }
    }
    let x_range = match fig.x_range {
        Some(r) => r,
        None => {
            let xs = panels
                .iter()
                .flat_map(|p| p.series.iter())
                .flat_map(|s| s.xs.iter().copied());
            data_range(xs, false, 0.0)
        }
    };
    let figure = Figure::Lines {
        title,
        x_label,
        panels,
        x_range,
    };
    render_both(stem, fig.size, &figure)
}

/// A heat map written to `STEM.png` and `STEM.svg`: `z[j][i]` is the value
/// at (`xs[i]`, `ys[j]`), with a colour bar labelled `z_label`. Cells are
/// drawn equal-sized, in grid-index space, so log-spaced sweeps look right;
/// the tick labels show the grid values. NaN (or <= 0 with `log_z`) cells are
/// grey.
#[allow(clippy::too_many_arguments)]
pub fn heatmap(
    stem: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    z_label: &str,
    xs: &[f64],
    ys: &[f64],
    z: &[Vec<f64>],
    opts: &HeatmapOpts,
) -> Result<()> {
    if xs.is_empty() || ys.is_empty() {
        bail!("{}: empty grid", stem.display());
    }
    if z.len() != ys.len() || z.iter().any(|row| row.len() != xs.len()) {
        bail!(
            "{}: z must be {} rows of {} values",
            stem.display(),
            ys.len(),
            xs.len()
        );
    }
    let z_range = match opts.z_range {
        Some(r) => r,
        None => data_range(z.iter().flatten().copied(), opts.log_z, 0.0),
    };
    let figure = Figure::Heatmap {
        title,
        x_label,
        y_label,
        z_label,
        xs,
        ys,
        z,
        z_range,
        log_z: opts.log_z,
        lines: &opts.lines,
    };
    render_both(stem, opts.size, &figure)
}

/// What to draw (one description, rendered once per backend).
enum Figure<'a> {
    Lines {
        title: &'a str,
        x_label: &'a str,
        panels: &'a [Panel],
        x_range: (f64, f64),
    },
    Heatmap {
        title: &'a str,
        x_label: &'a str,
        y_label: &'a str,
        z_label: &'a str,
        xs: &'a [f64],
        ys: &'a [f64],
        z: &'a [Vec<f64>],
        z_range: (f64, f64),
        log_z: bool,
        lines: &'a [(Vec<f64>, Vec<f64>)],
    },
}

/// Render `figure` to `STEM.png` and `STEM.svg`.
fn render_both(stem: &Path, size: (u32, u32), figure: &Figure) -> Result<()> {
    ensure_font()?;
    let (png_path, svg_path) = output_paths(stem);
    let (w, h) = size;

    // PNG: draw into an RGB buffer, encode, write atomically.
    let mut buf = vec![0u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut buf, size).into_drawing_area();
        draw(&root, figure, true).map_err(|e| anyhow!("{}: {e}", png_path.display()))?;
        root.present()
            .map_err(|e| anyhow!("{}: {e}", png_path.display()))?;
    }
    write_atomic(&png_path, |wr| {
        let mut enc = png::Encoder::new(wr, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header().map_err(std::io::Error::other)?;
        writer
            .write_image_data(&buf)
            .map_err(std::io::Error::other)?;
        writer.finish().map_err(std::io::Error::other)?;
        Ok(())
    })?;

    // SVG: draw into a string, write atomically.
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        draw(&root, figure, false).map_err(|e| anyhow!("{}: {e}", svg_path.display()))?;
        root.present()
            .map_err(|e| anyhow!("{}: {e}", svg_path.display()))?;
    }
    write_atomic(&svg_path, |wr| wr.write_all(svg.as_bytes()))
}

/// Draw error as text (plotters' error type is generic over the backend).
type DrawResult = std::result::Result<(), String>;

fn err<E: std::fmt::Debug>(e: E) -> String {
    format!("drawing failed: {e:?}")
}

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    figure: &Figure,
    bitmap: bool,
) -> DrawResult {
    root.fill(&WHITE).map_err(err)?;
    match figure {
        Figure::Lines {
            title,
            x_label,
            panels,
            x_range,
        } => {
            let body = root.titled(title, font(24.0)).map_err(err)?;
            let n = panels.len();
            // The bottom panel also carries the x tick labels and x label.
            let (_, h) = body.dim_in_pixel();
            let extra = 45u32;
            let each = h.saturating_sub(extra) / n as u32;
            let mut rest = body;
            let mut palette_next = 0usize;
            for (i, panel) in panels.iter().enumerate() {
                let last = i + 1 == n;
                let (area, below) = if last {
                    (rest.clone(), rest.clone())
                } else {
                    rest.split_vertically(each)
                };
                draw_panel(
                    &area,
                    panel,
                    *x_range,
                    if last { Some(x_label) } else { None },
                    bitmap,
                    &mut palette_next,
                )?;
                rest = below;
            }
            Ok(())
        }
        Figure::Heatmap {
            title,
            x_label,
            y_label,
            z_label,
            xs,
            ys,
            z,
            z_range,
            log_z,
            lines,
        } => draw_heatmap(
            root, title, x_label, y_label, z_label, xs, ys, z, *z_range, *log_z, lines, bitmap,
        ),
    }
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    x_range: (f64, f64),
    x_label: Option<&str>,
    bitmap: bool,
    palette_next: &mut usize,
) -> DrawResult {
    let o = &panel.opts;
    let (y0, y1) = match o.y_range {
        Some(r) => r,
        None => {
            let ys = panel
                .series
                .iter()
                .flat_map(|s| {
                    let band = s.band.iter().flat_map(|(l, h)| l.iter().chain(h));
                    s.ys.iter().chain(band).copied()
                })
                .chain(o.hlines.iter().map(|h| h.y));
            data_range(ys, o.log_y, 0.05)
        }
    };
    // The legend strip above the plot (Legend::Above).
    // One named curve needs no legend: the y label names it.
    let named = panel.series.iter().filter(|s| !s.name.is_empty()).count();
    let area = if o.legend == Legend::Above && named > 1 {
        draw_legend_strip(area, panel, *palette_next)?
    } else {
        area.clone()
    };
    // PNG: y label unrotated in its own line above the plot (issue #655).
    let area = if bitmap {
        let (label_row, rest) = area.split_vertically(24);
        label_row
            .draw_text(&panel.y_label, &font(16.0), (12, 4))
            .map_err(err)?;
        rest
    } else {
        area.clone()
    };
    // Equal scales: the plotting area is the panel minus the margins and
    // label areas of `draw_panel_in` (8 px and the right margin across plus the y label
    // area; 8 px above plus the x label area).
    let (y0, y1) = if o.equal_aspect && !o.log_y {
        let (w, h) = area.dim_in_pixel();
        let plot_w = w as f64 - 8.0 - right_margin(o) as f64 - if bitmap { 90.0 } else { 115.0 };
        let plot_h = h as f64 - 8.0 - if x_label.is_some() { 50.0 } else { 24.0 };
        (y0, y0 + (x_range.1 - x_range.0) * plot_h / plot_w)
    } else {
        (y0, y1)
    };
    // plotters' key points break down for spans far from 1 (it compares
    // with an absolute f64::EPSILON): draw in rescaled coordinates and
    // label the ticks with the true values.
    let kx = axis_scale(x_range.0, x_range.1);
    let x = x_range.0 * kx..x_range.1 * kx;
    if o.log_y {
        let y = (y0..y1).log_scale();
        let k = (kx, 1.0);
        draw_panel_in(
            &area,
            panel,
            x,
            y,
            (y0, y1),
            k,
            x_label,
            bitmap,
            palette_next,
        )
    } else {
        let ky = axis_scale(y0, y1);
        let y = y0 * ky..y1 * ky;
        let k = (kx, ky);
        draw_panel_in(
            &area,
            panel,
            x,
            y,
            (y0, y1),
            k,
            x_label,
            bitmap,
            palette_next,
        )
    }
}

/// The colour of each series of `panel`, as `draw_panel_in` assigns them
/// (the next palette colours, from `palette_next`, for series without one).
fn series_colors(panel: &Panel, palette_next: usize) -> Vec<(u8, u8, u8)> {
    let mut next = palette_next;
    panel
        .series
        .iter()
        .map(|s| {
            s.style.color.unwrap_or_else(|| {
                let c = PALETTE[next % PALETTE.len()];
                next += 1;
                c
            })
        })
        .collect()
}

/// Draw the legend of `panel` in rows across the top of `area` (outside the
/// plot) and return the rest of the area.
fn draw_legend_strip<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    palette_next: usize,
) -> std::result::Result<DrawingArea<DB, Shift>, String> {
    const ROW: i32 = 22;
    const SAMPLE: i32 = 26;
    let style = font(14.0);
    let colors = series_colors(panel, palette_next);
    let (w, _) = area.dim_in_pixel();
    let left = 60i32;
    let right = w as i32 - 24;
    // Lay the entries out first (to know the strip's height).
    let mut placed = Vec::new();
    let (mut x, mut row) = (left, 0i32);
    for (s, rgb) in panel.series.iter().zip(&colors) {
        if s.name.is_empty() {
            continue;
        }
        let (tw, _) = area.estimate_text_size(&s.name, &style).map_err(err)?;
        let width = SAMPLE + 6 + tw as i32 + 18;
        if x + width > right && x > left {
            row += 1;
            x = left;
        }
        placed.push((x, row, s, *rgb));
        x += width;
    }
    let rows = row + 1;
    let (strip, rest) = area.split_vertically((rows * ROW + 6) as u32);
    for (x, row, s, rgb) in placed {
        let y = 4 + row * ROW + ROW / 2;
        let line = RGBColor(rgb.0, rgb.1, rgb.2).stroke_width(s.style.width.max(2));
        if s.band.is_some() {
            strip
                .draw(&Rectangle::new(
                    [(x, y - 7), (x + SAMPLE, y + 7)],
                    RGBColor(rgb.0, rgb.1, rgb.2).mix(0.25).filled(),
                ))
                .map_err(err)?;
        }
        if s.style.dashed {
            strip
                .draw(&DashedPathElement::new(
                    vec![(x, y), (x + SAMPLE, y)],
                    6,
                    3,
                    line,
                ))
                .map_err(err)?;
        } else {
            strip
                .draw(&PathElement::new(vec![(x, y), (x + SAMPLE, y)], line))
                .map_err(err)?;
        }
        strip
            .draw_text(&s.name, &style, (x + SAMPLE + 6, y - 8))
            .map_err(err)?;
    }
    Ok(rest)
}

/// The width [px] of a vertical mark's label box: about 7 px a character
/// at 13 px, and a margin.
fn vline_label_width(label: &str) -> i32 {
    8 + 7 * label.chars().count() as i32
}

/// The plot's right margin [px]: room for the reference lines' labels
/// (about 8 px a character at 14 px), which stand right of the plot.
fn right_margin(o: &PlotOpts) -> u32 {
    let widest = o
        .hlines
        .iter()
        .filter_map(|h| h.label.as_ref())
        .map(|l| l.chars().count() as u32)
        .max();
    widest.map_or(24, |n| 24u32.max(14 + 8 * n))
}

/// Shaded windows, vertical marks and horizontal reference lines of `o`
/// (under the curves), on a chart whose axes are scaled by `(kx, ky)`,
/// over the drawn range `(xa, xb)`, `(ya, yb)` (scaled coordinates).
fn draw_marks<DB, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    o: &PlotOpts,
    (xa, xb): (f64, f64),
    (ya, yb): (f64, f64),
    (kx, ky): (f64, f64),
    log_y: bool,
) -> DrawResult
where
    DB: DrawingBackend,
    Y: Ranged<ValueType = f64>,
{
    let mark = RGBColor(70, 70, 70);
    for sp in &o.spans {
        if !(sp.x0.is_finite() && sp.x1.is_finite()) {
            continue;
        }
        let (a, b) = ((sp.x0 * kx).max(xa), (sp.x1 * kx).min(xb));
        if a >= b {
            continue;
        }
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(a, ya), (b, yb)],
                RGBColor(150, 150, 150).mix(0.15).filled(),
            )))
            .map_err(err)?;
        if !sp.label.is_empty() {
            chart
                .draw_series(std::iter::once(
                    EmptyElement::at((a, yb))
                        + Text::new(sp.label.clone(), (4, 4), font(13.0).color(&mark)),
                ))
                .map_err(err)?;
        }
    }
    for v in &o.vlines {
        let vx = v.x * kx;
        if !vx.is_finite() || vx < xa || vx > xb {
            continue;
        }
        chart
            .draw_series(DashedLineSeries::new(
                vec![(vx, ya), (vx, yb)],
                5,
                4,
                mark.stroke_width(1),
            ))
            .map_err(err)?;
    }

    // Reference lines.
    let grey = RGBColor(110, 110, 110);
    for h in &o.hlines {
        if !h.y.is_finite() || (log_y && h.y <= 0.0) {
            continue;
        }
        let hy = h.y * ky;
        chart
            .draw_series(DashedLineSeries::new(
                vec![(xa, hy), (xb, hy)],
                6,
                4,
                grey.stroke_width(1),
            ))
            .map_err(err)?;
        // The label right of the plot, level with its line: clear of the
        // curves and of the marks' labels at the top (the right margin is
        // made wide enough, see `right_margin`).
        if let Some(label) = &h.label {
            chart
                .plotting_area()
                .draw(
                    &(EmptyElement::at((xb, hy))
                        + Text::new(label.clone(), (6, -8), font(14.0).color(&grey))),
                )
                .map_err(err)?;
        }
    }

    // The marks' labels last, on a white box: a reference line near the
    // top (π) ran through them (fig12, fig14).
    for v in &o.vlines {
        let vx = v.x * kx;
        if v.label.is_empty() || !vx.is_finite() || vx < xa || vx > xb {
            continue;
        }
        let w = vline_label_width(&v.label);
        chart
            .draw_series(std::iter::once(
                EmptyElement::at((vx, yb))
                    + Rectangle::new([(2, 16), (w, 33)], WHITE.mix(0.85).filled())
                    + Text::new(v.label.clone(), (4, 18), font(13.0).color(&mark)),
            ))
            .map_err(err)?;
    }

    Ok(())
}

/// The band `(lo, hi)` of a series at `xs`, shaded in its colour `rgb`: one
/// polygon per run of finite points, lo forward and hi back.
fn draw_band<DB, Y>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, Y>>,
    xs: &[f64],
    (lo, hi): &(Vec<f64>, Vec<f64>),
    rgb: (u8, u8, u8),
    log_y: bool,
    (kx, ky): (f64, f64),
) -> DrawResult
where
    DB: DrawingBackend,
    Y: Ranged<ValueType = f64>,
{
    // One polygon per run of finite points: lo forward, hi back.
    let fill = RGBColor(rgb.0, rgb.1, rgb.2).mix(0.25).filled();
    let mut run: Vec<(f64, f64, f64)> = Vec::new();
    let flush = |run: &mut Vec<(f64, f64, f64)>| -> Vec<(f64, f64)> {
        let mut poly: Vec<(f64, f64)> = run.iter().map(|p| (p.0, p.1)).collect();
        poly.extend(run.iter().rev().map(|p| (p.0, p.2)));
        run.clear();
        poly
    };
    let mut polys = Vec::new();
    for ((&x, &l), &h) in xs.iter().zip(lo).zip(hi) {
        let ok = x.is_finite() && l.is_finite() && h.is_finite() && !(log_y && l <= 0.0);
        if ok {
            run.push((x * kx, l * ky, h * ky));
        } else if run.len() > 1 {
            polys.push(flush(&mut run));
        } else {
            run.clear();
        }
    }
    if run.len() > 1 {
        polys.push(flush(&mut run));
    }
    for poly in polys {
        chart
            .draw_series(std::iter::once(Polygon::new(poly, fill)))
            .map_err(err)?;
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn draw_panel_in<DB, YS>(
    area: &DrawingArea<DB, Shift>,
    panel: &Panel,
    x: Range<f64>,
    y: YS,
    (y0, y1): (f64, f64),
    (kx, ky): (f64, f64),
    x_label: Option<&str>,
    bitmap: bool,
    palette_next: &mut usize,
) -> DrawResult
where
    DB: DrawingBackend,
    YS: AsRangedCoord<Value = f64>,
    YS::CoordDescType: ValueFormatter<f64>,
{
    let o = &panel.opts;
    let (xa, xb) = (x.start, x.end);
    let mut chart = ChartBuilder::on(area)
        .margin_top(8)
        .margin_right(right_margin(o))
        .margin_left(8)
        .x_label_area_size(if x_label.is_some() { 50 } else { 24 })
        .y_label_area_size(if bitmap { 90 } else { 115 })
        .build_cartesian_2d(x, y)
        .map_err(err)?;

    let x_step = nice_step((xb - xa).abs() / kx / 10.0);
    let y_step = nice_step((y1 - y0).abs() / 10.0);
    let log_y = o.log_y;
    let x_fmt = move |v: &f64| format_tick(*v / kx, x_step);
    let y_fmt = move |v: &f64| {
        if log_y {
            format_log_tick(*v)
        } else {
            format_tick(*v / ky, y_step)
        }
    };
    {
        let mut mesh = chart.configure_mesh();
        mesh.x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .label_style(font(14.0))
            .axis_desc_style(font(16.0))
            .light_line_style(RGBColor(243, 243, 243))
            .bold_line_style(RGBColor(205, 205, 205))
            .x_labels(10)
            .y_labels(if log_y { 12 } else { 8 });
        if let Some(xl) = x_label {
            mesh.x_desc(xl);
        }
        if !bitmap {
            mesh.y_desc(panel.y_label.as_str());
        }
        mesh.draw().map_err(err)?;
    }

    draw_marks(&mut chart, o, (xa, xb), (y0 * ky, y1 * ky), (kx, ky), log_y)?;

    let mut any_named = false;
    for s in &panel.series {
        let rgb = match s.style.color {
            Some(c) => c,
            None => {
                let c = PALETTE[*palette_next % PALETTE.len()];
                *palette_next += 1;
                c
            }
        };
        let style = RGBColor(rgb.0, rgb.1, rgb.2).stroke_width(s.style.width);
        if let Some(band) = &s.band {
            draw_band(&mut chart, &s.xs, band, rgb, log_y, (kx, ky))?;
        }
        let mut labelled = false;
        let clip = Some([(xa, xb), (y0 * ky, y1 * ky)]);
        for seg in segments(&s.xs, &s.ys, log_y, (kx, ky), clip) {
            let anno = if s.style.dashed {
                chart
                    .draw_series(DashedLineSeries::new(seg, 10, 6, style))
                    .map_err(err)?
            } else if bitmap && s.style.width > 1 {
                // The bitmap backend joins thick polylines with mitres, which
                // spike far out at sharp turns (noisy data): draw the
                // segments separately instead.
                chart
                    .draw_series(
                        seg.windows(2)
                            .map(|w| PathElement::new(vec![w[0], w[1]], style)),
                    )
                    .map_err(err)?
            } else {
                chart
                    .draw_series(LineSeries::new(seg, style))
                    .map_err(err)?
            };
            if !labelled && !s.name.is_empty() {
                labelled = true;
                any_named = true;
                let dashed = s.style.dashed;
                anno.label(s.name.clone()).legend(move |(x, y)| {
                    if dashed {
                        DashedPathElement::new(vec![(x, y), (x + 24, y)], 6, 3, style).into_dyn()
                    } else {
                        PathElement::new(vec![(x, y), (x + 24, y)], style).into_dyn()
                    }
                });
            }
        }
    }

    if any_named && !matches!(o.legend, Legend::None | Legend::Above) {
        let pos = match o.legend {
            Legend::UpperLeft => SeriesLabelPosition::UpperLeft,
            Legend::LowerRight => SeriesLabelPosition::LowerRight,
            Legend::LowerLeft => SeriesLabelPosition::LowerLeft,
            Legend::MiddleRight => SeriesLabelPosition::MiddleRight,
            _ => SeriesLabelPosition::UpperRight,
        };
        chart
            .configure_series_labels()
            .position(pos)
            .label_font(font(14.0))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(160, 160, 160))
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn draw_heatmap<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    title: &str,
    x_label: &str,
    y_label: &str,
    z_label: &str,
    xs: &[f64],
    ys: &[f64],
    z: &[Vec<f64>],
    (z0, z1): (f64, f64),
    log_z: bool,
    lines: &[(Vec<f64>, Vec<f64>)],
    bitmap: bool,
) -> DrawResult {
    let body = root.titled(title, font(24.0)).map_err(err)?;
    let (w, _) = body.dim_in_pixel();
    let (main, bar) = body.split_horizontally(w.saturating_sub(150));
    let main = if bitmap {
        let (label_row, rest) = main.split_vertically(24);
        label_row
            .draw_text(y_label, &font(16.0), (12, 4))
            .map_err(err)?;
        rest
    } else {
        main
    };
    let (nx, ny) = (xs.len(), ys.len());
    let mut chart = ChartBuilder::on(&main)
        .margin_top(8)
        .margin_right(16)
        .margin_left(8)
        .x_label_area_size(50)
        .y_label_area_size(if bitmap { 90 } else { 115 })
        .build_cartesian_2d(-0.5..nx as f64 - 0.5, -0.5..ny as f64 - 0.5)
        .map_err(err)?;
    let grid_label = |vals: &[f64], v: f64| -> String {
        let i = v.round();
        if (v - i).abs() > 1e-6 || i < 0.0 || i as usize >= vals.len() {
            return String::new();
        }
        format_value(vals[i as usize])
    };
    let x_fmt = |v: &f64| grid_label(xs, *v);
    let y_fmt = |v: &f64| grid_label(ys, *v);
    {
        let mut mesh = chart.configure_mesh();
        mesh.disable_mesh()
            .x_labels(nx.min(12))
            .y_labels(ny.min(12))
            .x_label_formatter(&x_fmt)
            .y_label_formatter(&y_fmt)
            .label_style(font(14.0))
            .axis_desc_style(font(16.0))
            .x_desc(x_label);
        if !bitmap {
            mesh.y_desc(y_label);
        }
        mesh.draw().map_err(err)?;
    }
    let scale = |v: f64| -> Option<f64> {
        if !v.is_finite() || (log_z && v <= 0.0) {
            return None;
        }
        let (a, b, v) = if log_z {
            (z0.log10(), z1.log10(), v.log10())
        } else {
            (z0, z1, v)
        };
        Some(if b > a {
            ((v - a) / (b - a)).clamp(0.0, 1.0)
        } else {
            0.5
        })
    };
    let cells = z.iter().enumerate().flat_map(|(j, row)| {
        row.iter().enumerate().map(move |(i, &v)| {
            let color = match scale(v) {
                Some(t) => colormap(t),
                None => RGBColor(200, 200, 200),
            };
            let (x, y) = (i as f64, j as f64);
            Rectangle::new([(x - 0.5, y - 0.5), (x + 0.5, y + 0.5)], color.filled())
        })
    });
    chart.draw_series(cells).map_err(err)?;
    // Overlay curves: data coordinates to cell-index coordinates.
    for (lx, ly) in lines {
        let pts: Vec<(f64, f64)> = lx
            .iter()
            .zip(ly)
            .filter_map(|(&x, &y)| Some((cell_index(xs, x)?, cell_index(ys, y)?)))
            .collect();
        chart
            .draw_series(LineSeries::new(pts, WHITE.stroke_width(3)))
            .map_err(err)?;
    }
    draw_colour_bar(&bar, z_label, (z0, z1), log_z)
}

/// A data coordinate `v` as a cell-index coordinate of the grid values
/// `vals` (linear between neighbouring values; `None` off the grid).
fn cell_index(vals: &[f64], v: f64) -> Option<f64> {
    if !v.is_finite() || vals.is_empty() {
        return None;
    }
    if vals.len() == 1 {
        return Some(0.0);
    }
    let n = vals.len();
    let seg = |i: usize| {
        let (a, b) = (vals[i], vals[i + 1]);
        i as f64 + (v - a) / (b - a)
    };
    let i = (0..n - 1)
        .find(|&i| (vals[i] - v) * (vals[i + 1] - v) <= 0.0)
        .unwrap_or(if (v - vals[0]).abs() < (v - vals[n - 1]).abs() {
            0
        } else {
            n - 2
        });
    let idx = seg(i);
    (-0.5..=n as f64 - 0.5).contains(&idx).then_some(idx)
}

/// The colour bar of a heat map beside it in `bar`: linear in z, or in
/// log10 z.
fn draw_colour_bar<DB: DrawingBackend>(
    bar: &DrawingArea<DB, Shift>,
    z_label: &str,
    (z0, z1): (f64, f64),
    log_z: bool,
) -> DrawResult {
    let (b0, b1) = if log_z {
        (z0.log10(), z1.log10())
    } else {
        (z0, z1)
    };
    let (b0, b1) = if b1 > b0 {
        (b0, b1)
    } else {
        (b0 - 0.5, b0 + 0.5)
    };
    let bar = bar.margin(8, 58, 4, 16);
    let kb = axis_scale(b0, b1);
    let mut cb = ChartBuilder::on(&bar)
        .caption(z_label, font(15.0))
        .y_label_area_size(75)
        .build_cartesian_2d(0.0..1.0, b0 * kb..b1 * kb)
        .map_err(err)?;
    let step = nice_step((b1 - b0) / 8.0);
    let cb_fmt = move |v: &f64| {
        if log_z {
            format_log_tick(10f64.powf(*v / kb))
        } else {
            format_tick(*v / kb, step)
        }
    };
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(8)
        .y_label_formatter(&cb_fmt)
        .label_style(font(13.0))
        .draw()
        .map_err(err)?;
    let n = 200;
    cb.draw_series((0..n).map(|k| {
        let a = b0 + (b1 - b0) * k as f64 / n as f64;
        let b = b0 + (b1 - b0) * (k + 1) as f64 / n as f64;
        Rectangle::new(
            [(0.0, a * kb), (1.0, b * kb)],
            colormap((k as f64 + 0.5) / n as f64).filled(),
        )
    }))
    .map_err(err)?;
    Ok(())
}

/// Viridis-like colour map, `t` in \[0, 1\].
pub fn colormap(t: f64) -> RGBColor {
    const STOPS: [(u8, u8, u8); 9] = [
        (68, 1, 84),
        (71, 44, 122),
        (59, 81, 139),
        (44, 113, 142),
        (33, 144, 141),
        (39, 173, 129),
        (92, 200, 99),
        (170, 220, 50),
        (253, 231, 37),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    let f = t * (STOPS.len() - 1) as f64;
    let i = (f.floor() as usize).min(STOPS.len() - 2);
    let u = f - i as f64;
    let lerp = |a: u8, b: u8| (a as f64 + (b as f64 - a as f64) * u).round() as u8;
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    RGBColor(lerp(a.0, b.0), lerp(a.1, b.1), lerp(a.2, b.2))
}

/// `(x, mean, min, max)` of `ys` over a window of width `window` sliding
/// across `points` equally spaced x values of the data's extent (see
/// [`Series::envelope`]). `xs` must be sorted.
pub fn running_envelope(
    xs: &[f64],
    ys: &[f64],
    points: usize,
    window: f64,
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let finite: Vec<(f64, f64)> = xs
        .iter()
        .zip(ys)
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .map(|(x, y)| (*x, *y))
        .collect();
    let (mut gx, mut mean, mut lo, mut hi) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let (Some(first), Some(last)) = (finite.first(), finite.last()) else {
        return (gx, mean, lo, hi);
    };
    let (a, b) = (first.0, last.0);
    let n = points.max(2);
    let half = 0.5 * window.max(0.0);
    let (mut i0, mut i1) = (0usize, 0usize);
    for k in 0..n {
        let x = a + (b - a) * k as f64 / (n - 1) as f64;
        while i0 < finite.len() && finite[i0].0 < x - half {
            i0 += 1;
        }
        i1 = i1.max(i0);
        while i1 < finite.len() && finite[i1].0 <= x + half {
            i1 += 1;
        }
        gx.push(x);
        let w = &finite[i0..i1];
        if w.is_empty() {
            mean.push(f64::NAN);
            lo.push(f64::NAN);
            hi.push(f64::NAN);
        } else {
            mean.push(w.iter().map(|p| p.1).sum::<f64>() / w.len() as f64);
            lo.push(w.iter().map(|p| p.1).fold(f64::INFINITY, f64::min));
            hi.push(w.iter().map(|p| p.1).fold(f64::NEG_INFINITY, f64::max));
        }
    }
    (gx, mean, lo, hi)
}

/// Split a curve into drawable runs: gaps at non-finite points and at
/// y <= 0 on a log axis, and, with `clip` (the plot's x and y ranges, in
/// drawn coordinates), cut where it leaves the plot. Coordinates are
/// multiplied by `(kx, ky)`.
fn segments(
    xs: &[f64],
    ys: &[f64],
    log_y: bool,
    (kx, ky): (f64, f64),
    clip: Option<[(f64, f64); 2]>,
) -> Vec<Vec<(f64, f64)>> {
    let mut out = Vec::new();
    let mut cur: Vec<(f64, f64)> = Vec::new();
    let flush = |cur: &mut Vec<(f64, f64)>, out: &mut Vec<Vec<(f64, f64)>>| {
        if cur.len() > 1 {
            out.push(std::mem::take(cur));
        } else {
            cur.clear();
        }
    };
    let point = |x: f64, y: f64| {
        (x.is_finite() && y.is_finite() && !(log_y && y <= 0.0)).then_some((x * kx, y * ky))
    };
    let Some(rect) = clip else {
        // No fixed range: the curve as it is, broken at gaps (a lone point
        // between gaps is kept: a one-point run draws nothing).
        for (&x, &y) in xs.iter().zip(ys) {
            match point(x, y) {
                Some(p) => cur.push(p),
                None if !cur.is_empty() => out.push(std::mem::take(&mut cur)),
                None => {}
            }
        }
        if !cur.is_empty() {
            out.push(cur);
        }
        return out;
    };
    // Each step between two points, cut to the plot's rectangle (in log10 y
    // on a log axis): a run ends where a step leaves it and starts again
    // where one comes back in.
    let ly = |y: f64| if log_y { y.log10() } else { y };
    let unly = |y: f64| if log_y { 10f64.powf(y) } else { y };
    let [(xa, xb), (ya, yb)] = rect;
    let (ya, yb) = (ly(ya), ly(yb));
    let mut prev: Option<(f64, f64)> = None;
    for (&x, &y) in xs.iter().zip(ys) {
        let Some(q) = point(x, y) else {
            flush(&mut cur, &mut out);
            prev = None;
            continue;
        };
        let Some(p) = prev.replace(q) else {
            continue;
        };
        let (p1, q1) = ((p.0, ly(p.1)), (q.0, ly(q.1)));
        let Some((t0, t1)) = clip_step(p1, q1, (xa, xb), (ya, yb)) else {
            flush(&mut cur, &mut out);
            continue;
        };
        // The ends kept exactly where they are the points themselves.
        let at = |t: f64| {
            if t == 0.0 {
                p
            } else if t == 1.0 {
                q
            } else {
                (p1.0 + t * (q1.0 - p1.0), unly(p1.1 + t * (q1.1 - p1.1)))
            }
        };
        let (a, b) = (at(t0), at(t1));
        if cur.last() != Some(&a) {
            flush(&mut cur, &mut out);
            cur.push(a);
        }
        cur.push(b);
        if t1 < 1.0 {
            flush(&mut cur, &mut out);
        }
    }
    flush(&mut cur, &mut out);
    out
}

/// The part `[t0, t1]` of the step from `p` to `q` inside the rectangle
/// `x` × `y` (Liang–Barsky), `None` if none of it is inside.
fn clip_step(
    p: (f64, f64),
    q: (f64, f64),
    (xa, xb): (f64, f64),
    (ya, yb): (f64, f64),
) -> Option<(f64, f64)> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (d, lo, hi, v) in [
        (dx, xa.min(xb), xa.max(xb), p.0),
        (dy, ya.min(yb), ya.max(yb), p.1),
    ] {
        if d == 0.0 {
            if v < lo || v > hi {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo - v) / d, (hi - v) / d);
        let (enter, leave) = if a < b { (a, b) } else { (b, a) };
        t0 = t0.max(enter);
        t1 = t1.min(leave);
        if t0 > t1 {
            return None;
        }
    }
    (t0 < t1).then_some((t0, t1))
}

/// The extent of the finite values (positive ones if `log`), widened by
/// `pad` × span on each side (a factor on a log axis); a degenerate extent
/// is widened so the axis is never empty. `(0, 1)` when nothing is finite.
pub fn data_range(values: impl Iterator<Item = f64>, log: bool, pad: f64) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for v in values {
        if v.is_finite() && !(log && v <= 0.0) {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        return if log { (0.1, 10.0) } else { (0.0, 1.0) };
    }
    if log {
        if hi / lo < 1.0 + 1e-9 {
            return (lo / 10f64.sqrt(), hi * 10f64.sqrt());
        }
        let f = (hi / lo).powf(pad);
        return (lo / f, hi * f);
    }
    let span = hi - lo;
    if span <= f64::EPSILON * lo.abs().max(hi.abs()) || span == 0.0 {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo - pad * span, hi + pad * span)
}

/// A power of ten that brings the span `hi − lo` to order 1..10 (1 when it
/// already is within 1e-2..1e3, so ordinary axes are untouched).
fn axis_scale(lo: f64, hi: f64) -> f64 {
    let span = (hi - lo).abs();
    if !span.is_finite() || span == 0.0 || (1e-2..1e3).contains(&span) {
        return 1.0;
    }
    let k = 10f64.powi(-(span.log10().floor() as i32));
    if k.is_finite() && k > 0.0 { k } else { 1.0 }
}

/// The 1-2-5 × 10^k number nearest `raw` from below (for tick precision).
pub fn nice_step(raw: f64) -> f64 {
    if !raw.is_finite() || raw <= 0.0 {
        return 0.0;
    }
    let e = raw.log10().floor();
    let base = 10f64.powf(e);
    let m = raw / base;
    let n = if m >= 5.0 {
        5.0
    } else if m >= 2.0 {
        2.0
    } else {
        1.0
    };
    n * base
}

/// Trim trailing zeros of a decimal mantissa: "1.50" -> "1.5", "2.00" -> "2".
fn trim_zeros(s: &str) -> String {
    if let Some((m, e)) = s.split_once('e') {
        format!("{}e{e}", trim_zeros(m))
    } else if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// An axis tick label for `v` on an axis with tick spacing about `step`:
/// a power of ten (`1.2×10⁻²⁴`, `-3×10⁷`) when |v| < 1e-3 or |v| >= 1e4, otherwise
/// fixed with just enough decimals; values within `step`·1e-6 of zero are
/// `0`.
pub fn format_tick(v: f64, step: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let step = step.abs();
    if v == 0.0 || (step > 0.0 && v.abs() < step * 1e-6) {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e4).contains(&a) {
        let e = a.log10().floor();
        let rel = step / 10f64.powf(e);
        let digits = if rel > 0.0 && rel.is_finite() {
            ((-rel.log10()).ceil() + 1.0).clamp(0.0, 8.0) as usize
        } else {
            2
        };
        times_pow10(&trim_zeros(&format!("{v:.digits$e}")))
    } else {
        let dec = if step > 0.0 {
            ((-step.log10()).ceil() + 1.0).clamp(0.0, 10.0) as usize
        } else {
            4
        };
        trim_zeros(&format!("{v:.dec$}"))
    }
}

/// `1.2e-24` (Rust's exponent form) as a reader writes it: `1.2×10⁻²⁴`;
/// anything else unchanged.
fn times_pow10(s: &str) -> String {
    let Some((m, e)) = s.split_once('e') else {
        return s.to_string();
    };
    const SUP: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let exp: String = e
        .trim_start_matches('+')
        .chars()
        .map(|c| match c {
            '-' => '⁻',
            d => d.to_digit(10).map_or(d, |i| SUP[i as usize]),
        })
        .collect();
    format!("{m}×10{exp}")
}

/// A tick label on a log axis (three significant digits at most; a power
/// of ten as `10⁻⁴`, others as `2×10⁵`).
pub fn format_log_tick(v: f64) -> String {
    let s = times_pow10(&format_value(v));
    match s.strip_prefix("1×") {
        Some(pow) => pow.to_string(),
        None => s,
    }
}

/// A stand-alone value for a label: three significant digits, scientific
/// when |v| < 1e-3 or |v| >= 1e4.
pub fn format_value(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if !(1e-3..1e4).contains(&a) {
        trim_zeros(&format!("{v:.2e}"))
    } else {
        let dec = (2.0 - a.log10().floor()).max(0.0) as usize;
        trim_zeros(&format!("{v:.dec$}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn ticks_are_legible() {
        // Powers of ten as a reader writes them, never `5e6`.
        assert_eq!(format_tick(1.2e-24, 0.2e-24), "1.2×10⁻²⁴");
        assert_eq!(format_tick(1e-10, 1e-11), "1×10⁻¹⁰");
        assert_eq!(format_tick(3e7, 5e6), "3×10⁷");
        assert_eq!(format_tick(-3.5e7, 5e6), "-3.5×10⁷");
        assert_eq!(format_tick(5e6, 1e6), "5×10⁶");
        assert_eq!(format_log_tick(1e-4), "10⁻⁴");
        assert_eq!(format_log_tick(1e-3), "0.001");
        assert_eq!(format_log_tick(2e5), "2×10⁵");
        assert_eq!(format_log_tick(0.5), "0.5");
        assert_eq!(format_tick(0.5, 0.5), "0.5");
        assert_eq!(format_tick(2.0, 0.5), "2");
        assert_eq!(format_tick(1.25, 0.25), "1.25");
        assert_eq!(format_tick(150.0, 50.0), "150");
        assert_eq!(format_tick(1e-17, 0.5), "0");
        assert_eq!(format_value(1.196e-24), "1.2e-24");
        assert_eq!(format_value(PI), "3.14");
        assert_eq!(format_value(100.0), "100");
        assert_eq!(format_value(0.0123), "0.0123");
    }

    /// A curve leaving a fixed range is cut at the edge, where it crosses
    /// it, and resumes where it comes back: never drawn along the edge.
    #[test]
    fn segments_are_clipped_to_the_plot() {
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let ys = [1.0, 0.5, -2.0, -3.0, 0.5, 1.0];
        let clip = Some([(0.0, 5.0), (0.0, 2.0)]);
        let same = |got: Vec<Vec<(f64, f64)>>, want: Vec<Vec<(f64, f64)>>| {
            assert_eq!(got.len(), want.len(), "{got:?}");
            for (g, w) in got.iter().zip(&want) {
                assert_eq!(g.len(), w.len(), "{got:?}");
                for (a, b) in g.iter().zip(w) {
                    assert!(
                        (a.0 - b.0).abs() < 1e-12 && (a.1 - b.1).abs() < 1e-12,
                        "{got:?}"
                    );
                }
            }
        };
        same(
            segments(&xs, &ys, false, (1.0, 1.0), clip),
            vec![
                vec![(0.0, 1.0), (1.0, 0.5), (1.2, 0.0)],
                vec![(3.0 + 3.0 / 3.5, 0.0), (4.0, 0.5), (5.0, 1.0)],
            ],
        );
        // Wholly outside: nothing drawn; through the range: its part.
        assert!(segments(&xs, &[-1.0; 6], false, (1.0, 1.0), clip).is_empty());
        same(
            segments(&[0.0, 1.0], &[-1.0, 3.0], false, (1.0, 1.0), clip),
            vec![vec![(0.25, 0.0), (0.75, 2.0)]],
        );
        // A log axis cuts in log10 y: from 1 to 1e4, the edge 100 is
        // crossed half way.
        let c = segments(
            &[0.0, 1.0],
            &[1.0, 1e4],
            true,
            (1.0, 1.0),
            Some([(0.0, 1.0), (0.1, 100.0)]),
        );
        assert_eq!(c.len(), 1);
        assert_eq!(c[0][0], (0.0, 1.0));
        assert!((c[0][1].0 - 0.5).abs() < 1e-12 && (c[0][1].1 - 100.0).abs() < 1e-9);
    }

    /// The x and y of every SVG `<text>` whose content is `what`.
    fn svg_texts(svg: &str, what: &str) -> Vec<(f64, f64)> {
        let attr = |tag: &str, name: &str| -> f64 {
            let k = tag.find(&format!(" {name}=\"")).unwrap() + name.len() + 3;
            tag[k..].split('"').next().unwrap().parse().unwrap()
        };
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let (tag, rest) = t.split_once('>')?;
                (rest.split("</text>").next()?.trim() == what)
                    .then(|| (attr(tag, "x"), attr(tag, "y")))
            })
            .collect()
    }

    /// A reference line's label stands right of the plot, beside its line:
    /// clear of the curves and of a vertical mark's label at the top (fig14:
    /// "π" and "force off" collided at the top left).
    #[test]
    fn reference_labels_stand_clear_of_data_and_marks() {
        let dir = tempfile::tempdir().unwrap();
        let stem = dir.path().join("marks");
        let t: Vec<f64> = (0..=100).map(f64::from).collect();
        let th: Vec<f64> = t.iter().map(|x| 1.5 + 1.5 * (x / 5.0).sin()).collect();
        let opts = PlotOpts {
            hlines: vec![RefLine::new(PI / 2.0, "π/2"), RefLine::new(PI, "π")],
            vlines: vec![VLine::new(1.0, "force off")],
            ..PlotOpts::default()
        };
        line_plot(
            &stem,
            "marks",
            "t [µs]",
            "θ [rad]",
            &[Series::new("θ", t, th)],
            &opts,
        )
        .unwrap();
        let svg = std::fs::read_to_string(dir.path().join("marks.svg")).unwrap();
        // The x axis's last tick, 100, is centred on the plot's right edge.
        let right = svg_texts(&svg, "100")[0].0;
        let off = svg_texts(&svg, "force off")[0];
        for label in ["π", "π/2"] {
            let at = svg_texts(&svg, label);
            assert_eq!(at.len(), 1, "{label}: {at:?}");
            assert!(
                at[0].0 > right + 4.0,
                "{label} at {at:?}, the plot ends at {right}"
            );
            assert!(
                at[0].0 > off.0 + 80.0 || (at[0].1 - off.1).abs() > 16.0,
                "{label} {at:?} on {off:?}"
            );
        }
    }

    #[test]
    fn ranges_never_empty() {
        assert_eq!(data_range([0.0, 0.0].into_iter(), false, 0.05), (-1.0, 1.0));
        let (a, b) = data_range([1e-24, 1e-24].into_iter(), false, 0.05);
        assert!(a < 1e-24 && b > 1e-24);
        let (a, b) = data_range([f64::NAN, 2.0, 4.0].into_iter(), false, 0.0);
        assert_eq!((a, b), (2.0, 4.0));
        let (a, b) = data_range([-1.0, 1e-3, 1e3].into_iter(), true, 0.0);
        assert_eq!((a, b), (1e-3, 1e3));
        assert_eq!(data_range(std::iter::empty(), false, 0.0), (0.0, 1.0));
    }

    #[test]
    fn segments_break_at_gaps() {
        let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
        let ys = [1.0, f64::NAN, 2.0, 3.0, -1.0];
        assert_eq!(segments(&xs, &ys, false, (1.0, 1.0), None).len(), 2);
        assert_eq!(segments(&xs, &ys, true, (1.0, 1.0), None).len(), 2);
        assert_eq!(
            segments(&xs, &ys, true, (1.0, 10.0), None)[1],
            vec![(2.0, 20.0), (3.0, 30.0)]
        );
        assert_eq!(axis_scale(0.0, 5.0), 1.0);
        assert_eq!(axis_scale(1e-24, 3e-24), 1e24);
        assert_eq!(axis_scale(0.0, 3e7), 1e-7);
    }

    /// A temporary directory, or `$TIPPETOP_PLOT_PREVIEW` (kept) to look at
    /// the figures: `TIPPETOP_PLOT_PREVIEW=/tmp/p cargo test -p tippetop-cli plot`.
    fn out_dir() -> (Option<tempfile::TempDir>, PathBuf) {
        match std::env::var_os("TIPPETOP_PLOT_PREVIEW") {
            Some(p) => {
                let p = PathBuf::from(p);
                std::fs::create_dir_all(&p).unwrap();
                (None, p)
            }
            None => {
                let t = tempfile::tempdir().unwrap();
                let p = t.path().to_path_buf();
                (Some(t), p)
            }
        }
    }

    fn check_png(path: &Path, size: (u32, u32)) {
        let bytes = std::fs::read(path).unwrap();
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let dec = png::Decoder::new(std::io::Cursor::new(bytes));
        let reader = dec.read_info().unwrap();
        assert_eq!((reader.info().width, reader.info().height), size);
    }

    #[test]
    fn line_plot_writes_png_and_svg() {
        let dir = tempfile::tempdir().unwrap();
        let stem = dir.path().join("theta");
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.5).collect();
        let th: Vec<f64> = t
            .iter()
            .map(|x| 0.1 + 3.0 / (1.0 + (-(x - 50.0) / 8.0).exp()))
            .collect();
        let opts = PlotOpts {
            hlines: vec![RefLine::new(PI / 2.0, "π/2"), RefLine::new(PI, "π")],
            legend: Legend::LowerRight,
            ..PlotOpts::default()
        };
        line_plot(
            &stem,
            "Nutation",
            "t [µs]",
            "θ [rad]",
            &[Series::new("θ", t, th)],
            &opts,
        )
        .unwrap();
        check_png(&dir.path().join("theta.png"), DEFAULT_SIZE);
        let svg = std::fs::read_to_string(dir.path().join("theta.svg")).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("θ [rad]") && svg.contains("Nutation"));
        // Only the two figures: no temporary files left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 2);
    }

    #[test]
    fn running_envelope_of_a_fast_sine() {
        // y = x/10 + sin(2π x): over a window of whole periods the mean is
        // the trend x/10 (to the sampling), the band ±1 around it.
        let xs: Vec<f64> = (0..=20_000).map(|i| i as f64 * 1e-3).collect();
        let ys: Vec<f64> = xs.iter().map(|x| 0.1 * x + (2.0 * PI * x).sin()).collect();
        let (gx, mean, lo, hi) = running_envelope(&xs, &ys, 41, 2.0);
        assert_eq!(gx.len(), 41);
        for k in 5..36 {
            let trend = 0.1 * gx[k];
            assert!(
                (mean[k] - trend).abs() < 2e-3,
                "mean {} at {}",
                mean[k],
                gx[k]
            );
            assert!(
                (hi[k] - trend - 1.0).abs() < 0.11,
                "hi {} at {}",
                hi[k],
                gx[k]
            );
            assert!(
                (lo[k] - trend + 1.0).abs() < 0.11,
                "lo {} at {}",
                lo[k],
                gx[k]
            );
        }
        let (_tmp, dir) = out_dir();
        let s = Series::envelope("y", &xs, &ys, 200, 2.0);
        line_plot(
            &dir.join("envelope"),
            "Envelope",
            "x",
            "y",
            &[
                s.clone(),
                Series::new("trend", gx.clone(), gx.iter().map(|x| 0.1 * x).collect()),
            ],
            &PlotOpts::default(),
        )
        .unwrap();
        check_png(&dir.join("envelope.png"), DEFAULT_SIZE);
    }

    #[test]
    fn tiny_and_huge_values_and_log_y() {
        let (_tmp, dir) = out_dir();
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 1e-6).collect();
        let n: Vec<f64> = t
            .iter()
            .map(|x| 1.17e-23 * (1.0 + 0.3 * (x * 1e5).sin()))
            .collect();
        let w: Vec<f64> = t.iter().map(|x| 3e7 * (1.0 - x * 1e4)).collect();
        let d: Vec<f64> = t.iter().map(|x| 1e-12 + x * 1e-6).collect();
        let mut log = Panel::new("drift", vec![Series::new("rel", t.clone(), d)]);
        log.opts.log_y = true;
        let panels = vec![
            Panel::new("N [N]", vec![Series::new("N", t.clone(), n)]),
            Panel::new("ω [rad/s]", vec![Series::new("ω", t.clone(), w).dashed()]),
            log,
        ];
        multi_panel(
            &dir.join("diag"),
            "Diagnostics",
            "t [s]",
            &panels,
            &PlotOpts {
                size: (1000, 900),
                ..PlotOpts::default()
            },
        )
        .unwrap();
        check_png(&dir.join("diag.png"), (1000, 900));
    }

    #[test]
    fn heatmap_writes_both() {
        let (_tmp, dir) = out_dir();
        let xs: Vec<f64> = (0..8).map(|i| 1e-23 * 2f64.powi(i)).collect();
        let ys: Vec<f64> = (0..5).map(|j| 0.05 + 0.05 * j as f64).collect();
        let z: Vec<Vec<f64>> = ys
            .iter()
            .map(|y| xs.iter().map(|x| x * 1e23 * y).collect())
            .collect();
        let mut z = z;
        z[0][0] = f64::NAN;
        heatmap(
            &dir.join("sweep"),
            "Flip time",
            "H [N]",
            "μ",
            "t_flip [µs]",
            &xs,
            &ys,
            &z,
            &HeatmapOpts::default(),
        )
        .unwrap();
        check_png(&dir.join("sweep.png"), DEFAULT_SIZE);
        assert!(dir.join("sweep.svg").exists());
        assert!(
            heatmap(
                &dir.join("bad"),
                "",
                "",
                "",
                "",
                &xs,
                &ys,
                &z[1..],
                &HeatmapOpts::default()
            )
            .is_err()
        );
    }
}
