//! Assets: `POST /api/assets` (raw bytes in, [`AssetRef`] out) and
//! `GET /api/assets/{hash}`.
//!
//! An asset is a file a model refers to: an imported mesh, an image. It is
//! stored once by the BLAKE3 hash of its content. So its URL is immutable
//! and served like an artefact (`Cache-Control: immutable`, `ETag` the
//! hash). Uploads are bounded by `limits.asset_bytes`, the route's own body
//! limit. The media type is the request's `Content-Type`, the name is
//! `?name=`.

use axum::body::Bytes;
use axum::extract::State;
use axum::http::{header, HeaderMap, HeaderValue, StatusCode};
use axum::response::{IntoResponse, Response};
use axum::Json;
use frep_wire::{ApiError, AssetRef};
use serde::Deserialize;

use crate::artefacts::IMMUTABLE;
use crate::auth::User;
use crate::error::{ApiPath, ApiQuery, AppError, AppResult};
use crate::state::AppState;

/// `?name=` of an upload.
#[derive(Debug, Default, Deserialize, utoipa::IntoParams)]
pub struct UploadQuery {
    /// The name the source uses for it.
    #[serde(default)]
    pub name: String,
}

/// Longest media type accepted.
const MAX_MEDIA_TYPE: usize = 127;

/// Stores an uploaded file.
#[utoipa::path(
    post, path = "/api/assets", tag = "assets",
    params(UploadQuery),
    request_body(content = Vec<u8>, description = "The file's bytes", content_type = "application/octet-stream"),
    responses(
        (status = 201, description = "Stored", body = AssetRef),
        (status = 413, description = "Over `asset_bytes`", body = ApiError),
    )
)]
pub async fn upload(
    State(state): State<AppState>,
    _user: User,
    ApiQuery(q): ApiQuery<UploadQuery>,
    headers: HeaderMap,
    body: Result<Bytes, axum::extract::rejection::BytesRejection>,
) -> AppResult<(StatusCode, Json<AssetRef>)> {
    let bytes = body.map_err(|r| {
        if r.status() == StatusCode::PAYLOAD_TOO_LARGE {
            AppError::limit(
                "asset_bytes",
                StatusCode::PAYLOAD_TOO_LARGE,
                format!(
                    "the asset is larger than the limit asset_bytes = {}",
                    state.config.limits.asset_bytes
                ),
            )
        } else {
            AppError::BadRequest(r.body_text())
        }
    })?;
    if bytes.is_empty() {
        return Err(AppError::BadRequest("an asset cannot be empty".into()));
    }
    let media_type = headers
        .get(header::CONTENT_TYPE)
        .and_then(|v| v.to_str().ok())
        .filter(|t| t.len() <= MAX_MEDIA_TYPE && !t.is_empty())
        .unwrap_or("application/octet-stream")
        .to_string();
    if q.name.chars().count() > crate::models::MAX_NAME_CHARS {
        return Err(AppError::BadRequest("the asset name is too long".into()));
    }
    let meta = state
        .store_call(move |s| s.put_asset(&bytes, &media_type))
        .await?;
    Ok((
        StatusCode::CREATED,
        Json(AssetRef {
            hash: meta.hash,
            size: meta.size,
            media_type: meta.media_type,
            name: q.name,
        }),
    ))
}

/// An uploaded file.
#[utoipa::path(
    get, path = "/api/assets/{hash}", tag = "assets",
    params(("hash" = String, Path, description = "BLAKE3 of the content, hex")),
    responses(
        (status = 200, description = "The bytes, `Cache-Control: immutable`"),
        (status = 304, description = "`If-None-Match` names the hash"),
        (status = 404, description = "No such asset", body = ApiError),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    ApiPath(hash): ApiPath<String>,
    headers: HeaderMap,
) -> AppResult<Response> {
    if !frep_artefact::is_key(&hash) {
        return Err(AppError::NotFound(format!("no asset {hash}")));
    }
    let etag = format!("\"{hash}\"");
    let cache = |r: &mut Response| {
        r.headers_mut()
            .insert(header::CACHE_CONTROL, HeaderValue::from_static(IMMUTABLE));
        if let Ok(v) = HeaderValue::from_str(&etag) {
            r.headers_mut().insert(header::ETAG, v);
        }
    };
    let matches = headers
        .get(header::IF_NONE_MATCH)
        .and_then(|v| v.to_str().ok())
        .is_some_and(|v| v.split(',').any(|t| t.trim() == etag));
    if matches {
        let mut r = StatusCode::NOT_MODIFIED.into_response();
        cache(&mut r);
        return Ok(r);
    }
    let asset = state.store_call(move |s| s.get_asset(&hash)).await?;
    let mut r = asset.bytes.into_response();
    if let Ok(v) = HeaderValue::from_str(&asset.meta.media_type) {
        r.headers_mut().insert(header::CONTENT_TYPE, v);
    }
    cache(&mut r);
    Ok(r)
}
