//! # frep-artefact
//!
//! What the server computes from a model: still images, view sets, meshes,
//! slices, the generated shader, mesh exports. Each lives at a content
//! address, is computed once on a bounded worker pool, and is cached on disk.
//!
//! - [`compiled`]: [`Compiled`], a model compiled once with its box,
//!   parameters, graph hash and [`CompileSummary`](frep_wire::CompileSummary).
//!   The box is the `-- bounds:` line, else the detected extent, as on the
//!   command line. Also [`CompileCache`] by source hash, and diagnostics for
//!   the wire.
//! - [`mod@key`]: the content address of an artefact and its media type, file
//!   extension and URL.
//! - [`camera`]: the one camera convention of the server and the browser.
//! - [`mod@compute`]: the computations, synchronous, each kernel called as the
//!   CLI calls it, with a [`Cancel`] and a [`JobProgress`].
//! - [`jobs`], [`service`]: [`Artefacts`], the async-facing service: single
//!   flight per key, bounded pool and queue, cancel when superseded or when
//!   nobody waits, progress.
//! - [`cache`]: the size-bounded disk cache.
//!
//! ```no_run
//! # async fn demo() -> Result<(), frep_artefact::ArtefactError> {
//! use frep_artefact::*;
//! let artefacts = Artefacts::new(ArtefactConfig::new("/tmp/frep-cache"))?;
//! let compiled = compile("my_model(x[3], a[1]) { my_model = 1 - x[1]^2 - x[2]^2 - x[3]^2; }",
//!     None, &CompileLimits::default()).map_err(ArtefactError::Model)?;
//! let spec = frep_wire::ArtefactSpec::Mesh { depth: 5 };
//! let r = artefacts.request(compiled, &[], spec, None)?;
//! let body = artefacts.get(&r.key).await?; // glb bytes
//! # let _ = body; Ok(()) }
//! ```
#![warn(missing_docs)]

pub mod cache;
pub mod camera;
pub mod compiled;
pub mod compute;
pub mod config;
pub mod error;
pub mod jobs;
pub mod key;
pub mod service;

pub use compiled::{compile, compile_with_params, to_wire_diagnostic, CompileCache, Compiled};
pub use compute::{compute, Cancel, JobProgress, Output};
pub use config::{ArtefactConfig, ArtefactLimits, CompileLimits};
pub use error::ArtefactError;
pub use frep_mesh::poly::bounds::BoxOrigin;
pub use frep_render::ImagePool;
pub use key::{extension, is_key, key, media_type, url};
pub use service::{ArtefactBody, Artefacts, SupersedeGroup};
