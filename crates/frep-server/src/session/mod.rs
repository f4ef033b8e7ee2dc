//! The studio's WebSocket session, `GET /api/session`: one socket per open
//! studio. Over it the server:
//! - measures the client and its link;
//! - decides how the model reaches the screen (the adaptive engine);
//! - streams mode 1 frames;
//! - pushes decisions, artefacts, progress and model changes.
//!
//! Protocol: frep-wire's `session.rs`. JSON text messages go both ways;
//! binary messages go down for probe bytes and frames. Parts, one per file:
//! - [`probe`]: round trips, bandwidth;
//! - [`decide`]: the engine;
//! - [`open`]: resolve and compile;
//! - [`specs`]: the artefacts of a mode;
//! - [`deliver`]: registering, computing, progress;
//! - [`stream`]: mode 1 frames;
//! - [`follow`]: other editors' saves;
//! - [`hub`]: what sessions share;
//! - `core`: one session's state and its reactions;
//! - [`wire`].
//!
//! Each session is one task with a tracing span (`session.id`). Its loop
//! owns the socket and waits on four things:
//! 1. the client's messages;
//! 2. events from the session's own tasks (compiles, artefact jobs, the
//!    frame renderer), over a bounded channel;
//! 3. a housekeeping tick;
//! 4. the server's change feed and shutdown.
//!
//! Reactions only change state and queue messages. The loop then writes
//! them, so every message to the client goes through one writer. A bad
//! message gets an `error` message, never a panic or a close. The socket
//! closes on the client's close, a socket error, a message over
//! `max_message_bytes`, or the server's shutdown.

pub mod config;
mod core;
pub mod decide;
pub mod deliver;
pub mod follow;
pub mod hub;
pub mod open;
pub mod probe;
pub mod specs;
pub mod stream;
pub mod wire;

use std::net::SocketAddr;
use std::time::Duration;

use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{ConnectInfo, State};
use axum::http::HeaderMap;
use axum::response::Response;
use axum::Extension;
use frep_adapt::ServerSample;
use tokio::sync::{broadcast, mpsc};
use tracing::Instrument;

pub use config::SessionConfig;
pub use hub::Hub;

use crate::auth::User;
use crate::state::AppState;

/// What a session's own tasks tell its loop.
#[derive(Debug)]
pub enum Event {
    /// A message to send as is (progress).
    Send(Message),
    /// A rendered frame.
    Frame(stream::Frame),
    /// An `open` was resolved and compiled (or not).
    Opened {
        /// The open's number (stale ones are ignored).
        gen: u64,
        /// The model, or what went wrong.
        result: Result<open::Opened, String>,
    },
    /// A computed artefact's cost.
    Measured(ServerSample),
    /// A problem to report to the client.
    Error(String),
}

/// `GET /api/session`: upgrades to the session's WebSocket.
pub async fn handler(
    ws: WebSocketUpgrade,
    State(state): State<AppState>,
    headers: HeaderMap,
    peer: Option<Extension<ConnectInfo<SocketAddr>>>,
) -> Response {
    let hub = Hub::of(&state);
    let max = hub.config.max_message_bytes;
    let user = User::from_headers(&headers).0;
    let peer = peer.map(|Extension(ConnectInfo(a))| a.ip());
    ws.max_message_size(max)
        .max_frame_size(max)
        .on_upgrade(move |socket| run(socket, state, hub, user, peer))
}

/// One session from its upgrade to its close.
async fn run(
    mut socket: WebSocket,
    state: AppState,
    hub: std::sync::Arc<Hub>,
    user: String,
    peer: Option<std::net::IpAddr>,
) {
    let Some(ticket) = hub.enter() else {
        let msg = format!(
            "the server has {} sessions open (limit max_sessions)",
            hub.sessions()
        );
        let _ = socket.send(wire::error(msg)).await;
        let _ = socket.send(Message::Close(None)).await;
        return;
    };
    let id = session_id(ticket.number);
    let span = tracing::info_span!("session", session.id = %id, user = %user);
    async move {
        tracing::info!(peer = ?peer, sessions = hub.sessions(), "session opened");
        let (events_tx, events_rx) = mpsc::channel(hub.config.outbox.max(1));
        let core = core::Session::new(id, state.clone(), hub.clone(), user, peer, events_tx);
        match core {
            Ok(core) => serve(socket, state, core, events_rx).await,
            Err(e) => {
                let _ = socket.send(wire::error(e)).await;
            }
        }
        tracing::info!("session closed");
        drop(ticket);
    }
    .instrument(span)
    .await;
}

/// The session loop (module docs).
async fn serve(
    mut socket: WebSocket,
    state: AppState,
    mut s: core::Session,
    mut events: mpsc::Receiver<Event>,
) {
    let mut changes = state.changes.subscribe();
    let mut shutdown = state.shutdown.clone();
    let cfg = s.config();
    let every = cfg.tick_ms.min(cfg.ping_ms).clamp(10, 500);
    let mut tick = tokio::time::interval(Duration::from_millis(every));
    tick.set_missed_tick_behavior(tokio::time::MissedTickBehavior::Delay);
    s.welcome();
    loop {
        // The first decision's wait for a probe ends at its own deadline,
        // not at the next tick.
        let deadline = s.first_decision_deadline();
        let first_due = async move {
            match deadline {
                Some(t) => tokio::time::sleep_until(t.into()).await,
                None => std::future::pending().await,
            }
        };
        for msg in s.take_outbox() {
            if let Err(e) = socket.send(msg).await {
                tracing::debug!("send failed: {e}");
                return;
            }
        }
        tokio::select! {
            msg = socket.recv() => match msg {
                Some(Ok(Message::Text(t))) => s.client_text(t.as_str()),
                Some(Ok(Message::Binary(_))) => {
                    s.error("the session takes JSON text messages only");
                }
                Some(Ok(Message::Close(_))) | None => break,
                Some(Ok(_)) => {}
                Some(Err(e)) => {
                    tracing::debug!("socket: {e}");
                    break;
                }
            },
            Some(event) = events.recv() => s.event(event),
            _ = tick.tick() => s.tick(),
            () = first_due => s.first_decision_due(),
            change = changes.recv() => match change {
                Ok(c) => s.change(&c),
                Err(broadcast::error::RecvError::Lagged(n)) => s.lagged(n),
                Err(broadcast::error::RecvError::Closed) => {}
            },
            _ = shutdown.changed() => {
                let _ = socket.send(Message::Close(None)).await;
                break;
            }
        }
    }
    s.close();
}

/// A session id: the session's number on this server and 8 hex digits of
/// the time. It is unique within a server, and hard to guess across
/// restarts.
fn session_id(number: usize) -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    let h = blake3::hash(format!("{number}/{nanos}").as_bytes());
    format!("{number}-{}", &h.to_hex()[..8])
}
