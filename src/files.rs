//! Output files written safely: the guard that keeps a command from writing over a file it reads
//! or over another of its outputs, the lock that keeps two runs from writing one file, and the
//! write to a temporary file renamed into place, so that a reader never sees half a file.
//!
//! - **Identity.** Two paths name the same file when they resolve to the same device and inode
//!   (a hard link, a symlink, `..` or another spelling); a path that does not exist yet is known
//!   by its resolved directory and name.
//! - **The guard** ([`OutputGuard`]) is told every file the command reads, then every file it will
//!   write; an output that is an input, or another output, is refused before any work, naming both.
//! - **The lock** ([`OutputLock`]): a hidden `.NAME.kecsim-lock` beside each output, locked
//!   (`flock`) while the command runs and holding its pid; a second run on the same output
//!   refuses, naming the first's pid. The operating system releases the lock when a process ends,
//!   however it ends, so a lock left by a killed run never blocks the next.
//! - **The write** ([`AtomicFile`]): into a part file of its own, `.NAME.part-PID-N` (N its writer
//!   in the process: two writers of one file never share one) in the output's directory (a
//!   recording: `.NAME.part-PID`, its target locked by the guard), renamed onto
//!   the output when complete (through a symlink: onto the file it points to). A write that is
//!   abandoned removes its part file; a process killed mid-write leaves it (it holds what was
//!   written). Every write's error — the flush and the sync included — is checked before the
//!   rename: a full disk keeps the old file and fails the command with the reason.
//! - **Streams** ([`OutputKind::Stream`]): an output that exists and is a character device, a FIFO
//!   or a socket (`/dev/null`, `/dev/stdout`, a named pipe) is written directly, never renamed
//!   over, and takes no lock; a FIFO waits at most [`STREAM_WAIT`] (`KECSIM_STREAM_WAIT_S`) for its reader. Block devices
//!   are refused.
//! - **Side files** (the lock, the part file, a directory's write probe) are created without
//!   following a symlink (`O_NOFOLLOW`, the part and the probe exclusively): a link planted at
//!   their predictable names is refused or replaced, never written through. An output may not
//!   be named like one of them. A side file's name that would pass 255 bytes (an output's legal
//!   250-byte name) is shortened with a hash of the whole name.

use std::fs::{self, File, OpenOptions};
use std::io::{self, Read, Seek, Write};
#[cfg(unix)]
use std::os::unix::fs::{FileTypeExt, OpenOptionsExt};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use thiserror::Error;

/// Why an output cannot be written.
#[derive(Debug, Error)]
pub enum GuardError {
    /// The output is a file the command reads.
    #[error("{what} {path}: this is {input}, which this command reads; writing it would destroy it")]
    Input {
        what: String,
        path: String,
        /// The input as it was named, with how it is the same file.
        input: String,
    },
    /// Two outputs are one file.
    #[error("{what} and {other} both name the file {path}: one output would overwrite the other")]
    Twice {
        what: String,
        other: String,
        path: String,
    },
    /// Another process holds the output's lock.
    #[error("{what} {path}: another kecsim run (pid {pid}) is writing this file; wait for it to end or choose another path")]
    Locked { what: String, path: String, pid: String },
    /// The output cannot be written (its directory, its permissions).
    #[error("{what} {path}: {problem}")]
    Unwritable {
        what: String,
        path: String,
        problem: String,
    },
}

/// What a file is, for comparing two paths: its device and inode where it exists, else its
/// resolved path (the directory's symlinks and `..` resolved, the name kept).
#[derive(Debug, Clone, PartialEq, Eq)]
enum Identity {
    Inode(u64, u64),
    Path(PathBuf),
}

fn identity(p: &Path) -> Identity {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        if let Ok(m) = fs::metadata(p) {
            return Identity::Inode(m.dev(), m.ino());
        }
    }
    Identity::Path(resolved(p))
}

/// The directory of `p` (`.` for a bare name).
fn dir_of(p: &Path) -> PathBuf {
    match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    }
}

/// `p` with every symlink and `..` resolved: the file it names if it exists, else its resolved
/// directory joined with its name.
pub fn resolved(p: &Path) -> PathBuf {
    if let Ok(c) = fs::canonicalize(p) {
        return c;
    }
    let dir = dir_of(p);
    let dir = fs::canonicalize(&dir).unwrap_or(dir);
    match p.file_name() {
        Some(n) => dir.join(n),
        None => dir,
    }
}

/// The longest file name most file systems take (ext4, xfs, btrfs, tmpfs: 255 bytes).
const NAME_MAX: usize = 255;

/// A hidden file beside `target`: `.NAME` + `suffix`. Where that name would be longer than a
/// file system takes ([`NAME_MAX`]; an output's legal 250-byte name), NAME is shortened to its
/// start and a hash of the whole name (FNV-1a, 64 bit: the same in every process, so that two
/// runs on one output still find one lock).
fn beside(target: &Path, suffix: &str) -> PathBuf {
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    let full = format!(".{name}{suffix}");
    if full.len() <= NAME_MAX {
        return dir_of(target).join(full);
    }
    let hash = name.bytes().fold(0xcbf2_9ce4_8422_2325_u64, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
    });
    let tag = format!("~{hash:016x}");
    let mut keep = NAME_MAX.saturating_sub(1 + tag.len() + suffix.len());
    while !name.is_char_boundary(keep.min(name.len())) {
        keep -= 1;
    }
    dir_of(target).join(format!(".{}{tag}{suffix}", &name[..keep.min(name.len())]))
}

/// How an output is written.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OutputKind {
    /// A regular file (or none yet): written to its part file and renamed into place.
    File,
    /// An existing character device, FIFO or socket (`/dev/null`, `/dev/stdout` on a pipe, a named
    /// pipe): written directly, in order, never renamed over.
    Stream,
}

/// How an output at `p` is written; a block device (or another non-file) is refused with why.
pub fn output_kind(p: &Path) -> Result<OutputKind, String> {
    let Ok(m) = fs::metadata(p) else {
        return Ok(OutputKind::File);
    };
    let t = m.file_type();
    if t.is_file() {
        return Ok(OutputKind::File);
    }
    if t.is_dir() {
        return Err("is a directory; expected a file name".into());
    }
    #[cfg(unix)]
    {
        if t.is_char_device() || t.is_fifo() || t.is_socket() {
            return Ok(OutputKind::Stream);
        }
        if t.is_block_device() {
            return Err("is a block device; kecsim writes files, pipes and character devices only".into());
        }
    }
    Err("is not a file, a pipe or a character device".into())
}

/// How long a write to a FIFO waits for a reader before failing (a FIFO nobody reads would
/// otherwise hang the command); `KECSIM_STREAM_WAIT_S` sets another ([`stream_wait`]).
pub const STREAM_WAIT: Duration = Duration::from_secs(10);

/// A wait of the outputs: the seconds in the environment variable `var` (a finite number ≥ 0; a
/// test's short wait, a batch system's long one), else `default`. The one place where the
/// library reads its waits from the environment: they are the process's settings, not the run's.
pub fn wait_from_env(var: &str, default: Duration) -> Duration {
    std::env::var(var)
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|v| v.is_finite() && (0.0..=86_400.0).contains(v))
        .map_or(default, Duration::from_secs_f64)
}

/// [`STREAM_WAIT`], or `KECSIM_STREAM_WAIT_S`.
pub fn stream_wait() -> Duration {
    wait_from_env("KECSIM_STREAM_WAIT_S", STREAM_WAIT)
}

/// Opens the stream `p` for writing ([`OutputKind::Stream`]): a FIFO without a reader is waited
/// for at most [`stream_wait`], then an error.
pub fn open_stream(p: &Path) -> io::Result<File> {
    #[cfg(unix)]
    {
        let fifo = fs::metadata(p).is_ok_and(|m| m.file_type().is_fifo());
        if fifo {
            let start = Instant::now();
            loop {
                match OpenOptions::new()
                    .write(true)
                    .custom_flags(libc::O_NONBLOCK)
                    .open(p)
                {
                    Ok(f) => {
                        set_blocking(&f)?;
                        return Ok(f);
                    }
                    Err(e) if e.raw_os_error() == Some(libc::ENXIO) => {
                        let wait = stream_wait();
                        if start.elapsed() > wait {
                            return Err(io::Error::other(format!(
                                "a named pipe (FIFO) that nobody read within {:.0} s",
                                wait.as_secs_f64()
                            )));
                        }
                        std::thread::sleep(Duration::from_millis(50));
                    }
                    Err(e) => return Err(e),
                }
            }
        }
    }
    OpenOptions::new().write(true).open(p)
}

/// Clears `O_NONBLOCK` on an open file.
#[cfg(unix)]
fn set_blocking(f: &File) -> io::Result<()> {
    use std::os::fd::AsRawFd;
    let fd = f.as_raw_fd();
    // SAFETY: fcntl on a descriptor this process owns (held by `f` for the call).
    let flags = unsafe { libc::fcntl(fd, libc::F_GETFL) };
    if flags < 0 || unsafe { libc::fcntl(fd, libc::F_SETFL, flags & !libc::O_NONBLOCK) } < 0 {
        return Err(io::Error::last_os_error());
    }
    Ok(())
}

/// Opens `p` for reading only if it is a regular file, without following a symlink at `p`
/// itself when `nofollow`, and without blocking on a FIFO: what a cache or a case file is read
/// with. The error says what `p` is instead.
pub fn open_regular(p: &Path, nofollow: bool) -> io::Result<File> {
    let mut o = OpenOptions::new();
    o.read(true);
    #[cfg(unix)]
    o.custom_flags(libc::O_NONBLOCK | if nofollow { libc::O_NOFOLLOW } else { 0 });
    let f = o.open(p).map_err(|e| {
        #[cfg(unix)]
        if e.raw_os_error() == Some(libc::ELOOP) {
            return io::Error::other("is a symlink, which is not followed here");
        }
        e
    })?;
    if !f.metadata()?.is_file() {
        return Err(io::Error::new(
            io::ErrorKind::InvalidInput,
            "not a regular file (a directory, a device or a pipe)",
        ));
    }
    Ok(f)
}

/// Reads at most `limit` bytes of the regular file `p` ([`open_regular`]); a larger file is an
/// error naming both sizes (read no further: a symlink to `/dev/zero` or a huge file costs
/// nothing).
pub fn read_bounded(p: &Path, limit: u64, nofollow: bool) -> io::Result<Vec<u8>> {
    let f = open_regular(p, nofollow)?;
    let len = f.metadata()?.len();
    if len > limit {
        return Err(io::Error::other(format!(
            "{len} bytes, more than the {limit} expected here"
        )));
    }
    let mut bytes = Vec::with_capacity(len as usize);
    f.take(limit + 1).read_to_end(&mut bytes)?;
    if bytes.len() as u64 > limit {
        return Err(io::Error::other(format!(
            "more than the {limit} bytes expected here"
        )));
    }
    Ok(bytes)
}

/// Whether `name` is one of kecsim's side files (`.NAME.kecsim-lock`, `.NAME.part-PID`,
/// `.kecsim-write-check-PID`): an output named so would be another output's lock or part file.
fn side_file_name(name: &str) -> bool {
    if !name.starts_with('.') {
        return false;
    }
    if name.ends_with(".kecsim-lock") || name.starts_with(".kecsim-write-check-") {
        return true;
    }
    // `.part-PID` (a recording's) or `.part-PID-N` (a file's, N its writer in the process).
    name.rsplit_once(".part-").is_some_and(|(_, tail)| {
        let mut parts = tail.splitn(2, '-');
        let number = |t: &str| !t.is_empty() && t.bytes().all(|b| b.is_ascii_digit());
        parts.next().is_some_and(number) && parts.next().is_none_or(number)
    })
}

/// Creates `p` exclusively without following a link: a file (or a link) already at the name is
/// removed first — the name is kecsim's own (a part file, a probe), so whatever stands there is
/// stale or planted, and removing a link never touches what it points to.
pub fn create_side_file(p: &Path) -> io::Result<File> {
    let open = || {
        let mut o = OpenOptions::new();
        o.write(true).create_new(true);
        #[cfg(unix)]
        o.custom_flags(libc::O_NOFOLLOW);
        o.open(p)
    };
    match open() {
        Err(e) if e.kind() == io::ErrorKind::AlreadyExists => {
            if fs::symlink_metadata(p).is_ok_and(|m| m.is_dir()) {
                return Err(io::Error::other(format!(
                    "{}: a directory stands at this temporary name",
                    p.display()
                )));
            }
            fs::remove_file(p)?;
            open()
        }
        r => r,
    }
}

/// Checks, before any work, that files can be created in the directory `dir`: a probe
/// `.kecsim-write-check-PID` is created exclusively (never through a link planted at its name)
/// and removed.
pub fn check_dir_writable(dir: &Path) -> io::Result<()> {
    let probe = dir.join(format!(".kecsim-write-check-{}", std::process::id()));
    drop(create_side_file(&probe)?);
    fs::remove_file(&probe)
}

/// Whether `p` names the process's standard output (`/dev/stdout`, `/proc/self/fd/1`, the file
/// or pipe stdout is): the binary then prints its lines to stderr from its first line on.
pub fn is_stdout(p: &Path) -> bool {
    let Some(out) = stdout_identity() else {
        return false;
    };
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        fs::metadata(p).is_ok_and(|m| Identity::Inode(m.dev(), m.ino()) == out)
    }
    #[cfg(not(unix))]
    {
        let _ = (p, out);
        false
    }
}

/// The identity of the process's standard output, if it can be known.
fn stdout_identity() -> Option<Identity> {
    #[cfg(unix)]
    {
        use std::os::fd::AsFd;
        use std::os::unix::fs::MetadataExt;
        let fd = io::stdout().as_fd().try_clone_to_owned().ok()?;
        let m = File::from(fd).metadata().ok()?;
        Some(Identity::Inode(m.dev(), m.ino()))
    }
    #[cfg(not(unix))]
    None
}

/// The files a command reads and writes; an output that is an input or another output is refused
/// ([`OutputGuard::output`]), and each output is locked while the guard lives.
#[derive(Debug, Default)]
pub struct OutputGuard {
    inputs: Vec<(PathBuf, Identity)>,
    /// Directories the command reads from (a study's cases): no output may lie inside.
    trees: Vec<(PathBuf, PathBuf)>,
    outputs: Vec<(String, PathBuf, Identity)>,
    locks: Vec<OutputLock>,
}

impl OutputGuard {
    pub fn new() -> Self {
        Self::default()
    }

    /// A file the command reads (one that does not exist is skipped: it cannot be destroyed).
    pub fn input(&mut self, path: impl AsRef<Path>) {
        let p = path.as_ref();
        if fs::metadata(p).is_ok() {
            self.inputs.push((p.to_path_buf(), identity(p)));
        }
    }

    /// Every file in `paths` as an input.
    pub fn inputs<P: AsRef<Path>>(&mut self, paths: impl IntoIterator<Item = P>) {
        for p in paths {
            self.input(p);
        }
    }

    /// A directory whose files the command reads (a study's `cases/`): no output may be inside
    /// it, by any spelling (whether the file exists yet or not).
    pub fn input_tree(&mut self, dir: impl AsRef<Path>) {
        let d = dir.as_ref();
        self.trees.push((d.to_path_buf(), resolved(d)));
    }

    /// Whether one of the outputs is the process's standard output (`--save /dev/stdout`): the
    /// command's printed lines then belong on stderr.
    pub fn writes_stdout(&self) -> bool {
        let Some(out) = stdout_identity() else {
            return false;
        };
        self.outputs.iter().any(|(_, _, id)| *id == out)
    }

    /// A file the command will write (`what` names it: the option, or the option and the file in
    /// its directory). Refused if it is an input or another output, a directory, a dangling
    /// symlink or in a directory that does not exist or cannot be written; else locked (refused if
    /// another run holds its lock) until the guard drops.
    pub fn output(&mut self, what: &str, path: &Path) -> Result<(), GuardError> {
        let shown = path.display().to_string();
        let unwritable = |problem: String| GuardError::Unwritable {
            what: what.to_string(),
            path: shown.clone(),
            problem,
        };
        let kind = output_kind(path).map_err(&unwritable)?;
        if fs::symlink_metadata(path).is_ok_and(|m| m.file_type().is_symlink()) && fs::metadata(path).is_err()
        {
            return Err(unwritable("is a symlink to nothing; give the file itself".into()));
        }
        let target = resolved(path);
        if target
            .file_name()
            .and_then(|n| n.to_str())
            .is_some_and(side_file_name)
        {
            return Err(unwritable(
                "is named like a lock or a temporary file of another kecsim output; choose another name"
                    .into(),
            ));
        }
        for (dir, rdir) in &self.trees {
            if target.starts_with(rdir) {
                return Err(GuardError::Input {
                    what: what.to_string(),
                    path: shown,
                    input: format!("inside {}, whose files this command reads", dir.display()),
                });
            }
        }
        let id = identity(path);
        for (input, iid) in &self.inputs {
            if *iid == id {
                let how = if resolved(input) == resolved(path) {
                    format!("the input {}", input.display())
                } else {
                    format!(
                        "the input {} (the same file by a link or another name)",
                        input.display()
                    )
                };
                return Err(GuardError::Input {
                    what: what.to_string(),
                    path: shown,
                    input: how,
                });
            }
        }
        let device = fs::metadata(path).is_ok_and(|m| {
            #[cfg(unix)]
            {
                m.file_type().is_char_device()
            }
            #[cfg(not(unix))]
            {
                let _ = m;
                false
            }
        });
        for (other, _, oid) in &self.outputs {
            // Two outputs may both go to a character device (`/dev/null`); not to one pipe.
            if *oid == id && !device {
                return Err(GuardError::Twice {
                    what: what.to_string(),
                    other: other.clone(),
                    path: shown,
                });
            }
        }
        if kind == OutputKind::Stream {
            // Written directly, in order; no lock (two runs may both write to /dev/null).
            self.outputs.push((what.to_string(), path.to_path_buf(), id));
            return Ok(());
        }
        let dir = dir_of(path);
        if !dir.is_dir() {
            return Err(unwritable(format!(
                "the directory {} does not exist",
                dir.display()
            )));
        }
        if let Ok(m) = fs::metadata(path) {
            if m.permissions().readonly() {
                return Err(unwritable("the file is read-only".into()));
            }
        }
        let lock = OutputLock::acquire(path).map_err(|e| match e {
            LockFailure::Held { pid } => GuardError::Locked {
                what: what.to_string(),
                path: shown.clone(),
                pid,
            },
            LockFailure::Io(e) => unwritable(format!("cannot write in its directory ({e})")),
        })?;
        self.locks.push(lock);
        self.outputs.push((what.to_string(), path.to_path_buf(), id));
        Ok(())
    }
}

/// Why a lock was not taken.
#[derive(Debug)]
pub enum LockFailure {
    /// Another process holds it (its pid as it wrote it, or `unknown`).
    Held {
        pid: String,
    },
    Io(io::Error),
}

/// The lock of one output file: `.NAME.kecsim-lock` beside it, `flock`ed and holding the pid;
/// removed and released on drop.
#[derive(Debug)]
pub struct OutputLock {
    path: PathBuf,
    _file: File,
}

impl OutputLock {
    /// Takes the lock of `target`, or says who holds it.
    pub fn acquire(target: &Path) -> Result<OutputLock, LockFailure> {
        let path = beside(&resolved(target), ".kecsim-lock");
        // A holder that ends removes the file after we opened it: the lock we then take is on a
        // file no longer at the path, and is taken again on the new one.
        for _ in 0..8 {
            let mut o = OpenOptions::new();
            o.read(true).write(true).create(true).truncate(false);
            // Never through a link planted at the lock's name, never blocking on a FIFO there.
            #[cfg(unix)]
            o.custom_flags(libc::O_NOFOLLOW | libc::O_NONBLOCK);
            let mut file = o.open(&path).map_err(|e| {
                #[cfg(unix)]
                if e.raw_os_error() == Some(libc::ELOOP) {
                    return LockFailure::Io(io::Error::other(format!(
                        "{} is a symlink; a lock file is never followed — remove it",
                        path.display()
                    )));
                }
                LockFailure::Io(e)
            })?;
            if !file.metadata().is_ok_and(|m| m.is_file()) {
                return Err(LockFailure::Io(io::Error::other(format!(
                    "{} is not a regular file; remove it",
                    path.display()
                ))));
            }
            match file.try_lock() {
                Ok(()) => {}
                Err(fs::TryLockError::WouldBlock) => {
                    let mut pid = String::new();
                    file.read_to_string(&mut pid).ok();
                    let pid = pid.trim();
                    return Err(LockFailure::Held {
                        pid: if pid.is_empty() {
                            "unknown".into()
                        } else {
                            pid.to_string()
                        },
                    });
                }
                Err(fs::TryLockError::Error(e)) => return Err(LockFailure::Io(e)),
            }
            if !same_file(&file, &path) {
                continue;
            }
            let written = file
                .set_len(0)
                .and_then(|_| file.rewind())
                .and_then(|_| write!(file, "{}", std::process::id()));
            if let Err(e) = written {
                // (A full disk: the lock we made is not left behind.)
                fs::remove_file(&path).ok();
                return Err(LockFailure::Io(e));
            }
            return Ok(OutputLock { path, _file: file });
        }
        Err(LockFailure::Io(io::Error::other(format!(
            "{}: the lock file keeps changing",
            path.display()
        ))))
    }
}

/// Whether the open `file` is still the file at `path`.
fn same_file(file: &File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

impl Drop for OutputLock {
    fn drop(&mut self) {
        // Removed while still locked: a run waiting on it then finds the path gone or new.
        fs::remove_file(&self.path).ok();
    }
}

/// A file written in full or not at all: the bytes go to `.NAME.part-PID` beside the target,
/// renamed onto it by [`AtomicFile::commit`]; dropped without the commit, the part file is
/// removed and the target is as it was.
#[derive(Debug)]
pub struct AtomicFile {
    target: PathBuf,
    /// The part file; None for a stream (written directly).
    part: Option<PathBuf>,
    file: Option<io::BufWriter<File>>,
}

impl AtomicFile {
    /// Opens the part file of `target` (a symlink's target: the file it points to), created
    /// exclusively and never through a link at its name; a stream ([`OutputKind::Stream`]) is
    /// opened itself.
    pub fn create(target: &Path) -> io::Result<AtomicFile> {
        if output_kind(target).map_err(io::Error::other)? == OutputKind::Stream {
            return Ok(AtomicFile {
                target: target.to_path_buf(),
                part: None,
                file: Some(io::BufWriter::new(open_stream(target)?)),
            });
        }
        let target = write_target(target);
        let (part, file) = create_writer_part(&target)?;
        Ok(AtomicFile {
            target,
            part: Some(part),
            file: Some(io::BufWriter::new(file)),
        })
    }

    /// The file this becomes.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The part file the bytes go to until the commit (None for a stream, written directly).
    pub fn part(&self) -> Option<&Path> {
        self.part.as_deref()
    }

    /// Flushes the bytes, syncs them to the disk and renames the part file onto the target; any
    /// error (a full disk) removes the part file and leaves the target as it was.
    pub fn commit(mut self) -> io::Result<()> {
        let file = self
            .file
            .take()
            .ok_or_else(|| io::Error::other("committed twice"))?;
        let written = file
            .into_inner()
            .map_err(|e| e.into_error())
            .and_then(|f| match &self.part {
                Some(_) => f.sync_all(),
                None => Ok(()),
            });
        let Some(part) = self.part.take() else {
            return written;
        };
        if let Err(e) = written {
            fs::remove_file(&part).ok();
            return Err(e);
        }
        fs::rename(&part, &self.target).inspect_err(|_| {
            fs::remove_file(&part).ok();
        })
    }
}

impl Write for AtomicFile {
    fn write(&mut self, buf: &[u8]) -> io::Result<usize> {
        match self.file.as_mut() {
            Some(f) => f.write(buf),
            None => Err(io::Error::other("written after its commit")),
        }
    }
    fn flush(&mut self) -> io::Result<()> {
        match self.file.as_mut() {
            Some(f) => f.flush(),
            None => Ok(()),
        }
    }
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.take().is_some() {
            if let Some(part) = &self.part {
                fs::remove_file(part).ok();
            }
        }
    }
}

/// The file a write to `p` replaces: `p` itself, or the file it points to if it is a symlink
/// (the link is kept).
pub fn write_target(p: &Path) -> PathBuf {
    if fs::symlink_metadata(p).is_ok_and(|m| m.file_type().is_symlink()) {
        fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf())
    } else {
        p.to_path_buf()
    }
}

/// The part file `.NAME.part-PID` beside `target`, where a recording is written before its
/// rename (the recording's target is locked by the [`OutputGuard`]: one writer per process; an
/// [`AtomicFile`] takes a part file of its own instead, [`AtomicFile::part`]).
pub fn part_path(target: &Path) -> PathBuf {
    beside(target, &format!(".part-{}", std::process::id()))
}

/// The most part files one process opens for one target at a time ([`create_writer_part`]).
const MAX_WRITERS: u32 = 1000;

/// A part file of its own for one writer of `target`: `.NAME.part-PID-N` with the first N
/// (1, 2, …) whose name is free, created exclusively and never through a link. Two writers of
/// one target in one process (threads of a library user, two outputs of one command that name
/// one file) each get theirs: neither removes nor renames the other's. Whatever already stands
/// at a name (a stale part file, a planted link) is left and the next name taken.
fn create_writer_part(target: &Path) -> io::Result<(PathBuf, File)> {
    for n in 1..=MAX_WRITERS {
        let part = beside(target, &format!(".part-{}-{n}", std::process::id()));
        let mut o = OpenOptions::new();
        o.write(true).create_new(true);
        #[cfg(unix)]
        o.custom_flags(libc::O_NOFOLLOW);
        match o.open(&part) {
            Ok(f) => return Ok((part, f)),
            Err(e) if e.kind() == io::ErrorKind::AlreadyExists => continue,
            Err(e) => return Err(e),
        }
    }
    Err(io::Error::other(format!(
        "{}: {MAX_WRITERS} part files of this process stand beside it; remove the stale ones",
        target.display()
    )))
}

/// A CSV writer onto an [`AtomicFile`] at `path`; [`commit_csv`] puts the file in place.
pub fn csv_writer(path: &Path) -> io::Result<csv::Writer<AtomicFile>> {
    Ok(csv::Writer::from_writer(AtomicFile::create(path)?))
}

/// Flushes a [`csv_writer`] and renames its file into place.
pub fn commit_csv(w: csv::Writer<AtomicFile>) -> io::Result<()> {
    w.into_inner().map_err(|e| e.into_error())?.commit()
}

/// Writes `bytes` to `path` in full or not at all ([`AtomicFile`]).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> io::Result<()> {
    let mut f = AtomicFile::create(path)?;
    f.write_all(bytes)?;
    f.commit()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dir(tag: &str) -> PathBuf {
        let d = std::env::temp_dir().join(format!("kecsim-files-{tag}-{}", std::process::id()));
        fs::remove_dir_all(&d).ok();
        fs::create_dir_all(&d).unwrap();
        d
    }

    /// An output that is an input by a hard link, a symlink, `..` or its own name is refused, and
    /// so is one output twice; other files pass.
    #[test]
    fn an_output_that_is_an_input_by_any_name_is_refused() {
        let d = dir("guard");
        let input = d.join("scene.toml");
        fs::write(&input, "x").unwrap();
        fs::hard_link(&input, d.join("hard.toml")).unwrap();
        #[cfg(unix)]
        std::os::unix::fs::symlink(&input, d.join("soft.toml")).unwrap();
        fs::create_dir(d.join("sub")).unwrap();
        let mut g = OutputGuard::new();
        g.input(&input);
        let mut routes = vec![
            d.join("scene.toml"),
            d.join("hard.toml"),
            d.join("sub").join("..").join("scene.toml"),
        ];
        if cfg!(unix) {
            routes.push(d.join("soft.toml"));
        }
        for p in routes {
            let e = g.output("--json", &p).unwrap_err().to_string();
            assert!(
                e.contains("this command reads") && e.contains("scene.toml"),
                "{e}"
            );
        }
        g.output("--json", &d.join("out.json")).unwrap();
        let e = g
            .output("--save", &d.join("sub/../out.json"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("--save and --json both name"), "{e}");
        assert_eq!(fs::read_to_string(&input).unwrap(), "x");
        fs::remove_dir_all(&d).ok();
    }

    /// A second guard on the same output refuses, naming the first's pid; once the first drops,
    /// the output is free and no lock file is left.
    #[test]
    fn a_held_output_is_refused_with_the_holders_pid() {
        let d = dir("lock");
        let out = d.join("run.json");
        let mut a = OutputGuard::new();
        a.output("--json", &out).unwrap();
        let e = OutputGuard::new().output("--json", &out).unwrap_err().to_string();
        assert!(e.contains(&format!("pid {}", std::process::id())), "{e}");
        drop(a);
        let mut b = OutputGuard::new();
        b.output("--json", &out).unwrap();
        drop(b);
        let left: Vec<_> = fs::read_dir(&d).unwrap().collect();
        assert!(left.is_empty(), "{left:?}");
        fs::remove_dir_all(&d).ok();
    }

    /// Until the commit, the target keeps its old bytes and the new ones are in the part file; an
    /// abandoned write leaves the target as it was and no part file; through a symlink, the file
    /// it points to is replaced and the link kept.
    #[test]
    fn an_atomic_file_appears_whole_or_not_at_all() {
        let d = dir("atomic");
        let out = d.join("a.csv");
        fs::write(&out, "old").unwrap();
        let mut f = AtomicFile::create(&out).unwrap();
        f.write_all(b"new").unwrap();
        f.flush().unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "old");
        assert_eq!(fs::read_to_string(f.part().unwrap()).unwrap(), "new");
        f.commit().unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "new");
        let mut f = AtomicFile::create(&out).unwrap();
        f.write_all(b"half").unwrap();
        let part = f.part().unwrap().to_path_buf();
        drop(f);
        assert_eq!(fs::read_to_string(&out).unwrap(), "new");
        assert!(!part.exists());
        #[cfg(unix)]
        {
            let link = d.join("link.csv");
            std::os::unix::fs::symlink(&out, &link).unwrap();
            write_atomic(&link, b"through").unwrap();
            assert!(fs::symlink_metadata(&link).unwrap().file_type().is_symlink());
            assert_eq!(fs::read_to_string(&out).unwrap(), "through");
        }
        fs::remove_dir_all(&d).ok();
    }

    /// Two writers of one file in one process (two threads, two outputs naming one file) each
    /// write their own part file: neither removes or renames the other's, each commit puts its
    /// whole bytes in place, and nothing is left beside the file. (With one part file per
    /// process, the second writer removed the first's and the first's commit failed.)
    #[test]
    fn two_writers_of_one_file_never_share_a_part_file() {
        let d = dir("writers");
        let out = d.join("r.csv");
        let mut a = AtomicFile::create(&out).unwrap();
        let mut b = AtomicFile::create(&out).unwrap();
        assert_ne!(a.part(), b.part());
        a.write_all(b"first").unwrap();
        b.write_all(b"second").unwrap();
        a.commit().unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "first");
        b.commit().unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "second");
        let left: Vec<_> = fs::read_dir(&d)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(left, vec![std::ffi::OsString::from("r.csv")]);
        // A link planted at the first part name is left alone and never written through.
        #[cfg(unix)]
        {
            let victim = d.join("victim");
            fs::write(&victim, "keep").unwrap();
            let first = beside(&out, &format!(".part-{}-1", std::process::id()));
            std::os::unix::fs::symlink(&victim, &first).unwrap();
            write_atomic(&out, b"third").unwrap();
            assert_eq!(fs::read_to_string(&victim).unwrap(), "keep");
            assert_eq!(fs::read_to_string(&out).unwrap(), "third");
        }
        fs::remove_dir_all(&d).ok();
    }

    /// An output's legal 250-byte name gets its lock and part file (their names would pass the
    /// file system's 255 bytes: shortened with a hash), the same lock in every process; a second
    /// guard on it is refused.
    #[test]
    fn a_long_output_name_gets_its_lock_and_part_file() {
        let d = dir("longname");
        let out = d.join(format!("{}.csv", "n".repeat(246)));
        assert_eq!(out.file_name().unwrap().len(), 250);
        let mut g = OutputGuard::new();
        g.output("--json", &out).unwrap();
        let lock = beside(&resolved(&out), ".kecsim-lock");
        assert!(
            lock.file_name().unwrap().len() <= NAME_MAX && lock.exists(),
            "{lock:?}"
        );
        assert!(side_file_name(&lock.file_name().unwrap().to_string_lossy()));
        let mut again = OutputGuard::new();
        assert!(matches!(
            again.output("--json", &out),
            Err(GuardError::Locked { .. })
        ));
        write_atomic(&out, b"whole").unwrap();
        assert_eq!(fs::read_to_string(&out).unwrap(), "whole");
        let other = d.join(format!("{}.csv", "n".repeat(245) + "m"));
        assert_ne!(
            beside(&other, ".kecsim-lock"),
            lock,
            "a different name, a different lock"
        );
        drop(g);
        fs::remove_dir_all(&d).ok();
    }
}
