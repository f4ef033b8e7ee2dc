//! `POST /api/compile`: a source's diagnostics, or its summary.
//!
//! - The source is checked against `limits.source_bytes` before any work. A
//!   refusal names the limit.
//! - It is then compiled on the blocking pool, through the shared
//!   [`frep_artefact::CompileCache`]. The editor compiles the same text
//!   again and again, and artefact requests reuse the compiled model.
//! - A model error is not a failed request. The answer is 200 with
//!   `ok: false`, and diagnostics giving line, column and the caret text.
//! - Compile limits (nodes, steps, loop iterations) come back as
//!   diagnostics too, since they are properties of the model.

use std::sync::Arc;

use axum::extract::State;
use axum::http::StatusCode;
use axum::Json;
use frep_artefact::Compiled;
use frep_wire::{ApiError, CompileRequest, CompileResponse, Diagnostic};

use crate::error::{ApiJson, AppError, AppResult};
use crate::state::AppState;

/// Refuses a source over `limits.source_bytes` (413, naming the limit).
pub fn check_source(state: &AppState, source: &str) -> Result<(), AppError> {
    let max = state.config.limits.source_bytes;
    if source.len() > max {
        return Err(AppError::limit(
            "source_bytes",
            StatusCode::PAYLOAD_TOO_LARGE,
            format!(
                "the source is {} bytes, over the limit source_bytes = {max}",
                source.len()
            ),
        ));
    }
    Ok(())
}

/// Refuses too many or non-finite parameter values.
pub fn check_params(state: &AppState, params: &[f64]) -> Result<(), AppError> {
    let max = state.config.limits.params;
    if params.len() > max {
        return Err(AppError::limit(
            "params",
            StatusCode::UNPROCESSABLE_ENTITY,
            format!(
                "{} parameter values, over the limit params = {max}",
                params.len()
            ),
        ));
    }
    if let Some(p) = params.iter().find(|p| !p.is_finite()) {
        return Err(AppError::BadRequest(format!(
            "parameter value {p} is not a finite number"
        )));
    }
    Ok(())
}

/// Compiles `source` (cached) on the blocking pool: the model, or its
/// diagnostics. The source must have passed [`check_source`].
pub async fn compile_source(
    state: &AppState,
    source: String,
    body: Option<String>,
    params: Vec<f64>,
) -> AppResult<Result<Arc<Compiled>, Vec<Diagnostic>>> {
    let cache = Arc::clone(&state.compiles);
    let limits = state.config.compile_limits();
    let span = tracing::debug_span!("compile", bytes = source.len());
    Ok(tokio::task::spawn_blocking(move || {
        let _enter = span.enter();
        cache.get_or_compile(&source, body.as_deref(), &params, &limits)
    })
    .await?)
}

/// Compiles a source: diagnostics or a summary.
#[utoipa::path(
    post,
    path = "/api/compile",
    tag = "compile",
    request_body = CompileRequest,
    responses(
        (status = 200, description = "Compiled (`ok`), or the model's diagnostics", body = CompileResponse),
        (status = 400, description = "Malformed request", body = ApiError),
        (status = 413, description = "Source over `source_bytes`", body = ApiError),
    )
)]
pub async fn compile(
    State(state): State<AppState>,
    ApiJson(req): ApiJson<CompileRequest>,
) -> AppResult<Json<CompileResponse>> {
    check_source(&state, &req.source)?;
    check_params(&state, &req.params)?;
    let outcome = compile_source(&state, req.source, req.body, req.params).await?;
    Ok(Json(match outcome {
        Ok(compiled) => CompileResponse {
            ok: true,
            diagnostics: Vec::new(),
            summary: Some(compiled.summary().clone()),
        },
        Err(diagnostics) => CompileResponse {
            ok: false,
            diagnostics,
            summary: None,
        },
    }))
}
