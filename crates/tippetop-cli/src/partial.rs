//! The partial CSV files of the streaming commands (`sweep`, `ensemble`,
//! `bit --runs`, `bit --vary`), checked: what `--resume` keeps is what this
//! tool wrote, or the command refuses it.
//!
//! Beside `DIR/NAME.partial` (header, then one row per case or run, in
//! order) the command keeps `DIR/NAME.partial.sum`, its checkpoints: after
//! a `#` comment line, the line `fingerprint FP` (the fingerprint of the
//! run the rows belong to: the scenario, its `--set`s, the grid or the
//! number of runs), then one line per flush of the CSV,
//! `ROWS BYTES HASH [EXTRA]`: the CSV's first `BYTES` bytes (the header and
//! `ROWS` rows) have the FNV-1a 64-bit hash `HASH` (16 hex digits); `EXTRA`
//! is the hash of a file written with them (the ensemble's histogram
//! checkpoint). A checkpoint line is appended only once the bytes it covers
//! are written, so a kill leaves checkpoints that hold.
//!
//! [`verify`] (for `--resume`) first checks the fingerprint against the
//! resuming run's: the partial files of another run (another scenario, or
//! the same one with another `solver.samples`, say), copied in beside this
//! run's description, are refused even though their rows and checkpoints
//! agree with each other. It then walks the checkpoints over the CSV: an
//! edited, removed or inserted byte before the last checkpoint makes a hash
//! differ, and the partial is refused (one line naming the file and its
//! lines; exit code 2). The verified rows are also checked one by one by
//! the command's row check (field count, numbers, status, the case's grid
//! values or the run's index and seed). Rows after the last checkpoint
//! (written after the last flush, or appended by anyone) are not trusted:
//! they are cut and run again, with a note. A partial CSV without its
//! checkpoint file is not trusted at all (the command starts over, with a
//! note).
//!
//! The hash is a check against damage and edits, not a signature: someone
//! who edits both files and recomputes the hash is not detected (that needs
//! a secret, and the output directory is theirs to write).
//!
//! The final files keep their format: the CSV is renamed, and the hash of
//! the whole file goes into `shard.json` (`checksums`, see
//! [`checksum_text`]), which `tippetop merge` checks.

use std::fs::{File, OpenOptions};
use std::io::{Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use tippetop::analysis::sweep::Prefix;

use crate::output::{check_plain, open_plain, read_plain, write_bytes_atomic};

/// Suffix of the checkpoint file beside a partial CSV
/// (`sweep.csv.partial.sum`).
pub const SUM_SUFFIX: &str = ".sum";

/// The checkpoint file of the partial CSV `partial`.
pub fn sum_name(partial: &str) -> String {
    format!("{partial}{SUM_SUFFIX}")
}

/// The FNV-1a 64-bit hash's initial state.
pub const FNV_OFFSET: u64 = 0xcbf2_9ce4_8422_2325;

/// FNV-1a 64 of `bytes`, continued from the state `h` ([`FNV_OFFSET`] for
/// a fresh hash): `fnv1a(fnv1a(FNV_OFFSET, a), b) == fnv1a(FNV_OFFSET, ab)`.
pub fn fnv1a(mut h: u64, bytes: &[u8]) -> u64 {
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// The checksum `shard.json` records for a file: `fnv1a64:` and the 16 hex
/// digits of the FNV-1a 64 hash `h` of its bytes.
pub fn checksum_text(h: u64) -> String {
    format!("fnv1a64:{h:016x}")
}

/// [`checksum_text`] of `bytes`.
pub fn checksum(bytes: &[u8]) -> String {
    checksum_text(fnv1a(FNV_OFFSET, bytes))
}

/// Check the checksum `shard.json` (`json`, the path for messages) records
/// for `file` (its name in the shard directory `dir`) against its bytes
/// `text`: `Err` is the one-line message for bad input (no checksum, or
/// another one).
pub fn check_checksum(
    checksums: &std::collections::BTreeMap<String, String>,
    dir: &Path,
    file: &str,
    text: &[u8],
) -> std::result::Result<(), String> {
    let json = dir.join("shard.json");
    let path = dir.join(file);
    match checksums.get(file) {
        None => Err(format!(
            "{}: no checksum of {file} (a shard written by this tippetop: its shard.json \
             records the checksums of its files; run the shard again)",
            json.display()
        )),
        Some(want) if *want != checksum(text) => Err(format!(
            "{}: does not match its checksum in {} ({} bytes read; the file was edited or \
             damaged: run the shard again)",
            path.display(),
            json.display(),
            text.len()
        )),
        Some(_) => Ok(()),
    }
}

/// One line of the checkpoint file: the first `bytes` bytes of the CSV
/// (the header and `rows` rows) hash to `hash`; `extra` is the hash of a
/// file written with them.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Checkpoint {
    /// Rows covered (after the header).
    pub rows: usize,
    /// Bytes covered (the header's included).
    pub bytes: u64,
    /// FNV-1a 64 of those bytes.
    pub hash: u64,
    /// FNV-1a 64 of a file written with them, if any.
    pub extra: Option<u64>,
}

impl Checkpoint {
    /// The line (with its `\n`).
    fn line(&self) -> String {
        match self.extra {
            Some(x) => format!("{} {} {:016x} {x:016x}\n", self.rows, self.bytes, self.hash),
            None => format!("{} {} {:016x}\n", self.rows, self.bytes, self.hash),
        }
    }

    /// Parse a line (without its `\n`).
    fn parse(line: &str) -> Option<Checkpoint> {
        let f: Vec<&str> = line.split(' ').collect();
        let hex = |s: &str| {
            (s.len() == 16)
                .then(|| u64::from_str_radix(s, 16).ok())
                .flatten()
        };
        let (rows, bytes, hash, extra) = match f.as_slice() {
            [r, b, h] => (r, b, h, None),
            [r, b, h, x] => (r, b, h, Some(hex(x)?)),
            _ => return None,
        };
        Some(Checkpoint {
            rows: rows.parse().ok()?,
            bytes: bytes.parse().ok()?,
            hash: hex(hash)?,
            extra,
        })
    }
}

/// The start of the line of a checkpoint file that names the run's
/// fingerprint (after the comment, before the checkpoints).
pub const FINGERPRINT_KEY: &str = "fingerprint ";

/// The first line of a checkpoint file.
const SUM_COMMENT: &str = "# tippetop checkpoints of the partial CSV beside this file: rows, bytes, FNV-1a 64 of those bytes [, of the checkpoint file written with them]\n";

/// What `--resume` keeps of a partial CSV: its first `rows` rows (`bytes`
/// bytes with the header), verified up to its last checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Kept {
    /// Rows kept.
    pub rows: usize,
    /// Bytes kept (the header's included; 0: nothing, not even it).
    pub bytes: u64,
    /// Kept rows whose status is not `ok`.
    pub failed: usize,
    /// The checkpoints that hold, up to the kept rows.
    pub checkpoints: Vec<Checkpoint>,
}

/// How the files of one streaming command are named and described.
pub struct Names<'a> {
    /// The output directory.
    pub dir: &'a Path,
    /// The partial CSV's name, e.g. `sweep.csv.partial`.
    pub partial: &'a str,
    /// What runs, for messages: `sweep`, `ensemble`, `map`, `bit ensemble`.
    pub what: &'a str,
    /// What a row is, for messages: `case`, `run`, `point`.
    pub unit: &'a str,
    /// The fingerprint of the run that resumes (its shard description's
    /// `fingerprint`): the checkpoint file must name it.
    pub fingerprint: &'a str,
}

/// Check the partial CSV `names.partial` and its checkpoints for
/// `--resume` (see the module doc): `Ok(Ok(kept))` the rows to keep
/// (none if there is no partial CSV, or no checkpoint file: a note
/// says so unless `quiet`); `Ok(Err(message))` a partial that is a link,
/// not this command's, edited or damaged: the one-line message for bad
/// input (`--resume: FILE:LINE: ...`); `Err` an I/O failure. `prefix`
/// checks rows as the command writes them ([`Prefix`]: how many of the
/// text's rows it accepts, and why it stopped).
pub fn verify(
    names: &Names,
    prefix: &dyn Fn(&str) -> Prefix,
    quiet: bool,
) -> Result<std::result::Result<Kept, String>> {
    let Names {
        dir,
        partial,
        what,
        unit,
        fingerprint,
    } = *names;
    let path = dir.join(partial);
    let sum_path = dir.join(sum_name(partial));
    for p in [&path, &sum_path] {
        if let Err(e) = check_plain(p) {
            return Ok(Err(format!("--resume: {e}")));
        }
    }
    let refuse = |at: String, what_is_wrong: String| Ok(Err(refusal(at, what_is_wrong, what)));
    if !path.exists() {
        return Ok(Ok(Kept::default()));
    }
    let data = read_plain(&path)?;
    if !sum_path.exists() {
        if !quiet {
            eprintln!(
                "note: {} has no checkpoints ({} is missing): its rows cannot be verified; \
                 starting from the first {unit}",
                path.display(),
                sum_path.display()
            );
        }
        return Ok(Ok(Kept::default()));
    }
    let sum = read_plain(&sum_path)?;
    let sum = String::from_utf8_lossy(&sum);
    let cps = match read_checkpoints(&sum, &sum_path, what, fingerprint) {
        Ok(c) => c,
        Err(msg) => return Ok(Err(msg)),
    };
    if cps.is_empty() {
        if !quiet {
            eprintln!(
                "note: {} has no checkpoint yet: starting from the first {unit}",
                sum_path.display()
            );
        }
        return Ok(Ok(Kept::default()));
    }
    // Walk the checkpoints over the data.
    let mut h = FNV_OFFSET;
    let mut pos = 0usize;
    let mut prev_rows: Option<usize> = None;
    for &(sum_line, cp) in &cps {
        let end = usize::try_from(cp.bytes).unwrap_or(usize::MAX);
        if end > data.len() {
            return refuse(
                path.display().to_string(),
                format!(
                    "{} bytes, shorter than the {} bytes its checkpoint {}:{sum_line} covers \
                     (the file was cut or edited)",
                    data.len(),
                    cp.bytes,
                    sum_path.display()
                ),
            );
        }
        h = fnv1a(h, &data[pos..end]);
        pos = end;
        if h != cp.hash {
            return Ok(Err(mismatch(
                &data,
                prefix,
                (prev_rows, cp.rows, sum_line),
                &path,
                &sum_path,
                what,
            )));
        }
        prev_rows = Some(cp.rows);
    }
    let (_, last) = *cps.last().expect("not empty");
    let end = pos;
    // The verified rows, checked as rows too.
    let Ok(text) = std::str::from_utf8(&data[..end]) else {
        return refuse(path.display().to_string(), "not UTF-8 text".into());
    };
    let p = prefix(text);
    if p.bytes == 0 {
        return refuse(
            format!("{}:1", path.display()),
            format!("not the header of this {what}"),
        );
    }
    if p.rows != last.rows || p.bytes != end {
        return refuse(
            format!("{}:{}", path.display(), p.rows + 2),
            format!(
                "not a row of this {what} ({})",
                p.problem.unwrap_or("past the rows of this shard")
            ),
        );
    }
    // Rows after the last checkpoint: not trusted.
    let tail = &data[end..];
    if !tail.is_empty() && !quiet {
        let lines =
            tail.iter().filter(|&&b| b == b'\n').count() + usize::from(!tail.ends_with(b"\n"));
        eprintln!(
            "note: {}: {lines} line{} after line {} (after the last checkpoint) not verified: \
             cut, and their {unit}s run again",
            path.display(),
            if lines == 1 { "" } else { "s" },
            last.rows + 1
        );
    }
    Ok(Ok(Kept {
        rows: last.rows,
        bytes: last.bytes,
        failed: p.failed,
        checkpoints: cps.into_iter().map(|(_, c)| c).collect(),
    }))
}

/// The message of a refused partial file: `at` (file and line) and what
/// is wrong; `what` runs (`"sweep"`, ...).
fn refusal(at: String, what_is_wrong: String, what: &str) -> String {
    format!(
        "--resume: {at}: {what_is_wrong} (a partial file as tippetop wrote it; without \
         --resume the {what} starts over)"
    )
}

/// The checkpoints of a `.sum` file (`sum`, read from `sum_path`) with
/// their line numbers, up to a torn last line, once its `fingerprint` line
/// has named `fingerprint`. `Err`: the message refusing a file without
/// that line or with another run's fingerprint, or a line that is not a
/// checkpoint or goes backwards.
fn read_checkpoints(
    sum: &str,
    sum_path: &Path,
    what: &str,
    fingerprint: &str,
) -> std::result::Result<Vec<(usize, Checkpoint)>, String> {
    let refuse = |at: String, what_is_wrong: String| Err(refusal(at, what_is_wrong, what));
    let mut cps: Vec<(usize, Checkpoint)> = Vec::new();
    let mut named = false;
    for (i, line) in sum.split_inclusive('\n').enumerate() {
        let Some(body) = line.strip_suffix('\n') else {
            // A torn last line: the checkpoint was being written.
            break;
        };
        if body.starts_with('#') {
            continue;
        }
        if !named {
            let at = format!("{}:{}", sum_path.display(), i + 1);
            match body.strip_prefix(FINGERPRINT_KEY) {
                Some(fp) if fp == fingerprint => {
                    named = true;
                    continue;
                }
                Some(fp) => {
                    return refuse(
                        at,
                        format!(
                            "the checkpoints of another {what} (fingerprint {fp}), not of this \
                             one ({fingerprint}): the rows beside them are not this {what}'s"
                        ),
                    );
                }
                None => {
                    return refuse(
                        at,
                        format!(
                            "no fingerprint line (`{FINGERPRINT_KEY}{fingerprint}` for this \
                             {what}) before the checkpoints: the rows beside them cannot be \
                             told to be this {what}'s"
                        ),
                    );
                }
            }
        }
        let Some(cp) = Checkpoint::parse(body) else {
            return refuse(
                format!("{}:{}", sum_path.display(), i + 1),
                "not a checkpoint (ROWS BYTES HASH [HASH])".into(),
            );
        };
        if let Some((_, prev)) = cps.last() {
            if cp.rows < prev.rows || cp.bytes < prev.bytes {
                return refuse(
                    format!("{}:{}", sum_path.display(), i + 1),
                    "a checkpoint before the one on the line above it".into(),
                );
            }
        }
        cps.push((i + 1, cp));
    }
    Ok(cps)
}

/// Why the data do not match a checkpoint (`rows` = (rows of the previous
/// checkpoint, rows of this one, its line in `sum_path`)): the first row
/// the row check refuses, if it is one of the lines the checkpoint
/// covers, else those lines.
fn mismatch(
    data: &[u8],
    prefix: &dyn Fn(&str) -> Prefix,
    (prev_rows, rows, sum_line): (Option<usize>, usize, usize),
    path: &Path,
    sum_path: &Path,
    what: &str,
) -> String {
    let refuse = |at: String, what_is_wrong: String| refusal(at, what_is_wrong, what);
    let text = String::from_utf8_lossy(data);
    let p = prefix(&text);
    let first = prev_rows.map_or(1, |r| r + 2);
    let last = rows + 1;
    if p.bytes == 0 {
        return refuse(
            format!("{}:1", path.display()),
            format!("not the header of this {what}"),
        );
    }
    if p.problem.is_some() && (first..=last).contains(&(p.rows + 2)) {
        return refuse(
            format!("{}:{}", path.display(), p.rows + 2),
            format!(
                "not a row of this {what} ({})",
                p.problem.unwrap_or("unreadable")
            ),
        );
    }
    let lines = if first == last {
        format!("{first}")
    } else {
        format!("{first}-{last}")
    };
    refuse(
        format!("{}:{lines}", path.display()),
        format!(
            "does not match its checksum in {}:{sum_line} (the file was edited or \
             damaged)",
            sum_path.display()
        ),
    )
}

/// Bytes of rows buffered before a checkpoint is due (see
/// [`PartialWriter::due`]).
const FLUSH_BYTES: usize = 1 << 20;

/// Time after which a checkpoint is due (see [`PartialWriter::due`]).
const FLUSH_EVERY: Duration = Duration::from_secs(1);

/// The environment variable that replaces [`FLUSH_EVERY`] \[s\]: the speed
/// gate (`.ci/perf-gate`) sets it to a day, so that how many checkpoints a
/// run writes (and so its instruction count) does not depend on how fast
/// the machine is (under callgrind a run is ~50x slower and a 1 s
/// checkpoint fell 0-4 times into the same ensemble: 94.4-98.5 M
/// instructions). The files written are the same either way.
pub const FLUSH_EVERY_ENV: &str = "TIPPETOP_CHECKPOINT_SECONDS";

/// [`FLUSH_EVERY`], or the whole seconds [`FLUSH_EVERY_ENV`] gives (read
/// once; an unreadable value is ignored).
fn flush_every() -> Duration {
    static EVERY: std::sync::OnceLock<Duration> = std::sync::OnceLock::new();
    *EVERY.get_or_init(|| {
        std::env::var(FLUSH_EVERY_ENV)
            .ok()
            .and_then(|v| v.trim().parse::<u64>().ok())
            .map_or(FLUSH_EVERY, Duration::from_secs)
    })
}

/// A partial CSV being written, with its checkpoints (see the module doc).
#[derive(Debug)]
pub struct PartialWriter {
    file: File,
    sum: File,
    path: PathBuf,
    sum_path: PathBuf,
    hash: u64,
    bytes: u64,
    rows: usize,
    buf: Vec<u8>,
    last: Instant,
}

impl PartialWriter {
    /// Open `dir/partial` (never through a link) to continue after the
    /// rows `kept` (the file is cut there; the checkpoint file rewritten to
    /// the kept checkpoints), or, with nothing kept, from a fresh `header`
    /// (with its `\n`); the checkpoint file names the run's `fingerprint`.
    pub fn open(
        dir: &Path,
        partial: &str,
        header: &str,
        fingerprint: &str,
        kept: &Kept,
    ) -> Result<PartialWriter> {
        let path = dir.join(partial);
        let sum_path = dir.join(sum_name(partial));
        let mut file = open_plain(
            &path,
            OpenOptions::new().write(true).create(true).truncate(false),
        )?;
        let (cps, fresh) = match kept.checkpoints.last() {
            Some(_) => (kept.checkpoints.clone(), false),
            None => (
                vec![Checkpoint {
                    rows: 0,
                    bytes: header.len() as u64,
                    hash: fnv1a(FNV_OFFSET, header.as_bytes()),
                    extra: None,
                }],
                true,
            ),
        };
        let last = *cps.last().expect("one or more");
        let writing = || format!("writing {}", path.display());
        file.set_len(if fresh { 0 } else { last.bytes })
            .and_then(|()| file.seek(SeekFrom::End(0)).map(|_| ()))
            .with_context(writing)?;
        if fresh {
            file.write_all(header.as_bytes()).with_context(writing)?;
        }
        let mut text = String::from(SUM_COMMENT);
        text.push_str(&format!("{FINGERPRINT_KEY}{fingerprint}\n"));
        for c in &cps {
            text.push_str(&c.line());
        }
        write_bytes_atomic(&sum_path, text.as_bytes())?;
        let sum = open_plain(&sum_path, OpenOptions::new().append(true))?;
        Ok(PartialWriter {
            file,
            sum,
            path,
            sum_path,
            hash: last.hash,
            bytes: last.bytes,
            rows: last.rows,
            buf: Vec::with_capacity(64 * 1024),
            last: Instant::now(),
        })
    }

    /// Add a row (a line with its `\n`); written at the next checkpoint.
    pub fn push(&mut self, line: &str) {
        self.buf.extend_from_slice(line.as_bytes());
        self.rows += 1;
    }

    /// Whether a checkpoint is due: rows are waiting and 1 MiB of them or
    /// a second since the last.
    pub fn due(&self) -> bool {
        !self.buf.is_empty()
            && (self.buf.len() >= FLUSH_BYTES || self.last.elapsed() >= flush_every())
    }

    /// Rows written or waiting (the kept ones included).
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// Write the waiting rows, then append their checkpoint (with `extra`,
    /// the hash of a file written with them; nothing to do without rows or
    /// `extra`).
    pub fn checkpoint(&mut self, extra: Option<u64>) -> Result<()> {
        if self.buf.is_empty() && extra.is_none() {
            return Ok(());
        }
        self.file
            .write_all(&self.buf)
            .with_context(|| format!("writing {}", self.path.display()))?;
        self.hash = fnv1a(self.hash, &self.buf);
        self.bytes += self.buf.len() as u64;
        self.buf.clear();
        let cp = Checkpoint {
            rows: self.rows,
            bytes: self.bytes,
            hash: self.hash,
            extra,
        };
        self.sum
            .write_all(cp.line().as_bytes())
            .with_context(|| format!("writing {}", self.sum_path.display()))?;
        self.last = Instant::now();
        Ok(())
    }

    /// Write the last rows and their checkpoint; the hash of the whole
    /// file (the final CSV's, for `shard.json`).
    pub fn finish(mut self) -> Result<u64> {
        self.checkpoint(None)?;
        Ok(self.hash)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// FNV-1a 64 against its published test vectors (the FNV authors'
    /// list: "" and "a", "foobar"), and continued hashing.
    #[test]
    fn fnv1a_published_vectors() {
        assert_eq!(fnv1a(FNV_OFFSET, b""), 0xcbf2_9ce4_8422_2325);
        assert_eq!(fnv1a(FNV_OFFSET, b"a"), 0xaf63_dc4c_8601_ec8c);
        assert_eq!(fnv1a(FNV_OFFSET, b"foobar"), 0x8594_4171_f739_67e8);
        assert_eq!(
            fnv1a(fnv1a(FNV_OFFSET, b"foo"), b"bar"),
            0x8594_4171_f739_67e8
        );
        assert_eq!(checksum(b"a"), "fnv1a64:af63dc4c8601ec8c");
    }

    #[test]
    fn checkpoint_lines_round_trip() {
        for c in [
            Checkpoint {
                rows: 0,
                bytes: 12,
                hash: 0x0123_4567_89ab_cdef,
                extra: None,
            },
            Checkpoint {
                rows: 7,
                bytes: 1234,
                hash: u64::MAX,
                extra: Some(5),
            },
        ] {
            let l = c.line();
            assert_eq!(Checkpoint::parse(l.strip_suffix('\n').unwrap()), Some(c));
        }
        for bad in [
            "",
            "1 2",
            "1 2 3",
            "x 2 0123456789abcdef",
            "1 2 0123456789abcdeg",
        ] {
            assert_eq!(Checkpoint::parse(bad), None, "{bad:?}");
        }
    }
}
