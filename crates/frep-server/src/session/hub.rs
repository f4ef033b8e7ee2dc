//! What all sessions of one server share: the count of open sessions, the
//! pool of workers that render streamed frames, their spare image buffers,
//! and the session settings.
//!
//! `AppState` has no field for it. So hubs are kept in a small registry,
//! keyed by the server's artefact service (one `Arc` per server). Tests that
//! start several servers in one process get one hub each. A hub goes away
//! with its server, since the registry holds only a weak reference.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex, Weak};

use frep_adapt::ServerLoad;
use frep_artefact::{Artefacts, ImagePool};
use tokio::sync::Semaphore;

use super::config::SessionConfig;
use crate::state::AppState;

/// The sessions' shared state of one server.
#[derive(Debug)]
pub struct Hub {
    /// The session settings.
    pub config: Arc<SessionConfig>,
    /// Renders of streamed frames at once, all sessions together.
    pub frames: Arc<Semaphore>,
    /// Spare image buffers of the frame workers (the artefact service's:
    /// one limit, `ArtefactConfig::image_pool_bytes`, for both).
    pub images: ImagePool,
    frame_workers: usize,
    artefact_workers: usize,
    sessions: AtomicUsize,
    next_id: AtomicUsize,
}

/// One open session's place in the hub (given back on drop).
#[derive(Debug)]
pub struct SessionTicket {
    hub: Arc<Hub>,
    /// The session's number on this server (1, 2, …).
    pub number: usize,
}

impl Drop for SessionTicket {
    fn drop(&mut self) {
        self.hub.sessions.fetch_sub(1, Ordering::SeqCst);
    }
}

type Registry = Vec<(Weak<Artefacts>, Arc<Hub>)>;

static HUBS: Mutex<Registry> = Mutex::new(Vec::new());

impl Hub {
    /// The hub of `state`'s server (made on first use).
    pub fn of(state: &AppState) -> Arc<Hub> {
        // The registry is a list of weak references and hubs; a panic while
        // it is locked cannot leave it inconsistent, so poisoning is ignored.
        let mut hubs = HUBS.lock().unwrap_or_else(|p| p.into_inner());
        hubs.retain(|(w, _)| w.strong_count() > 0);
        if let Some((_, hub)) = hubs
            .iter()
            .find(|(w, _)| std::ptr::eq(w.as_ptr(), Arc::as_ptr(&state.artefacts)))
        {
            return hub.clone();
        }
        let hub = Arc::new(Hub::new(
            state.config.session.clone(),
            state.config.limits.workers,
            state.artefacts.image_pool().clone(),
        ));
        hubs.push((Arc::downgrade(&state.artefacts), hub.clone()));
        hub
    }

    fn new(config: SessionConfig, artefact_workers: usize, images: ImagePool) -> Hub {
        let artefact_workers = artefact_workers.max(1);
        let frame_workers = match config.frame_workers {
            0 => artefact_workers,
            n => n,
        };
        Hub {
            config: Arc::new(config),
            frames: Arc::new(Semaphore::new(frame_workers)),
            images,
            frame_workers,
            artefact_workers,
            sessions: AtomicUsize::new(0),
            next_id: AtomicUsize::new(0),
        }
    }

    /// Takes a place for a new session, or `None` when `max_sessions` are
    /// open.
    pub fn enter(self: &Arc<Self>) -> Option<SessionTicket> {
        let max = self.config.max_sessions;
        let taken = self
            .sessions
            .fetch_update(Ordering::SeqCst, Ordering::SeqCst, |n| {
                (n < max).then_some(n + 1)
            });
        taken.ok()?;
        Some(SessionTicket {
            hub: self.clone(),
            number: self.next_id.fetch_add(1, Ordering::SeqCst) + 1,
        })
    }

    /// Sessions open now.
    pub fn sessions(&self) -> usize {
        self.sessions.load(Ordering::SeqCst)
    }

    /// The server's load for the engine: artefact jobs and frame renders
    /// running or waiting, over both pools' workers.
    pub fn load(&self, artefacts: &Artefacts) -> ServerLoad {
        let frames_busy = self
            .frame_workers
            .saturating_sub(self.frames.available_permits());
        let jobs = artefacts.in_flight();
        let jobs_busy = jobs.min(self.artefact_workers);
        ServerLoad {
            busy_workers: (frames_busy + jobs_busy) as u32,
            workers: (self.frame_workers + self.artefact_workers) as u32,
            queued: (jobs - jobs_busy) as u32,
        }
    }
}
