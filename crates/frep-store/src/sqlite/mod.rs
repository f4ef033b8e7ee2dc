//! The SQLite store: connections, transactions, and the [`Store`] impl.
//!
//! Connections:
//! - One writer connection sits behind a mutex, so writes are serialized in
//!   this process. Each runs in one `IMMEDIATE` transaction; the version
//!   number and log seq are read and assigned inside it.
//! - Reads of a file database use a small pool of separate read
//!   connections. In WAL mode readers see the last committed snapshot. They
//!   never wait for a writer that is syncing its commit (with
//!   `synchronous=FULL` a commit waits for the disk). So listing and loading
//!   stay fast while someone saves.
//! - An in-memory database is private to its connection, so there every
//!   call uses the writer connection.
//!
//! Every read runs in one (deferred) transaction, so a call that reads
//! several tables sees one consistent snapshot.

mod access;
mod assets;
mod check;
mod log;
mod migrate;
mod models;
mod store;
mod versions;

use std::path::{Path, PathBuf};
use std::sync::{Mutex, MutexGuard};
use std::time::Duration;

use rusqlite::{Connection, OpenFlags, Transaction, TransactionBehavior};

use crate::error::{Result, StoreError};
use crate::limits::StoreLimits;

/// The SQLite implementation of [`crate::Store`].
pub struct SqliteStore {
    /// The one connection that writes; `None` once closed.
    writer: Mutex<Option<Connection>>,
    /// Idle read connections of a file database (`None`: in memory).
    readers: Option<Readers>,
    /// The configured bounds.
    limits: StoreLimits,
    /// Migrations applied when this store was opened.
    applied: Vec<u32>,
}

/// The read-connection pool of a file database.
struct Readers {
    path: PathBuf,
    idle: Mutex<Vec<Connection>>,
}

impl SqliteStore {
    /// Opens (creating if needed) the database file at `path`: WAL mode,
    /// `synchronous=FULL`, foreign keys on, pending migrations applied.
    pub fn open(path: &Path, limits: StoreLimits) -> Result<SqliteStore> {
        let mut conn = Connection::open(path)?;
        configure(&conn, &limits)?;
        let mode: String = conn.query_row("PRAGMA journal_mode=WAL", [], |r| r.get(0))?;
        if !mode.eq_ignore_ascii_case("wal") {
            return Err(StoreError::Invalid(format!(
                "{}: SQLite refused WAL mode (journal mode {mode})",
                path.display()
            )));
        }
        let applied = migrate::migrate(&mut conn)?;
        Ok(SqliteStore {
            writer: Mutex::new(Some(conn)),
            readers: Some(Readers {
                path: path.to_path_buf(),
                idle: Mutex::new(Vec::new()),
            }),
            limits,
            applied,
        })
    }

    /// A private in-memory database (tests, throwaway sessions).
    pub fn open_in_memory(limits: StoreLimits) -> Result<SqliteStore> {
        let mut conn = Connection::open_in_memory()?;
        configure(&conn, &limits)?;
        let applied = migrate::migrate(&mut conn)?;
        Ok(SqliteStore {
            writer: Mutex::new(Some(conn)),
            readers: None,
            limits,
            applied,
        })
    }

    /// The migrations this open applied (empty when the schema was current).
    pub fn migrations_applied(&self) -> &[u32] {
        &self.applied
    }

    /// The schema version this code writes.
    pub fn schema_version() -> u32 {
        migrate::latest()
    }

    /// The configured bounds.
    pub fn limits(&self) -> &StoreLimits {
        &self.limits
    }

    /// Runs `f` in one `IMMEDIATE` transaction of the writer and commits;
    /// on `Err` (or a panic) the transaction rolls back.
    pub(crate) fn write<T>(&self, f: impl FnOnce(&Transaction) -> Result<T>) -> Result<T> {
        let mut guard = lock(&self.writer);
        let conn = guard.as_mut().ok_or(StoreError::Closed)?;
        let tx = conn.transaction_with_behavior(TransactionBehavior::Immediate)?;
        let value = f(&tx)?;
        tx.commit()?;
        Ok(value)
    }

    /// Runs `f` in one read transaction (one snapshot).
    pub(crate) fn read<T>(&self, f: impl FnOnce(&Transaction) -> Result<T>) -> Result<T> {
        let Some(readers) = &self.readers else {
            return self.write_conn_read(f);
        };
        if lock(&self.writer).is_none() {
            return Err(StoreError::Closed);
        }
        let pooled = lock(&readers.idle).pop();
        let mut conn = match pooled {
            Some(c) => c,
            None => open_reader(&readers.path, &self.limits)?,
        };
        // Dropping the read transaction ends it: a rollback, with nothing to
        // keep. The connection goes back to the pool even after an error
        // such as NotFound, which followers polling a log meet often.
        let value = conn
            .transaction()
            .map_err(StoreError::from)
            .and_then(|tx| f(&tx));
        let mut idle = lock(&readers.idle);
        if idle.len() < self.limits.read_connections {
            idle.push(conn);
        }
        value
    }

    /// A read on the writer connection (in-memory databases).
    fn write_conn_read<T>(&self, f: impl FnOnce(&Transaction) -> Result<T>) -> Result<T> {
        let mut guard = lock(&self.writer);
        let conn = guard.as_mut().ok_or(StoreError::Closed)?;
        let tx = conn.transaction()?;
        f(&tx)
    }

    /// Checkpoints the WAL into the main file and closes every connection.
    pub(crate) fn close_all(&self) -> Result<()> {
        if let Some(readers) = &self.readers {
            lock(&readers.idle).clear();
        }
        let conn = lock(&self.writer).take();
        if let Some(conn) = conn {
            if self.readers.is_some() {
                // Fold the WAL back so the file alone holds everything.
                conn.query_row("PRAGMA wal_checkpoint(TRUNCATE)", [], |_| Ok(()))?;
            }
            conn.close().map_err(|(_, e)| StoreError::Db(e))?;
        }
        Ok(())
    }
}

/// Settings every connection gets.
fn configure(conn: &Connection, limits: &StoreLimits) -> Result<()> {
    conn.busy_timeout(Duration::from_millis(limits.busy_timeout_ms))?;
    conn.execute_batch("PRAGMA foreign_keys = ON; PRAGMA synchronous = FULL;")?;
    Ok(())
}

/// A read connection to the file (`query_only`: a bug cannot write through
/// it, bypassing the writer's serialization).
fn open_reader(path: &Path, limits: &StoreLimits) -> Result<Connection> {
    let flags = OpenFlags::SQLITE_OPEN_READ_WRITE
        | OpenFlags::SQLITE_OPEN_URI
        | OpenFlags::SQLITE_OPEN_NO_MUTEX;
    let conn = Connection::open_with_flags(path, flags)?;
    configure(&conn, limits)?;
    conn.execute_batch("PRAGMA query_only = ON;")?;
    Ok(conn)
}

/// Locks a mutex. A poisoned one is still consistent here, so use it: a
/// panic inside a transaction rolled it back when the transaction dropped.
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(|p| p.into_inner())
}
