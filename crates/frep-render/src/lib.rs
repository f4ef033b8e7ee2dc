//! # frep-render
//!
//! The FRep ray caster and everything around it:
//!
//! - [`camera`]: turntable cameras that frame a bounding box, primary rays,
//!   tile frusta (for interval pruning) and pixel footprints;
//! - [`tiles`]: the seam for the caster ([`TileCaster`]) and the parallel
//!   tile driver ([`cast_tiled`]);
//! - [`image`]: images, hit buffers and shading ([`shade`]);
//! - [`mod@encode`]: PNG, JPEG and lossy WebP encoders;
//! - [`progressive`]: coarse-to-fine frame plans and upscaling;
//! - [`viewset`]: turntable view sets with a sprite sheet and JSON index;
//! - [`slices`]: grid sampling through a batch callback, PNG slice stacks and
//!   8-bit 3D textures;
//! - [`raycast`]: the FRep ray caster ([`ModelCaster`]) and [`render`];
//! - [`files`]: an export's files as names and bytes (the library writes
//!   no files; the caller does);
//! - [`golden`]: text masks for small golden renders;
//! - [`synthetic`]: an analytic sphere scene for tests and demos.
//!
//! Conventions: world z is up; fields are HyperFun's (positive inside).
//!
//! The pipeline, with the analytic sphere standing in for the FRep ray caster
//! (both implement [`TileCaster`]):
//!
//! ```
//! use frep_render::{cast_tiled, encode, shade, Aabb, Camera, ImageFormat, Lighting};
//! use frep_render::synthetic::SphereCaster;
//!
//! let bounds = Aabb::new([-1.0; 3], [1.0; 3]);
//! let camera = Camera::orbit(&bounds, 30.0, 20.0, Some(35.0));
//! let caster = SphereCaster { center: [0.0; 3], radius: 0.8, color: None };
//! let hits = cast_tiled(&caster, &camera, 64, 48, 16);
//! let image = shade(&hits, &Lighting::default());
//! let jpeg = encode(&image, ImageFormat::Jpeg, 75).unwrap();
//! assert_eq!(&jpeg[..2], &[0xFF, 0xD8]);
//! ```
#![warn(missing_docs)]

pub mod camera;
pub mod encode;
pub mod files;
pub mod golden;
pub mod image;
pub mod progressive;
pub mod raycast;
pub mod slices;
pub mod synthetic;
pub mod tiles;
pub mod viewset;

pub use camera::{Aabb, Camera, Frustum, Projection, Ray, RayMaker};
pub use encode::{encode, EncodeError, ImageFormat};
pub use files::OutFile;
pub use frep_core::CancelToken;
pub use golden::ascii_mask;
pub use image::{shade, DepthImage, Hit, HitBuffer, Image, ImagePool, Light, Lighting, Shader};
pub use progressive::{upscale_nearest, ProgressivePlan, ProgressiveStep};
pub use raycast::{
    render, render_camera, render_hits, render_with, CastStats, ModelCaster, RenderError,
    RenderLimits, RenderSettings, Section, SectionError, SECTION_CAP,
};
pub use slices::{sample_grid, slice_files, Grid, SliceIndex, SliceOptions};
pub use tiles::{cast_tiled, Tile, TileCaster};
pub use viewset::{render_view_set, view_set_files, ViewSet, ViewSetIndex, ViewSetOptions};
