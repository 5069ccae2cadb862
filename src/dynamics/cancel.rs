//! A request to stop a run, shared between whoever may ask (the binary's Ctrl-C / SIGTERM handler)
//! and the runs that honour it: the integrator checks it after every step and the run loop at
//! every output time, and a run asked to stop ends normally — as a stop, `"stopped":
//! "interrupted"` in the summary — so that everything recorded up to it (CSV, JSON, `.rrd`) is
//! written. A study checks it before each case. The token travels in the run's settings
//! ([`super::integrator::Settings::cancel`], the scenario's `RunOptions`, the study's options);
//! the library installs no handler and keeps no global.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// A shared stop request: clones are the same request. The default is a fresh one, never asked.
#[derive(Debug, Clone, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A fresh request, not asked for.
    pub fn new() -> CancelToken {
        CancelToken::default()
    }

    /// Asks every run holding this token to stop at its next step. Returns whether a stop had
    /// already been asked for (a second Ctrl-C).
    pub fn request(&self) -> bool {
        self.0.swap(true, Ordering::SeqCst)
    }

    /// Whether a stop was asked for.
    pub fn requested(&self) -> bool {
        self.0.load(Ordering::SeqCst)
    }

    /// Forgets a request (a new run starts with the same token).
    pub fn clear(&self) {
        self.0.store(false, Ordering::SeqCst);
    }
}

/// Two tokens are equal when they are the same request.
impl PartialEq for CancelToken {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clones_share_the_request() {
        let a = CancelToken::new();
        let b = a.clone();
        assert!(!b.requested());
        assert!(!a.request(), "the first request");
        assert!(b.requested());
        assert!(b.request(), "the second request knows of the first");
        a.clear();
        assert!(!b.requested());
        assert_ne!(a, CancelToken::new());
        assert_eq!(a, b);
    }
}
