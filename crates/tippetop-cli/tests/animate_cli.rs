//! `tippetop animate DIR`: the GIF (decoded and checked frame by frame), the
//! viewer (self-contained, with the data; loaded in headless Chromium when
//! it is installed) and bad input.
//!
//! The browser test, [`viewer_loads_in_headless_chromium`], runs when
//! `chromium` is on PATH and otherwise passes with a "skipped" message on
//! stderr (set `TIPPETOP_REQUIRE_BROWSER=1` to make a missing browser a
//! failure, as `.ci/run` does once it has installed Chromium). To run it by
//! hand on Debian:
//!
//! ```text
//! apt-get update && apt-get install -y chromium
//! cargo test -p tippetop-cli --test animate_cli viewer_loads_in_headless_chromium -- --nocapture
//! ```

use std::collections::{BTreeSet, HashSet};
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command as Std;

use assert_cmd::Command;

fn tippetop() -> Command {
    Command::cargo_bin("tippetop").unwrap()
}

/// Run `tippetop run ARGS --no-plot --out DIR` quietly.
fn run_into(dir: &Path, args: &[&str]) {
    let out = tippetop()
        .args(["run", "-q", "--no-plot", "--out"])
        .arg(dir)
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The classical top with regularized friction: it inverts in a few
/// seconds, spinning at ~100 rad/s (rows too coarse: the run is replayed).
fn classical(dir: &Path, t_end: &str) {
    run_into(
        dir,
        &[
            "--preset",
            "classical",
            "--set",
            "surface.friction_law=regularized",
            "--set",
            "surface.friction_eps=1e-2",
            "--set",
            &format!("solver.t_end={t_end}"),
        ],
    );
}

/// The GIF's frames, composited (RGBA, `w × h`), with the file's size.
struct Decoded {
    width: usize,
    height: usize,
    frames: Vec<Vec<u8>>,
    delays: Vec<u16>,
}

fn decode_gif(path: &Path) -> Decoded {
    let mut opts = gif::DecodeOptions::new();
    opts.set_color_output(gif::ColorOutput::RGBA);
    let mut dec = opts.read_info(fs::File::open(path).unwrap()).unwrap();
    let (w, h) = (dec.width() as usize, dec.height() as usize);
    let mut canvas = vec![0u8; 4 * w * h];
    let mut frames = Vec::new();
    let mut delays = Vec::new();
    while let Some(f) = dec.read_next_frame().unwrap() {
        let (fl, ft, fw, fh) = (
            f.left as usize,
            f.top as usize,
            f.width as usize,
            f.height as usize,
        );
        assert!(fl + fw <= w && ft + fh <= h, "frame outside the canvas");
        for y in 0..fh {
            for x in 0..fw {
                let s = 4 * (y * fw + x);
                if f.buffer[s + 3] == 0 {
                    continue;
                }
                let d = 4 * ((ft + y) * w + fl + x);
                canvas[d..d + 4].copy_from_slice(&f.buffer[s..s + 4]);
            }
        }
        frames.push(canvas.clone());
        delays.push(f.delay);
    }
    Decoded {
        width: w,
        height: h,
        frames,
        delays,
    }
}

/// Check the frames: the count, none blank, each differs from the previous.
fn check_frames(d: &Decoded, count: usize, size: (usize, usize)) {
    assert_eq!((d.width, d.height), size);
    assert_eq!(d.frames.len(), count);
    for (i, f) in d.frames.iter().enumerate() {
        let colours: HashSet<&[u8]> = f.chunks_exact(4).collect();
        assert!(
            colours.len() > 20,
            "frame {i} is (nearly) blank: {} colours",
            colours.len()
        );
        if i > 0 {
            let changed = f
                .chunks_exact(4)
                .zip(d.frames[i - 1].chunks_exact(4))
                .filter(|(a, b)| a != b)
                .count();
            assert!(changed > 0, "frame {i} is the same as frame {}", i - 1);
        }
    }
}

fn files(dir: &Path) -> BTreeSet<String> {
    fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect()
}

/// The `"t":[...]` array of the viewer's data: the frame times.
fn viewer_times(html: &str) -> Vec<f64> {
    let start = html.find("\"t\":[").expect("frame times in the viewer") + 5;
    let end = start + html[start..].find(']').unwrap();
    html[start..end]
        .split(',')
        .map(|x| x.parse::<f64>().unwrap())
        .collect()
}

#[test]
fn classical_run_replayed_small_gif_and_viewer() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("classical");
    classical(&dir, "3");
    let before = files(&dir);
    let out = tippetop()
        .arg("animate")
        .arg(&dir)
        .args(["--fps", "10", "--duration", "2.5", "--size", "160x120"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains("frames: 25 (replayed scenario.toml"),
        "{stdout}"
    );
    assert!(
        stdout.contains("animation.gif (25 frames, 160x120, 10 fps"),
        "{stdout}"
    );

    // The run's files are kept; the animation's are added (and listed in
    // the manifest, so that a later run into DIR removes them).
    let after = files(&dir);
    assert!(after.is_superset(&before));
    assert!(after.contains("animation.gif") && after.contains("viewer.html"));
    let manifest = fs::read_to_string(dir.join(".tippetop-manifest")).unwrap();
    for name in [
        "animation.gif",
        "viewer.html",
        "trajectory.csv",
        "summary.json",
    ] {
        assert!(
            manifest.lines().any(|l| l.split('\t').next() == Some(name)),
            "{name} not in {manifest}"
        );
    }

    let gif_path = dir.join("animation.gif");
    let size = fs::metadata(&gif_path).unwrap().len();
    assert!(size < 500_000, "{size} bytes");
    let d = decode_gif(&gif_path);
    check_frames(&d, 25, (160, 120));
    assert!(d.delays.iter().all(|&x| x == 10));

    let html = fs::read_to_string(dir.join("viewer.html")).unwrap();
    assert!(!html.contains("http://") && !html.contains("https://"));
    assert!(!html.contains("<script src") && !html.contains("<link"));
    let times = viewer_times(&html);
    assert_eq!(times.len(), 25);
    assert_eq!(times[0], 0.0);
    assert_eq!(times[24], 3.0);
    assert!(html.contains("\"theta\":[0.1,"), "the first frame's theta");

    // A later run into DIR removes the animation of the run it replaces.
    classical(&dir, "1");
    let again = files(&dir);
    assert!(!again.contains("animation.gif") && !again.contains("viewer.html"));
}

#[test]
fn nano_run_interpolated_between_rows() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("nano");
    run_into(&dir, &["--preset", "nano", "--set", "solver.t_end=2e-5"]);
    let out = tippetop()
        .arg("animate")
        .arg(&dir)
        .args(["--fps", "8", "--duration", "2", "--size", "96x80"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(
        stdout.contains("frames: 16 (interpolated between the 1001 rows"),
        "{stdout}"
    );
    let d = decode_gif(&dir.join("animation.gif"));
    check_frames(&d, 16, (96, 80));
    let html = fs::read_to_string(dir.join("viewer.html")).unwrap();
    let times = viewer_times(&html);
    assert_eq!(times.len(), 16);
    assert_eq!(*times.last().unwrap(), 2e-5);
    // --quiet prints nothing.
    let out = tippetop()
        .arg("animate")
        .arg(&dir)
        .args(["--quiet", "--duration", "0.2"])
        .output()
        .unwrap();
    assert!(out.status.success() && out.stdout.is_empty() && out.stderr.is_empty());
}

/// The defaults: 200 frames at 480x360, at most 10 MB (the classical top
/// inverting over 10 s: the trace leaves the view, so most frames change
/// everywhere).
#[test]
fn defaults_stay_under_ten_megabytes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("c");
    classical(&dir, "10");
    tippetop()
        .args(["animate", "-q"])
        .arg(&dir)
        .assert()
        .success();
    let size = fs::metadata(dir.join("animation.gif")).unwrap().len();
    assert!(size <= 10_000_000, "{size} bytes");
    let d = decode_gif(&dir.join("animation.gif"));
    check_frames(&d, 200, (480, 360));
}

#[test]
fn bad_input_is_one_line_exit_2_nothing_written() {
    let tmp = tempfile::tempdir().unwrap();
    let empty = tmp.path().join("empty");
    fs::create_dir(&empty).unwrap();
    let half = tmp.path().join("half");
    fs::create_dir(&half).unwrap();
    fs::write(half.join("scenario.toml"), "[top]\nradius = 0.01\n").unwrap();
    let good = tmp.path().join("good");
    run_into(&good, &["--preset", "nano", "--set", "solver.t_end=1e-6"]);
    let broken = tmp.path().join("broken");
    fs::create_dir(&broken).unwrap();
    fs::copy(good.join("scenario.toml"), broken.join("scenario.toml")).unwrap();
    fs::write(broken.join("trajectory.csv"), "t,theta\n0,0.1\n").unwrap();
    let missing = tmp.path().join("missing");

    let cases: Vec<(PathBuf, Vec<&str>, &str)> = vec![
        (missing.clone(), vec![], "missing: no such directory"),
        (empty.clone(), vec![], "scenario.toml is missing"),
        (half.clone(), vec![], "trajectory.csv is missing"),
        (broken.clone(), vec![], "no column omega"),
        (good.clone(), vec!["--fps", "0"], "--fps: 0 is not allowed"),
        (good.clone(), vec!["--fps", "abc"], "--fps: abc"),
        (
            good.clone(),
            vec!["--fps", "51"],
            "(a whole number of frames per second, 1 to 50)",
        ),
        (
            good.clone(),
            vec!["--duration", "0"],
            "--duration: 0 is not allowed",
        ),
        (good.clone(), vec!["--duration", "-3"], "--duration: -3"),
        (good.clone(), vec!["--duration", "inf"], "--duration: inf"),
        (
            good.clone(),
            vec!["--fps", "50", "--duration", "60"],
            "--duration: 60 s at 50 fps is 3000 frames",
        ),
        (
            good.clone(),
            vec!["--size", "10x10"],
            "--size: 10x10 is not allowed",
        ),
        (good.clone(), vec!["--size", "480"], "--size: 480"),
        (good.clone(), vec!["--size", "480x360x2"], "--size"),
    ];
    for (dir, args, expected) in cases {
        let before = dir.exists().then(|| files(&dir));
        let out = tippetop()
            .arg("animate")
            .arg(&dir)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(out.stdout.is_empty());
        assert_eq!(dir.exists().then(|| files(&dir)), before, "{args:?}");
    }
    // Issue 26: a link planted where the lock should be is bad input too
    // (exit 2, was 1), and its target is neither read nor written.
    let victim = tmp.path().join("victim");
    fs::write(&victim, "keep").unwrap();
    std::os::unix::fs::symlink(&victim, good.join(".tippetop.lock")).unwrap();
    let before = files(&good);
    let out = tippetop().arg("animate").arg(&good).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains(".tippetop.lock: is a symbolic link"), "{err}");
    assert_eq!(fs::read_to_string(&victim).unwrap(), "keep");
    assert_eq!(files(&good), before);
    // The directory errors name the directory.
    let out = tippetop().arg("animate").arg(&empty).output().unwrap();
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(
        err.starts_with(&format!("error: {}: ", empty.display())),
        "{err}"
    );
}

/// `chromium` on PATH, or None (then the browser test skips, unless
/// `TIPPETOP_REQUIRE_BROWSER=1`).
fn chromium() -> Option<PathBuf> {
    let path = std::env::var_os("PATH")?;
    for dir in std::env::split_paths(&path) {
        for name in ["chromium", "chromium-browser"] {
            let p = dir.join(name);
            if p.is_file() {
                return Some(p);
            }
        }
    }
    None
}

/// The viewer in a real browser: headless Chromium loads viewer.html from
/// the file system, runs its script with no console message and no error
/// (the page sets `data-status="ok"` on `<body>` once it has drawn, an
/// `error` handler sets `"error"`), and draws a frame that is not blank.
/// Skips (passing, with a message) when Chromium is not installed; see the
/// module docs for the command.
#[test]
fn viewer_loads_in_headless_chromium() {
    let Some(browser) = chromium() else {
        if std::env::var("TIPPETOP_REQUIRE_BROWSER").as_deref() == Ok("1") {
            panic!("chromium is not on PATH and TIPPETOP_REQUIRE_BROWSER=1");
        }
        eprintln!(
            "skipped: chromium is not on PATH (apt-get install -y chromium, then cargo test -p tippetop-cli --test animate_cli viewer_loads_in_headless_chromium)"
        );
        return;
    };
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().join("run");
    classical(&dir, "4");
    tippetop()
        .args([
            "animate",
            "-q",
            "--fps",
            "10",
            "--duration",
            "3",
            "--size",
            "400x300",
        ])
        .arg(&dir)
        .assert()
        .success();
    let page = format!("file://{}", dir.join("viewer.html").display());
    let profile = tmp.path().join("profile");
    let base = |extra: &[&str]| {
        let mut c = Std::new(&browser);
        c.args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-first-run",
            "--hide-scrollbars",
            "--enable-logging=stderr",
            "--v=0",
            "--window-size=1000,520",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .args(extra)
        .arg(&page);
        c.output().unwrap()
    };

    // 1. The DOM after a second of (virtual) play: the script ran to the
    //    end, no error, no console message.
    let out = base(&["--virtual-time-budget=1000", "--dump-dom"]);
    let dom = String::from_utf8_lossy(&out.stdout);
    let log = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{log}");
    assert!(
        dom.contains("data-status=\"ok\""),
        "no ok status: {dom:.2000}\n{log}"
    );
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(console.is_empty(), "console messages: {console:?}");
    assert!(!log.contains("Uncaught"), "{log}");

    // 2. A screenshot: not blank (many colours, much of it not background).
    let shot = tmp.path().join("shot.png");
    let out = base(&[&format!("--screenshot={}", shot.display())]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let decoder = png::Decoder::new(fs::File::open(&shot).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let bpp = info.color_type.samples();
    let px: Vec<&[u8]> = buf[..info.buffer_size()].chunks_exact(bpp).collect();
    let colours: HashSet<&[u8]> = px.iter().copied().collect();
    let mut counts = std::collections::HashMap::new();
    for p in &px {
        *counts.entry(*p).or_insert(0usize) += 1;
    }
    let background = counts.values().max().copied().unwrap_or(0);
    let drawn = px.len() - background;
    assert!(colours.len() > 200, "{} colours: blank?", colours.len());
    assert!(
        drawn * 10 > px.len(),
        "only {drawn} of {} pixels drawn",
        px.len()
    );
}
