//! The table of contents of the server: every route in one place, and the
//! layers every request goes through.
//!
//! Layers, outermost first:
//! 1. a tracing span per request: method, path, then status and duration
//!    when answered;
//! 2. a panic in a handler becomes a 500 `ApiError`; the connection and the
//!    server live on;
//! 3. compression for the bodies it helps. Not images, glb or 3MF, which
//!    are compressed already;
//! 4. the request body limit (`limits.request_bytes`, `limits.asset_bytes`
//!    for uploads). The extractors enforce it, so that a refusal is a JSON
//!    `ApiError` naming the limit.

use std::any::Any;
use std::path::Path;
use std::time::Duration;

use axum::body::Body;
use axum::extract::{DefaultBodyLimit, State};
use axum::http::{header, HeaderValue, Request, Response, StatusCode};
use axum::response::IntoResponse;
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::Serialize;
use tower::ServiceBuilder;
use tower_http::catch_panic::CatchPanicLayer;
use tower_http::compression::predicate::{NotForContentType, Predicate, SizeAbove};
use tower_http::compression::CompressionLayer;
use tower_http::services::{ServeDir, ServeFile};
use tower_http::set_header::SetResponseHeaderLayer;
use tower_http::trace::TraceLayer;
use tracing::Span;

use crate::artefacts::IMMUTABLE;
use crate::error::AppError;
use crate::state::AppState;
use crate::{artefacts, assets, compile, models, openapi, page, session, versions};

/// The whole application.
pub fn router(state: AppState) -> Router {
    let limits = &state.config.limits;
    let api = Router::new()
        .route("/api/models", get(models::list).post(models::create))
        .route(
            "/api/models/{id}",
            get(models::get)
                .patch(models::rename)
                .delete(models::delete),
        )
        .route(
            "/api/models/{id}/versions",
            get(versions::history).post(versions::save),
        )
        .route("/api/models/{id}/versions/{n}", get(versions::get_version))
        .route("/api/models/{id}/diff", get(versions::diff))
        .route("/api/models/{id}/restore", post(versions::restore))
        .route("/api/models/{id}/duplicate", post(models::duplicate))
        .route("/api/models/{id}/log", get(models::log))
        .route("/api/compile", post(compile::compile))
        .route("/api/artefacts", post(artefacts::request))
        .route("/api/artefacts/{file}", get(artefacts::get))
        .route(
            "/api/assets",
            post(assets::upload).layer(DefaultBodyLimit::max(limits.asset_bytes)),
        )
        .route("/api/assets/{hash}", get(assets::get))
        .route("/api/openapi.json", get(openapi::document))
        .route("/api/health", get(health))
        .route("/api/session", get(session::handler))
        .route("/api/{*rest}", axum::routing::any(api_not_found))
        .method_not_allowed_fallback(method_not_allowed);
    let app = match state.config.studio_dir() {
        Some(dir) => studio(api, dir),
        None => api.route("/", get(page::index)).fallback(page_not_found),
    };
    app.layer(DefaultBodyLimit::max(limits.request_bytes))
        .layer(CompressionLayer::new().compress_when(compressible()))
        .layer(CatchPanicLayer::custom(panic_response))
        .layer(
            TraceLayer::new_for_http()
                .make_span_with(|req: &Request<Body>| {
                    tracing::info_span!(
                        "request",
                        method = %req.method(),
                        path = %req.uri().path(),
                        status = tracing::field::Empty,
                        duration_ms = tracing::field::Empty,
                    )
                })
                .on_request(())
                .on_response(|res: &Response<_>, latency: Duration, span: &Span| {
                    span.record("status", res.status().as_u16());
                    span.record("duration_ms", latency.as_secs_f64() * 1e3);
                    tracing::info!("answered");
                })
                .on_failure(()),
        )
        .with_state(state)
}

/// The built studio. Its hashed `assets/` are immutable. Everything else is
/// revalidated on every load, so that a new build is picked up: that is
/// `index.html`, also for the studio's own client-side paths. The build
/// writes `.br` and `.gz` beside each file (web/build/precompress.ts). They
/// are sent where the client accepts them, so nothing is compressed per
/// request.
fn studio(api: Router<AppState>, dir: &Path) -> Router<AppState> {
    let assets = ServiceBuilder::new()
        .layer(SetResponseHeaderLayer::if_not_present(
            header::CACHE_CONTROL,
            |res: &Response<_>| {
                res.status()
                    .is_success()
                    .then(|| HeaderValue::from_static(IMMUTABLE))
            },
        ))
        .service(
            ServeDir::new(dir.join("assets"))
                .precompressed_br()
                .precompressed_gzip(),
        );
    let rest = ServiceBuilder::new()
        .layer(SetResponseHeaderLayer::if_not_present(
            header::CACHE_CONTROL,
            HeaderValue::from_static("no-cache"),
        ))
        .service(
            ServeDir::new(dir)
                .precompressed_br()
                .precompressed_gzip()
                .fallback(
                    ServeFile::new(dir.join("index.html"))
                        .precompressed_br()
                        .precompressed_gzip(),
                ),
        );
    api.nest_service("/assets", assets).fallback_service(rest)
}

/// Compress text-like bodies over 256 bytes; never images, glb (meshopt
/// already), 3MF (a zip), or anything already encoded.
fn compressible() -> impl Predicate {
    SizeAbove::new(256)
        .and(NotForContentType::GRPC)
        .and(NotForContentType::IMAGES)
        .and(NotForContentType::SSE)
        .and(NotForContentType::const_new("model/gltf-binary"))
        .and(NotForContentType::const_new("model/3mf"))
        .and(NotForContentType::const_new("application/zip"))
}

/// A handler's panic as a 500 `ApiError` (logged with its message).
fn panic_response(err: Box<dyn Any + Send + 'static>) -> Response<Body> {
    let message = err
        .downcast_ref::<String>()
        .map(String::as_str)
        .or_else(|| err.downcast_ref::<&str>().copied())
        .unwrap_or("a handler panicked");
    AppError::Internal(format!("panic: {message}")).into_response()
}

async fn api_not_found(uri: axum::http::Uri) -> AppError {
    AppError::NotFound(format!("no API route {}", uri.path()))
}

async fn method_not_allowed(method: axum::http::Method, uri: axum::http::Uri) -> AppError {
    AppError::MethodNotAllowed(format!("{method} is not allowed on {}", uri.path()))
}

async fn page_not_found(uri: axum::http::Uri) -> AppError {
    AppError::NotFound(format!("nothing at {}", uri.path()))
}

/// `GET /api/health`.
#[derive(Debug, Serialize, utoipa::ToSchema)]
#[serde(rename_all = "camelCase")]
pub struct Health {
    /// Always `ok` when the server answers.
    pub status: &'static str,
    /// The server's version.
    pub version: &'static str,
    /// Artefact jobs running or queued.
    pub jobs: usize,
    /// Bytes in the artefact cache.
    pub cache_bytes: u64,
    /// Whether shutdown has begun.
    pub shutting_down: bool,
}

/// Whether the server answers, and how loaded it is.
#[utoipa::path(
    get,
    path = "/api/health",
    tag = "server",
    responses((status = 200, description = "The server is up", body = Health))
)]
pub async fn health(State(state): State<AppState>) -> impl IntoResponse {
    let status = if state.is_shutting_down() {
        StatusCode::SERVICE_UNAVAILABLE
    } else {
        StatusCode::OK
    };
    (
        status,
        Json(Health {
            status: if state.is_shutting_down() {
                "shutting_down"
            } else {
                "ok"
            },
            version: env!("CARGO_PKG_VERSION"),
            jobs: state.artefacts.in_flight(),
            cache_bytes: state.artefacts.cache_bytes(),
            shutting_down: state.is_shutting_down(),
        }),
    )
}
