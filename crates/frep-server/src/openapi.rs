//! `GET /api/openapi.json`: the HTTP API described from the code itself.
//!
//! Every handler carries a `#[utoipa::path]` annotation next to its code.
//! The bodies are the frep-wire types, whose `openapi` feature derives the
//! schemas. So the document cannot drift from what the server does. It is
//! built once, on first request.

use std::sync::OnceLock;

use axum::http::header;
use axum::response::IntoResponse;
use utoipa::OpenApi;

use frep_wire::*;

/// The OpenAPI document of the server.
#[derive(OpenApi)]
#[openapi(
    info(
        title = "frep",
        description = "The frep server: HyperFun models with their history, compiled, and their \
                       artefacts (images, view sets, meshes, slices, shaders, exports) at immutable \
                       content-addressed URLs. Every failure answers an `ApiError`."
    ),
    paths(
        crate::models::list,
        crate::models::create,
        crate::models::get,
        crate::models::rename,
        crate::models::delete,
        crate::models::duplicate,
        crate::models::log,
        crate::versions::history,
        crate::versions::save,
        crate::versions::get_version,
        crate::versions::diff,
        crate::versions::restore,
        crate::compile::compile,
        crate::artefacts::request,
        crate::artefacts::get,
        crate::assets::upload,
        crate::assets::get,
        crate::router::health,
        document,
    ),
    components(schemas(
        ApiError,
        ModelSummary,
        ModelDetail,
        Version,
        VersionSummary,
        CreateModel,
        SaveVersion,
        RenameModel,
        RestoreVersion,
        DuplicateModel,
        SourceDiff,
        DiffLine,
        DiffKind,
        Change,
        ChangeKind,
        AssetRef,
        CompileRequest,
        CompileResponse,
        CompileSummary,
        Diagnostic,
        ParamInfo,
        ArtefactRequest,
        ArtefactRef,
        ArtefactSpec,
        ModelRef,
        CameraView,
        ImageEncoding,
        ExportFormat,
        ShaderArtefact,
        ShaderUniform,
        ViewSetLayout,
        VolumeLayout,
    )),
    tags(
        (name = "models", description = "Models and their change log"),
        (name = "versions", description = "Immutable versions: history, save, diff, restore"),
        (name = "compile", description = "Diagnostics and summaries"),
        (name = "artefacts", description = "Computed artefacts at content addresses"),
        (name = "assets", description = "Uploaded files, by content hash"),
        (name = "server", description = "Health and this document"),
    )
)]
pub struct ApiDoc;

/// The document as JSON text (built once).
pub fn json() -> &'static str {
    static DOC: OnceLock<String> = OnceLock::new();
    DOC.get_or_init(|| {
        ApiDoc::openapi()
            .to_pretty_json()
            // Serialising a document built from static annotations cannot
            // fail; an empty object keeps the route answering JSON if it did.
            .unwrap_or_else(|_| "{}".to_string())
    })
}

/// The OpenAPI document.
#[utoipa::path(
    get,
    path = "/api/openapi.json",
    tag = "server",
    responses((status = 200, description = "OpenAPI 3.1 document", content_type = "application/json"))
)]
pub async fn document() -> impl IntoResponse {
    ([(header::CONTENT_TYPE, "application/json")], json())
}
