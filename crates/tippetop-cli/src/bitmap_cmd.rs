//! `tippetop bit FILE --vary KEY=FROM:TO:N ...`: design maps of a memory
//! bit ([`tippetop::analysis::bitmap`]), streamed into `bitmap.csv` in grid
//! order like a sweep's rows ([`crate::common::grid::stream_rows`]: shards,
//! `--resume`, `tippetop merge`), with heat maps of the write probability
//! and the write switching time.

use std::io::BufRead;
use std::path::Path;
use std::process::ExitCode;

use anyhow::{Context, Result};
use tippetop::analysis::bitmap::{self, BitMap};
use tippetop::analysis::sweep::{Axis, Shard, ShardInfo, Sweep};

use crate::bit_args::BitArgs;
use crate::common::args::MergeArgs;
use crate::common::grid::{GridInput, Streamed, read_shard_of, stream_rows, write_info};
use crate::output::{OutDir, write_bytes_atomic};
use crate::partial::checksum_text;
use crate::scenario_load::input_error;

/// The CSV a map streams its rows into while it runs.
pub const PARTIAL_CSV: &str = "bitmap.csv.partial";

/// The `shard.json` of the running map (at the end `shard.json` is
/// written with the checksum of `bitmap.csv`).
pub const PARTIAL_INFO: &str = "shard.json.partial";

/// Most grid values per axis drawn in a heat map: a longer axis is drawn
/// at every `ceil(n / MAX_PLOT_SIDE)`-th value (the CSV has every row).
pub const MAX_PLOT_SIDE: usize = 250;

/// Run a map (`args.vary` not empty). Bad input: one line on stderr and
/// exit code 2 (returned as `Ok`), nothing written; `Err` for I/O failures.
pub fn run(args: &BitArgs, quiet: bool) -> Result<ExitCode> {
    let GridInput {
        toml_text,
        axes,
        shard,
        threads,
    } = match GridInput::parse(
        args.source.scenario.as_deref(),
        &args.vary,
        args.shard.as_deref(),
        args.cores.threads,
    ) {
        Ok(g) => g,
        Err(code) => return Ok(code),
    };
    let map = BitMap {
        grid: Sweep {
            preset: args.source.preset.clone(),
            toml_text,
            sets: args.source.sets.clone(),
            axes,
        },
        runs: args.runs.unwrap_or(bitmap::DEFAULT_RUNS),
    };
    if let Err(e) = map.validate() {
        return Ok(input_error(e));
    }
    let threads = match map.threads_within_memory(threads) {
        Ok(t) => crate::scenario_load::note_threads(quiet, threads, t),
        Err(e) => return Ok(input_error(e)),
    };
    let info = match map.shard_info(shard) {
        Ok(i) => i,
        Err(e) => return Ok(input_error(e)),
    };
    let mut info_json = serde_json::to_string_pretty(&info)?;
    info_json.push('\n');

    let mut out = OutDir::open(&args.out)?;
    let start = std::time::Instant::now();
    let spec = Streamed {
        partial_csv: PARTIAL_CSV,
        partial_info: PARTIAL_INFO,
        header: bitmap::csv_header(&map.grid.axes),
        what: "map",
        unit: "point",
        resume: args.resume,
        quiet,
    };
    let done = match stream_rows(
        &mut out,
        &spec,
        &info,
        &info_json,
        &|text| map.complete_prefix(info.first_index, text),
        &mut |todo, sink| {
            map.run_streaming(todo, Some(threads), &mut |row| {
                sink(bitmap::csv_row(&row), row.status != "ok")
            })
        },
    )? {
        Ok(d) => d,
        Err(code) => {
            out.abandon();
            return Ok(code);
        }
    };
    let failed = done.failed;
    let csv_path = args.out.join(PARTIAL_CSV);
    out.adopt(PARTIAL_CSV, bitmap::CSV_NAME);
    write_info(
        out.stage(),
        &info,
        &[(bitmap::CSV_NAME, checksum_text(done.hash))],
    )?;
    if shard == Shard::ALL {
        write_plots(out.stage(), &csv_path, &info.axes)?;
    }
    out.commit(&["shard.json"])?;
    if !quiet {
        let n = info.end_index - info.first_index;
        let what = if shard == Shard::ALL {
            format!("{n} points")
        } else {
            format!(
                "shard {}/{}: points {}..{} of {}",
                shard.k, shard.n, info.first_index, info.end_index, info.total_cases
            )
        };
        println!(
            "{what} ({} ok, {failed} invalid or with failed runs) in {} -> {}",
            n - failed,
            crate::output::fmt_duration(start.elapsed().as_secs_f64()),
            args.out.join(bitmap::CSV_NAME).display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// Whether `dir` holds a map's output (`bitmap.csv`), for `tippetop merge`.
pub fn is_bitmap_dir(dir: &Path) -> bool {
    dir.join(bitmap::CSV_NAME).is_file()
}

/// `tippetop merge` of map shards: `bitmap.csv` byte for byte an
/// unsharded run's, `shard.json`, and the plots.
pub fn merge(args: &MergeArgs, quiet: bool) -> Result<ExitCode> {
    let mut shards: Vec<(ShardInfo, String)> = Vec::new();
    for dir in &args.dirs {
        let _reading = crate::output::read_lock(dir)?;
        match read_shard(dir) {
            Ok(s) => shards.push(s),
            Err(msg) => return Ok(input_error(msg)),
        }
    }
    let csv = match bitmap::merge(&shards) {
        Ok(c) => c,
        Err(e) => return Ok(input_error(e)),
    };
    drop(shards.drain(1..));
    let first = &shards[0].0;
    let info = ShardInfo {
        fingerprint: first.fingerprint.clone(),
        k: 1,
        n: 1,
        total_cases: first.total_cases,
        first_index: 0,
        end_index: first.total_cases,
        axes: first.axes.clone(),
        checksums: Default::default(),
    };
    let out = OutDir::open(&args.out)?;
    let csv_path = out.stage().join(bitmap::CSV_NAME);
    write_bytes_atomic(&csv_path, csv.as_bytes())?;
    write_info(
        out.stage(),
        &info,
        &[(bitmap::CSV_NAME, crate::partial::checksum(csv.as_bytes()))],
    )?;
    drop(csv);
    write_plots(out.stage(), &csv_path, &info.axes)?;
    out.commit(&["shard.json"])?;
    if !quiet {
        println!(
            "merged {} shards: {} points -> {}",
            args.dirs.len(),
            info.total_cases,
            args.out.join(bitmap::CSV_NAME).display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn read_shard(dir: &Path) -> std::result::Result<(ShardInfo, String), String> {
    read_shard_of(
        dir,
        bitmap::CSV_NAME,
        "a directory written by tippetop bit --vary, with shard.json and bitmap.csv",
    )
}

/// The columns the plots need, read from `bitmap.csv` line by line.
struct PlotData {
    /// Per plotted axis, the grid indices drawn.
    picks: Vec<Vec<usize>>,
    /// Write probability and median write time at `[j][i]` (`ys[j]`,
    /// `xs[i]`); one row for a single axis.
    prob: Vec<Vec<f64>>,
    time: Vec<Vec<f64>>,
    ci: [Vec<Vec<f64>>; 2],
}

/// Read what the plots draw: the first two axes (one for a 1-key map),
/// the other keys at their first value, at most [`MAX_PLOT_SIDE`] values
/// per axis (every `s`-th).
fn plot_data(csv: &Path, axes: &[Axis]) -> Result<PlotData> {
    let stride = |n: usize| n.div_ceil(MAX_PLOT_SIDE).max(1);
    let shown = axes.len().min(2);
    let picks: Vec<Vec<usize>> = axes[..shown]
        .iter()
        .map(|a| (0..a.n).step_by(stride(a.n)).collect())
        .collect();
    let rest: usize = axes[shown..].iter().map(|a| a.n).product();
    let (nx, ny) = (picks[0].len(), picks.get(1).map_or(1, Vec::len));
    let blank = || vec![vec![f64::NAN; nx]; ny];
    let mut d = PlotData {
        prob: blank(),
        time: blank(),
        ci: [blank(), blank()],
        picks,
    };
    let f = crate::output::open_plain(csv, std::fs::OpenOptions::new().read(true))?;
    let mut lines = std::io::BufReader::new(f).lines();
    let header = lines.next().transpose()?.unwrap_or_default();
    let col = |name: &str| {
        bitmap::column_index(&header, name)
            .with_context(|| format!("{}: no column {name}", csv.display()))
    };
    let cols = [
        col("write_probability")?,
        col("write_time_median")?,
        col("write_ci_lo")?,
        col("write_ci_hi")?,
    ];
    let n1 = axes.get(1).filter(|_| shown == 2).map_or(1, |a| a.n);
    let pos = |picks: &[usize], i: usize| picks.binary_search(&i).ok();
    for (index, line) in lines.enumerate() {
        let line = line.with_context(|| format!("reading {}", csv.display()))?;
        if index % rest != 0 {
            continue;
        }
        let g = index / rest;
        let (i0, i1) = (g / n1, g % n1);
        let (Some(x), Some(y)) = (
            pos(&d.picks[0], i0),
            if shown == 2 {
                pos(&d.picks[1], i1)
            } else {
                Some(0)
            },
        ) else {
            continue;
        };
        let fields: Vec<&str> = line.split(',').collect();
        let num = |c: usize| {
            fields
                .get(c)
                .and_then(|s| s.parse::<f64>().ok())
                .unwrap_or(f64::NAN)
        };
        d.prob[y][x] = num(cols[0]);
        d.time[y][x] = num(cols[1]);
        d.ci[0][y][x] = num(cols[2]);
        d.ci[1][y][x] = num(cols[3]);
    }
    Ok(d)
}

/// The plots of a whole map into `dir`: for one key, `bitmap.png`/`.svg`
/// (write probability with its 95 % interval, and the median write time,
/// against the key); for two or more, heat maps `write_probability` and
/// `write_time` over the first two keys (the others at their first value).
fn write_plots(dir: &Path, csv: &Path, axes: &[Axis]) -> Result<()> {
    use crate::plot::{HeatmapOpts, Panel, PlotOpts, Series, heatmap, multi_panel};
    let d = plot_data(csv, axes)?;
    let value = |a: usize, i: usize| axes[a].value(d.picks[a][i]);
    let stride = |a: usize| d.picks[a].get(1).copied().unwrap_or(1);
    let every = |a: usize| {
        if stride(a) > 1 {
            format!(", 1 in {} values of {}", stride(a), axes[a].key)
        } else {
            String::new()
        }
    };
    let others = if axes.len() > 2 {
        let keys: Vec<&str> = axes[2..].iter().map(|a| a.key.as_str()).collect();
        let whose = if keys.len() == 1 { "its" } else { "their" };
        format!(" ({} at {whose} first value)", keys.join(", "))
    } else {
        String::new()
    };
    let xs: Vec<f64> = (0..d.picks[0].len()).map(|i| value(0, i)).collect();
    if axes.len() == 1 {
        let series = |name: &str, ys: &[f64]| Series::new(name, xs.clone(), ys.to_vec());
        let p = Panel::new(
            "write probability",
            vec![
                series("P(write)", &d.prob[0]),
                series("95 % low", &d.ci[0][0]).dashed(),
                series("95 % high", &d.ci[1][0]).dashed(),
            ],
        );
        let t = Panel::new(
            "write time median [s]",
            vec![series("median write time", &d.time[0])],
        );
        return multi_panel(
            &dir.join("bitmap"),
            &format!("Write over {}{}", axes[0].key, every(0)),
            &axes[0].key,
            &[p, t],
            &PlotOpts {
                size: (1000, 700),
                ..Default::default()
            },
        );
    }
    let ys: Vec<f64> = (0..d.picks[1].len()).map(|j| value(1, j)).collect();
    let extra = match (stride(0), stride(1)) {
        (1, 1) => others,
        (s0, s1) => format!(" (drawn: 1 in {s0} x 1 in {s1} values){others}"),
    };
    heatmap(
        &dir.join("write_probability"),
        &format!("Write probability{extra}"),
        &axes[0].key,
        &axes[1].key,
        "P(write)",
        &xs,
        &ys,
        &d.prob,
        &HeatmapOpts {
            z_range: Some((0.0, 1.0)),
            ..Default::default()
        },
    )?;
    heatmap(
        &dir.join("write_time"),
        &format!("Median write time (grey: no write){extra}"),
        &axes[0].key,
        &axes[1].key,
        "t [s]",
        &xs,
        &ys,
        &d.time,
        &HeatmapOpts {
            // A map where no point writes: the colour bar still has a range.
            z_range: d
                .time
                .iter()
                .flatten()
                .all(|t| t.is_nan())
                .then_some((0.0, 1.0)),
            ..Default::default()
        },
    )
}
