//! Mesh file formats: writers for delivery and readers for round-trip tests.
//!
//! | format | extension | normals | colours | notes |
//! |---|---|---|---|---|
//! | [`Format::StlBinary`] | `.stl` | facet | no | 50 bytes per triangle |
//! | [`Format::StlAscii`] | | facet | no | |
//! | [`Format::Obj`] | `.obj` | `vn` | `v x y z r g b` | |
//! | [`Format::Ply`] | `.ply` | `nx ny nz` | uchar RGB | binary little endian |
//! | [`Format::PlyAscii`] | | `nx ny nz` | uchar RGB | |
//! | [`Format::Glb`] | | i8 | u8 `COLOR_0` | `KHR_mesh_quantization`, u16 positions |
//! | [`Format::GlbMeshopt`] | `.glb` | i8 (octahedral) | u8 `COLOR_0` | plus `EXT_meshopt_compression` |
//! | [`Format::ThreeMf`] | `.3mf` | no | `m:colorgroup` | millimetres |
//!
//! Readers accept what the writers produce and common variants, not every file in the wild.
//! Triangle-soup formats (STL) come back with bit-identical positions merged. Writers
//! reject malformed meshes ([`Mesh::validate`]) with [`io::ErrorKind::InvalidInput`];
//! readers report malformed files with [`io::ErrorKind::InvalidData`].

mod glb;
mod obj;
mod ply;
mod stl;
mod threemf;

use std::io::{self, Read, Write};
use std::path::Path;

use crate::Mesh;

/// A mesh file format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// Binary STL.
    StlBinary,
    /// ASCII STL.
    StlAscii,
    /// Wavefront OBJ, with `vn` normals and `v x y z r g b` colours when present.
    Obj,
    /// Binary little-endian PLY.
    Ply,
    /// ASCII PLY.
    PlyAscii,
    /// glTF 2.0 binary with quantized attributes (`KHR_mesh_quantization`).
    Glb,
    /// glTF 2.0 binary, quantized and compressed with `EXT_meshopt_compression`.
    GlbMeshopt,
    /// 3D Manufacturing Format (a zip package), unit millimetre.
    ThreeMf,
}

impl Format {
    /// All formats.
    pub const ALL: [Format; 8] = [
        Format::StlBinary,
        Format::StlAscii,
        Format::Obj,
        Format::Ply,
        Format::PlyAscii,
        Format::Glb,
        Format::GlbMeshopt,
        Format::ThreeMf,
    ];

    /// The format for a file name's extension (case-insensitive): `.stl` is binary STL,
    /// `.ply` binary PLY, `.glb` meshopt-compressed glTF.
    pub fn from_path(path: &Path) -> Option<Format> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        Some(match ext.as_str() {
            "stl" => Format::StlBinary,
            "obj" => Format::Obj,
            "ply" => Format::Ply,
            "glb" => Format::GlbMeshopt,
            "3mf" => Format::ThreeMf,
            _ => return None,
        })
    }

    /// The usual file extension, without the dot.
    pub fn extension(self) -> &'static str {
        match self {
            Format::StlBinary | Format::StlAscii => "stl",
            Format::Obj => "obj",
            Format::Ply | Format::PlyAscii => "ply",
            Format::Glb | Format::GlbMeshopt => "glb",
            Format::ThreeMf => "3mf",
        }
    }

    /// The media type to serve the format with.
    pub fn mime_type(self) -> &'static str {
        match self {
            Format::StlBinary | Format::StlAscii => "model/stl",
            Format::Obj => "model/obj",
            Format::Ply | Format::PlyAscii => "application/ply",
            Format::Glb | Format::GlbMeshopt => "model/gltf-binary",
            Format::ThreeMf => "model/3mf",
        }
    }
}

/// Writes `mesh` in `format`. Fails with [`io::ErrorKind::InvalidInput`] when the mesh is
/// malformed (see [`Mesh::validate`]).
pub fn write(mesh: &Mesh, format: Format, w: &mut impl Write) -> io::Result<()> {
    mesh.validate()
        .map_err(|e| io::Error::new(io::ErrorKind::InvalidInput, e))?;
    match format {
        Format::StlBinary => stl::write_binary(mesh, w),
        Format::StlAscii => stl::write_ascii(mesh, w),
        Format::Obj => obj::write(mesh, w),
        Format::Ply => ply::write(mesh, w, false),
        Format::PlyAscii => ply::write(mesh, w, true),
        Format::Glb => glb::write(mesh, w, false),
        Format::GlbMeshopt => glb::write(mesh, w, true),
        Format::ThreeMf => threemf::write(mesh, w),
    }
}

/// Writes `mesh` into a new byte vector.
pub fn to_bytes(mesh: &Mesh, format: Format) -> io::Result<Vec<u8>> {
    let mut out = Vec::new();
    write(mesh, format, &mut out)?;
    Ok(out)
}

/// Reads a mesh in `format`. ASCII and binary STL are told apart by content, as are ASCII
/// and binary PLY, and the two glTF variants.
pub fn read(format: Format, r: &mut impl Read) -> io::Result<Mesh> {
    let mut bytes = Vec::new();
    r.read_to_end(&mut bytes)?;
    let mesh = match format {
        Format::StlBinary | Format::StlAscii => stl::read(&bytes)?,
        Format::Obj => obj::read(&bytes)?,
        Format::Ply | Format::PlyAscii => ply::read(&bytes)?,
        Format::Glb | Format::GlbMeshopt => glb::read(&bytes)?,
        Format::ThreeMf => threemf::read(&bytes)?,
    };
    mesh.validate().map_err(invalid)?;
    Ok(mesh)
}

/// An [`io::ErrorKind::InvalidData`] error.
pub(crate) fn invalid(e: impl Into<Box<dyn std::error::Error + Send + Sync>>) -> io::Error {
    io::Error::new(io::ErrorKind::InvalidData, e)
}

/// Splits text into whitespace-separated tokens and parses them, for the text formats.
pub(crate) fn parse<T: std::str::FromStr>(token: Option<&str>, what: &str) -> io::Result<T> {
    let token = token.ok_or_else(|| invalid(format!("missing {what}")))?;
    token
        .parse()
        .map_err(|_| invalid(format!("bad {what}: {token:?}")))
}

/// Quantizes a colour channel in `[0, 1]` to a byte.
pub(crate) fn color_byte(c: f32) -> u8 {
    (c.clamp(0.0, 1.0) * 255.0).round() as u8
}
