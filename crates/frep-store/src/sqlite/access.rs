//! The access list: a model's owner plus the editors the owner granted.
//!
//! Policy (the server enforces writes; the store answers):
//! - anyone may read;
//! - the owner and granted editors may write;
//! - only the owner grants and revokes, and the owner's own right cannot be
//!   revoked;
//! - a deleted model has no editors (`NotFound`).

use rusqlite::{params, Transaction};

use super::{check, models};
use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;

/// Whether `user` owns or may edit the live model.
pub(crate) fn may_edit(tx: &Transaction, model_id: &str, user: &str) -> Result<bool> {
    let model = models::live(tx, model_id)?;
    if model.owner == user {
        return Ok(true);
    }
    let n: i64 = tx.query_row(
        "SELECT count(*) FROM editors WHERE model_id = ?1 AND user = ?2",
        params![model_id, user],
        |r| r.get(0),
    )?;
    Ok(n > 0)
}

/// Refuses unless `by` owns the live model.
fn owner_only(tx: &Transaction, model_id: &str, by: &str) -> Result<String> {
    let model = models::live(tx, model_id)?;
    if model.owner != by {
        return Err(StoreError::Forbidden(format!(
            "only the owner of model {model_id} changes who may edit it"
        )));
    }
    Ok(model.owner)
}

/// Lets `user` edit (idempotent).
pub(crate) fn grant(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    by: &str,
    user: &str,
) -> Result<()> {
    check::user(limits, user)?;
    let owner = owner_only(tx, model_id, by)?;
    if owner == user {
        // The owner may always edit; no row needed.
        return Ok(());
    }
    tx.execute(
        "INSERT INTO editors (model_id, user, granted_by, granted) VALUES (?1, ?2, ?3, ?4)
         ON CONFLICT (model_id, user) DO NOTHING",
        params![model_id, user, by, check::now_ms()],
    )?;
    Ok(())
}

/// Withdraws `user`'s right (idempotent for someone never granted).
pub(crate) fn revoke(tx: &Transaction, model_id: &str, by: &str, user: &str) -> Result<()> {
    let owner = owner_only(tx, model_id, by)?;
    if owner == user {
        return Err(StoreError::Invalid(
            "the owner's right to edit cannot be revoked".into(),
        ));
    }
    tx.execute(
        "DELETE FROM editors WHERE model_id = ?1 AND user = ?2",
        params![model_id, user],
    )?;
    Ok(())
}

/// The granted editors, sorted.
pub(crate) fn editors(tx: &Transaction, model_id: &str) -> Result<Vec<String>> {
    models::live(tx, model_id)?;
    let mut stmt =
        tx.prepare_cached("SELECT user FROM editors WHERE model_id = ?1 ORDER BY user")?;
    let rows = stmt.query_map([model_id], |r| r.get(0))?;
    rows.map(|r| r.map_err(StoreError::from)).collect()
}
