//! The shards of grid commands (`sweep`, `bit --vary`, and the ensembles of
//! `bit`): reading the grid's arguments, streaming the rows into a partial
//! CSV with `--resume` ([`crate::partial`]), and `shard.json`, which
//! `tippetop merge` checks.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;
use tippetop::analysis::sweep::{self, Axis, Shard, ShardInfo};

use crate::output::{OutDir, check_plain, read_plain, write_bytes_atomic};
use crate::partial::PartialWriter;
use crate::scenario_load::input_error;

/// What the grid commands (`sweep`, `bit --vary`) read from their
/// arguments before anything else.
pub struct GridInput {
    /// The scenario file's text, if any.
    pub toml_text: Option<String>,
    /// The `--vary` axes.
    pub axes: Vec<Axis>,
    /// `--shard` ([`Shard::ALL`] without it).
    pub shard: Shard,
    /// `--threads` (resolved, see [`sweep::threads`]).
    pub threads: usize,
}

impl GridInput {
    /// Read the scenario file and parse `--vary`, `--shard`, `--threads`.
    /// Bad input: one line on stderr, `Err(exit code 2)`.
    pub fn parse(
        scenario: Option<&Path>,
        vary: &[String],
        shard: Option<&str>,
        threads: Option<usize>,
    ) -> std::result::Result<GridInput, ExitCode> {
        let toml_text = crate::scenario_load::read_text(scenario)?;
        let axes = vary
            .iter()
            .map(|s| Axis::parse(s))
            .collect::<Result<Vec<_>, _>>()
            .map_err(input_error)?;
        let shard = shard
            .map(Shard::parse)
            .transpose()
            .map_err(input_error)?
            .unwrap_or(Shard::ALL);
        let threads = sweep::threads(threads).map_err(input_error)?;
        Ok(GridInput {
            toml_text,
            axes,
            shard,
            threads,
        })
    }
}

/// How [`stream_rows`] writes a grid's rows: the partial files' names in
/// the output directory, the CSV's header line (with its `\n`), and words
/// for the messages (`"sweep"`, `"case"`).
pub struct Streamed<'a> {
    /// The CSV being written, e.g. `sweep.csv.partial`.
    pub partial_csv: &'a str,
    /// The shard.json of the run being written, e.g. `shard.json.partial`.
    pub partial_info: &'a str,
    /// The CSV's header line.
    pub header: String,
    /// What runs, for messages: `"sweep"`, `"map"`.
    pub what: &'a str,
    /// What a row is, for messages: `"case"`, `"point"`.
    pub unit: &'a str,
    /// `--resume`: keep the rows of an interrupted run of the same grid.
    pub resume: bool,
    /// `--quiet`: no progress bar, no notes.
    pub quiet: bool,
}

/// What [`stream_rows`] ends with.
#[derive(Debug, Clone, Copy)]
pub struct StreamDone {
    /// Rows whose status is not `ok` (kept ones included).
    pub failed: usize,
    /// FNV-1a 64 of the whole partial CSV (the final CSV's bytes), for the
    /// checksum in `shard.json` ([`crate::partial::checksum_text`]).
    pub hash: u64,
}

/// Stream the rows of the grid points `info.first_index..info.end_index`
/// into `spec.partial_csv` (beside `spec.partial_info` = `info_json`, which
/// identifies the run, and the checkpoints, [`crate::partial`]) in grid
/// order, with `--resume` (`spec.resume`): keep the verified rows of an
/// interrupted run of the same grid ([`crate::partial::verify`];
/// `prefix(text)` checks rows as this grid writes them) and run the rest.
/// Bad input: the partial files are links or other non-regular files,
/// another run's partial files, or an edited or damaged partial CSV (one
/// line, exit code 2, returned as `Ok(Err(code))`, the files left as they
/// are). `run(todo, sink)` runs the points `todo` in order and hands each
/// row's CSV line and whether it failed to `sink` (which returns `false`
/// to stop). The caller adopts the partial CSV.
#[allow(clippy::type_complexity)]
pub fn stream_rows(
    out: &mut OutDir,
    spec: &Streamed,
    info: &ShardInfo,
    info_json: &str,
    prefix: &dyn Fn(&str) -> sweep::Prefix,
    run: &mut dyn FnMut(
        std::ops::Range<usize>,
        &mut dyn FnMut(String, bool) -> bool,
    ) -> std::result::Result<bool, tippetop::Error>,
) -> Result<std::result::Result<StreamDone, ExitCode>> {
    let dir = out.dir().to_path_buf();
    let (csv_partial, info_partial) = (dir.join(spec.partial_csv), dir.join(spec.partial_info));
    let sum = crate::partial::sum_name(spec.partial_csv);
    let range = info.first_index..info.end_index;
    let (what, unit, quiet) = (spec.what, spec.unit, spec.quiet);

    // Never through a link (planted, it would make the command overwrite
    // its target).
    for name in [spec.partial_csv, spec.partial_info, sum.as_str()] {
        if let Err(e) = check_plain(&dir.join(name)) {
            return Ok(Err(input_error(e)));
        }
    }

    // What an interrupted run of this grid left, with --resume.
    let resume = Resume {
        dir: &dir,
        partial_csv: spec.partial_csv,
        partial_info: spec.partial_info,
        what,
        unit,
        keys: "--set, --vary and --shard",
        quiet,
        range_len: range.len(),
        fingerprint: &info.fingerprint,
    };
    let kept = if spec.resume {
        let described = |o: &ShardInfo| {
            format!(
                "fingerprint {}, {unit}s {}..{} of {}",
                o.fingerprint, o.first_index, o.end_index, o.total_cases
            )
        };
        match resume_kept(
            &resume,
            info_json,
            info,
            &|o: &mut ShardInfo| o.checksums.clear(),
            &described,
            prefix,
        )? {
            Ok(k) => k,
            Err(code) => return Ok(Err(code)),
        }
    } else {
        crate::partial::Kept::default()
    };

    // Stream the rows into the partial CSV in grid order (claimed in the
    // manifest first, so that a later command into this directory removes
    // it), beside the partial shard.json, which identifies the run.
    out.claim(&[spec.partial_csv, spec.partial_info, sum.as_str()])?;
    write_bytes_atomic(&info_partial, info_json.as_bytes())?;
    let mut w = PartialWriter::open(
        &dir,
        spec.partial_csv,
        &spec.header,
        &info.fingerprint,
        &kept,
    )?;
    let todo = range.start + kept.rows..range.end;
    if !quiet && kept.rows > 0 {
        eprintln!(
            "resuming: {} of {} {unit}s kept from {} (verified against its checkpoints)",
            kept.rows,
            range.len(),
            csv_partial.display()
        );
    }
    let pb = crate::progress::bar(quiet, range.len() as u64, what);
    pb.inc(kept.rows as u64);
    let mut failed = kept.failed;
    let mut write_error: Option<anyhow::Error> = None;
    let done = run(todo, &mut |line, bad| {
        if bad {
            failed += 1;
        }
        w.push(&line);
        // About once a second (or each MiB): what is on disk and
        // checkpointed is what --resume keeps.
        let result = if w.due() { w.checkpoint(None) } else { Ok(()) };
        pb.inc(1);
        match result {
            Ok(()) => true,
            Err(e) => {
                write_error = Some(e);
                false
            }
        }
    });
    pb.finish_and_clear();
    if let Err(e) = done {
        // A thread pool that cannot start (the count is bounded, so this is
        // the system's limit): an I/O-like failure, exit code 1.
        anyhow::bail!("{e}");
    }
    if let Some(e) = write_error {
        return Err(e);
    }
    let hash = w.finish()?;
    Ok(Ok(StreamDone { failed, hash }))
}

/// What `sweep.csv.partial` holds (the `shard.json` of the running sweep),
/// so that `--resume` continues only the same sweep; at the end
/// `shard.json` is written with the checksum of `sweep.csv`.
pub const PARTIAL_INFO: &str = "shard.json.partial";

/// A grid shard directory's `shard.json` and its CSV `csv`, checked
/// against the checksum `shard.json` records for it (`what`: such a
/// directory, in words, for the messages).
pub fn read_shard_of(
    dir: &Path,
    csv: &str,
    what: &str,
) -> std::result::Result<(ShardInfo, String), String> {
    let read = |name: &str| {
        let path = dir.join(name);
        std::fs::read_to_string(&path)
            .map_err(|e| format!("{}: cannot read it: {e} ({what})", path.display()))
    };
    let json = crate::scenario_load::read_small(&dir.join("shard.json"), what)?;
    let info: ShardInfo = serde_json::from_str(&json).map_err(|e| {
        format!(
            "{}: not a shard description: {e} ({what})",
            dir.join("shard.json").display()
        )
    })?;
    let text = read(csv)?;
    crate::partial::check_checksum(&info.checksums, dir, csv, text.as_bytes())?;
    Ok((info, text))
}

/// Write `shard.json` into `dir` (atomically): `info` with `checksums`
/// (file name, [`crate::partial::checksum_text`] of its bytes).
pub fn write_info(dir: &Path, info: &ShardInfo, checksums: &[(&str, String)]) -> Result<()> {
    let mut info = info.clone();
    info.checksums = checksums
        .iter()
        .map(|(n, c)| (n.to_string(), c.clone()))
        .collect();
    let mut json = serde_json::to_string_pretty(&info)?;
    json.push('\n');
    write_bytes_atomic(&dir.join("shard.json"), json.as_bytes())
}

/// The partial files of an interrupted grid run (`sweep`, `bit --vary`,
/// `ensemble`) in `--out`, and how they are named in messages.
pub struct Resume<'a> {
    /// The output directory.
    pub dir: &'a Path,
    /// The partial CSV's name.
    pub partial_csv: &'a str,
    /// The partial description's name (the run's shard.json).
    pub partial_info: &'a str,
    /// The command's noun (`sweep`, `ensemble`).
    pub what: &'a str,
    /// One row's noun (`case`, `run`).
    pub unit: &'a str,
    /// The options besides the scenario that make the run this one.
    pub keys: &'a str,
    /// No notes on stderr.
    pub quiet: bool,
    /// Rows this run (or shard) writes.
    pub range_len: usize,
    /// The run's fingerprint, which the partial CSV's checkpoints must
    /// name.
    pub fingerprint: &'a str,
}

/// `--resume`: the rows an interrupted run left that this run keeps (none
/// if it left nothing), verified against their checkpoints
/// (`crate::partial::verify`, `prefix` reading the kept CSV). The partial
/// description must be this run's, `info` (its JSON `info_json`), up to
/// what `unfinished` clears (the checksums that only a finished run
/// records); `described` names another run's in the message. Bad input (another
/// run's files, damaged ones, more rows than the run has): one line on
/// stderr, `Ok(Err(exit code 2))`.
pub fn resume_kept<I: serde::de::DeserializeOwned + PartialEq>(
    r: &Resume,
    info_json: &str,
    info: &I,
    unfinished: &dyn Fn(&mut I),
    described: &dyn Fn(&I) -> String,
    prefix: &dyn Fn(&str) -> sweep::Prefix,
) -> Result<std::result::Result<crate::partial::Kept, ExitCode>> {
    let (what, unit) = (r.what, r.unit);
    let info_partial = r.dir.join(r.partial_info);
    if !info_partial.exists() {
        if !r.quiet {
            eprintln!(
                "note: no partial {what} to resume in {}: starting from the first {unit}",
                r.dir.display()
            );
        }
        return Ok(Ok(crate::partial::Kept::default()));
    }
    let old = String::from_utf8_lossy(&read_plain(&info_partial)?).into_owned();
    // The same run: the same description (checksums aside, which only a
    // finished run records).
    let same = old == info_json
        || serde_json::from_str::<I>(&old).is_ok_and(|mut o| {
            unfinished(&mut o);
            o == *info
        });
    if !same {
        let other = match &serde_json::from_str::<I>(&old) {
            Ok(o) => described(o),
            Err(_) => "unreadable".to_string(),
        };
        return Ok(Err(input_error(format!(
            "--resume: the partial {what} in {} is another {what} ({other}), not this one \
             ({}) (the same scenario, {} as the interrupted run; without --resume a new {what} \
             starts over)",
            r.dir.display(),
            described(info),
            r.keys,
        ))));
    }
    let names = crate::partial::Names {
        dir: r.dir,
        partial: r.partial_csv,
        what,
        unit,
        fingerprint: r.fingerprint,
    };
    let kept = match crate::partial::verify(&names, prefix, r.quiet)? {
        Ok(k) => k,
        Err(msg) => return Ok(Err(input_error(msg))),
    };
    if kept.rows > r.range_len {
        return Ok(Err(input_error(format!(
            "--resume: {}: {} rows, more than the {} {unit}s of this {what} (a partial file as \
             tippetop wrote it; without --resume the {what} starts over)",
            r.dir.join(r.partial_csv).display(),
            kept.rows,
            r.range_len
        ))));
    }
    Ok(Ok(kept))
}
