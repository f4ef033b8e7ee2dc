//! The disk cache: one file per artefact, `{key}.bin`, beside a small
//! `{key}.json` with its media type, compute time and (for slices) the byte
//! mapping. Total size bounded; the least recently used go first.
//!
//! - Writes go to a temporary file renamed into place (atomic on one file
//!   system). The metadata goes first, then the body, so a body on disk
//!   always has its metadata.
//! - The index (key → size, last use, metadata) lives in memory. It is
//!   rebuilt from the folder at start, oldest modification first.
//! - At start, leftover temporary files are deleted, and so are bodies whose
//!   length disagrees with their metadata (a crash mid-write).
//! - Files are not synced. The cache acknowledges nothing to anyone: a lost
//!   file is computed again. The length check catches a body the crash left
//!   short.

use std::collections::HashMap;
use std::fs;
use std::io::{self, Write};
use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::SystemTime;

use frep_wire::VolumeLayout;
use serde::{Deserialize, Serialize};

/// What is known of a cached artefact besides its bytes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Meta {
    /// Media type of the body.
    pub media_type: String,
    /// Length of the body, bytes.
    pub len: u64,
    /// Server time it took to compute, ms.
    pub server_ms: f64,
    /// For slices: the byte mapping.
    pub volume: Option<VolumeLayout>,
}

#[derive(Debug)]
struct Entry {
    size: u64,
    last_use: u64,
    meta: Meta,
}

#[derive(Debug, Default)]
struct Index {
    clock: u64,
    total: u64,
    entries: HashMap<String, Entry>,
}

/// A size-bounded folder of artefacts by key.
#[derive(Debug)]
pub struct DiskCache {
    dir: PathBuf,
    max_bytes: u64,
    index: Mutex<Index>,
}

const TMP_PREFIX: &str = ".tmp-";

impl DiskCache {
    /// Opens (creating) the cache folder and indexes what it holds, then
    /// trims it to `max_bytes`.
    pub fn open(dir: &Path, max_bytes: u64) -> io::Result<DiskCache> {
        fs::create_dir_all(dir)?;
        let mut found: Vec<(SystemTime, String, u64, Meta)> = Vec::new();
        for e in fs::read_dir(dir)? {
            let e = e?;
            let name = e.file_name().to_string_lossy().into_owned();
            if name.starts_with(TMP_PREFIX) {
                let _ = fs::remove_file(e.path());
                continue;
            }
            let Some(key) = name.strip_suffix(".bin") else {
                continue;
            };
            let md = e.metadata()?;
            let meta = fs::read(dir.join(format!("{key}.json")))
                .ok()
                .and_then(|b| serde_json::from_slice::<Meta>(&b).ok());
            match meta {
                Some(m) if m.len == md.len() && crate::key::is_key(key) => {
                    let t = md.modified().unwrap_or(SystemTime::UNIX_EPOCH);
                    found.push((t, key.to_string(), md.len(), m));
                }
                _ => {
                    let _ = fs::remove_file(e.path());
                    let _ = fs::remove_file(dir.join(format!("{key}.json")));
                }
            }
        }
        found.sort_by_key(|a| a.0);
        let cache = DiskCache {
            dir: dir.to_path_buf(),
            max_bytes,
            index: Mutex::new(Index::default()),
        };
        {
            let mut ix = cache.lock();
            for (_, key, len, meta) in found {
                ix.clock += 1;
                let size = len + meta_size(&meta);
                ix.total += size;
                let last_use = ix.clock;
                ix.entries.insert(
                    key,
                    Entry {
                        size,
                        last_use,
                        meta,
                    },
                );
            }
        }
        cache.evict(None);
        Ok(cache)
    }

    /// The metadata of a cached artefact, without touching the disk.
    pub fn meta(&self, key: &str) -> Option<Meta> {
        self.lock().entries.get(key).map(|e| e.meta.clone())
    }

    /// The body and metadata of a cached artefact (marked as used now);
    /// `None` when not cached (or deleted under us).
    pub fn get(&self, key: &str) -> io::Result<Option<(Vec<u8>, Meta)>> {
        let meta = {
            let mut ix = self.lock();
            ix.clock += 1;
            let now = ix.clock;
            match ix.entries.get_mut(key) {
                Some(e) => {
                    e.last_use = now;
                    e.meta.clone()
                }
                None => return Ok(None),
            }
        };
        match fs::read(self.body_path(key)) {
            Ok(b) if b.len() as u64 == meta.len => Ok(Some((b, meta))),
            Ok(_) => {
                self.remove(key);
                Ok(None)
            }
            Err(e) if e.kind() == io::ErrorKind::NotFound => {
                self.remove(key);
                Ok(None)
            }
            Err(e) => Err(e),
        }
    }

    /// Stores an artefact (replacing one of the same key), then evicts the
    /// least recently used others until the total fits. A body bigger than
    /// the whole cache is not stored.
    pub fn put(&self, key: &str, bytes: &[u8], meta: &Meta) -> io::Result<()> {
        let size = bytes.len() as u64 + meta_size(meta);
        if size > self.max_bytes || !crate::key::is_key(key) {
            return Ok(());
        }
        let json = serde_json::to_vec(meta).map_err(io::Error::other)?;
        self.write_atomic(&format!("{key}.json"), &json)?;
        self.write_atomic(&format!("{key}.bin"), bytes)?;
        {
            let mut ix = self.lock();
            ix.clock += 1;
            let last_use = ix.clock;
            let old = ix.entries.insert(
                key.to_string(),
                Entry {
                    size,
                    last_use,
                    meta: meta.clone(),
                },
            );
            ix.total = ix.total - old.map_or(0, |o| o.size) + size;
        }
        self.evict(Some(key));
        Ok(())
    }

    /// Total size of the cached files, bytes.
    pub fn total_bytes(&self) -> u64 {
        self.lock().total
    }

    /// Artefacts cached.
    pub fn len(&self) -> usize {
        self.lock().entries.len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Whether `key` is cached.
    pub fn contains(&self, key: &str) -> bool {
        self.lock().entries.contains_key(key)
    }

    fn body_path(&self, key: &str) -> PathBuf {
        self.dir.join(format!("{key}.bin"))
    }

    fn write_atomic(&self, name: &str, bytes: &[u8]) -> io::Result<()> {
        static SEQ: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
        let n = SEQ.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let tmp = self
            .dir
            .join(format!("{TMP_PREFIX}{}-{n}-{name}", std::process::id()));
        let r = (|| {
            let mut f = fs::File::create(&tmp)?;
            f.write_all(bytes)?;
            f.flush()?;
            fs::rename(&tmp, self.dir.join(name))
        })();
        if r.is_err() {
            let _ = fs::remove_file(&tmp);
        }
        r
    }

    fn remove(&self, key: &str) {
        let removed = {
            let mut ix = self.lock();
            let e = ix.entries.remove(key);
            if let Some(e) = &e {
                ix.total -= e.size;
            }
            e.is_some()
        };
        if removed {
            let _ = fs::remove_file(self.body_path(key));
            let _ = fs::remove_file(self.dir.join(format!("{key}.json")));
        }
    }

    /// Removes least recently used entries (never `keep`) until the total
    /// fits.
    fn evict(&self, keep: Option<&str>) {
        loop {
            let victim = {
                let ix = self.lock();
                if ix.total <= self.max_bytes {
                    return;
                }
                ix.entries
                    .iter()
                    .filter(|(k, _)| Some(k.as_str()) != keep)
                    .min_by_key(|(_, e)| e.last_use)
                    .map(|(k, _)| k.clone())
            };
            match victim {
                Some(k) => self.remove(&k),
                None => return,
            }
        }
    }

    fn lock(&self) -> MutexGuard<'_, Index> {
        // Every update of the index is a few plain assignments; a panic
        // elsewhere while it is held cannot leave it half-updated.
        self.index.lock().unwrap_or_else(|p| p.into_inner())
    }
}

/// The size the metadata file takes (its JSON), counted in the total.
fn meta_size(meta: &Meta) -> u64 {
    serde_json::to_vec(meta).map_or(256, |v| v.len() as u64)
}
