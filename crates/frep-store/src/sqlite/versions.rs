//! Versions: insert (save, restore, create), load, history, diff.
//!
//! Algorithm of a save, inside the writer's `IMMEDIATE` transaction:
//! 1. read the model's `latest`;
//! 2. with a `base` that is not it, refuse with `Conflict { latest }`;
//! 3. else bump `latest` (`UPDATE … RETURNING`);
//! 4. insert the version under that number, and its asset links;
//! 5. log the change.
//!
//! The number is assigned where it is written.
//! `PRIMARY KEY (model_id, number)` refuses a second version N from any
//! other writer. So two saves can never both become version N.
//!
//! A version is two rows, so listing never reads sources. Its small columns
//! (what a history page lists) are in `versions`. Its source and parameters
//! are in `version_sources`.

use std::collections::HashSet;
use std::time::Duration;

use frep_wire::{AssetRef, ChangeKind, SourceDiff, Version, VersionSummary};
use rusqlite::{params, OptionalExtension, Transaction};

use super::log::{self, Entry};
use super::{check, models};
use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;
use crate::{AssetLink, Committed, HistoryPage, NewVersion};

/// What a new version holds (checked against the limits by the caller).
pub(crate) struct Content {
    pub source: String,
    pub params: Vec<f64>,
    pub message: String,
    pub restored_from: Option<u32>,
    pub assets: Vec<AssetLink>,
}

/// Inserts the model's next version; the model row must exist.
pub(crate) fn insert(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
    time: i64,
    c: Content,
) -> Result<Version> {
    check::at_most(
        "max_assets_per_version",
        limits.max_assets_per_version,
        c.assets.len(),
    )?;
    let number: u32 = tx.query_row(
        "UPDATE models SET latest = latest + 1, updated = ?2 WHERE id = ?1 RETURNING latest",
        params![model_id, time],
        |r| r.get(0),
    )?;
    tx.execute(
        "INSERT INTO versions (model_id, number, author, created, restored_from,
                               source_bytes, message)
         VALUES (?1, ?2, ?3, ?4, ?5, ?6, ?7)",
        params![
            model_id,
            number,
            author,
            time,
            c.restored_from,
            c.source.len() as i64,
            c.message,
        ],
    )?;
    tx.execute(
        "INSERT INTO version_sources (model_id, number, params, source) VALUES (?1, ?2, ?3, ?4)",
        params![model_id, number, check::params_to_blob(&c.params), c.source],
    )?;
    link_assets(tx, model_id, number, &c.assets)?;
    Ok(Version {
        model_id: model_id.to_string(),
        number,
        source: c.source,
        params: c.params,
        author: author.to_string(),
        created: time,
        message: c.message,
        restored_from: c.restored_from,
        assets: assets_of(tx, model_id, number)?,
    })
}

/// Records a version's asset links; every asset must be stored already and
/// every name used once.
fn link_assets(tx: &Transaction, model_id: &str, number: u32, links: &[AssetLink]) -> Result<()> {
    let mut names = HashSet::new();
    for l in links {
        check::hash(&l.hash)?;
        if l.name.trim().is_empty() || !names.insert(l.name.as_str()) {
            return Err(StoreError::Invalid(format!(
                "asset name {:?} is empty or used twice in one version",
                l.name
            )));
        }
        let stored: Option<i64> = tx
            .query_row("SELECT 1 FROM assets WHERE hash = ?1", [&l.hash], |r| {
                r.get(0)
            })
            .optional()?;
        if stored.is_none() {
            return Err(StoreError::NotFound(format!(
                "asset {} (upload it before saving a version that uses it)",
                l.hash
            )));
        }
        tx.execute(
            "INSERT INTO version_assets (model_id, number, name, hash) VALUES (?1, ?2, ?3, ?4)",
            params![model_id, number, l.name, l.hash],
        )?;
    }
    Ok(())
}

/// A version's assets, by name.
fn assets_of(tx: &Transaction, model_id: &str, number: u32) -> Result<Vec<AssetRef>> {
    let mut stmt = tx.prepare_cached(
        "SELECT a.hash, a.size, a.media_type, v.name FROM version_assets v
         JOIN assets a ON a.hash = v.hash
         WHERE v.model_id = ?1 AND v.number = ?2 ORDER BY v.name",
    )?;
    let rows = stmt.query_map(params![model_id, number], |r| {
        Ok(AssetRef {
            hash: r.get(0)?,
            size: r.get(1)?,
            media_type: r.get(2)?,
            name: r.get(3)?,
        })
    })?;
    rows.map(|r| r.map_err(StoreError::from)).collect()
}

/// The links a copy of a version needs.
pub(crate) fn links(assets: &[AssetRef]) -> Vec<AssetLink> {
    assets
        .iter()
        .map(|a| AssetLink {
            name: a.name.clone(),
            hash: a.hash.clone(),
        })
        .collect()
}

/// Version `number` of a model (liveness checked by the caller).
pub(crate) fn load(tx: &Transaction, model_id: &str, number: u32) -> Result<Version> {
    let row = tx
        .query_row(
            "SELECT s.source, s.params, v.author, v.created, v.message, v.restored_from
             FROM versions v JOIN version_sources s USING (model_id, number)
             WHERE v.model_id = ?1 AND v.number = ?2",
            params![model_id, number],
            |r| {
                Ok((
                    r.get::<_, String>(0)?,
                    r.get::<_, Vec<u8>>(1)?,
                    r.get::<_, String>(2)?,
                    r.get::<_, i64>(3)?,
                    r.get::<_, String>(4)?,
                    r.get::<_, Option<u32>>(5)?,
                ))
            },
        )
        .optional()?;
    let Some((source, params, author, created, message, restored_from)) = row else {
        return Err(StoreError::NotFound(format!(
            "version {number} of model {model_id}"
        )));
    };
    Ok(Version {
        model_id: model_id.to_string(),
        number,
        source,
        params: check::params_from_blob(&params)?,
        author,
        created,
        message,
        restored_from,
        assets: assets_of(tx, model_id, number)?,
    })
}

/// Version `number` (`None`: the latest) of a live model.
pub(crate) fn get(tx: &Transaction, model_id: &str, number: Option<u32>) -> Result<Version> {
    let model = models::live(tx, model_id)?;
    load(tx, model_id, number.unwrap_or(model.latest))
}

/// A page of a live model's history, newest first.
pub(crate) fn history(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    page: HistoryPage,
) -> Result<Vec<VersionSummary>> {
    let limit = check::page(
        "max_versions_listed",
        limits.max_versions_listed,
        page.limit,
    )?;
    let model = models::live(tx, model_id)?;
    let before = page.before.unwrap_or(model.latest.saturating_add(1));
    let mut stmt = tx.prepare_cached(
        "SELECT number, author, created, message, restored_from, source_bytes
         FROM versions WHERE model_id = ?1 AND number < ?2 ORDER BY number DESC LIMIT ?3",
    )?;
    let rows = stmt.query_map(params![model_id, before, limit], |r| {
        Ok(VersionSummary {
            number: r.get(0)?,
            author: r.get(1)?,
            created: r.get(2)?,
            message: r.get(3)?,
            restored_from: r.get(4)?,
            source_bytes: r.get(5)?,
        })
    })?;
    rows.map(|r| r.map_err(StoreError::from)).collect()
}

/// Saves a new version of a live model; logs `Saved`.
pub(crate) fn save(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
    v: NewVersion,
) -> Result<Committed<Version>> {
    check::user(limits, author)?;
    check::content(limits, &v.source, &v.params, &v.message)?;
    let model = models::live(tx, model_id)?;
    if let Some(base) = v.base {
        if base != model.latest {
            return Err(StoreError::Conflict {
                base,
                latest: model.latest,
            });
        }
    }
    let content = Content {
        source: v.source,
        params: v.params,
        message: v.message,
        restored_from: None,
        assets: v.assets,
    };
    write_logged(tx, limits, model_id, author, content, ChangeKind::Saved)
}

/// A new version equal to version `number`; logs `Restored`.
pub(crate) fn restore(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
    number: u32,
    message: &str,
) -> Result<Committed<Version>> {
    check::user(limits, author)?;
    check::at_most(
        "max_message_chars",
        limits.max_message_chars,
        message.chars().count(),
    )?;
    models::live(tx, model_id)?;
    let old = load(tx, model_id, number)?;
    let message = if message.trim().is_empty() {
        format!("restore {number}")
    } else {
        message.to_string()
    };
    let content = Content {
        source: old.source,
        params: old.params,
        message,
        restored_from: Some(number),
        assets: links(&old.assets),
    };
    write_logged(tx, limits, model_id, author, content, ChangeKind::Restored)
}

/// Inserts a version and logs it under `kind`.
fn write_logged(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    author: &str,
    content: Content,
    kind: ChangeKind,
) -> Result<Committed<Version>> {
    let time = check::now_ms();
    let version = insert(tx, limits, model_id, author, time, content)?;
    let change = log::append(
        tx,
        model_id,
        Entry {
            kind,
            version: Some(version.number),
            name: None,
            author,
            time,
        },
    )?;
    Ok(Committed {
        value: version,
        change,
    })
}

/// The line diff of two versions of a live model.
pub(crate) fn diff(
    tx: &Transaction,
    limits: &StoreLimits,
    model_id: &str,
    from: u32,
    to: u32,
) -> Result<SourceDiff> {
    models::live(tx, model_id)?;
    let old = load(tx, model_id, from)?;
    let new = load(tx, model_id, to)?;
    let timeout = Duration::from_millis(limits.diff_timeout_ms);
    Ok(SourceDiff {
        from,
        to,
        lines: crate::diff::line_diff(&old.source, &new.source, timeout),
        params_changed: old.params != new.params,
    })
}
