//! Versions: `GET/POST /api/models/{id}/versions`,
//! `GET /api/models/{id}/versions/{n}`, `GET /api/models/{id}/diff?from&to`,
//! `POST /api/models/{id}/restore`.
//!
//! Versions are immutable: a save or a restore makes a new one. A save
//! naming a `base` that is no longer the latest is refused with 409
//! `conflict` and the latest number. So no client overwrites an edit it has
//! not seen. The check and the insert are one store transaction.

use axum::extract::State;
use axum::http::StatusCode;
use axum::Json;
use frep_store::{HistoryPage, NewVersion};
use frep_wire::{ApiError, RestoreVersion, SaveVersion, SourceDiff, Version, VersionSummary};
use serde::Deserialize;

use crate::auth::User;
use crate::compile::{check_params, check_source};
use crate::error::{ApiJson, ApiPath, ApiQuery, AppResult};
use crate::state::AppState;

/// A version of a model: `n`, or the latest.
pub async fn load_version(state: &AppState, id: String, n: Option<u32>) -> AppResult<Version> {
    state.store_call(move |s| s.get_version(&id, n)).await
}

/// `?before=N&limit=M` of the history route.
#[derive(Debug, Default, Deserialize, utoipa::IntoParams)]
pub struct HistoryQuery {
    /// Only versions numbered below this (default: from the latest).
    pub before: Option<u32>,
    /// Most versions (default and maximum: the store's
    /// `max_versions_listed`).
    pub limit: Option<u32>,
}

/// A model's history, newest first, a page at a time.
#[utoipa::path(
    get, path = "/api/models/{id}/versions", tag = "versions",
    params(("id" = String, Path, description = "Model id"), HistoryQuery),
    responses(
        (status = 200, description = "Versions newest first, without sources", body = [VersionSummary]),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn history(
    State(state): State<AppState>,
    ApiPath(id): ApiPath<String>,
    ApiQuery(q): ApiQuery<HistoryQuery>,
) -> AppResult<Json<Vec<VersionSummary>>> {
    let page = HistoryPage {
        before: q.before,
        limit: q.limit,
    };
    Ok(Json(state.store_call(move |s| s.history(&id, page)).await?))
}

/// Saves a new version.
#[utoipa::path(
    post, path = "/api/models/{id}/versions", tag = "versions",
    params(("id" = String, Path, description = "Model id")),
    request_body = SaveVersion,
    responses(
        (status = 201, description = "Committed", body = Version),
        (status = 403, description = "Not the owner", body = ApiError),
        (status = 404, description = "No such model", body = ApiError),
        (status = 409, description = "`base` is stale; `latest` says the latest", body = ApiError),
        (status = 413, description = "Source over `source_bytes`", body = ApiError),
    )
)]
pub async fn save(
    State(state): State<AppState>,
    user: User,
    ApiPath(id): ApiPath<String>,
    ApiJson(req): ApiJson<SaveVersion>,
) -> AppResult<(StatusCode, Json<Version>)> {
    check_source(&state, &req.source)?;
    check_params(&state, &req.params)?;
    user.check_edit(&state, &id).await?;
    let c = state
        .store_call(move |s| s.save_version(&id, &user.0, NewVersion::from(req)))
        .await?;
    tracing::info!(model = %c.value.model_id, version = c.value.number, "saved");
    state.publish([c.change]);
    Ok((StatusCode::CREATED, Json(c.value)))
}

/// One version, with its source.
#[utoipa::path(
    get, path = "/api/models/{id}/versions/{n}", tag = "versions",
    params(
        ("id" = String, Path, description = "Model id"),
        ("n" = u32, Path, description = "Version number"),
    ),
    responses(
        (status = 200, description = "The version", body = Version),
        (status = 404, description = "No such model or version", body = ApiError),
    )
)]
pub async fn get_version(
    State(state): State<AppState>,
    ApiPath((id, n)): ApiPath<(String, u32)>,
) -> AppResult<Json<Version>> {
    Ok(Json(load_version(&state, id, Some(n)).await?))
}

/// `?from=A&to=B` of the diff route.
#[derive(Debug, Deserialize, utoipa::IntoParams)]
pub struct DiffQuery {
    /// The older version.
    pub from: u32,
    /// The newer version.
    pub to: u32,
}

/// The line diff of two versions' sources.
#[utoipa::path(
    get, path = "/api/models/{id}/diff", tag = "versions",
    params(("id" = String, Path, description = "Model id"), DiffQuery),
    responses(
        (status = 200, description = "The diff", body = SourceDiff),
        (status = 404, description = "No such model or version", body = ApiError),
    )
)]
pub async fn diff(
    State(state): State<AppState>,
    ApiPath(id): ApiPath<String>,
    ApiQuery(q): ApiQuery<DiffQuery>,
) -> AppResult<Json<SourceDiff>> {
    Ok(Json(
        state.store_call(move |s| s.diff(&id, q.from, q.to)).await?,
    ))
}

/// Makes a new version equal to an old one.
#[utoipa::path(
    post, path = "/api/models/{id}/restore", tag = "versions",
    params(("id" = String, Path, description = "Model id")),
    request_body = RestoreVersion,
    responses(
        (status = 201, description = "The new version", body = Version),
        (status = 403, description = "Not the owner", body = ApiError),
        (status = 404, description = "No such model or version", body = ApiError),
    )
)]
pub async fn restore(
    State(state): State<AppState>,
    user: User,
    ApiPath(id): ApiPath<String>,
    ApiJson(req): ApiJson<RestoreVersion>,
) -> AppResult<(StatusCode, Json<Version>)> {
    user.check_edit(&state, &id).await?;
    let c = state
        .store_call(move |s| s.restore(&id, &user.0, req.version, &req.message))
        .await?;
    state.publish([c.change]);
    Ok((StatusCode::CREATED, Json(c.value)))
}
