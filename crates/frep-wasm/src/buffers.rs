//! The packed binary mesh the module hands to JavaScript: typed-array views
//! over one buffer, no parsing.
//!
//! Layout (little-endian, every section 4-byte aligned):
//! 1. `u32 magic "FRM1"`, `u32 vertices`, `u32 triangles`, `u32 flags`
//!    (bit 0: colours present, bit 1: normals present);
//! 2. `f32` positions `[3·vertices]`;
//! 3. normals `[3·vertices]`, when present;
//! 4. colours `[3·vertices]`, when present;
//! 5. `u32` indices `[3·triangles]`.

use frep_mesh::Mesh;

/// "FRM1" read as a little-endian u32.
pub const MESH_MAGIC: u32 = u32::from_le_bytes(*b"FRM1");
/// Flag bit: colours present.
pub const HAS_COLORS: u32 = 1;
/// Flag bit: normals present.
pub const HAS_NORMALS: u32 = 2;

/// Packs a mesh (see the module docs).
pub fn pack_mesh(mesh: &Mesh) -> Vec<u8> {
    let v = mesh.positions.len();
    let colors = mesh.colors.len() == v && v > 0;
    let normals = mesh.normals.len() == v && v > 0;
    let floats = 3 * v * (1 + usize::from(colors) + usize::from(normals));
    let mut out = Vec::with_capacity(16 + 4 * floats + 12 * mesh.triangles.len());
    let flags = (u32::from(colors) * HAS_COLORS) | (u32::from(normals) * HAS_NORMALS);
    for w in [MESH_MAGIC, v as u32, mesh.triangles.len() as u32, flags] {
        out.extend_from_slice(&w.to_le_bytes());
    }
    let mut put = |xs: &[[f32; 3]]| {
        for c in xs.iter().flatten() {
            out.extend_from_slice(&c.to_le_bytes());
        }
    };
    put(&mesh.positions);
    if normals {
        put(&mesh.normals);
    }
    if colors {
        put(&mesh.colors);
    }
    for i in mesh.triangles.iter().flatten() {
        out.extend_from_slice(&i.to_le_bytes());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layout_of_a_triangle() {
        let mesh = Mesh {
            positions: vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            normals: Vec::new(),
            colors: vec![[1.0, 0.5, 0.0]; 3],
            triangles: vec![[0, 1, 2]],
        };
        let b = pack_mesh(&mesh);
        assert_eq!(b.len(), 16 + 9 * 4 * 2 + 12);
        assert_eq!(&b[0..4], b"FRM1");
        assert_eq!(u32::from_le_bytes(b[4..8].try_into().unwrap()), 3);
        assert_eq!(u32::from_le_bytes(b[8..12].try_into().unwrap()), 1);
        assert_eq!(
            u32::from_le_bytes(b[12..16].try_into().unwrap()),
            HAS_COLORS
        );
        // Second position's x.
        assert_eq!(f32::from_le_bytes(b[28..32].try_into().unwrap()), 1.0);
        // The last index.
        assert_eq!(u32::from_le_bytes(b[b.len() - 4..].try_into().unwrap()), 2);
    }
}
