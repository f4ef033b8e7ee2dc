//! Assets (content-addressed, deduplicated, referenced by versions), the
//! access list, and the configured limits.

mod common;

use common::{create, edit, memory};
use frep_store::{
    AssetLink, CreateModel, HistoryPage, NewVersion, SaveVersion, SqliteStore, Store, StoreError,
    StoreLimits,
};

#[test]
fn assets_are_content_addressed_and_deduplicated() {
    let s = memory();
    let bytes = b"solid cube\nendsolid cube\n".to_vec();
    let a = s.put_asset(&bytes, "model/stl").unwrap();
    assert_eq!(a.hash, blake3::hash(&bytes).to_hex().to_string());
    assert_eq!(a.size, bytes.len() as u64);
    let again = s.put_asset(&bytes, "application/octet-stream").unwrap();
    // Same content, same asset: the first media type stays.
    assert_eq!(again, a);
    let other = s.put_asset(b"different", "text/plain").unwrap();
    assert_ne!(other.hash, a.hash);

    let got = s.get_asset(&a.hash).unwrap();
    assert_eq!(got.bytes, bytes);
    assert_eq!(got.meta, a);
    let missing = "0".repeat(64);
    assert!(matches!(
        s.get_asset(&missing),
        Err(StoreError::NotFound(_))
    ));
    assert!(matches!(s.get_asset("../etc"), Err(StoreError::Invalid(_))));
    assert!(matches!(
        s.put_asset(b"x", "nonsense"),
        Err(StoreError::Invalid(_))
    ));
}

#[test]
fn versions_reference_assets_by_name() {
    let s = memory();
    let id = create(&s, "ada", "m", "1").model.id;
    let mesh = s.put_asset(b"mesh bytes", "model/stl").unwrap();
    let img = s.put_asset(b"image bytes", "image/png").unwrap();
    let v = s
        .save_version(
            &id,
            "ada",
            NewVersion {
                source: "uses assets".into(),
                assets: vec![
                    AssetLink {
                        name: "part.stl".into(),
                        hash: mesh.hash.clone(),
                    },
                    AssetLink {
                        name: "decal.png".into(),
                        hash: img.hash.clone(),
                    },
                ],
                ..NewVersion::default()
            },
        )
        .unwrap()
        .value;
    let names: Vec<(&str, &str, u64)> = v
        .assets
        .iter()
        .map(|a| (a.name.as_str(), a.media_type.as_str(), a.size))
        .collect();
    assert_eq!(
        names,
        vec![
            ("decal.png", "image/png", 11),
            ("part.stl", "model/stl", 10)
        ]
    );
    assert_eq!(s.get_version(&id, Some(2)).unwrap().assets, v.assets);

    // A restore and a duplicate keep the references.
    s.save_version(&id, "ada", edit("no assets")).unwrap();
    let r = s.restore(&id, "ada", 2, "").unwrap().value;
    assert_eq!(r.assets, v.assets);
    let d = s.duplicate(&id, "bob", "copy").unwrap().value;
    assert_eq!(d.version.assets, v.assets);

    // The wire form names an asset by its hash.
    let wire = SaveVersion {
        source: "wire".into(),
        params: vec![],
        message: String::new(),
        base: None,
        assets: vec![mesh.hash.clone()],
    };
    let w = s.save_version(&id, "ada", wire.into()).unwrap().value;
    assert_eq!(w.assets[0].name, mesh.hash);

    // Unknown or repeated assets are refused, and nothing is written.
    let latest = s.get_model(&id).unwrap().model.latest;
    let unknown = NewVersion {
        source: "x".into(),
        assets: vec![AssetLink {
            name: "a".into(),
            hash: "f".repeat(64),
        }],
        ..NewVersion::default()
    };
    assert!(matches!(
        s.save_version(&id, "ada", unknown),
        Err(StoreError::NotFound(_))
    ));
    let twice = NewVersion {
        source: "x".into(),
        assets: vec![
            AssetLink {
                name: "a".into(),
                hash: mesh.hash.clone(),
            },
            AssetLink {
                name: "a".into(),
                hash: img.hash.clone(),
            },
        ],
        ..NewVersion::default()
    };
    assert!(matches!(
        s.save_version(&id, "ada", twice),
        Err(StoreError::Invalid(_))
    ));
    assert_eq!(s.get_model(&id).unwrap().model.latest, latest);
}

#[test]
fn access_list() {
    let s = memory();
    let id = create(&s, "ada", "m", "1").model.id;
    assert!(s.may_edit(&id, "ada").unwrap());
    assert!(!s.may_edit(&id, "bob").unwrap());

    assert!(matches!(
        s.grant(&id, "bob", "bob"),
        Err(StoreError::Forbidden(_))
    ));
    s.grant(&id, "ada", "bob").unwrap();
    s.grant(&id, "ada", "bob").unwrap();
    s.grant(&id, "ada", "cy").unwrap();
    assert!(s.may_edit(&id, "bob").unwrap());
    assert_eq!(s.editors(&id).unwrap(), vec!["bob", "cy"]);
    // An editor may not change the list.
    assert!(matches!(
        s.revoke(&id, "bob", "cy"),
        Err(StoreError::Forbidden(_))
    ));
    assert!(matches!(
        s.revoke(&id, "ada", "ada"),
        Err(StoreError::Invalid(_))
    ));
    s.revoke(&id, "ada", "bob").unwrap();
    assert!(!s.may_edit(&id, "bob").unwrap());
    assert_eq!(s.editors(&id).unwrap(), vec!["cy"]);

    // A duplicate belongs to whoever made it, with no editors.
    let copy = s.duplicate(&id, "cy", "mine").unwrap().value.model.id;
    assert!(s.may_edit(&copy, "cy").unwrap());
    assert!(!s.may_edit(&copy, "ada").unwrap());
    assert!(s.editors(&copy).unwrap().is_empty());

    assert!(matches!(
        s.may_edit("nope", "ada"),
        Err(StoreError::NotFound(_))
    ));
}

fn small() -> SqliteStore {
    SqliteStore::open_in_memory(StoreLimits {
        max_source_bytes: 10,
        max_name_chars: 5,
        max_message_chars: 8,
        max_user_chars: 4,
        max_params: 2,
        max_asset_bytes: 4,
        max_assets_per_version: 1,
        max_versions_listed: 3,
        max_changes_listed: 2,
        ..StoreLimits::default()
    })
    .unwrap()
}

fn limit_name<T: std::fmt::Debug>(r: Result<T, StoreError>) -> (&'static str, u64, u64) {
    match r {
        Err(StoreError::Limit { name, limit, got }) => (name, limit, got),
        other => panic!("expected a limit, got {other:?}"),
    }
}

#[test]
fn limits_are_refused_by_name() {
    let s = small();
    let id = create(&s, "ada", "m", "0123456789").model.id;
    let new = |name: &str, source: &str, params: Vec<f64>, message: &str| CreateModel {
        name: name.into(),
        source: source.into(),
        params,
        message: message.into(),
    };
    assert_eq!(
        limit_name(s.create_model("ada", new("m", "01234567890", vec![], ""))),
        ("max_source_bytes", 10, 11)
    );
    assert_eq!(
        limit_name(s.create_model("ada", new("sixsix", "s", vec![], ""))),
        ("max_name_chars", 5, 6)
    );
    assert_eq!(
        limit_name(s.create_model("ada", new("m", "s", vec![1.0; 3], ""))),
        ("max_params", 2, 3)
    );
    assert_eq!(
        limit_name(s.create_model("ada", new("m", "s", vec![], "123456789"))),
        ("max_message_chars", 8, 9)
    );
    assert_eq!(
        limit_name(s.create_model("adalb", new("m", "s", vec![], ""))),
        ("max_user_chars", 4, 5)
    );
    assert_eq!(
        limit_name(s.put_asset(b"12345", "text/plain")),
        ("max_asset_bytes", 4, 5)
    );
    let a = s.put_asset(b"1", "text/plain").unwrap();
    let b = s.put_asset(b"2", "text/plain").unwrap();
    let two = NewVersion {
        source: "s".into(),
        assets: vec![
            AssetLink {
                name: "a".into(),
                hash: a.hash,
            },
            AssetLink {
                name: "b".into(),
                hash: b.hash,
            },
        ],
        ..NewVersion::default()
    };
    assert_eq!(
        limit_name(s.save_version(&id, "ada", two)),
        ("max_assets_per_version", 1, 2)
    );
    for i in 0..4 {
        s.save_version(&id, "ada", edit(&i.to_string())).unwrap();
    }
    assert_eq!(s.history(&id, HistoryPage::default()).unwrap().len(), 3);
    let too_many = HistoryPage {
        before: None,
        limit: Some(4),
    };
    assert_eq!(
        limit_name(s.history(&id, too_many)),
        ("max_versions_listed", 3, 4)
    );
    assert_eq!(s.changes(&id, 0, None).unwrap().len(), 2);
    assert_eq!(
        limit_name(s.changes(&id, 0, Some(3))),
        ("max_changes_listed", 2, 3)
    );
    assert_eq!(
        limit_name(s.changes_since(0, Some(3))),
        ("max_changes_listed", 2, 3)
    );
    // Only the model and its five versions were written.
    assert_eq!(s.list_models().unwrap().len(), 1);
    assert_eq!(s.get_model(&id).unwrap().model.latest, 5);
}
