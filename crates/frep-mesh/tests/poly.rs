//! The polygonizer on the benchmark models, the examples and the corpus.

use std::path::{Path, PathBuf};

use frep_core::eval::grad::GradEval;
use frep_core::{Inputs, Model};
use frep_mesh::{polygonize, CancelToken, Mesh, MeshSettings, Method, Progress, Resolution};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn example(name: &str) -> (Model, [f64; 6]) {
    let src = std::fs::read_to_string(root().join("examples").join(name)).expect("example");
    (Model::compile(&src).expect("compiles"), bounds_line(&src))
}

fn bounds_line(src: &str) -> [f64; 6] {
    src.lines()
        .find_map(|l| l.strip_prefix("-- bounds:"))
        .map(|b| {
            let v: Vec<f64> = b
                .split(',')
                .map(|t| t.trim().parse().expect("number"))
                .collect();
            [v[0], v[1], v[2], v[3], v[4], v[5]]
        })
        .unwrap_or([-10.0, -10.0, -10.0, 10.0, 10.0, 10.0])
}

fn mesh(model: &Model, bounds: [f64; 6], depth: u8, method: Method) -> Mesh {
    let s = MeshSettings {
        bounds,
        resolution: Resolution::Depth(depth),
        method,
        ..Default::default()
    };
    polygonize(model, &s, &Progress::new(), &CancelToken::new()).expect("polygonize")
}

/// Closed, oriented outward, no degenerate triangles; self-intersections checked when asked.
fn check_closed(name: &str, m: &Mesh, intersections: bool) {
    m.validate().expect("valid");
    let t = m.topology();
    assert!(t.is_closed_manifold(), "{name}: {t:?}");
    assert!(t.is_consistently_oriented(), "{name}: {t:?}");
    assert_eq!(t.degenerate_triangles, 0, "{name}: {t:?}");
    if !m.triangles.is_empty() {
        assert!(
            m.signed_volume() > 0.0,
            "{name}: volume {}",
            m.signed_volume()
        );
    }
    if intersections {
        assert_eq!(m.self_intersections(1), 0, "{name}: self-intersections");
    }
}

#[test]
fn m1_sphere_watertight() {
    let (m, b) = example("m1_sphere.hf");
    let mesh = mesh(&m, b, 5, Method::Watertight);
    check_closed("m1", &mesh, true);
    let t = mesh.topology();
    assert_eq!(t.euler_characteristic(), 2);
    assert_eq!(t.components, 1);
    let h = 2.0 / 32.0;
    let err = mesh.max_distance_to(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt() - 0.8);
    assert!(err < h, "hausdorff {err}");
    let v = mesh.signed_volume();
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 0.512;
    assert!((v - exact).abs() < 0.02 * exact, "{v} vs {exact}");
}

/// `|f| / |∇f|`: a first-order distance estimate to the model's surface.
fn distance(model: &Model) -> impl Fn([f64; 3]) -> f64 {
    let tape = model.tape();
    move |p| {
        let g = GradEval::new(&tape).eval(p[0], p[1], p[2], &Inputs::default());
        let len = (g.dx * g.dx + g.dy * g.dy + g.dz * g.dz).sqrt();
        g.v.abs() / len
    }
}

fn compile(src: &str) -> Model {
    Model::compile(src).expect("compiles")
}

fn unit() -> [f64; 6] {
    [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0]
}

const ALL: [Method; 3] = [
    Method::Watertight,
    Method::DualContouring,
    Method::MarchingCubes,
];

#[test]
fn benchmark_models_all_methods() {
    for (name, euler) in [
        ("m1_sphere.hf", Some(2)),
        ("m2_spheres100.hf", None),
        ("m3_gyroid.hf", None),
        ("m4_rblend10.hf", Some(2)),
    ] {
        let (m, b) = example(name);
        for method in ALL {
            let mesh = mesh(&m, b, 5, method);
            let label = format!("{name} {method:?}");
            check_closed(
                &label,
                &mesh,
                method == Method::Watertight && name != "m3_gyroid.hf",
            );
            if let Some(e) = euler {
                assert_eq!(mesh.topology().euler_characteristic(), e, "{label}");
            }
            let h = 2.0 / 32.0;
            // Cap vertices are on the box, away from the surface: only M1 and M2 lie inside.
            if name == "m1_sphere.hf" || name == "m2_spheres100.hf" {
                let err = mesh.max_distance_to(distance(&m));
                assert!(err < h, "{label}: hausdorff {err}");
            }
        }
    }
}

#[test]
fn gyroid_watertight_has_no_self_intersections() {
    let (m, b) = example("m3_gyroid.hf");
    let mesh = mesh(&m, b, 5, Method::Watertight);
    assert_eq!(mesh.self_intersections(1), 0);
}

#[test]
fn examples_are_closed() {
    let dir = root().join("examples");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .expect("examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "hf"))
        .collect();
    names.sort();
    assert!(names.len() >= 8);
    for p in names {
        let src = std::fs::read_to_string(&p).expect("read");
        let m = compile(&src);
        let b = bounds_line(&src);
        for method in [Method::Watertight, Method::DualContouring] {
            let mesh = mesh(&m, b, 5, method);
            let label = format!("{} {method:?}", p.display());
            assert!(!mesh.triangles.is_empty(), "{label}: empty");
            check_closed(&label, &mesh, method == Method::Watertight);
        }
    }
}

#[test]
fn corpus_is_closed() {
    let dir = root().join("../shared/hyperfun/corpus");
    let Ok(rd) = std::fs::read_dir(&dir) else {
        eprintln!("note: corpus not found at {}, skipped", dir.display());
        return;
    };
    let mut names: Vec<_> = rd.filter_map(|e| e.ok().map(|e| e.path())).collect();
    names.sort();
    let mut meshed = 0;
    for p in names {
        let Ok(src) = std::fs::read_to_string(&p) else {
            continue;
        };
        let Ok(m) = Model::compile(&src) else {
            continue;
        };
        let b = frep_mesh::poly::bounds::detect(&m, &Inputs::default())
            .unwrap_or([-10.0, -10.0, -10.0, 10.0, 10.0, 10.0]);
        let mesh = mesh(&m, b, 5, Method::Watertight);
        check_closed(&p.display().to_string(), &mesh, false);
        meshed += usize::from(!mesh.triangles.is_empty());
    }
    assert!(meshed >= 5, "{meshed} corpus models meshed");
}

const TORUS: &str = "my_model(x[3], a[1]) {
  r = sqrt(x[1]*x[1] + x[2]*x[2]) - 0.6;
  my_model = 0.0625 - (r*r + x[3]*x[3]);
}";

const TWO_HOLES: &str = "my_model(x[3], a[1]) {
  b = (0.8 - x[1]) & (0.8 + x[1]) & (0.5 - x[2]) & (0.5 + x[2]) & (0.2 - x[3]) & (0.2 + x[3]);
  c1 = 0.04 - ((x[1] - 0.4)^2 + x[2]^2);
  c2 = 0.04 - ((x[1] + 0.4)^2 + x[2]^2);
  my_model = b \\ c1 \\ c2;
}";

#[test]
fn euler_characteristics() {
    for method in ALL {
        let t = mesh(&compile(TORUS), unit(), 5, method).topology();
        assert!(t.is_closed_manifold(), "{method:?} {t:?}");
        assert_eq!(t.euler_characteristic(), 0, "torus {method:?}");
        let t = mesh(&compile(TWO_HOLES), unit(), 5, method).topology();
        assert!(t.is_closed_manifold(), "{method:?} {t:?}");
        assert_eq!(t.euler_characteristic(), -2, "two holes {method:?}");
    }
}

#[test]
fn thin_slabs_are_present_and_closed() {
    let h = 2.0 / 32.0;
    // Centre on a sample plane for the half-cell slab; anywhere for the thicker ones.
    for (t, c) in [
        (0.5 * h, -1.0 + 16.5 * h),
        (1.1 * h, 0.1234),
        (2.0 * h, -0.377),
    ] {
        let src = format!(
            "my_model(x[3], a[1]) {{ my_model = ({} - abs(x[3] - ({c}))) & (0.7 - abs(x[1])) & (0.7 - abs(x[2])); }}",
            t / 2.0
        );
        let m = compile(&src);
        for method in [Method::Watertight, Method::DualContouring] {
            let mesh = mesh(&m, unit(), 5, method);
            let label = format!("slab {t} {method:?}");
            check_closed(&label, &mesh, method == Method::Watertight);
            let top = mesh.topology();
            assert_eq!(
                (top.components, top.euler_characteristic()),
                (1, 2),
                "{label}"
            );
            let (lo, hi) = mesh.bounds().expect("not empty");
            assert!(
                lo[0] < -0.6 && hi[0] > 0.6 && (hi[2] - lo[2]) < (t + 2.0 * h) as f32,
                "{label}"
            );
        }
    }
}

#[test]
fn scaled_fields_give_the_same_mesh() {
    let base = "0.8 - sqrt(x[1]*x[1] + x[2]*x[2] + x[3]*x[3])";
    let m1 = mesh(
        &compile(&format!("my_model(x[3], a[1]) {{ my_model = {base}; }}")),
        unit(),
        5,
        Method::Watertight,
    );
    for k in ["100", "0.01"] {
        let m = compile(&format!(
            "my_model(x[3], a[1]) {{ my_model = {k} * ({base}); }}"
        ));
        for method in ALL {
            let a = mesh(&m, unit(), 5, method);
            let b = if method == Method::Watertight {
                m1.clone()
            } else {
                mesh(
                    &compile(&format!("my_model(x[3], a[1]) {{ my_model = {base}; }}")),
                    unit(),
                    5,
                    method,
                )
            };
            assert_eq!(a.triangles.len(), b.triangles.len(), "×{k} {method:?}");
            let d = a
                .positions
                .iter()
                .zip(&b.positions)
                .map(|(p, q)| (0..3).map(|i| (p[i] - q[i]).abs()).fold(0.0f32, f32::max))
                .fold(0.0f32, f32::max);
            assert!(d < 1e-4, "×{k} {method:?}: {d}");
        }
    }
}

#[test]
fn nan_counts_as_outside() {
    // sqrt of a negative number is a runtime error (NaN) for x < 0.
    let m = compile("my_model(x[3], a[1]) { my_model = 0.8 - sqrt(x[1]*x[1] + x[2]*x[2] + x[3]*x[3]) + 0 * sqrt(x[1]); }");
    for method in ALL {
        let mesh = mesh(&m, unit(), 5, method);
        check_closed(
            &format!("nan {method:?}"),
            &mesh,
            method == Method::Watertight,
        );
        let (lo, hi) = mesh.bounds().expect("half a sphere");
        assert!(lo[0] > -0.07 && hi[0] > 0.75, "{lo:?} {hi:?}");
    }
}

#[test]
fn box_caps_close_a_clipped_sphere() {
    let m = compile("my_model(x[3], a[1]) { my_model = 1 - (x[1]*x[1] + x[2]*x[2] + x[3]*x[3]); }");
    let b = [-0.7, -0.7, -0.7, 0.7, 0.7, 0.7];
    for method in ALL {
        let mesh = mesh(&m, b, 5, method);
        let label = format!("caps {method:?}");
        check_closed(&label, &mesh, method == Method::Watertight);
        assert_eq!(mesh.topology().euler_characteristic(), 2, "{label}");
        let (lo, hi) = mesh.bounds().expect("not empty");
        assert_eq!((lo, hi), ([-0.7f32; 3], [0.7f32; 3]), "{label}");
        let on_face = mesh
            .positions
            .iter()
            .filter(|p| p.iter().any(|c| c.abs() == 0.7f32))
            .count();
        assert!(on_face > 100, "{label}: {on_face}");
    }
    // The whole box inside: a closed box of caps.
    let mesh = mesh(
        &m,
        [-0.3; 3]
            .into_iter()
            .chain([0.3; 3])
            .collect::<Vec<_>>()
            .try_into()
            .unwrap(),
        4,
        Method::Watertight,
    );
    check_closed("box inside", &mesh, true);
    let v = mesh.signed_volume();
    assert!(v > 0.9 * 0.216 && v <= 0.216 + 1e-6, "{v}");
}

#[test]
fn attributes_become_colours() {
    let (m, b) = example("android_robot.hf");
    let mesh = mesh(&m, b, 5, Method::Watertight);
    assert_eq!(mesh.colors.len(), mesh.positions.len());
    let green = mesh
        .colors
        .iter()
        .filter(|c| {
            (c[0] - 0.64).abs() < 1e-3 && (c[1] - 0.78).abs() < 1e-3 && (c[2] - 0.22).abs() < 1e-3
        })
        .count();
    assert!(
        green > mesh.colors.len() / 2,
        "{green} of {}",
        mesh.colors.len()
    );
    let (m1, b1) = example("m1_sphere.hf");
    assert!(mesh_colors_empty(&m1, b1));
}

fn mesh_colors_empty(m: &Model, b: [f64; 6]) -> bool {
    mesh(m, b, 3, Method::Watertight).colors.is_empty()
}

#[test]
fn dual_contouring_keeps_sharp_corners() {
    let c = 0.53;
    let m = compile(&format!(
        "my_model(x[3], a[1]) {{ my_model = ({c} - x[1]) & ({c} + x[1]) & ({c} - x[2]) & ({c} + x[2]) & ({c} - x[3]) & ({c} + x[3]); }}"
    ));
    let h = 2.0 / 32.0;
    let mesh = mesh(&m, unit(), 5, Method::DualContouring);
    check_closed("block dc", &mesh, false);
    for s in 0..8 {
        let corner = [0, 1, 2].map(|k| if s >> k & 1 == 1 { c } else { -c });
        let d = mesh
            .positions
            .iter()
            .map(|p| {
                (0..3)
                    .map(|k| (p[k] as f64 - corner[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(f64::MAX, f64::min);
        assert!(d < 0.05 * h, "corner {corner:?}: {d}");
    }
}

#[test]
fn cancel_and_progress() {
    let (m, b) = example("m4_rblend10.hf");
    let s = MeshSettings {
        bounds: b,
        resolution: Resolution::Depth(5),
        ..Default::default()
    };
    let cancel = CancelToken::new();
    cancel.cancel();
    let r = polygonize(&m, &s, &Progress::new(), &cancel);
    assert_eq!(r.err(), Some(frep_mesh::MeshError::Cancelled));
    let p = Progress::new();
    polygonize(&m, &s, &p, &CancelToken::new()).expect("runs");
    assert!(p.estimated() > 0 && p.done() == p.estimated(), "{p:?}");
    assert_eq!(p.fraction(), 1.0);
    // Cancelled from another thread while running.
    let s8 = MeshSettings {
        resolution: Resolution::Depth(9),
        ..s
    };
    let cancel = CancelToken::new();
    let c2 = cancel.clone();
    let t = std::thread::spawn(move || {
        std::thread::sleep(std::time::Duration::from_millis(50));
        c2.cancel();
    });
    let r = polygonize(&m, &s8, &Progress::new(), &cancel);
    t.join().expect("thread");
    assert_eq!(r.err(), Some(frep_mesh::MeshError::Cancelled));
}

#[test]
fn limits_are_enforced() {
    let (m, b) = example("m1_sphere.hf");
    let mut s = MeshSettings {
        bounds: b,
        resolution: Resolution::Depth(13),
        ..Default::default()
    };
    assert!(matches!(
        polygonize(&m, &s, &Progress::new(), &CancelToken::new()),
        Err(frep_mesh::MeshError::TooDeep { .. })
    ));
    s.resolution = Resolution::Depth(5);
    s.limits.max_triangles = 100;
    assert!(matches!(
        polygonize(&m, &s, &Progress::new(), &CancelToken::new()),
        Err(frep_mesh::MeshError::TooManyTriangles(100))
    ));
    s.bounds = [0.0, 0.0, 0.0, -1.0, 1.0, 1.0];
    assert!(matches!(
        polygonize(&m, &s, &Progress::new(), &CancelToken::new()),
        Err(frep_mesh::MeshError::InvalidBounds(_))
    ));
}

/// A pair from a polygonized can that the intersection test once misjudged (nearly
/// coplanar, touching a common plane at two different points).
#[test]
fn nearly_coplanar_neighbours_do_not_intersect() {
    let m = Mesh {
        positions: vec![
            [-0.10909091, -0.59, -0.7125],
            [-0.036363635, -0.5988979, -0.7125],
            [-0.036363635, -0.5988978, -0.6375],
            [-0.10909091, -0.5899999, -0.6375],
            [-0.036363635, -0.59889776, -0.5625],
            [-0.10909091, -0.58999985, -0.5625],
        ],
        triangles: vec![[0, 1, 2], [3, 4, 5]],
        ..Default::default()
    };
    assert_eq!(m.self_intersections(1), 0);
}

#[test]
fn surface_error_measures_both_directions() {
    use frep_mesh::poly::error::SurfaceSamples;
    let (m, b) = example("m1_sphere.hf");
    let h = 2.0 / 32.0;
    let samples = SurfaceSamples::new(&m, &Inputs::default(), b, 5, h);
    assert!(samples.points.len() > 1000);
    let mesh = mesh(&m, b, 5, Method::Watertight);
    let e = samples.error(&mesh);
    assert!(e.hausdorff() < 0.1 * h, "{e:?}");
    // A mesh scaled by 1.02 is 0.016 off the sphere of radius 0.8, both ways.
    let mut big = mesh.clone();
    for p in &mut big.positions {
        *p = p.map(|c| c * 1.02);
    }
    let e = samples.error(&big);
    assert!((e.mesh_to_surface - 0.016).abs() < 0.002, "{e:?}");
    assert!((e.surface_to_mesh - 0.016).abs() < 0.002, "{e:?}");
    // Half the sphere gone: surface points far from the mesh.
    let mut half = mesh.clone();
    half.triangles
        .retain(|t| mesh.positions[t[0] as usize][2] > 0.0);
    let e = samples.error(&half);
    assert!(
        e.mesh_to_surface < 0.1 * h && e.surface_to_mesh > 2.0 * h,
        "{e:?}"
    );
}

#[test]
fn surface_error_is_not_led_astray_by_a_weak_gradient() {
    // The union of z ≤ 0 and x ≤ 0, the second with a field of gradient 0.01: at (0.5, 0, 0.1)
    // the larger (active) field is the weak one, and Newton steps along its gradient travel
    // 0.5 to the plane x = 0, while the surface z = 0 is 0.1 away (formerly measured 0.5).
    use frep_mesh::poly::error::SurfaceSamples;
    let m = Model::compile("my_model(x[3], a[1]) { my_model = max(-x[3], -0.01 * x[1]); }")
        .expect("compiles");
    let b = [-1.0, -1.0, -1.0, 1.0, 1.0, 1.0];
    let samples = SurfaceSamples::new(&m, &Inputs::default(), b, 4, 0.0);
    let p = [0.5f32, 0.0, 0.1];
    let tri = Mesh {
        positions: vec![p, [0.5, 0.01, 0.1], [0.51, 0.0, 0.1]],
        triangles: vec![[0, 1, 2]],
        ..Default::default()
    };
    let e = samples.error(&tri);
    assert!((e.mesh_to_surface - 0.1).abs() < 0.002, "{e:?}");
}

#[test]
fn dual_contouring_vertices_lie_on_creases() {
    // R-union of ten spheres: every crease is sharp (the R-union's zero set is the union's).
    use frep_mesh::poly::error::SurfaceSamples;
    let (m, b) = example("m4_rblend10.hf");
    let h = 2.0 / 64.0;
    let samples = SurfaceSamples::new(&m, &Inputs::default(), b, 6, h);
    let dc = samples.error(&mesh(&m, b, 6, Method::DualContouring));
    let wt = samples.error(&mesh(&m, b, 6, Method::Watertight));
    assert!(dc.hausdorff() < 0.35 * h, "dc {dc:?}");
    assert!(dc.hausdorff() < 0.6 * wt.hausdorff(), "dc {dc:?} wt {wt:?}");
}

#[test]
fn verified_simplification_keeps_the_guarantees() {
    let (m, b) = example("m4_rblend10.hf");
    let full = mesh(&m, b, 6, Method::Watertight);
    let h = 2.0 / 64.0;
    for frac in [0.05, 0.25, 1.0] {
        let mut s = full.clone();
        if frac_kept(&mut s, frac * h) {
            check_closed(&format!("simplified {frac}"), &s, true);
            assert_eq!(
                s.topology().euler_characteristic(),
                full.topology().euler_characteristic()
            );
            let most = if frac < 0.1 { 1.0 } else { 0.5 };
            assert!(
                (s.triangles.len() as f64) < most * full.triangles.len() as f64,
                "{frac}: {} of {}",
                s.triangles.len(),
                full.triangles.len()
            );
        } else {
            assert_eq!(s.triangles.len(), full.triangles.len());
        }
    }
}

fn frac_kept(m: &mut Mesh, e: f64) -> bool {
    frep_mesh::poly::simplify_verified(m, e as f32, true).is_some()
}

#[test]
fn dual_contouring_follows_grooves_between_samples() {
    // Two spheres of radius 0.2 (union) whose neck, a groove less than a cell deep, lies on
    // z = 0, midway between two planes of samples: the cubes it runs through have all their
    // samples inside, and the vertices that see both sheets must leave their cubes to reach it
    // (H 0.25 cell when they may leave by half a cell; the axis off-centre as M2's spheres are
    // to the lattice).
    use frep_mesh::poly::error::SurfaceSamples;
    let m = compile(
        "my_model(x[3], a[1]) { r = (x[1] - 0.015)^2 + (x[2] - 0.014375)^2; \
         my_model = max(0.2 - sqrt(r + (x[3] - 0.18)^2), 0.2 - sqrt(r + (x[3] + 0.18)^2)); }",
    );
    let b = [-0.5, -0.5, -0.5, 0.5, 0.5, 0.5];
    let h = 1.0 / 64.0;
    let samples = SurfaceSamples::new(&m, &Inputs::default(), b, 6, h);
    let dc = mesh(&m, b, 6, Method::DualContouring);
    check_closed("two spheres", &dc, false);
    let e = samples.error(&dc);
    assert!(e.hausdorff() < 0.1 * h, "{e:?}");
}

#[test]
fn watertight_vertices_lie_on_the_surface() {
    // Every crossing is searched until its estimate stops moving: on an R-function field (not
    // a distance), 95 % of the vertices are within 1e-4 cell of `f = 0` (first order); the
    // others are kept 0.01 edge away from a sample (`EDGE_MARGIN`).
    let (m, b) = example("m4_rblend10.hf");
    let h = 2.0 / 32.0;
    let mesh = mesh(&m, b, 5, Method::Watertight);
    let tape = m.tape();
    let mut ge = GradEval::new(&tape);
    let (mut far, mut all) = (0, 0);
    for p in &mesh.positions {
        let p = p.map(f64::from);
        if (0..3).any(|k| p[k] <= b[k] + 1e-6 || p[k] >= b[k + 3] - 1e-6) {
            continue;
        }
        let g = ge.eval(p[0], p[1], p[2], &Inputs::default());
        let len = (g.dx * g.dx + g.dy * g.dy + g.dz * g.dz).sqrt();
        all += 1;
        if g.v.abs() / len > 1e-4 * h {
            far += 1;
        }
    }
    assert!(all > 1000 && far * 20 < all, "{far} of {all}");
}

fn adaptive(model: &Model, bounds: [f64; 6], depth: u8, tol: f64) -> Mesh {
    let s = MeshSettings {
        bounds,
        resolution: Resolution::Depth(depth),
        method: Method::DualContouring,
        adaptive: Some(tol),
        ..Default::default()
    };
    polygonize(model, &s, &Progress::new(), &CancelToken::new()).expect("polygonize")
}

#[test]
fn adaptive_dual_contouring_keeps_the_topology() {
    // Every example at depths 4–7 (and the torus, two holes, a cube): closed, oriented,
    // 2-manifold, the components and Euler characteristic of plain dual contouring.
    let dir = root().join("examples");
    let mut models: Vec<(String, Model, [f64; 6])> = std::fs::read_dir(&dir)
        .expect("examples")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "hf"))
        .map(|p| {
            let src = std::fs::read_to_string(&p).expect("read");
            (p.display().to_string(), compile(&src), bounds_line(&src))
        })
        .collect();
    models.sort_by(|a, b| a.0.cmp(&b.0));
    assert!(models.len() >= 8);
    models.push(("torus".into(), compile(TORUS), unit()));
    models.push(("two holes".into(), compile(TWO_HOLES), unit()));
    let mut fewer = 0;
    for (name, m, b) in &models {
        for depth in 4..=7 {
            // Depth 7 of the slowest models only in release builds.
            if depth == 7 && cfg!(debug_assertions) && !name.contains("sphere.hf") {
                continue;
            }
            let plain = mesh(m, *b, depth, Method::DualContouring).topology();
            for tol in [0.1, 1.0] {
                let a = adaptive(m, *b, depth, tol);
                let label = format!("{name} d{depth} adaptive {tol}");
                check_closed(&label, &a, false);
                let t = a.topology();
                assert_eq!(t.components, plain.components, "{label}");
                assert_eq!(
                    t.euler_characteristic(),
                    plain.euler_characteristic(),
                    "{label}"
                );
                assert!(t.faces <= plain.faces, "{label}");
                fewer += usize::from(t.faces * 2 < plain.faces);
            }
        }
    }
    assert!(fewer >= 10, "{fewer} meshes halved");
}

#[test]
fn adaptive_dual_contouring_is_bounded_by_its_threshold() {
    use frep_mesh::poly::error::SurfaceSamples;
    // A sphere: big polygons, each within a fraction of a cell of the surface.
    let (m, b) = example("m1_sphere.hf");
    let h = 2.0 / 64.0;
    let samples = SurfaceSamples::new(&m, &Inputs::default(), b, 6, h);
    let plain = mesh(&m, b, 6, Method::DualContouring);
    for (tol, most) in [(0.05, 0.6), (0.2, 0.2)] {
        let a = adaptive(&m, b, 6, tol);
        let e = samples.error(&a).hausdorff() / h;
        assert!(e < 1.5 * tol, "{tol}: H {e}");
        assert!(
            (a.triangles.len() as f64) < most * plain.triangles.len() as f64,
            "{tol}: {} of {}",
            a.triangles.len(),
            plain.triangles.len()
        );
    }
    // Sharp corners of a cube are kept.
    let c = 0.53;
    let cube = compile(&format!(
        "my_model(x[3], a[1]) {{ my_model = ({c} - x[1]) & ({c} + x[1]) & ({c} - x[2]) & ({c} + x[2]) & ({c} - x[3]) & ({c} + x[3]); }}"
    ));
    let a = adaptive(&cube, unit(), 5, 0.1);
    let plain = mesh(&cube, unit(), 5, Method::DualContouring);
    assert!(a.triangles.len() * 4 < plain.triangles.len());
    for s in 0..8 {
        let corner = [0, 1, 2].map(|k| if s >> k & 1 == 1 { c } else { -c });
        let d = a
            .positions
            .iter()
            .map(|p| {
                (0..3)
                    .map(|k| (p[k] as f64 - corner[k]).powi(2))
                    .sum::<f64>()
                    .sqrt()
            })
            .fold(f64::MAX, f64::min);
        assert!(d < 0.05 * 2.0 / 32.0, "corner {corner:?}: {d}");
    }
}
