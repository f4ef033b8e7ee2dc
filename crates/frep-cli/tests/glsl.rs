//! `frep glsl` writes the annotated shader and its uniforms.

use std::process::Command;

fn frep() -> Command {
    Command::new(env!("CARGO_BIN_EXE_frep"))
}

fn example(name: &str) -> String {
    format!("{}/../../examples/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn glsl_writes_shader_and_uniforms() {
    let dir = std::env::temp_dir().join(format!("frep-cli-glsl-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("robot.frag");
    let st = frep()
        .args(["glsl", &example("android_robot.hf"), "-o"])
        .arg(&out)
        .status()
        .unwrap();
    assert!(st.success());
    let src = std::fs::read_to_string(&out).unwrap();
    assert!(
        src.starts_with("#version 300 es\n// Uniforms"),
        "{}",
        &src[..80]
    );
    assert!(src.contains("vec2 field_iv(vec2 x, vec2 y, vec2 z)"));
    assert!(src.contains("vec3 attrs(vec3 p)"));
    let json = std::fs::read_to_string(dir.join("robot.frag.json")).unwrap();
    assert!(json.contains("\"name\":\"u_consts\""));
    // The box of the `-- bounds:` line.
    assert!(
        json.contains("\"name\":\"u_box_min\",\"type\":\"vec3\",\"values\":[-0.85,-0.65,-1.05]"),
        "{json}"
    );

    // --bounds overrides it; --body picks a body.
    let out2 = dir.join("m1.frag");
    let st = frep()
        .args([
            "glsl",
            &example("m1_sphere.hf"),
            "--bounds",
            "-2,-2,-2,2,2,2",
            "--body",
            "my_model",
            "--param",
            "0.5",
            "-o",
        ])
        .arg(&out2)
        .status()
        .unwrap();
    assert!(st.success());
    let json = std::fs::read_to_string(dir.join("m1.frag.json")).unwrap();
    assert!(
        json.contains("\"u_box_max\",\"type\":\"vec3\",\"values\":[2.0,2.0,2.0]"),
        "{json}"
    );

    assert!(
        json.contains("\"name\":\"u_params\",\"type\":\"float[1]\",\"values\":[0.5]"),
        "{json}"
    );

    // Bad bounds: an error, exit status 2.
    let o = frep()
        .args([
            "glsl",
            &example("m1_sphere.hf"),
            "--bounds",
            "1,2,3,4",
            "-o",
        ])
        .arg(dir.join("bad.frag"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--bounds"));

    // A model error: exit status 1 with the diagnostic.
    let bad = dir.join("bad.hf");
    std::fs::write(&bad, "my_model(x[3]) { my_model = ; }").unwrap();
    let o = frep()
        .args(["glsl"])
        .arg(&bad)
        .arg("-o")
        .arg(dir.join("bad2.frag"))
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    let _ = std::fs::remove_dir_all(&dir);
}
