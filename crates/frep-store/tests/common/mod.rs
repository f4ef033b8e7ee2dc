//! Helpers shared by the store's integration tests.
#![allow(dead_code)]

use frep_store::{CreateModel, ModelDetail, NewVersion, SqliteStore, Store, StoreLimits};

/// A fresh in-memory store with default limits.
pub fn memory() -> SqliteStore {
    SqliteStore::open_in_memory(StoreLimits::default()).unwrap()
}

/// Creates a model owned by `owner` with `source` as version 1.
pub fn create(store: &dyn Store, owner: &str, name: &str, source: &str) -> ModelDetail {
    store
        .create_model(
            owner,
            CreateModel {
                name: name.into(),
                source: source.into(),
                params: vec![],
                message: "first".into(),
            },
        )
        .unwrap()
        .value
}

/// A save of `source` with no base.
pub fn edit(source: &str) -> NewVersion {
    NewVersion {
        source: source.into(),
        message: format!("save {}", source.len()),
        ..NewVersion::default()
    }
}
