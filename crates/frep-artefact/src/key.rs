//! Content addresses. An artefact's key is BLAKE3 over a canonical
//! serialization of what determines its bytes:
//! - the graph hash;
//! - the model box;
//! - the parameter values, defaults filled in;
//! - the spec.
//!
//! So the same request always has the same key, and a different one never
//! does.
//!
//! Floats are hashed by their bits. `-0.0` and `0.0` differ, which is
//! harmless: two keys for one picture. The spec is hashed as its JSON, whose
//! field order is the struct's, fixed at compile time.

use frep_wire::{ArtefactSpec, ExportFormat, ImageEncoding};

/// Bumped whenever an artefact's bytes change for the same inputs (a new
/// encoder setting, a kernel change that moves pixels).
const KEY_VERSION: &[u8] = b"frep-artefact-key-1\n";

/// The key (64 hex digits) of `spec` for the model with graph hash
/// `graph_hash` framed in `bounds`, at parameter values `params`.
pub fn key(graph_hash: &str, bounds: &[f64; 6], params: &[f64], spec: &ArtefactSpec) -> String {
    let mut h = blake3::Hasher::new();
    h.update(KEY_VERSION);
    h.update(graph_hash.as_bytes());
    h.update(b"\n");
    for b in bounds {
        h.update(&b.to_bits().to_le_bytes());
    }
    h.update(&(params.len() as u64).to_le_bytes());
    for p in params {
        h.update(&p.to_bits().to_le_bytes());
    }
    // Serializing a plain data enum to JSON cannot fail: no maps with
    // non-string keys, no custom serializers. An empty string would still
    // give a key that differs per kind through the graph hash.
    h.update(serde_json::to_string(spec).unwrap_or_default().as_bytes());
    h.finalize().to_hex().to_string()
}

/// Whether `key` has the form of a key (64 lowercase hex digits): the server
/// checks URLs with it before touching the disk.
pub fn is_key(key: &str) -> bool {
    key.len() == 64 && key.bytes().all(|b| matches!(b, b'0'..=b'9' | b'a'..=b'f'))
}

/// The media type of a spec's body.
pub fn media_type(spec: &ArtefactSpec) -> &'static str {
    match spec {
        ArtefactSpec::Image { format, .. } | ArtefactSpec::ViewSet { format, .. } => {
            image_media_type(*format)
        }
        ArtefactSpec::ViewSetIndex { .. } | ArtefactSpec::Shader => "application/json",
        ArtefactSpec::Mesh { .. } => "model/gltf-binary",
        ArtefactSpec::Slices { .. } => "application/octet-stream",
        ArtefactSpec::Export { format, .. } => export_format(*format).mime_type(),
    }
}

/// The file extension (no dot) of a spec's URL.
pub fn extension(spec: &ArtefactSpec) -> &'static str {
    match spec {
        ArtefactSpec::Image { format, .. } | ArtefactSpec::ViewSet { format, .. } => {
            image_format(*format).extension()
        }
        ArtefactSpec::ViewSetIndex { .. } | ArtefactSpec::Shader => "json",
        ArtefactSpec::Mesh { .. } => "glb",
        ArtefactSpec::Slices { .. } => "raw",
        ArtefactSpec::Export { format, .. } => export_format(*format).extension(),
    }
}

/// The immutable URL of an artefact: `/api/artefacts/{key}.{ext}`.
pub fn url(key: &str, spec: &ArtefactSpec) -> String {
    format!("/api/artefacts/{key}.{}", extension(spec))
}

fn image_media_type(f: ImageEncoding) -> &'static str {
    image_format(f).mime()
}

/// The ray caster's image format for a wire encoding.
pub fn image_format(f: ImageEncoding) -> frep_render::ImageFormat {
    match f {
        ImageEncoding::Jpeg => frep_render::ImageFormat::Jpeg,
        ImageEncoding::Webp => frep_render::ImageFormat::Webp,
        ImageEncoding::Png => frep_render::ImageFormat::Png,
    }
}

/// The mesh writer's format for a wire export format (STL binary, PLY
/// binary with colours, glb quantized and meshopt-compressed).
pub fn export_format(f: ExportFormat) -> frep_mesh::Format {
    match f {
        ExportFormat::Stl => frep_mesh::Format::StlBinary,
        ExportFormat::Obj => frep_mesh::Format::Obj,
        ExportFormat::Ply => frep_mesh::Format::Ply,
        ExportFormat::Glb => frep_mesh::Format::GlbMeshopt,
        ExportFormat::ThreeMf => frep_mesh::Format::ThreeMf,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use frep_wire::{CameraView, SectionPlane};

    fn image(section: Option<SectionPlane>) -> ArtefactSpec {
        ArtefactSpec::Image {
            camera: CameraView::default(),
            width: 64,
            height: 48,
            format: ImageEncoding::Png,
            quality: 80,
            section,
        }
    }

    /// No plane: the key of the spec as it was before planes existed (its
    /// JSON has no `section` field); each plane its own key.
    #[test]
    fn the_section_plane_is_part_of_the_key() {
        let b = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0];
        let plain = key("g", &b, &[], &image(None));
        let old: ArtefactSpec = serde_json::from_str(
            r#"{"kind":"image","camera":{"yaw":30.0,"pitch":20.0,"fov":30.0,"zoom":1.0,"pan":[0.0,0.0,0.0]},"width":64,"height":48,"format":"png","quality":80}"#,
        )
        .unwrap();
        assert_eq!(key("g", &b, &[], &old), plain);
        let cut = |normal, offset| key("g", &b, &[], &image(Some(SectionPlane { normal, offset })));
        let a = cut([0.0, 0.0, 1.0], 0.0);
        assert_ne!(a, plain);
        assert_ne!(a, cut([0.0, 0.0, 1.0], 0.1));
        assert_ne!(a, cut([0.0, 1.0, 0.0], 0.0));
        assert_eq!(a, cut([0.0, 0.0, 1.0], 0.0));
    }
}
