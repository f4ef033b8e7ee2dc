//! A real server for the HTTP tests: `frep_server::run` on 127.0.0.1:0 with
//! its data in a temporary folder, a reqwest client, and a graceful stop.
#![allow(dead_code)]

use std::path::{Path, PathBuf};

use frep_server::{Config, ServerError};
use frep_wire::{ApiError, CreateModel, ModelDetail};
use reqwest::{Client, Response, StatusCode};
use tokio::sync::oneshot;
use tokio::task::JoinHandle;

/// A small sphere (radius `a[1]`, default 0.8), with its box and a named
/// parameter: cheap to compile, render and mesh.
pub const SPHERE: &str = "-- description: a test sphere
-- bounds: -1,-1,-1,1,1,1
-- param: 1 radius 0.8 0.2 0.95
my_model(x[3], a[1])
{
  array c[3];
  c = [0, 0, 0];
  my_model = hfSphere(x, c, a[1]);
}
";

/// A configuration for tests: data in `dir`, no studio, small limits.
pub fn config(dir: &Path) -> Config {
    let mut c = Config {
        data_dir: dir.to_path_buf(),
        static_dir: None,
        shutdown_grace_ms: 2_000,
        ..Config::default()
    };
    c.limits.image_max_pixels = 512 * 512;
    c.limits.mesh_max_depth = 7;
    c.limits.export_max_depth = 7;
    c
}

/// A running server.
pub struct Server {
    /// `http://127.0.0.1:PORT`.
    pub base: String,
    /// The client.
    pub client: Client,
    /// The data folder.
    pub dir: PathBuf,
    stop: Option<oneshot::Sender<()>>,
    task: Option<JoinHandle<Result<(), ServerError>>>,
}

impl Server {
    /// Starts a server with `config` on a free port.
    pub async fn start(config: Config) -> Server {
        let listener = tokio::net::TcpListener::bind("127.0.0.1:0").await.unwrap();
        let addr = listener.local_addr().unwrap();
        let (tx, rx) = oneshot::channel::<()>();
        let dir = config.data_dir.clone();
        let task = tokio::spawn(frep_server::run(listener, config, async move {
            let _ = rx.await;
        }));
        let server = Server {
            base: format!("http://{addr}"),
            client: Client::new(),
            dir,
            stop: Some(tx),
            task: Some(task),
        };
        // Ready when health answers (the store opens before the listener
        // is served, so this is quick).
        for _ in 0..500 {
            if let Ok(r) = server.client.get(server.url("/api/health")).send().await {
                if r.status().is_success() {
                    return server;
                }
            }
            tokio::time::sleep(std::time::Duration::from_millis(10)).await;
        }
        panic!("the server did not become healthy");
    }

    /// The absolute URL of a path.
    pub fn url(&self, path: &str) -> String {
        format!("{}{path}", self.base)
    }

    /// Stops the server gracefully and waits for `run` to return.
    pub async fn stop(mut self) {
        if let Some(tx) = self.stop.take() {
            let _ = tx.send(());
        }
        if let Some(task) = self.task.take() {
            task.await.unwrap().unwrap();
        }
    }

    /// GET, expecting JSON of type T and a 2xx status.
    pub async fn get_json<T: serde::de::DeserializeOwned>(&self, path: &str) -> T {
        let r = self.client.get(self.url(path)).send().await.unwrap();
        ok_json(r).await
    }

    /// POST JSON, expecting a 2xx JSON answer.
    pub async fn post_json<T: serde::de::DeserializeOwned>(
        &self,
        path: &str,
        body: &impl serde::Serialize,
    ) -> T {
        let r = self
            .client
            .post(self.url(path))
            .json(body)
            .send()
            .await
            .unwrap();
        ok_json(r).await
    }

    /// Creates a model from a source.
    pub async fn create(&self, name: &str, source: &str) -> ModelDetail {
        self.post_json(
            "/api/models",
            &CreateModel {
                name: name.into(),
                source: source.into(),
                params: vec![],
                message: "v1".into(),
            },
        )
        .await
    }
}

/// The body of a 2xx answer as JSON (panics with the body otherwise).
pub async fn ok_json<T: serde::de::DeserializeOwned>(r: Response) -> T {
    let status = r.status();
    let text = r.text().await.unwrap();
    assert!(status.is_success(), "HTTP {status}: {text}");
    serde_json::from_str(&text).unwrap_or_else(|e| panic!("not the JSON expected ({e}): {text}"))
}

/// The `ApiError` of a failed answer, with its status.
pub async fn api_error(r: Response) -> (StatusCode, ApiError) {
    let status = r.status();
    let text = r.text().await.unwrap();
    assert!(
        !status.is_success(),
        "expected a failure, got {status}: {text}"
    );
    let e = serde_json::from_str(&text).unwrap_or_else(|e| panic!("not an ApiError ({e}): {text}"));
    (status, e)
}
