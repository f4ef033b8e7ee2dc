/**
 * Mode 4a's fragment shader is frep-glsl's, whole: the model's field
 * functions, the viewer's scene (camera, section plane, background,
 * lighting: frep-glsl's scene.glsl), the ray traversal and the viewer's
 * `main`, as the server's `shader` artefact or the WebAssembly kernel
 * deliver it (frep-glsl's `ShaderTarget::Viewer`; the same Rust). The
 * studio writes no GLSL of its own here: it compiles the source and sets
 * uniforms by name (the model's from the artefact's table, the scene's
 * from raycast-scene.ts).
 */
export { SCENE_UNIFORMS, VERTEX_SHADER } from './scene-glsl';

/** The delivered source, checked to be frep-glsl's viewer shader. */
export function viewerShader(source: string): string {
  if (!source.startsWith('#version 300 es') || !/\buniform vec3 u_eye;/.test(source) || !source.includes('hf_trace(')) {
    throw new Error("the shader artefact is not frep-glsl's viewer shader (no viewer camera or traversal)");
  }
  return source;
}
