//! Real models through the engine: the examples and, when present, the
//! corpus of HyperFun models written by others (read in place, never
//! copied). Their statistics are computed as the server computes them
//! (tape length, graph nodes, shader statements), and every client profile
//! must get a feasible, explained decision; the shader is refused exactly
//! for the models too big for a browser.

mod common;

use std::path::{Path, PathBuf};

use common::*;
use frep_adapt::{Measured, ModelStats};
use frep_core::{CompileOptions, Model};
use frep_glsl::{shader_for_model, ShaderOptions};
use frep_wire::Mode;

/// Longest tape whose shader is generated here (longer ones count their
/// tape as statements: generation is linear, but debug builds are slow).
const GENERATE_UP_TO: usize = 3000;

fn models() -> Vec<PathBuf> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let mut out = Vec::new();
    for dir in [
        root.join("examples"),
        PathBuf::from("/work/shared/hyperfun/corpus"),
    ] {
        let Ok(entries) = std::fs::read_dir(&dir) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.extension().is_some_and(|x| x == "hf") {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

/// The stats of a model file, or `None` when it does not compile.
fn stats(path: &Path) -> Option<ModelStats> {
    let source = std::fs::read_to_string(path).ok()?;
    let m = Model::compile_with(&source, &CompileOptions::default()).ok()?;
    let tape_len = m.tape().len();
    let statements = if tape_len <= GENERATE_UP_TO {
        shader_for_model(&m, &ShaderOptions::default())
            .stats
            .statements
    } else {
        tape_len
    };
    Some(ModelStats {
        tape_len: tape_len as u32,
        nodes: m.graph.len() as u32,
        closed_form: false,
        attributes: if m.has_attributes { m.s_dim as u32 } else { 0 },
        primitives: None,
        shader_statements: statements as u32,
        measured: Measured::default(),
    })
}

#[test]
fn every_model_gets_a_feasible_explained_decision_on_every_client() {
    let files = models();
    assert!(files.len() >= 10, "examples missing: {files:?}");
    let mut compiled = 0;
    for path in &files {
        let Some(s) = stats(path) else {
            continue;
        };
        compiled += 1;
        let name = path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        let profiles = [
            ("phone", phone(), net(1.5, 150.0)),
            ("no WebGL", desktop_without_webgl(), net(20.0, 30.0)),
            ("SwiftShader", laptop_swiftshader(), net(50.0, 20.0)),
            ("workstation", workstation(), lan()),
        ];
        for (profile, report, network) in profiles {
            let d = engine().connect(report, network, s.clone(), 0);
            let p = chosen(&d);
            assert!(p.feasible, "{name} on {profile}: {}", d.reason);
            assert!(!d.reason.is_empty());
            assert_eq!(d.predictions.len(), 6);
            if profile == "no WebGL" {
                assert!(
                    matches!(d.mode, Mode::Still | Mode::ViewSet),
                    "{name}: {}",
                    d.reason
                );
            }
            // The workstation refuses the shader only for what is too big
            // for a browser (about 1000 primitives, 5 operations each).
            if profile == "workstation" {
                let gpu = prediction(&d, Mode::GpuRaycast);
                assert_eq!(
                    gpu.feasible,
                    s.tape_len <= 5000,
                    "{name}: tape {} {:?}",
                    s.tape_len,
                    gpu.refusal
                );
            }
        }
    }
    assert!(compiled >= 10, "only {compiled} models compiled");
}

#[test]
fn a_hundred_spheres_ray_cast_on_a_workstation() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/m2_spheres100.hf");
    let s = stats(&path).expect("the example compiles");
    assert_eq!(s.primitives_estimate(), s.tape_len / 5);
    let d = engine().connect(workstation(), lan(), s, 0);
    assert_eq!(d.mode, Mode::GpuRaycast, "{}", d.reason);
}
