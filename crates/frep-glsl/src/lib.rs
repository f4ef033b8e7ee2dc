//! # frep-glsl
//!
//! GLSL ES 3.00 (WebGL2) generated from a frep [`Tape`]: the model's graph as
//! straight-line code, and a fragment shader that ray casts it.
//!
//! ## What is generated
//! * `float field(vec3 p)` — the point value (`f >= 0` inside);
//! * `vec2 field_iv(vec2 x, vec2 y, vec2 z)` — bounds `[lo, hi]` of the field
//!   over a box, with tight rules per operation. R-functions and blends go
//!   by monotonicity, `sin`/`cos` by their extrema. Even powers and `abs`
//!   have their own rules, products take four corners, comparisons give
//!   `[0, 1]` when undecided, and selects are decided or hulled.
//!   - Intervals never hold NaN. Where an operation may fail, the bound is
//!     `[-inf, +inf]`, which stays sound downstream of `min`, `max` and
//!     selects. Examples: a checked division whose divisor meets
//!     `|b| < 1e-6`, or `sqrt` of a range reaching below 0.
//!   - Bounds are computed in f32 without outward rounding. Pruning may be
//!     off by an ulp; the final point bisection decides the hit;
//! * `vec4 field_grad(vec3 p)` — value and gradient by forward-mode dual
//!   numbers (one call site in the shader);
//! * `vec3 attrs(vec3 p)` — the attributes `s[1..3]` when the tape has at
//!   least four outputs (value, s1, s2, s3).
//!
//! ## Rules for software WebGL (SwiftShader)
//! SwiftShader compiles at the first draw and inlines every call. So:
//! - the helpers of the prelude are branch-free and loop-free. Selects go
//!   through `mix` with a bool, with one `return`. Integer powers `x ^ n` go
//!   through generated straight-line `hf_pwK` squarings.
//! - the ray caster calls each field function from exactly one place, in one
//!   loop bounded by a uniform. It uses no stack array, but an implicit
//!   binary tree of ray segments.
//!
//! With branchy helpers, the first frame of a chain of nine R-unions (129
//! nodes) took more than a minute. It now takes 0.7 s at 64²
//! (`tests/browser.rs` measures it).
//!
//! Each function is straight-line SSA: one statement per live tape node
//! (`float t12 = t3 + t7;`), operands always temporaries. So nesting depth is
//! bounded by a small constant whatever the model; ANGLE rejects expressions
//! nested past ~250. Shared subexpressions (the tape is hash-consed) are
//! computed once. Generation is linear in the tape length.
//!
//! ## Semantics
//! Point values follow [`frep_core::ops`] in f32:
//! - runtime errors of the reference interpreter become NaN: checked
//!   division `|b| < 1e-6`, HyperFun's `^`, `sqrt`/`log` domains,
//!   [`Node::Error`];
//! - `Check(g, v)` is `v`, truth is `|v| >= 1e-6`, comparisons are 1.0/0.0;
//! - `min`/`max` are `a < b ? a : b` / `a > b ? a : b`;
//! - `mod` is C `fmod` of the half-up rounded operands (GLSL `mod` is
//!   floor-based), `int` truncates;
//! - R-functions use a cancellation-free form (see [`f32ref`]).
//!
//! ## Uniforms (editing a number never recompiles)
//! * `uniform float u_params[N]` — the model parameters `a[1..N]`;
//! * `uniform vec4 u_consts[K]` — **every** constant of the tape, packed four
//!   to a `vec4`: constant `j` is `u_consts[j / 4]` component `j % 4`.
//!   - The packing lets a model of a thousand primitives fit WebGL's
//!     uniform-vector limit. A `float[]` uses a whole vector per element on
//!     many implementations.
//!   - The rule is simply "every `Const` node of the tape": 0 and 1 included.
//!   - What is *not* a uniform is structural: the integer exponent of
//!     `x ^ n` (a [`Node::PowI`], e.g. `x^2`), the `1e-6` tolerance, and the
//!     literals of the helpers.
//!   - Changing such a number changes the source. So does any edit after
//!     which constant folding gives a different tape structure.
//!   - So a client should regenerate the shader after every edit. It
//!     recompiles only when [`Shader::source`] differs, and otherwise just
//!     uploads the new uniform values.
//!   - Above [`ShaderOptions::max_uniform_consts`] constants, every constant
//!     is inlined as a literal instead ([`ShaderStats::consts_inlined`]).
//! * `uniform float u_xextra[K]` — coordinate slots `x[4]...` (models
//!   declaring `x[4]` or more);
//! * the ray caster's, by [`ShaderTarget`]. Both trace rays the same way
//!   (trace.glsl; `u_max_steps` caps interval evaluations per pixel,
//!   magenta when hit) and differ in camera and shading:
//!   - `Standalone` (`frep glsl`): `u_resolution`, `u_inv_view_proj`
//!     (column-major; see [`Camera`]), `u_box_min`, `u_box_max`,
//!     `u_max_steps`, `u_background`, all with defaults;
//!   - `Viewer` (the studio's mode 4a, through the `shader` artefact and the
//!     WebAssembly kernel): the viewer's camera, section plane, background
//!     and lighting, [`SCENE_UNIFORMS`] declared by [`SCENE`]. The studio
//!     sets them; its volume mode uses the same scene (a generated copy,
//!     web/src/viewer/modes/scene-glsl.ts).
//!
//! [`Shader::uniforms`] lists every uniform with its GLSL type, default
//! values and a description; [`Shader::uniforms_json`] gives the same as
//! JSON. This crate does no I/O.
#![warn(missing_docs)]

pub mod camera;
mod emit;
pub mod f32ref;

use std::fmt::Write as _;

use frep_core::{Model, Node, Tape};

pub use camera::Camera;
use emit::{Flavour, Leaves};

/// The GLSL helper functions every generated field uses (no `#version`).
pub const PRELUDE: &str = include_str!("prelude.glsl");

/// The studio's scene (GLSL, no `#version`): camera, section and lighting
/// uniforms and helpers shared by its client-drawn modes. The volume mode
/// uses it too (web/src/viewer/modes/scene-glsl.ts is generated from it).
pub const SCENE: &str = concat!(include_str!("box.glsl"), include_str!("scene.glsl"));

/// The uniforms [`SCENE`] declares, which the studio sets from its camera.
pub const SCENE_UNIFORMS: [(&str, &str); 26] = [
    ("u_resolution", "vec2"),
    ("u_eye", "vec3"),
    ("u_right", "vec3"),
    ("u_up", "vec3"),
    ("u_forward", "vec3"),
    ("u_k", "float"),
    ("u_perspective", "float"),
    ("u_box_min", "vec3"),
    ("u_box_max", "vec3"),
    ("u_max_steps", "int"),
    ("u_bg_top", "vec3"),
    ("u_bg_bottom", "vec3"),
    ("u_base", "vec3"),
    ("u_cap", "vec3"),
    ("u_key", "vec3"),
    ("u_fill", "vec3"),
    ("u_rim", "vec3"),
    ("u_key_color", "vec3"),
    ("u_fill_color", "vec3"),
    ("u_rim_color", "vec3"),
    ("u_sky", "vec3"),
    ("u_ground", "vec3"),
    ("u_specular", "float"),
    ("u_shininess", "float"),
    ("u_section", "vec4"),
    ("u_section_on", "float"),
];

const BOX: &str = include_str!("box.glsl");
const TRACE: &str = include_str!("trace.glsl");
const STANDALONE_SCENE: &str = include_str!("standalone_scene.glsl");
const STANDALONE_MAIN: &str = include_str!("standalone_main.glsl");
const VIEWER_MAIN: &str = include_str!("viewer.glsl");

const HEADER: &str = "#version 300 es\nprecision highp float;\nprecision highp int;\n";

/// One uniform of a generated shader.
#[derive(Clone, Debug, PartialEq)]
pub struct UniformInfo {
    /// The GLSL name (`u_consts`, `u_params`, ...).
    pub name: String,
    /// The GLSL type, with the array size (`float[3]`, `vec4[2]`, `mat4`,
    /// `int`): it tells the client which `gl.uniform*` to call.
    pub ty: String,
    /// Default values, flattened (a `vec4[K]` has `4K` values, a `mat4` 16
    /// in column-major order, an `int` one value).
    pub values: Vec<f32>,
    /// What the uniform is.
    pub description: String,
}

/// Sizes of the generated code.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ShaderStats {
    /// Nodes in the tape.
    pub tape_nodes: usize,
    /// Statements in `field` (the same number in `field_iv` and `field_grad`).
    pub statements: usize,
    /// Statements in `attrs` (0 without attributes).
    pub attr_statements: usize,
    /// Number of constants (uniform slots, or literals when inlined).
    pub consts: usize,
    /// Whether constants were inlined as literals (too many for uniforms).
    pub consts_inlined: bool,
    /// Size of `u_params`.
    pub params: usize,
    /// Whether `attrs()` was generated.
    pub attributes: bool,
}

/// A generated shader (or shader fragment) and its uniforms.
#[derive(Clone, Debug, PartialEq)]
pub struct Shader {
    /// GLSL source.
    pub source: String,
    /// Every uniform the source declares, with default values.
    pub uniforms: Vec<UniformInfo>,
    /// Code size figures.
    pub stats: ShaderStats,
}

/// Choices for the generated shaders.
#[derive(Clone, Debug, PartialEq)]
pub struct ShaderOptions {
    /// Lower corner of the bounding box (HyperFun's default box is
    /// `[-10, 10]³`).
    pub box_min: [f64; 3],
    /// Upper corner of the bounding box.
    pub box_max: [f64; 3],
    /// Default viewport size in pixels (`u_resolution`).
    pub resolution: [u32; 2],
    /// Default camera; `None` frames the box ([`Camera::framing`]).
    pub camera: Option<Camera>,
    /// Default cap on interval evaluations per pixel (`u_max_steps`).
    pub max_steps: u32,
    /// Default parameter values `a[1..]`; `u_params` has at least this many
    /// slots (missing values are 0).
    pub params: Vec<f64>,
    /// Default values of the coordinate slots `x[4]...` (missing are 0).
    pub extra_x: Vec<f64>,
    /// Most constants held as uniforms; beyond, all are inlined literals.
    pub max_uniform_consts: usize,
    /// Background colour (linear RGB).
    pub background: [f32; 3],
    /// Which ray caster follows the field functions.
    pub target: ShaderTarget,
}

/// The ray caster a fragment shader carries (both trace rays the same way,
/// trace.glsl).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ShaderTarget {
    /// Self-contained: a camera matrix and every uniform with a default
    /// (`frep glsl`; see the uniforms in the crate doc).
    #[default]
    Standalone,
    /// The studio's mode 4a: its camera, section plane, background and
    /// lighting ([`SCENE`], [`SCENE_UNIFORMS`]), which the studio sets.
    Viewer,
}

impl Default for ShaderOptions {
    fn default() -> Self {
        ShaderOptions {
            box_min: [-10.0; 3],
            box_max: [10.0; 3],
            resolution: [512, 512],
            camera: None,
            max_steps: 512,
            params: Vec::new(),
            extra_x: Vec::new(),
            max_uniform_consts: 4096,
            background: [0.12, 0.13, 0.15],
            target: ShaderTarget::Standalone,
        }
    }
}

/// The field functions of `tape`, with the helper prelude and the model's
/// uniform declarations, for a client that brings its own renderer. They are
/// `field`, `field_iv`, `field_grad`, and `attrs` when the tape has at least
/// four outputs. There is no `#version` or `main`. `tape.outputs[0]` is the
/// value.
pub fn field_library(tape: &Tape, opts: &ShaderOptions) -> Shader {
    assert!(!tape.outputs.is_empty(), "the tape has no output");
    let attr_outs =
        (tape.outputs.len() >= 4).then(|| [tape.outputs[1], tape.outputs[2], tape.outputs[3]]);
    let mut all_outs = vec![tape.outputs[0]];
    all_outs.extend(attr_outs.iter().flatten());
    let live = emit::live_nodes(tape, &all_outs);
    let leaves = Leaves::new(tape, &live, opts.max_uniform_consts);

    let mut n_params = opts.params.len();
    let mut n_extra = opts.extra_x.len();
    for (i, n) in tape.nodes.iter().enumerate() {
        match *n {
            Node::Param(k) if live[i] => n_params = n_params.max(k as usize + 1),
            Node::X(k) if live[i] && k >= 3 => n_extra = n_extra.max(k as usize - 2),
            _ => {}
        }
    }

    let mut uniforms = Vec::new();
    let mut src = String::with_capacity(PRELUDE.len() + 200 * tape.len());
    src.push_str("// ---- model uniforms ----\n");
    if n_params > 0 {
        let _ = writeln!(src, "uniform float u_params[{n_params}];");
        uniforms.push(UniformInfo {
            name: "u_params".into(),
            ty: format!("float[{n_params}]"),
            values: (0..n_params)
                .map(|k| opts.params.get(k).copied().unwrap_or(0.0) as f32)
                .collect(),
            description: "model parameters a[1..]".into(),
        });
    }
    if n_extra > 0 {
        let _ = writeln!(src, "uniform float u_xextra[{n_extra}];");
        uniforms.push(UniformInfo {
            name: "u_xextra".into(),
            ty: format!("float[{n_extra}]"),
            values: (0..n_extra)
                .map(|k| opts.extra_x.get(k).copied().unwrap_or(0.0) as f32)
                .collect(),
            description: "coordinate slots x[4..] (beyond x, y, z)".into(),
        });
    }
    let n_consts = leaves.consts.iter().flatten().count();
    if !leaves.const_values.is_empty() {
        let k = leaves.const_values.len().div_ceil(4);
        let _ = writeln!(src, "uniform vec4 u_consts[{k}];");
        let mut values = leaves.const_values.clone();
        values.resize(4 * k, 0.0);
        uniforms.push(UniformInfo {
            name: "u_consts".into(),
            ty: format!("vec4[{k}]"),
            values,
            description: format!(
                "the model's {} constants in tape order, four to a vec4 (constant j is u_consts[j/4][j%4])",
                leaves.const_values.len()
            ),
        });
    }
    src.push_str(PRELUDE);
    src.push_str("// ---- model ----\n");
    emit::power_functions(&mut src, tape, &live);
    let out = tape.outputs[0];
    let statements = emit::field_function(&mut src, Flavour::Point, tape, out, &leaves);
    emit::field_function(&mut src, Flavour::Interval, tape, out, &leaves);
    emit::field_function(&mut src, Flavour::Dual, tape, out, &leaves);
    let attr_statements = match attr_outs {
        Some(outs) => emit::attrs_function(&mut src, tape, outs, &leaves),
        None => 0,
    };
    Shader {
        source: src,
        uniforms,
        stats: ShaderStats {
            tape_nodes: tape.len(),
            statements,
            attr_statements,
            consts: n_consts,
            consts_inlined: leaves.inlined,
            params: n_params,
            attributes: attr_outs.is_some(),
        },
    }
}

/// A complete GLSL ES 3.00 fragment shader ray casting `tape` (see the crate
/// docs). Draw it with [`vertex_shader`] as one full-screen triangle:
/// `gl.drawArrays(gl.TRIANGLES, 0, 3)`, no attributes.
pub fn fragment_shader(tape: &Tape, opts: &ShaderOptions) -> Shader {
    match opts.target {
        ShaderTarget::Standalone => standalone_shader(tape, opts),
        ShaderTarget::Viewer => viewer_shader(tape, opts),
    }
}

/// The studio's shader: the field functions, [`SCENE`], the traversal and
/// the viewer's `main`. The scene uniforms have no defaults (the studio
/// sets them); the model's do.
fn viewer_shader(tape: &Tape, opts: &ShaderOptions) -> Shader {
    let lib = field_library(tape, opts);
    let parts = [SCENE, TRACE, VIEWER_MAIN];
    let mut src =
        String::with_capacity(lib.source.len() + parts.iter().map(|p| p.len()).sum::<usize>() + 64);
    src.push_str(HEADER);
    src.push_str(&lib.source);
    let _ = writeln!(src, "#define HF_ATTRS {}", u8::from(lib.stats.attributes));
    for p in parts {
        src.push_str(p);
    }
    let mut uniforms = lib.uniforms;
    uniforms.extend(SCENE_UNIFORMS.iter().map(|(name, ty)| UniformInfo {
        name: (*name).into(),
        ty: (*ty).into(),
        values: Vec::new(),
        description: "the viewer's scene (set by the studio)".into(),
    }));
    Shader {
        source: src,
        uniforms,
        stats: lib.stats,
    }
}

fn standalone_shader(tape: &Tape, opts: &ShaderOptions) -> Shader {
    let lib = field_library(tape, opts);
    let parts = [BOX, STANDALONE_SCENE, TRACE, STANDALONE_MAIN];
    let mut src = String::with_capacity(
        lib.source.len() + parts.iter().map(|p| p.len()).sum::<usize>() + 512,
    );
    src.push_str(HEADER);
    src.push_str(&lib.source);
    if lib.stats.attributes {
        src.push_str("vec3 hf_material(vec3 p) {\n  vec3 c = attrs(p);\n  return any(isnan(c)) ? vec3(0.8) : clamp(c, 0.0, 1.0);\n}\n");
    } else {
        src.push_str("vec3 hf_material(vec3 p) { return vec3(0.85, 0.62, 0.38); }\n");
    }
    for p in parts {
        src.push_str(p);
    }

    let mut uniforms = lib.uniforms;
    let [w, h] = opts.resolution;
    let cam = opts
        .camera
        .clone()
        .unwrap_or_else(|| Camera::framing(opts.box_min, opts.box_max));
    let f3 = |v: [f64; 3]| v.iter().map(|&x| x as f32).collect::<Vec<_>>();
    let mut add = |name: &str, ty: &str, values: Vec<f32>, description: &str| {
        uniforms.push(UniformInfo {
            name: name.into(),
            ty: ty.into(),
            values,
            description: description.into(),
        })
    };
    add(
        "u_resolution",
        "vec2",
        vec![w as f32, h as f32],
        "viewport size in pixels",
    );
    add(
        "u_inv_view_proj",
        "mat4",
        cam.inv_view_proj(f64::from(w) / f64::from(h.max(1)))
            .to_vec(),
        "inverse of projection x view, column-major (NDC to world; perspective or orthographic)",
    );
    add(
        "u_box_min",
        "vec3",
        f3(opts.box_min),
        "bounding box, lower corner",
    );
    add(
        "u_box_max",
        "vec3",
        f3(opts.box_max),
        "bounding box, upper corner",
    );
    add(
        "u_max_steps",
        "int",
        vec![opts.max_steps as f32],
        "cap on interval evaluations per pixel (magenta where reached)",
    );
    add(
        "u_background",
        "vec3",
        opts.background.to_vec(),
        "background colour (linear RGB)",
    );
    Shader {
        source: src,
        uniforms,
        stats: lib.stats,
    }
}

/// The vertex shader to pair with [`fragment_shader`]: one full-screen
/// triangle from `gl_VertexID`, no vertex attributes.
pub fn vertex_shader() -> &'static str {
    "#version 300 es\nvoid main() {\n  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n}\n"
}

/// The ray-casting fragment shader of a compiled model. It casts the value.
/// When the body declares `s[]` with at least three items, the attributes
/// `s[1..3]` give the colour. `u_params` is sized to the model's `a[]`.
pub fn shader_for_model(model: &Model, opts: &ShaderOptions) -> Shader {
    let tape = model.tape_with_attributes();
    let mut opts = opts.clone();
    if opts.params.len() < model.a_dim {
        opts.params.resize(model.a_dim, 0.0);
    }
    fragment_shader(&tape, &opts)
}

fn json_str(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

impl Shader {
    /// The shader and its uniform table as frep-wire's `ShaderArtefact`,
    /// ray casting `bounds` (`[x0, y0, z0, x1, y1, z1]`).
    #[cfg(feature = "wire")]
    pub fn into_wire(self, bounds: [f64; 6]) -> frep_wire::ShaderArtefact {
        frep_wire::ShaderArtefact {
            source: self.source,
            uniforms: self
                .uniforms
                .into_iter()
                .map(|u| frep_wire::ShaderUniform {
                    name: u.name,
                    ty: u.ty,
                    values: u.values,
                    description: u.description,
                })
                .collect(),
            bounds,
            statements: self.stats.statements as u32,
        }
    }

    /// The uniforms as JSON:
    /// `{"uniforms":[{"name":…,"type":…,"values":[…],"description":…},…]}`
    /// (non-finite values, possible only for constants, are `null`).
    pub fn uniforms_json(&self) -> String {
        let mut out = String::from("{\"uniforms\":[");
        for (i, u) in self.uniforms.iter().enumerate() {
            if i > 0 {
                out.push(',');
            }
            out.push_str("\n{\"name\":");
            json_str(&mut out, &u.name);
            out.push_str(",\"type\":");
            json_str(&mut out, &u.ty);
            out.push_str(",\"values\":[");
            for (k, v) in u.values.iter().enumerate() {
                if k > 0 {
                    out.push(',');
                }
                if v.is_finite() {
                    let _ = write!(out, "{v:?}");
                } else {
                    out.push_str("null");
                }
            }
            out.push_str("],\"description\":");
            json_str(&mut out, &u.description);
            out.push('}');
        }
        out.push_str("\n]}\n");
        out
    }

    /// The source with a comment block listing every uniform's name, type
    /// and default values, placed after the `#version` line (which must stay
    /// first). Long value lists are cut after 64 values.
    pub fn annotated_source(&self) -> String {
        let mut block = String::from("// Uniforms (name type = default values):\n");
        for u in &self.uniforms {
            let shown: Vec<String> = u.values.iter().take(64).map(|v| format!("{v:?}")).collect();
            let more = if u.values.len() > 64 { ", ..." } else { "" };
            let _ = writeln!(
                block,
                "//   {} {} = [{}{more}]  -- {}",
                u.name,
                u.ty,
                shown.join(", "),
                u.description
            );
        }
        match self.source.split_once('\n') {
            Some((first, rest)) if first.starts_with("#version") => {
                format!("{first}\n{block}{rest}")
            }
            _ => format!("{block}{}", self.source),
        }
    }
}
