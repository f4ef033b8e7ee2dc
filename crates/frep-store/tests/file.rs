//! The SQLite file: durability across reopen, migrations, concurrency,
//! close.

mod common;

use std::collections::BTreeSet;
use std::sync::Arc;

use common::{create, edit};
use frep_store::{
    AssetLink, ChangeKind, HistoryPage, NewVersion, SqliteStore, Store, StoreError, StoreLimits,
};

fn open(path: &std::path::Path) -> SqliteStore {
    SqliteStore::open(path, StoreLimits::default()).unwrap()
}

#[test]
fn everything_written_is_read_back_after_reopen() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    let (id, asset, editor_id) = {
        let s = open(&path);
        assert_eq!(s.migrations_applied(), &[1, 2]);
        let id = create(&s, "ada", "kept", "v1").model.id;
        let asset = s.put_asset(b"mesh", "model/stl").unwrap();
        let v2 = NewVersion {
            source: "v2".into(),
            params: vec![1.5, -2.0],
            message: "second".into(),
            base: Some(1),
            assets: vec![AssetLink {
                name: "m.stl".into(),
                hash: asset.hash.clone(),
            }],
        };
        s.save_version(&id, "bob", v2).unwrap();
        s.rename(&id, "ada", "renamed").unwrap();
        s.grant(&id, "ada", "bob").unwrap();
        let gone = create(&s, "ada", "gone", "x").model.id;
        s.delete(&gone, "ada").unwrap();
        // Dropped without close: every acknowledged write must survive.
        (id, asset, gone)
    };
    let s = open(&path);
    assert!(s.migrations_applied().is_empty());
    let m = s.get_model(&id).unwrap();
    assert_eq!(m.model.name, "renamed");
    assert_eq!(m.model.latest, 2);
    assert_eq!(m.version.source, "v2");
    assert_eq!(m.version.params, vec![1.5, -2.0]);
    assert_eq!(m.version.author, "bob");
    assert_eq!(m.version.assets[0].hash, asset.hash);
    assert_eq!(s.get_asset(&asset.hash).unwrap().bytes, b"mesh");
    assert_eq!(s.get_version(&id, Some(1)).unwrap().source, "v1");
    assert_eq!(s.history(&id, HistoryPage::default()).unwrap().len(), 2);
    assert!(s.may_edit(&id, "bob").unwrap());
    let kinds: Vec<ChangeKind> = s
        .changes(&id, 0, None)
        .unwrap()
        .iter()
        .map(|c| c.kind)
        .collect();
    assert_eq!(
        kinds,
        vec![ChangeKind::Created, ChangeKind::Saved, ChangeKind::Renamed]
    );
    assert_eq!(s.list_models().unwrap().len(), 1);
    assert!(matches!(
        s.get_model(&editor_id),
        Err(StoreError::NotFound(_))
    ));
    assert_eq!(s.changes(&editor_id, 0, None).unwrap().len(), 2);
    // The journal is WAL.
    let conn = rusqlite::Connection::open(&path).unwrap();
    let mode: String = conn
        .query_row("PRAGMA journal_mode", [], |r| r.get(0))
        .unwrap();
    assert_eq!(mode, "wal");
}

#[test]
fn a_newer_database_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    drop(open(&path));
    let newer = i64::from(SqliteStore::schema_version()) + 1;
    {
        let conn = rusqlite::Connection::open(&path).unwrap();
        conn.execute_batch(&format!("PRAGMA user_version = {newer}"))
            .unwrap();
    }
    match SqliteStore::open(&path, StoreLimits::default()) {
        Err(StoreError::SchemaTooNew { found, known }) => {
            assert_eq!(found, newer);
            assert_eq!(known, newer - 1);
        }
        Err(e) => panic!("expected SchemaTooNew, got {e}"),
        Ok(_) => panic!("a newer database was opened"),
    }
}

#[test]
fn migrations_apply_once() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    for round in 0..3 {
        let s = open(&path);
        let expect: &[u32] = if round == 0 { &[1, 2] } else { &[] };
        assert_eq!(s.migrations_applied(), expect);
        create(&s, "ada", &format!("m{round}"), "x");
        assert_eq!(s.list_models().unwrap().len(), round + 1);
        s.close().unwrap();
    }
    let conn = rusqlite::Connection::open(&path).unwrap();
    let v: i64 = conn
        .query_row("PRAGMA user_version", [], |r| r.get(0))
        .unwrap();
    assert_eq!(v, i64::from(SqliteStore::schema_version()));
}

#[test]
fn concurrent_saves_get_distinct_consecutive_numbers() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    let store = Arc::new(open(&path));
    let id = create(store.as_ref(), "ada", "busy", "v1").model.id;
    // A second store on the same file: another process's writer.
    let other = Arc::new(open(&path));
    let threads = 6;
    let per = 8;
    let mut handles = Vec::new();
    for t in 0..threads {
        let s: Arc<SqliteStore> = if t % 2 == 0 {
            Arc::clone(&store)
        } else {
            Arc::clone(&other)
        };
        let id = id.clone();
        handles.push(std::thread::spawn(move || {
            let mut mine = Vec::new();
            let mut conflicts = 0;
            for i in 0..per {
                let mut v = edit(&format!("t{t} i{i}"));
                // Every other save claims a base: it may lose the race.
                if i % 2 == 1 {
                    v.base = Some(s.get_model(&id).unwrap().model.latest);
                }
                match s.save_version(&id, "ada", v) {
                    Ok(c) => mine.push(c.value.number),
                    Err(StoreError::Conflict { base, latest }) => {
                        assert!(latest > base);
                        conflicts += 1;
                    }
                    Err(e) => panic!("save failed: {e}"),
                }
            }
            (mine, conflicts)
        }));
    }
    let mut numbers = Vec::new();
    let mut refused = 0;
    for h in handles {
        let (mine, conflicts) = h.join().unwrap();
        refused += conflicts;
        assert!(mine.windows(2).all(|w| w[0] < w[1]));
        numbers.extend(mine);
    }
    // Every save either committed or was refused as a conflict.
    assert_eq!(numbers.len() + refused, threads * per);
    let set: BTreeSet<u32> = numbers.iter().copied().collect();
    assert_eq!(set.len(), numbers.len(), "a number was given twice");
    let expect: BTreeSet<u32> = (2..=numbers.len() as u32 + 1).collect();
    assert_eq!(set, expect, "numbers are not consecutive");
    let log = store.changes(&id, 0, None).unwrap();
    let seqs: Vec<i64> = log.iter().map(|c| c.seq).collect();
    assert_eq!(seqs, (1..=numbers.len() as i64 + 1).collect::<Vec<_>>());
    let logged: BTreeSet<u32> = log.iter().skip(1).filter_map(|c| c.version).collect();
    assert_eq!(logged, expect);
}

#[test]
fn closed_store_refuses_calls() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    let s = open(&path);
    let id = create(&s, "ada", "m", "x").model.id;
    s.close().unwrap();
    assert!(matches!(s.get_model(&id), Err(StoreError::Closed)));
    assert!(matches!(
        s.save_version(&id, "ada", edit("y")),
        Err(StoreError::Closed)
    ));
    s.close().unwrap();
    let wal = path.with_extension("db-wal");
    // The checkpoint folded the WAL back into the file.
    assert!(!wal.exists() || std::fs::metadata(&wal).unwrap().len() == 0);
    assert_eq!(open(&path).get_model(&id).unwrap().version.source, "x");
}

#[test]
fn a_schema_1_database_is_upgraded_with_its_data() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("frep.db");
    {
        // A database as schema 1 left it, with a model of two versions and
        // an asset link (the foreign keys the rebuild must keep).
        let conn = rusqlite::Connection::open(&path).unwrap();
        conn.execute_batch(include_str!("../migrations/0001_init.sql"))
            .unwrap();
        conn.execute_batch(
            "PRAGMA foreign_keys = ON;
             INSERT INTO models VALUES ('m1', 'old', 'ada', 10, 20, 2, 2, NULL);
             INSERT INTO versions VALUES ('m1', 1, 'héllo', x'', 'ada', 10, 'first', NULL);
             INSERT INTO versions VALUES ('m1', 2, 'bye', x'000000000000F03F', 'bob', 20,
                                          'second', 1);
             INSERT INTO assets VALUES ('a', 1, 'text/plain', x'41', 15);
             INSERT INTO version_assets VALUES ('m1', 2, 'note', 'a');
             INSERT INTO changes (model_id, seq, kind, version, name, author, time)
             VALUES ('m1', 1, 'created', 1, 'old', 'ada', 10),
                    ('m1', 2, 'restored', 2, NULL, 'bob', 20);
             PRAGMA user_version = 1;",
        )
        .unwrap();
    }
    let s = open(&path);
    assert_eq!(s.migrations_applied(), &[2]);
    let v2 = s.get_version("m1", Some(2)).unwrap();
    assert_eq!(v2.source, "bye");
    assert_eq!(v2.params, vec![1.0]);
    assert_eq!(v2.restored_from, Some(1));
    assert_eq!(v2.assets[0].name, "note");
    let h = s.history("m1", HistoryPage::default()).unwrap();
    let sizes: Vec<(u32, u32, &str)> = h
        .iter()
        .map(|v| (v.number, v.source_bytes, v.author.as_str()))
        .collect();
    assert_eq!(sizes, vec![(2, 3, "bob"), (1, 6, "ada")]);
    // The upgraded database takes new versions with foreign keys enforced.
    let v3 = s.save_version("m1", "cy", edit("three")).unwrap().value;
    assert_eq!(v3.number, 3);
    assert_eq!(s.changes("m1", 0, None).unwrap().len(), 3);
    let conn = rusqlite::Connection::open(&path).unwrap();
    conn.execute_batch("PRAGMA foreign_keys = ON").unwrap();
    let orphan = conn.execute("INSERT INTO version_assets VALUES ('m1', 99, 'x', 'a')", []);
    assert!(orphan.is_err(), "the rebuilt table lost its foreign key");
}
