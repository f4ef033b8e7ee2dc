//! [`CancelToken`]: the one way to stop a long computation from another
//! thread.
//!
//! - The token is a shared flag (`Arc<AtomicBool>`); clones share it.
//! - The owner of a job keeps a clone and calls [`CancelToken::cancel`].
//! - The kernels (meshing, rendering, slicing, view sets) poll
//!   [`CancelToken::is_cancelled`] between units of work and stop with
//!   their own `Cancelled` error.
//! - It needs no threads or I/O, so it works on `wasm32-unknown-unknown`
//!   too (there nothing cancels it, and polling costs one load).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// Cancels a run from another thread (clones share the flag).
#[derive(Clone, Debug, Default)]
pub struct CancelToken(Arc<AtomicBool>);

impl CancelToken {
    /// A token not yet cancelled.
    pub fn new() -> Self {
        Self::default()
    }

    /// Asks the run to stop; the kernel returns its `Cancelled` error soon
    /// after. Cancelling twice is harmless.
    pub fn cancel(&self) {
        // Relaxed is enough: the flag guards no other data, and a run that
        // sees it a little late only does a little more work.
        self.0.store(true, Ordering::Relaxed);
    }

    /// Whether [`CancelToken::cancel`] was called on this token or a clone.
    pub fn is_cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

#[cfg(test)]
mod tests {
    use super::CancelToken;

    #[test]
    fn clones_share_the_flag() {
        let a = CancelToken::new();
        let b = a.clone();
        assert!(!b.is_cancelled());
        a.cancel();
        assert!(b.is_cancelled());
        assert!(!CancelToken::new().is_cancelled());
    }
}
