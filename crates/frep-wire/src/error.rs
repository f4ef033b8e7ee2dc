//! The one error body every failing API call answers with.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

use crate::Diagnostic;

/// A failed request: HTTP status, a machine-readable code, a message a person
/// can read, and model diagnostics where the model was at fault.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ApiError {
    /// e.g. `not_found`, `model_error`, `too_large`, `conflict`, `limit`.
    pub code: String,
    /// What went wrong, in words.
    pub message: String,
    /// Model errors with line and column (for `model_error`).
    #[serde(default)]
    pub diagnostics: Vec<Diagnostic>,
    /// The limit that was exceeded, by its configuration name.
    #[serde(default)]
    pub limit: Option<String>,
    /// The model's latest version number (for `conflict`: the save's base
    /// was stale).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[ts(optional)]
    pub latest: Option<u32>,
}
