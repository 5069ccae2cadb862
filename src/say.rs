//! The command's printed lines (the binary's `println!` and `print!`, which `main.rs` redefines
//! to come here): standard output that fails never panics and never stops the command.
//!
//! - A closed pipe (`kecsim run | head -1`): the rest of the printed text is dropped, the command
//!   runs to its end and writes every file it was asked for; its exit status is what it would
//!   have been.
//! - Any other failure (stdout on a full device): the same, then a message on stderr and a
//!   non-zero exit, since the printed summary was lost.
//! - Standard error the same (`eprintln!`, `eprint!`, through [`write_err`]): a closed or failing
//!   stderr (`kecsim run 2>&1 | head -1`) drops the rest of the warnings, progress lines and
//!   messages; the command runs to its end, writes every file, and its exit status is what it
//!   would have been (there is nowhere left to say more).
//! - An output that is the standard output itself (`--save /dev/stdout`): the printed lines go to
//!   stderr, so that the stream holds only the file.

use std::fmt;
use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;

/// Printing stopped (the pipe closed, or stdout failed).
static STOPPED: AtomicBool = AtomicBool::new(false);
/// The printed lines go to stderr (an output is stdout).
static TO_STDERR: AtomicBool = AtomicBool::new(false);
/// Writing to stderr stopped (closed or failed).
static STDERR_STOPPED: AtomicBool = AtomicBool::new(false);
/// Why stdout failed, where it was not a closed pipe.
static FAILED: OnceLock<String> = OnceLock::new();

/// Writes `args` to stdout (or stderr, see [`to_stderr`]); a failure is remembered, not raised.
pub fn write(args: fmt::Arguments<'_>) {
    if TO_STDERR.load(Ordering::Relaxed) {
        write_err(args);
        return;
    }
    if STOPPED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = io::stdout().lock();
    if let Err(e) = out.write_fmt(args) {
        STOPPED.store(true, Ordering::Relaxed);
        if e.kind() != io::ErrorKind::BrokenPipe {
            FAILED.set(e.to_string()).ok();
        }
    }
}

/// Writes `args` to stderr; a failure stops further writes there and is not raised (the
/// binary's `eprintln!` and `eprint!`).
pub fn write_err(args: fmt::Arguments<'_>) {
    if STDERR_STOPPED.load(Ordering::Relaxed) {
        return;
    }
    let mut err = io::stderr().lock();
    if err.write_fmt(args).and_then(|()| err.flush()).is_err() {
        STDERR_STOPPED.store(true, Ordering::Relaxed);
    }
}

/// From now on, the printed lines go to stderr.
pub fn to_stderr() {
    TO_STDERR.store(true, Ordering::Relaxed);
}

/// At the command's end: stdout flushed; the reason it failed, where it did (not a closed pipe).
pub fn finish() -> Option<String> {
    if !STOPPED.load(Ordering::Relaxed) {
        if let Err(e) = io::stdout().lock().flush() {
            if e.kind() != io::ErrorKind::BrokenPipe {
                FAILED.set(e.to_string()).ok();
            }
        }
    }
    FAILED.get().cloned()
}
