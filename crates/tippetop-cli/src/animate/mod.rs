//! `tippetop animate DIR`: the top of a run in 3D, as a GIF
//! (`DIR/animation.gif`, [`gif_out`]) and as a self-contained HTML viewer
//! (`DIR/viewer.html`, [`viewer`]).
//!
//! The frames: `fps × duration` frames at equally spaced times from the
//! first to the last row of `DIR/trajectory.csv`. Where the rows are too
//! coarse for that (a gap between rows longer than a frame's interval, or
//! the body turning more than [`MAX_TURN_PER_ROW`] between rows), the run is
//! replayed from `DIR/scenario.toml` with [`tippetop::Simulation`] and each
//! frame is the state read from the dense output at its time
//! (`integrate_to(t)` then `state()`); otherwise the frames are interpolated
//! between rows (linear; the attitude by spherical interpolation). The
//! geometry and the camera are in [`scene`].

pub mod gif_out;
pub mod scene;
pub mod viewer;

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::Result;
use tippetop::{Sample, Scenario, Simulation};

use crate::output::{OutDir, read_lock};

/// Long help of `tippetop animate`.
pub const ANIMATE_LONG_ABOUT: &str = "Animate the output of `tippetop run ... --out DIR`: \
    writes into DIR
  animation.gif   the top in 3D: a shaded sphere with a painted meridian band (so the spin
                  shows) and a white cap on the end the symmetry axis points to (the stem's
                  end of a real toy; with top.stem_radius the stem's ball too, shaded where it sticks
                  out of the sphere), the symmetry axis, the centre of mass (red dot, drawn
                  through the sphere), the contact point's trace on the floor so far, the
                  applied force as an orange arrow on the floor from the contact point (1.5 R
                  long at the run's largest |H|) with its magnitude [N], a scale bar (a round
                  length near R: true along the screen's horizontal), a clock and the value of
                  theta; an inset map of the whole trace when it is longer
                  than the view; fixed oblique orthographic camera (azimuth -65 deg from the lab
                  X axis, elevation 25 deg) that follows the top across the floor; loops
  viewer.html     one self-contained file (no network; open it in any browser, from the
                  file system): the same scene, which you turn with the mouse (drag; wheel:
                  zoom), play/pause (space), a time slider, a speed control, and theta(t)
                  beside it with a moving cursor (click it to jump there)

The frames: fps x duration frames (default 20 x 10 = 200) at equally spaced times from the
first to the last row of DIR/trajectory.csv, so the whole run plays in --duration seconds
(the first frame is the first row, the last frame the last row). If the rows are too coarse
for that (a gap between rows longer than a frame's interval, or the top turning more than
0.2 rad between rows), the run is replayed from DIR/scenario.toml (tippetop::Simulation;
stochastic Langevin/Brownian runs replay bit for bit) and each frame is the state at its time
from the integrator's dense output; otherwise frames are interpolated between rows. The
contact trace is drawn from the rows. A spin faster than the frames can show (more than a
small angle per frame) is drawn with the band smeared over the angle it turns through in a
frame's interval (motion blur), as a camera would, instead of a strobing stripe. A GIF
frame lasts a whole number of hundredths of a second: 100/fps rounded (exact for 1, 2, 4, 5,
10, 20, 25 and 50 fps).

The files are written aside and moved in together; the run's files are kept (a later `run`
into DIR removes the animation, which belongs to the run it replaced). Bad input (a DIR
without a run, a flag out of range) prints one line and exits with code 2, writing nothing.";

/// At most this angle \[rad\] of attitude change between two rows for the
/// rows to be interpolated rather than the run replayed.
pub const MAX_TURN_PER_ROW: f64 = 0.2;

/// Largest number of frames (`fps × duration`).
pub const MAX_FRAMES: usize = 600;

/// Animate a run: DIR/animation.gif and DIR/viewer.html (a 3D view in the browser).
#[derive(Debug, Clone, clap::Args)]
#[command(long_about = ANIMATE_LONG_ABOUT)]
#[command(after_help = "Example:\n  \
    tippetop run --preset classical --set surface.friction_law=regularized \\\n      --set surface.friction_eps=0.01 --out out/classical\n  \
    tippetop animate out/classical\n  \
    tippetop animate out/classical --fps 25 --duration 8 --size 640x480\n\n\
    Exit codes: 0 ok, 2 bad input (one line), 1 I/O failure or DIR in use.")]
pub struct AnimateArgs {
    /// The output directory of a `tippetop run` (with scenario.toml and
    /// trajectory.csv); the animation is written into it.
    #[arg(value_name = "DIR")]
    pub dir: PathBuf,
    /// Frames per second of the animation, 1 to 50.
    #[arg(long, value_name = "N", default_value = "20")]
    pub fps: String,
    /// Length of the animation [s of wall-clock time], 0.1 to 60; the whole
    /// run plays in it. At most 600 frames (fps × duration).
    #[arg(
        long,
        value_name = "S",
        default_value = "10",
        allow_negative_numbers = true
    )]
    pub duration: String,
    /// Size of the GIF [pixels], WxH, W 64 to 1280, H 64 to 960 (the
    /// viewer's 3D view has the same size).
    #[arg(long, value_name = "WxH", default_value = "480x360")]
    pub size: String,
}

/// Checked settings of an animation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Settings {
    /// Frames per second \[1/s\].
    pub fps: u32,
    /// Number of frames.
    pub frames: usize,
    /// Width \[px\].
    pub width: u32,
    /// Height \[px\].
    pub height: u32,
}

/// Parse and check `--fps`, `--duration`, `--size`: `Err` is the one-line
/// message naming the flag and its range.
pub fn settings(args: &AnimateArgs) -> std::result::Result<Settings, String> {
    let fps = match args.fps.trim().parse::<u32>() {
        Ok(v) if (1..=50).contains(&v) => v,
        _ => {
            return Err(format!(
                "--fps: {} is not allowed (a whole number of frames per second, 1 to 50)",
                args.fps
            ));
        }
    };
    let duration = match args.duration.trim().parse::<f64>() {
        Ok(v) if (0.1..=60.0).contains(&v) => v,
        _ => {
            return Err(format!(
                "--duration: {} is not allowed (seconds of animation, 0.1 to 60)",
                args.duration
            ));
        }
    };
    let frames = (fps as f64 * duration).round();
    if !(2.0..=MAX_FRAMES as f64).contains(&frames) {
        return Err(format!(
            "--duration: {} s at {fps} fps is {frames} frames (fps x duration: 2 to {MAX_FRAMES} frames)",
            args.duration
        ));
    }
    let size = args
        .size
        .trim()
        .split_once(['x', 'X'])
        .and_then(|(w, h)| Some((w.parse::<u32>().ok()?, h.parse::<u32>().ok()?)))
        .filter(|(w, h)| (64..=1280).contains(w) && (64..=960).contains(h));
    let Some((width, height)) = size else {
        return Err(format!(
            "--size: {} is not allowed (WxH in pixels, W 64 to 1280, H 64 to 960, e.g. 480x360)",
            args.size
        ));
    };
    Ok(Settings {
        fps,
        frames: frames as usize,
        width,
        height,
    })
}

/// One frame's state: what the drawing needs of a trajectory row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// Time \[s\].
    pub t: f64,
    /// Nutation angle θ \[rad\].
    pub theta: f64,
    /// Spin ω about the symmetry axis \[rad/s\].
    pub spin: f64,
    /// Centre of mass `(x, y, z)`, lab frame \[m\].
    pub com: [f64; 3],
    /// Attitude, unit quaternion body → lab `(w, x, y, z)` \[1\].
    pub q: [f64; 4],
    /// Contact point `(x_P, y_P)` on the plane \[m\].
    pub contact: [f64; 2],
    /// Applied force `(H_x, H_y)` at the contact point \[N\] (zero for a
    /// trajectory.csv without the columns).
    pub force: [f64; 2],
}

impl Frame {
    fn from_sample(s: &Sample) -> Frame {
        Frame {
            t: s.t,
            theta: s.theta,
            spin: s.spin,
            com: [s.x, s.y, s.z],
            q: normalized([s.qw, s.qx, s.qy, s.qz]),
            contact: [s.xp, s.yp],
            force: [s.hx, s.hy],
        }
    }
}

/// Everything drawn: the top's geometry, the frames, the trace and θ(t).
#[derive(Debug, Clone)]
pub struct Movie {
    /// What is shown (the directory's name).
    pub title: String,
    /// Sphere radius R \[m\].
    pub radius: f64,
    /// Offset a of the centre of mass from the sphere's centre \[m\].
    pub offset: f64,
    /// The stem (`top.stem_radius` r2, `top.stem_distance` d2) \[m\], if
    /// any: drawn as a peg along `k` ending in a ball of radius r2 centred
    /// at `O + d2 k` (docs/physics.md#stem).
    pub stem: Option<(f64, f64)>,
    /// The frames, in time order.
    pub frames: Vec<Frame>,
    /// Time between frames \[s of run time\].
    pub frame_dt: f64,
    /// Frames per second of playback \[1/s\].
    pub fps: u32,
    /// The contact point's trace: `(t [s], x_P [m], y_P [m])`, thinned to at
    /// most [`TRACE_POINTS`] rows.
    pub trace: Vec<[f64; 3]>,
    /// θ(t) from the rows: `(t [s], θ [rad])`, thinned to at most
    /// [`TRACE_POINTS`] rows.
    pub theta_curve: Vec<[f64; 2]>,
    /// How the frames were obtained (for the printed summary).
    pub source: String,
    /// Largest |H| over the frames \[N\] (0: no applied force): the
    /// force arrow is 1.5 R long at this magnitude.
    pub force_max: f64,
    /// The scale bar: a round length near R \[m\] and its label.
    pub scale_bar: (f64, String),
}

/// A round length (1, 2 or 5 times a power of ten) at most `r` \[m\], and
/// its label with an SI prefix (`"5 mm"`, `"200 pm"`).
pub fn scale_bar(r: f64) -> (f64, String) {
    if !(r.is_finite() && r > 0.0) {
        return (0.0, String::new());
    }
    let p = 10f64.powf(r.log10().floor());
    let m = [5.0, 2.0, 1.0]
        .into_iter()
        .find(|m| m * p <= r * (1.0 + 1e-12))
        .unwrap_or(1.0);
    let len = m * p;
    let prefixes = [
        (1.0, "m"),
        (1e-3, "mm"),
        (1e-6, "µm"),
        (1e-9, "nm"),
        (1e-12, "pm"),
        (1e-15, "fm"),
    ];
    let (unit, name) = prefixes
        .into_iter()
        .find(|(u, _)| len >= u * (1.0 - 1e-9))
        .unwrap_or((1e-15, "fm"));
    let v = len / unit;
    let text = if (v - v.round()).abs() < 1e-9 {
        format!("{}", v.round())
    } else {
        format!("{v}")
    };
    (len, format!("{text} {name}"))
}

/// Largest number of rows kept for the trace and for θ(t).
pub const TRACE_POINTS: usize = 4000;

/// The rows of `trajectory.csv` that the animation reads.
#[derive(Debug, Clone, Default)]
struct Rows {
    frames: Vec<Frame>,
}

/// One line of bad input about `path`.
fn bad(path: &Path, what: impl std::fmt::Display) -> String {
    format!("{}: {what}", path.display())
}

/// Parse `trajectory.csv` (the columns the animation needs, by name).
fn parse_rows(path: &Path, text: &str) -> std::result::Result<Rows, String> {
    let mut lines = text.lines();
    let header: Vec<&str> = lines
        .next()
        .ok_or_else(|| bad(path, "empty (no header line)"))?
        .split(',')
        .map(str::trim)
        .collect();
    let names = [
        "t", "theta", "omega", "x", "y", "z", "qw", "qx", "qy", "qz", "xp", "yp",
    ];
    let mut idx = [0usize; 12];
    // A run written with `--no-pose` has no pose to draw.
    if header.contains(&"rolling") && !header.contains(&"qw") {
        return Err(bad(
            path,
            "no pose columns (x, y, z, qw, ...): the run was written with --no-pose; run it again without --no-pose to animate it",
        ));
    }
    for (i, name) in names.iter().enumerate() {
        idx[i] = header.iter().position(|h| h == name).ok_or_else(|| {
            bad(
                path,
                format!("no column {name} (a trajectory.csv of tippetop run, 0.1 or later)"),
            )
        })?;
    }
    // The applied force (optional: older files lack it).
    let force_idx = ["hx", "hy"].map(|name| header.iter().position(|h| *h == name));
    let mut frames = Vec::new();
    for (n, line) in lines.enumerate() {
        if line.trim().is_empty() {
            continue;
        }
        let fields: Vec<&str> = line.split(',').collect();
        let mut v = [0.0f64; 12];
        for (k, &i) in idx.iter().enumerate() {
            v[k] = fields
                .get(i)
                .and_then(|f| f.trim().parse::<f64>().ok())
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    bad(
                        path,
                        format!("row {}: column {} is not a finite number", n + 2, names[k]),
                    )
                })?;
        }
        if let Some(last) = frames.last().map(|f: &Frame| f.t)
            && v[0] < last
        {
            return Err(bad(path, format!("row {}: time goes backwards", n + 2)));
        }
        let mut force = [0.0; 2];
        for (k, i) in force_idx.iter().enumerate() {
            if let Some(i) = i {
                force[k] = fields
                    .get(*i)
                    .and_then(|f| f.trim().parse::<f64>().ok())
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        bad(
                            path,
                            format!(
                                "row {}: column {} is not a finite number",
                                n + 2,
                                ["hx", "hy"][k]
                            ),
                        )
                    })?;
            }
        }
        frames.push(Frame {
            t: v[0],
            theta: v[1],
            spin: v[2],
            com: [v[3], v[4], v[5]],
            q: normalized([v[6], v[7], v[8], v[9]]),
            contact: [v[10], v[11]],
            force,
        });
    }
    if frames.len() < 2 || frames[frames.len() - 1].t <= frames[0].t {
        return Err(bad(
            path,
            "fewer than two rows at distinct times (nothing to animate)",
        ));
    }
    Ok(Rows { frames })
}

/// `q / |q|` (the identity for a zero quaternion).
fn normalized(q: [f64; 4]) -> [f64; 4] {
    let n = q.iter().map(|c| c * c).sum::<f64>().sqrt();
    if n > 0.0 && n.is_finite() {
        q.map(|c| c / n)
    } else {
        [1.0, 0.0, 0.0, 0.0]
    }
}

/// Angle \[rad\] of the rotation between two unit quaternions.
fn turn_angle(p: [f64; 4], q: [f64; 4]) -> f64 {
    let dot: f64 = p.iter().zip(q).map(|(a, b)| a * b).sum();
    2.0 * dot.abs().min(1.0).acos()
}

/// Spherical interpolation between unit quaternions, `s` in \[0, 1\].
fn slerp(p: [f64; 4], q: [f64; 4], s: f64) -> [f64; 4] {
    let mut dot: f64 = p.iter().zip(q).map(|(a, b)| a * b).sum();
    let q = if dot < 0.0 {
        dot = -dot;
        q.map(|c| -c)
    } else {
        q
    };
    if dot > 0.9995 {
        return normalized(std::array::from_fn(|i| p[i] + s * (q[i] - p[i])));
    }
    let th = dot.min(1.0).acos();
    let (a, b) = (((1.0 - s) * th).sin(), (s * th).sin());
    let st = th.sin();
    normalized(std::array::from_fn(|i| (a * p[i] + b * q[i]) / st))
}

/// The state at time `t` interpolated between the rows (`rows` sorted by
/// time, `t` within them).
fn interpolate(rows: &[Frame], t: f64) -> Frame {
    let j = rows.partition_point(|r| r.t <= t);
    if j == 0 {
        return rows[0];
    }
    if j >= rows.len() {
        return rows[rows.len() - 1];
    }
    let (a, b) = (&rows[j - 1], &rows[j]);
    let s = if b.t > a.t {
        (t - a.t) / (b.t - a.t)
    } else {
        0.0
    };
    let l = |x: f64, y: f64| x + s * (y - x);
    Frame {
        t,
        theta: l(a.theta, b.theta),
        spin: l(a.spin, b.spin),
        com: std::array::from_fn(|i| l(a.com[i], b.com[i])),
        q: slerp(a.q, b.q, s),
        contact: std::array::from_fn(|i| l(a.contact[i], b.contact[i])),
        // A force switches rather than glides: the row before's value.
        force: a.force,
    }
}

/// Whether the rows are too coarse for frames `frame_dt` \[s\] apart.
fn too_coarse(rows: &[Frame], frame_dt: f64) -> bool {
    rows.windows(2).any(|w| {
        w[1].t - w[0].t > frame_dt * (1.0 + 1e-9) || turn_angle(w[0].q, w[1].q) > MAX_TURN_PER_ROW
    })
}

/// Every `step`-th element and the last: at most `max` of `items`.
fn thin<T: Copy>(items: &[T], max: usize) -> Vec<T> {
    if items.len() <= max {
        return items.to_vec();
    }
    let step = items.len().div_ceil(max - 1);
    let mut out: Vec<T> = items.iter().step_by(step).copied().collect();
    if (items.len() - 1) % step != 0 {
        out.push(items[items.len() - 1]);
    }
    out
}

/// The frames of the run in `dir`: the checked scenario and rows, then the
/// frames (interpolated or replayed). `Err(Input)` for bad input (exit 2),
/// `Err(Other)` otherwise.
pub fn load_movie(dir: &Path, settings: &Settings) -> std::result::Result<Movie, LoadError> {
    if !dir.is_dir() {
        return Err(LoadError::Input(bad(
            dir,
            "no such directory (the --out directory of a tippetop run)",
        )));
    }
    let scenario_path = dir.join("scenario.toml");
    let csv_path = dir.join("trajectory.csv");
    for p in [&scenario_path, &csv_path] {
        if !p.is_file() {
            return Err(LoadError::Input(bad(
                dir,
                format!(
                    "no run here: {} is missing (animate reads the --out directory of a tippetop run: scenario.toml and trajectory.csv)",
                    p.file_name().unwrap_or_default().to_string_lossy()
                ),
            )));
        }
    }
    // A link where the lock should be, like any bad input, is exit 2.
    let _guard = read_lock(dir).map_err(|e| match e.downcast_ref::<tippetop::Error>() {
        Some(te) => LoadError::Input(te.to_string()),
        None => LoadError::Other(format!("{e:#}")),
    })?;
    let read = |p: &Path| {
        std::fs::read_to_string(p).map_err(|e| LoadError::Input(bad(p, format!("unreadable: {e}"))))
    };
    let toml =
        tippetop::limits::read_file(&scenario_path).map_err(|e| LoadError::Input(e.to_string()))?;
    let scenario =
        Scenario::from_toml_str(&toml).map_err(|e| LoadError::Input(bad(&scenario_path, e)))?;
    let rows = parse_rows(&csv_path, &read(&csv_path)?)
        .map_err(LoadError::Input)?
        .frames;
    let (t0, t1) = (rows[0].t, rows[rows.len() - 1].t);
    let n = settings.frames;
    let frame_dt = (t1 - t0) / (n - 1) as f64;
    let times: Vec<f64> = (0..n)
        .map(|i| {
            if i + 1 == n {
                t1
            } else {
                t0 + frame_dt * i as f64
            }
        })
        .collect();
    let (frames, source) = if too_coarse(&rows, frame_dt) {
        (
            replay(&scenario, &times).map_err(LoadError::Input)?,
            format!(
                "replayed scenario.toml: states at the frame times from the dense output ({} rows were too coarse for a frame every {})",
                rows.len(),
                tippetop::human::si(frame_dt, "s", 3)
            ),
        )
    } else {
        (
            times.iter().map(|&t| interpolate(&rows, t)).collect(),
            format!(
                "interpolated between the {} rows of trajectory.csv (fine enough for a frame every {})",
                rows.len(),
                tippetop::human::si(frame_dt, "s", 3)
            ),
        )
    };
    let title = std::fs::canonicalize(dir)
        .ok()
        .and_then(|p| p.file_name().map(|s| s.to_string_lossy().into_owned()))
        .unwrap_or_else(|| dir.display().to_string());
    let trace: Vec<[f64; 3]> = rows
        .iter()
        .map(|r| [r.t, r.contact[0], r.contact[1]])
        .collect();
    let theta_curve: Vec<[f64; 2]> = rows.iter().map(|r| [r.t, r.theta]).collect();
    Ok(Movie {
        title,
        radius: scenario.top.radius,
        offset: scenario.top.offset,
        stem: scenario.top.stem.map(|st| (st.radius, st.distance)),
        frame_dt,
        fps: settings.fps,
        trace: thin(&trace, TRACE_POINTS),
        theta_curve: thin(&theta_curve, TRACE_POINTS),
        source,
        force_max: frames
            .iter()
            .map(|f| f.force[0].hypot(f.force[1]))
            .fold(0.0, f64::max),
        scale_bar: scale_bar(scenario.top.radius),
        frames,
    })
}

/// Why [`load_movie`] failed.
#[derive(Debug, Clone, PartialEq)]
pub enum LoadError {
    /// Bad input: one line, exit code 2.
    Input(String),
    /// Anything else (e.g. the directory is in use): exit code 1.
    Other(String),
}

/// Replay `scenario` and read its state at each of `times` (increasing,
/// within the run) from the dense output. A run that failed before a time
/// gives its last state there.
fn replay(scenario: &Scenario, times: &[f64]) -> std::result::Result<Vec<Frame>, String> {
    let mut sim = Simulation::new(scenario).map_err(|e| format!("scenario.toml: {e}"))?;
    let t_end = scenario.solver.t_end;
    let mut frames = Vec::with_capacity(times.len());
    for &t in times {
        let t = t.min(t_end).max(sim.time());
        sim.integrate_to(t)
            .map_err(|e| format!("scenario.toml: replaying: {e}"))?;
        let mut f = Frame::from_sample(&sim.state());
        f.t = t;
        frames.push(f);
    }
    Ok(frames)
}

/// Run `tippetop animate`.
pub fn run(args: &AnimateArgs, quiet: bool) -> Result<ExitCode> {
    let input_error = |msg: String| {
        eprintln!(
            "error: {}",
            msg.split_whitespace().collect::<Vec<_>>().join(" ")
        );
        Ok(ExitCode::from(2))
    };
    let settings = match settings(args) {
        Ok(s) => s,
        Err(m) => return input_error(m),
    };
    let start = Instant::now();
    let movie = match load_movie(&args.dir, &settings) {
        Ok(m) => m,
        Err(LoadError::Input(m)) => return input_error(m),
        Err(LoadError::Other(m)) => anyhow::bail!(m),
    };
    let mut out = OutDir::open(&args.dir)?;
    out.keep_previous();
    let gif_path = out.stage().join("animation.gif");
    let stats = gif_out::write_gif(&gif_path, &movie, &settings)?;
    let html = viewer::html(&movie, &settings)?;
    crate::output::write_bytes_atomic(&out.stage().join("viewer.html"), html.as_bytes())?;
    out.commit(&[])?;
    if !quiet {
        let dir = args.dir.display();
        println!("frames: {} ({})", movie.frames.len(), movie.source);
        println!(
            "wrote {dir}/animation.gif ({} frames, {}x{}, {} fps, {:.2} MB) and {dir}/viewer.html ({:.0} kB) in {}",
            stats.frames,
            settings.width,
            settings.height,
            settings.fps,
            stats.bytes as f64 / 1e6,
            html.len() as f64 / 1e3,
            crate::output::fmt_duration(start.elapsed().as_secs_f64())
        );
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {

    #[test]
    fn scale_bar_is_a_round_length_below_r() {
        assert_eq!(scale_bar(0.015), (0.01, "10 mm".to_string()));
        assert_eq!(scale_bar(3.55e-10).1, "200 pm");
        assert!((scale_bar(3.55e-10).0 - 2e-10).abs() < 1e-24);
        assert_eq!(scale_bar(0.005).1, "5 mm");
        assert_eq!(scale_bar(1.0).1, "1 m");
        assert_eq!(scale_bar(2.5e-6).1, "2 µm");
    }
    use super::*;

    fn args(fps: &str, duration: &str, size: &str) -> AnimateArgs {
        AnimateArgs {
            dir: PathBuf::from("x"),
            fps: fps.into(),
            duration: duration.into(),
            size: size.into(),
        }
    }

    #[test]
    fn settings_ranges() {
        let s = settings(&args("20", "10", "480x360")).unwrap();
        assert_eq!((s.fps, s.frames, s.width, s.height), (20, 200, 480, 360));
        for (a, flag) in [
            (args("0", "10", "480x360"), "--fps"),
            (args("x", "10", "480x360"), "--fps"),
            (args("20", "-1", "480x360"), "--duration"),
            (args("20", "nan", "480x360"), "--duration"),
            (args("50", "60", "480x360"), "--duration"),
            (args("20", "10", "10x10"), "--size"),
            (args("20", "10", "480"), "--size"),
        ] {
            let e = settings(&a).unwrap_err();
            assert!(e.starts_with(flag), "{e}");
            assert!(!e.contains('\n'));
        }
    }

    #[test]
    fn slerp_and_interpolation() {
        let p = [1.0, 0.0, 0.0, 0.0];
        let h = std::f64::consts::FRAC_PI_4;
        let q = [h.cos(), 0.0, 0.0, h.sin()]; // 90° about z
        let m = slerp(p, q, 0.5);
        assert!((turn_angle(p, m) - h).abs() < 1e-12);
        // The short way round for the negated quaternion.
        let m2 = slerp(p, q.map(|c| -c), 0.5);
        assert!((turn_angle(p, m2) - h).abs() < 1e-12);
        assert_eq!(thin(&[1, 2, 3, 4, 5, 6, 7], 3), vec![1, 5, 7]);
        assert_eq!(thin(&[1, 2, 3, 4, 5], 3), vec![1, 4, 5]);
    }
}
