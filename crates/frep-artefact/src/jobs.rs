//! Jobs: one in-flight computation per key.
//! - It is shared by every request that waits for it (single flight).
//! - It runs on a bounded pool.
//! - It is cancelled when superseded, or when its last waiter goes away.
//!
//! A [`Flight`] holds the job's [`Cancel`], its [`JobProgress`], the count
//! of its waiters and a `watch` channel its outcome is published on. The
//! service's map key → flight is locked for every join and leave. So a
//! waiter never joins a flight its last waiter has just cancelled. The
//! leaving waiter removes the flight from the map in the same critical
//! section, and the next request starts a fresh one.
//!
//! The pool is a `Semaphore` with one permit per worker. A flight's driver
//! task waits for a permit or its cancel, whichever comes first. Then it
//! runs the computation with `spawn_blocking`. Flights not yet running are
//! the queue, bounded by the service ([`crate::ArtefactError::Busy`]).

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Arc;

use bytes::Bytes;
use tokio::sync::{watch, Notify};

use crate::cache::Meta;
use crate::compute::{Cancel, JobProgress};
use crate::error::ArtefactError;

/// A finished artefact, shared by its waiters (the bytes are not copied).
#[derive(Clone, Debug)]
pub struct Done {
    /// The body.
    pub bytes: Bytes,
    /// What is known of it.
    pub meta: Meta,
}

/// The outcome a flight publishes.
pub type Outcome = Result<Done, ArtefactError>;

/// One in-flight computation.
#[derive(Debug)]
pub struct Flight {
    /// Stops the computation.
    pub cancel: Cancel,
    /// Its progress.
    pub progress: Arc<JobProgress>,
    /// Wakes the driver waiting for a worker when cancelled.
    pub cancelled: Notify,
    waiters: AtomicUsize,
    outcome: watch::Sender<Option<Outcome>>,
}

impl Flight {
    /// A flight nobody waits for yet.
    pub fn new() -> Flight {
        Flight {
            cancel: Cancel::new(),
            progress: Arc::new(JobProgress::new()),
            cancelled: Notify::new(),
            waiters: AtomicUsize::new(0),
            outcome: watch::channel(None).0,
        }
    }

    /// Cancels the computation (its waiters get `Cancelled` once it stops).
    pub fn cancel(&self) {
        self.cancel.cancel();
        // notify_one keeps a permit when the driver is not waiting yet.
        self.cancelled.notify_one();
    }

    /// Publishes the outcome (the first one wins).
    pub fn finish(&self, outcome: Outcome) {
        self.outcome.send_if_modified(|o| {
            if o.is_some() {
                return false;
            }
            *o = Some(outcome);
            true
        });
    }

    /// Whether the outcome is published.
    pub fn is_finished(&self) -> bool {
        self.outcome.borrow().is_some()
    }

    /// What is known of the artefact once it is computed (not on error).
    pub fn done_meta(&self) -> Option<Meta> {
        match self.outcome.borrow().as_ref() {
            Some(Ok(done)) => Some(done.meta.clone()),
            _ => None,
        }
    }

    /// Counts one more waiter.
    pub fn join(&self) {
        self.waiters.fetch_add(1, Ordering::SeqCst);
    }

    /// Counts one waiter less; true when it was the last.
    pub fn leave(&self) -> bool {
        self.waiters.fetch_sub(1, Ordering::SeqCst) == 1
    }

    /// Waiters now.
    pub fn waiters(&self) -> usize {
        self.waiters.load(Ordering::SeqCst)
    }

    /// Waits for the outcome.
    pub async fn outcome(&self) -> Outcome {
        let mut rx = self.outcome.subscribe();
        loop {
            if let Some(o) = rx.borrow_and_update().as_ref() {
                return o.clone();
            }
            if rx.changed().await.is_err() {
                // The sender lives in `self`; it cannot be dropped while
                // `self` is borrowed. Kept as an error, not a panic.
                return Err(ArtefactError::Cancelled);
            }
        }
    }
}

impl Default for Flight {
    fn default() -> Self {
        Flight::new()
    }
}
