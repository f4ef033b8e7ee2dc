//! The HTTP API end to end: a real server on 127.0.0.1:0 (`frep_server::run`)
//! and a reqwest client. Models, versions, compile, the change log, errors.

mod harness;

use frep_wire::{
    Change, ChangeKind, CompileRequest, CompileResponse, DiffKind, ModelDetail, ModelSummary,
    SaveVersion, SourceDiff, Version, VersionSummary,
};
use harness::{api_error, config, ok_json, Server, SPHERE};
use reqwest::StatusCode;
use serde_json::json;

fn save(source: &str, base: Option<u32>, message: &str) -> SaveVersion {
    SaveVersion {
        source: source.into(),
        params: vec![],
        message: message.into(),
        base,
        assets: vec![],
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn models_are_created_listed_renamed_duplicated_and_deleted() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let created = s.create("ball", SPHERE).await;
    assert_eq!(created.model.name, "ball");
    assert_eq!(created.model.owner, "studio");
    assert_eq!(created.version.number, 1);
    assert_eq!(created.version.source, SPHERE);
    let id = created.model.id.clone();

    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    assert!(list.iter().any(|m| m.id == id && m.name == "ball"));

    let got: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert_eq!(got.version.source, SPHERE);

    let r = s
        .client
        .patch(s.url(&format!("/api/models/{id}")))
        .json(&json!({"name": "big ball"}))
        .send()
        .await
        .unwrap();
    let renamed: ModelSummary = ok_json(r).await;
    assert_eq!(renamed.name, "big ball");

    let copy: ModelDetail = s
        .post_json(
            &format!("/api/models/{id}/duplicate"),
            &json!({"name": "copy"}),
        )
        .await;
    assert_ne!(copy.model.id, id);
    assert_eq!(copy.version.source, SPHERE);

    let r = s
        .client
        .delete(s.url(&format!("/api/models/{id}")))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::NO_CONTENT);
    let r = s
        .client
        .get(s.url(&format!("/api/models/{id}")))
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::NOT_FOUND);
    assert_eq!(e.code, "not_found");
    // The copy lives on.
    let _: ModelDetail = s.get_json(&format!("/api/models/{}", copy.model.id)).await;

    // The log of the deleted model stays readable, in order.
    let log: Vec<Change> = s.get_json(&format!("/api/models/{id}/log")).await;
    let kinds: Vec<ChangeKind> = log.iter().map(|c| c.kind).collect();
    assert_eq!(
        kinds,
        [
            ChangeKind::Created,
            ChangeKind::Renamed,
            ChangeKind::Deleted
        ]
    );
    assert_eq!(log.iter().map(|c| c.seq).collect::<Vec<_>>(), [1, 2, 3]);
    let after: Vec<Change> = s.get_json(&format!("/api/models/{id}/log?after=2")).await;
    assert_eq!(after.len(), 1);
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn versions_history_diff_and_restore() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let id = s.create("ball", SPHERE).await.model.id;
    let v2_source = SPHERE.replace("c = [0, 0, 0];", "c = [0, 0, 0.1];");
    let v2: Version = s
        .post_json(
            &format!("/api/models/{id}/versions"),
            &save(&v2_source, Some(1), "up"),
        )
        .await;
    assert_eq!(v2.number, 2);
    assert_eq!(v2.author, "studio");
    let v3_source = format!("{v2_source}-- end\n");
    let v3: Version = s
        .post_json(
            &format!("/api/models/{id}/versions"),
            &save(&v3_source, None, "end"),
        )
        .await;
    assert_eq!(v3.number, 3);

    let history: Vec<VersionSummary> = s.get_json(&format!("/api/models/{id}/versions")).await;
    let mut numbers: Vec<u32> = history.iter().map(|v| v.number).collect();
    numbers.sort();
    assert_eq!(numbers, [1, 2, 3]);
    assert!(history.iter().any(|v| v.number == 2 && v.message == "up"));

    let diff: SourceDiff = s
        .get_json(&format!("/api/models/{id}/diff?from=1&to=3"))
        .await;
    assert_eq!((diff.from, diff.to), (1, 3));
    let removed: Vec<&str> = diff
        .lines
        .iter()
        .filter(|l| l.kind == DiffKind::Removed)
        .map(|l| l.text.as_str())
        .collect();
    let added: Vec<&str> = diff
        .lines
        .iter()
        .filter(|l| l.kind == DiffKind::Added)
        .map(|l| l.text.as_str())
        .collect();
    assert_eq!(removed, ["  c = [0, 0, 0];"]);
    assert_eq!(added, ["  c = [0, 0, 0.1];", "-- end"]);

    let restored: Version = s
        .post_json(&format!("/api/models/{id}/restore"), &json!({"version": 1}))
        .await;
    assert_eq!(restored.number, 4);
    assert_eq!(restored.restored_from, Some(1));
    let v4: Version = s.get_json(&format!("/api/models/{id}/versions/4")).await;
    assert_eq!(v4.source, SPHERE, "the restore shows the old source");
    let latest: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert_eq!(latest.version.number, 4);
    assert_eq!(latest.model.latest, 4);

    let r = s
        .client
        .get(s.url(&format!("/api/models/{id}/versions/9")))
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::NOT_FOUND);
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stale_base_is_a_conflict_naming_the_latest() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let id = s.create("ball", SPHERE).await.model.id;
    let url = s.url(&format!("/api/models/{id}/versions"));
    // Two editors start from version 1; the first saves.
    let _: Version = ok_json(
        s.client
            .post(&url)
            .json(&save("-- a\n", Some(1), "a"))
            .send()
            .await
            .unwrap(),
    )
    .await;
    let r = s
        .client
        .post(&url)
        .json(&save("-- b\n", Some(1), "b"))
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::CONFLICT);
    assert_eq!(e.code, "conflict");
    assert_eq!(e.latest, Some(2));
    // Nothing was written by the refused save.
    let latest: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert_eq!(latest.version.number, 2);
    assert_eq!(latest.version.source, "-- a\n");
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn compile_gives_diagnostics_or_a_summary() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let bad = "my_model(x[3], a[1])\n{\n  my_model = 1 - x[1] * ;\n}\n";
    let r: CompileResponse = s
        .post_json(
            "/api/compile",
            &CompileRequest {
                source: bad.into(),
                params: vec![],
                body: None,
            },
        )
        .await;
    assert!(!r.ok);
    assert!(r.summary.is_none());
    let d = &r.diagnostics[0];
    assert_eq!(d.line, 3, "{d:?}");
    assert!(d.column > 1, "{d:?}");
    assert!(d.rendered.contains('^'), "{}", d.rendered);
    assert!(
        d.rendered.contains("my_model = 1 - x[1] * ;"),
        "{}",
        d.rendered
    );

    let ok: CompileResponse = s
        .post_json(
            "/api/compile",
            &CompileRequest {
                source: SPHERE.into(),
                params: vec![],
                body: None,
            },
        )
        .await;
    assert!(ok.ok, "{:?}", ok.diagnostics);
    let sum = ok.summary.unwrap();
    assert_eq!(sum.body, "my_model");
    assert!(sum.nodes > 0);
    assert_eq!(sum.params.len(), 1);
    assert_eq!(sum.params[0].name, "radius");
    assert_eq!(sum.params[0].default, 0.8);
    assert_eq!((sum.params[0].min, sum.params[0].max), (0.2, 0.95));
    assert_eq!(sum.bounds, [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]);
    assert_eq!(sum.bounds_origin, "comment");
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_input_gets_a_clear_json_error() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    c.limits.source_bytes = 4000;
    c.limits.request_bytes = 20_000;
    let s = Server::start(c).await;

    // Malformed JSON.
    let r = s
        .client
        .post(s.url("/api/models"))
        .header("content-type", "application/json")
        .body("{\"name\": ")
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::BAD_REQUEST);
    assert_eq!(e.code, "bad_request");

    // A source over source_bytes, at create, save and compile.
    let big = format!("{SPHERE}{}", "-- padding\n".repeat(400));
    for (path, body) in [
        ("/api/models", json!({"name": "big", "source": big})),
        ("/api/compile", json!({"source": big})),
    ] {
        let r = s.client.post(s.url(path)).json(&body).send().await.unwrap();
        let (status, e) = api_error(r).await;
        assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE, "{path}");
        assert_eq!(e.code, "limit");
        assert_eq!(e.limit.as_deref(), Some("source_bytes"), "{path}");
    }

    // A body over request_bytes.
    let huge = "x".repeat(30_000);
    let r = s
        .client
        .post(s.url("/api/compile"))
        .json(&json!({"source": huge}))
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    assert_eq!(e.limit.as_deref(), Some("request_bytes"));

    // A known route with another method is a JSON 405.
    let r = s.client.put(s.url("/api/models")).send().await.unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::METHOD_NOT_ALLOWED);
    assert_eq!(e.code, "method_not_allowed");

    // Unknown routes and models are JSON 404s; an empty name is refused.
    let r = s.client.get(s.url("/api/nothing")).send().await.unwrap();
    assert_eq!(api_error(r).await.1.code, "not_found");
    let r = s
        .client
        .post(s.url("/api/models"))
        .json(&json!({"name": " ", "source": SPHERE}))
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::BAD_REQUEST);
    let r = s
        .client
        .get(s.url("/api/models/x/diff?from=a&to=2"))
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::BAD_REQUEST);

    // The server is still up and the store intact.
    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    assert_eq!(list.len(), frep_server::examples::EXAMPLES.len());
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn writes_need_the_owner_unless_access_is_open() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    c.open_access = false;
    let s = Server::start(c).await;
    let r = s
        .client
        .post(s.url("/api/models"))
        .header("x-frep-user", "ada")
        .json(&json!({"name": "ada's", "source": SPHERE}))
        .send()
        .await
        .unwrap();
    let m: ModelDetail = ok_json(r).await;
    assert_eq!(m.model.owner, "ada");
    let url = s.url(&format!("/api/models/{}/versions", m.model.id));
    let r = s
        .client
        .post(&url)
        .header("x-frep-user", "bob")
        .json(&save("-- bob\n", None, "mine now"))
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::FORBIDDEN);
    assert_eq!(e.code, "forbidden");
    let r = s
        .client
        .delete(s.url(&format!("/api/models/{}", m.model.id)))
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::FORBIDDEN);
    // The owner may; bob may still read and duplicate.
    let r = s
        .client
        .post(&url)
        .header("x-frep-user", "ada")
        .json(&save("-- ada\n", None, "v2"))
        .send()
        .await
        .unwrap();
    let v: Version = ok_json(r).await;
    assert_eq!((v.number, v.author.as_str()), (2, "ada"));
    let r = s
        .client
        .post(s.url(&format!("/api/models/{}/duplicate", m.model.id)))
        .header("x-frep-user", "bob")
        .json(&json!({"name": "bob's"}))
        .send()
        .await
        .unwrap();
    let copy: ModelDetail = ok_json(r).await;
    assert_eq!(copy.model.owner, "bob");
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn openapi_lists_the_routes_and_schemas() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let r = s
        .client
        .get(s.url("/api/openapi.json"))
        .send()
        .await
        .unwrap();
    assert_eq!(r.headers()["content-type"], "application/json");
    let doc: serde_json::Value = ok_json(r).await;
    let paths = doc["paths"].as_object().unwrap();
    for p in [
        "/api/models",
        "/api/models/{id}",
        "/api/models/{id}/versions",
        "/api/models/{id}/versions/{n}",
        "/api/models/{id}/diff",
        "/api/models/{id}/restore",
        "/api/models/{id}/duplicate",
        "/api/models/{id}/log",
        "/api/compile",
        "/api/artefacts",
        "/api/artefacts/{file}",
        "/api/assets",
        "/api/assets/{hash}",
        "/api/health",
    ] {
        assert!(
            paths.contains_key(p),
            "{p} missing from the OpenAPI document"
        );
    }
    assert!(paths["/api/models"]["post"].is_object());
    let schemas = doc["components"]["schemas"].as_object().unwrap();
    for t in [
        "ApiError",
        "ModelDetail",
        "ArtefactRequest",
        "CompileResponse",
        "ArtefactSpec",
    ] {
        assert!(schemas.contains_key(t), "schema {t} missing");
    }
    // Compressed when asked: the document is large text.
    let r = s
        .client
        .get(s.url("/api/openapi.json"))
        .header("accept-encoding", "gzip")
        .send()
        .await
        .unwrap();
    assert_eq!(r.headers()["content-encoding"], "gzip");
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn assets_are_stored_by_content() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let body = b"solid x\nendsolid x\n".to_vec();
    let r = s
        .client
        .post(s.url("/api/assets?name=part.stl"))
        .header("content-type", "model/stl")
        .body(body.clone())
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::CREATED);
    let a: frep_wire::AssetRef = ok_json(r).await;
    assert_eq!(a.hash, blake3::hash(&body).to_hex().to_string());
    assert_eq!(
        (a.size, a.media_type.as_str(), a.name.as_str()),
        (body.len() as u64, "model/stl", "part.stl")
    );
    let r = s
        .client
        .get(s.url(&format!("/api/assets/{}", a.hash)))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::OK);
    assert_eq!(r.headers()["content-type"], "model/stl");
    assert!(r.headers()["cache-control"]
        .to_str()
        .unwrap()
        .contains("immutable"));
    assert_eq!(r.bytes().await.unwrap().to_vec(), body);
    let missing = "0".repeat(64);
    let r = s
        .client
        .get(s.url(&format!("/api/assets/{missing}")))
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::NOT_FOUND);
    s.stop().await;

    // An upload over asset_bytes is refused, naming the limit.
    let mut c = config(dir.path());
    c.limits.asset_bytes = 100;
    let s = Server::start(c).await;
    let r = s
        .client
        .post(s.url("/api/assets?name=big.bin"))
        .body(vec![7u8; 200])
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::PAYLOAD_TOO_LARGE);
    assert_eq!(e.limit.as_deref(), Some("asset_bytes"));
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn compile_limits_come_back_as_diagnostics() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    c.limits.compile_iterations = 10;
    let s = Server::start(c).await;
    let looping = "my_model(x[3], a[1])\n{\n  i = 0;\n  while i < 100 loop\n    i = i + 1;\n  endloop;\n  my_model = 1 - x[1] * i;\n}\n";
    let r: CompileResponse = s
        .post_json(
            "/api/compile",
            &CompileRequest {
                source: looping.into(),
                params: vec![],
                body: None,
            },
        )
        .await;
    assert!(!r.ok);
    let d = &r.diagnostics[0];
    assert!(d.line >= 1 && d.column >= 1, "{d:?}");
    assert!(!d.message.is_empty());
    // Under the default limits the same model compiles.
    let dir2 = tempfile::tempdir().unwrap();
    let s2 = Server::start(config(dir2.path())).await;
    let r: CompileResponse = s2
        .post_json(
            "/api/compile",
            &CompileRequest {
                source: looping.into(),
                params: vec![],
                body: None,
            },
        )
        .await;
    assert!(r.ok, "{:?}", r.diagnostics);
    s.stop().await;
    s2.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn concurrent_saves_from_one_base_let_exactly_one_through() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let id = s.create("contested", SPHERE).await.model.id;
    let url = s.url(&format!("/api/models/{id}/versions"));
    let tasks: Vec<_> = (0..12)
        .map(|i| {
            let (client, url) = (s.client.clone(), url.clone());
            tokio::spawn(async move {
                client
                    .post(url)
                    .json(&save(&format!("-- editor {i}\n"), Some(1), "race"))
                    .send()
                    .await
                    .unwrap()
                    .status()
            })
        })
        .collect();
    let mut created = 0;
    for t in tasks {
        match t.await.unwrap() {
            StatusCode::CREATED => created += 1,
            StatusCode::CONFLICT => {}
            other => panic!("unexpected {other}"),
        }
    }
    assert_eq!(created, 1);
    let latest: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert_eq!(latest.version.number, 2);
    s.stop().await;
}
