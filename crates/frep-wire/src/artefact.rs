//! Artefacts: what the server computes from a model (images, view sets,
//! meshes, slices, shaders, exports), at immutable content-addressed URLs.
//!
//! `POST /api/artefacts` with an [`ArtefactRequest`] answers an
//! [`ArtefactRef`] at once: the key is the hash of the compiled graph, the
//! parameter values and the settings, so the same request always gets the
//! same URL. `GET` on the URL computes it if needed (identical concurrent
//! requests computed once) and serves it with `Cache-Control: immutable`.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// Which model an artefact is made from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "from", rename_all = "camelCase")]
pub enum ModelRef {
    /// A stored version.
    #[serde(rename_all = "camelCase")]
    Version {
        /// Model id.
        model_id: String,
        /// Version number (`None`: the latest).
        version: Option<u32>,
    },
    /// A source not saved yet (the editor's text while typing).
    #[serde(rename_all = "camelCase")]
    Source {
        /// HyperFun source.
        source: String,
    },
}

/// The one camera of every mode: a turntable around the model box's centre
/// (moved by `pan`), framing the box at `zoom` 1. The server's images and the
/// client's 3D views use the same conventions, so switching modes keeps the
/// view. World z is up; yaw 0 looks along +y; pitch 90 looks straight down.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct CameraView {
    /// Degrees around z.
    pub yaw: f64,
    /// Degrees above the horizon.
    pub pitch: f64,
    /// Vertical field of view in degrees; `None`: orthographic.
    pub fov: Option<f64>,
    /// 1 frames the box; 2 is twice as close.
    pub zoom: f64,
    /// Offset of the orbit's centre from the box's centre, world units.
    pub pan: [f64; 3],
}

impl Default for CameraView {
    fn default() -> Self {
        CameraView {
            yaw: 30.0,
            pitch: 20.0,
            fov: Some(30.0),
            zoom: 1.0,
            pan: [0.0; 3],
        }
    }
}

/// A section (clipping) plane: the part of the model with
/// `normal · p > offset` is cut away, showing the solid's inside (the cut
/// face in the model's colour there). The studio's viewer uses the same
/// form in every mode.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct SectionPlane {
    /// Normal, world coordinates (z up); any non-zero length (the plane is
    /// `normal · p = offset` as given).
    pub normal: [f64; 3],
    /// Offset along the normal, world units (for a unit normal).
    pub offset: f64,
}

/// Image encodings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub enum ImageEncoding {
    /// Baseline JPEG.
    Jpeg,
    /// Lossy WebP.
    Webp,
    /// PNG (lossless).
    Png,
}

/// Mesh export formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub enum ExportFormat {
    /// Binary STL.
    Stl,
    /// Wavefront OBJ.
    Obj,
    /// PLY with vertex colours.
    Ply,
    /// glTF binary.
    Glb,
    /// 3D Manufacturing Format.
    #[serde(rename = "3mf")]
    #[ts(rename = "3mf")]
    ThreeMf,
}

/// What to compute, with its settings.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(tag = "kind", rename_all = "camelCase")]
pub enum ArtefactSpec {
    /// A still image (mode 1).
    #[serde(rename_all = "camelCase")]
    Image {
        /// The camera.
        camera: CameraView,
        /// Pixels.
        width: u32,
        /// Pixels.
        height: u32,
        /// Encoding.
        format: ImageEncoding,
        /// JPEG / WebP quality 1–100.
        quality: u8,
        /// A section plane cutting the model open (absent: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[ts(optional)]
        section: Option<SectionPlane>,
    },
    /// A view set: `views` images per ring around the model on one sprite
    /// sheet, with its index (mode 2).
    #[serde(rename_all = "camelCase")]
    ViewSet {
        /// Views per ring.
        views: u32,
        /// Pitch of each ring, degrees.
        elevations: Vec<f64>,
        /// Pixels per view.
        width: u32,
        /// Pixels per view.
        height: u32,
        /// Encoding of the sheet.
        format: ImageEncoding,
        /// Quality 1–100.
        quality: u8,
        /// Field of view (`None`: orthographic).
        fov: Option<f64>,
        /// A section plane cutting the model open (absent: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[ts(optional)]
        section: Option<SectionPlane>,
    },
    /// The view set's index (JSON) for the same settings.
    #[serde(rename_all = "camelCase")]
    ViewSetIndex {
        /// Views per ring.
        views: u32,
        /// Pitch of each ring, degrees.
        elevations: Vec<f64>,
        /// Pixels per view.
        width: u32,
        /// Pixels per view.
        height: u32,
        /// Encoding of the sheet.
        format: ImageEncoding,
        /// Quality 1–100.
        quality: u8,
        /// Field of view (`None`: orthographic).
        fov: Option<f64>,
        /// A section plane cutting the model open (absent: none).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        #[ts(optional)]
        section: Option<SectionPlane>,
    },
    /// A meshopt-compressed glb for the viewer (mode 3).
    #[serde(rename_all = "camelCase")]
    Mesh {
        /// Octree depth (cells along the longest side: 2^depth).
        depth: u8,
    },
    /// An 8-bit 3D texture of the field with its mapping (the volume mode).
    #[serde(rename_all = "camelCase")]
    Slices {
        /// Samples per axis.
        grid: u32,
    },
    /// The generated WebGL2 shader and its uniforms (mode 4a).
    Shader,
    /// A mesh file to download.
    #[serde(rename_all = "camelCase")]
    Export {
        /// The file format.
        format: ExportFormat,
        /// Octree depth.
        depth: u8,
    },
}

/// `POST /api/artefacts`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ArtefactRequest {
    /// The model.
    pub model: ModelRef,
    /// Parameter values (empty: the version's own).
    #[serde(default)]
    pub params: Vec<f64>,
    /// What to compute.
    pub spec: ArtefactSpec,
}

/// Where an artefact is, and what is known about it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ArtefactRef {
    /// The content address: hash of graph, parameters and settings.
    pub key: String,
    /// Its immutable URL (`/api/artefacts/{key}.{ext}`).
    pub url: String,
    /// MIME type of the body.
    pub media_type: String,
    /// Whether it is already computed (then `bytes` and `serverMs` are set).
    pub ready: bool,
    /// Size in bytes, when ready.
    #[ts(type = "number | null")]
    pub bytes: Option<u64>,
    /// Server time it took to compute, when ready.
    pub server_ms: Option<f64>,
}

/// The generated shader with its uniform table (the body of a `shader`
/// artefact).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ShaderArtefact {
    /// GLSL ES 3.00 fragment shader.
    pub source: String,
    /// Every uniform with its default values.
    pub uniforms: Vec<ShaderUniform>,
    /// The box ray cast.
    pub bounds: [f64; 6],
    /// Statements per field flavour.
    pub statements: u32,
}

/// One uniform of a generated shader.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ShaderUniform {
    /// GLSL name.
    pub name: String,
    /// GLSL type with array size (`float[3]`, `mat4`, …).
    #[serde(rename = "type")]
    pub ty: String,
    /// Default values, flattened.
    pub values: Vec<f32>,
    /// What it is.
    pub description: String,
}

/// The index of a view set (the body of a `viewSetIndex` artefact): where each
/// view is on the sheet.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ViewSetLayout {
    /// Views per ring.
    pub views_per_ring: u32,
    /// Pitch of each ring, degrees.
    pub elevations: Vec<f64>,
    /// Yaw of the first view of each ring, degrees.
    pub start_yaw: f64,
    /// Pixels per view.
    pub view_size: [u32; 2],
    /// Views per row of the sheet.
    pub columns: u32,
    /// The sheet's size in pixels.
    pub sheet_size: [u32; 2],
}

/// The mapping of a `slices` artefact's bytes (the body is the raw volume,
/// x fastest, then y, then z; this rides in the `x-frep-volume` header and in
/// the `slicesIndex` answer).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct VolumeLayout {
    /// Samples along x, y, z.
    pub dims: [u32; 3],
    /// The sampled box.
    pub bounds: [f64; 6],
    /// byte = 128 + 127 · f / scale, clamped: 128 is the surface.
    pub scale: f64,
}
