//! Models: create, list, load, rename, duplicate, soft delete.
//!
//! A model row holds its name, owner, times, the number of its latest
//! version and the seq of its latest log entry. Both are bumped inside the
//! writing transaction. Ids are 128 random bits from SQLite's own generator
//! (`randomblob`), as 32 lowercase hex digits. They are opaque, and
//! unguessable enough that ids of models one may not see do not leak by
//! counting.

use frep_wire::{ChangeKind, CreateModel, ModelDetail, ModelSummary};
use rusqlite::{params, OptionalExtension, Row, Transaction};

use super::check;
use super::log::{self, Entry};
use super::versions::{self, Content};
use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;
use crate::Committed;

const SUMMARY: &str = "SELECT id, name, owner, created, updated, latest FROM models";

fn row_to_summary(r: &Row) -> rusqlite::Result<ModelSummary> {
    Ok(ModelSummary {
        id: r.get(0)?,
        name: r.get(1)?,
        owner: r.get(2)?,
        created: r.get(3)?,
        updated: r.get(4)?,
        latest: r.get(5)?,
    })
}

/// A model that exists and is not deleted, else `NotFound`.
pub(crate) fn live(tx: &Transaction, model_id: &str) -> Result<ModelSummary> {
    tx.query_row(
        &format!("{SUMMARY} WHERE id = ?1 AND deleted IS NULL"),
        [model_id],
        row_to_summary,
    )
    .optional()?
    .ok_or_else(|| StoreError::NotFound(format!("model {model_id}")))
}

/// Every live model, oldest first.
pub(crate) fn list(tx: &Transaction) -> Result<Vec<ModelSummary>> {
    let mut stmt = tx.prepare_cached(&format!(
        "{SUMMARY} WHERE deleted IS NULL ORDER BY created, id"
    ))?;
    let rows = stmt.query_map([], row_to_summary)?;
    rows.map(|r| r.map_err(StoreError::from)).collect()
}

/// A live model with its latest version.
pub(crate) fn detail(tx: &Transaction, model_id: &str) -> Result<ModelDetail> {
    let model = live(tx, model_id)?;
    let version = versions::load(tx, model_id, model.latest)?;
    Ok(ModelDetail { model, version })
}

/// Creates a model with version 1; logs `Created`.
pub(crate) fn create(
    tx: &Transaction,
    limits: &StoreLimits,
    owner: &str,
    m: CreateModel,
) -> Result<Committed<ModelDetail>> {
    check::user(limits, owner)?;
    check::name(limits, &m.name)?;
    check::content(limits, &m.source, &m.params, &m.message)?;
    let content = Content {
        source: m.source,
        params: m.params,
        message: m.message,
        restored_from: None,
        assets: Vec::new(),
    };
    create_with(tx, limits, owner, &m.name, content)
}

/// Creates a model whose version 1 is `content` (already checked).
fn create_with(
    tx: &Transaction,
    limits: &StoreLimits,
    owner: &str,
    name: &str,
    content: Content,
) -> Result<Committed<ModelDetail>> {
    let time = check::now_ms();
    let id: String = tx.query_row("SELECT lower(hex(randomblob(16)))", [], |r| r.get(0))?;
    tx.execute(
        "INSERT INTO models (id, name, owner, created, updated, latest, last_seq, deleted)
         VALUES (?1, ?2, ?3, ?4, ?4, 0, 0, NULL)",
        params![id, name, owner, time],
    )?;
    let version = versions::insert(tx, limits, &id, owner, time, content)?;
    let change = log::append(
        tx,
        &id,
        Entry {
            kind: ChangeKind::Created,
            version: Some(version.number),
            name: Some(name),
            author: owner,
            time,
        },
    )?;
    let model = live(tx, &id)?;
    Ok(Committed {
        value: ModelDetail { model, version },
        change,
    })
}

/// Renames a live model; logs `Renamed`.
pub(crate) fn rename(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
    name: &str,
) -> Result<Committed<ModelSummary>> {
    check::user(limits, author)?;
    check::name(limits, name)?;
    live(tx, model_id)?;
    let time = check::now_ms();
    // `updated` is the time of the latest version, so a rename leaves it.
    tx.execute(
        "UPDATE models SET name = ?2 WHERE id = ?1",
        params![model_id, name],
    )?;
    let change = log::append(
        tx,
        model_id,
        Entry {
            kind: ChangeKind::Renamed,
            version: None,
            name: Some(name),
            author,
            time,
        },
    )?;
    Ok(Committed {
        value: live(tx, model_id)?,
        change,
    })
}

/// A new model for `owner` whose version 1 copies `model_id`'s latest.
pub(crate) fn duplicate(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    owner: &str,
    name: &str,
) -> Result<Committed<ModelDetail>> {
    check::user(limits, owner)?;
    check::name(limits, name)?;
    let from = detail(tx, model_id)?;
    let content = Content {
        source: from.version.source,
        params: from.version.params,
        // Generated, so not held to max_message_chars (the name is bounded).
        message: format!("duplicate of {} v{}", from.model.name, from.version.number),
        restored_from: None,
        assets: versions::links(&from.version.assets),
    };
    create_with(tx, limits, owner, name, content)
}

/// Marks a live model deleted; logs `Deleted`. Its rows stay (the log must
/// stay readable, and assets stay referenced).
pub(crate) fn delete(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
) -> Result<frep_wire::Change> {
    check::user(limits, author)?;
    live(tx, model_id)?;
    let time = check::now_ms();
    tx.execute(
        "UPDATE models SET deleted = ?2 WHERE id = ?1",
        params![model_id, time],
    )?;
    log::append(
        tx,
        model_id,
        Entry {
            kind: ChangeKind::Deleted,
            version: None,
            name: None,
            author,
            time,
        },
    )
}
