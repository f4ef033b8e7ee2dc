//! The errors of artefact work: one enum the server maps to HTTP statuses.
//! - unknown key → 404;
//! - limit → 413/422;
//! - busy → 503;
//! - cancelled → 499/503;
//! - model → 422;
//! - compute and I/O → 500.

use frep_wire::Diagnostic;

/// Why an artefact could not be had. `Clone`: one job's outcome is handed to
/// every request waiting on it.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArtefactError {
    /// No recipe is registered for this key (never requested, or forgotten)
    /// and nothing is cached under it.
    #[error("unknown artefact {0}")]
    UnknownKey(String),
    /// The request asks for more than a configured limit allows.
    #[error("{name} {got} is over the limit {limit}")]
    Limit {
        /// What is limited, e.g. `image pixels`.
        name: &'static str,
        /// The limit.
        limit: u64,
        /// What was asked for.
        got: u64,
    },
    /// The request is malformed in another way (e.g. a zero size).
    #[error("bad request: {0}")]
    BadRequest(String),
    /// The job queue is full; retry later.
    #[error("the artefact queue is full ({0} jobs)")]
    Busy(usize),
    /// The job was cancelled: superseded, or nobody waited any more.
    #[error("cancelled")]
    Cancelled,
    /// The model does not compile.
    #[error("the model has {} error(s)", .0.len())]
    Model(Vec<Diagnostic>),
    /// The ray caster or an image encoder failed.
    #[error("render: {0}")]
    Render(String),
    /// The polygonizer or a mesh writer failed.
    #[error("mesh: {0}")]
    Mesh(String),
    /// The disk cache failed.
    #[error("i/o: {0}")]
    Io(String),
}

impl From<std::io::Error> for ArtefactError {
    fn from(e: std::io::Error) -> Self {
        ArtefactError::Io(e.to_string())
    }
}

impl From<frep_render::RenderError> for ArtefactError {
    fn from(e: frep_render::RenderError) -> Self {
        match e {
            frep_render::RenderError::Cancelled => ArtefactError::Cancelled,
            e => ArtefactError::Render(e.to_string()),
        }
    }
}

impl From<frep_render::EncodeError> for ArtefactError {
    fn from(e: frep_render::EncodeError) -> Self {
        ArtefactError::Render(e.to_string())
    }
}

impl From<frep_mesh::MeshError> for ArtefactError {
    fn from(e: frep_mesh::MeshError) -> Self {
        match e {
            frep_mesh::MeshError::Cancelled => ArtefactError::Cancelled,
            e => ArtefactError::Mesh(e.to_string()),
        }
    }
}
