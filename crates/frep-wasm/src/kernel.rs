//! The safe half of the bindings: what each exported function does, in plain
//! Rust over slices and strings, so that native tests run the very code the
//! WebAssembly module runs.
//!
//! A [`Kernel`] holds compiled models in a table of handles (small positive
//! integers; 0 is never a handle). Every call delegates to the kernel crates:
//! frep-core compiles and evaluates, frep-mesh polygonizes, frep-glsl
//! generates the shader. Results leave as JSON (frep-wire's camelCase types
//! where one exists) or as the packed buffers of [`crate::buffers`].

use frep_core::eval::batch::BatchEval;
use frep_core::{CompileOptions, Inputs, Model, PointEval};
use frep_glsl::{shader_for_model, ShaderOptions, ShaderTarget};
use frep_mesh::poly::bounds::{model_box, HFP_DEFAULT};
use frep_mesh::{polygonize, CancelToken, Limits, MeshSettings, Method, Progress, Resolution};
use frep_wire::{Diagnostic, ShaderArtefact};
use serde::{Deserialize, Serialize};

use crate::buffers;

/// Options of [`Kernel::compile`] (JSON, camelCase; every field optional).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "camelCase", default)]
pub struct CompileRequest {
    /// The body to compile (default: `my_model`, else the first).
    pub body: Option<String>,
    /// Parameter values `a[]` (for the detected extent).
    pub params: Vec<f64>,
    /// Skip the box (no extent detection): diagnostics while typing.
    pub no_bounds: bool,
}

/// What [`Kernel::compile`] answers (JSON, camelCase).
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Compiled {
    /// Whether the model compiled (then `handle` is set).
    pub ok: bool,
    /// The model's handle for the other calls (0 when not `ok`).
    pub handle: u32,
    /// The model errors (empty when `ok`), frep-wire's diagnostics.
    pub diagnostics: Vec<Diagnostic>,
    /// The compiled body.
    pub body: String,
    /// Every body of the file.
    pub bodies: Vec<String>,
    /// Size of `a[]`.
    pub params: u32,
    /// Size of `s[]` when declared (else 0).
    pub attributes: u32,
    /// Nodes of the expression graph.
    pub nodes: u32,
    /// Operations of the value's tape.
    pub tape_len: u32,
    /// The model box (the `-- bounds:` comment, else the detected extent,
    /// else hfp's ±10), `None` when `noBounds` was asked.
    pub bounds: Option<[f64; 6]>,
    /// `comment`, `extent`, `default` or `none`.
    pub bounds_origin: String,
}

/// Settings of [`Kernel::polygonize`] (JSON, camelCase).
#[derive(Clone, Debug, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct MeshRequest {
    /// The box `x0, y0, z0, x1, y1, z1`.
    pub bounds: [f64; 6],
    /// Octree depth: `2^depth` cells along the longest side.
    pub depth: u8,
    /// `watertight` (default), `dc` or `mc`.
    #[serde(default)]
    pub method: Option<String>,
    /// Parameter values `a[]`.
    #[serde(default)]
    pub params: Vec<f64>,
    /// Per-vertex colours from `s[1..3]` (default true).
    #[serde(default)]
    pub colors: Option<bool>,
    /// Most triangles (default: [`DEFAULT_MAX_TRIANGLES`]).
    #[serde(default)]
    pub max_triangles: Option<usize>,
    /// Deepest octree allowed (default: [`DEFAULT_MAX_DEPTH`]).
    #[serde(default)]
    pub max_depth: Option<u8>,
}

/// Options of [`Kernel::shader`] (JSON, camelCase; every field optional).
#[derive(Clone, Debug, Default, Deserialize)]
#[serde(rename_all = "camelCase", default)]
pub struct ShaderRequest {
    /// The box ray cast (default: the box found at compile time).
    pub bounds: Option<[f64; 6]>,
    /// Default parameter values (`u_params`).
    pub params: Vec<f64>,
}

/// A browser's memory is small: the default triangle cap of a mesh made in
/// WebAssembly (about 100 MB of buffers).
pub const DEFAULT_MAX_TRIANGLES: usize = 2_000_000;
/// The default deepest octree of a mesh made in WebAssembly.
pub const DEFAULT_MAX_DEPTH: u8 = 9;

/// An error of a call, reported to the caller as text.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct CallError(pub String);

fn err(msg: impl Into<String>) -> CallError {
    CallError(msg.into())
}

/// One compiled model with its evaluators (made on first use).
struct Entry {
    model: Model,
    bounds: Option<[f64; 6]>,
    batch: Option<BatchEval>,
    point: Option<PointEval>,
}

/// The table of compiled models (see the module docs).
#[derive(Default)]
pub struct Kernel {
    models: Vec<Option<Entry>>,
}

/// frep-core's diagnostic as frep-wire's (the server's conversion).
fn wire_diagnostic(d: &frep_core::Diagnostic, source: &str) -> Diagnostic {
    Diagnostic {
        message: d.to_string(),
        line: d.span.line,
        column: d.span.col,
        start: d.span.start as u32,
        end: d.span.end as u32,
        rendered: d.render(source, None),
    }
}

impl Kernel {
    /// An empty table.
    pub fn new() -> Self {
        Self::default()
    }

    /// Parses and compiles `source`; on success the model is kept under the
    /// returned handle.
    pub fn compile(&mut self, source: &str, req: &CompileRequest) -> Compiled {
        let opts = CompileOptions {
            body: req.body.clone(),
            ..Default::default()
        };
        let model = match Model::compile_with(source, &opts) {
            Ok(m) => m,
            Err(d) => {
                return Compiled {
                    ok: false,
                    handle: 0,
                    diagnostics: vec![wire_diagnostic(&d, source)],
                    body: String::new(),
                    bodies: Vec::new(),
                    params: 0,
                    attributes: 0,
                    nodes: 0,
                    tape_len: 0,
                    bounds: None,
                    bounds_origin: "none".into(),
                }
            }
        };
        let (bounds, origin) = if req.no_bounds {
            (None, "none")
        } else {
            // The box rule of the command line and the server.
            let (b, origin) = model_box(source, &model, &Inputs::with_params(&req.params));
            (Some(b), origin.as_str())
        };
        let out = Compiled {
            ok: true,
            handle: 0,
            diagnostics: Vec::new(),
            body: model.body.clone(),
            bodies: model.bodies.clone(),
            params: model.a_dim as u32,
            attributes: if model.has_attributes {
                model.s_dim as u32
            } else {
                0
            },
            nodes: model.graph.len() as u32,
            tape_len: model.tape().len() as u32,
            bounds,
            bounds_origin: origin.into(),
        };
        let entry = Entry {
            model,
            bounds,
            batch: None,
            point: None,
        };
        let handle = match self.models.iter().position(Option::is_none) {
            Some(i) => {
                self.models[i] = Some(entry);
                i + 1
            }
            None => {
                self.models.push(Some(entry));
                self.models.len()
            }
        };
        Compiled {
            handle: handle as u32,
            ..out
        }
    }

    fn entry(&mut self, handle: u32) -> Result<&mut Entry, CallError> {
        (handle as usize)
            .checked_sub(1)
            .and_then(|i| self.models.get_mut(i))
            .and_then(Option::as_mut)
            .ok_or_else(|| err(format!("no model with handle {handle}")))
    }

    /// Forgets a model; false when the handle was not in use.
    pub fn free(&mut self, handle: u32) -> bool {
        match (handle as usize)
            .checked_sub(1)
            .and_then(|i| self.models.get_mut(i))
        {
            Some(slot) if slot.is_some() => {
                *slot = None;
                true
            }
            _ => false,
        }
    }

    /// Number of outputs of the model's evaluations: the value, then the
    /// attributes `s[]` when declared.
    pub fn outputs(&mut self, handle: u32) -> Result<usize, CallError> {
        let e = self.entry(handle)?;
        Ok(1 + if e.model.has_attributes {
            e.model.attributes.len()
        } else {
            0
        })
    }

    /// Evaluates the value and the attributes at `n` points given planar
    /// (`xyz` = x₀…xₙ₋₁, y₀…, z₀…) with the batch evaluator: NaN where an
    /// error reaches an output. `out` receives output-major values
    /// (`out[k·n + i]`: output `k` at point `i`), in place: a caller that
    /// keeps `out` between calls allocates nothing.
    pub fn eval_points(
        &mut self,
        handle: u32,
        xyz: &[f64],
        params: &[f64],
        out: &mut Vec<f64>,
    ) -> Result<usize, CallError> {
        if !xyz.len().is_multiple_of(3) {
            return Err(err("the points are not a multiple of 3 numbers"));
        }
        let n = xyz.len() / 3;
        let e = self.entry(handle)?;
        let model = &e.model;
        let batch = e
            .batch
            .get_or_insert_with(|| BatchEval::new(&model.tape_with_attributes()));
        let k = batch.tape().outputs.len();
        // Every slot is written, so a buffer of the right size is not
        // cleared first (that would be one more pass over it).
        if out.len() != k * n {
            out.clear();
            out.resize(k * n, 0.0);
        }
        let (xs, rest) = xyz.split_at(n);
        let (ys, zs) = rest.split_at(n);
        batch.eval_outputs_into(xs, ys, zs, &Inputs::with_params(params), out);
        Ok(k)
    }

    /// Evaluates one point with the point evaluator, which reports the
    /// reference interpreter's runtime errors: `Ok(outputs)` or the error's
    /// message.
    pub fn eval_point(
        &mut self,
        handle: u32,
        p: [f64; 3],
        params: &[f64],
    ) -> Result<Result<Vec<f64>, String>, CallError> {
        let e = self.entry(handle)?;
        let model = &e.model;
        let ev = e
            .point
            .get_or_insert_with(|| PointEval::new(model.point_tape()));
        Ok(
            match ev.eval(p[0], p[1], p[2], &Inputs::with_params(params)) {
                Ok(v) => {
                    let mut vals = vec![v];
                    for k in 1..ev.outputs() {
                        vals.push(ev.output(k).unwrap_or(f64::NAN));
                    }
                    Ok(vals)
                }
                Err(e) => Err(e.message().to_string()),
            },
        )
    }

    /// Polygonizes the model (frep-mesh, single-threaded) and packs the mesh
    /// ([`buffers::pack_mesh`]).
    pub fn polygonize(&mut self, handle: u32, req: &MeshRequest) -> Result<Vec<u8>, CallError> {
        let method = match req.method.as_deref().unwrap_or("watertight") {
            "watertight" | "wt" => Method::Watertight,
            "dc" => Method::DualContouring,
            "mc" => Method::MarchingCubes,
            m => return Err(err(format!("unknown method {m:?} (watertight, dc or mc)"))),
        };
        let settings = MeshSettings {
            bounds: req.bounds,
            resolution: Resolution::Depth(req.depth),
            method,
            colors: req.colors.unwrap_or(true),
            inputs: Inputs::with_params(&req.params),
            limits: Limits {
                max_depth: req.max_depth.unwrap_or(DEFAULT_MAX_DEPTH),
                max_triangles: req.max_triangles.unwrap_or(DEFAULT_MAX_TRIANGLES),
            },
            ..Default::default()
        };
        let e = self.entry(handle)?;
        // No other thread can cancel a call in WebAssembly: the worker
        // cancels between calls (coarse, then refined).
        let mesh = polygonize(&e.model, &settings, &Progress::new(), &CancelToken::new())
            .map_err(|e| err(e.to_string()))?;
        Ok(buffers::pack_mesh(&mesh))
    }

    /// The studio's ray-casting shader of the model (frep-glsl's viewer
    /// target) as frep-wire's [`ShaderArtefact`].
    pub fn shader(
        &mut self,
        handle: u32,
        req: &ShaderRequest,
    ) -> Result<ShaderArtefact, CallError> {
        let e = self.entry(handle)?;
        let b = req.bounds.or(e.bounds).unwrap_or(HFP_DEFAULT);
        if !(b.iter().all(|v| v.is_finite()) && (0..3).all(|a| b[a] < b[a + 3])) {
            return Err(err(format!("invalid box {b:?}")));
        }
        let opts = ShaderOptions {
            box_min: [b[0], b[1], b[2]],
            box_max: [b[3], b[4], b[5]],
            params: req.params.clone(),
            target: ShaderTarget::Viewer,
            ..Default::default()
        };
        Ok(shader_for_model(&e.model, &opts).into_wire(b))
    }
}
