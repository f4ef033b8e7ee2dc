//! Topology, volume, intersection and distance checks on hand-made meshes.

mod common;

use common::{concat, cube, cube_at, torus, uv_sphere};
use frep_mesh::Mesh;

#[test]
fn cube_is_a_closed_oriented_sphere() {
    let m = cube();
    let t = m.topology();
    assert_eq!((t.vertices, t.edges, t.faces), (8, 18, 12));
    assert_eq!(t.euler_characteristic(), 2);
    assert!(t.is_closed_manifold() && t.is_consistently_oriented());
    assert_eq!(
        (
            t.components,
            t.degenerate_triangles,
            t.non_manifold_vertices
        ),
        (1, 0, 0)
    );
    assert!((m.signed_volume() - 1.0).abs() < 1e-12);
    assert_eq!(m.self_intersections(10), 0);
    assert_eq!(m.bounds(), Some(([0.0; 3], [1.0; 3])));
}

#[test]
fn torus_has_euler_characteristic_zero() {
    let m = torus(2.0, 0.5, 24, 12);
    let t = m.topology();
    assert_eq!(t.euler_characteristic(), 0);
    assert!(t.is_closed_manifold() && t.is_consistently_oriented());
    // Volume 2π²Rr², less for the polygonal approximation.
    let exact = 2.0 * std::f64::consts::PI.powi(2) * 2.0 * 0.25;
    let v = m.signed_volume();
    assert!(v > 0.9 * exact && v < exact, "{v} vs {exact}");
    assert_eq!(m.self_intersections(10), 0);
}

#[test]
fn cube_missing_a_triangle_has_three_boundary_edges() {
    let mut m = cube();
    m.triangles.pop();
    let t = m.topology();
    assert_eq!(t.boundary_edges, 3);
    assert!(!t.is_closed_manifold());
    assert!(t.is_consistently_oriented());
    assert_eq!(t.non_manifold_vertices, 0, "boundary fans are still discs");
    assert_eq!(t.euler_characteristic(), 1);
}

#[test]
fn flipped_triangle_is_an_orientation_error() {
    let mut m = cube();
    m.triangles[5].swap(1, 2);
    let t = m.topology();
    assert_eq!(t.inconsistent_edges, 3);
    assert!(!t.is_consistently_oriented());
    assert!(t.is_closed_manifold());
}

#[test]
fn cubes_sharing_an_edge_are_non_manifold() {
    let mut m = concat(&[cube(), cube_at([1.0, 1.0, 0.0])]);
    m.merge_duplicate_vertices(0.0);
    assert_eq!(m.positions.len(), 14);
    let t = m.topology();
    assert_eq!(t.non_manifold_edges, 1);
    assert_eq!(t.non_manifold_vertices, 2, "the shared edge's two ends");
    assert_eq!(t.components, 1);
    assert!(!t.is_closed_manifold());
    assert_eq!(
        m.self_intersections(10),
        0,
        "touching along a shared edge is not an intersection"
    );
}

#[test]
fn cubes_sharing_a_vertex_are_non_manifold_there() {
    let mut m = concat(&[cube(), cube_at([1.0, 1.0, 1.0])]);
    m.merge_duplicate_vertices(0.0);
    let t = m.topology();
    assert_eq!((t.non_manifold_edges, t.non_manifold_vertices), (0, 1));
    assert_eq!(m.self_intersections(10), 0);
}

fn triangles(ts: &[[[f32; 3]; 3]]) -> Mesh {
    Mesh {
        positions: ts.iter().flatten().copied().collect(),
        triangles: (0..ts.len() as u32)
            .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
            .collect(),
        ..Mesh::default()
    }
}

#[test]
fn crossing_triangles_intersect_once() {
    let m = triangles(&[
        [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
        [[0.5, 0.5, -1.0], [0.5, 0.5, 1.0], [1.5, -1.0, 0.0]],
    ]);
    assert_eq!(m.self_intersections(10), 1);
    let t = m.topology();
    assert_eq!((t.components, t.boundary_edges), (2, 6));
}

#[test]
fn separated_and_touching_triangles() {
    let apart = triangles(&[
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]],
    ]);
    assert_eq!(apart.self_intersections(10), 0);
    // Coplanar and overlapping.
    let overlap = triangles(&[
        [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]],
        [[0.5, 0.5, 0.0], [3.0, 0.5, 0.0], [0.5, 3.0, 0.0]],
    ]);
    assert_eq!(overlap.self_intersections(10), 1);
}

#[test]
fn folded_triangles_sharing_an_edge_intersect() {
    let mut m = Mesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 2.0, 0.0],
        ],
        triangles: vec![[0, 1, 2], [1, 0, 3]],
        ..Mesh::default()
    };
    // Opposite sides of the shared edge: a flat, valid pair.
    m.positions[3] = [0.5, -1.0, 0.0];
    assert_eq!(m.self_intersections(10), 0);
    // Same side: folded over.
    m.positions[3] = [0.5, 2.0, 0.0];
    assert_eq!(m.self_intersections(10), 1);
    // Bent out of plane: fine again.
    m.positions[3] = [0.5, 2.0, 1.0];
    assert_eq!(m.self_intersections(10), 0);
}

#[test]
fn triangles_sharing_a_vertex() {
    let mut m = Mesh {
        positions: vec![
            [0.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.0, 2.0, 0.0],
            [1.0, 1.0, -1.0],
            [1.0, 1.0, 1.0],
        ],
        triangles: vec![[0, 1, 2], [0, 3, 4]],
        ..Mesh::default()
    };
    // The second triangle pierces the first away from the shared vertex.
    assert_eq!(m.self_intersections(10), 1);
    m.positions[3] = [-1.0, -1.0, -1.0];
    m.positions[4] = [-1.0, -2.0, 1.0];
    assert_eq!(m.self_intersections(10), 0);
}

#[test]
fn sphere_is_clean_and_close_to_its_sdf() {
    let m = uv_sphere(1.0, 101, 100);
    assert_eq!(m.triangles.len(), 20_000);
    let t = m.topology();
    assert!(t.is_closed_manifold() && t.is_consistently_oriented());
    assert_eq!(t.euler_characteristic(), 2);
    assert_eq!(m.self_intersections(1), 0);
    let d = m.max_distance_to(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 1.0);
    // The chord sag of a 3.6° segment is about 5e-4.
    assert!(d > 1e-4 && d < 1e-3, "{d}");
    let v = m.signed_volume();
    assert!((v - 4.0 / 3.0 * std::f64::consts::PI).abs() < 0.01, "{v}");
    // Normals point outward.
    for (p, n) in m.positions.iter().zip(&m.normals) {
        assert!((0..3).map(|k| p[k] * n[k]).sum::<f32>() > 0.99);
    }
}

#[test]
fn self_intersections_stop_at_max_pairs() {
    // Two interpenetrating spheres intersect along a circle.
    let a = uv_sphere(1.0, 20, 20);
    let mut b = a.clone();
    b.positions.iter_mut().for_each(|p| p[0] += 1.0);
    let m = concat(&[a, b]);
    let all = m.self_intersections(usize::MAX);
    assert!(all > 20, "{all}");
    assert_eq!(m.self_intersections(5), 5);
}

#[test]
fn merge_and_degenerate_triangles() {
    let mut m = Mesh {
        positions: vec![
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1e-7, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ],
        triangles: vec![[0, 1, 2], [3, 1, 2], [0, 1, 4], [0, 3, 1]],
        ..Mesh::default()
    };
    let t = m.topology();
    assert_eq!(t.degenerate_triangles, 2, "two collinear triangles");
    assert_eq!(m.merge_duplicate_vertices(1e-6), 1);
    // [3, 1, 2] now duplicates [0, 1, 2]; [0, 3, 1] lost a corner.
    assert_eq!(m.triangles, vec![[0, 1, 2], [0, 1, 2], [0, 1, 3]]);
    assert_eq!(m.positions.len(), 4);
}

#[test]
fn validate_reports_bad_meshes() {
    let mut m = cube();
    assert!(m.validate().is_ok());
    m.normals.push([0.0, 0.0, 1.0]);
    assert!(m.validate().is_err());
    m.normals.clear();
    m.triangles.push([0, 1, 8]);
    assert!(m.validate().is_err());
}

#[test]
fn checks_scale_to_200k_triangles() {
    // 200,000 triangles; timings are printed for the record (`-- --nocapture`).
    let m = torus(2.0, 0.7, 500, 200);
    let start = std::time::Instant::now();
    let t = m.topology();
    let topology = start.elapsed();
    let start = std::time::Instant::now();
    assert_eq!(m.self_intersections(1), 0);
    let intersections = start.elapsed();
    println!(
        "{} triangles: topology {topology:?}, self-intersections {intersections:?}",
        m.triangles.len()
    );
    assert!(t.is_closed_manifold() && t.euler_characteristic() == 0);
}
