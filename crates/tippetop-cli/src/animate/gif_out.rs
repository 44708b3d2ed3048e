//! `animation.gif`: each frame drawn in software (floor, shadow and trace,
//! then the sphere pixel by pixel, then the axis, the centre of mass and
//! the text with plotters on the same buffer), one global 256-colour
//! palette (NeuQuant over a few frames), each frame stored as the rectangle
//! that changed since the previous one.

use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use anyhow::{Context, Result, anyhow};
use plotters::prelude::*;

use super::scene::{Camera, Pose, V3, axpy, dot, surface_colour};
use super::{Movie, Settings};
use crate::plot::{ensure_font, font};

/// What was written.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GifStats {
    /// Number of frames.
    pub frames: usize,
    /// File size \[bytes\].
    pub bytes: u64,
}

/// Time unit for the clock: (factor to divide seconds by, name), from the
/// run's length `t` \[s\].
pub fn time_unit(t: f64) -> (f64, &'static str) {
    let t = t.abs();
    if t >= 1.0 {
        (1.0, "s")
    } else if t >= 1e-3 {
        (1e-3, "ms")
    } else if t >= 1e-6 {
        (1e-6, "µs")
    } else if t >= 1e-9 {
        (1e-9, "ns")
    } else {
        (1e-12, "ps")
    }
}

/// Decimals that resolve a step `dt` \[s\] in `unit` \[s\] (0 to 6).
pub fn time_decimals(dt: f64, unit: f64) -> usize {
    let x = dt / unit;
    if x > 0.0 && x.is_finite() {
        (-x.log10()).ceil().clamp(0.0, 6.0) as usize
    } else {
        3
    }
}

/// Floor colours.
const BACKGROUND: V3 = [0.97, 0.97, 0.98];
const STAGE: V3 = [0.90, 0.89, 0.86];
const GRID: V3 = [0.74, 0.73, 0.70];
const TRACE: RGBColor = RGBColor(20, 120, 140);

/// Colour of the applied-force arrow and its label.
const FORCE: RGBColor = RGBColor(230, 110, 0);

/// Colour of the stem (§stem), before shading.
const STEM: V3 = [0.62, 0.45, 0.25];

fn to_u8(c: V3) -> [u8; 3] {
    c.map(|v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8)
}

/// Draw frame `i` of `movie` into `buf` (RGB, `w × h`).
pub fn render_frame(movie: &Movie, i: usize, settings: &Settings, buf: &mut [u8]) -> Result<()> {
    let (w, h) = (settings.width, settings.height);
    let f = &movie.frames[i];
    let rr = movie.radius;
    let pose = Pose::new(f.com, f.q, movie.offset);
    let cam = Camera::standard(w, h, rr, pose.centre);
    let sweep = (f.spin * movie.frame_dt).abs();
    let rpx = rr * cam.scale;

    draw_floor(buf, (w, h), &cam, &pose, rr);

    // 2. The contact trace so far (clipped to the image).
    let screen = |p: V3| {
        let (x, y, _) = cam.project(p);
        (x, y)
    };
    {
        let root = BitMapBackend::with_buffer(buf, (w, h)).into_drawing_area();
        let mut pts: Vec<(f64, f64)> = movie
            .trace
            .iter()
            .take_while(|p| p[0] <= f.t)
            .map(|p| screen([p[1], p[2], 0.0]))
            .collect();
        pts.push(screen([f.contact[0], f.contact[1], 0.0]));
        for run in clipped_runs(&pts, w, h) {
            root.draw(&PathElement::new(run, TRACE.stroke_width(2)))
                .map_err(|e| anyhow!("drawing the trace: {e}"))?;
        }
        root.present()
            .map_err(|e| anyhow!("drawing the trace: {e}"))?;
    }

    draw_sphere(buf, (w, h), &cam, &pose, rr, sweep);
    if let Some(stem) = movie.stem {
        draw_stem_ball(buf, (w, h), &cam, &pose, rr, stem);
    }

    // 4. Axis (visible parts), centre of mass, text, map.
    ensure_font()?;
    let root = BitMapBackend::with_buffer(buf, (w, h)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing frame {i}: {e}");
    let pixel = |p: V3| {
        let (x, y) = screen(p);
        (x.clamp(-1e4, 1e4) as i32, y.clamp(-1e4, 1e4) as i32)
    };
    if let Some((r2, d2)) = movie.stem {
        // The stem (§stem): a peg along +k from inside the sphere to a ball of
        // radius r2 at O + d2 k, where not behind the sphere.
        let tip = axpy(pose.com, d2, pose.k);
        let start = axpy(pose.centre, 0.8 * rr, pose.k);
        let width = (1.2 * r2 * cam.scale).max(2.0) as u32;
        let peg = RGBColor(120, 85, 45).stroke_width(width);
        let mut parts: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for s in 0..=40 {
            let p = axpy(start, s as f64 / 40.0, axpy(tip, -1.0, start));
            if cam.hidden_by_sphere(p, pose.centre, rr) {
                parts.push(Vec::new());
            } else if let Some(last) = parts.last_mut() {
                last.push(screen(p));
            }
        }
        for part in &parts {
            for run in clipped_runs(part, w, h) {
                root.draw(&PathElement::new(run, peg)).map_err(err)?;
            }
        }
    }
    let axis_ends = (
        axpy(pose.centre, -1.45 * rr, pose.k),
        axpy(pose.centre, 1.45 * rr, pose.k),
    );
    let steps = 120;
    let axis_style = RGBColor(30, 30, 40).stroke_width(2);
    let mut visible: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
    for s in 0..=steps {
        let p = axpy(
            axis_ends.0,
            s as f64 / steps as f64,
            axpy(axis_ends.1, -1.0, axis_ends.0),
        );
        if cam.hidden_by_sphere(p, pose.centre, rr) {
            visible.push(Vec::new());
        } else if let Some(last) = visible.last_mut() {
            last.push(screen(p));
        }
    }
    for part in &visible {
        for run in clipped_runs(part, w, h) {
            root.draw(&PathElement::new(run, axis_style)).map_err(err)?;
        }
    }
    let dot_r = (0.06 * rpx).clamp(3.0, 8.0) as i32;
    if !cam.hidden_by_sphere(axis_ends.1, pose.centre, rr) {
        root.draw(&Circle::new(
            pixel(axis_ends.1),
            dot_r - 1,
            RGBColor(30, 30, 40).filled(),
        ))
        .map_err(err)?;
    }
    let o = pixel(pose.com);
    root.draw(&Circle::new(o, dot_r + 1, WHITE.filled()))
        .map_err(err)?;
    root.draw(&Circle::new(o, dot_r, RGBColor(200, 20, 30).filled()))
        .map_err(err)?;

    let fmag = f.force[0].hypot(f.force[1]);
    draw_force_arrow(&root, movie, i, &cam, &pose)?;

    let size = (h as f64 / 22.0).clamp(10.0, 28.0);
    let t_last = movie.frames[movie.frames.len() - 1].t;
    let (unit, uname) = time_unit(t_last);
    let dec = time_decimals(movie.frame_dt, unit);
    let lines = [
        format!("t = {:.*} {uname}", dec, f.t / unit),
        format!("θ = {:.3} rad ({:.1}°)", f.theta, f.theta.to_degrees()),
    ];
    for (n, l) in lines.iter().enumerate() {
        root.draw(&Text::new(
            l.clone(),
            (8, 6 + (n as f64 * size * 1.2) as i32),
            font(size),
        ))
        .map_err(err)?;
    }
    if movie.force_max > 0.0 {
        root.draw(&Text::new(
            format!("→ applied force H = {} N", tippetop::human::s4(fmag)),
            (8, 6 + (2.0 * size * 1.2) as i32),
            font(size * 0.8).color(&FORCE),
        ))
        .map_err(err)?;
    }
    draw_scale_bar(&root, movie, i, &cam, size)?;
    let small = font(size * 0.7).color(&RGBColor(90, 90, 90));
    root.draw(&Text::new(
        movie.title.clone(),
        (8, h as i32 - (size * 0.9) as i32 - 4),
        small.clone(),
    ))
    .map_err(err)?;

    draw_map(&root, movie, i, size)?;
    root.present().map_err(err)?;
    Ok(())
}

/// The applied force of frame `i`: an arrow on the floor from the contact
/// point, 1.5 R long at the run's largest |H|, where not behind the sphere.
fn draw_force_arrow(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    movie: &Movie,
    i: usize,
    cam: &Camera,
    pose: &Pose,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing frame {i}: {e}");
    let (w, h) = root.dim_in_pixel();
    let f = &movie.frames[i];
    let rr = movie.radius;
    let screen = |p: V3| {
        let (x, y, _) = cam.project(p);
        (x, y)
    };
    let pixel = |p: V3| {
        let (x, y) = screen(p);
        (x.clamp(-1e4, 1e4) as i32, y.clamp(-1e4, 1e4) as i32)
    };
    let fmag = f.force[0].hypot(f.force[1]);
    if movie.force_max > 0.0 && fmag > 0.0 {
        let len = 1.5 * rr * fmag / movie.force_max;
        let dir = [f.force[0] / fmag, f.force[1] / fmag, 0.0];
        let base = [f.contact[0], f.contact[1], 0.0];
        let tip = axpy(base, len, dir);
        let side = [-dir[1], dir[0], 0.0];
        let head = 0.3 * rr.min(len);
        let back = axpy(tip, -head, dir);
        let style = FORCE.stroke_width(3);
        let mut shaft: Vec<Vec<(f64, f64)>> = vec![Vec::new()];
        for s in 0..=60 {
            let p = axpy(base, s as f64 / 60.0 * (len - 0.5 * head), dir);
            if cam.hidden_by_sphere(p, pose.centre, rr) {
                shaft.push(Vec::new());
            } else if let Some(last) = shaft.last_mut() {
                last.push(screen(p));
            }
        }
        // Each visible part is straight: draw it as one segment (a thick
        // polyline of many short pieces would zigzag in the bitmap).
        for part in shaft.iter().filter(|p| p.len() > 1) {
            let ends = [part[0], part[part.len() - 1]];
            for run in clipped_runs(&ends, w, h) {
                root.draw(&PathElement::new(run, style)).map_err(err)?;
            }
        }
        if !cam.hidden_by_sphere(tip, pose.centre, rr) {
            root.draw(&Polygon::new(
                vec![
                    pixel(tip),
                    pixel(axpy(back, 0.5 * head, side)),
                    pixel(axpy(back, -0.5 * head, side)),
                ],
                FORCE.filled(),
            ))
            .map_err(err)?;
        }
    }

    Ok(())
}

/// The scale bar of frame `i` (true length along the screen's horizontal,
/// which is level in the lab: the camera is orthographic; `size`: the text
/// size \[px\]).
fn draw_scale_bar(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    movie: &Movie,
    i: usize,
    cam: &Camera,
    size: f64,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing frame {i}: {e}");
    let (_, h) = root.dim_in_pixel();
    let (bar_m, bar_label) = &movie.scale_bar;
    let bar_px = (bar_m * cam.scale).round() as i32;
    if bar_px > 4 {
        let (bx, by) = (
            12,
            h as i32 - (size * 0.9) as i32 - 14 - (size * 0.8) as i32,
        );
        let ink = RGBColor(40, 40, 40);
        root.draw(&PathElement::new(
            vec![(bx, by), (bx + bar_px, by)],
            ink.stroke_width(3),
        ))
        .map_err(err)?;
        for x in [bx, bx + bar_px] {
            root.draw(&PathElement::new(
                vec![(x, by - 5), (x, by + 5)],
                ink.stroke_width(2),
            ))
            .map_err(err)?;
        }
        root.draw(&Text::new(
            bar_label.clone(),
            (bx + bar_px + 8, by - (size * 0.35) as i32),
            font(size * 0.7).color(&ink),
        ))
        .map_err(err)?;
    }
    Ok(())
}

/// The floor: a stage around the top with a grid of spacing R, the
/// shadow (RGB pixels of a `w` x `h` image in `buf`).
fn draw_floor(buf: &mut [u8], (w, h): (u32, u32), cam: &Camera, pose: &Pose, rr: f64) {
    let sin_el = cam.d[2];
    let px_m = 1.0 / cam.scale; // metres per pixel on the screen plane
    for py in 0..h {
        for px in 0..w {
            let q = cam.unproject(px as f64 + 0.5, py as f64 + 0.5);
            // Along -d down to Z = 0.
            let s = q[2] / sin_el;
            let fp = axpy(q, -s, cam.d);
            let dx = fp[0] - pose.centre[0];
            let dy = fp[1] - pose.centre[1];
            let rho = (dx * dx + dy * dy).sqrt() / rr;
            let stage = (1.0 - (rho - 4.5) / 1.5).clamp(0.0, 1.0);
            let mut c: V3 =
                std::array::from_fn(|k| BACKGROUND[k] + stage * (STAGE[k] - BACKGROUND[k]));
            let line = |v: f64| {
                let g = v / rr;
                let dist = (g - g.round()).abs() * rr;
                (1.0 - dist / (0.8 * px_m / sin_el.max(0.3))).clamp(0.0, 1.0)
            };
            let gl = line(fp[0]).max(line(fp[1])) * stage;
            c = std::array::from_fn(|k| c[k] + gl * (GRID[k] - c[k]));
            let shadow = 0.35 * (1.0 - (rho - 0.55) / 0.45).clamp(0.0, 1.0);
            c = c.map(|v| v * (1.0 - shadow));
            let o = 3 * (py * w + px) as usize;
            buf[o..o + 3].copy_from_slice(&to_u8(c));
        }
    }
}

/// The sphere, pixel by pixel, with an anti-aliased edge.
fn draw_sphere(buf: &mut [u8], (w, h): (u32, u32), cam: &Camera, pose: &Pose, rr: f64, sweep: f64) {
    let light = cam.light();
    let (scx, scy, _) = cam.project(pose.centre);
    shade_disc(buf, (w, h), (scx, scy), rr * cam.scale, cam, &mut |n| {
        Some(surface_colour(n, pose.to_body(n), light, cam.d, sweep))
    });
}

/// The stem's ball (§stem) of radius `r2` at O + `d2` k, pixel by pixel
/// where it is in front of the sphere (its surface points outside the
/// sphere's silhouette or nearer the camera than the sphere's front),
/// shaded as the sphere.
fn draw_stem_ball(
    buf: &mut [u8],
    (w, h): (u32, u32),
    cam: &Camera,
    pose: &Pose,
    rr: f64,
    (r2, d2): (f64, f64),
) {
    let light = cam.light();
    let sc = axpy(pose.com, d2, pose.k);
    let (bx, by, _) = cam.project(sc);
    shade_disc(buf, (w, h), (bx, by), r2 * cam.scale, cam, &mut |n| {
        if cam.hidden_by_sphere(axpy(sc, r2, n), pose.centre, rr) {
            return None;
        }
        let lam = dot(n, light).max(0.0);
        Some(std::array::from_fn(|k| STEM[k] * (0.3 + 0.7 * lam)))
    });
}

/// A ball's disc of radius `rpx` \[px\] centred at `(cx, cy)` \[px\],
/// pixel by pixel with an anti-aliased edge: `colour(n)` of the outward
/// normal `n` (lab frame) at each pixel (at the silhouette for the edge
/// pixels), blended by the pixel's coverage; `None` leaves the pixel.
fn shade_disc(
    buf: &mut [u8],
    (w, h): (u32, u32),
    (cx, cy): (f64, f64),
    rpx: f64,
    cam: &Camera,
    colour: &mut dyn FnMut(V3) -> Option<V3>,
) {
    let x0 = (cx - rpx - 2.0).floor().max(0.0) as u32;
    let x1 = ((cx + rpx + 2.0).ceil().max(0.0) as u32).min(w);
    let y0 = (cy - rpx - 2.0).floor().max(0.0) as u32;
    let y1 = ((cy + rpx + 2.0).ceil().max(0.0) as u32).min(h);
    for py in y0..y1 {
        for px in x0..x1 {
            let ex = (px as f64 + 0.5 - cx) / rpx;
            let ey = -(py as f64 + 0.5 - cy) / rpx;
            let r2 = ex * ex + ey * ey;
            let alpha = (rpx * (1.0 - r2.sqrt()) + 0.5).clamp(0.0, 1.0);
            if alpha <= 0.0 {
                continue;
            }
            let (ex, ey) = if r2 > 1.0 {
                let r = r2.sqrt();
                (ex / r, ey / r)
            } else {
                (ex, ey)
            };
            let ez = (1.0 - ex * ex - ey * ey).max(0.0).sqrt();
            let n: V3 = std::array::from_fn(|k| ex * cam.r[k] + ey * cam.u[k] + ez * cam.d[k]);
            let Some(c) = colour(n) else {
                continue;
            };
            let o = 3 * (py * w + px) as usize;
            for k in 0..3 {
                let old = buf[o + k] as f64 / 255.0;
                buf[o + k] = ((old + alpha * (c[k] - old)).clamp(0.0, 1.0) * 255.0 + 0.5) as u8;
            }
        }
    }
}

/// The map of the whole trace in a corner of frame `i` when the trace is
/// longer than the view (`size`: the text size [px]).
fn draw_map(
    root: &DrawingArea<BitMapBackend, plotters::coord::Shift>,
    movie: &Movie,
    i: usize,
    size: f64,
) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<_>| anyhow!("drawing frame {i}: {e}");
    let (w, h) = root.dim_in_pixel();
    let f = &movie.frames[i];
    let rr = movie.radius;
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in &movie.trace {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k + 1]);
            hi[k] = hi[k].max(p[k + 1]);
        }
    }
    let extent = (hi[0] - lo[0]).max(hi[1] - lo[1]);
    if extent > 3.0 * rr {
        let side = (0.3 * w.min(h) as f64) as i32;
        let (mx, my) = (w as i32 - side - 8, h as i32 - side - 8);
        root.draw(&Rectangle::new(
            [(mx, my), (mx + side, my + side)],
            RGBColor(255, 255, 255).mix(0.85).filled(),
        ))
        .map_err(err)?;
        root.draw(&Rectangle::new(
            [(mx, my), (mx + side, my + side)],
            RGBColor(150, 150, 150),
        ))
        .map_err(err)?;
        let pad = 6.0;
        let sc = (side as f64 - 2.0 * pad) / extent;
        let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        let map = |x: f64, y: f64| {
            (
                mx + side / 2 + ((x - mid[0]) * sc) as i32,
                my + side / 2 - ((y - mid[1]) * sc) as i32,
            )
        };
        let all: Vec<(i32, i32)> = movie.trace.iter().map(|p| map(p[1], p[2])).collect();
        root.draw(&PathElement::new(all, RGBColor(190, 190, 190)))
            .map_err(err)?;
        let mut done: Vec<(i32, i32)> = movie
            .trace
            .iter()
            .take_while(|p| p[0] <= f.t)
            .map(|p| map(p[1], p[2]))
            .collect();
        let here = map(f.contact[0], f.contact[1]);
        done.push(here);
        if done.len() > 1 {
            root.draw(&PathElement::new(done, TRACE)).map_err(err)?;
        }
        root.draw(&Circle::new(here, 3, RGBColor(200, 20, 30).filled()))
            .map_err(err)?;
        root.draw(&Text::new(
            "trace, top view",
            (mx + 4, my + 3),
            font(size * 0.55).color(&RGBColor(90, 90, 90)),
        ))
        .map_err(err)?;
    }
    Ok(())
}

/// The parts of the polyline `pts` \[px\] inside the `w × h` image (with a
/// margin of a few pixels), each a run of integer points: segments are
/// clipped (Liang–Barsky), not clamped onto the border.
pub fn clipped_runs(pts: &[(f64, f64)], w: u32, h: u32) -> Vec<Vec<(i32, i32)>> {
    let (lo, hx, hy) = (-4.0, w as f64 + 4.0, h as f64 + 4.0);
    let mut runs: Vec<Vec<(i32, i32)>> = Vec::new();
    let mut open = false;
    let ip = |p: (f64, f64)| (p.0.round() as i32, p.1.round() as i32);
    for seg in pts.windows(2) {
        let (a, b) = (seg[0], seg[1]);
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let (mut t0, mut t1) = (0.0f64, 1.0f64);
        let mut inside = a.0.is_finite() && a.1.is_finite() && b.0.is_finite() && b.1.is_finite();
        for (p, q) in [
            (-dx, a.0 - lo),
            (dx, hx - a.0),
            (-dy, a.1 - lo),
            (dy, hy - a.1),
        ] {
            if !inside {
                break;
            }
            if p == 0.0 {
                inside = q >= 0.0;
            } else {
                let r = q / p;
                if p < 0.0 {
                    t0 = t0.max(r);
                } else {
                    t1 = t1.min(r);
                }
                inside = t0 <= t1;
            }
        }
        if !inside {
            open = false;
            continue;
        }
        let pa = ip((a.0 + t0 * dx, a.1 + t0 * dy));
        let pb = ip((a.0 + t1 * dx, a.1 + t1 * dy));
        if !open || t0 > 0.0 {
            runs.push(vec![pa]);
        }
        if let Some(run) = runs.last_mut()
            && run.last() != Some(&pb)
        {
            run.push(pb);
        }
        open = t1 >= 1.0;
    }
    runs.retain(|r| r.len() > 1);
    runs
}

/// Frame indices the palette is learnt from.
fn palette_frames(n: usize) -> Vec<usize> {
    let mut v: Vec<usize> = (0..6).map(|k| k * (n - 1) / 5).collect();
    v.dedup();
    v
}

/// Write `movie` as an animated GIF to `path` (looping).
pub fn write_gif(path: &Path, movie: &Movie, settings: &Settings) -> Result<GifStats> {
    let (w, h) = (settings.width as usize, settings.height as usize);
    let n = movie.frames.len();
    let mut rgb = vec![0u8; 3 * w * h];

    // The palette: NeuQuant over a few frames, then a 6-bit-per-channel
    // lookup table from colour to palette index.
    let mut sample: Vec<u8> = Vec::new();
    for i in palette_frames(n) {
        render_frame(movie, i, settings, &mut rgb)?;
        for px in rgb.chunks_exact(3).step_by(3) {
            sample.extend_from_slice(&[px[0], px[1], px[2], 255]);
        }
    }
    let nq = color_quant::NeuQuant::new(10, 256, &sample);
    let palette = nq.color_map_rgb();
    let mut lut = vec![0u8; 1 << 18];
    for (code, slot) in lut.iter_mut().enumerate() {
        let r = ((code >> 12) & 63) as u8;
        let g = ((code >> 6) & 63) as u8;
        let b = (code & 63) as u8;
        let c = [r << 2 | r >> 4, g << 2 | g >> 4, b << 2 | b >> 4, 255];
        *slot = nq.index_of(&c) as u8;
    }
    let index_of = |p: &[u8]| {
        lut[((p[0] as usize >> 2) << 12) | ((p[1] as usize >> 2) << 6) | (p[2] as usize >> 2)]
    };

    let file = File::create(path).with_context(|| format!("writing {}", path.display()))?;
    let mut enc = gif::Encoder::new(BufWriter::new(file), w as u16, h as u16, &palette)
        .with_context(|| format!("writing {}", path.display()))?;
    enc.set_repeat(gif::Repeat::Infinite)
        .with_context(|| format!("writing {}", path.display()))?;
    let delay = (100.0 / settings.fps as f64).round() as u16;
    let mut prev: Vec<u8> = Vec::new();
    let mut idx = vec![0u8; w * h];
    for i in 0..n {
        render_frame(movie, i, settings, &mut rgb)?;
        for (d, p) in idx.iter_mut().zip(rgb.chunks_exact(3)) {
            *d = index_of(p);
        }
        // The rectangle that changed (the whole frame first).
        let (mut x0, mut y0, mut x1, mut y1) = (0, 0, w, h);
        if !prev.is_empty() {
            (x0, y0, x1, y1) = (w, h, 0, 0);
            for y in 0..h {
                let row = &idx[y * w..(y + 1) * w];
                let old = &prev[y * w..(y + 1) * w];
                if row == old {
                    continue;
                }
                let first = row.iter().zip(old).position(|(a, b)| a != b).unwrap_or(0);
                let last = w - row
                    .iter()
                    .zip(old)
                    .rev()
                    .position(|(a, b)| a != b)
                    .unwrap_or(0);
                x0 = x0.min(first);
                x1 = x1.max(last);
                y0 = y0.min(y);
                y1 = y1.max(y + 1);
            }
            if x1 <= x0 {
                (x0, y0, x1, y1) = (0, 0, 1, 1);
            }
        }
        let mut part = Vec::with_capacity((x1 - x0) * (y1 - y0));
        for y in y0..y1 {
            part.extend_from_slice(&idx[y * w + x0..y * w + x1]);
        }
        let frame = gif::Frame {
            delay,
            dispose: gif::DisposalMethod::Keep,
            left: x0 as u16,
            top: y0 as u16,
            width: (x1 - x0) as u16,
            height: (y1 - y0) as u16,
            buffer: std::borrow::Cow::Owned(part),
            ..gif::Frame::default()
        };
        enc.write_frame(&frame)
            .with_context(|| format!("writing {}", path.display()))?;
        std::mem::swap(&mut prev, &mut idx);
        if idx.len() != w * h {
            idx = vec![0u8; w * h];
        }
    }
    let writer = enc
        .into_inner()
        .with_context(|| format!("writing {}", path.display()))?;
    writer
        .into_inner()
        .map_err(|e| e.into_error())
        .with_context(|| format!("writing {}", path.display()))?;
    let bytes = std::fs::metadata(path)
        .with_context(|| format!("writing {}", path.display()))?
        .len();
    Ok(GifStats { frames: n, bytes })
}

#[cfg(test)]
mod tests {
    use super::*;
    /// The applied force is an orange arrow on the floor from the contact
    /// point: a pixel 1.0 R along it (screen-horizontal, outside the
    /// sphere's silhouette) is orange with the force and not without.
    #[test]
    fn the_force_arrow_is_drawn() {
        let (r, a) = (0.015, 0.0015);
        let pose = Pose::new([0.0, 0.0, r - a], [1.0, 0.0, 0.0, 0.0], a);
        let cam = Camera::standard(320, 240, r, pose.centre);
        let dir = [cam.r[0], cam.r[1]];
        let n = dir[0].hypot(dir[1]);
        let frame = |f: f64| super::super::Frame {
            t: 0.0,
            theta: 0.0,
            spin: 0.0,
            com: [0.0, 0.0, r - a],
            q: [1.0, 0.0, 0.0, 0.0],
            contact: [0.0, 0.0],
            force: [f * dir[0] / n, f * dir[1] / n],
        };
        let movie = |f: f64| Movie {
            title: String::new(),
            radius: r,
            offset: a,
            stem: None,
            frames: vec![frame(f)],
            frame_dt: 0.05,
            fps: 20,
            trace: vec![[0.0, 0.0, 0.0]],
            theta_curve: vec![[0.0, 0.0]],
            source: String::new(),
            force_max: 1.0,
            scale_bar: super::super::scale_bar(r),
        };
        let settings = Settings {
            fps: 20,
            frames: 1,
            width: 320,
            height: 240,
        };
        let (x, y, _) = cam.project([r * dir[0] / n, r * dir[1] / n, 0.0]);
        let at = |f: f64| {
            let mut buf = vec![0u8; 320 * 240 * 3];
            render_frame(&movie(f), 0, &settings, &mut buf).unwrap();
            let o = 3 * (y.round() as usize * 320 + x.round() as usize);
            [buf[o], buf[o + 1], buf[o + 2]]
        };
        let with = at(1.0);
        let without = at(0.0);
        assert!(with[0] > 200 && with[2] < 60, "arrow pixel {with:?}");
        assert!(
            without[0].abs_diff(without[2]) < 40,
            "no-force pixel {without:?}"
        );
    }

    /// The stem's ball (§stem) is drawn: with the top upright (k = Z), the
    /// toy's stem (r2 = 2.5 mm at d2 = 16 mm, R = 15 mm, a = 1.5 mm) sticks
    /// 2 mm out of the sphere's top; the pixel of the ball's front surface
    /// point with screen offsets (0.5 r2 right, 0.7 r2 up) from its centre
    /// (2.1 mm higher than the ball's centre, 16.6 mm from the sphere's
    /// centre: outside the sphere; 4 px right of the axis line) is the
    /// stem's brown, shaded (red > blue by far); without the stem it is the
    /// background's grey.
    #[test]
    fn the_stem_ball_is_drawn() {
        let (r, a, r2, d2) = (0.015, 0.0015, 0.0025, 0.016);
        let frame = super::super::Frame {
            t: 0.0,
            theta: 0.0,
            spin: 0.0,
            com: [0.0, 0.0, r - a],
            q: [1.0, 0.0, 0.0, 0.0],
            contact: [0.0, 0.0],
            force: [0.0, 0.0],
        };
        let movie = |stem| Movie {
            title: String::new(),
            radius: r,
            offset: a,
            stem,
            frames: vec![frame],
            frame_dt: 0.05,
            fps: 20,
            trace: vec![[0.0, 0.0, 0.0]],
            theta_curve: vec![[0.0, 0.0]],
            source: String::new(),
            force_max: 0.0,
            scale_bar: super::super::scale_bar(r),
        };
        let settings = Settings {
            fps: 20,
            frames: 1,
            width: 320,
            height: 240,
        };
        let pose = Pose::new(frame.com, frame.q, a);
        let cam = Camera::standard(320, 240, r, pose.centre);
        let sc = [0.0, 0.0, r - a + d2];
        let p = axpy(axpy(sc, 0.5 * r2, cam.r), 0.7 * r2, cam.u);
        let (x, y, _) = cam.project(p);
        let at = |stem| {
            let mut buf = vec![0u8; 320 * 240 * 3];
            render_frame(&movie(stem), 0, &settings, &mut buf).unwrap();
            let o = 3 * (y as usize * 320 + x as usize);
            [buf[o], buf[o + 1], buf[o + 2]]
        };
        let with = at(Some((r2, d2)));
        let without = at(None);
        assert!(with[0] as i32 - with[2] as i32 > 40, "stem pixel {with:?}");
        assert!(
            without[0].abs_diff(without[2]) < 30,
            "no-stem pixel {without:?}"
        );
    }

    #[test]
    fn clock_units() {
        assert_eq!(time_unit(10.0).1, "s");
        assert_eq!(time_unit(1e-4).1, "µs");
        assert_eq!(time_unit(2e-9).1, "ns");
        assert_eq!(time_decimals(0.05, 1.0), 2);
        assert_eq!(time_decimals(5e-7, 1e-6), 1);
        assert_eq!(palette_frames(200), vec![0, 39, 79, 119, 159, 199]);
        assert_eq!(palette_frames(2), vec![0, 1]);
    }

    #[test]
    fn clipping_cuts_segments_at_the_border() {
        let runs = clipped_runs(
            &[(10.0, 10.0), (1000.0, 10.0), (1000.0, 50.0), (20.0, 50.0)],
            100,
            80,
        );
        assert_eq!(
            runs,
            vec![vec![(10, 10), (104, 10)], vec![(104, 50), (20, 50)]]
        );
        assert!(clipped_runs(&[(-50.0, -50.0), (-10.0, 500.0)], 100, 80).is_empty());
        assert!(clipped_runs(&[(f64::NAN, 1.0), (2.0, 3.0)], 100, 80).is_empty());
    }
}
