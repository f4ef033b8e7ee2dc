//! STL, binary and ASCII: a triangle soup with facet normals and no colours.

use std::io::{self, BufWriter, Write};

use super::{invalid, parse};
use crate::mesh::{dot, Mesh};

fn facet_normal(mesh: &Mesh, t: [u32; 3]) -> [f32; 3] {
    let n = mesh.triangle_cross(t);
    let len = dot(n, n).sqrt();
    if len > 0.0 {
        n.map(|c| (c / len) as f32)
    } else {
        [0.0; 3]
    }
}

pub(super) fn write_binary(mesh: &Mesh, w: &mut impl Write) -> io::Result<()> {
    let count = u32::try_from(mesh.triangles.len())
        .map_err(|_| io::Error::new(io::ErrorKind::InvalidInput, "too many triangles for STL"))?;
    let mut w = BufWriter::new(w);
    let mut header = [b' '; 80];
    header[..13].copy_from_slice(b"frep-mesh STL");
    w.write_all(&header)?;
    w.write_all(&count.to_le_bytes())?;
    for &t in &mesh.triangles {
        let corners = t.map(|i| mesh.positions[i as usize]);
        for v in std::iter::once(facet_normal(mesh, t)).chain(corners) {
            for c in v {
                w.write_all(&c.to_le_bytes())?;
            }
        }
        w.write_all(&[0, 0])?;
    }
    w.flush()
}

pub(super) fn write_ascii(mesh: &Mesh, w: &mut impl Write) -> io::Result<()> {
    let mut w = BufWriter::new(w);
    writeln!(w, "solid frep")?;
    for &t in &mesh.triangles {
        let [nx, ny, nz] = facet_normal(mesh, t);
        // `{:e}` prints the shortest text that reads back to the same f32.
        writeln!(w, "facet normal {nx:e} {ny:e} {nz:e}\n outer loop")?;
        for i in t {
            let [x, y, z] = mesh.positions[i as usize];
            writeln!(w, "  vertex {x:e} {y:e} {z:e}")?;
        }
        writeln!(w, " endloop\nendfacet")?;
    }
    writeln!(w, "endsolid frep")?;
    w.flush()
}

/// Reads either kind; a file is binary when its size matches the triangle count in the header.
pub(super) fn read(bytes: &[u8]) -> io::Result<Mesh> {
    let soup = match bytes.get(80..84) {
        Some(n)
            if bytes.len()
                == 84 + 50 * u32::from_le_bytes(n.try_into().unwrap_or_default()) as usize =>
        {
            read_binary(bytes)
        }
        _ => read_ascii(bytes)?,
    };
    let mut mesh = Mesh {
        triangles: (0..soup.len() as u32 / 3)
            .map(|t| [3 * t, 3 * t + 1, 3 * t + 2])
            .collect(),
        positions: soup,
        ..Mesh::default()
    };
    mesh.merge_duplicate_vertices(0.0);
    Ok(mesh)
}

fn read_binary(bytes: &[u8]) -> Vec<[f32; 3]> {
    let mut soup = Vec::new();
    for rec in bytes[84..].chunks_exact(50) {
        let f = |o: usize| f32::from_le_bytes([rec[o], rec[o + 1], rec[o + 2], rec[o + 3]]);
        // Skip the facet normal (12 bytes); three corners follow.
        soup.extend((1..4).map(|k| [0, 1, 2].map(|c| f(12 * k + 4 * c))));
    }
    soup
}

fn read_ascii(bytes: &[u8]) -> io::Result<Vec<[f32; 3]>> {
    let text = std::str::from_utf8(bytes).map_err(invalid)?;
    if !text.trim_start().starts_with("solid") {
        return Err(invalid("neither binary nor ASCII STL"));
    }
    let mut soup = Vec::new();
    let mut tokens = text.split_ascii_whitespace();
    while let Some(tok) = tokens.next() {
        if tok == "vertex" {
            let mut next = || parse::<f32>(tokens.next(), "STL vertex coordinate");
            soup.push([next()?, next()?, next()?]);
        }
    }
    if !soup.len().is_multiple_of(3) {
        return Err(invalid("STL vertex count is not a multiple of 3"));
    }
    Ok(soup)
}
