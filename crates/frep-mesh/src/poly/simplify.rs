//! Mesh simplification after polygonization (meshopt; the `export`
//! feature).

use crate::Mesh;

/// [`simplify_mesh`], then a check that the result keeps what the input had:
/// - closed, 2-manifold, consistently oriented, no degenerate triangles;
/// - the same components and Euler characteristic (genus);
/// - when `intersections`, no self-intersections.
///
/// A result that fails is dropped, and the simplification retried with half the error (three
/// tries). The mesh stays unsimplified when every try fails. Returns the error bound that was
/// kept.
#[cfg(feature = "export")]
pub fn simplify_verified(mesh: &mut Mesh, error: f32, intersections: bool) -> Option<f32> {
    let before = mesh.topology();
    if !(before.is_closed_manifold() && before.is_consistently_oriented()) {
        simplify_mesh(mesh, error);
        return Some(error);
    }
    let mut e = error;
    for _ in 0..3 {
        let mut m = mesh.clone();
        simplify_mesh(&mut m, e);
        let t = m.topology();
        let ok = t.is_closed_manifold()
            && t.is_consistently_oriented()
            && t.degenerate_triangles == 0
            && t.components == before.components
            && t.euler_characteristic() == before.euler_characteristic()
            && (!intersections || m.self_intersections(1) == 0);
        if ok {
            *mesh = m;
            return Some(e);
        }
        e *= 0.5;
    }
    None
}

/// Error-bounded edge-collapse simplification (meshopt), absolute error `error`.
#[cfg(feature = "export")]
pub fn simplify_mesh(mesh: &mut Mesh, error: f32) {
    if mesh.triangles.is_empty() {
        return;
    }
    let flat: Vec<u32> = mesh.triangles.iter().flatten().copied().collect();
    let bytes: Vec<u8> = mesh
        .positions
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    let Ok(adapter) = meshopt::VertexDataAdapter::new(&bytes, 12, 0) else {
        return;
    };
    let out = meshopt::simplify(
        &flat,
        &adapter,
        0,
        error,
        meshopt::SimplifyOptions::LockBorder | meshopt::SimplifyOptions::ErrorAbsolute,
        None,
    );
    let mut remap = vec![u32::MAX; mesh.positions.len()];
    let mut m = Mesh::default();
    for &i in &out {
        if remap[i as usize] == u32::MAX {
            remap[i as usize] = m.positions.len() as u32;
            m.positions.push(mesh.positions[i as usize]);
            if !mesh.normals.is_empty() {
                m.normals.push(mesh.normals[i as usize]);
            }
            if !mesh.colors.is_empty() {
                m.colors.push(mesh.colors[i as usize]);
            }
        }
    }
    m.triangles = out
        .chunks_exact(3)
        .map(|t| {
            [
                remap[t[0] as usize],
                remap[t[1] as usize],
                remap[t[2] as usize],
            ]
        })
        .collect();
    *mesh = m;
}
