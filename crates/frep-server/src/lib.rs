//! # frep-server
//!
//! The frep server: one axum application in front of three tiers.
//!
//! 1. **Store** (`frep-store`): the master copy of every model, in SQLite
//!    under the data folder. It holds immutable versions, the ordered change
//!    log and uploaded assets. Its calls block, so they run on tokio's
//!    blocking pool. A write is answered only after the store committed it,
//!    and only then published to the sessions ([`AppState::changes`]).
//! 2. **Artefacts** (`frep-artefact`): compiled models (cached by source),
//!    and what is computed from them: images, view sets, meshes, slices,
//!    shaders, exports. They live at content-addressed URLs. Each is
//!    computed once on a bounded worker pool, and kept in a disk cache under
//!    the data folder.
//! 3. **Sessions** (`session`, WebSocket `/api/session`): a studio's live
//!    connection, where the adaptive engine (`frep-adapt`) picks the
//!    delivery mode.
//!
//! How a request flows:
//! 1. [`router::router`] lists every route.
//! 2. A request gets a tracing span, the body limit, compression.
//! 3. Its handler reads typed JSON; a malformed body is a 400 `ApiError`.
//!    There is one file per resource: [`models`], [`versions`],
//!    [`compile`], [`artefacts`], [`assets`].
//! 4. The handler checks the configured limits, and asks the store or the
//!    artefact service.
//! 5. It answers JSON or bytes.
//!
//! Every failure is one [`AppError`], answered as a JSON `ApiError` with a
//! status ([`error`] has the policy).
//!
//! Start it with [`run`]: `run(listener, config, shutdown)` serves until
//! `shutdown` completes. Then it stops accepting, and lets requests in
//! flight finish for `config.shutdown_grace_ms`. It cancels the artefact
//! jobs still running after that, and closes the store. Tests drive a real
//! server on `127.0.0.1:0` this way; `frep serve` is the same call.
#![warn(missing_docs)]

pub mod artefacts;
pub mod assets;
pub mod auth;
pub mod compile;
pub mod config;
pub mod error;
pub mod examples;
pub mod models;
pub mod openapi;
pub mod page;
pub mod router;
pub mod session;
pub mod state;
pub mod versions;

use std::future::{Future, IntoFuture};
use std::net::SocketAddr;
use std::sync::Arc;
use std::time::Duration;

use frep_artefact::{Artefacts, CompileCache};
use frep_store::{SqliteStore, Store};
use tokio::sync::{broadcast, watch};

pub use config::{Config, ConfigError, Limits};
pub use error::AppError;
pub use state::AppState;

/// Why the server could not start or stopped with an error.
#[derive(Debug, thiserror::Error)]
pub enum ServerError {
    /// The data folder could not be created.
    #[error("data folder {path}: {source}")]
    DataDir {
        /// The folder.
        path: std::path::PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The store could not be opened or seeded.
    #[error("store: {0}")]
    Store(String),
    /// The artefact service could not start (its cache folder).
    #[error("artefacts: {0}")]
    Artefacts(#[from] frep_artefact::ArtefactError),
    /// Serving failed.
    #[error("serve: {0}")]
    Serve(#[from] std::io::Error),
}

/// Opens the data folder's store and artefact cache, seeds the examples on
/// first start, and builds the state. `shutdown` and `cancel_jobs` are the
/// receivers of [`run`]'s signals.
pub fn open_state(
    config: Config,
    shutdown: watch::Receiver<bool>,
    cancel_jobs: watch::Receiver<bool>,
) -> Result<AppState, ServerError> {
    std::fs::create_dir_all(&config.data_dir).map_err(|source| ServerError::DataDir {
        path: config.data_dir.clone(),
        source,
    })?;
    let store = SqliteStore::open(&config.database_path(), config.store_limits())
        .map_err(|e| ServerError::Store(e.to_string()))?;
    let store: Arc<dyn Store> = Arc::new(store);
    let seeded = examples::seed(store.as_ref(), &config.data_dir)
        .map_err(|e| ServerError::Store(e.to_string()))?;
    if seeded > 0 {
        tracing::info!(models = seeded, "seeded the example models");
    }
    let artefacts = Artefacts::new(config.artefact_config())?;
    let (changes, _) = broadcast::channel(state::CHANGE_BACKLOG);
    Ok(AppState {
        store,
        artefacts: Arc::new(artefacts),
        compiles: Arc::new(CompileCache::new(config.limits.compile_cache)),
        config: Arc::new(config),
        changes,
        jobs: Arc::new(state::ClientJobs::default()),
        shutdown,
        cancel_jobs,
        session_hub: Arc::new(std::sync::OnceLock::new()),
    })
}

/// Serves the API and the studio on `listener` until `shutdown` completes,
/// then shuts down gracefully (see the crate doc).
pub async fn run(
    listener: tokio::net::TcpListener,
    config: Config,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ServerError> {
    let (shutdown_tx, shutdown_rx) = watch::channel(false);
    let (cancel_tx, cancel_rx) = watch::channel(false);
    let grace = Duration::from_millis(config.shutdown_grace_ms);
    let state = {
        let config = config.clone();
        let (s, c) = (shutdown_rx.clone(), cancel_rx);
        tokio::task::spawn_blocking(move || open_state(config, s, c))
            .await
            .map_err(|e| ServerError::Store(format!("opening the store: {e}")))??
    };
    if let Ok(addr) = listener.local_addr() {
        tracing::info!(%addr, data = %config.data_dir.display(), "listening");
    }
    let app = router::router(state.clone());
    let mut drained = shutdown_rx.clone();
    let serve = axum::serve(
        listener,
        app.into_make_service_with_connect_info::<SocketAddr>(),
    )
    .with_graceful_shutdown(async move {
        shutdown.await;
        tracing::info!("shutting down: no new connections");
        let _ = shutdown_tx.send(true);
    })
    .into_future();
    tokio::pin!(serve);
    // Requests in flight may finish within the grace period; after it,
    // those still waiting for an artefact give up, which cancels the jobs.
    let served = tokio::select! {
        r = &mut serve => r,
        _ = async {
            let _ = drained.wait_for(|v| *v).await;
            tokio::time::sleep(grace).await;
        } => {
            tracing::warn!("grace period over: cancelling artefact jobs");
            let _ = cancel_tx.send(true);
            // A request stuck elsewhere (not on a job) must not hold the
            // exit forever: its connection is left to the runtime.
            match tokio::time::timeout(grace, serve).await {
                Ok(r) => r,
                Err(_) => {
                    tracing::warn!("requests still open after the grace period; leaving them");
                    Ok(())
                }
            }
        }
    };
    let _ = cancel_tx.send(true);
    wait_for_jobs(&state, grace).await;
    close(state).await;
    served.map_err(ServerError::Serve)
}

/// Waits (bounded) for the artefact jobs to wind down after cancellation.
async fn wait_for_jobs(state: &AppState, bound: Duration) {
    let deadline = tokio::time::Instant::now() + bound;
    while state.artefacts.in_flight() > 0 && tokio::time::Instant::now() < deadline {
        tokio::time::sleep(Duration::from_millis(20)).await;
    }
    let left = state.artefacts.in_flight();
    if left > 0 {
        tracing::warn!(jobs = left, "artefact jobs still winding down at exit");
    }
}

/// Closes the store: every write was committed before it was answered, so
/// this only releases the database (checkpointing its journal).
async fn close(state: AppState) {
    let store = Arc::clone(&state.store);
    drop(state);
    let r = tokio::task::spawn_blocking(move || store.close()).await;
    match r {
        Ok(Ok(())) => tracing::info!("store closed"),
        Ok(Err(e)) => tracing::error!("closing the store: {e}"),
        Err(e) => tracing::error!("closing the store: {e}"),
    }
}
