//! Wavefront OBJ with `vn` normals and the common `v x y z r g b` colour extension.

use std::io::{self, BufWriter, Write};

use super::{invalid, parse};
use crate::Mesh;

pub(super) fn write(mesh: &Mesh, w: &mut impl Write) -> io::Result<()> {
    let mut w = BufWriter::new(w);
    writeln!(w, "# frep-mesh")?;
    for (i, [x, y, z]) in mesh.positions.iter().enumerate() {
        match mesh.colors.get(i) {
            Some([r, g, b]) => writeln!(w, "v {x} {y} {z} {r} {g} {b}")?,
            None => writeln!(w, "v {x} {y} {z}")?,
        }
    }
    for [x, y, z] in &mesh.normals {
        writeln!(w, "vn {x} {y} {z}")?;
    }
    let with_normals = !mesh.normals.is_empty();
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| i as u64 + 1);
        if with_normals {
            writeln!(w, "f {a}//{a} {b}//{b} {c}//{c}")?;
        } else {
            writeln!(w, "f {a} {b} {c}")?;
        }
    }
    w.flush()
}

/// Resolves a 1-based (or negative, relative) OBJ index against `count` items.
fn index(token: &str, count: usize) -> io::Result<usize> {
    let i: i64 = token
        .parse()
        .map_err(|_| invalid(format!("bad OBJ index {token:?}")))?;
    let resolved = if i < 0 { count as i64 + i } else { i - 1 };
    if resolved < 0 || resolved >= count as i64 {
        return Err(invalid(format!("OBJ index {i} out of range")));
    }
    Ok(resolved as usize)
}

/// Reads `v`, `vn` and `f` lines; polygons are fanned into triangles, and a vertex takes the
/// normal its last face corner names.
pub(super) fn read(bytes: &[u8]) -> io::Result<Mesh> {
    let text = std::str::from_utf8(bytes).map_err(invalid)?;
    let mut mesh = Mesh::default();
    let mut normals = Vec::new();
    let mut vertex_normal: Vec<Option<usize>> = Vec::new();
    for line in text.lines() {
        let mut tok = line.split_ascii_whitespace();
        match tok.next() {
            Some("v") => {
                let v: Vec<f32> = tok
                    .map(|t| parse(Some(t), "OBJ coordinate"))
                    .collect::<io::Result<_>>()?;
                match v.len() {
                    3 | 4 => mesh.positions.push([v[0], v[1], v[2]]),
                    6 | 7 => {
                        mesh.positions.push([v[0], v[1], v[2]]);
                        mesh.colors.resize(mesh.positions.len() - 1, [1.0; 3]);
                        mesh.colors.push([v[3], v[4], v[5]]);
                    }
                    _ => return Err(invalid("OBJ vertex needs 3 or 6 numbers")),
                }
            }
            Some("vn") => {
                let mut next = || parse::<f32>(tok.next(), "OBJ normal");
                normals.push([next()?, next()?, next()?]);
            }
            Some("f") => {
                vertex_normal.resize(mesh.positions.len(), None);
                let mut corners = Vec::new();
                for corner in tok {
                    let mut parts = corner.split('/');
                    let v = index(parts.next().unwrap_or(""), mesh.positions.len())?;
                    if let Some(n) = parts.nth(1).filter(|n| !n.is_empty()) {
                        vertex_normal[v] = Some(index(n, normals.len())?);
                    }
                    corners.push(v as u32);
                }
                if corners.len() < 3 {
                    return Err(invalid("OBJ face with fewer than 3 corners"));
                }
                for k in 1..corners.len() - 1 {
                    mesh.triangles
                        .push([corners[0], corners[k], corners[k + 1]]);
                }
            }
            _ => {}
        }
    }
    if !mesh.colors.is_empty() {
        mesh.colors.resize(mesh.positions.len(), [1.0; 3]);
    }
    vertex_normal.resize(mesh.positions.len(), None);
    if vertex_normal.iter().any(Option::is_some) {
        mesh.normals = vertex_normal
            .iter()
            .map(|n| n.map_or([0.0; 3], |n| normals[n]))
            .collect();
    }
    Ok(mesh)
}
