//! Compiling a source (`POST /api/compile`): diagnostics or a summary.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// `POST /api/compile`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct CompileRequest {
    /// HyperFun source.
    pub source: String,
    /// Parameter values (for the detected extent).
    #[serde(default)]
    pub params: Vec<f64>,
    /// The body to compile (default: `my_model`, else the first).
    #[serde(default)]
    pub body: Option<String>,
}

/// A model error, placed in the source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct Diagnostic {
    /// The message, e.g. "expected `;`".
    pub message: String,
    /// 1-based line of the start.
    pub line: u32,
    /// 1-based column (in characters) of the start.
    pub column: u32,
    /// Byte offsets of the span in the source, `[start, end)`.
    pub start: u32,
    /// End byte offset.
    pub end: u32,
    /// The rendered text: message, the source line and a caret under the span.
    pub rendered: String,
}

/// A parameter `a[i]` of a model, with what the slider needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ParamInfo {
    /// 1-based index in `a[]`.
    pub index: u32,
    /// Display name (from a `-- param:` comment, else `a[i]`).
    pub name: String,
    /// Default value.
    pub default: f64,
    /// Slider minimum.
    pub min: f64,
    /// Slider maximum.
    pub max: f64,
}

/// What a compiled model is, for the studio and the adaptive engine.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct CompileSummary {
    /// The compiled body.
    pub body: String,
    /// Every body in the file.
    pub bodies: Vec<String>,
    /// Nodes of the expression graph.
    pub nodes: u32,
    /// Operations of the value's tape (what an evaluator runs per point).
    pub tape_len: u32,
    /// The model's parameters `a[]`.
    pub params: Vec<ParamInfo>,
    /// The model box `[x0, y0, z0, x1, y1, z1]`.
    pub bounds: [f64; 6],
    /// Where the box came from: `comment`, `extent` or `default`.
    pub bounds_origin: String,
    /// Number of attributes `s[]` (0 when the header declares none).
    pub attributes: u32,
    /// Whether the ray caster solves it in closed form (quadric set
    /// expressions): cheap to render.
    pub closed_form: bool,
    /// Statements per field flavour of the generated shader.
    pub shader_statements: u32,
    /// Content hash of the compiled graph (the artefacts' key prefix).
    pub graph_hash: String,
}

/// The answer to a compile: diagnostics, or the summary.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct CompileResponse {
    /// Whether the model compiled.
    pub ok: bool,
    /// Model errors (empty when `ok`).
    pub diagnostics: Vec<Diagnostic>,
    /// The summary (when `ok`).
    pub summary: Option<CompileSummary>,
}
