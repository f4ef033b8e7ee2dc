//! Models and versions: create, list, get, save, history, rename,
//! duplicate, delete, restore, diff, conflicts.

mod common;

use common::{create, edit, memory};
use frep_store::{ChangeKind, CreateModel, DiffKind, HistoryPage, NewVersion, Store, StoreError};

const SPHERE: &str =
    "my_model(x[3], a[1])\n{\n  array xt[3];\n  my_model = hfSphere(x, xt, 1);\n}\n";

#[test]
fn create_list_get() {
    let s = memory();
    let a = create(&s, "ada", "sphere", SPHERE);
    let b = create(&s, "bob", "other", "b(x[3], a[1]) { b = 1; }");
    assert_eq!(a.model.name, "sphere");
    assert_eq!(a.model.owner, "ada");
    assert_eq!(a.model.latest, 1);
    assert_eq!(a.version.number, 1);
    assert_eq!(a.version.source, SPHERE);
    assert_eq!(a.version.author, "ada");
    assert_eq!(a.version.message, "first");
    assert_eq!(a.version.model_id, a.model.id);
    assert_ne!(a.model.id, b.model.id);
    assert_eq!(a.model.id.len(), 32);

    let list = s.list_models().unwrap();
    assert_eq!(list.len(), 2);
    assert!(list.contains(&a.model) && list.contains(&b.model));

    let got = s.get_model(&a.model.id).unwrap();
    assert_eq!(got, a);
    assert!(matches!(s.get_model("nope"), Err(StoreError::NotFound(_))));
}

#[test]
fn versions_numbered_in_order_with_params_and_history() {
    let s = memory();
    let m = create(&s, "ada", "m", "v1");
    let id = &m.model.id;
    for i in 2..=5u32 {
        let v = s
            .save_version(
                id,
                "bob",
                NewVersion {
                    source: format!("v{i}"),
                    params: vec![f64::from(i), 0.1 + 0.2, -1e-300],
                    message: format!("m{i}"),
                    base: Some(i - 1),
                    assets: vec![],
                },
            )
            .unwrap();
        assert_eq!(v.value.number, i);
        assert_eq!(v.change.kind, ChangeKind::Saved);
        assert_eq!(v.change.version, Some(i));
    }
    let v3 = s.get_version(id, Some(3)).unwrap();
    assert_eq!(v3.source, "v3");
    assert_eq!(v3.params, vec![3.0, 0.1 + 0.2, -1e-300]);
    assert_eq!(v3.author, "bob");
    assert_eq!(s.get_version(id, None).unwrap().number, 5);
    assert_eq!(s.get_model(id).unwrap().model.latest, 5);
    assert!(matches!(
        s.get_version(id, Some(6)),
        Err(StoreError::NotFound(_))
    ));

    let h = s.history(id, HistoryPage::default()).unwrap();
    let numbers: Vec<u32> = h.iter().map(|v| v.number).collect();
    assert_eq!(numbers, vec![5, 4, 3, 2, 1]);
    assert_eq!(h[0].message, "m5");
    assert_eq!(h[0].source_bytes, 2);
    let page = s
        .history(
            id,
            HistoryPage {
                before: Some(4),
                limit: Some(2),
            },
        )
        .unwrap();
    assert_eq!(
        page.iter().map(|v| v.number).collect::<Vec<_>>(),
        vec![3, 2]
    );
}

#[test]
fn stale_base_is_a_conflict_naming_the_latest() {
    let s = memory();
    let id = create(&s, "ada", "m", "v1").model.id;
    let mut first = edit("ours");
    first.base = Some(1);
    s.save_version(&id, "ada", first).unwrap();
    let mut theirs = edit("theirs");
    theirs.base = Some(1);
    match s.save_version(&id, "bob", theirs) {
        Err(StoreError::Conflict { base, latest }) => assert_eq!((base, latest), (1, 2)),
        other => panic!("expected a conflict, got {other:?}"),
    }
    // Nothing was written by the refused save.
    assert_eq!(s.get_model(&id).unwrap().version.source, "ours");
    assert_eq!(s.changes(&id, 0, None).unwrap().len(), 2);
}

#[test]
fn diff_lines_and_numbers() {
    let s = memory();
    let id = create(&s, "ada", "m", "a\nb\nc\n").model.id;
    s.save_version(&id, "ada", edit("a\nc\nd\n")).unwrap();
    let mut p = edit("a\nc\nd\n");
    p.params = vec![1.0];
    s.save_version(&id, "ada", p).unwrap();

    let d = s.diff(&id, 1, 2).unwrap();
    assert_eq!((d.from, d.to), (1, 2));
    assert!(!d.params_changed);
    let got: Vec<(DiffKind, Option<u32>, Option<u32>, &str)> = d
        .lines
        .iter()
        .map(|l| (l.kind, l.old_line, l.new_line, l.text.as_str()))
        .collect();
    assert_eq!(
        got,
        vec![
            (DiffKind::Same, Some(1), Some(1), "a"),
            (DiffKind::Removed, Some(2), None, "b"),
            (DiffKind::Same, Some(3), Some(2), "c"),
            (DiffKind::Added, None, Some(3), "d"),
        ]
    );
    let same = s.diff(&id, 2, 3).unwrap();
    assert!(same.params_changed);
    assert!(same.lines.iter().all(|l| l.kind == DiffKind::Same));
    assert!(matches!(s.diff(&id, 1, 9), Err(StoreError::NotFound(_))));
}

#[test]
fn restore_makes_an_equal_new_version() {
    let s = memory();
    let created = s
        .create_model(
            "ada",
            CreateModel {
                name: "m".into(),
                source: "one".into(),
                params: vec![0.5, 2.0],
                message: String::new(),
            },
        )
        .unwrap();
    let id = created.value.model.id;
    s.save_version(&id, "ada", edit("two")).unwrap();
    let r = s.restore(&id, "bob", 1, "").unwrap();
    let v = r.value;
    assert_eq!(v.number, 3);
    assert_eq!(v.source, "one");
    assert_eq!(v.params, vec![0.5, 2.0]);
    assert_eq!(v.restored_from, Some(1));
    assert_eq!(v.message, "restore 1");
    assert_eq!(v.author, "bob");
    assert_eq!(r.change.kind, ChangeKind::Restored);
    assert_eq!(r.change.version, Some(3));
    assert_eq!(s.get_version(&id, None).unwrap(), v);
    let h = s.history(&id, HistoryPage::default()).unwrap();
    assert_eq!(h[0].restored_from, Some(1));
    let d = s.diff(&id, 1, 3).unwrap();
    assert!(!d.params_changed && d.lines.iter().all(|l| l.kind == DiffKind::Same));
    assert!(matches!(
        s.restore(&id, "bob", 7, "x"),
        Err(StoreError::NotFound(_))
    ));
}

#[test]
fn rename_duplicate_delete() {
    let s = memory();
    let m = create(&s, "ada", "old", "src");
    let id = m.model.id.clone();
    s.save_version(&id, "ada", edit("src2")).unwrap();

    let r = s.rename(&id, "ada", "new name").unwrap();
    assert_eq!(r.value.name, "new name");
    assert_eq!(r.change.kind, ChangeKind::Renamed);
    assert_eq!(r.change.name.as_deref(), Some("new name"));
    assert_eq!(s.get_model(&id).unwrap().model.name, "new name");
    assert_eq!(s.get_model(&id).unwrap().model.latest, 2);
    let v2_time = s.get_version(&id, Some(2)).unwrap().created;
    assert_eq!(
        r.value.updated, v2_time,
        "updated is the latest version's time"
    );

    let d = s.duplicate(&id, "bob", "copy").unwrap();
    assert_ne!(d.value.model.id, id);
    assert_eq!(d.value.model.owner, "bob");
    assert_eq!(d.value.model.name, "copy");
    assert_eq!(d.value.version.number, 1);
    assert_eq!(d.value.version.source, "src2");
    assert_eq!(d.change.kind, ChangeKind::Created);
    assert_eq!(d.change.model_id, d.value.model.id);
    assert_eq!(d.change.seq, 1);
    // The original is untouched by the copy.
    assert_eq!(s.changes(&id, 0, None).unwrap().len(), 3);

    let del = s.delete(&id, "ada").unwrap();
    assert_eq!(del.kind, ChangeKind::Deleted);
    assert_eq!(del.seq, 4);
    assert!(matches!(s.get_model(&id), Err(StoreError::NotFound(_))));
    assert!(matches!(
        s.get_version(&id, Some(1)),
        Err(StoreError::NotFound(_))
    ));
    assert!(matches!(
        s.save_version(&id, "ada", edit("x")),
        Err(StoreError::NotFound(_))
    ));
    assert!(matches!(s.delete(&id, "ada"), Err(StoreError::NotFound(_))));
    let listed: Vec<String> = s.list_models().unwrap().into_iter().map(|m| m.id).collect();
    assert_eq!(listed, vec![d.value.model.id.clone()]);
    // The log stays readable after the delete.
    let log = s.changes(&id, 0, None).unwrap();
    assert_eq!(log.last().map(|c| c.kind), Some(ChangeKind::Deleted));
}

#[test]
fn log_is_gapless_ordered_and_typed() {
    let s = memory();
    let id = create(&s, "ada", "m", "1").model.id;
    let other = create(&s, "bob", "o", "1").model.id;
    s.save_version(&id, "ada", edit("2")).unwrap();
    s.save_version(&other, "bob", edit("2")).unwrap();
    s.rename(&id, "ada", "m2").unwrap();
    s.restore(&id, "ada", 1, "back").unwrap();
    s.delete(&id, "ada").unwrap();

    let log = s.changes(&id, 0, None).unwrap();
    let seqs: Vec<i64> = log.iter().map(|c| c.seq).collect();
    assert_eq!(seqs, vec![1, 2, 3, 4, 5]);
    let kinds: Vec<ChangeKind> = log.iter().map(|c| c.kind).collect();
    use ChangeKind::*;
    assert_eq!(kinds, vec![Created, Saved, Renamed, Restored, Deleted]);
    let versions: Vec<Option<u32>> = log.iter().map(|c| c.version).collect();
    assert_eq!(versions, vec![Some(1), Some(2), None, Some(3), None]);
    assert_eq!(log[0].name.as_deref(), Some("m"));
    assert!(log.iter().all(|c| c.model_id == id && c.author == "ada"));
    assert!(log.windows(2).all(|w| w[0].time <= w[1].time));

    let tail = s.changes(&id, 3, Some(1)).unwrap();
    assert_eq!(tail.len(), 1);
    assert_eq!(tail[0].seq, 4);
    assert!(s.changes(&id, 5, None).unwrap().is_empty());
    assert!(matches!(
        s.changes("nope", 0, None),
        Err(StoreError::NotFound(_))
    ));

    let all = s.changes_since(0, None).unwrap();
    assert_eq!(all.len(), 7);
    assert!(all.windows(2).all(|w| w[0].global_seq < w[1].global_seq));
    let per_model: Vec<i64> = all
        .iter()
        .filter(|g| g.change.model_id == other)
        .map(|g| g.change.seq)
        .collect();
    assert_eq!(per_model, vec![1, 2]);
    let after = all[4].global_seq;
    let rest = s.changes_since(after, None).unwrap();
    assert_eq!(rest, all[5..].to_vec());
}

#[test]
fn bad_input_is_refused_not_stored() {
    let s = memory();
    let id = create(&s, "ada", "m", "1").model.id;
    let mut nan = edit("2");
    nan.params = vec![1.0, f64::NAN];
    assert!(matches!(
        s.save_version(&id, "ada", nan),
        Err(StoreError::Invalid(_))
    ));
    assert!(matches!(
        s.rename(&id, "ada", "  "),
        Err(StoreError::Invalid(_))
    ));
    assert!(matches!(
        s.rename(&id, "ada", "a\nb"),
        Err(StoreError::Invalid(_))
    ));
    assert!(matches!(
        s.save_version(&id, "", edit("2")),
        Err(StoreError::Invalid(_))
    ));
    assert_eq!(s.get_model(&id).unwrap().model.latest, 1);
    assert_eq!(s.changes(&id, 0, None).unwrap().len(), 1);
}
