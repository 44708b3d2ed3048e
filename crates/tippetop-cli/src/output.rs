//! Writing results to disk: the output directory as a unit ([`OutDir`]),
//! atomic file writes, CSV with shortest round-trip floats, pretty JSON, and
//! the `summary.json` document of a run.
//!
//! Every file goes through [`write_atomic`]: it is written to a temporary
//! name unique to the process and the write (`DIR/.NAME.PID-N.tmp`) and
//! renamed over `DIR/NAME`, so a reader never sees half a file, a failed
//! write leaves any previous version in place, and two writers never share a
//! temporary file.

use std::collections::{BTreeMap, BTreeSet};
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, Read, Seek, Write};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use anyhow::{Context, Result, bail};
use serde::Serialize;
use tippetop::trajectory::COLUMNS;
use tippetop::{EventRecord, Summary, Trajectory};

/// The subcommand this process runs and whether `--force` was given
/// ([`set_invocation`]).
static INVOCATION: std::sync::OnceLock<(&'static str, bool)> = std::sync::OnceLock::new();

/// Record the subcommand this process runs (`run`, `sweep`, ...) and
/// whether `--force` was given: [`OutDir::open`] names it in the manifest
/// and refuses, without `--force`, to replace another subcommand's output.
/// Called once by `main`; without it (library use, tests) no check is made.
pub fn set_invocation(command: &'static str, force: bool) {
    let _ = INVOCATION.set((command, force));
}

/// Subcommands that add their files beside another's output (`animate`
/// beside a run's) rather than replace it.
const ADDING: [&str; 1] = ["animate"];

/// Whether `now` may replace the output `before` wrote: the same
/// subcommand, or `merge` of shards of a streaming subcommand (it writes
/// that subcommand's output) and that subcommand again.
fn may_replace(before: &str, now: &str) -> bool {
    const SHARDED: [&str; 4] = ["sweep", "ensemble", "bit", "rare"];
    before == now
        || (before == "merge" && SHARDED.contains(&now))
        || (now == "merge" && SHARDED.contains(&before))
}

/// Counter that makes each temporary name of this process unique.
static TMP_COUNTER: AtomicU64 = AtomicU64::new(0);

/// A fresh temporary path for [`write_atomic`] next to `path`:
/// `DIR/.NAME.PID-RANDOM-N.tmp`, with this process's id, a random number
/// drawn once per process and a per-process counter, so neither two
/// processes nor two writes of one process share it.
pub fn tmp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    let n = TMP_COUNTER.fetch_add(1, Ordering::Relaxed);
    path.with_file_name(format!(".{name}.{}-{n}.tmp", process_tag()))
}

/// This process's id and a random number drawn once per process
/// (`PID-RANDOM`): unique among the processes that may share a directory,
/// even on several machines of a cluster sharing a file system (where
/// process ids repeat).
fn process_tag() -> &'static str {
    use std::hash::{BuildHasher, Hasher};
    static TAG: std::sync::OnceLock<String> = std::sync::OnceLock::new();
    TAG.get_or_init(|| {
        // std's hasher keys are random per process.
        let mut h = std::collections::hash_map::RandomState::new().build_hasher();
        h.write_u32(std::process::id());
        format!("{}-{:08x}", std::process::id(), h.finish() as u32)
    })
}

/// Write `path` atomically: `fill` writes the contents into a buffered
/// temporary file ([`tmp_path`], created anew, never through a link:
/// `O_CREAT | O_EXCL | O_NOFOLLOW`), which is flushed and renamed to `path`
/// (the rename replaces a link at `path`, never its target). On any error
/// the temporary file is removed and `path` is left as it was. A process
/// that is interrupted never leaves a half-written `path` (the rename is
/// atomic). The file is not fsync'ed: that would guard only against power
/// loss, at a cost of milliseconds per file (more than a whole simulation).
///
/// In this process's own staging directory ([`OutDir::stage`]) `path` is
/// written in place, without the temporary file: no other process reads
/// it, only [`OutDir::commit`] moves it into the output directory, and a
/// write that fails (or panics) removes it. (Two renames per file, ~0.1 ms
/// a run: docs/performance.md, "The speed gate".)
pub fn write_atomic<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    if in_own_stage(path) {
        return write_in_stage(path, fill);
    }
    let tmp = tmp_path(path);
    let result = (|| -> io::Result<()> {
        let file = open_no_follow(&tmp, OpenOptions::new().write(true).create_new(true))?;
        let mut w = BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        drop(file);
        fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(e).with_context(|| format!("writing {}", path.display()));
    }
    Ok(())
}

/// Whether `path` is in a staging directory of this process: its parent is
/// named with this process's tag ([`process_tag`]), or it is the shared
/// [`STAGE_NAME`] of a directory whose lock this process holds now
/// ([`OWN_SHARED_STAGES`]).
fn in_own_stage(path: &Path) -> bool {
    let Some(parent) = path.parent() else {
        return false;
    };
    match parent.file_name().and_then(|n| n.to_str()) {
        Some(STAGE_NAME) => own_shared_stages().iter().any(|s| s == parent),
        Some(n) => n.strip_prefix(STAGE_PREFIX) == Some(process_tag()),
        None => false,
    }
}

/// The shared stages ([`STAGE_NAME`]) of the output directories this
/// process holds the lock of, while it does ([`OutDir`] adds and removes
/// them). Apart from the registry of [`live`] stages, which
/// [`OutDir::commit`] holds while it writes the manifest.
static OWN_SHARED_STAGES: std::sync::Mutex<Vec<PathBuf>> = std::sync::Mutex::new(Vec::new());

fn own_shared_stages() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    OWN_SHARED_STAGES.lock().unwrap_or_else(|e| e.into_inner())
}

/// [`write_atomic`] in this process's staging directory: `path` created
/// (or truncated) without following a link and written in place; removed
/// if the write fails or panics.
fn write_in_stage<F>(path: &Path, fill: F) -> Result<()>
where
    F: FnOnce(&mut BufWriter<File>) -> io::Result<()>,
{
    /// Removes the file when dropped, unless disarmed.
    struct Partial<'a>(Option<&'a Path>);
    impl Drop for Partial<'_> {
        fn drop(&mut self) {
            if let Some(p) = self.0 {
                let _ = fs::remove_file(p);
            }
        }
    }
    let mut partial = Partial(None);
    let result = (|| -> io::Result<()> {
        let file = open_no_follow(
            path,
            OpenOptions::new().write(true).create(true).truncate(true),
        )?;
        partial.0 = Some(path);
        let mut w = BufWriter::new(file);
        fill(&mut w)?;
        w.into_inner().map_err(|e| e.into_error())?;
        Ok(())
    })();
    match result {
        Ok(()) => {
            partial.0 = None;
            Ok(())
        }
        Err(e) => Err(e).with_context(|| format!("writing {}", path.display())),
    }
}

/// Write `bytes` to `path` atomically (see [`write_atomic`]).
pub fn write_bytes_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    write_atomic(path, |w| w.write_all(bytes))
}

/// Shortest decimal text that parses back to exactly `v` (via `zmij`, a
/// shortest-round-trip formatter about twice as fast as `ryu` with the same
/// digits): `0.1`, `1.196e-24`, `-30000000.0`, `5e-324`, `1e+300`; `NaN`,
/// `inf`, `-inf` for non-finite values (all accepted by `str::parse::<f64>`
/// and by every CSV reader).
pub fn fmt_f64(v: f64) -> String {
    let mut buf = zmij::Buffer::new();
    buf.format(v).to_string()
}

/// Append [`fmt_f64`]`(v)` to `out` without an intermediate allocation.
fn push_f64(out: &mut String, v: f64) {
    let mut buf = zmij::Buffer::new();
    out.push_str(buf.format(v));
}

/// A duration for people, to 3 significant figures: `12.3 ms` below a
/// second (`0.0123 ms` for very short ones, never `0.0 s`), `1.23 s`,
/// `12.3 s`, `123 s`, whole seconds beyond.
pub fn fmt_duration(seconds: f64) -> String {
    let (x, unit) = if seconds.abs() < 1.0 {
        (seconds * 1e3, "ms")
    } else {
        (seconds, "s")
    };
    if x == 0.0 || !x.is_finite() {
        return format!("{x} {unit}");
    }
    let decimals = (2 - x.abs().log10().floor() as i64).clamp(0, 12) as usize;
    // Rounding can carry into the next digit (9.996 -> 10.00): one fewer.
    let text = format!("{x:.decimals$}");
    // Significant digits: leading zeros ("0.000120") do not count.
    let digits = text
        .chars()
        .filter(char::is_ascii_digit)
        .skip_while(|&c| c == '0')
        .count();
    let text = if digits > 3 && decimals > 0 {
        format!("{x:.prec$}", prec = decimals - 1)
    } else {
        text
    };
    format!("{text} {unit}")
}

/// The CSV header line of `trajectory.csv`: [`COLUMNS`] joined by commas.
pub fn trajectory_header() -> String {
    COLUMNS.join(",")
}

/// Which columns of `trajectory.csv` to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Columns {
    /// All of [`COLUMNS`] (the default).
    All,
    /// [`COLUMNS`] less the pose's
    /// ([`tippetop::trajectory::POSE_COLUMNS`], the last nine:
    /// `run --no-pose`).
    WithoutPose,
}

impl Columns {
    /// How many of [`COLUMNS`], from the first.
    fn count(self) -> usize {
        match self {
            Columns::All => COLUMNS.len(),
            Columns::WithoutPose => COLUMNS.len() - tippetop::trajectory::POSE_COLUMNS.len(),
        }
    }
}

/// Write a trajectory as CSV: the [`COLUMNS`] header, then one row per
/// sample, floats in shortest round-trip form, `rolling` as `0`/`1`.
pub fn write_trajectory_csv(path: &Path, traj: &Trajectory) -> Result<()> {
    write_trajectory_csv_columns(path, traj, Columns::All)
}

/// [`write_trajectory_csv`] with the first [`Columns::count`] columns.
pub fn write_trajectory_csv_columns(
    path: &Path,
    traj: &Trajectory,
    columns: Columns,
) -> Result<()> {
    let n = columns.count();
    // The pose's columns are the last ones.
    debug_assert!(
        tippetop::trajectory::POSE_COLUMNS
            .iter()
            .zip(&COLUMNS[COLUMNS.len() - tippetop::trajectory::POSE_COLUMNS.len()..])
            .all(|(a, b)| a == b)
    );
    write_atomic(path, |w| {
        writeln!(w, "{}", COLUMNS[..n].join(","))?;
        let mut line = String::with_capacity(640);
        let rolling = COLUMNS.iter().position(|c| *c == "rolling").unwrap();
        for s in &traj.samples {
            line.clear();
            for (i, v) in s.values()[..n].iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                if i == rolling {
                    line.push_str(if s.rolling != 0 { "1" } else { "0" });
                } else {
                    push_f64(&mut line, *v);
                }
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    })
}

/// Write figure data as CSV: `headers[i]` names `columns[i]` (by convention
/// the first column is `t`, then one column per curve). All columns must have
/// the same length; NaN is written as an empty field (a missing value), other
/// numbers in shortest round-trip form. Headers must not contain commas,
/// quotes or newlines.
pub fn write_series_csv(path: &Path, headers: &[&str], columns: &[&[f64]]) -> Result<()> {
    if headers.len() != columns.len() {
        bail!(
            "{}: {} headers for {} columns",
            path.display(),
            headers.len(),
            columns.len()
        );
    }
    if let Some(h) = headers.iter().find(|h| h.contains([',', '"', '\n', '\r'])) {
        bail!("{}: header {h:?} needs quoting", path.display());
    }
    let n = columns.first().map_or(0, |c| c.len());
    if let Some((i, c)) = columns.iter().enumerate().find(|(_, c)| c.len() != n) {
        bail!(
            "{}: column {:?} has {} values, expected {n}",
            path.display(),
            headers[i],
            c.len()
        );
    }
    write_atomic(path, |w| {
        writeln!(w, "{}", headers.join(","))?;
        let mut line = String::with_capacity(32 * columns.len());
        for row in 0..n {
            line.clear();
            for (i, c) in columns.iter().enumerate() {
                if i > 0 {
                    line.push(',');
                }
                let v = c[row];
                if !v.is_nan() {
                    push_f64(&mut line, v);
                }
            }
            line.push('\n');
            w.write_all(line.as_bytes())?;
        }
        Ok(())
    })
}

/// Write `value` as pretty-printed JSON (trailing newline), atomically.
/// `None` becomes `null`; serde_json also writes non-finite floats as `null`.
pub fn write_json_pretty<T: Serialize + ?Sized>(path: &Path, value: &T) -> Result<()> {
    let mut text = serde_json::to_string_pretty(value)
        .with_context(|| format!("serializing {}", path.display()))?;
    text.push('\n');
    write_bytes_atomic(path, text.as_bytes())
}

// ---------------------------------------------------------------------------
// Files in an output directory: never through a link.

/// The one-line bad-input error (exit code 2) for `path`, a file tippetop
/// reads or writes in an output directory, found to be a symbolic link or
/// not a regular file (`what`): tippetop never writes through a link
/// there (a planted link would make it overwrite the link's target).
pub fn not_plain(path: &Path, what: &str) -> anyhow::Error {
    tippetop::Error::invalid(
        &path.display().to_string(),
        what.to_string(),
        "a regular file or nothing: tippetop does not read or write through links in an \
         output directory; remove it"
            .into(),
    )
    .into()
}

/// `Ok` if `path` is a regular file or does not exist; the [`not_plain`]
/// error if it is a symbolic link (to anything, even to nothing) or
/// another kind of file (a directory, a FIFO, ...). For a check before
/// anything is written; the files are then opened with [`open_plain`],
/// which checks again.
pub fn check_plain(path: &Path) -> Result<()> {
    match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => Err(not_plain(path, "is a symbolic link")),
        Ok(m) if !m.is_file() => Err(not_plain(path, "is not a regular file")),
        _ => Ok(()),
    }
}

/// Open `path` with `opts` without following a symbolic link at its last
/// component (`O_NOFOLLOW`; without blocking on a FIFO) and only if it is a
/// regular file: a link or another kind of file is the [`not_plain`]
/// error (exit code 2). Other errors carry `opening PATH`.
pub fn open_plain(path: &Path, opts: &mut OpenOptions) -> Result<File> {
    check_plain(path)?;
    let file = match open_no_follow(path, opts) {
        Ok(f) => f,
        Err(e) if is_link_error(&e) => return Err(not_plain(path, "is a symbolic link")),
        Err(e) => return Err(e).with_context(|| format!("opening {}", path.display())),
    };
    let meta = file
        .metadata()
        .with_context(|| format!("opening {}", path.display()))?;
    if !meta.is_file() {
        return Err(not_plain(path, "is not a regular file"));
    }
    Ok(file)
}

/// The bytes of `path`, read as [`open_plain`] opens it.
pub fn read_plain(path: &Path) -> Result<Vec<u8>> {
    let mut file = open_plain(path, OpenOptions::new().read(true))?;
    let mut bytes = Vec::new();
    file.read_to_end(&mut bytes)
        .with_context(|| format!("reading {}", path.display()))?;
    Ok(bytes)
}

/// `opts` with `O_NOFOLLOW | O_NONBLOCK` (Unix), opened.
fn open_no_follow(path: &Path, opts: &mut OpenOptions) -> io::Result<File> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::OpenOptionsExt;
        opts.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
    }
    opts.open(path)
}

/// Whether an open failed because of `O_NOFOLLOW` on a link.
fn is_link_error(e: &io::Error) -> bool {
    #[cfg(unix)]
    {
        e.raw_os_error() == Some(libc::ELOOP)
    }
    #[cfg(not(unix))]
    {
        let _ = e;
        false
    }
}

// ---------------------------------------------------------------------------
// The output directory as a unit.

/// The lock file of an output directory: held (an OS advisory lock, released
/// when the process ends, however it ends) by the one tippetop process that
/// writes into the directory; it holds that process's id. It is opened
/// without following links and removed when the command ends (also on
/// SIGINT, SIGTERM and SIGHUP), in a way that lets no second writer in
/// ([`DirLock`]); one left by a killed process (`kill -9`) is taken over.
pub const LOCK_NAME: &str = ".tippetop.lock";

/// The manifest of an output directory: the files the last command wrote
/// into it, one per line after `#` comment lines: `NAME<TAB>SIZE<TAB>HASH`,
/// the file's size in bytes and the XXH3-64 hash of its bytes (16 hex
/// digits) as the command wrote it ([`Record`]), or `NAME` alone for a
/// partial file a command streams into the directory as it runs
/// (`NAME.partial`, `NAME.partial.sum`, see [`OutDir::claim`]).
///
/// A manifest is a claim that anyone who can write the directory can make:
/// a later command removes a listed file only when it is still what
/// tippetop wrote, its size and hash those recorded, or, for a name
/// without a record, when it is a partial file's name. Any other listed
/// file (a forged line, an old manifest's name without a record, a file
/// the user has since replaced) is left alone, with a note on stderr. The
/// hash tells a file that changed or that tippetop did not write from its
/// own; it is not a signature (someone who can read a file and write the
/// manifest can record its hash).
pub const MANIFEST_NAME: &str = ".tippetop-manifest";

/// What the manifest records of a file tippetop wrote: its size and the
/// XXH3-64 hash of its bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Record {
    /// Size \[bytes\].
    pub size: u64,
    /// XXH3-64 of the bytes.
    pub hash: u64,
}

impl Record {
    /// The record of the file at `path` as it is now (read without
    /// following a link), `None` if it cannot be read.
    fn of(path: &Path) -> Option<Record> {
        let bytes = read_plain(path).ok()?;
        Some(Record {
            size: bytes.len() as u64,
            hash: xxhash_rust::xxh3::xxh3_64(&bytes),
        })
    }
}

/// Whether a name listed without a [`Record`] may be removed: the name of
/// a partial file that a command streams as it runs and a kill leaves.
fn is_partial_name(name: &str) -> bool {
    name.ends_with(".partial") || name.ends_with(".partial.sum")
}

/// The staging directory (`DIR/.tippetop-stage`) where a command writes its
/// files before [`OutDir::commit`] moves them into place. Used only by the
/// holder of the directory's lock (and only if it is the user's own, not
/// another user's), so commands take turns in it: it is
/// emptied when a command takes it, left empty after a commit (creating and
/// removing a directory each time cost every command ~0.08 ms on ext4:
/// docs/performance.md, "The speed gate"), and removed when a command
/// fails or is interrupted by a signal.
pub const STAGE_NAME: &str = ".tippetop-stage";

/// Prefix of the staging directory of a command that could not lock the
/// directory (a file system without locks), or that found [`STAGE_NAME`]
/// to be another user's: `DIR/.tippetop-stage-PID-RANDOM`, its own,
/// removed at the end.
const STAGE_PREFIX: &str = ".tippetop-stage-";

/// A lock on a directory's [`LOCK_NAME`]: exclusive for the one command
/// that writes into the directory ([`OutDir`]), shared for the commands
/// that read it ([`read_lock`]). Dropping it releases it and removes the
/// lock file when no one else holds it.
///
/// The protocol (`flock(2)` on Unix): open the file without following a
/// link (creating it if missing), lock it, then check that the path still
/// names the file locked (else the holder that just ended removed it: start
/// again). The holder removes the file while it still holds the exclusive
/// lock (a reader first tries to upgrade to one, and leaves the file to the
/// others if it cannot), so whoever opened the old file before the removal
/// finds, once it gets the lock, that the path no longer names it. The OS
/// releases the lock of a process that dies, so a lock file a killed
/// process left behind is simply taken over.
#[derive(Debug)]
pub struct DirLock {
    file: File,
    path: PathBuf,
    /// Whether the OS lock is held (false on a file system without locks).
    held: bool,
    exclusive: bool,
    /// Whether this process created the lock file.
    created: bool,
    /// Why no OS lock could be taken (a file system without locks).
    unsupported: Option<io::Error>,
    id: u64,
}

/// What [`take_lock`] found.
enum Taken {
    Lock(DirLock),
    /// Held by another process, whose id the file holds (or "unknown").
    Busy(String),
    /// No lock file, and a reader could not create one (a read-only
    /// directory): nothing to lock.
    Absent,
}

/// A process-wide counter naming the registered stages and locks.
fn next_id() -> u64 {
    static ID: AtomicU64 = AtomicU64::new(0);
    ID.fetch_add(1, Ordering::Relaxed)
}

/// Open the lock file `path` without following a link: a writer creates it
/// if missing (then opens it read-write); a reader opens it read-only, or
/// creates it if it can. `Ok(None)`: a reader found none and could not
/// create one. The bool: created by this call.
fn open_lock_file(path: &Path, writer: bool) -> Result<Option<(File, bool)>> {
    let refuse = |e: io::Error| -> anyhow::Error {
        if is_link_error(&e) {
            not_plain(path, "is a symbolic link")
        } else {
            anyhow::Error::new(e)
        }
    };
    for _ in 0..64 {
        if !writer {
            match open_no_follow(path, OpenOptions::new().read(true)) {
                Ok(f) => return Ok(Some((f, false))),
                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                Err(e) => return Err(refuse(e)),
            }
        }
        match open_no_follow(
            path,
            OpenOptions::new().read(true).write(true).create_new(true),
        ) {
            Ok(f) => return Ok(Some((f, true))),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {}
            Err(_) if !writer => return Ok(None),
            Err(e) => return Err(refuse(e)),
        }
        if writer {
            match open_no_follow(path, OpenOptions::new().read(true).write(true)) {
                Ok(f) => return Ok(Some((f, false))),
                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                Err(e) => return Err(refuse(e)),
            }
        }
        // Removed or created between two calls: again.
    }
    bail!("{} keeps appearing and disappearing", path.display())
}

/// Take `dir`'s lock, exclusive (a writer) or shared (a reader), without
/// waiting (see [`DirLock`] for the protocol).
fn take_lock(dir: &Path, exclusive: bool) -> Result<Taken> {
    let path = dir.join(LOCK_NAME);
    for _ in 0..64 {
        let Some((file, created)) = open_lock_file(&path, exclusive)? else {
            return Ok(Taken::Absent);
        };
        if !file.metadata()?.is_file() {
            return Err(not_plain(&path, "is not a regular file"));
        }
        #[cfg(unix)]
        let mode = if exclusive {
            libc::LOCK_EX
        } else {
            libc::LOCK_SH
        };
        #[cfg(not(unix))]
        let mode = 0;
        let (held, unsupported) = match try_flock(&file, mode) {
            Ok(true) => (true, None),
            Ok(false) => return Ok(Taken::Busy(lock_holder(&file))),
            // A file system without locks (some cluster file systems).
            Err(e) => (false, Some(e)),
        };
        if held && !same_file(&file, &path) {
            // The holder that just ended removed it: take the new one.
            continue;
        }
        let lock = DirLock {
            file,
            path: path.clone(),
            held,
            exclusive,
            created,
            unsupported,
            id: next_id(),
        };
        let mut live = live();
        live.locks.push(lock.entry());
        publish(&live);
        return Ok(Taken::Lock(lock));
    }
    bail!("cannot lock {}: it keeps being replaced", path.display())
}

/// Whether `path` (not followed) names the open file `file`.
fn same_file(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::symlink_metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino() && b.is_file(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

/// What [`release_lock`] needs of a [`DirLock`], kept in the registry of
/// live locks so that the signal handler can release them too.
#[derive(Debug, Clone)]
struct LockEntry {
    id: u64,
    #[cfg(unix)]
    fd: std::os::fd::RawFd,
    path: PathBuf,
    held: bool,
    exclusive: bool,
    created: bool,
}

impl DirLock {
    fn entry(&self) -> LockEntry {
        LockEntry {
            id: self.id,
            #[cfg(unix)]
            fd: std::os::fd::AsRawFd::as_raw_fd(&self.file),
            path: self.path.clone(),
            held: self.held,
            exclusive: self.exclusive,
            created: self.created,
        }
    }
}

impl Drop for DirLock {
    /// Release the lock: remove the lock file if no one else holds it (see
    /// [`DirLock`]); the OS lock goes with the file, closed after this.
    fn drop(&mut self) {
        let mut live = live();
        // Released before it leaves the signal handler's snapshot: a signal
        // in between finds the file gone (or another's) and leaves it.
        release_lock(&self.entry());
        live.locks.retain(|l| l.id != self.id);
        publish(&live);
    }
}

/// Remove a lock file this process holds, if it may: a writer holding the
/// lock always, a reader if it can upgrade to the exclusive lock (no other
/// reader), without locks only the file it created; and only if the path
/// still names the locked file. On Unix the signal handler's own code does
/// it ([`signals::release_lock`]), written once for both.
fn release_lock(l: &LockEntry) {
    #[cfg(unix)]
    {
        use std::os::unix::ffi::OsStrExt;
        if let Ok(path) = std::ffi::CString::new(l.path.as_os_str().as_bytes()) {
            // The fd is the live DirLock's, open until after this.
            signals::release_lock(l.fd, &path, l.held, l.exclusive, l.created);
        }
    }
    #[cfg(not(unix))]
    {
        if l.created {
            let _ = fs::remove_file(&l.path);
        }
    }
}

#[cfg(unix)]
mod signals;

/// The stages and locks of this process, for the signal handler.
struct Live {
    /// (id, output directory, staging directory).
    stages: Vec<(u64, PathBuf, PathBuf)>,
    locks: Vec<LockEntry>,
}

static LIVE: std::sync::Mutex<Live> = std::sync::Mutex::new(Live {
    stages: Vec::new(),
    locks: Vec::new(),
});

/// The registry of live stages and locks (also held by [`OutDir::commit`]
/// while it moves files).
fn live() -> std::sync::MutexGuard<'static, Live> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Whether `name` is a temporary name of [`tmp_path`]:
/// `.NAME.PID-RANDOM-N.tmp`.
fn is_tmp_name(name: &str) -> bool {
    let Some(stem) = name.strip_prefix('.').and_then(|n| n.strip_suffix(".tmp")) else {
        return false;
    };
    let Some((_, tag)) = stem.rsplit_once('.') else {
        return false;
    };
    let parts: Vec<&str> = tag.split('-').collect();
    matches!(parts.as_slice(), [pid, rnd, n]
        if !pid.is_empty() && pid.bytes().all(|b| b.is_ascii_digit())
            && rnd.len() == 8 && rnd.bytes().all(|b| b.is_ascii_hexdigit())
            && !n.is_empty() && n.bytes().all(|b| b.is_ascii_digit()))
}

/// On SIGINT, SIGTERM or SIGHUP (those not ignored when the process
/// started, e.g. under `nohup`): remove this process's staging
/// directories, temporary files and lock files, then die of the signal as
/// before (partial files stay, for `--resume`). The handler does the work
/// itself, on what [`publish`] last gave it, after any commit in progress
/// (`output/signals.rs`). Installed once, by the first [`OutDir::open`] or
/// [`read_lock`].
pub fn install_signal_cleanup() {
    #[cfg(unix)]
    signals::install();
}

/// Fault injection for the end-to-end test of a signal during a commit:
/// with `TIPPETOP_TEST_SIGNAL_IN_COMMIT=SIGNUM`, the commit raises that
/// signal after moving its first file.
fn test_signal_in_commit() {
    #[cfg(unix)]
    if let Some(sig) = std::env::var("TIPPETOP_TEST_SIGNAL_IN_COMMIT")
        .ok()
        .and_then(|v| v.trim().parse::<libc::c_int>().ok())
    {
        // SAFETY: raise(3) of a signal number; the handler is ours.
        unsafe {
            libc::raise(sig);
        }
    }
}

/// Give the signal handler the registry as it is now (call after each
/// change, with the registry locked).
fn publish(live: &Live) {
    #[cfg(unix)]
    signals::publish(
        live.stages
            .iter()
            .map(|(_, d, s)| (d.as_path(), s.as_path())),
        live.locks.iter().map(|l| signals::LockFile {
            fd: l.fd,
            path: &l.path,
            held: l.held,
            exclusive: l.exclusive,
            created: l.created,
        }),
        &format!(".{}-", process_tag()),
    );
    #[cfg(not(unix))]
    let _ = live;
}

/// `Ok` if `dir` can be an output directory (`--out`): a directory, or a
/// path that does not exist yet under one; bad input (exit code 2, key
/// `--out`) if it is a file, or a part of its path is.
pub fn check_out_dir(dir: &Path) -> Result<()> {
    if dir.exists() {
        if !dir.is_dir() {
            return Err(not_a_dir(dir, "exists and is not a directory"));
        }
        return Ok(());
    }
    let mut p = dir.parent();
    while let Some(a) = p.filter(|a| !a.as_os_str().is_empty()) {
        if a.exists() {
            if !a.is_dir() {
                return Err(not_a_dir(
                    dir,
                    "a part of the path is a file, not a directory",
                ));
            }
            break;
        }
        p = a.parent();
    }
    Ok(())
}

/// The bad-input error of an `--out` that cannot be a directory.
fn not_a_dir(dir: &Path, what: &str) -> anyhow::Error {
    tippetop::Error::invalid(
        "--out",
        format!("{} {what}", dir.display()),
        "a directory, created if missing".into(),
    )
    .into()
}

/// An output directory (`--out`) that one command updates as a unit.
///
/// [`OutDir::open`] creates the directory, takes its lock ([`LOCK_NAME`];
/// a second process gets an error at once, it does not wait) and checks that
/// files can be created in it, all before anything is computed. The command
/// then writes its files into [`OutDir::stage`], a private staging directory
/// inside `DIR`, and [`OutDir::commit`] moves them into `DIR`, removes the
/// files of the previous command (those listed in its [`MANIFEST_NAME`])
/// that this one did not write, and writes the new manifest. A command that
/// fails before the commit leaves `DIR` as it was (its staging directory is
/// removed when the `OutDir` is dropped, or on SIGINT, SIGTERM, SIGHUP:
/// [`install_signal_cleanup`]). The lock file is removed at the end.
#[derive(Debug)]
pub struct OutDir {
    dir: PathBuf,
    stage: PathBuf,
    /// The directory's lock (not held on a file system without locks).
    lock: Option<DirLock>,
    created_dir: bool,
    /// Files of the previous command (its manifest, with what it records
    /// of each) and files claimed since.
    previous: BTreeMap<String, Option<Record>>,
    /// The manifest's bytes as this command last read or wrote them
    /// (`None`: none), read once in [`OutDir::open`]: the lock keeps other
    /// tippetop processes from writing it meanwhile.
    manifest: Option<Vec<u8>>,
    /// Files already in `DIR` to move into place at the commit: (from, to).
    adopted: Vec<(String, String)>,
    /// Keep the previous command's files at the commit ([`OutDir::keep_previous`]).
    keep: bool,
    done: bool,
    /// Name of the stage in the registry of live stages.
    id: u64,
    /// Whether the shared stage ([`STAGE_NAME`]) was there before this
    /// command: it is then left (emptied) if the command fails.
    stage_existed: bool,
}

impl OutDir {
    /// Create `dir` (and its parents) if missing, take its lock, remove the
    /// staging directories of processes that died, create this process's
    /// staging directory ([`create_stage`]). Errors: `dir` is
    /// not a directory (or a part of its path is a file), or its lock file
    /// is a link or not a regular file (bad input, exit code 2); the
    /// directory cannot be created or written, or another process holds
    /// the lock (`DIR is in use by another tippetop process (pid N); ...`)
    /// (exit code 1). On error nothing is left behind that this call
    /// created, except when the directory is in use (then nothing is
    /// touched at all). On a file system without locks (`flock` fails
    /// otherwise than "held") it goes on without the lock, with a warning
    /// on stderr.
    pub fn open(dir: &Path) -> Result<OutDir> {
        install_signal_cleanup();
        // The usual cases in two calls: a directory that exists, or one
        // to create under one that does.
        let created_dir = match fs::create_dir(dir) {
            Ok(()) => true,
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists && dir.is_dir() => false,
            Err(_) => {
                check_out_dir(dir)?;
                let created = !dir.exists();
                if let Err(e) = fs::create_dir_all(dir) {
                    if e.kind() == io::ErrorKind::NotADirectory {
                        return Err(not_a_dir(
                            dir,
                            "a part of the path is a file, not a directory",
                        ));
                    }
                    return Err(e).with_context(|| format!("cannot create {}", dir.display()));
                }
                created
            }
        };
        let lock = match take_lock(dir, true) {
            Ok(Taken::Lock(l)) => l,
            Ok(Taken::Busy(pid)) => bail!(
                "{} is in use by another tippetop process (pid {pid}); choose another --out or wait until it ends",
                dir.display(),
            ),
            Ok(Taken::Absent) => unreachable!("a writer creates the lock file"),
            Err(e) => {
                if created_dir {
                    let _ = fs::remove_dir(dir);
                }
                if e.downcast_ref::<tippetop::Error>().is_some() {
                    return Err(e);
                }
                return Err(e).with_context(|| {
                    format!("cannot write in {}: creating {LOCK_NAME}", dir.display())
                });
            }
        };
        if let Some(e) = &lock.unsupported {
            eprintln!(
                "warning: cannot lock {} ({e}): another tippetop process writing into {} at the same time would not be detected",
                lock.path.display(),
                dir.display()
            );
        }
        let mut out = OutDir {
            dir: dir.to_path_buf(),
            stage: if lock.held && !foreign_stage(&dir.join(STAGE_NAME)) {
                dir.join(STAGE_NAME)
            } else {
                dir.join(format!("{STAGE_PREFIX}{}", process_tag()))
            },
            lock: Some(lock),
            created_dir,
            previous: BTreeMap::new(),
            manifest: None,
            adopted: Vec::new(),
            keep: false,
            done: false,
            id: next_id(),
            stage_existed: false,
        };
        match out.prepare() {
            Ok(()) => Ok(out),
            Err(e) => {
                out.abandon();
                Err(e)
            }
        }
    }

    /// Whether this process holds the directory's lock.
    fn locked(&self) -> bool {
        self.lock.as_ref().is_some_and(|l| l.held)
    }

    /// The part of [`OutDir::open`] after the lock is taken.
    fn prepare(&mut self) -> Result<()> {
        let cannot = |what: &str| format!("cannot write in {}: {what}", self.dir.display());
        if let Some(lock) = self.lock.as_mut() {
            let f = &mut lock.file;
            // Truncated only when not empty (a lock left by a process that
            // died): on ext4 a file truncated to zero and then written is
            // flushed at its close (`auto_da_alloc`), ~0.25 ms per run for a
            // lock this run just created (docs/performance.md, "The speed gate").
            f.metadata()
                .and_then(|m| if m.len() > 0 { f.set_len(0) } else { Ok(()) })
                .and_then(|()| f.rewind())
                .and_then(|()| f.write_all(format!("{}\n", std::process::id()).as_bytes()))
                .with_context(|| cannot(LOCK_NAME))?;
        }
        // Staging directories and temporary files of processes that died:
        // we hold the lock, so no live process uses them (without the lock
        // we cannot know).
        if let Some(entries) = fs::read_dir(&self.dir).ok().filter(|_| self.locked()) {
            for e in entries.flatten() {
                let name = e.file_name().to_string_lossy().into_owned();
                let Ok(t) = e.file_type() else { continue };
                if name.starts_with(STAGE_PREFIX) && t.is_dir() {
                    let _ = fs::remove_dir_all(e.path());
                } else if is_tmp_name(&name) && t.is_file() {
                    let _ = fs::remove_file(e.path());
                }
            }
        }
        {
            let mut live = live();
            live.stages
                .push((self.id, self.dir.clone(), self.stage.clone()));
            publish(&live);
        }
        let shared = self.stage.file_name().is_some_and(|n| n == STAGE_NAME);
        self.stage_existed = create_stage(&self.stage, shared)?;
        if shared {
            own_shared_stages().push(self.stage.clone());
        }
        self.manifest = read_plain(&self.dir.join(MANIFEST_NAME)).ok();
        let text = self.manifest.as_deref().unwrap_or_default();
        self.previous = manifest_names(text);
        if let (Some(&(now, force)), Some(before)) = (INVOCATION.get(), manifest_owner(text))
            && !force
            && !ADDING.contains(&now)
            && !self.previous.is_empty()
            && !may_replace(&before, now)
        {
            let n = self.previous.len();
            return Err(tippetop::Error::invalid(
                "--out",
                format!(
                    "{} holds the output of `tippetop {before}` ({n} file{}); `tippetop {now}` would remove it",
                    self.dir.display(),
                    if n == 1 { "" } else { "s" },
                ),
                "another --out, or --force to replace that output".into(),
            )
            .into());
        }
        Ok(())
    }

    /// Without the lock (a file system without locks) another process may
    /// have written the manifest since it was read: read it again.
    fn refresh_manifest(&mut self) {
        if !self.locked() {
            self.manifest = read_plain(&self.dir.join(MANIFEST_NAME)).ok();
        }
    }

    /// The output directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// The staging directory: write the command's files here (by their final
    /// names); [`OutDir::commit`] moves them into [`OutDir::dir`].
    pub fn stage(&self) -> &Path {
        &self.stage
    }

    /// Record now, in the manifest, that the command writes `names` directly
    /// into the directory (e.g. a partial file streamed as it is computed),
    /// so that a later command removes them if this one is interrupted.
    pub fn claim(&mut self, names: &[&str]) -> Result<()> {
        debug_assert!(names.iter().all(|n| is_partial_name(n)), "{names:?}");
        self.previous
            .extend(names.iter().map(|n| (n.to_string(), None)));
        self.refresh_manifest();
        write_manifest(&self.dir, &self.previous, &mut self.manifest)
    }

    /// Add to the directory rather than replace its contents: at the
    /// commit, keep the previous command's files (and list them in the
    /// manifest with the new ones), e.g. `animate` adding its files beside
    /// the run's.
    pub fn keep_previous(&mut self) {
        self.keep = true;
    }

    /// At the commit, rename `DIR/from` (a file written directly into the
    /// directory, see [`OutDir::claim`]) to `DIR/to`.
    pub fn adopt(&mut self, from: &str, to: &str) {
        self.adopted.push((from.to_string(), to.to_string()));
    }

    /// Move the staged files (and the adopted ones) into the directory, the
    /// files named in `last` after all others (and any old version of them
    /// removed first, so that e.g. an old `summary.json` never sits beside a
    /// new `trajectory.csv`); then remove the previous command's files that
    /// this one did not write, and write the manifest. Returns the names of
    /// the removed files. The manifest is rewritten first to list the old and
    /// the new files, so an interruption at any point leaves every file the
    /// tool wrote listed; a signal waits for the commit to end. A rename
    /// replaces a link at the destination (never its target); an adopted
    /// file must be a regular file ([`check_plain`]). The lock is released
    /// (its file removed) at the end.
    pub fn commit(mut self, last: &[&str]) -> Result<Vec<String>> {
        let mut names: BTreeSet<String> = BTreeSet::new();
        // Entries not moved in (hidden names, directories): the stage is
        // then removed rather than left empty.
        let mut left = false;
        for e in fs::read_dir(&self.stage)
            .with_context(|| format!("reading {}", self.stage.display()))?
        {
            let e = e.with_context(|| format!("reading {}", self.stage.display()))?;
            let name = e.file_name().to_string_lossy().into_owned();
            if !name.starts_with('.') && e.file_type().is_ok_and(|t| t.is_file()) {
                names.insert(name);
            } else {
                left = true;
            }
        }
        for (from, _) in &self.adopted {
            check_plain(&self.dir.join(from))?;
        }
        names.extend(self.adopted.iter().map(|(_, to)| to.clone()));
        let (adopted, dir, stage) = (self.adopted.clone(), self.dir.clone(), self.stage.clone());
        let source = |name: &str| -> PathBuf {
            match adopted.iter().find(|(_, to)| to == name) {
                Some((from, _)) => dir.join(from),
                None => stage.join(name),
            }
        };
        // What the manifest records of each new file, from its bytes as
        // written (the rename below moves them unchanged).
        let mut written: BTreeMap<String, Option<Record>> = BTreeMap::new();
        for name in &names {
            let record = Record::of(&source(name))
                .with_context(|| format!("reading {}", source(name).display()))?;
            written.insert(name.clone(), Some(record));
        }
        let removed = {
            // A signal from here on waits for the end of the block.
            #[cfg(unix)]
            let _committing = signals::Committing::begin();
            let _moving = live();
            let mut all = self.previous.clone();
            all.extend(written.iter().map(|(n, r)| (n.clone(), *r)));
            self.refresh_manifest();
            write_manifest(&self.dir, &all, &mut self.manifest)?;
            for l in last.iter().filter(|l| names.contains(**l)) {
                remove_if_present(&self.dir.join(l))?;
            }
            let (tail, head): (Vec<&String>, Vec<&String>) =
                names.iter().partition(|n| last.contains(&n.as_str()));
            for (k, name) in head.into_iter().chain(tail).enumerate() {
                let to = self.dir.join(name);
                fs::rename(source(name), &to)
                    .with_context(|| format!("writing {}", to.display()))?;
                if k == 0 {
                    test_signal_in_commit();
                }
            }
            let mut removed = Vec::new();
            // The list written before the move stands unless some of the
            // previous command's files are to go.
            let write_again = !self.keep && written != all;
            if self.keep {
                written = all;
            }
            for (stale, record) in &self.previous {
                if written.contains_key(stale) {
                    continue;
                }
                let p = self.dir.join(stale);
                if !fs::symlink_metadata(&p).is_ok_and(|m| !m.is_dir()) {
                    continue;
                }
                let why = match record {
                    Some(r) if Record::of(&p) == Some(*r) => None,
                    Some(_) => Some("its size or bytes are not those recorded"),
                    None if is_partial_name(stale) => None,
                    None => Some("no size and hash recorded for it"),
                };
                match why {
                    None => {
                        remove_if_present(&p)?;
                        removed.push(stale.clone());
                    }
                    Some(why) => eprintln!(
                        "note: {}: listed in {} but not as tippetop wrote it ({why}): left alone",
                        p.display(),
                        self.dir.join(MANIFEST_NAME).display()
                    ),
                }
            }
            if write_again {
                write_manifest(&self.dir, &written, &mut self.manifest)?;
            }
            removed
        };
        self.cleanup_stage(true, !left);
        self.done = true;
        Ok(removed)
    }

    /// Give up without writing anything: remove the staging directory, the
    /// lock file, and the directory if [`OutDir::open`] created it and it
    /// is empty (for an input error found only after the directory was
    /// opened).
    pub fn abandon(mut self) {
        self.cleanup();
    }

    /// Forget the staging directory, and remove it, unless it is the shared
    /// one ([`STAGE_NAME`]) and the command `committed` or found it there:
    /// then it is left, emptied unless it is known to be `empty`.
    fn cleanup_stage(&mut self, committed: bool, empty: bool) {
        let shared = self.stage.file_name().is_some_and(|n| n == STAGE_NAME);
        if shared {
            own_shared_stages().retain(|s| s != &self.stage);
        }
        if shared && (committed || self.stage_existed) {
            if !empty {
                let _ = empty_dir(&self.stage);
            }
        } else if fs::remove_dir(&self.stage).is_err()
            // Never what is not a directory (a planted link or file that
            // `create_stage` refused).
            && fs::symlink_metadata(&self.stage).is_ok_and(|m| m.is_dir())
        {
            let _ = fs::remove_dir_all(&self.stage);
        }
        let mut live = live();
        live.stages.retain(|(id, _, _)| *id != self.id);
        publish(&live);
    }

    fn cleanup(&mut self) {
        if self.done {
            return;
        }
        self.done = true;
        self.cleanup_stage(false, false);
        self.lock = None;
        if self.created_dir {
            let _ = fs::remove_dir(&self.dir);
        }
    }
}

impl Drop for OutDir {
    /// Not committed: remove the staging directory (the directory keeps the
    /// previous command's files; partial files stay); then the lock is
    /// released and its file removed.
    fn drop(&mut self) {
        if !self.done {
            self.cleanup_stage(false, false);
        }
    }
}

/// Create the staging directory `stage`, for this user alone: mode 0700
/// whatever the umask (one that takes the owner's bits away, e.g. 0277, is
/// undone), so that the files can then be written into it. The `shared`
/// one ([`STAGE_NAME`], taken under the lock) may exist already: it is
/// then emptied (of what a killed command left), and refused (exit code 2)
/// if it is a symbolic link or not a directory. Returns whether it was
/// there already. (A probe file written and removed here until 2026-11
/// cost two journal updates a run; the lock file's write already fails on
/// a full disk or quota.)
fn create_stage(stage: &Path, shared: bool) -> Result<bool> {
    let cannot = || {
        let dir = stage.parent().unwrap_or(stage);
        format!(
            "cannot write in {}: creating a staging directory",
            dir.display()
        )
    };
    #[cfg(unix)]
    use std::os::unix::fs::{DirBuilderExt, PermissionsExt};
    let mut builder = fs::DirBuilder::new();
    #[cfg(unix)]
    builder.mode(0o700);
    let existed = match builder.create(stage) {
        Ok(()) => false,
        Err(e) if shared && e.kind() == io::ErrorKind::AlreadyExists => {
            let meta = fs::symlink_metadata(stage).with_context(cannot)?;
            if !meta.is_dir() {
                let what = if meta.file_type().is_symlink() {
                    "is a symbolic link"
                } else {
                    "is not a directory"
                };
                return Err(tippetop::Error::invalid(
                    &stage.display().to_string(),
                    what.to_string(),
                    "the staging directory tippetop makes there, or nothing; remove it".into(),
                )
                .into());
            }
            empty_dir(stage).with_context(cannot)?;
            true
        }
        Err(e) => return Err(e).with_context(cannot),
    };
    #[cfg(unix)]
    if fs::symlink_metadata(stage)
        .with_context(cannot)?
        .permissions()
        .mode()
        & 0o700
        != 0o700
    {
        fs::set_permissions(stage, fs::Permissions::from_mode(0o700)).with_context(cannot)?;
    }
    Ok(existed)
}

/// Whether `stage` is a directory of another user (an output directory that
/// several users write into, in turn): a command then stages its files in a
/// directory of its own, as without the lock, and leaves that one alone.
fn foreign_stage(stage: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        // SAFETY: geteuid(2) has no preconditions.
        let me = unsafe { libc::geteuid() };
        fs::symlink_metadata(stage).is_ok_and(|m| m.is_dir() && m.uid() != me)
    }
    #[cfg(not(unix))]
    {
        let _ = stage;
        false
    }
}

/// Remove everything in the directory `dir` (links not followed).
fn empty_dir(dir: &Path) -> io::Result<()> {
    for e in fs::read_dir(dir)? {
        let e = e?;
        if e.file_type()?.is_dir() {
            fs::remove_dir_all(e.path())?;
        } else {
            fs::remove_file(e.path())?;
        }
    }
    Ok(())
}

/// `flock(file, mode | LOCK_NB)`: `Ok(true)` taken, `Ok(false)` another
/// open file description holds it (another process, or another lock of
/// this one); `Err`: the file system has no locks. The lock goes with the
/// open file and is released when the process ends, however it ends (std's
/// `File::try_lock` does the same but needs Rust 1.89, above this
/// workspace's rust-version).
#[cfg(unix)]
fn try_flock(file: &File, mode: libc::c_int) -> io::Result<bool> {
    use std::os::fd::AsRawFd;
    // SAFETY: flock on a file descriptor that `file` keeps open.
    let r = unsafe { libc::flock(file.as_raw_fd(), mode | libc::LOCK_NB) };
    if r == 0 {
        return Ok(true);
    }
    let e = io::Error::last_os_error();
    if e.kind() == io::ErrorKind::WouldBlock {
        Ok(false)
    } else {
        Err(e)
    }
}

/// Without `flock(2)` (not Unix) no lock is taken: two processes writing
/// into one directory are not detected there (they still never share a
/// temporary file, and each commits its own files as a unit).
#[cfg(not(unix))]
fn try_flock(_file: &File, _mode: i32) -> io::Result<bool> {
    Ok(true)
}

/// Take a shared lock on `dir`'s [`LOCK_NAME`] before reading files a
/// tippetop command writes there (e.g. `merge` reading a shard's
/// directory): several readers may hold it, but not while a command writes
/// into the directory. The lock file is created if missing (and removed by
/// the last reader); returns the lock (drop it to release), or `None` when
/// there is nothing to lock (a read-only directory without a lock file, or
/// a file system without locks). Errors: a command is writing into `dir`
/// (`DIR is in use by another tippetop process (pid N); wait until it
/// ends`); the lock file is a link (exit code 2).
pub fn read_lock(dir: &Path) -> Result<Option<DirLock>> {
    install_signal_cleanup();
    if !dir.is_dir() {
        return Ok(None);
    }
    match take_lock(dir, false)? {
        Taken::Lock(l) if l.held => Ok(Some(l)),
        Taken::Lock(_) | Taken::Absent => Ok(None),
        Taken::Busy(pid) => bail!(
            "{} is in use by another tippetop process (pid {pid}); wait until it ends",
            dir.display(),
        ),
    }
}

/// The process id written in a lock file held by another process, or
/// "unknown" if it has not written it yet.
fn lock_holder(lock: &File) -> String {
    for _ in 0..20 {
        let mut s = String::new();
        let mut f = lock;
        if f.rewind().is_ok() && f.read_to_string(&mut s).is_ok() && !s.trim().is_empty() {
            return s.trim().to_string();
        }
        std::thread::sleep(std::time::Duration::from_millis(10));
    }
    "unknown".to_string()
}

/// Remove `path`; a file that is already gone is fine.
fn remove_if_present(path: &Path) -> Result<()> {
    match fs::remove_file(path) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => {
            Err(e).with_context(|| format!("removing {}", path.display()))
        }
        _ => Ok(()),
    }
}

/// The file names listed in `DIR/`[`MANIFEST_NAME`] (none if it is missing,
/// unreadable or a link). Only plain names are accepted: no path separator,
/// not `.` or `..`, not the tool's own hidden files, so a manifest can never
/// make the tool remove anything outside the directory.
pub fn read_manifest(dir: &Path) -> BTreeSet<String> {
    manifest_names(&read_plain(&dir.join(MANIFEST_NAME)).unwrap_or_default())
        .into_keys()
        .collect()
}

/// The file names a manifest's text lists, each with its [`Record`] if the
/// line has one (see [`read_manifest`], [`MANIFEST_NAME`]).
fn manifest_names(bytes: &[u8]) -> BTreeMap<String, Option<Record>> {
    String::from_utf8_lossy(bytes)
        .lines()
        .map(|l| {
            let f: Vec<&str> = l.split('\t').collect();
            let record = match f.as_slice() {
                [_, size, hash] => size.parse().ok().zip(
                    (hash.len() == 16)
                        .then(|| u64::from_str_radix(hash, 16).ok())
                        .flatten(),
                ),
                _ => None,
            };
            match record {
                Some((size, hash)) => (f[0].trim(), Some(Record { size, hash })),
                None => (l.trim(), None),
            }
        })
        .filter(|(l, _)| {
            !l.is_empty()
                && !l.starts_with('#')
                && !l.starts_with(".tippetop")
                && *l != "."
                && *l != ".."
                && !l.contains(['/', '\\', '\t'])
        })
        .map(|(l, r)| (l.to_string(), r))
        .collect()
}

/// The subcommand that wrote `DIR/`[`MANIFEST_NAME`] (its `# command:`
/// line), if it says.
pub fn manifest_command(dir: &Path) -> Option<String> {
    manifest_owner(&read_plain(&dir.join(MANIFEST_NAME)).ok()?)
}

/// The `# command:` line of a manifest's text (see [`manifest_command`]).
fn manifest_owner(bytes: &[u8]) -> Option<String> {
    String::from_utf8_lossy(bytes)
        .lines()
        .find_map(|l| l.strip_prefix("# command: "))
        .map(|c| c.trim().to_string())
        .filter(|c| !c.is_empty())
}

/// Write `DIR/`[`MANIFEST_NAME`] listing `names`, atomically, with the
/// subcommand that writes them (an adding one, `animate`, keeps the
/// owner's name). `current`: the manifest's bytes as this process last
/// read or wrote them (`None`: there is none), updated here.
fn write_manifest(
    dir: &Path,
    names: &BTreeMap<String, Option<Record>>,
    current: &mut Option<Vec<u8>>,
) -> Result<()> {
    let owner_before = || current.as_deref().and_then(manifest_owner);
    let mut text = String::from(
        "# tippetop: the files the last command wrote into this directory (the next one removes those it does not write)\n",
    );
    let owner = match INVOCATION.get() {
        Some((now, _)) if ADDING.contains(now) => owner_before(),
        Some((now, _)) => Some(now.to_string()),
        None => owner_before(),
    };
    if let Some(c) = owner {
        text.push_str(&format!("# command: {c}\n"));
    }
    for (n, record) in names {
        text.push_str(n);
        if let Some(r) = record {
            text.push_str(&format!("\t{}\t{:016x}", r.size, r.hash));
        }
        text.push('\n');
    }
    let path = dir.join(MANIFEST_NAME);
    // Already this text (the same command run again into the directory):
    // left as it is. Replacing a file by a rename costs a flush of the new
    // one on ext4 (`auto_da_alloc`), ~0.3 ms a run.
    if current.as_deref() == Some(text.as_bytes()) {
        return Ok(());
    }
    write_bytes_atomic(&path, text.as_bytes())?;
    *current = Some(text.into_bytes());
    Ok(())
}

/// Print `value` as pretty JSON on stdout (the `--json` output of the
/// report commands).
pub fn print_json<T: Serialize + ?Sized>(value: &T) -> Result<()> {
    println!(
        "{}",
        serde_json::to_string_pretty(value).context("serialising the report")?
    );
    Ok(())
}

/// The `summary.json` document of a run: every [`Summary`] field at the top
/// level, plus `wall_seconds`, the resolved `scenario` (as TOML text) and the
/// `events`.
#[derive(Debug, Serialize)]
pub struct SummaryDoc<'a> {
    /// The library's summary, flattened into the top level.
    #[serde(flatten)]
    pub summary: &'a Summary,
    /// Wall-clock time of the simulation \[s\].
    pub wall_seconds: f64,
    /// The resolved scenario as TOML (what `scenario.toml` holds).
    pub scenario: &'a str,
    /// Events in time order, each `{t, kind}`.
    pub events: &'a [EventRecord],
    /// The regime the scenario is in (`tippetop regime`; without a
    /// temperature, so the thermal ratios are null).
    pub regime: Option<tippetop::analysis::regime::Regime>,
}

impl<'a> SummaryDoc<'a> {
    /// The document for `traj`. If the run failed and the library left
    /// `status` at `"ok"`, the caller should pass a summary whose `status`
    /// is the error (see [`summary_with_status`]).
    pub fn new(
        summary: &'a Summary,
        events: &'a [EventRecord],
        scenario_toml: &'a str,
        wall_seconds: f64,
    ) -> Self {
        SummaryDoc {
            summary,
            wall_seconds,
            scenario: scenario_toml,
            events,
            regime: None,
        }
    }

    /// The same document with the scenario's regime.
    pub fn with_regime(mut self, regime: tippetop::analysis::regime::Regime) -> Self {
        self.regime = Some(regime);
        self
    }
}

/// `traj.summary`, with `status` set to the run-time error's message when the
/// run failed (and the library did not already say so).
pub fn summary_with_status(traj: &Trajectory) -> Summary {
    let mut s = traj.summary.clone();
    if let Some(e) = &traj.error {
        if s.status.is_empty() || s.status == "ok" {
            s.status = e.to_string();
        }
    }
    s
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use tippetop::{Error, Sample};

    /// A hand-built trajectory (simulate is not available to unit tests):
    /// `n` samples over `[0, t_end]` of a top that flips from 0.1 to ~π.
    pub(crate) fn fake_trajectory(n: usize, t_end: f64, failed: bool) -> Trajectory {
        let samples: Vec<Sample> = (0..n)
            .map(|i| {
                let t = t_end * i as f64 / (n - 1) as f64;
                let x = t / t_end;
                let theta = 0.1 + (std::f64::consts::PI - 0.15) / (1.0 + (-12.0 * (x - 0.5)).exp());
                Sample {
                    t,
                    theta,
                    theta_dot: 0.3 * (20.0 * x).sin(),
                    precession: 150.0 * (x * 3.0).sin(),
                    spin: 100.0 * (1.0 - 1.8 * x),
                    ux: 1e-12 * x,
                    uy: -1e-12 * x,
                    uz: 0.0,
                    normal: 1.172e-23 * (1.0 + 0.2 * (30.0 * x).sin()),
                    slip: 1e-10 * (1.0 - x),
                    jellett: 3.0e-40 * (1.0 + 1e-9 * (5.0 * x).sin()),
                    energy: 1.0e-20 - 2e-21 * x,
                    work_friction: -2e-21 * x,
                    work_applied: 0.0,
                    hx: 1e-22,
                    hy: 1e-22,
                    rolling: u8::from(i % 7 == 0),
                    x: 2e-12 * x,
                    y: -3e-12 * x * x,
                    z: 1.5e-7 - 1e-8 * x,
                    qw: (0.5 * theta).cos(),
                    qx: 0.0,
                    qy: (0.5 * theta).sin(),
                    qz: 0.0,
                    xp: 2e-12 * x + 3e-8 * theta.sin(),
                    yp: -3e-12 * x * x,
                }
            })
            .collect();
        let last = *samples.last().unwrap();
        let error = failed.then(|| {
            Error::runtime(
                last.t,
                tippetop::Failure::StepUnderflow,
                "step size underflow",
            )
        });
        Trajectory {
            events: vec![EventRecord {
                t: 0.5 * t_end,
                kind: "theta_above_half_pi".into(),
            }],
            summary: Summary {
                t_end: last.t,
                theta_final: last.theta,
                theta_max: last.theta,
                omega_final: last.spin,
                precession_final: last.precession,
                jellett_initial: samples[0].jellett,
                jellett_max_rel_drift: 1.2e-9,
                energy_initial: samples[0].energy,
                energy_final: last.energy,
                energy_balance_max_rel_error: 3e-11,
                first_time_theta_above_half_pi: Some(0.5 * t_end),
                contact_lost_at: None,
                negative_normal_fraction: 0.0,
                rolling_fraction: 0.14,
                stem: None,
                pull_off_margin_min: None,
                normal_intervals: None,
                steps: 1234,
                rejected_steps: 5,
                rhs_evaluations: 15000,
                status: "ok".into(),
                failure: error.as_ref().and_then(|e| e.failure()).map(|f| f.as_str()),
            },
            samples,
            error,
        }
    }

    /// Three significant figures, in ms below a second: never "0.0 s".
    #[test]
    fn durations_have_three_significant_figures() {
        for (s, want) in [
            (0.0123, "12.3 ms"),
            (0.000_456_7, "0.457 ms"),
            (0.5, "500 ms"),
            (0.9996, "1000 ms"),
            (1.234, "1.23 s"),
            (9.996, "10.0 s"),
            (12.34, "12.3 s"),
            (123.4, "123 s"),
            (5432.1, "5432 s"),
            (1.2e-7, "0.000120 ms"),
            (0.0, "0 ms"),
        ] {
            assert_eq!(fmt_duration(s), want, "{s}");
        }
    }

    #[test]
    fn floats_round_trip_exactly() {
        let cases = [
            1.196e-24,
            0.1,
            -3.0e7,
            5e-324,
            1e300,
            f64::MAX,
            f64::MIN_POSITIVE,
            -0.0,
            0.0,
            std::f64::consts::PI,
            1.0 / 3.0,
            2.0f64.sqrt() * 1e-10,
            123_456_789.123_456_79,
        ];
        for v in cases {
            let s = fmt_f64(v);
            let back: f64 = s.parse().unwrap();
            assert_eq!(back.to_bits(), v.to_bits(), "{v:e} -> {s}");
        }
        assert_eq!(fmt_f64(0.1), "0.1");
        assert_eq!(fmt_f64(1.196e-24), "1.196e-24");
        assert_eq!(fmt_f64(5e-324), "5e-324");
        assert_eq!(fmt_f64(1e300), "1e+300");
        for v in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let back: f64 = fmt_f64(v).parse().unwrap();
            assert!(back.is_nan() == v.is_nan() && (v.is_nan() || back == v));
        }
    }

    #[test]
    fn atomic_write_replaces_and_leaves_no_tmp() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_bytes_atomic(&p, b"first").unwrap();
        write_bytes_atomic(&p, b"second").unwrap();
        assert_eq!(fs::read_to_string(&p).unwrap(), "second");
        let names: Vec<_> = fs::read_dir(dir.path()).unwrap().collect();
        assert_eq!(names.len(), 1);
    }

    /// Two writers (two processes, or two writes of one process) never share
    /// a temporary file: the name has the process id and a counter. Before,
    /// every writer of `DIR/NAME` used `DIR/.NAME.tmp`.
    #[test]
    fn tmp_names_are_unique_per_process_and_write() {
        let p = Path::new("/some/dir/summary.json");
        let (a, b) = (tmp_path(p), tmp_path(p));
        assert_ne!(a, b);
        let pid = std::process::id().to_string();
        for t in [&a, &b] {
            let name = t.file_name().unwrap().to_string_lossy().into_owned();
            assert!(name.starts_with(".summary.json.") && name.ends_with(".tmp"));
            assert!(name.contains(&pid), "{name}");
            assert_eq!(t.parent(), p.parent());
        }
    }

    fn listing(dir: &Path) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }

    /// A second `OutDir` on a directory in use fails at once, naming the
    /// holder's pid; it touches nothing; once the first is gone it works.
    #[test]
    fn out_dir_lock_refuses_a_second_writer() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let first = OutDir::open(&dir).unwrap();
        assert_eq!(
            fs::read_to_string(dir.join(LOCK_NAME)).unwrap().trim(),
            std::process::id().to_string()
        );
        let before = listing(&dir);
        let err = OutDir::open(&dir).unwrap_err().to_string();
        assert_eq!(
            err,
            format!(
                "{} is in use by another tippetop process (pid {}); choose another --out or wait until it ends",
                dir.display(),
                std::process::id()
            )
        );
        assert_eq!(listing(&dir), before);
        drop(first);
        let again = OutDir::open(&dir).unwrap();
        again.commit(&[]).unwrap();
    }

    /// Readers (merge reading a shard) share a lock that excludes a writer,
    /// both ways; a directory no tippetop wrote has nothing to lock.
    #[test]
    fn read_lock_excludes_writers() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        // Nothing to lock where there is no directory.
        assert!(read_lock(&dir).unwrap().is_none());
        let writer = OutDir::open(&dir).unwrap();
        let err = read_lock(&dir).unwrap_err().to_string();
        assert!(
            err.contains(&format!(
                "in use by another tippetop process (pid {})",
                std::process::id()
            )),
            "{err}"
        );
        writer.commit(&[]).unwrap();
        // The writer removed its lock file at the end; readers make one.
        assert!(!dir.join(LOCK_NAME).exists());
        let r1 = read_lock(&dir).unwrap();
        let r2 = read_lock(&dir).unwrap();
        assert!(r1.is_some() && r2.is_some());
        assert!(OutDir::open(&dir).is_err());
        // The first reader to leave leaves the file to the other.
        drop(r1);
        assert!(dir.join(LOCK_NAME).exists());
        assert!(OutDir::open(&dir).is_err());
        drop(r2);
        assert!(!dir.join(LOCK_NAME).exists());
        OutDir::open(&dir).unwrap();
        assert!(!dir.join(LOCK_NAME).exists());
    }

    /// The commit moves the staged files in, removes the previous command's
    /// files that this one did not write (only those: a user's file stays),
    /// and lists the new files in the manifest.
    #[test]
    fn out_dir_commit_replaces_the_previous_run_as_a_unit() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let out = OutDir::open(&dir).unwrap();
        for name in ["trajectory.csv", "theta.png", "summary.json"] {
            write_bytes_atomic(&out.stage().join(name), b"old").unwrap();
        }
        assert!(out.commit(&["summary.json"]).unwrap().is_empty());
        fs::write(dir.join("notes.txt"), "mine").unwrap();
        assert_eq!(
            read_manifest(&dir).into_iter().collect::<Vec<_>>(),
            ["summary.json", "theta.png", "trajectory.csv"]
        );

        let out = OutDir::open(&dir).unwrap();
        for name in ["trajectory.csv", "summary.json"] {
            write_bytes_atomic(&out.stage().join(name), b"new").unwrap();
        }
        assert_eq!(out.commit(&["summary.json"]).unwrap(), ["theta.png"]);
        assert_eq!(
            listing(&dir),
            [
                ".tippetop-manifest",
                ".tippetop-stage",
                "notes.txt",
                "summary.json",
                "trajectory.csv"
            ]
        );
        assert_eq!(
            fs::read_to_string(dir.join("trajectory.csv")).unwrap(),
            "new"
        );
        assert_eq!(fs::read_to_string(dir.join("notes.txt")).unwrap(), "mine");
    }

    /// A write that fails before the commit leaves the directory exactly as
    /// the previous run left it: never a new trajectory.csv beside an old
    /// summary.json (before, each file was renamed into place as written).
    #[test]
    fn out_dir_failed_write_leaves_the_previous_run() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let out = OutDir::open(&dir).unwrap();
        for name in ["trajectory.csv", "summary.json"] {
            write_bytes_atomic(&out.stage().join(name), b"old").unwrap();
        }
        out.commit(&["summary.json"]).unwrap();
        let before = listing(&dir);

        let result = (|| -> Result<()> {
            let out = OutDir::open(&dir)?;
            write_bytes_atomic(&out.stage().join("trajectory.csv"), b"new")?;
            write_atomic(&out.stage().join("summary.json"), |w| {
                w.write_all(b"{")?;
                Err(io::Error::other("disk full"))
            })?;
            out.commit(&["summary.json"])?;
            Ok(())
        })();
        assert!(format!("{:#}", result.unwrap_err()).contains("disk full"));
        assert_eq!(listing(&dir), before);
        for name in ["trajectory.csv", "summary.json"] {
            assert_eq!(fs::read_to_string(dir.join(name)).unwrap(), "old");
        }
    }

    /// In the stage a file is written in place (no temporary file), and a
    /// write that fails or panics removes it, so that a commit after a
    /// failed write tolerated by its command (a plot, say) moves in no
    /// partial file. The stage is the user's alone (mode 0700).
    #[test]
    fn stage_writes_in_place_and_removes_a_failed_write() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let out = OutDir::open(&dir).unwrap();
        let stage = out.stage().to_path_buf();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let mode = fs::metadata(&stage).unwrap().permissions().mode();
            assert_eq!(mode & 0o777, 0o700, "{mode:o}");
        }
        assert!(in_own_stage(&stage.join("a.csv")));
        assert!(!in_own_stage(&dir.join("a.csv")));
        assert!(!in_own_stage(
            &dir.join(format!("{STAGE_PREFIX}1-0badf00d")).join("a.csv")
        ));
        write_bytes_atomic(&stage.join("a.csv"), b"a").unwrap();
        let failed = write_atomic(&stage.join("b.png"), |w| {
            w.write_all(&[7; 20_000])?;
            Err(io::Error::other("disk full"))
        });
        assert!(format!("{:#}", failed.unwrap_err()).contains("disk full"));
        let panicked = std::panic::catch_unwind(|| {
            let _ = write_atomic(&stage.join("c.svg"), |w| {
                w.write_all(&[7; 20_000])?;
                panic!("a plot panicked")
            });
        });
        assert!(panicked.is_err());
        // Only the finished file, and no temporary one.
        assert_eq!(listing(&stage), ["a.csv"]);
        out.commit(&[]).unwrap();
        assert_eq!(listing(&dir), [MANIFEST_NAME, STAGE_NAME, "a.csv"]);
        // Left empty, and no longer this process's: written through a
        // temporary file again.
        assert!(listing(&stage).is_empty());
        assert!(!in_own_stage(&stage.join("a.csv")));
    }

    /// Another user's shared stage (a directory several users write into) is
    /// left alone: the command stages in a directory of its own, removed at
    /// the end. Needs root (to give the stage away); skipped otherwise.
    #[cfg(unix)]
    #[test]
    fn another_users_shared_stage_is_left_alone() {
        // SAFETY: geteuid(2) has no preconditions.
        if unsafe { libc::geteuid() } != 0 {
            eprintln!("skipped: needs root to give a directory to another user");
            return;
        }
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let stage = dir.join(STAGE_NAME);
        fs::create_dir_all(&stage).unwrap();
        fs::write(stage.join("theirs.csv"), "x").unwrap();
        std::os::unix::fs::chown(&stage, Some(54_321), Some(54_321)).unwrap();
        let out = OutDir::open(&dir).unwrap();
        assert_ne!(out.stage(), stage);
        assert!(
            out.stage()
                .file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(STAGE_PREFIX)
        );
        write_bytes_atomic(&out.stage().join("a.csv"), b"a").unwrap();
        out.commit(&[]).unwrap();
        assert_eq!(listing(&dir), [MANIFEST_NAME, STAGE_NAME, "a.csv"]);
        assert_eq!(listing(&stage), ["theirs.csv"]);
    }

    /// The shared stage is created by the first command, left empty by each
    /// commit, emptied of what a killed command left by the next one, left
    /// (emptied) by a command that fails if it was there before and removed
    /// if that command created it; a link or a file in its place is refused
    /// (exit code 2) and left alone.
    #[test]
    fn the_shared_stage_is_reused_emptied_and_never_followed() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let stage = dir.join(STAGE_NAME);
        // A command that fails in a new directory leaves nothing.
        fs::create_dir(&dir).unwrap();
        let out = OutDir::open(&dir).unwrap();
        write_bytes_atomic(&out.stage().join("a.csv"), b"a").unwrap();
        drop(out);
        assert!(listing(&dir).is_empty());
        // Created, then left empty by the commit.
        let out = OutDir::open(&dir).unwrap();
        assert_eq!(out.stage(), stage);
        write_bytes_atomic(&stage.join("a.csv"), b"a").unwrap();
        out.commit(&[]).unwrap();
        assert!(listing(&stage).is_empty());
        // What a killed command left in it (a file, a directory of plots)
        // is gone when the next command takes it.
        fs::write(stage.join("trajectory.csv"), "half").unwrap();
        fs::create_dir(stage.join("frames")).unwrap();
        fs::write(stage.join("frames").join("0.png"), "x").unwrap();
        let out = OutDir::open(&dir).unwrap();
        assert!(listing(&stage).is_empty());
        // A failed command leaves it as it found it: there, empty.
        write_bytes_atomic(&stage.join("b.csv"), b"b").unwrap();
        out.abandon();
        assert_eq!(listing(&dir), [MANIFEST_NAME, STAGE_NAME, "a.csv"]);
        assert!(listing(&stage).is_empty());
        // What a commit does not move in is removed.
        let out = OutDir::open(&dir).unwrap();
        fs::create_dir(stage.join("sub")).unwrap();
        fs::write(stage.join(".hidden"), "x").unwrap();
        out.commit(&[]).unwrap();
        assert!(listing(&stage).is_empty());
        fs::remove_dir(&stage).unwrap();
        // Something else in its place.
        let elsewhere = tmp.path().join("elsewhere");
        fs::create_dir(&elsewhere).unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(&elsewhere, &stage).unwrap();
            let e = OutDir::open(&dir).unwrap_err();
            let msg = format!("{e:#}");
            assert!(e.downcast_ref::<tippetop::Error>().is_some(), "{msg}");
            assert!(msg.contains("is a symbolic link"), "{msg}");
            assert!(
                fs::symlink_metadata(&stage)
                    .unwrap()
                    .file_type()
                    .is_symlink()
            );
            assert!(listing(&elsewhere).is_empty());
            fs::remove_file(&stage).unwrap();
        }
        fs::write(&stage, "mine").unwrap();
        let e = OutDir::open(&dir).unwrap_err();
        assert!(format!("{e:#}").contains("is not a directory"), "{e:#}");
        assert_eq!(fs::read_to_string(&stage).unwrap(), "mine");
        assert!(!dir.join(LOCK_NAME).exists());
    }

    /// Claimed files (streamed straight into the directory) are in the
    /// manifest at once, so a later command removes them; adopted files are
    /// renamed into place at the commit.
    #[test]
    fn out_dir_claim_and_adopt() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let mut out = OutDir::open(&dir).unwrap();
        out.claim(&["x.partial"]).unwrap();
        fs::write(dir.join("x.partial"), "rows").unwrap();
        assert!(read_manifest(&dir).contains("x.partial"));
        drop(out); // interrupted
        let out = OutDir::open(&dir).unwrap();
        assert_eq!(out.commit(&[]).unwrap(), ["x.partial"]);
        assert!(!dir.join("x.partial").exists());

        let mut out = OutDir::open(&dir).unwrap();
        out.claim(&["x.partial"]).unwrap();
        fs::write(dir.join("x.partial"), "rows").unwrap();
        out.adopt("x.partial", "x");
        out.commit(&["x"]).unwrap();
        assert_eq!(fs::read_to_string(dir.join("x")).unwrap(), "rows");
        assert_eq!(read_manifest(&dir).into_iter().collect::<Vec<_>>(), ["x"]);
    }

    /// Abandoning (an input error found after `open`) leaves nothing that
    /// `open` created; a manifest cannot name a path outside the directory.
    #[test]
    fn out_dir_abandon_and_safe_manifest() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("new");
        OutDir::open(&dir).unwrap().abandon();
        assert!(!dir.exists());
        let old = tmp.path().join("old");
        fs::create_dir(&old).unwrap();
        OutDir::open(&old).unwrap().abandon();
        assert!(listing(&old).is_empty());

        fs::write(tmp.path().join("victim"), "keep").unwrap();
        fs::write(
            old.join(MANIFEST_NAME),
            "# x\n../victim\n/etc/passwd\n.\n..\n.tippetop.lock\nok.txt\n",
        )
        .unwrap();
        assert_eq!(
            read_manifest(&old).into_iter().collect::<Vec<_>>(),
            ["ok.txt"]
        );
        OutDir::open(&old).unwrap().commit(&[]).unwrap();
        assert_eq!(
            fs::read_to_string(tmp.path().join("victim")).unwrap(),
            "keep"
        );
    }

    /// A directory that cannot be created or written is an error at `open`
    /// (before anything is computed): a path under a regular file, and (when
    /// not running as root, which ignores permissions) a read-only directory.
    #[test]
    fn out_dir_unwritable_fails_at_open() {
        let tmp = tempfile::tempdir().unwrap();
        let file = tmp.path().join("file");
        fs::write(&file, "x").unwrap();
        // A path that is a file, or under one: bad input (exit code 2).
        for p in [file.clone(), file.join("sub")] {
            let e = OutDir::open(&p).unwrap_err();
            let te = e.downcast_ref::<tippetop::Error>().expect("an input error");
            assert!(
                te.is_input() && te.to_string().starts_with("--out: "),
                "{te}"
            );
        }
        assert_eq!(listing(tmp.path()), ["file"]);
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            let ro = tmp.path().join("ro");
            fs::create_dir(&ro).unwrap();
            fs::set_permissions(&ro, fs::Permissions::from_mode(0o555)).unwrap();
            // Root writes anyway: nothing to test then.
            if fs::write(ro.join("t"), "").is_err() {
                let err = format!("{:#}", OutDir::open(&ro).unwrap_err());
                assert!(err.starts_with("cannot write in "), "{err}");
                assert!(listing(&ro).is_empty());
            }
            fs::set_permissions(&ro, fs::Permissions::from_mode(0o755)).unwrap();
        }
    }

    /// Issue 26: a link planted where the lock file goes made `run` write
    /// its pid into the link's target. Now the lock is opened without
    /// following links: bad input (exit code 2, the file named), the target
    /// untouched, nothing left behind.
    #[cfg(unix)]
    #[test]
    fn a_planted_lock_link_is_refused() {
        let tmp = tempfile::tempdir().unwrap();
        let victim = tmp.path().join("victim");
        fs::write(&victim, "keep").unwrap();
        for existing in [false, true] {
            let dir = tmp.path().join(format!("out{existing}"));
            fs::create_dir(&dir).unwrap();
            if existing {
                std::os::unix::fs::symlink(&victim, dir.join(LOCK_NAME)).unwrap();
            } else {
                // A dangling link: creating through it would make the target.
                std::os::unix::fs::symlink(tmp.path().join("new"), dir.join(LOCK_NAME)).unwrap();
            }
            let e = OutDir::open(&dir).unwrap_err();
            let te = e.downcast_ref::<tippetop::Error>().expect("an input error");
            assert!(te.is_input(), "{te}");
            assert!(
                te.to_string()
                    .contains(".tippetop.lock: is a symbolic link"),
                "{te}"
            );
            assert!(read_lock(&dir).is_err());
            assert_eq!(listing(&dir), [LOCK_NAME]);
        }
        assert_eq!(fs::read_to_string(&victim).unwrap(), "keep");
        assert!(!tmp.path().join("new").exists());
    }

    /// Issue 26: the lock file stayed in every output directory. Now it is
    /// removed at the end (commit, abandon, drop), and one left by a
    /// process that no longer exists (kill -9: the OS released its lock)
    /// is taken over.
    #[test]
    fn the_lock_file_is_removed_at_the_end_and_a_dead_ones_taken_over() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        OutDir::open(&dir).unwrap().commit(&[]).unwrap();
        assert!(!dir.join(LOCK_NAME).exists());
        drop(OutDir::open(&dir).unwrap());
        assert!(!dir.join(LOCK_NAME).exists());
        OutDir::open(&dir).unwrap().abandon();
        assert!(!dir.join(LOCK_NAME).exists());
        // What a killed process leaves: its lock file (pid inside, no OS
        // lock), its staging directory and a temporary file.
        fs::write(dir.join(LOCK_NAME), "999999999\n").unwrap();
        let stage = dir.join(format!("{STAGE_PREFIX}999999999-0badf00d"));
        fs::create_dir(&stage).unwrap();
        fs::write(stage.join("big.csv"), "x").unwrap();
        fs::write(dir.join(".sweep.csv.999999999-0badf00d-3.tmp"), "x").unwrap();
        let out = OutDir::open(&dir).unwrap();
        assert_eq!(
            fs::read_to_string(dir.join(LOCK_NAME)).unwrap().trim(),
            std::process::id().to_string()
        );
        assert!(!stage.exists());
        assert!(!dir.join(".sweep.csv.999999999-0badf00d-3.tmp").exists());
        out.commit(&[]).unwrap();
        assert_eq!(listing(&dir), [MANIFEST_NAME, STAGE_NAME]);
    }

    /// The re-check after locking: a file opened before the holder removed
    /// it no longer is the lock file (the path names another file or none),
    /// so whoever locks it late knows to start again.
    #[cfg(unix)]
    #[test]
    fn a_removed_lock_file_is_told_from_the_new_one() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        let first = OutDir::open(&dir).unwrap();
        let late = File::open(dir.join(LOCK_NAME)).unwrap();
        assert!(same_file(&late, &dir.join(LOCK_NAME)));
        drop(first);
        assert!(!same_file(&late, &dir.join(LOCK_NAME)));
        // The OS lock on the old file is free now...
        assert!(try_flock(&late, libc::LOCK_EX).unwrap());
        // ...but it is not the directory's lock: a new writer gets in, and
        // while it holds the lock no second one does.
        let second = OutDir::open(&dir).unwrap();
        assert!(!same_file(&late, &dir.join(LOCK_NAME)));
        assert!(OutDir::open(&dir).is_err());
        drop(second);
    }

    /// Issue 26: writes followed links. `write_atomic` now replaces a link
    /// at the destination (the target stays as it was), and its temporary
    /// file is created anew (`O_EXCL | O_NOFOLLOW`).
    #[cfg(unix)]
    #[test]
    fn atomic_write_replaces_a_link_not_its_target() {
        let tmp = tempfile::tempdir().unwrap();
        let victim = tmp.path().join("victim");
        fs::write(&victim, "keep").unwrap();
        let p = tmp.path().join("sweep.csv");
        std::os::unix::fs::symlink(&victim, &p).unwrap();
        write_bytes_atomic(&p, b"new").unwrap();
        assert!(fs::symlink_metadata(&p).unwrap().is_file());
        assert_eq!(fs::read_to_string(&p).unwrap(), "new");
        assert_eq!(fs::read_to_string(&victim).unwrap(), "keep");
    }

    /// `open_plain` and `check_plain` refuse a link (to a file, or
    /// dangling) and a FIFO (without blocking on it), as bad input; a
    /// regular file or nothing is fine.
    #[cfg(unix)]
    #[test]
    fn plain_files_only() {
        let tmp = tempfile::tempdir().unwrap();
        let victim = tmp.path().join("victim");
        fs::write(&victim, "keep").unwrap();
        let link = tmp.path().join("link");
        std::os::unix::fs::symlink(&victim, &link).unwrap();
        let dangling = tmp.path().join("dangling");
        std::os::unix::fs::symlink(tmp.path().join("none"), &dangling).unwrap();
        let fifo = tmp.path().join("fifo");
        let c = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
        // SAFETY: mkfifo with a valid C string.
        assert_eq!(unsafe { libc::mkfifo(c.as_ptr(), 0o644) }, 0);
        for p in [&link, &dangling, &fifo] {
            for e in [
                check_plain(p).unwrap_err(),
                open_plain(p, OpenOptions::new().write(true).create(true)).unwrap_err(),
                read_plain(p).unwrap_err(),
            ] {
                let te = e.downcast_ref::<tippetop::Error>().expect("an input error");
                assert!(te.is_input(), "{te}");
            }
        }
        assert_eq!(fs::read_to_string(&victim).unwrap(), "keep");
        assert!(!tmp.path().join("none").exists());
        check_plain(&victim).unwrap();
        check_plain(&tmp.path().join("nothing")).unwrap();
        assert_eq!(read_plain(&victim).unwrap(), b"keep");
    }

    /// A manifest planted as a link (to a list naming the user's files) is
    /// not read: the commit removes nothing it lists, and replaces the link
    /// with the directory's own manifest (the target untouched).
    #[cfg(unix)]
    #[test]
    fn a_manifest_link_is_not_followed() {
        let tmp = tempfile::tempdir().unwrap();
        let dir = tmp.path().join("out");
        fs::create_dir(&dir).unwrap();
        fs::write(dir.join("mine.txt"), "mine").unwrap();
        let list = tmp.path().join("list");
        fs::write(&list, "# x\nmine.txt\n").unwrap();
        std::os::unix::fs::symlink(&list, dir.join(MANIFEST_NAME)).unwrap();
        assert!(read_manifest(&dir).is_empty());
        let out = OutDir::open(&dir).unwrap();
        write_bytes_atomic(&out.stage().join("a.csv"), b"a").unwrap();
        assert!(out.commit(&[]).unwrap().is_empty());
        assert_eq!(fs::read_to_string(dir.join("mine.txt")).unwrap(), "mine");
        assert_eq!(fs::read_to_string(&list).unwrap(), "# x\nmine.txt\n");
        assert!(
            fs::symlink_metadata(dir.join(MANIFEST_NAME))
                .unwrap()
                .is_file()
        );
        assert_eq!(
            read_manifest(&dir).into_iter().collect::<Vec<_>>(),
            ["a.csv"]
        );
    }

    #[test]
    fn tmp_names_are_recognised() {
        let t = tmp_path(Path::new("/d/sweep.csv"));
        assert!(is_tmp_name(&t.file_name().unwrap().to_string_lossy()));
        for name in [
            ".sweep.csv.partial",
            "sweep.csv",
            ".a.1-2-3.tmp",
            ".a.x-0badf00d-3.tmp",
        ] {
            assert!(!is_tmp_name(name), "{name}");
        }
    }

    #[test]
    fn atomic_write_failure_keeps_old_file() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.txt");
        write_bytes_atomic(&p, b"old").unwrap();
        let err = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        })
        .unwrap_err();
        assert!(format!("{err:#}").contains("boom"));
        assert_eq!(fs::read_to_string(&p).unwrap(), "old");
        assert_eq!(
            fs::read_dir(dir.path()).unwrap().count(),
            1,
            "a tmp file was left"
        );
        // A missing directory is an error, not a panic.
        assert!(write_bytes_atomic(&dir.path().join("no/such/file"), b"x").is_err());
    }

    #[test]
    fn trajectory_csv_round_trips() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("trajectory.csv");
        let traj = fake_trajectory(11, 1e-4, false);
        write_trajectory_csv(&p, &traj).unwrap();
        let text = fs::read_to_string(&p).unwrap();
        let mut lines = text.lines();
        let header = lines.next().unwrap();
        assert!(header.starts_with("t,theta,theta_dot,Omega,omega,ux,uy,uz,N,slip,J,energy"));
        assert_eq!(header, COLUMNS.join(","));
        let rows: Vec<&str> = lines.collect();
        assert_eq!(rows.len(), traj.samples.len());
        for (row, s) in rows.iter().zip(&traj.samples) {
            let fields: Vec<&str> = row.split(',').collect();
            assert_eq!(fields.len(), COLUMNS.len());
            let vals = s.values();
            for (f, v) in fields.iter().zip(vals) {
                assert_eq!(f.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{f}");
            }
            let rolling = COLUMNS.iter().position(|c| *c == "rolling").unwrap();
            assert!(matches!(fields[rolling], "0" | "1"));
        }
    }

    #[test]
    fn series_csv_missing_and_mismatch() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("fig.csv");
        let t = [0.0, 0.5, 1.0];
        let a = [1.196e-24, f64::NAN, -3.0e7];
        write_series_csv(&p, &["t", "a"], &[&t, &a]).unwrap();
        assert_eq!(
            fs::read_to_string(&p).unwrap(),
            "t,a\n0.0,1.196e-24\n0.5,\n1.0,-30000000.0\n"
        );
        let short = [1.0];
        assert!(write_series_csv(&p, &["t", "b"], &[&t, &short]).is_err());
        assert!(write_series_csv(&p, &["t"], &[&t, &a]).is_err());
        assert!(write_series_csv(&p, &["t", "a,b"], &[&t, &a]).is_err());
        // The failed writes left the good file alone.
        assert!(fs::read_to_string(&p).unwrap().starts_with("t,a\n"));
    }

    #[test]
    fn summary_doc_has_all_fields() {
        let traj = fake_trajectory(5, 1.0, true);
        let summary = summary_with_status(&traj);
        assert!(summary.status.contains("step size underflow"));
        let doc = SummaryDoc::new(&summary, &traj.events, "[top]\nradius = 0.015\n", 0.25);
        let v = serde_json::to_value(&doc).unwrap();
        for key in [
            "t_end",
            "theta_final",
            "theta_max",
            "omega_final",
            "Omega_final",
            "J_initial",
            "J_max_rel_drift",
            "energy_initial",
            "energy_final",
            "energy_balance_max_rel_error",
            "first_time_theta_above_half_pi",
            "contact_lost_at",
            "negative_normal_fraction",
            "rolling_fraction",
            "pull_off_margin_min",
            "steps",
            "rejected_steps",
            "rhs_evaluations",
            "status",
            "failure",
            "wall_seconds",
            "scenario",
            "events",
        ] {
            assert!(v.get(key).is_some(), "missing {key}");
        }
        assert!(v["contact_lost_at"].is_null());
        assert!(v["pull_off_margin_min"].is_null());
        assert_eq!(v["events"][0]["kind"], "theta_above_half_pi");
        assert_eq!(v["events"][0]["t"], 0.5);
        assert_eq!(v["wall_seconds"], 0.25);
    }
}
