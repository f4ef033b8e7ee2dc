//! The bindings against the native kernel: the meshes the module makes
//! (serial frep-mesh, no exports) equal the native mesher's (rayon) for the
//! same settings, byte for byte once packed; and their summaries are the
//! fixture `web/tests/node/fixtures/meshes.json`, which the Node test of the
//! WebAssembly build compares with (`FREP_BLESS=1` rewrites it).

use std::path::{Path, PathBuf};

use frep_core::{CompileOptions, Inputs, Model};
use frep_mesh::{polygonize, CancelToken, MeshSettings, Progress, Resolution};
use frep_wasm::buffers::pack_mesh;
use frep_wasm::{CompileRequest, Kernel, MeshRequest};

/// Examples meshed, with their depth: a sphere, the gyroid (transcendental
/// functions), a coloured model (attributes), R-function blends.
const CASES: &[(&str, u8)] = &[
    ("sphere", 5),
    ("m3_gyroid", 5),
    ("android_robot", 5),
    ("m4_rblend10", 5),
];

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// FNV-1a, 64 bits, as 16 hex digits (the Node test computes the same).
fn fnv1a(bytes: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

#[test]
fn module_meshes_equal_the_native_ones() {
    let mut fixture = Vec::new();
    let mut kernel = Kernel::new();
    for &(name, depth) in CASES {
        let src = std::fs::read_to_string(root().join(format!("examples/{name}.hf"))).unwrap();
        let compiled = kernel.compile(&src, &CompileRequest::default());
        assert!(compiled.ok, "{name}: {:?}", compiled.diagnostics);
        let bounds = compiled.bounds.unwrap();
        assert_eq!(compiled.bounds_origin, "comment");
        let req = MeshRequest {
            bounds,
            depth,
            method: None,
            params: Vec::new(),
            colors: None,
            max_triangles: None,
            max_depth: None,
        };
        let packed = kernel.polygonize(compiled.handle, &req).unwrap();

        let model = Model::compile_with(&src, &CompileOptions::default()).unwrap();
        let settings = MeshSettings {
            bounds,
            resolution: Resolution::Depth(depth),
            inputs: Inputs::default(),
            threads: Some(2),
            ..Default::default()
        };
        let native = polygonize(&model, &settings, &Progress::new(), &CancelToken::new()).unwrap();
        assert!(!native.triangles.is_empty(), "{name}: empty mesh");
        assert!(
            pack_mesh(&native) == packed,
            "{name}: the bindings' mesh differs from the native one"
        );
        fixture.push(serde_json::json!({
            "name": name,
            "depth": depth,
            "bounds": bounds,
            "vertices": native.positions.len(),
            "triangles": native.triangles.len(),
            "colors": !native.colors.is_empty(),
            "fnv1a": fnv1a(&packed),
        }));
        assert!(kernel.free(compiled.handle));
    }
    let text = serde_json::to_string_pretty(&serde_json::json!({
        "about": "Summaries of native meshes (crates/frep-wasm/tests/native_mesh.rs; FREP_BLESS=1 rewrites): the WebAssembly build must produce the same packed bytes",
        "meshes": fixture,
    }))
    .unwrap()
        + "\n";
    let path = root().join("web/tests/node/fixtures/meshes.json");
    if std::env::var_os("FREP_BLESS").is_some() {
        std::fs::write(&path, &text).unwrap();
    } else {
        let old = std::fs::read_to_string(&path).unwrap_or_default();
        assert!(
            old == text,
            "{} is stale: run FREP_BLESS=1 cargo test -p frep-wasm",
            path.display()
        );
    }
}

#[test]
fn errors_are_reported_not_panics() {
    let mut kernel = Kernel::new();
    let bad = kernel.compile(
        "my_model(x[3], a[1]) { my_model = 1 - ; }",
        &Default::default(),
    );
    assert!(!bad.ok);
    assert_eq!(bad.handle, 0);
    assert_eq!(bad.diagnostics.len(), 1);
    assert_eq!(bad.diagnostics[0].line, 1);
    assert!(bad.diagnostics[0].rendered.contains('^'));
    assert!(kernel.outputs(7).is_err());
    let ok = kernel.compile(
        "my_model(x[3], a[1]) { my_model = a[1] - x[1]*x[1] - x[2]*x[2] - x[3]*x[3]; }",
        &CompileRequest {
            params: vec![1.0],
            ..Default::default()
        },
    );
    assert!(ok.ok);
    assert_eq!(ok.bounds_origin, "extent");
    let b = ok.bounds.unwrap();
    assert!(b[0] < -1.0 && b[0] > -1.2, "{b:?}");
    let mut out = Vec::new();
    assert!(kernel
        .eval_points(ok.handle, &[0.0, 0.0], &[1.0], &mut out)
        .is_err());
    assert_eq!(
        kernel
            .eval_points(ok.handle, &[0.0, 0.5, 0.0, 0.0, 0.0, 0.0], &[2.0], &mut out)
            .unwrap(),
        1
    );
    assert_eq!(out, vec![2.0, 1.75]);
    // The kept buffer is rewritten whole, whatever it held.
    out.fill(f64::INFINITY);
    assert_eq!(
        kernel
            .eval_points(ok.handle, &[0.0, 0.5, 0.0, 0.0, 0.0, 0.0], &[2.0], &mut out)
            .unwrap(),
        1
    );
    assert_eq!(out, vec![2.0, 1.75]);
    kernel
        .eval_points(ok.handle, &[1.0, 0.0, 0.0], &[2.0], &mut out)
        .unwrap();
    assert_eq!(out, vec![1.0]);
    let deep = MeshRequest {
        bounds: b,
        depth: 14,
        method: None,
        params: vec![1.0],
        colors: None,
        max_triangles: None,
        max_depth: None,
    };
    let e = kernel.polygonize(ok.handle, &deep).unwrap_err();
    assert!(e.0.contains("depth"), "{e}");
    let odd = MeshRequest {
        method: Some("cubes".into()),
        depth: 3,
        ..deep
    };
    assert!(kernel.polygonize(ok.handle, &odd).is_err());
    // A division by ~0 is the reference interpreter's runtime error.
    let div = kernel.compile(
        "my_model(x[3], a[1]) { my_model = 1 / x[1]; }",
        &Default::default(),
    );
    assert_eq!(
        kernel.eval_point(div.handle, [0.0, 1.0, 1.0], &[]).unwrap(),
        Err("Division by zero".to_string())
    );
    assert_eq!(
        kernel.eval_point(div.handle, [2.0, 1.0, 1.0], &[]).unwrap(),
        Ok(vec![0.5])
    );
}

#[test]
fn shader_is_the_glsl_crates() {
    let mut kernel = Kernel::new();
    let src = std::fs::read_to_string(root().join("examples/sphere.hf")).unwrap();
    let c = kernel.compile(&src, &Default::default());
    let a = kernel.shader(c.handle, &Default::default()).unwrap();
    assert!(a.source.starts_with("#version 300 es"));
    assert_eq!(a.bounds, c.bounds.unwrap());
    assert!(a.statements > 0);
    assert!(a.uniforms.iter().any(|u| u.name == "u_consts"));
    // The studio's target: the viewer's camera and section, no camera matrix.
    assert!(a.uniforms.iter().any(|u| u.name == "u_eye"));
    assert!(a.uniforms.iter().any(|u| u.name == "u_section"));
    assert!(!a.uniforms.iter().any(|u| u.name == "u_inv_view_proj"));
    assert!(kernel
        .shader(
            c.handle,
            &frep_wasm::ShaderRequest {
                bounds: Some([1.0, 0.0, 0.0, 0.0, 1.0, 1.0]),
                params: Vec::new()
            }
        )
        .is_err());
}
