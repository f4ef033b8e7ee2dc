//! Models: `GET/POST /api/models`, `GET/PATCH/DELETE /api/models/{id}`,
//! `POST /api/models/{id}/duplicate`, `GET /api/models/{id}/log?after=`.
//!
//! Each handler checks its input against the limits, and runs one store call
//! on the blocking pool. It answers once the store has committed. The
//! committed change is then published to the sessions. Writes to an
//! existing model go through [`User::check_edit`] (403 unless open access
//! or the owner). Creating needs no permission: the creator owns the model.

use axum::extract::State;
use axum::http::StatusCode;
use axum::Json;
use frep_wire::{
    ApiError, Change, CreateModel, DuplicateModel, ModelDetail, ModelSummary, RenameModel,
};
use serde::Deserialize;

use crate::auth::User;
use crate::compile::{check_params, check_source};
use crate::error::{ApiJson, ApiPath, ApiQuery, AppError, AppResult};
use crate::state::AppState;

/// Longest model name, characters.
pub const MAX_NAME_CHARS: usize = 200;

/// Refuses an empty or over-long name.
pub fn check_name(name: &str) -> Result<(), AppError> {
    if name.trim().is_empty() {
        return Err(AppError::BadRequest("a model name cannot be empty".into()));
    }
    if name.chars().count() > MAX_NAME_CHARS {
        return Err(AppError::BadRequest(format!(
            "a model name has at most {MAX_NAME_CHARS} characters"
        )));
    }
    Ok(())
}

/// Every model (for the page and the list route).
pub async fn list_models(state: &AppState) -> AppResult<Vec<ModelSummary>> {
    state.store_call(|s| s.list_models()).await
}

/// Every model, without sources.
#[utoipa::path(
    get, path = "/api/models", tag = "models",
    responses((status = 200, description = "The models", body = [ModelSummary]))
)]
pub async fn list(State(state): State<AppState>) -> AppResult<Json<Vec<ModelSummary>>> {
    Ok(Json(list_models(&state).await?))
}

/// Creates a model with its version 1 (the user owns it).
#[utoipa::path(
    post, path = "/api/models", tag = "models",
    request_body = CreateModel,
    responses(
        (status = 201, description = "Created", body = ModelDetail),
        (status = 400, description = "Malformed", body = ApiError),
        (status = 413, description = "Source over `source_bytes`", body = ApiError),
    )
)]
pub async fn create(
    State(state): State<AppState>,
    user: User,
    ApiJson(req): ApiJson<CreateModel>,
) -> AppResult<(StatusCode, Json<ModelDetail>)> {
    check_name(&req.name)?;
    check_source(&state, &req.source)?;
    check_params(&state, &req.params)?;
    let c = state
        .store_call(move |s| s.create_model(&user.0, req))
        .await?;
    state.publish([c.change]);
    Ok((StatusCode::CREATED, Json(c.value)))
}

/// A model with its latest version.
#[utoipa::path(
    get, path = "/api/models/{id}", tag = "models",
    params(("id" = String, Path, description = "Model id")),
    responses(
        (status = 200, description = "The model", body = ModelDetail),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn get(
    State(state): State<AppState>,
    ApiPath(id): ApiPath<String>,
) -> AppResult<Json<ModelDetail>> {
    Ok(Json(state.store_call(move |s| s.get_model(&id)).await?))
}

/// Renames a model.
#[utoipa::path(
    patch, path = "/api/models/{id}", tag = "models",
    params(("id" = String, Path, description = "Model id")),
    request_body = RenameModel,
    responses(
        (status = 200, description = "Renamed", body = ModelSummary),
        (status = 403, description = "Not the owner", body = ApiError),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn rename(
    State(state): State<AppState>,
    user: User,
    ApiPath(id): ApiPath<String>,
    ApiJson(req): ApiJson<RenameModel>,
) -> AppResult<Json<ModelSummary>> {
    check_name(&req.name)?;
    user.check_edit(&state, &id).await?;
    let c = state
        .store_call(move |s| s.rename(&id, &user.0, &req.name))
        .await?;
    state.publish([c.change]);
    Ok(Json(c.value))
}

/// Deletes a model (its log stays readable).
#[utoipa::path(
    delete, path = "/api/models/{id}", tag = "models",
    params(("id" = String, Path, description = "Model id")),
    responses(
        (status = 204, description = "Deleted"),
        (status = 403, description = "Not the owner", body = ApiError),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn delete(
    State(state): State<AppState>,
    user: User,
    ApiPath(id): ApiPath<String>,
) -> AppResult<StatusCode> {
    user.check_edit(&state, &id).await?;
    let change = state.store_call(move |s| s.delete(&id, &user.0)).await?;
    state.publish([change]);
    Ok(StatusCode::NO_CONTENT)
}

/// Copies a model's latest version into a new model the user owns.
#[utoipa::path(
    post, path = "/api/models/{id}/duplicate", tag = "models",
    params(("id" = String, Path, description = "Model id")),
    request_body = DuplicateModel,
    responses(
        (status = 201, description = "The copy", body = ModelDetail),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn duplicate(
    State(state): State<AppState>,
    user: User,
    ApiPath(id): ApiPath<String>,
    ApiJson(req): ApiJson<DuplicateModel>,
) -> AppResult<(StatusCode, Json<ModelDetail>)> {
    check_name(&req.name)?;
    let c = state
        .store_call(move |s| s.duplicate(&id, &user.0, &req.name))
        .await?;
    state.publish([c.change]);
    Ok((StatusCode::CREATED, Json(c.value)))
}

/// `?after=SEQ` of the log route.
#[derive(Debug, Default, Deserialize, utoipa::IntoParams)]
pub struct LogQuery {
    /// Entries after this sequence number (default 0: all).
    #[serde(default)]
    pub after: i64,
    /// Most entries (default and maximum: the store's `max_changes_listed`).
    pub limit: Option<u32>,
}

/// A model's change log after a sequence number.
#[utoipa::path(
    get, path = "/api/models/{id}/log", tag = "models",
    params(("id" = String, Path, description = "Model id"), LogQuery),
    responses(
        (status = 200, description = "Entries in order", body = [Change]),
        (status = 404, description = "No such model", body = ApiError),
    )
)]
pub async fn log(
    State(state): State<AppState>,
    ApiPath(id): ApiPath<String>,
    ApiQuery(q): ApiQuery<LogQuery>,
) -> AppResult<Json<Vec<Change>>> {
    Ok(Json(
        state
            .store_call(move |s| s.changes(&id, q.after, q.limit))
            .await?,
    ))
}
