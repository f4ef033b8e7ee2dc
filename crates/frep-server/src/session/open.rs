//! Opening a model in a session.
//!
//! `open` names a stored version (`modelId`, `version`) or carries a
//! source (unsaved, or edited on top of `modelId`), with parameter values.
//! - The source is compiled off the async threads, through the server's
//!   compile cache.
//! - It is compiled at its default parameters. So the model box, and with
//!   it the camera, stays put while a slider is dragged.
//! - The session's last compiled model is reused when the source is the
//!   same, so a parameter edit costs no compile.

use std::sync::Arc;

use frep_artefact::Compiled;

use crate::compile::{check_params, check_source, compile_source};
use crate::state::AppState;
use crate::versions::load_version;

/// What `open` asked for.
#[derive(Clone, Debug)]
pub struct OpenRequest {
    /// Stored model.
    pub model_id: Option<String>,
    /// Its version (`None`: latest).
    pub version: Option<u32>,
    /// Source text (unsaved or edited).
    pub source: Option<String>,
    /// Parameter values.
    pub params: Vec<f64>,
}

/// A model open in a session.
#[derive(Clone, Debug)]
pub struct Opened {
    /// Stored model, if any.
    pub model_id: Option<String>,
    /// The stored version it is (or was edited from).
    pub version: Option<u32>,
    /// The compiled model.
    pub compiled: Arc<Compiled>,
    /// Parameter values.
    pub params: Arc<Vec<f64>>,
}

/// Resolves and compiles an open request (`previous`: the session's last
/// model, reused when the source is the same).
pub async fn resolve(
    state: AppState,
    req: OpenRequest,
    previous: Option<Arc<Compiled>>,
) -> Result<Opened, String> {
    check_params(&state, &req.params).map_err(|e| e.to_string())?;
    let (source, version, stored_params) = match (&req.source, &req.model_id) {
        (Some(s), _) => (s.clone(), req.version, Vec::new()),
        (None, Some(id)) => {
            let v = load_version(&state, id.clone(), req.version)
                .await
                .map_err(|e| e.to_string())?;
            (v.source, Some(v.number), v.params)
        }
        (None, None) => return Err("open needs a modelId or a source".to_string()),
    };
    check_source(&state, &source).map_err(|e| e.to_string())?;
    let params = if req.params.is_empty() {
        stored_params
    } else {
        req.params.clone()
    };
    let compiled = match previous.filter(|p| p.source() == source) {
        Some(p) => p,
        None => {
            // The box is detected at the defaults, so a slider does not
            // move the camera; the compile does not depend on the values.
            let c = compile_source(&state, source, None, Vec::new())
                .await
                .map_err(|e| e.to_string())?
                .map_err(|d| {
                    let first = d.first().map(|d| d.rendered.clone()).unwrap_or_default();
                    format!("the model has {} error(s): {first}", d.len())
                })?;
            // The summary generates the shader: off the async threads.
            let c2 = c.clone();
            tokio::task::spawn_blocking(move || {
                let _ = c2.summary();
            })
            .await
            .map_err(|e| format!("summary task failed: {e}"))?;
            c
        }
    };
    Ok(Opened {
        model_id: req.model_id,
        version,
        compiled,
        params: Arc::new(params),
    })
}
