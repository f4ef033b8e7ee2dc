//! The TypeScript declarations of every wire type, as one file.

use ts_rs::TS;

use crate::*;

/// The contents of `web/src/wire.ts`: every wire type as a TypeScript
/// declaration, in a fixed order. `cargo test -p frep-wire` fails when the
/// committed file differs; `FREP_BLESS=1` rewrites it.
pub fn typescript() -> String {
    let cfg = ts_rs::Config::default();
    let decls = [
        ModelSummary::decl(&cfg),
        Version::decl(&cfg),
        VersionSummary::decl(&cfg),
        ModelDetail::decl(&cfg),
        CreateModel::decl(&cfg),
        SaveVersion::decl(&cfg),
        RenameModel::decl(&cfg),
        RestoreVersion::decl(&cfg),
        DuplicateModel::decl(&cfg),
        DiffLine::decl(&cfg),
        DiffKind::decl(&cfg),
        SourceDiff::decl(&cfg),
        ChangeKind::decl(&cfg),
        Change::decl(&cfg),
        AssetRef::decl(&cfg),
        CompileRequest::decl(&cfg),
        Diagnostic::decl(&cfg),
        ParamInfo::decl(&cfg),
        CompileSummary::decl(&cfg),
        CompileResponse::decl(&cfg),
        ApiError::decl(&cfg),
        ModelRef::decl(&cfg),
        CameraView::decl(&cfg),
        SectionPlane::decl(&cfg),
        ImageEncoding::decl(&cfg),
        ExportFormat::decl(&cfg),
        ArtefactSpec::decl(&cfg),
        ArtefactRequest::decl(&cfg),
        ArtefactRef::decl(&cfg),
        ShaderArtefact::decl(&cfg),
        ShaderUniform::decl(&cfg),
        ViewSetLayout::decl(&cfg),
        VolumeLayout::decl(&cfg),
        Mode::decl(&cfg),
        Screen::decl(&cfg),
        ClientReport::decl(&cfg),
        ModeSettings::decl(&cfg),
        ModePrediction::decl(&cfg),
        NetworkEstimate::decl(&cfg),
        Decision::decl(&cfg),
        ClientMessage::decl(&cfg),
        ServerMessage::decl(&cfg),
        BinaryHeader::decl(&cfg),
    ];
    let mut out = String::from(
        "// Generated from crates/frep-wire by `FREP_BLESS=1 cargo test -p frep-wire`.\n\
         // Do not edit: a test fails when this file differs from the Rust types.\n\n",
    );
    for d in decls {
        out.push_str("export ");
        out.push_str(&d);
        out.push_str("\n\n");
    }
    out
}
