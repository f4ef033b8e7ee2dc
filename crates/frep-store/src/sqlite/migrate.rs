//! Schema migrations: the numbered SQL files of `migrations/`, embedded.
//!
//! Algorithm, in one `IMMEDIATE` transaction (so two processes opening the
//! same new file cannot both migrate):
//! 1. read `PRAGMA user_version`;
//! 2. refuse a database newer than the newest migration here;
//! 3. run every migration numbered above it, in order;
//! 4. set `user_version` to the last one.
//!
//! The pragma lives in the database header, which is part of the
//! transaction. So either every pending migration is applied and recorded,
//! or none is.
//!
//! Foreign keys are off while migrations run. A table rebuild drops and
//! renames tables, which checks of each step would refuse.
//! `PRAGMA foreign_key_check` must find nothing before the commit. Foreign
//! keys are on again afterwards, whatever happened. This is the procedure of
//! SQLite's ALTER TABLE documentation.

use rusqlite::{Connection, OptionalExtension, TransactionBehavior};

use crate::error::{Result, StoreError};

/// Every migration: its number (= the schema version after it) and SQL.
pub(crate) const MIGRATIONS: &[(u32, &str)] = &[
    (1, include_str!("../../migrations/0001_init.sql")),
    (2, include_str!("../../migrations/0002_version_sources.sql")),
];

/// The schema version this code writes.
pub(crate) fn latest() -> u32 {
    MIGRATIONS.last().map_or(0, |m| m.0)
}

/// Brings the database up to [`latest`]; returns the numbers applied now
/// (empty when it already was).
pub(crate) fn migrate(conn: &mut Connection) -> Result<Vec<u32>> {
    // The pragma is a no-op inside a transaction, so it is set around it.
    conn.execute_batch("PRAGMA foreign_keys = OFF")?;
    let result = migrate_in_transaction(conn);
    conn.execute_batch("PRAGMA foreign_keys = ON")?;
    result
}

fn migrate_in_transaction(conn: &mut Connection) -> Result<Vec<u32>> {
    let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
    let found: i64 = tx.query_row("PRAGMA user_version", [], |r| r.get(0))?;
    let known = i64::from(latest());
    if found > known {
        return Err(StoreError::SchemaTooNew { found, known });
    }
    let mut applied = Vec::new();
    for &(number, sql) in MIGRATIONS {
        if i64::from(number) <= found {
            continue;
        }
        tx.execute_batch(sql)?;
        // Pragmas take no bound parameters; the number is our own constant.
        tx.execute_batch(&format!("PRAGMA user_version = {number}"))?;
        applied.push(number);
    }
    if !applied.is_empty() {
        let broken: Option<String> = tx
            .query_row("PRAGMA foreign_key_check", [], |r| r.get(0))
            .optional()?;
        if let Some(table) = broken {
            return Err(StoreError::Invalid(format!(
                "migration left a dangling reference in table {table}; nothing was changed"
            )));
        }
    }
    tx.commit()?;
    Ok(applied)
}
