//! Every resource bound of the store, configurable, with defaults.
//!
//! Inputs over a bound are refused with [`crate::StoreError::Limit`] naming
//! the field, never truncated: a save either stores what was sent or
//! nothing.

/// Bounds on what the store accepts and returns.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct StoreLimits {
    /// Longest HyperFun source of a version, in bytes.
    pub max_source_bytes: usize,
    /// Longest model name, in characters.
    pub max_name_chars: usize,
    /// Longest version message, in characters.
    pub max_message_chars: usize,
    /// Longest user name (owner, author, editor), in characters.
    pub max_user_chars: usize,
    /// Most parameter values saved with a version.
    pub max_params: usize,
    /// Largest asset, in bytes.
    pub max_asset_bytes: usize,
    /// Most assets one version refers to.
    pub max_assets_per_version: usize,
    /// Most versions one history page lists.
    pub max_versions_listed: u32,
    /// Most log entries one `changes` call returns.
    pub max_changes_listed: u32,
    /// Time the line diff may take before it settles for a correct but
    /// possibly longer (non-minimal) diff, in milliseconds.
    pub diff_timeout_ms: u64,
    /// Idle read connections kept open (file databases only).
    pub read_connections: usize,
    /// How long a write waits for another process's lock, in milliseconds.
    pub busy_timeout_ms: u64,
}

impl Default for StoreLimits {
    fn default() -> Self {
        StoreLimits {
            max_source_bytes: 1 << 20,
            max_name_chars: 200,
            max_message_chars: 2000,
            max_user_chars: 64,
            max_params: 1024,
            max_asset_bytes: 32 << 20,
            max_assets_per_version: 64,
            max_versions_listed: 500,
            max_changes_listed: 1000,
            diff_timeout_ms: 2000,
            read_connections: 4,
            busy_timeout_ms: 5000,
        }
    }
}
