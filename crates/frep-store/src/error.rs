//! The store's one error type.
//!
//! Every failure a caller can cause has its own variant so that the server
//! can map it to a status without parsing text:
//!
//! | variant | cause | server answer |
//! |---|---|---|
//! | [`StoreError::NotFound`] | no such (or a deleted) model, version or asset | 404 |
//! | [`StoreError::Conflict`] | a save whose `base` is no longer the latest | 409 with `latest` |
//! | [`StoreError::Limit`] | a [`crate::StoreLimits`] bound exceeded; `name` is the field | 413 / 422 |
//! | [`StoreError::Forbidden`] | an access-list change by someone other than the owner | 403 |
//! | [`StoreError::Invalid`] | malformed input (empty name, non-finite parameter, bad hash) | 400 |
//! | [`StoreError::SchemaTooNew`] | the database was written by a newer frep | refuse to start |
//! | [`StoreError::Closed`] | a call after [`crate::Store::close`] | 503 / 500 |
//! | [`StoreError::Db`] | SQLite itself failed (disk full, I/O error, corruption) | 500 |
//!
//! A write that returns `Ok` has been committed. For the SQLite store with
//! `synchronous=FULL`, it has also been synced to disk. A write that returns
//! `Err` changed nothing.

/// Why a store call failed.
#[derive(Debug, thiserror::Error)]
pub enum StoreError {
    /// No such model, version or asset (a deleted model counts as absent).
    #[error("not found: {0}")]
    NotFound(String),
    /// A save started from `base`, but the model's latest version is now
    /// `latest`: the caller has not seen the newer edit.
    #[error("version {base} is not the latest; the latest is {latest}")]
    Conflict {
        /// The version the edit started from.
        base: u32,
        /// The model's latest version number.
        latest: u32,
    },
    /// A configured limit was exceeded.
    #[error("{name} is {limit}, got {got}")]
    Limit {
        /// The [`crate::StoreLimits`] field that was exceeded.
        name: &'static str,
        /// The configured bound.
        limit: u64,
        /// What the request asked for.
        got: u64,
    },
    /// The user may not do this (only the owner changes the access list).
    #[error("forbidden: {0}")]
    Forbidden(String),
    /// Malformed input.
    #[error("invalid: {0}")]
    Invalid(String),
    /// The database's schema is newer than this code knows; it is refused
    /// rather than written with an older understanding of its tables.
    #[error(
        "the database has schema version {found}, newer than this frep's {known}; \
         upgrade frep or use another database"
    )]
    SchemaTooNew {
        /// The database's `user_version`.
        found: i64,
        /// The newest migration this code has.
        known: i64,
    },
    /// The store was closed.
    #[error("the store is closed")]
    Closed,
    /// SQLite failed.
    #[error("database: {0}")]
    Db(#[from] rusqlite::Error),
}

/// The store's result type.
pub type Result<T, E = StoreError> = std::result::Result<T, E>;
