//! Artefacts over HTTP: content addresses, immutable caching, bytes that
//! decode, exports as attachments, limits named.

mod harness;

use frep_wire::{
    ArtefactRef, ArtefactRequest, ArtefactSpec, CameraView, ExportFormat, ImageEncoding, ModelRef,
    ShaderArtefact,
};
use harness::{api_error, config, ok_json, Server, SPHERE};
use reqwest::StatusCode;

fn from_source(spec: ArtefactSpec) -> ArtefactRequest {
    ArtefactRequest {
        model: ModelRef::Source {
            source: SPHERE.into(),
        },
        params: vec![],
        spec,
    }
}

fn png(width: u32, height: u32) -> ArtefactSpec {
    ArtefactSpec::Image {
        camera: CameraView::default(),
        width,
        height,
        format: ImageEncoding::Png,
        quality: 90,
        section: None,
    }
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn an_image_is_served_immutable_and_revalidated() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let r: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(48, 32)))
        .await;
    assert_eq!(r.media_type, "image/png");
    assert!(
        r.url.starts_with("/api/artefacts/") && r.url.ends_with(".png"),
        "{}",
        r.url
    );
    assert!(!r.ready);
    // The same request gets the same address.
    let again: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(48, 32)))
        .await;
    assert_eq!(again.key, r.key);

    let resp = s.client.get(s.url(&r.url)).send().await.unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    let h = resp.headers().clone();
    assert_eq!(h["content-type"], "image/png");
    assert!(h["cache-control"].to_str().unwrap().contains("immutable"));
    let etag = h["etag"].to_str().unwrap().to_string();
    assert_eq!(etag, format!("\"{}\"", r.key));
    let bytes = resp.bytes().await.unwrap();
    let decoder = png::Decoder::new(std::io::Cursor::new(bytes.to_vec()));
    let reader = decoder.read_info().unwrap();
    assert_eq!((reader.info().width, reader.info().height), (48, 32));

    // A cache revalidation is 304 with no body.
    let resp = s
        .client
        .get(s.url(&r.url))
        .header("if-none-match", &etag)
        .send()
        .await
        .unwrap();
    assert_eq!(resp.status(), StatusCode::NOT_MODIFIED);
    assert!(resp.bytes().await.unwrap().is_empty());
    // Registered again, it is ready (from the disk cache).
    let ready: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(48, 32)))
        .await;
    assert!(ready.ready);
    assert_eq!(ready.bytes, Some(bytes.len() as u64));
    // Images are not compressed again.
    let resp = s
        .client
        .get(s.url(&r.url))
        .header("accept-encoding", "gzip")
        .send()
        .await
        .unwrap();
    assert!(resp.headers().get("content-encoding").is_none());
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn meshes_exports_and_shaders_of_a_stored_version() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    let id = s.create("ball", SPHERE).await.model.id;
    let of_version = |spec| ArtefactRequest {
        model: ModelRef::Version {
            model_id: id.clone(),
            version: None,
        },
        params: vec![0.5],
        spec,
    };

    let mesh: ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &of_version(ArtefactSpec::Mesh { depth: 4 }),
        )
        .await;
    let resp = s.client.get(s.url(&mesh.url)).send().await.unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    let glb = resp.bytes().await.unwrap();
    assert_eq!(&glb[..4], b"glTF");

    let stl: ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &of_version(ArtefactSpec::Export {
                format: ExportFormat::Stl,
                depth: 4,
            }),
        )
        .await;
    assert!(stl.url.ends_with(".stl"));
    let resp = s
        .client
        .get(s.url(&format!("{}?name=my ball", stl.url)))
        .send()
        .await
        .unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    assert_eq!(
        resp.headers()["content-disposition"],
        "attachment; filename=\"my_ball.stl\""
    );
    let body = resp.bytes().await.unwrap();
    // Binary STL: an 80-byte header, a triangle count, 50 bytes per triangle.
    let n = u32::from_le_bytes(body[80..84].try_into().unwrap()) as usize;
    assert!(n > 0);
    assert_eq!(body.len(), 84 + 50 * n);

    let shader: ArtefactRef = s
        .post_json("/api/artefacts", &of_version(ArtefactSpec::Shader))
        .await;
    let sh: ShaderArtefact = ok_json(s.client.get(s.url(&shader.url)).send().await.unwrap()).await;
    assert!(sh.source.contains("#version 300 es"));
    assert_eq!(sh.bounds, [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]);
    assert!(!sh.uniforms.is_empty());

    // Text meshes are compressed when the client accepts it; glb is not
    // (meshopt already).
    let obj: ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &of_version(ArtefactSpec::Export {
                format: ExportFormat::Obj,
                depth: 4,
            }),
        )
        .await;
    for (url, compressed) in [(&obj.url, true), (&mesh.url, false)] {
        let resp = s
            .client
            .get(s.url(url))
            .header("accept-encoding", "gzip")
            .send()
            .await
            .unwrap();
        assert_eq!(resp.status(), StatusCode::OK);
        assert_eq!(
            resp.headers().get("content-encoding").is_some(),
            compressed,
            "{url}"
        );
    }

    // A volume carries its mapping in a header.
    let slices: ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &of_version(ArtefactSpec::Slices { grid: 8 }),
        )
        .await;
    let resp = s.client.get(s.url(&slices.url)).send().await.unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    let layout: frep_wire::VolumeLayout =
        serde_json::from_str(resp.headers()["x-frep-volume"].to_str().unwrap()).unwrap();
    let volume = resp.bytes().await.unwrap();
    let [x, y, z] = layout.dims;
    assert_eq!(volume.len(), (x * y * z) as usize);

    // Another parameter value is another artefact.
    let other: ArtefactRef = s
        .post_json(
            "/api/artefacts",
            &ArtefactRequest {
                params: vec![0.6],
                ..of_version(ArtefactSpec::Mesh { depth: 4 })
            },
        )
        .await;
    assert_ne!(other.key, mesh.key);
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn artefact_limits_and_errors_are_named() {
    let dir = tempfile::tempdir().unwrap();
    let s = Server::start(config(dir.path())).await;
    // config(): image_max_pixels = 512², mesh_max_depth = 7.
    let r = s
        .client
        .post(s.url("/api/artefacts"))
        .json(&from_source(png(1024, 1024)))
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(e.code, "limit");
    assert_eq!(e.limit.as_deref(), Some("image_max_pixels"), "{e:?}");

    let r = s
        .client
        .post(s.url("/api/artefacts"))
        .json(&from_source(ArtefactSpec::Mesh { depth: 12 }))
        .send()
        .await
        .unwrap();
    assert_eq!(
        api_error(r).await.1.limit.as_deref(),
        Some("mesh_max_depth")
    );

    // A model error names line and column.
    let req = ArtefactRequest {
        model: ModelRef::Source {
            source: "my_model(x[3], a[1])\n{\n  my_model = ;\n}\n".into(),
        },
        params: vec![],
        spec: ArtefactSpec::Shader,
    };
    let r = s
        .client
        .post(s.url("/api/artefacts"))
        .json(&req)
        .send()
        .await
        .unwrap();
    let (status, e) = api_error(r).await;
    assert_eq!(status, StatusCode::UNPROCESSABLE_ENTITY);
    assert_eq!(e.code, "model_error");
    assert_eq!(e.diagnostics[0].line, 3);

    // A wrong extension for the key is a wrong URL.
    let shader: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(ArtefactSpec::Shader))
        .await;
    let wrong = shader.url.replace(".json", ".png");
    let r = s.client.get(s.url(&wrong)).send().await.unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::NOT_FOUND);

    // Unknown keys and malformed names are 404.
    let unknown = format!("/api/artefacts/{}.png", "ab".repeat(32));
    let r = s.client.get(s.url(&unknown)).send().await.unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::NOT_FOUND);
    let r = s
        .client
        .get(s.url("/api/artefacts/../../etc/passwd"))
        .send()
        .await
        .unwrap();
    assert_eq!(r.status(), StatusCode::NOT_FOUND);
    // An unknown model.
    let req = ArtefactRequest {
        model: ModelRef::Version {
            model_id: "nope".into(),
            version: None,
        },
        params: vec![],
        spec: ArtefactSpec::Shader,
    };
    let r = s
        .client
        .post(s.url("/api/artefacts"))
        .json(&req)
        .send()
        .await
        .unwrap();
    assert_eq!(api_error(r).await.0, StatusCode::NOT_FOUND);
    s.stop().await;
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn jobs_per_client_is_enforced_for_computations_only() {
    let dir = tempfile::tempdir().unwrap();
    let mut c = config(dir.path());
    c.limits.jobs_per_client = 1;
    let s = Server::start(c).await;
    let r: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(16, 16)))
        .await;
    // One computation at a time is allowed; it completes and is cached.
    let resp = s.client.get(s.url(&r.url)).send().await.unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    s.stop().await;

    // With no job slots, an uncached artefact is refused, naming the
    // limit; a cached one is still served.
    let mut c = config(dir.path());
    c.limits.jobs_per_client = 0;
    let s = Server::start(c).await;
    let cached: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(16, 16)))
        .await;
    assert!(cached.ready);
    let resp = s.client.get(s.url(&cached.url)).send().await.unwrap();
    assert_eq!(resp.status(), StatusCode::OK);
    let other: ArtefactRef = s
        .post_json("/api/artefacts", &from_source(png(16, 24)))
        .await;
    let resp = s.client.get(s.url(&other.url)).send().await.unwrap();
    let (status, e) = api_error(resp).await;
    assert_eq!(status, StatusCode::TOO_MANY_REQUESTS);
    assert_eq!(e.limit.as_deref(), Some("jobs_per_client"));
    s.stop().await;
}
