//! Artefacts: `POST /api/artefacts` (where it will be) and
//! `GET /api/artefacts/{key}.{ext}` (the bytes).
//!
//! The POST:
//! 1. resolves the model: a stored version, or a source being edited;
//! 2. compiles it (cached);
//! 3. registers the request with the artefact service, which answers the
//!    content address at once.
//!
//! The GET serves the bytes at that immutable URL.
//! - `ETag` is the key, so an `If-None-Match` carrying it is answered 304
//!   without touching the cache.
//! - Otherwise the body comes from the disk cache, or from the one job
//!   computing it.
//! - A job takes one of the client's `jobs_per_client` slots while the
//!   client waits for it. Cached answers take none.
//! - The service's own queue bounds the whole server: `workers` + `queue`,
//!   then 503.
//! - When shutdown's grace period ends, waiting requests give up, which
//!   cancels their jobs.
//!
//! Exports (`stl`, `obj`, `ply`, `glb`, `3mf`) are sent as attachments; the
//! file name is `?name=` (sanitised) or `frep-{key prefix}`.

use std::net::SocketAddr;

use axum::extract::{ConnectInfo, State};
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use frep_artefact::ArtefactError;
use frep_wire::{ApiError, ArtefactRef, ArtefactRequest, ModelRef};
use serde::Deserialize;
use tracing::Instrument;

use crate::compile::{check_params, check_source, compile_source};
use crate::error::{ApiJson, ApiPath, ApiQuery, AppError, AppResult};
use crate::state::AppState;

/// `Cache-Control` of every artefact: its URL is its content.
pub const IMMUTABLE: &str = "public, max-age=31536000, immutable";

/// Registers an artefact: its content address, at once.
#[utoipa::path(
    post,
    path = "/api/artefacts",
    tag = "artefacts",
    request_body = ArtefactRequest,
    responses(
        (status = 200, description = "Where the artefact is (`ready` when cached)", body = ArtefactRef),
        (status = 404, description = "No such model or version", body = ApiError),
        (status = 422, description = "Model error (diagnostics) or a limit (named)", body = ApiError),
    )
)]
pub async fn request(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<ArtefactRequest>,
) -> AppResult<Json<ArtefactRef>> {
    check_params(&state, &req.params)?;
    let (source, mut params) = match req.model {
        ModelRef::Source { source } => (source, Vec::new()),
        ModelRef::Version { model_id, version } => {
            let v = crate::versions::load_version(&state, model_id, version).await?;
            (v.source, v.params)
        }
    };
    check_source(&state, &source)?;
    if !req.params.is_empty() {
        params = req.params;
    }
    // The box is detected at the defaults (it stays put while a slider
    // moves), so the compile does not depend on the values.
    let compiled = compile_source(&state, source, None, Vec::new())
        .await?
        .map_err(AppError::Model)?;
    let span = tracing::info_span!("artefact_request", graph = compiled.graph_hash());
    let _enter = span.enter();
    let r = state
        .artefacts
        .request(compiled, &params, req.spec, None)
        .map_err(artefact_error)?;
    tracing::debug!(key = %r.key, ready = r.ready, "artefact registered");
    Ok(Json(r))
}

/// `?name=` of an artefact GET.
#[derive(Debug, Default, Deserialize, utoipa::IntoParams)]
pub struct ArtefactQuery {
    /// The download's file name, without extension.
    pub name: Option<String>,
}

/// The bytes of an artefact (computed if needed).
#[utoipa::path(
    get,
    path = "/api/artefacts/{file}",
    tag = "artefacts",
    params(
        ("file" = String, Path, description = "`{key}.{ext}` as in `ArtefactRef.url`"),
        ArtefactQuery,
    ),
    responses(
        (status = 200, description = "The body; `Cache-Control: immutable`, `ETag` the key"),
        (status = 304, description = "`If-None-Match` names the key"),
        (status = 404, description = "Unknown key", body = ApiError),
        (status = 429, description = "Over `jobs_per_client`", body = ApiError),
        (status = 503, description = "The queue is full, or shutting down", body = ApiError),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    ConnectInfo(peer): ConnectInfo<SocketAddr>,
    ApiPath(file): ApiPath<String>,
    ApiQuery(query): ApiQuery<ArtefactQuery>,
    headers: HeaderMap,
) -> AppResult<Response> {
    let (key, ext) = file
        .rsplit_once('.')
        .filter(|(k, _)| frep_artefact::is_key(k))
        .ok_or_else(|| AppError::NotFound(format!("no artefact {file}")))?;
    let etag = format!("\"{key}\"");
    if if_none_match(&headers, &etag) {
        let mut r = StatusCode::NOT_MODIFIED.into_response();
        set_cache_headers(r.headers_mut(), &etag);
        return Ok(r);
    }
    let _slot = if state.artefacts.is_cached(key) {
        None
    } else {
        Some(
            state
                .jobs
                .acquire(peer.ip(), state.config.limits.jobs_per_client)?,
        )
    };
    // The job's span: the artefact service's own events (compute, cache)
    // are recorded inside it.
    let span = tracing::info_span!("job", key = %key, ext = %ext);
    let body = tokio::select! {
        r = state.artefacts.get(key).instrument(span.clone()) => r.map_err(artefact_error)?,
        _ = state.jobs_cancelled() => {
            tracing::info!(parent: &span, "cancelled by shutdown");
            return Err(AppError::Cancelled("the server is shutting down".into()));
        }
    };
    if !extension_fits(ext, &body.media_type) {
        return Err(AppError::NotFound(format!(
            "artefact {key} is {}, not .{ext}",
            body.media_type
        )));
    }
    tracing::info!(
        parent: &span,
        cached = body.cached,
        bytes = body.bytes.len(),
        server_ms = body.server_ms,
        "artefact served"
    );
    let mut r = body.bytes.into_response();
    let h = r.headers_mut();
    set_cache_headers(h, &etag);
    insert(h, header::CONTENT_TYPE.as_str(), &body.media_type);
    insert(h, "x-frep-server-ms", &format!("{:.1}", body.server_ms));
    if let Some(volume) = &body.volume {
        if let Ok(json) = serde_json::to_string(volume) {
            insert(h, "x-frep-volume", &json);
        }
    }
    if is_export(ext) {
        let name =
            sanitize_name(query.name.as_deref()).unwrap_or_else(|| format!("frep-{}", &key[..12]));
        insert(
            h,
            header::CONTENT_DISPOSITION.as_str(),
            &format!("attachment; filename=\"{name}.{ext}\""),
        );
    }
    Ok(r)
}

/// Whether `If-None-Match` lists `etag` (or `*`).
fn if_none_match(headers: &HeaderMap, etag: &str) -> bool {
    headers
        .get_all(header::IF_NONE_MATCH)
        .iter()
        .filter_map(|v| v.to_str().ok())
        .flat_map(|v| v.split(','))
        .map(|t| t.trim().trim_start_matches("W/"))
        .any(|t| t == etag || t == "*")
}

fn set_cache_headers(h: &mut HeaderMap, etag: &str) {
    insert(h, header::CACHE_CONTROL.as_str(), IMMUTABLE);
    insert(h, header::ETAG.as_str(), etag);
}

/// Inserts a header, skipping a value that is not a valid header (it
/// cannot happen for the values built here, which are ASCII).
fn insert(h: &mut HeaderMap, name: &'static str, value: &str) {
    if let Ok(v) = HeaderValue::from_str(value) {
        h.insert(name, v);
    }
}

/// Downloads rather than views.
fn is_export(ext: &str) -> bool {
    matches!(ext, "stl" | "obj" | "ply" | "glb" | "3mf")
}

/// Whether a URL's extension is the one of the body's media type. The key
/// alone decides the body, so a wrong extension is a wrong URL.
fn extension_fits(ext: &str, media_type: &str) -> bool {
    let expected: &[&str] = match media_type {
        "image/jpeg" => &["jpg", "jpeg"],
        "image/png" => &["png"],
        "image/webp" => &["webp"],
        "application/json" => &["json"],
        "model/gltf-binary" => &["glb"],
        "application/octet-stream" => &["raw", "bin"],
        "model/stl" => &["stl"],
        "model/obj" => &["obj"],
        "application/ply" => &["ply"],
        "model/3mf" => &["3mf"],
        // A media type this table does not know: trust the key.
        _ => return true,
    };
    expected.contains(&ext)
}

/// A file name made of letters, digits, `-`, `_` and `.` (others become
/// `_`), at most 80 characters; `None` when nothing is left.
fn sanitize_name(name: Option<&str>) -> Option<String> {
    let cleaned: String = name?
        .chars()
        .take(80)
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '-' | '_' | '.') {
                c
            } else {
                '_'
            }
        })
        .collect();
    let cleaned = cleaned.trim_matches('.').to_string();
    (!cleaned.is_empty()).then_some(cleaned)
}

/// An artefact service error as an API error; limits are named by their
/// configuration names.
pub fn artefact_error(e: ArtefactError) -> AppError {
    match e {
        ArtefactError::UnknownKey(k) => AppError::NotFound(format!(
            "unknown artefact {k}: request it first (POST /api/artefacts)"
        )),
        ArtefactError::Limit { name, limit, got } => {
            let setting = limit_setting(name);
            AppError::limit(
                setting,
                StatusCode::UNPROCESSABLE_ENTITY,
                format!("{name} {got} is over the limit {setting} = {limit}"),
            )
        }
        ArtefactError::BadRequest(m) => AppError::BadRequest(m),
        ArtefactError::Busy(n) => AppError::limit(
            "queue",
            StatusCode::SERVICE_UNAVAILABLE,
            format!("the server is busy ({n} artefact jobs queued or running, limits workers + queue); retry later"),
        ),
        ArtefactError::Cancelled => AppError::Cancelled("the artefact job was cancelled".into()),
        ArtefactError::Model(d) => AppError::Model(d),
        // The kernels' own refusals of a model (e.g. a render that cannot
        // frame it) are the model's, not the server's.
        ArtefactError::Render(m) | ArtefactError::Mesh(m) => {
            AppError::Unprocessable(format!("the computation failed: {m}"))
        }
        ArtefactError::Io(m) => AppError::Internal(format!("artefact cache: {m}")),
    }
}

/// The [`crate::Limits`] field behind an artefact limit's name.
fn limit_setting(name: &str) -> &'static str {
    match name {
        "image side" => "image_max_side",
        "image pixels" => "image_max_pixels",
        "views" => "views_max",
        "sheet pixels" => "sheet_max_pixels",
        "mesh depth" => "mesh_max_depth",
        "export depth" => "export_max_depth",
        "volume grid" => "volume_max_grid",
        "triangles" => "triangles_max",
        "parameters" => "params",
        _ => "artefact",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn if_none_match_lists() {
        let mut h = HeaderMap::new();
        assert!(!if_none_match(&h, "\"k\""));
        h.insert(
            header::IF_NONE_MATCH,
            HeaderValue::from_static("\"a\", W/\"k\""),
        );
        assert!(if_none_match(&h, "\"k\""));
        assert!(!if_none_match(&h, "\"b\""));
    }

    #[test]
    fn names_are_sanitised() {
        assert_eq!(
            sanitize_name(Some("sake pot/../x")).as_deref(),
            Some("sake_pot_.._x")
        );
        assert_eq!(sanitize_name(Some("..")), None);
        assert_eq!(sanitize_name(None), None);
    }

    #[test]
    fn every_artefact_limit_has_a_setting() {
        for n in [
            "image side",
            "image pixels",
            "views",
            "sheet pixels",
            "mesh depth",
            "export depth",
            "volume grid",
            "parameters",
        ] {
            assert_ne!(limit_setting(n), "artefact", "{n}");
        }
    }
}
