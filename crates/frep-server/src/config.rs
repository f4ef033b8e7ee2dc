//! The server's configuration, read once into typed structs.
//!
//! Three sources, later ones winning: an optional JSON file, the
//! environment (`FREP_*`), and the command line's flags (applied by the
//! caller on the result). Every field has a default, so an empty file, no
//! environment and no flags give a working local studio.
//!
//! The file is the [`Config`] itself in JSON, snake_case keys, every key
//! optional, e.g. `{"addr": "0.0.0.0:8080", "limits": {"source_bytes": 65536}}`.
//! The sessions' limits and timers are under `session`.
//! The environment names are `FREP_ADDR`, `FREP_DATA`, `FREP_OPEN_ACCESS`,
//! `FREP_STATIC_DIR`, `FREP_SHUTDOWN_GRACE_MS` and one `FREP_LIMIT_<NAME>`
//! per limit (`FREP_LIMIT_SOURCE_BYTES`, …). The limits' names are also what
//! an [`frep_wire::ApiError`]'s `limit` field says, so a refused client can
//! be told which setting to raise.
//!
//! Environment overrides are applied generically:
//! 1. the configuration is turned into a JSON object;
//! 2. each variable that names one of its keys replaces that key's value,
//!    parsed as JSON when it parses, else taken as a string;
//! 3. the object is read back.
//!
//! So a new limit needs no new code here, and a bad value is refused with
//! the variable's name.

use std::net::SocketAddr;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// Everything the server needs to know at start.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Config {
    /// Where to listen (the CLI binds it; [`crate::run`] takes a listener).
    pub addr: SocketAddr,
    /// Folder of the database (`frep.sqlite`) and the artefact cache
    /// (`cache/`); created on first start.
    pub data_dir: PathBuf,
    /// Anyone may edit any model (the local studio). When false, a write
    /// needs the store's permission for the user (the owner).
    pub open_access: bool,
    /// The built studio (`web/dist`), served at `/`; `None` or a missing
    /// folder: the server's own HTML list of models.
    pub static_dir: Option<PathBuf>,
    /// How long shutdown waits for running artefact jobs before cancelling
    /// them, ms.
    pub shutdown_grace_ms: u64,
    /// Every resource limit.
    pub limits: Limits,
    /// Limits and timers of the WebSocket sessions.
    pub session: crate::session::SessionConfig,
}

impl Default for Config {
    fn default() -> Self {
        Config {
            addr: SocketAddr::from(([127, 0, 0, 1], 8080)),
            data_dir: PathBuf::from("frep-data"),
            open_access: true,
            static_dir: Some(PathBuf::from("web/dist")),
            shutdown_grace_ms: 5_000,
            limits: Limits::default(),
            session: crate::session::SessionConfig::default(),
        }
    }
}

/// Every resource limit of the server, by the name a refusal reports.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Limits {
    /// Largest request body, bytes (JSON and asset uploads).
    pub request_bytes: usize,
    /// Largest HyperFun source, bytes.
    pub source_bytes: usize,
    /// Largest expression graph of a compile, nodes.
    pub compile_nodes: usize,
    /// Statements executed and calls inlined by one compile.
    pub compile_steps: usize,
    /// Loop iterations executed by one compile.
    pub compile_iterations: usize,
    /// Most parameter values in a request.
    pub params: usize,
    /// Largest image or view, pixels.
    pub image_max_pixels: u64,
    /// Largest image side, pixels.
    pub image_max_side: u32,
    /// Most views in a view set.
    pub views_max: u32,
    /// Largest view set sprite sheet, pixels in all.
    pub sheet_max_pixels: u64,
    /// Deepest octree of a viewer mesh.
    pub mesh_max_depth: u8,
    /// Deepest octree of an export.
    pub export_max_depth: u8,
    /// Most triangles of a mesh or export.
    pub triangles_max: usize,
    /// Most samples per axis of a volume.
    pub volume_max_grid: u32,
    /// Artefact computations one client (peer address) may have running.
    pub jobs_per_client: usize,
    /// Artefact computations at once on the server.
    pub workers: usize,
    /// Artefact computations waiting for a worker; more are refused (503).
    pub queue: usize,
    /// Size of the artefact disk cache, bytes.
    pub cache_bytes: u64,
    /// Largest uploaded asset, bytes.
    pub asset_bytes: usize,
    /// Models listed on the server's HTML page.
    pub page_models: usize,
    /// Compiled models kept in memory.
    pub compile_cache: usize,
    /// Spare image buffers kept for the next renders, bytes (artefact
    /// workers and frame workers together); `0` keeps none.
    pub image_pool_bytes: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            request_bytes: 8 << 20,
            source_bytes: 1 << 20,
            compile_nodes: 1_000_000,
            compile_steps: 20_000_000,
            compile_iterations: 1_000_000,
            params: 256,
            image_max_pixels: 2048 * 2048,
            image_max_side: 4096,
            views_max: 144,
            sheet_max_pixels: 16_384 * 16_384,
            mesh_max_depth: 9,
            export_max_depth: 10,
            triangles_max: 20_000_000,
            volume_max_grid: 256,
            jobs_per_client: 8,
            workers: 2,
            queue: 64,
            cache_bytes: 1 << 30,
            asset_bytes: 4 << 20,
            page_models: 200,
            compile_cache: 256,
            image_pool_bytes: 64 << 20,
        }
    }
}

/// A configuration that could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ConfigError {
    /// The file could not be read.
    #[error("cannot read {path}: {source}")]
    Read {
        /// The file.
        path: PathBuf,
        /// Why.
        source: std::io::Error,
    },
    /// The file, or the configuration after the environment, is not a valid
    /// configuration.
    #[error("{origin}: {message}")]
    Invalid {
        /// The file's path, or the environment variable's name.
        origin: String,
        /// What is wrong.
        message: String,
    },
}

impl Config {
    /// Reads the configuration: defaults, then `file` (if given), then the
    /// process environment.
    pub fn load(file: Option<&Path>) -> Result<Config, ConfigError> {
        Config::load_from(file, |name| std::env::var(name).ok())
    }

    /// [`Config::load`] with the environment given as a lookup (tests).
    pub fn load_from(
        file: Option<&Path>,
        env: impl Fn(&str) -> Option<String>,
    ) -> Result<Config, ConfigError> {
        let config = match file {
            Some(path) => {
                let text = std::fs::read_to_string(path).map_err(|source| ConfigError::Read {
                    path: path.to_path_buf(),
                    source,
                })?;
                serde_json::from_str(&text).map_err(|e| ConfigError::Invalid {
                    origin: path.display().to_string(),
                    message: e.to_string(),
                })?
            }
            None => Config::default(),
        };
        config.with_env(env)
    }

    /// This configuration with the environment's `FREP_*` variables applied.
    pub fn with_env(self, env: impl Fn(&str) -> Option<String>) -> Result<Config, ConfigError> {
        let invalid = |origin: &str, e: serde_json::Error| ConfigError::Invalid {
            origin: origin.to_string(),
            message: e.to_string(),
        };
        let mut value = serde_json::to_value(&self).map_err(|e| invalid("configuration", e))?;
        let mut applied = Vec::new();
        if let Some(object) = value.as_object_mut() {
            for (var, key) in [
                ("FREP_ADDR", "addr"),
                ("FREP_DATA", "data_dir"),
                ("FREP_OPEN_ACCESS", "open_access"),
                ("FREP_STATIC_DIR", "static_dir"),
                ("FREP_SHUTDOWN_GRACE_MS", "shutdown_grace_ms"),
            ] {
                if let Some(text) = env(var) {
                    object.insert(key.to_string(), env_value(&text));
                    applied.push(var.to_string());
                }
            }
            if let Some(limits) = object.get_mut("limits").and_then(|l| l.as_object_mut()) {
                for (key, slot) in limits.iter_mut() {
                    let var = format!("FREP_LIMIT_{}", key.to_ascii_uppercase());
                    if let Some(text) = env(&var) {
                        *slot = env_value(&text);
                        applied.push(var);
                    }
                }
            }
        }
        serde_json::from_value(value).map_err(|e| ConfigError::Invalid {
            origin: if applied.is_empty() {
                "configuration".to_string()
            } else {
                format!("environment ({})", applied.join(", "))
            },
            message: e.to_string(),
        })
    }

    /// The SQLite database's path.
    pub fn database_path(&self) -> PathBuf {
        self.data_dir.join("frep.sqlite")
    }

    /// The artefact cache's folder.
    pub fn cache_dir(&self) -> PathBuf {
        self.data_dir.join("cache")
    }

    /// The store's limits (the ones the server also checks come from
    /// [`Limits`]; the rest are the store's defaults).
    pub fn store_limits(&self) -> frep_store::StoreLimits {
        frep_store::StoreLimits {
            max_source_bytes: self.limits.source_bytes,
            max_params: self.limits.params,
            max_asset_bytes: self.limits.asset_bytes,
            ..frep_store::StoreLimits::default()
        }
    }

    /// The compile limits of the artefact service.
    pub fn compile_limits(&self) -> frep_artefact::CompileLimits {
        let l = &self.limits;
        frep_artefact::CompileLimits {
            max_source_bytes: l.source_bytes,
            max_nodes: l.compile_nodes,
            max_steps: l.compile_steps,
            max_iterations: l.compile_iterations,
            max_params: l.params,
        }
    }

    /// The artefact service's configuration.
    pub fn artefact_config(&self) -> frep_artefact::ArtefactConfig {
        let l = &self.limits;
        let mut c = frep_artefact::ArtefactConfig::new(self.cache_dir());
        c.cache_max_bytes = l.cache_bytes;
        c.workers = l.workers.max(1);
        c.queue_max = l.queue;
        c.image_pool_bytes = l.image_pool_bytes;
        c.limits = frep_artefact::ArtefactLimits {
            max_image_pixels: l.image_max_pixels,
            max_image_side: l.image_max_side,
            max_views: l.views_max,
            max_sheet_pixels: l.sheet_max_pixels,
            max_mesh_depth: l.mesh_max_depth,
            max_export_depth: l.export_max_depth,
            max_triangles: l.triangles_max,
            max_volume_grid: l.volume_max_grid,
            max_params: l.params,
        };
        c
    }

    /// The built studio's folder, when it exists (with an `index.html`).
    pub fn studio_dir(&self) -> Option<&Path> {
        self.static_dir
            .as_deref()
            .filter(|d| d.join("index.html").is_file())
    }
}

/// An environment value as JSON: numbers and booleans as such, anything
/// else (an address, a path) as a string.
fn env_value(text: &str) -> serde_json::Value {
    match serde_json::from_str::<serde_json::Value>(text.trim()) {
        Ok(v @ (serde_json::Value::Number(_) | serde_json::Value::Bool(_))) => v,
        _ => serde_json::Value::String(text.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    fn env(pairs: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> = pairs
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| map.get(k).cloned()
    }

    #[test]
    fn defaults_without_file_or_environment() {
        let c = Config::load_from(None, env(&[])).unwrap();
        assert_eq!(c, Config::default());
        assert!(c.open_access);
        assert_eq!(c.addr.port(), 8080);
    }

    #[test]
    fn file_then_environment_wins() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("frep.json");
        std::fs::write(
            &path,
            r#"{"addr": "127.0.0.1:9000", "open_access": false,
                "limits": {"source_bytes": 1000, "workers": 3}}"#,
        )
        .unwrap();
        let c = Config::load_from(
            Some(&path),
            env(&[
                ("FREP_LIMIT_SOURCE_BYTES", "2000"),
                ("FREP_DATA", "/tmp/x y"),
            ]),
        )
        .unwrap();
        assert_eq!(c.addr.port(), 9000);
        assert!(!c.open_access);
        assert_eq!(c.limits.source_bytes, 2000, "environment over file");
        assert_eq!(c.limits.workers, 3, "file over default");
        assert_eq!(c.data_dir, PathBuf::from("/tmp/x y"));
        assert_eq!(c.limits.queue, Limits::default().queue);
    }

    #[test]
    fn the_image_pool_is_configured() {
        let c = Config::load_from(None, env(&[])).unwrap();
        assert_eq!(c.artefact_config().image_pool_bytes, 64 << 20);
        let c = Config::load_from(None, env(&[("FREP_LIMIT_IMAGE_POOL_BYTES", "1000")])).unwrap();
        assert_eq!(c.artefact_config().image_pool_bytes, 1000);
    }

    #[test]
    fn bad_values_name_their_origin() {
        let e = Config::load_from(None, env(&[("FREP_LIMIT_WORKERS", "many")])).unwrap_err();
        assert!(e.to_string().contains("FREP_LIMIT_WORKERS"), "{e}");
        let e = Config::load_from(None, env(&[("FREP_ADDR", "nowhere")])).unwrap_err();
        assert!(e.to_string().contains("FREP_ADDR"), "{e}");
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("c.json");
        std::fs::write(&path, r#"{"limits": {"no_such_limit": 1}}"#).unwrap();
        let e = Config::load_from(Some(&path), env(&[])).unwrap_err();
        assert!(e.to_string().contains("no_such_limit"), "{e}");
    }

    #[test]
    fn a_missing_file_is_an_error() {
        let e = Config::load_from(Some(Path::new("/no/such/frep.json")), env(&[])).unwrap_err();
        assert!(matches!(e, ConfigError::Read { .. }));
    }
}
