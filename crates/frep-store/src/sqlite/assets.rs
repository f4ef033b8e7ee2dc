//! Content-addressed assets.
//!
//! Algorithm: the key is the BLAKE3 hash of the bytes (hex). So storing the
//! same content twice finds the first row (`INSERT … ON CONFLICT DO
//! NOTHING`) and keeps one copy. The media type of the first upload stays.
//! Assets are never deleted: versions are immutable, and every version that
//! refers to one must stay loadable.

use rusqlite::{params, OptionalExtension, Transaction};

use super::check;
use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;
use crate::{Asset, AssetMeta};

/// Longest media type accepted (RFC 6838 names are at most 127 + 1 + 127).
const MAX_MEDIA_TYPE: usize = 255;

/// The hash an asset of these bytes has.
pub(crate) fn hash_of(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

/// Refuses input a `put` could not store; the hash is computed by the
/// caller outside the writer's lock (hashing 32 MiB takes a while).
pub(crate) fn check_put(limits: &StoreLimits, bytes: &[u8], media_type: &str) -> Result<()> {
    check::at_most("max_asset_bytes", limits.max_asset_bytes, bytes.len())?;
    let ok = !media_type.is_empty()
        && media_type.len() <= MAX_MEDIA_TYPE
        && media_type.contains('/')
        && media_type
            .bytes()
            .all(|b| b.is_ascii_graphic() || b == b' ');
    if ok {
        Ok(())
    } else {
        Err(StoreError::Invalid(format!(
            "{media_type:?} is not a media type (like model/stl)"
        )))
    }
}

/// Stores the bytes under `hash` unless they are there already.
pub(crate) fn put(
    tx: &Transaction,
    hash: &str,
    bytes: &[u8],
    media_type: &str,
) -> Result<AssetMeta> {
    tx.execute(
        "INSERT INTO assets (hash, size, media_type, bytes, created) VALUES (?1, ?2, ?3, ?4, ?5)
         ON CONFLICT (hash) DO NOTHING",
        params![hash, bytes.len() as i64, media_type, bytes, check::now_ms()],
    )?;
    meta(tx, hash)
}

/// An asset's description.
fn meta(tx: &Transaction, hash: &str) -> Result<AssetMeta> {
    tx.query_row(
        "SELECT hash, size, media_type FROM assets WHERE hash = ?1",
        [hash],
        |r| {
            Ok(AssetMeta {
                hash: r.get(0)?,
                size: r.get(1)?,
                media_type: r.get(2)?,
            })
        },
    )
    .optional()?
    .ok_or_else(|| StoreError::NotFound(format!("asset {hash}")))
}

/// An asset with its bytes.
pub(crate) fn get(tx: &Transaction, hash: &str) -> Result<Asset> {
    check::hash(hash)?;
    let meta = meta(tx, hash)?;
    let bytes: Vec<u8> = tx.query_row("SELECT bytes FROM assets WHERE hash = ?1", [hash], |r| {
        r.get(0)
    })?;
    Ok(Asset { meta, bytes })
}
