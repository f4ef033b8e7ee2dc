//! The studio's copy of the viewer scene is generated, not written by hand:
//! web/src/viewer/modes/scene-glsl.ts holds [`frep_glsl::SCENE`],
//! [`frep_glsl::SCENE_UNIFORMS`] and the vertex shader for the volume mode
//! (and mode 4a's full-screen triangle); the volume ray marches a
//! texture with the same camera, section and lighting as mode 4a. This test
//! fails when the committed file differs; `FREP_BLESS=1` rewrites it.

use std::path::PathBuf;

fn typescript() -> String {
    let mut out = String::from(
        "// Generated from crates/frep-glsl by `FREP_BLESS=1 cargo test -p frep-glsl`.\n\
         // Do not edit: change crates/frep-glsl/src/scene.glsl instead.\n\n\
         /** The viewer's scene (GLSL, no `#version`): frep-glsl's `SCENE`. */\n\
         export const SCENE_GLSL = `\n",
    );
    // A template literal: backquotes and `${` would end or interpolate it.
    assert!(!frep_glsl::SCENE.contains('`') && !frep_glsl::SCENE.contains("${"));
    out.push_str(frep_glsl::SCENE);
    out.push_str("`;\n\n/** The uniforms `SCENE_GLSL` declares (frep-glsl's `SCENE_UNIFORMS`). */\nexport const SCENE_UNIFORMS = [\n");
    for (name, _) in frep_glsl::SCENE_UNIFORMS {
        out.push_str(&format!("  '{name}',\n"));
    }
    out.push_str("] as const;\n\n/** The vertex shader: one full-screen triangle (frep-glsl's `vertex_shader`). */\nexport const VERTEX_SHADER = `");
    out.push_str(frep_glsl::vertex_shader());
    out.push_str("`;\n");
    out
}

#[test]
fn web_scene_glsl_ts_is_fresh() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../web/src/viewer/modes/scene-glsl.ts");
    let want = typescript();
    if std::env::var_os("FREP_BLESS").is_some() {
        std::fs::write(&path, &want).unwrap();
        return;
    }
    let have = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        have == want,
        "{} is stale: run `FREP_BLESS=1 cargo test -p frep-glsl --test scene_ts` and commit it",
        path.display()
    );
}

#[test]
fn every_scene_uniform_is_declared_once() {
    for (name, ty) in frep_glsl::SCENE_UNIFORMS {
        let decl = format!("uniform {ty} {name};");
        assert_eq!(frep_glsl::SCENE.matches(&decl).count(), 1, "{decl}");
    }
    assert_eq!(
        frep_glsl::SCENE.matches("uniform ").count(),
        frep_glsl::SCENE_UNIFORMS.len()
    );
}
