//! What every handler and session shares:
//! - the store and the artefact service;
//! - the configuration;
//! - the feed of committed changes;
//! - the per-client job counts;
//! - the shutdown signal.
//!
//! `AppState` is cheap to clone (a handful of `Arc`s and channel ends); axum
//! hands a clone to each request. Store calls are blocking (SQLite). So they
//! go through [`AppState::store_call`], which runs them on tokio's blocking
//! pool. A request then waits for the commit without stalling the other
//! connections.

use std::collections::HashMap;
use std::net::IpAddr;
use std::sync::{Arc, Mutex, OnceLock};

use axum::http::StatusCode;
use frep_artefact::{Artefacts, CompileCache};
use frep_store::Store;
use frep_wire::Change;
use tokio::sync::{broadcast, watch};

use crate::config::Config;
use crate::error::AppError;

/// Changes kept for slow subscribers of [`AppState::changes`]; one that
/// falls further behind gets `RecvError::Lagged` and should re-read the
/// model's log from the store (`Store::log(id, after)`).
pub const CHANGE_BACKLOG: usize = 1024;

/// The server's shared state.
#[derive(Clone)]
pub struct AppState {
    /// The model store (master copy of models, versions, log, assets).
    pub store: Arc<dyn Store>,
    /// Artefact computation, job pool and disk cache.
    pub artefacts: Arc<Artefacts>,
    /// Compiled models by source (the editor, artefact requests and
    /// sessions compile the same sources again and again).
    pub compiles: Arc<CompileCache>,
    /// The configuration the server was started with.
    pub config: Arc<Config>,
    /// Every committed change, published after the store committed it
    /// (sessions subscribe to follow the models they show).
    pub changes: broadcast::Sender<Change>,
    /// Artefact computations running per client.
    pub jobs: Arc<ClientJobs>,
    /// Turns `true` when the server starts shutting down (long-lived
    /// connections such as sessions should close).
    pub shutdown: watch::Receiver<bool>,
    /// Turns `true` when shutdown's grace period is over: requests still
    /// waiting for an artefact give up (their jobs are cancelled).
    pub cancel_jobs: watch::Receiver<bool>,
    /// What the sessions of this server share, made on first use by the
    /// session module (one per server, also when a process runs several).
    pub session_hub: Arc<OnceLock<Arc<crate::session::Hub>>>,
}

impl AppState {
    /// Runs a blocking store call on the blocking pool and waits for it.
    /// The store's own error becomes an [`AppError`] by its `From`.
    pub async fn store_call<T, E>(
        &self,
        f: impl FnOnce(&dyn Store) -> Result<T, E> + Send + 'static,
    ) -> Result<T, AppError>
    where
        T: Send + 'static,
        E: Into<AppError> + Send + 'static,
    {
        let store = Arc::clone(&self.store);
        tokio::task::spawn_blocking(move || f(store.as_ref()))
            .await?
            .map_err(Into::into)
    }

    /// Publishes committed changes to the sessions (no subscriber is fine).
    pub fn publish(&self, changes: impl IntoIterator<Item = Change>) {
        for change in changes {
            let _ = self.changes.send(change);
        }
    }

    /// Completes when waiting jobs must give up (shutdown's grace period is
    /// over); never, while the server runs.
    pub async fn jobs_cancelled(&self) {
        let mut rx = self.cancel_jobs.clone();
        if rx.wait_for(|v| *v).await.is_err() {
            // The sender is gone only when the server is gone: give up too.
        }
    }

    /// Whether the server is shutting down.
    pub fn is_shutting_down(&self) -> bool {
        *self.shutdown.borrow()
    }
}

/// Counts of running artefact computations per client address, bounded by
/// `limits.jobs_per_client`.
#[derive(Debug, Default)]
pub struct ClientJobs {
    running: Mutex<HashMap<IpAddr, usize>>,
}

impl ClientJobs {
    /// Takes one of `client`'s `max` job slots, or refuses with a `limit`
    /// error (429) naming `jobs_per_client`. The slot is given back when the
    /// guard drops (the job ended, or the client went away).
    pub fn acquire(self: &Arc<Self>, client: IpAddr, max: usize) -> Result<JobSlot, AppError> {
        // A poisoned lock only means another request panicked while counting;
        // the counts are still plain integers, so go on with them.
        let mut running = self.running.lock().unwrap_or_else(|p| p.into_inner());
        let n = running.entry(client).or_insert(0);
        if *n >= max {
            return Err(AppError::limit(
                "jobs_per_client",
                StatusCode::TOO_MANY_REQUESTS,
                format!("this client already has {n} artefact jobs running (limit jobs_per_client = {max})"),
            ));
        }
        *n += 1;
        Ok(JobSlot {
            jobs: Arc::clone(self),
            client,
        })
    }

    /// Jobs running for `client`.
    pub fn running(&self, client: IpAddr) -> usize {
        let running = self.running.lock().unwrap_or_else(|p| p.into_inner());
        running.get(&client).copied().unwrap_or(0)
    }
}

/// One taken job slot ([`ClientJobs::acquire`]).
#[derive(Debug)]
pub struct JobSlot {
    jobs: Arc<ClientJobs>,
    client: IpAddr,
}

impl Drop for JobSlot {
    fn drop(&mut self) {
        let mut running = self.jobs.running.lock().unwrap_or_else(|p| p.into_inner());
        if let Some(n) = running.get_mut(&self.client) {
            *n = n.saturating_sub(1);
            if *n == 0 {
                running.remove(&self.client);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn job_slots_are_bounded_per_client_and_given_back() {
        let jobs = Arc::new(ClientJobs::default());
        let a: IpAddr = [10, 0, 0, 1].into();
        let b: IpAddr = [10, 0, 0, 2].into();
        let s1 = jobs.acquire(a, 2).unwrap();
        let _s2 = jobs.acquire(a, 2).unwrap();
        let e = jobs.acquire(a, 2).unwrap_err();
        assert_eq!(e.status(), StatusCode::TOO_MANY_REQUESTS);
        assert_eq!(e.body().limit.as_deref(), Some("jobs_per_client"));
        let _s3 = jobs.acquire(b, 2).unwrap();
        drop(s1);
        assert_eq!(jobs.running(a), 1);
        let _s4 = jobs.acquire(a, 2).unwrap();
    }
}
