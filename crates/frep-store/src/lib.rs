//! # frep-store
//!
//! The master copy of frep's models:
//! - models (name, owner, creation time);
//! - every save as a new immutable version (HyperFun source, parameter
//!   values, author, time, message, referenced assets);
//! - an ordered change log per model, which clients follow by sequence
//!   number;
//! - content-addressed assets (BLAKE3);
//! - a small access list (owner plus granted editors).
//!
//! Everything is behind the synchronous [`Store`] trait so that a PostgreSQL
//! store can follow for scale-out. The server calls it on tokio's blocking
//! pool (`spawn_blocking`).
//!
//! ## The SQLite store
//!
//! [`SqliteStore`] uses `rusqlite` with SQLite bundled. It is synchronous,
//! so no async runtime is needed inside the store. There is no system
//! library to match, and no database is needed at compile time.
//! - The file is opened in WAL mode with `synchronous=FULL`, so a write is
//!   acknowledged only once its commit is on disk.
//! - `foreign_keys=ON`, and a busy timeout for other processes.
//! - Migrations are the numbered SQL files of `migrations/`, embedded in the
//!   binary. They are applied in order in one transaction and recorded in
//!   `PRAGMA user_version`. A database newer than the code is refused.
//!
//! ## Invariants
//!
//! - Versions are numbered 1, 2, 3, … per model without gaps. A number is
//!   assigned inside the writing transaction (`PRIMARY KEY (model, number)`),
//!   so two concurrent saves can never both become version N.
//! - Every change (create, save, restore, rename, delete) appends one entry
//!   to the model's log in the same transaction, `seq` 1, 2, 3, … without
//!   gaps. The log is never rewritten, and stays readable after a delete.
//! - A save with a `base` that is not the latest is refused with
//!   [`StoreError::Conflict`]: no blind overwrites.
//! - Deleting is soft: a deleted model is not listed and not gettable
//!   ([`StoreError::NotFound`]), but its log remains.
//!
//! Access policy, enforced by the server (the store answers
//! [`Store::may_edit`]):
//! - anyone may read;
//! - the owner and granted editors may write;
//! - only the owner changes the access list.
#![warn(missing_docs)]

mod diff;
mod error;
mod limits;
mod sqlite;

pub use diff::line_diff;
pub use error::{Result, StoreError};
pub use limits::StoreLimits;
pub use sqlite::SqliteStore;

pub use frep_wire::{
    AssetRef, Change, ChangeKind, CreateModel, DiffKind, DiffLine, ModelDetail, ModelSummary,
    SaveVersion, SourceDiff, Version, VersionSummary,
};

/// The result of a write: what was written, and the log entry it appended
/// (for the server to publish to the sessions following the model).
#[derive(Clone, Debug, PartialEq)]
pub struct Committed<T> {
    /// What the write made.
    pub value: T,
    /// The entry it appended to the model's log.
    pub change: Change,
}

/// A new version to save (the store's form of [`SaveVersion`]).
#[derive(Clone, Debug, PartialEq, Default)]
pub struct NewVersion {
    /// HyperFun source.
    pub source: String,
    /// Parameter values (finite).
    pub params: Vec<f64>,
    /// The author's message.
    pub message: String,
    /// The version the edit started from; when given and no longer the
    /// latest, the save is refused with [`StoreError::Conflict`].
    pub base: Option<u32>,
    /// Assets (already stored with [`Store::put_asset`]) the source uses.
    pub assets: Vec<AssetLink>,
}

impl From<SaveVersion> for NewVersion {
    /// The wire form names assets by hash only, so each is named by its
    /// hash.
    fn from(s: SaveVersion) -> Self {
        NewVersion {
            source: s.source,
            params: s.params,
            message: s.message,
            base: s.base,
            assets: s
                .assets
                .into_iter()
                .map(|hash| AssetLink {
                    name: hash.clone(),
                    hash,
                })
                .collect(),
        }
    }
}

/// A version's reference to a stored asset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AssetLink {
    /// The name the source uses for it (unique within the version).
    pub name: String,
    /// BLAKE3 hex of the content.
    pub hash: String,
}

/// A stored asset's description.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AssetMeta {
    /// BLAKE3 of the content, 64 lowercase hex digits.
    pub hash: String,
    /// Bytes.
    pub size: u64,
    /// MIME type given at the first upload.
    pub media_type: String,
}

/// A stored asset with its content.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Asset {
    /// Its description.
    pub meta: AssetMeta,
    /// The content.
    pub bytes: Vec<u8>,
}

/// A log entry with its position in the store-wide order (for following
/// every model at once).
#[derive(Clone, Debug, PartialEq)]
pub struct GlobalChange {
    /// Position across all models: increasing, unique (not necessarily
    /// without gaps).
    pub global_seq: i64,
    /// The entry.
    pub change: Change,
}

/// A page of a model's history.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub struct HistoryPage {
    /// Only versions numbered below this (`None`: from the latest).
    pub before: Option<u32>,
    /// Most versions to list (`None`: `max_versions_listed`; more than that
    /// is refused).
    pub limit: Option<u32>,
}

/// The model store. Every method is synchronous and may block on disk;
/// writes return only after their transaction has committed.
pub trait Store: Send + Sync {
    /// Creates a model owned by `owner` with its version 1; logs `Created`.
    fn create_model(&self, owner: &str, model: CreateModel) -> Result<Committed<ModelDetail>>;

    /// Every model not deleted, oldest first.
    fn list_models(&self) -> Result<Vec<ModelSummary>>;

    /// A model with its latest version.
    fn get_model(&self, model_id: &str) -> Result<ModelDetail>;

    /// One version of a model (`None`: the latest).
    fn get_version(&self, model_id: &str, number: Option<u32>) -> Result<Version>;

    /// A model's versions, newest first, one page at a time.
    fn history(&self, model_id: &str, page: HistoryPage) -> Result<Vec<VersionSummary>>;

    /// Saves a new version (number latest + 1); logs `Saved`. Refused with
    /// [`StoreError::Conflict`] when `version.base` is given and is not the
    /// latest.
    fn save_version(
        &self,
        model_id: &str,
        author: &str,
        version: NewVersion,
    ) -> Result<Committed<Version>>;

    /// Renames a model; logs `Renamed`.
    fn rename(&self, model_id: &str, author: &str, name: &str) -> Result<Committed<ModelSummary>>;

    /// A new model owned by `owner` whose version 1 copies the latest
    /// version of `model_id` (source, parameters, assets); logs `Created`
    /// on the new model.
    fn duplicate(&self, model_id: &str, owner: &str, name: &str) -> Result<Committed<ModelDetail>>;

    /// A new version equal to version `number` (source, parameters,
    /// assets) with `restored_from = number`; logs `Restored`. An empty
    /// message becomes "restore N".
    fn restore(
        &self,
        model_id: &str,
        author: &str,
        number: u32,
        message: &str,
    ) -> Result<Committed<Version>>;

    /// Soft-deletes a model: it is no longer listed or gettable, its log
    /// stays readable; logs `Deleted`.
    fn delete(&self, model_id: &str, author: &str) -> Result<Change>;

    /// The line diff of the sources of versions `from` and `to`.
    fn diff(&self, model_id: &str, from: u32, to: u32) -> Result<SourceDiff>;

    /// A model's log entries with `seq > after`, in order, at most `limit`
    /// (`None`: `max_changes_listed`). Readable after a delete.
    fn changes(&self, model_id: &str, after: i64, limit: Option<u32>) -> Result<Vec<Change>>;

    /// Every model's log entries with `global_seq > after`, in commit order,
    /// at most `limit` (`None`: `max_changes_listed`).
    fn changes_since(&self, after: i64, limit: Option<u32>) -> Result<Vec<GlobalChange>>;

    /// Stores content (idempotent: the same bytes give the same hash and
    /// are stored once) and describes it.
    fn put_asset(&self, bytes: &[u8], media_type: &str) -> Result<AssetMeta>;

    /// A stored asset by its hash.
    fn get_asset(&self, hash: &str) -> Result<Asset>;

    /// Whether `user` may write to the model (owner or granted editor).
    fn may_edit(&self, model_id: &str, user: &str) -> Result<bool>;

    /// Lets `user` edit the model; only the owner (`by`) may grant.
    fn grant(&self, model_id: &str, by: &str, user: &str) -> Result<()>;

    /// Withdraws `user`'s right to edit; only the owner (`by`) may revoke,
    /// and the owner's own right cannot be revoked.
    fn revoke(&self, model_id: &str, by: &str, user: &str) -> Result<()>;

    /// The granted editors of a model (not the owner), sorted.
    fn editors(&self, model_id: &str) -> Result<Vec<String>>;

    /// Flushes and closes the store; later calls fail with
    /// [`StoreError::Closed`].
    fn close(&self) -> Result<()>;
}
