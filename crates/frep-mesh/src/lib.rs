//! Triangle meshes for FRep models:
//! - the [`Mesh`] type;
//! - checks that tests of the polygonizers rely on ([`Mesh::topology`],
//!   [`Mesh::self_intersections`], [`Mesh::max_distance_to`]);
//! - file formats ([`export`]).
//!
//! Invariant: only the [`export`] module does I/O. The mesh type and its checks are pure
//! computation, so that the polygonizers in this crate stay free of I/O. The `export` feature
//! (on by default) gates the formats and their dependencies (meshopt is C++). Without it the
//! crate builds for `wasm32-unknown-unknown`.
#![warn(missing_docs)]

#[cfg(feature = "export")]
pub mod export;
mod intersect;
mod mesh;
pub mod poly;
mod topology;

#[cfg(feature = "export")]
pub use export::Format;
pub use mesh::{InvalidMesh, Mesh};
pub use poly::{
    polygonize, CancelToken, Limits, MeshError, MeshSettings, Method, Progress, Resolution,
};
pub use topology::Topology;
