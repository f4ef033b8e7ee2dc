// ---- the standalone ray caster: uniforms and camera ------------------------
// The camera is u_inv_view_proj (see camera.rs); the box, the step cap and
// the background come with defaults (`frep glsl`, the browser test). The
// traversal (trace.glsl) and main (standalone_main.glsl) follow.
uniform vec2 u_resolution;
uniform mat4 u_inv_view_proj;
uniform vec3 u_box_min;
uniform vec3 u_box_max;
uniform int u_max_steps;
uniform vec3 u_background;
out vec4 frag_color;

void hf_ray(vec2 frag, out vec3 o, out vec3 d) {
  vec2 ndc = frag / u_resolution * 2.0 - 1.0;
  vec4 a = u_inv_view_proj * vec4(ndc, -1.0, 1.0);
  vec4 b = u_inv_view_proj * vec4(ndc, 0.0, 1.0);
  o = a.xyz / a.w;
  d = normalize(b.xyz / b.w - o);
}

// Linear RGB to the (approximately sRGB) output.
vec4 hf_output(vec3 c) { return vec4(pow(clamp(c, 0.0, 1.0), vec3(1.0 / 2.2)), 1.0); }
