//! Cleanup on SIGINT, SIGTERM and SIGHUP, done by the signal handler itself.
//!
//! The handler removes this process's staging directories, its temporary
//! files in the output directories and its lock files, then dies of the
//! signal as if no handler were installed. It reads a snapshot of what to
//! remove, which the rest of the program publishes ([`publish`]) whenever a
//! stage or a lock comes or goes, and it makes only async-signal-safe calls
//! (`openat`, `getdents64`, `unlinkat`, `fstat`, `fstatat`, `flock`,
//! `close`, `sigaction`, `sigprocmask`, `raise`): no allocation, no lock.
//!
//! A signal during a commit ([`Committing`]) waits for it: the handler only
//! notes the signal, and the last commit to end does the cleanup and dies.
//!
//! (Until 2026-11 a thread did the work, woken by the handler through a
//! pipe; starting it cost a run ~0.1 ms, 1.5 % of the MuJoCo benchmark's
//! whole process: docs/performance.md, "The speed gate".)

use std::ffi::{CStr, CString};
use std::os::unix::ffi::OsStrExt;
use std::path::Path;
use std::sync::atomic::{AtomicI32, AtomicPtr, AtomicUsize, Ordering::SeqCst};

/// A lock file for the handler to release: see [`publish`].
pub(crate) struct LockFile<'a> {
    /// The open lock file.
    pub fd: libc::c_int,
    /// Its path.
    pub path: &'a Path,
    /// Whether the process holds its OS lock (`flock`).
    pub held: bool,
    /// Whether that lock is exclusive (a writer).
    pub exclusive: bool,
    /// Whether this process created the file.
    pub created: bool,
}

/// What the handler removes, as C strings made in advance.
struct Snapshot {
    /// (output directory, staging directory).
    stages: Vec<(CString, CString)>,
    /// (fd, path, held, exclusive, created).
    locks: Vec<(libc::c_int, CString, bool, bool, bool)>,
    /// `.PID-RANDOM-`: the mark of this process's temporary file names.
    tmp_mark: Vec<u8>,
}

/// The current snapshot (null: nothing to remove).
static SNAPSHOT: AtomicPtr<Snapshot> = AtomicPtr::new(std::ptr::null_mut());
/// Handlers that may be reading a snapshot: one replaced while this is not
/// zero is never freed.
static READING: AtomicUsize = AtomicUsize::new(0);
/// The number of commits in progress, or [`DYING`].
static STATE: AtomicUsize = AtomicUsize::new(0);
/// The process is cleaning up to die of a signal.
const DYING: usize = usize::MAX;
/// A signal that came during a commit (0: none).
static PENDING: AtomicI32 = AtomicI32::new(0);

/// Install the handler for SIGINT, SIGTERM and SIGHUP, each unless it is
/// ignored (e.g. under `nohup`) or already handled. Once per process.
pub(crate) fn install() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        for sig in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
            // SAFETY: sigaction(2) with zeroed, then filled, structs.
            unsafe {
                let mut old: libc::sigaction = std::mem::zeroed();
                if libc::sigaction(sig, std::ptr::null(), &mut old) != 0
                    || old.sa_sigaction != libc::SIG_DFL
                {
                    continue;
                }
                let mut act: libc::sigaction = std::mem::zeroed();
                act.sa_sigaction = on_signal as extern "C" fn(libc::c_int) as usize;
                act.sa_flags = libc::SA_RESTART;
                // The three block each other while one is handled.
                libc::sigemptyset(&mut act.sa_mask);
                for s in [libc::SIGINT, libc::SIGTERM, libc::SIGHUP] {
                    libc::sigaddset(&mut act.sa_mask, s);
                }
                libc::sigaction(sig, &act, std::ptr::null_mut());
            }
        }
    });
}

/// Publish what a signal must remove now: the staging directories (with
/// their output directories, where the temporary files named with
/// `tmp_mark` go) and the lock files. Call it after every change, before
/// creating a stage and after taking a lock.
pub(crate) fn publish<'a>(
    stages: impl Iterator<Item = (&'a Path, &'a Path)>,
    locks: impl Iterator<Item = LockFile<'a>>,
    tmp_mark: &str,
) {
    let c = |p: &Path| CString::new(p.as_os_str().as_bytes()).ok();
    let snapshot = Snapshot {
        stages: stages.filter_map(|(d, s)| Some((c(d)?, c(s)?))).collect(),
        locks: locks
            .filter_map(|l| Some((l.fd, c(l.path)?, l.held, l.exclusive, l.created)))
            .collect(),
        tmp_mark: tmp_mark.as_bytes().to_vec(),
    };
    let old = SNAPSHOT.swap(Box::into_raw(Box::new(snapshot)), SeqCst);
    // A handler counts itself in before it loads the pointer: if none is
    // counted now, any handler from here on loads the new snapshot.
    if !old.is_null() && READING.load(SeqCst) == 0 {
        // SAFETY: `old` came from Box::into_raw and no handler can read it.
        drop(unsafe { Box::from_raw(old) });
    }
}

/// A commit in progress ([`Committing::begin`]): a signal meanwhile waits
/// for the last commit to end, which then cleans up and dies of it.
pub(crate) struct Committing(());

impl Committing {
    /// Start a commit. If the process is already dying of a signal, wait
    /// for it to end (never returns).
    pub(crate) fn begin() -> Committing {
        while STATE
            .fetch_update(SeqCst, SeqCst, |s| (s != DYING).then_some(s + 1))
            .is_err()
        {
            std::thread::sleep(std::time::Duration::from_millis(10));
        }
        Committing(())
    }
}

impl Drop for Committing {
    /// End the commit; the last one to end dies of a signal that came
    /// meanwhile.
    fn drop(&mut self) {
        STATE.fetch_sub(1, SeqCst);
        let sig = PENDING.load(SeqCst);
        if sig != 0 {
            handle(sig);
        }
    }
}

extern "C" fn on_signal(sig: libc::c_int) {
    handle(sig);
}

/// Clean up and die of `sig`, unless a commit is in progress (then its end
/// does) or the process is already dying (then this returns).
fn handle(sig: libc::c_int) {
    // Noted first: a commit that ends after the check below sees it.
    PENDING.store(sig, SeqCst);
    if STATE.compare_exchange(0, DYING, SeqCst, SeqCst).is_err() {
        return;
    }
    READING.fetch_add(1, SeqCst);
    let snapshot = SNAPSHOT.load(SeqCst);
    // SAFETY: a snapshot is freed only when no handler is counted in
    // READING (see `publish`), and this one is, for good.
    if let Some(s) = unsafe { snapshot.as_ref() } {
        for (dir, stage) in &s.stages {
            remove_tree(libc::AT_FDCWD, stage, 0);
            remove_own_tmp_files(dir, &s.tmp_mark);
        }
        for (fd, path, held, exclusive, created) in &s.locks {
            release_lock(*fd, path, *held, *exclusive, *created);
        }
    }
    // SAFETY: back to the default action, unblocked in this thread, then
    // raised: the process ends, killed by `sig`.
    unsafe {
        let mut dfl: libc::sigaction = std::mem::zeroed();
        dfl.sa_sigaction = libc::SIG_DFL;
        libc::sigemptyset(&mut dfl.sa_mask);
        libc::sigaction(sig, &dfl, std::ptr::null_mut());
        let mut set: libc::sigset_t = std::mem::zeroed();
        libc::sigemptyset(&mut set);
        libc::sigaddset(&mut set, sig);
        libc::pthread_sigmask(libc::SIG_UNBLOCK, &set, std::ptr::null_mut());
        libc::raise(sig);
        libc::_exit(128 + sig);
    }
}

/// Call `f` with the name of each entry of the open directory `fd` (not
/// `.` and `..`), with a buffer on the stack (`getdents64`).
#[cfg(target_os = "linux")]
fn each_entry(fd: libc::c_int, mut f: impl FnMut(&CStr)) {
    // u64 words: the records are 8-byte aligned.
    let mut buf = [0u64; 512];
    loop {
        // SAFETY: getdents64 fills at most the buffer's length.
        let n = unsafe {
            libc::syscall(
                libc::SYS_getdents64,
                fd,
                buf.as_mut_ptr(),
                std::mem::size_of_val(&buf),
            )
        };
        if n <= 0 {
            return;
        }
        let bytes = buf.as_ptr().cast::<u8>();
        let mut at = 0usize;
        while at < n as usize {
            // SAFETY: a linux_dirent64 record at `at`: d_ino (8 bytes),
            // d_off (8), d_reclen (2), d_type (1), then the name,
            // NUL-terminated inside the record.
            let (reclen, name) = unsafe {
                let rec = bytes.add(at);
                let reclen = usize::from(rec.add(16).cast::<u16>().read_unaligned());
                (reclen, CStr::from_ptr(rec.add(19).cast()))
            };
            if reclen == 0 {
                return;
            }
            let b = name.to_bytes();
            if b != b"." && b != b".." {
                f(name);
            }
            at += reclen;
        }
    }
}

/// Call `f` with the name of each entry of the open directory `fd` (not
/// `.` and `..`). Elsewhere than on Linux through `readdir` on a
/// duplicate of `fd`, which POSIX does not list as async-signal-safe.
#[cfg(not(target_os = "linux"))]
fn each_entry(fd: libc::c_int, mut f: impl FnMut(&CStr)) {
    // SAFETY: dup/fdopendir/readdir/closedir on an open directory.
    unsafe {
        let dup = libc::dup(fd);
        if dup < 0 {
            return;
        }
        let dir = libc::fdopendir(dup);
        if dir.is_null() {
            libc::close(dup);
            return;
        }
        loop {
            let e = libc::readdir(dir);
            if e.is_null() {
                break;
            }
            let name = CStr::from_ptr((*e).d_name.as_ptr());
            let b = name.to_bytes();
            if b != b"." && b != b".." {
                f(name);
            }
        }
        libc::closedir(dir);
    }
}

/// Remove `name` (relative to the directory `at`) with everything in it,
/// links not followed; directories at most 8 deep.
fn remove_tree(at: libc::c_int, name: &CStr, depth: u32) {
    // SAFETY: openat/unlinkat/close on NUL-terminated names.
    unsafe {
        let fd = libc::openat(
            at,
            name.as_ptr(),
            libc::O_RDONLY | libc::O_DIRECTORY | libc::O_NOFOLLOW | libc::O_CLOEXEC,
        );
        if fd < 0 {
            return;
        }
        each_entry(fd, |entry| {
            if libc::unlinkat(fd, entry.as_ptr(), 0) != 0 && depth < 8 {
                // A directory (EISDIR on Linux).
                remove_tree(fd, entry, depth + 1);
            }
        });
        libc::close(fd);
        libc::unlinkat(at, name.as_ptr(), libc::AT_REMOVEDIR);
    }
}

/// Remove the temporary files in `dir` whose names carry `mark`
/// (`.NAME.PID-RANDOM-N.tmp`).
fn remove_own_tmp_files(dir: &CStr, mark: &[u8]) {
    // SAFETY: open/unlinkat/close on NUL-terminated names.
    unsafe {
        let fd = libc::open(
            dir.as_ptr(),
            libc::O_RDONLY | libc::O_DIRECTORY | libc::O_CLOEXEC,
        );
        if fd < 0 {
            return;
        }
        each_entry(fd, |entry| {
            let b = entry.to_bytes();
            if b.starts_with(b".") && b.ends_with(b".tmp") && contains(b, mark) {
                libc::unlinkat(fd, entry.as_ptr(), 0);
            }
        });
        libc::close(fd);
    }
}

/// Whether `hay` contains `needle`.
fn contains(hay: &[u8], needle: &[u8]) -> bool {
    !needle.is_empty() && hay.windows(needle.len()).any(|w| w == needle)
}

/// Remove a lock file this process holds, if it may (as the program does
/// when it ends, through this function too): a writer holding the lock
/// always, a reader if it can upgrade to the exclusive lock, without locks
/// only the file it created; and only if the path still names the locked
/// file (a regular file, not followed).
pub(crate) fn release_lock(
    fd: libc::c_int,
    path: &CStr,
    held: bool,
    exclusive: bool,
    created: bool,
) {
    // SAFETY: flock/fstat/fstatat/unlink on an fd and a NUL-terminated path,
    // into zeroed locals.
    unsafe {
        let ours = if held {
            exclusive || libc::flock(fd, libc::LOCK_EX | libc::LOCK_NB) == 0
        } else {
            created
        };
        if !ours {
            return;
        }
        let mut a: libc::stat = std::mem::zeroed();
        let mut b: libc::stat = std::mem::zeroed();
        if libc::fstat(fd, &mut a) == 0
            && libc::fstatat(
                libc::AT_FDCWD,
                path.as_ptr(),
                &mut b,
                libc::AT_SYMLINK_NOFOLLOW,
            ) == 0
            && a.st_dev == b.st_dev
            && a.st_ino == b.st_ino
            && (b.st_mode & libc::S_IFMT) == libc::S_IFREG
        {
            libc::unlink(path.as_ptr());
        }
    }
}
