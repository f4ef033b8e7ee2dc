//! One error type for every handler, answered as a JSON [`ApiError`].
//!
//! Policy:
//! - Every failure a client can cause gets a 4xx status, a stable
//!   machine-readable `code`, and a message a person can act on.
//! - Nothing a client sends can produce a 5xx, except a real fault of the
//!   server. Then the message is generic, and the cause goes to the log,
//!   not the wire.
//!
//! | code | status | when |
//! |---|---|---|
//! | `bad_request` | 400 | malformed JSON, bad path or query, impossible settings |
//! | `model_error` | 422 | the model does not compile; `diagnostics` name line and column |
//! | `limit` | 413 (sizes) / 422 (settings) / 429 (jobs) | a configured limit; `limit` names the setting |
//! | `compute_failed` | 422 | a kernel could not compute an artefact of the model |
//! | `forbidden` | 403 | a write by a user who may not edit the model |
//! | `not_found` | 404 | no such model, version, artefact or asset |
//! | `method_not_allowed` | 405 | a route used with another method |
//! | `conflict` | 409 | a save whose base is no longer the latest (the message and `latest` say which is) |
//! | `busy` | 503 | the artefact queue is full, or the server is shutting down |
//! | `cancelled` | 503 | the computation was cancelled (shutdown) |
//! | `internal` | 500 | a fault of the server (store, disk, a panic) |

use axum::extract::rejection::{JsonRejection, PathRejection, QueryRejection};
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use frep_store::StoreError;
use frep_wire::{ApiError, Diagnostic};

/// A failed request.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// Malformed input.
    #[error("{0}")]
    BadRequest(String),
    /// No such thing.
    #[error("{0}")]
    NotFound(String),
    /// The route exists, not with this method.
    #[error("{0}")]
    MethodNotAllowed(String),
    /// The user may not do this.
    #[error("{0}")]
    Forbidden(String),
    /// A save based on a version that is no longer the latest.
    #[error("version {base} is not the latest; the latest is {latest}")]
    Conflict {
        /// The version the edit started from.
        base: u32,
        /// The model's latest version.
        latest: u32,
    },
    /// The model does not compile.
    #[error("the model has {} error(s)", .0.len())]
    Model(Vec<Diagnostic>),
    /// A configured limit was exceeded.
    #[error("{message}")]
    Limit {
        /// The setting's name (`Limits`' field name).
        name: String,
        /// What was asked for and what is allowed.
        message: String,
        /// 413 for sizes, 422 for settings, 429 for jobs.
        status: StatusCode,
    },
    /// The model was accepted but a kernel could not compute the artefact.
    #[error("{0}")]
    Unprocessable(String),
    /// The server cannot take the work now.
    #[error("{0}")]
    Busy(String),
    /// The work was cancelled.
    #[error("cancelled: {0}")]
    Cancelled(String),
    /// A fault of the server; the text goes to the log only.
    #[error("internal error: {0}")]
    Internal(String),
}

impl AppError {
    /// A limit exceeded: `name` is the configuration name.
    pub fn limit(name: &str, status: StatusCode, message: impl Into<String>) -> AppError {
        AppError::Limit {
            name: name.to_string(),
            message: message.into(),
            status,
        }
    }

    /// The HTTP status.
    pub fn status(&self) -> StatusCode {
        match self {
            AppError::BadRequest(_) => StatusCode::BAD_REQUEST,
            AppError::NotFound(_) => StatusCode::NOT_FOUND,
            AppError::MethodNotAllowed(_) => StatusCode::METHOD_NOT_ALLOWED,
            AppError::Forbidden(_) => StatusCode::FORBIDDEN,
            AppError::Conflict { .. } => StatusCode::CONFLICT,
            AppError::Model(_) | AppError::Unprocessable(_) => StatusCode::UNPROCESSABLE_ENTITY,
            AppError::Limit { status, .. } => *status,
            AppError::Busy(_) | AppError::Cancelled(_) => StatusCode::SERVICE_UNAVAILABLE,
            AppError::Internal(_) => StatusCode::INTERNAL_SERVER_ERROR,
        }
    }

    /// The wire body.
    pub fn body(&self) -> ApiError {
        let (code, message) = match self {
            AppError::BadRequest(m) => ("bad_request", m.clone()),
            AppError::NotFound(m) => ("not_found", m.clone()),
            AppError::MethodNotAllowed(m) => ("method_not_allowed", m.clone()),
            AppError::Forbidden(m) => ("forbidden", m.clone()),
            AppError::Conflict { .. } => ("conflict", self.to_string()),
            AppError::Model(_) => ("model_error", self.to_string()),
            AppError::Unprocessable(m) => ("compute_failed", m.clone()),
            AppError::Limit { message, .. } => ("limit", message.clone()),
            AppError::Busy(m) => ("busy", m.clone()),
            AppError::Cancelled(_) => ("cancelled", self.to_string()),
            // The cause may name files or SQL: it is logged, not sent.
            AppError::Internal(_) => ("internal", "internal server error".to_string()),
        };
        ApiError {
            code: code.to_string(),
            message,
            diagnostics: match self {
                AppError::Model(d) => d.clone(),
                _ => Vec::new(),
            },
            limit: match self {
                AppError::Limit { name, .. } => Some(name.clone()),
                _ => None,
            },
            latest: match self {
                AppError::Conflict { latest, .. } => Some(*latest),
                _ => None,
            },
        }
    }
}

impl IntoResponse for AppError {
    fn into_response(self) -> Response {
        let status = self.status();
        if status.is_server_error() {
            tracing::error!(error = %self, "request failed");
        } else {
            tracing::debug!(error = %self, "request refused");
        }
        (status, Json(self.body())).into_response()
    }
}

impl From<JsonRejection> for AppError {
    fn from(r: JsonRejection) -> Self {
        if r.status() == StatusCode::PAYLOAD_TOO_LARGE {
            return AppError::limit(
                "request_bytes",
                StatusCode::PAYLOAD_TOO_LARGE,
                "the request body is larger than the limit request_bytes",
            );
        }
        AppError::BadRequest(r.body_text())
    }
}

impl From<PathRejection> for AppError {
    fn from(r: PathRejection) -> Self {
        AppError::BadRequest(r.body_text())
    }
}

impl From<QueryRejection> for AppError {
    fn from(r: QueryRejection) -> Self {
        AppError::BadRequest(r.body_text())
    }
}

impl From<StoreError> for AppError {
    fn from(e: StoreError) -> Self {
        match e {
            StoreError::NotFound(m) => AppError::NotFound(m),
            StoreError::Conflict { base, latest } => AppError::Conflict { base, latest },
            StoreError::Limit { name, limit, got } => {
                let (setting, status) = match name {
                    "max_source_bytes" => ("source_bytes", StatusCode::PAYLOAD_TOO_LARGE),
                    "max_asset_bytes" => ("asset_bytes", StatusCode::PAYLOAD_TOO_LARGE),
                    "max_params" => ("params", StatusCode::UNPROCESSABLE_ENTITY),
                    other => (other, StatusCode::UNPROCESSABLE_ENTITY),
                };
                AppError::limit(
                    setting,
                    status,
                    format!("{got} is over the limit {setting} = {limit}"),
                )
            }
            StoreError::Forbidden(m) => AppError::Forbidden(m),
            StoreError::Invalid(m) => AppError::BadRequest(m),
            StoreError::Closed => AppError::Busy("the store is closed (shutting down)".into()),
            e @ (StoreError::SchemaTooNew { .. } | StoreError::Db(_)) => {
                AppError::Internal(format!("store: {e}"))
            }
        }
    }
}

impl From<tokio::task::JoinError> for AppError {
    fn from(e: tokio::task::JoinError) -> Self {
        AppError::Internal(format!("a blocking task failed: {e}"))
    }
}

/// A handler's result.
pub type AppResult<T> = Result<T, AppError>;

/// `axum::Json` whose rejection is an [`AppError`] (a JSON [`ApiError`],
/// never axum's plain text).
#[derive(Debug, axum::extract::FromRequest)]
#[from_request(via(axum::Json), rejection(AppError))]
pub struct ApiJson<T>(pub T);

/// `axum::extract::Path` with an [`AppError`] rejection.
#[derive(Debug, axum::extract::FromRequestParts)]
#[from_request(via(axum::extract::Path), rejection(AppError))]
pub struct ApiPath<T>(pub T);

/// `axum::extract::Query` with an [`AppError`] rejection.
#[derive(Debug, axum::extract::FromRequestParts)]
#[from_request(via(axum::extract::Query), rejection(AppError))]
pub struct ApiQuery<T>(pub T);
