//! # frep-wire
//!
//! The one source of truth for what crosses the wire between the frep server
//! and its clients: the HTTP API's bodies, the WebSocket session's messages,
//! and the adaptive engine's decisions as the studio sees them.
//!
//! Every type derives `serde` (JSON, camelCase fields) and `ts_rs::TS`; the
//! browser's `web/src/wire.ts` is generated from them by [`typescript`], and
//! a test fails when the committed file is stale. With the `openapi`
//! feature every type also derives `utoipa::ToSchema` for the server's
//! OpenAPI document.
//!
//! Conventions: times are milliseconds since the Unix epoch (`i64`, a
//! TypeScript `number`); sizes are bytes; durations are milliseconds as
//! `f64`. Model ids are opaque strings.
#![warn(missing_docs)]

pub mod artefact;
pub mod compile;
pub mod decision;
pub mod error;
pub mod model;
pub mod session;
mod typescript;

pub use artefact::*;
pub use compile::*;
pub use decision::*;
pub use error::*;
pub use model::*;
pub use session::*;
pub use typescript::typescript;
