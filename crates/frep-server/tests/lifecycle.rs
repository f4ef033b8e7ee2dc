//! The server's life: examples seeded once, committed writes surviving a
//! restart, the HTML page without a studio, the studio when built.

mod harness;

use frep_wire::{ModelDetail, ModelSummary, SaveVersion, Version};
use harness::{config, Server, SPHERE};
use reqwest::StatusCode;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn committed_saves_survive_a_restart_and_examples_are_seeded_once() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    let examples = frep_server::examples::EXAMPLES;
    assert_eq!(list.len(), examples.len());
    assert!(list.iter().all(|m| m.owner == "examples"));
    let sake = list.iter().find(|m| m.name == "sake_pot").unwrap();
    let detail: ModelDetail = s.get_json(&format!("/api/models/{}", sake.id)).await;
    assert!(detail.version.source.contains("sake"));

    let id = s.create("kept", SPHERE).await.model.id;
    let v2: Version = s
        .post_json(
            &format!("/api/models/{id}/versions"),
            &SaveVersion {
                source: "-- saved before the restart\n".into(),
                params: vec![0.5],
                message: "v2".into(),
                base: Some(1),
                assets: vec![],
            },
        )
        .await;
    assert_eq!(v2.number, 2);
    s.stop().await;

    let s = Server::start(config(dir.path())).await;
    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    assert_eq!(list.len(), examples.len() + 1, "examples not seeded twice");
    let back: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert_eq!(back.version.number, 2);
    assert_eq!(back.version.source, "-- saved before the restart\n");
    assert_eq!(back.version.params, [0.5]);

    // Deleted examples stay deleted across a restart.
    let r = s
        .client
        .delete(s.url(&format!("/api/models/{}", sake.id)))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::NO_CONTENT);
    s.stop().await;
    let s = Server::start(config(dir.path())).await;
    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    assert_eq!(list.len(), examples.len());
    assert!(!list.iter().any(|m| m.name == "sake_pot"));
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn without_a_studio_the_page_lists_models_with_images_and_downloads() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(&dir.path().join("data"))).await;
    s.create("a <b> & c", SPHERE).await;
    let r = s.client.get(s.url("/")).send().await.unwrap();
    assert_eq!(r.status(), StatusCode::OK);
    assert!(r.headers()["content-type"]
        .to_str()
        .unwrap()
        .starts_with("text/html"));
    let html = r.text().await.unwrap();
    assert!(html.contains("a &lt;b&gt; &amp; c"), "names are escaped");
    for (name, _) in frep_server::examples::EXAMPLES {
        assert!(html.contains(&format!("<h2>{name}</h2>")), "{name} listed");
    }
    // Every image and download link is a registered artefact URL.
    let links: Vec<&str> = html
        .split("\"/api/artefacts/")
        .skip(1)
        .map(|rest| &rest[..rest.find('"').unwrap()])
        .collect();
    let imgs = links.iter().filter(|l| l.ends_with(".jpg")).count();
    assert_eq!(imgs, frep_server::examples::EXAMPLES.len() + 1);
    for ext in [".stl?", ".obj?", ".ply?", ".glb?", ".3mf?"] {
        assert!(links.iter().any(|l| l.contains(ext)), "{ext} download");
    }
    // The test sphere's image is real: fetch it.
    let sphere_img = html
        .split("<article>")
        .find(|a| a.contains("a &lt;b&gt; &amp; c"))
        .and_then(|a| a.split("src=\"").nth(1))
        .map(|rest| rest[..rest.find('"').unwrap()].to_string())
        .unwrap();
    let r = s.client.get(s.url(&sphere_img)).send().await.unwrap();
    assert_eq!(r.status(), StatusCode::OK);
    let jpeg = r.bytes().await.unwrap();
    assert_eq!(&jpeg[..2], &[0xFF, 0xD8], "JPEG start of image");
    let r = s.client.get(s.url("/nothing-here")).send().await.unwrap();
    assert_eq!(r.status(), StatusCode::NOT_FOUND);
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_built_studio_is_served_with_an_index_fallback() {
    let dir = tempfile::tempdir().unwrap();
    let studio = dir.path().join("dist");
    std::fs::create_dir_all(studio.join("assets")).unwrap();
    std::fs::write(
        studio.join("index.html"),
        "<!doctype html><title>studio</title>",
    )
    .unwrap();
    std::fs::write(studio.join("assets/app.js"), "console.log('frep');").unwrap();
    // What the build writes beside it (web/build/precompress.ts); the server
    // sends it as it is, so distinct bytes show which file was sent.
    std::fs::write(studio.join("assets/app.js.br"), b"brotli bytes").unwrap();
    let mut c = config(&dir.path().join("data"));
    c.static_dir = Some(studio);
    let s = Server::start(c).await;
    let get = |p: &str| s.client.get(s.url(p)).send();
    let r = get("/").await.unwrap();
    assert_eq!(r.headers()["cache-control"], "no-cache");
    assert!(r.text().await.unwrap().contains("<title>studio</title>"));
    // Built assets have hashed names: immutable.
    let r = get("/assets/app.js").await.unwrap();
    assert!(r.headers()["cache-control"]
        .to_str()
        .unwrap()
        .contains("immutable"));
    assert_eq!(r.text().await.unwrap(), "console.log('frep');");
    let r = s
        .client
        .get(s.url("/assets/app.js"))
        .header("accept-encoding", "gzip, br")
        .send()
        .await
        .unwrap();
    assert_eq!(r.headers()["content-encoding"], "br");
    assert!(r.headers()["content-type"]
        .to_str()
        .unwrap()
        .contains("javascript"));
    assert_eq!(&r.bytes().await.unwrap()[..], b"brotli bytes");
    // No .gz beside it: a gzip-only client gets the plain file.
    let r = s
        .client
        .get(s.url("/assets/app.js"))
        .header("accept-encoding", "gzip")
        .send()
        .await
        .unwrap();
    assert!(r.headers().get("content-encoding").is_none());
    assert_eq!(r.text().await.unwrap(), "console.log('frep');");
    let r = get("/assets/missing.js").await.unwrap();
    assert_eq!(r.status(), StatusCode::NOT_FOUND);
    assert!(r.headers().get("cache-control").is_none());
    // A client-side route gets the studio's page.
    let r = get("/models/abc").await.unwrap();
    assert!(r.text().await.unwrap().contains("<title>studio</title>"));
    // The API stays the API.
    let r = get("/api/nothing").await.unwrap();
    assert_eq!(r.status(), StatusCode::NOT_FOUND);
    assert!(r.text().await.unwrap().contains("not_found"));
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn shutdown_cancels_a_running_job_and_returns() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    // No grace: a job still running at shutdown is cancelled at once.
    c.shutdown_grace_ms = 0;
    c.limits.mesh_max_depth = 9;
    let s = Server::start(c).await;
    let gyroid = frep_server::examples::EXAMPLES
        .iter()
        .find(|(n, _)| *n == "m3_gyroid")
        .unwrap()
        .1;
    let r: frep_wire::ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &frep_wire::ArtefactRequest {
                model: frep_wire::ModelRef::Source {
                    source: gyroid.into(),
                },
                params: vec![],
                spec: frep_wire::ArtefactSpec::Mesh { depth: 9 },
            },
        )
        .await;
    let client = s.client.clone();
    let url = s.url(&r.url);
    let waiting = tokio::spawn(async move { client.get(url).send().await });
    // Wait until the job runs (health counts it).
    loop {
        let h: serde_json::Value = s.get_json("/api/health").await;
        if h["jobs"].as_u64().unwrap() > 0 {
            break;
        }
        tokio::time::sleep(std::time::Duration::from_millis(5)).await;
    }
    // Stopping returns (run() completes) although the job was long.
    s.stop().await;
    let outcome = waiting.await.unwrap();
    eprintln!(
        "request at shutdown: {:?}",
        outcome.as_ref().map(|r| r.status())
    );
    match outcome {
        // The usual case: the request was answered "cancelled".
        Ok(resp) if resp.status() == StatusCode::SERVICE_UNAVAILABLE => {
            let e: frep_wire::ApiError = resp.json().await.unwrap();
            assert_eq!(e.code, "cancelled");
        }
        // The job may have finished just before the stop.
        Ok(resp) => assert_eq!(resp.status(), StatusCode::OK),
        // Or the connection closed with the server.
        Err(e) => assert!(e.is_request() || e.is_connect() || e.is_body(), "{e}"),
    }
    // The data folder is intact: a new server opens it.
    let s = Server::start(config(dir.path())).await;
    let list: Vec<ModelSummary> = s.get_json("/api/models").await;
    assert_eq!(list.len(), frep_server::examples::EXAMPLES.len());
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_acknowledged_save_survives_a_shutdown_in_the_middle() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let id = s.create("busy", SPHERE).await.model.id;
    let url = s.url(&format!("/api/models/{id}/versions"));
    let saves: Vec<_> = (0..16)
        .map(|i| {
            let (client, url) = (s.client.clone(), url.clone());
            tokio::spawn(async move {
                let body = SaveVersion {
                    source: format!("-- save {i}\n"),
                    params: vec![],
                    message: format!("save {i}"),
                    base: None,
                    assets: vec![],
                };
                let r = client.post(url).json(&body).send().await.ok()?;
                (r.status() == StatusCode::CREATED).then_some(())?;
                r.json::<Version>().await.ok()
            })
        })
        .collect();
    // Stop while the saves are on their way.
    s.stop().await;
    let mut acknowledged = Vec::new();
    for t in saves {
        if let Some(v) = t.await.unwrap() {
            acknowledged.push(v);
        }
    }
    let s = Server::start(config(dir.path())).await;
    for v in &acknowledged {
        let back: Version = s
            .get_json(&format!("/api/models/{id}/versions/{}", v.number))
            .await;
        assert_eq!(back.source, v.source, "acknowledged save {} kept", v.number);
    }
    // Versions are numbered without gaps, whatever got through.
    let latest: ModelDetail = s.get_json(&format!("/api/models/{id}")).await;
    assert!(latest.model.latest as usize > acknowledged.len());
    for n in 1..=latest.model.latest {
        let _: Version = s.get_json(&format!("/api/models/{id}/versions/{n}")).await;
    }
    s.stop().await;
}
