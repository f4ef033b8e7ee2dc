//! The change log: one ordered list of entries per model.
//!
//! Algorithm: an entry's `seq` is the model's `last_seq + 1`, read and
//! bumped in the writing transaction. So a model's log is 1, 2, 3, …
//! without gaps. `UNIQUE (model_id, seq)` guards it against any other
//! writer. `global_seq` is the table's AUTOINCREMENT key. It increases in
//! commit order across models (the writer is serialized), and is never
//! reused.

use frep_wire::{Change, ChangeKind};
use rusqlite::{params, OptionalExtension, Row, Transaction};

use crate::error::{Result, StoreError};
use crate::GlobalChange;

/// What a new entry says.
pub(crate) struct Entry<'a> {
    pub kind: ChangeKind,
    pub version: Option<u32>,
    pub name: Option<&'a str>,
    pub author: &'a str,
    pub time: i64,
}

/// Appends an entry to `model_id`'s log and returns it.
pub(crate) fn append(tx: &Transaction, model_id: &str, e: Entry) -> Result<Change> {
    let seq: i64 = tx.query_row(
        "UPDATE models SET last_seq = last_seq + 1 WHERE id = ?1 RETURNING last_seq",
        [model_id],
        |r| r.get(0),
    )?;
    tx.execute(
        "INSERT INTO changes (model_id, seq, kind, version, name, author, time)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
        params![
            model_id,
            seq,
            kind_name(e.kind),
            e.version,
            e.name,
            e.author,
            e.time
        ],
    )?;
    Ok(Change {
        seq,
        model_id: model_id.to_string(),
        kind: e.kind,
        version: e.version,
        name: e.name.map(str::to_string),
        author: e.author.to_string(),
        time: e.time,
    })
}

/// A model's entries after `after`, at most `limit`. The model must exist
/// (deleted or not).
pub(crate) fn changes(
    tx: &Transaction,
    model_id: &str,
    after: i64,
    limit: u32,
) -> Result<Vec<Change>> {
    let exists: Option<i64> = tx
        .query_row("SELECT 1 FROM models WHERE id = ?1", [model_id], |r| {
            r.get(0)
        })
        .optional()?;
    if exists.is_none() {
        return Err(StoreError::NotFound(format!("model {model_id}")));
    }
    let mut stmt = tx.prepare_cached(
        "SELECT global_seq, seq, model_id, kind, version, name, author, time FROM changes
         WHERE model_id = ?1 AND seq > ?2 ORDER BY seq LIMIT ?3",
    )?;
    let rows = stmt.query_map(params![model_id, after, limit], row_to_change)?;
    rows.map(|r| Ok(r?.change)).collect()
}

/// Every model's entries after `after` (global order), at most `limit`.
pub(crate) fn since(tx: &Transaction, after: i64, limit: u32) -> Result<Vec<GlobalChange>> {
    let mut stmt = tx.prepare_cached(
        "SELECT global_seq, seq, model_id, kind, version, name, author, time FROM changes
         WHERE global_seq > ?1 ORDER BY global_seq LIMIT ?2",
    )?;
    let rows = stmt.query_map(params![after, limit], row_to_change)?;
    rows.map(|r| r.map_err(StoreError::from)).collect()
}

fn row_to_change(r: &Row) -> rusqlite::Result<GlobalChange> {
    let kind: String = r.get(3)?;
    let kind = kind_from_name(&kind).ok_or_else(|| {
        rusqlite::Error::FromSqlConversionFailure(
            3,
            rusqlite::types::Type::Text,
            format!("unknown change kind {kind:?}").into(),
        )
    })?;
    Ok(GlobalChange {
        global_seq: r.get(0)?,
        change: Change {
            seq: r.get(1)?,
            model_id: r.get(2)?,
            kind,
            version: r.get(4)?,
            name: r.get(5)?,
            author: r.get(6)?,
            time: r.get(7)?,
        },
    })
}

/// The stored name of a kind (the migration's CHECK lists the same).
fn kind_name(k: ChangeKind) -> &'static str {
    match k {
        ChangeKind::Created => "created",
        ChangeKind::Saved => "saved",
        ChangeKind::Restored => "restored",
        ChangeKind::Renamed => "renamed",
        ChangeKind::Deleted => "deleted",
    }
}

fn kind_from_name(s: &str) -> Option<ChangeKind> {
    Some(match s {
        "created" => ChangeKind::Created,
        "saved" => ChangeKind::Saved,
        "restored" => ChangeKind::Restored,
        "renamed" => ChangeKind::Renamed,
        "deleted" => ChangeKind::Deleted,
        _ => return None,
    })
}
