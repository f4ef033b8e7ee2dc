//! `frep mesh`: methods and options end to end.

use std::path::Path;
use std::process::Command;

fn frep() -> Command {
    Command::new(env!("CARGO_BIN_EXE_frep"))
}

fn example(name: &str) -> String {
    format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// Triangles of an OBJ file written by `frep mesh`.
fn faces(path: &Path) -> usize {
    let text = std::fs::read_to_string(path).unwrap();
    text.lines().filter(|l| l.starts_with("f ")).count()
}

#[test]
fn adaptive_dual_contouring_makes_fewer_triangles() {
    let dir = std::env::temp_dir().join(format!("frep-cli-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = |out: &Path, extra: &[&str]| {
        frep()
            .args([
                "mesh",
                &example("m1_sphere.hf"),
                "-q",
                "-d",
                "6",
                "-m",
                "dc",
                "-o",
            ])
            .arg(out)
            .args(extra)
            .status()
            .unwrap()
    };
    let (full, adaptive) = (dir.join("full.obj"), dir.join("adaptive.obj"));
    assert!(mesh(&full, &[]).success());
    assert!(mesh(&adaptive, &["--adaptive", "0.1"]).success());
    let (n, a) = (faces(&full), faces(&adaptive));
    assert!(n > 10_000 && a * 3 < n, "{a} of {n}");
    // Dual contouring only, and a sensible threshold.
    let wt = frep()
        .args([
            "mesh",
            &example("m1_sphere.hf"),
            "-q",
            "-d",
            "5",
            "--adaptive",
            "0.1",
            "-o",
        ])
        .arg(dir.join("wt.obj"))
        .output()
        .unwrap();
    assert!(!wt.status.success());
    assert!(String::from_utf8_lossy(&wt.stderr).contains("--adaptive needs --method dc"));
    let neg = frep()
        .args([
            "mesh",
            &example("m1_sphere.hf"),
            "-q",
            "-m",
            "dc",
            "--adaptive=-1",
            "-o",
        ])
        .arg(dir.join("neg.obj"))
        .output()
        .unwrap();
    assert!(!neg.status.success());
    let _ = std::fs::remove_dir_all(&dir);
}
