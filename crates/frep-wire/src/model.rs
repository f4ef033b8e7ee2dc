//! Models, their versions and their change log (`/api/models`).
//!
//! A model is a name and an owner; its content lives in immutable versions,
//! numbered from 1. Every change (create, save, rename, restore, delete) is an
//! entry of the model's ordered log, which clients follow by sequence number.

use serde::{Deserialize, Serialize};
use ts_rs::TS;

/// A model as listed: no source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ModelSummary {
    /// Opaque id, stable for the model's life.
    pub id: String,
    /// Display name (unique per owner is not enforced).
    pub name: String,
    /// Who created it.
    pub owner: String,
    /// Creation time, ms since the epoch.
    #[ts(type = "number")]
    pub created: i64,
    /// Time of the latest version, ms since the epoch.
    #[ts(type = "number")]
    pub updated: i64,
    /// Number of the latest version (1 for a new model).
    pub latest: u32,
}

/// One immutable version of a model.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct Version {
    /// The model it belongs to.
    pub model_id: String,
    /// 1, 2, 3, … in the order they were saved.
    pub number: u32,
    /// HyperFun source.
    pub source: String,
    /// Values of the parameters `a[1..]` saved with it.
    pub params: Vec<f64>,
    /// Who saved it.
    pub author: String,
    /// When it was committed, ms since the epoch.
    #[ts(type = "number")]
    pub created: i64,
    /// The author's message.
    pub message: String,
    /// The version it restores, when it was made by a restore.
    pub restored_from: Option<u32>,
    /// Content-addressed files the source refers to.
    pub assets: Vec<AssetRef>,
}

/// A version as listed in a history: no source.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct VersionSummary {
    /// 1, 2, 3, …
    pub number: u32,
    /// Who saved it.
    pub author: String,
    /// When, ms since the epoch.
    #[ts(type = "number")]
    pub created: i64,
    /// The author's message.
    pub message: String,
    /// The version it restores, when it was made by a restore.
    pub restored_from: Option<u32>,
    /// Bytes of source.
    pub source_bytes: u32,
}

/// A model with its latest (or requested) version.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct ModelDetail {
    /// The model.
    pub model: ModelSummary,
    /// Its version.
    pub version: Version,
}

/// `POST /api/models`: a new model and its first version.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct CreateModel {
    /// Display name.
    pub name: String,
    /// HyperFun source of version 1.
    pub source: String,
    /// Parameter values (empty: none saved).
    #[serde(default)]
    pub params: Vec<f64>,
    /// Message of version 1.
    #[serde(default)]
    pub message: String,
}

/// `POST /api/models/{id}/versions`: save a new version.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct SaveVersion {
    /// HyperFun source.
    pub source: String,
    /// Parameter values.
    #[serde(default)]
    pub params: Vec<f64>,
    /// The author's message.
    #[serde(default)]
    pub message: String,
    /// The version the edit started from. When given and no longer the
    /// latest, the save is refused with 409 and the latest number, so that a
    /// client never overwrites an edit it has not seen.
    #[serde(default)]
    pub base: Option<u32>,
    /// Hashes of assets (uploaded before) the source refers to.
    #[serde(default)]
    pub assets: Vec<String>,
}

/// `PATCH /api/models/{id}`: rename.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct RenameModel {
    /// The new name.
    pub name: String,
}

/// `POST /api/models/{id}/restore`: a new version equal to an old one.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct RestoreVersion {
    /// The version to copy.
    pub version: u32,
    /// The author's message (default: "restore N").
    #[serde(default)]
    pub message: String,
}

/// `POST /api/models/{id}/duplicate`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct DuplicateModel {
    /// The copy's name.
    pub name: String,
}

/// One line of a source diff.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct DiffLine {
    /// `same`, `added` or `removed`.
    pub kind: DiffKind,
    /// Line number in the older version (1-based), if the line is there.
    pub old_line: Option<u32>,
    /// Line number in the newer version (1-based), if the line is there.
    pub new_line: Option<u32>,
    /// The line's text, without its line ending.
    pub text: String,
}

/// What a diff line is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub enum DiffKind {
    /// In both versions.
    Same,
    /// Only in the newer one.
    Added,
    /// Only in the older one.
    Removed,
}

/// `GET /api/models/{id}/diff?from=A&to=B`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct SourceDiff {
    /// The older version.
    pub from: u32,
    /// The newer version.
    pub to: u32,
    /// The lines of both, in order.
    pub lines: Vec<DiffLine>,
    /// Whether the parameter values differ.
    pub params_changed: bool,
}

/// What happened to a model, as one entry of its log.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub enum ChangeKind {
    /// The model and its version 1.
    Created,
    /// A new version.
    Saved,
    /// A new version copied from an old one.
    Restored,
    /// A new name.
    Renamed,
    /// The model was deleted (its log stays readable).
    Deleted,
}

/// One entry of a model's ordered change log
/// (`GET /api/models/{id}/log?after=SEQ`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct Change {
    /// Position in the model's log: 1, 2, 3, … without gaps.
    #[ts(type = "number")]
    pub seq: i64,
    /// The model.
    pub model_id: String,
    /// What happened.
    pub kind: ChangeKind,
    /// The version it made, if any.
    pub version: Option<u32>,
    /// The name after a rename (or at creation).
    pub name: Option<String>,
    /// Who did it.
    pub author: String,
    /// When, ms since the epoch.
    #[ts(type = "number")]
    pub time: i64,
}

/// A content-addressed file a version refers to (an imported mesh, an
/// image, …).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, TS)]
#[cfg_attr(feature = "openapi", derive(utoipa::ToSchema))]
#[serde(rename_all = "camelCase")]
pub struct AssetRef {
    /// BLAKE3 of the content, hex (the asset's URL is `/api/assets/{hash}`).
    pub hash: String,
    /// Bytes.
    #[ts(type = "number")]
    pub size: u64,
    /// MIME type given at upload.
    pub media_type: String,
    /// The name the source uses for it.
    pub name: String,
}
