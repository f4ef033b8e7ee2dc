//! Input checks against [`StoreLimits`], shared by every write.
//!
//! Each check refuses with [`StoreError::Limit`] naming the limit's field,
//! or [`StoreError::Invalid`] for input no limit could make acceptable.

use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;

/// Refuses `got > limit`, naming the limit.
pub(crate) fn at_most(name: &'static str, limit: usize, got: usize) -> Result<()> {
    if got > limit {
        return Err(StoreError::Limit {
            name,
            limit: limit as u64,
            got: got as u64,
        });
    }
    Ok(())
}

/// A model name: not blank, no control characters, bounded.
pub(crate) fn name(limits: &StoreLimits, name: &str) -> Result<()> {
    if name.trim().is_empty() {
        return Err(StoreError::Invalid("a model name cannot be empty".into()));
    }
    if name.chars().any(char::is_control) {
        return Err(StoreError::Invalid(
            "a model name cannot contain control characters".into(),
        ));
    }
    at_most(
        "max_name_chars",
        limits.max_name_chars,
        name.chars().count(),
    )
}

/// A user name (owner, author, editor): not blank, bounded.
pub(crate) fn user(limits: &StoreLimits, user: &str) -> Result<()> {
    if user.trim().is_empty() {
        return Err(StoreError::Invalid("a user name cannot be empty".into()));
    }
    at_most(
        "max_user_chars",
        limits.max_user_chars,
        user.chars().count(),
    )
}

/// A version's content: source size, parameter count and finiteness,
/// message length.
pub(crate) fn content(
    limits: &StoreLimits,
    source: &str,
    params: &[f64],
    message: &str,
) -> Result<()> {
    at_most("max_source_bytes", limits.max_source_bytes, source.len())?;
    at_most("max_params", limits.max_params, params.len())?;
    if let Some(i) = params.iter().position(|p| !p.is_finite()) {
        return Err(StoreError::Invalid(format!(
            "parameter a[{}] is not a finite number",
            i + 1
        )));
    }
    at_most(
        "max_message_chars",
        limits.max_message_chars,
        message.chars().count(),
    )
}

/// A page size: `None` is the limit, above it is refused, zero is invalid.
pub(crate) fn page(name: &'static str, limit: u32, asked: Option<u32>) -> Result<u32> {
    let n = asked.unwrap_or(limit);
    if n == 0 {
        return Err(StoreError::Invalid("a page size must be at least 1".into()));
    }
    at_most(name, limit as usize, n as usize)?;
    Ok(n)
}

/// A BLAKE3 hex hash: 64 lowercase hex digits.
pub(crate) fn hash(hash: &str) -> Result<()> {
    let ok = hash.len() == 64
        && hash
            .bytes()
            .all(|b| b.is_ascii_digit() || (b'a'..=b'f').contains(&b));
    if ok {
        Ok(())
    } else {
        Err(StoreError::Invalid(format!(
            "{hash:?} is not an asset hash (64 lowercase hex digits)"
        )))
    }
}

/// Parameter values as stored: 8 little-endian bytes each.
pub(crate) fn params_to_blob(params: &[f64]) -> Vec<u8> {
    params.iter().flat_map(|p| p.to_le_bytes()).collect()
}

/// Stored parameter bytes back to values.
pub(crate) fn params_from_blob(blob: &[u8]) -> Result<Vec<f64>> {
    if !blob.len().is_multiple_of(8) {
        return Err(StoreError::Invalid(format!(
            "stored parameters have {} bytes, not a multiple of 8",
            blob.len()
        )));
    }
    Ok(blob
        .chunks_exact(8)
        .map(|c| {
            let mut b = [0u8; 8];
            b.copy_from_slice(c);
            f64::from_le_bytes(b)
        })
        .collect())
}

/// Milliseconds since the Unix epoch (0 if the clock is before it).
pub(crate) fn now_ms() -> i64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| i64::try_from(d.as_millis()).unwrap_or(i64::MAX))
}
