//! A request to stop: set by the binary's Ctrl-C / SIGTERM handler, read by the run loop at each
//! output time, which then ends the run normally — as a stop, `"stopped": "interrupted"` in the
//! summary — so that everything recorded up to it (CSV, JSON, `.rrd`) is written. The library
//! installs no handler itself.

use std::sync::atomic::{AtomicBool, Ordering};

static REQUESTED: AtomicBool = AtomicBool::new(false);

/// Asks the running simulation to stop at its next output time. Returns whether a stop had
/// already been asked for (a second Ctrl-C).
pub fn request() -> bool {
    REQUESTED.swap(true, Ordering::SeqCst)
}

/// Whether a stop was asked for.
pub fn requested() -> bool {
    REQUESTED.load(Ordering::SeqCst)
}

/// Forgets a request (a new run starts).
pub fn clear() {
    REQUESTED.store(false, Ordering::SeqCst);
}
