//! The .glb outputs checked by the official Khronos glTF validator (npm `gltf-validator`);
//! meshopt files are also decompressed with meshoptimizer's JavaScript decoder (what three.js
//! uses) and validated again, since the validator does not implement the extension.
//!
//! Needs `node` and `npm` with access to the npm registry (or its cache) the first time; the
//! package is installed under `target/tmp/npm`. Without them the test fails, unless
//! `FREP_SKIP_NODE=1` is set.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

use common::{cube, torus, uv_sphere};
use frep_mesh::export::to_bytes;
use frep_mesh::{Format, Mesh};

/// The npm packages the check needs, pinned.
const PACKAGES: [&str; 2] = ["gltf-validator@2.0.0-dev.3.10", "meshoptimizer@1.0.1"];

fn skip_or_fail(why: &str) {
    if std::env::var("FREP_SKIP_NODE").as_deref() == Ok("1") {
        eprintln!("skipping the Khronos glTF validator: {why}");
    } else {
        panic!("{why}; install node and npm (or set FREP_SKIP_NODE=1 to skip this check)");
    }
}

/// The directory holding `node_modules/gltf-validator`, installing it when missing.
fn validator_prefix() -> Result<PathBuf, String> {
    let prefix = Path::new(env!("CARGO_TARGET_TMPDIR")).join("npm");
    let installed = ["gltf-validator", "meshoptimizer"].iter().all(|p| {
        prefix
            .join("node_modules")
            .join(p)
            .join("package.json")
            .exists()
    });
    if installed {
        return Ok(prefix);
    }
    std::fs::create_dir_all(&prefix).map_err(|e| e.to_string())?;
    let status = Command::new("npm")
        .args(["install", "--no-audit", "--no-fund", "--prefix"])
        .arg(&prefix)
        .args(PACKAGES)
        .status()
        .map_err(|e| format!("cannot run npm: {e}"))?;
    if !status.success() {
        return Err(format!(
            "`npm install {}` failed ({status})",
            PACKAGES.join(" ")
        ));
    }
    Ok(prefix)
}

#[test]
fn khronos_validator_accepts_the_glb_outputs() {
    if Command::new("node").arg("--version").output().is_err() {
        return skip_or_fail("`node` is not installed");
    }
    let prefix = match validator_prefix() {
        Ok(p) => p,
        Err(why) => return skip_or_fail(&why),
    };
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("validate-glb");
    std::fs::create_dir_all(&dir).unwrap();
    let mut plain = torus(2.0, 0.5, 24, 12);
    plain.compute_normals();
    let meshes: [(&str, Mesh); 4] = [
        ("sphere", uv_sphere(1.0, 41, 40)),
        ("wide", uv_sphere(1.0, 250, 300)),
        ("torus", plain),
        ("cube", cube()),
    ];
    let mut files = Vec::new();
    for (name, mesh) in &meshes {
        for (format, suffix) in [(Format::Glb, "quantized"), (Format::GlbMeshopt, "meshopt")] {
            let path = dir.join(format!("{name}-{suffix}.glb"));
            std::fs::write(&path, to_bytes(mesh, format).unwrap()).unwrap();
            files.push(path);
        }
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/validate_glb.mjs");
    let out = Command::new("node")
        .arg(script)
        .arg(&prefix)
        .args(&files)
        .output()
        .unwrap();
    let report = String::from_utf8_lossy(&out.stdout);
    println!("{report}{}", String::from_utf8_lossy(&out.stderr));
    assert!(
        out.status.success(),
        "the glTF validator reported errors:\n{report}"
    );
    // Each meshopt file is validated twice: as is, and decompressed.
    assert_eq!(report.matches(": 0 errors").count(), files.len() / 2 * 3);
}
