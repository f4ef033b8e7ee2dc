//! A model compiled once, with everything every artefact of it needs:
//! - the source and the body;
//! - the model box, and where it came from;
//! - the default parameters;
//! - a content hash of the compiled graph.
//!
//! The box follows the one rule of the command line
//! ([`frep_mesh::poly::bounds::model_box`]):
//! 1. the source's `-- bounds:` line;
//! 2. else the solid's detected extent, at the default parameters or those
//!    given to [`compile_with_params`];
//! 3. else hfp's `[-10, 10]³`.
//!
//! It stays fixed while parameters change, so a dragged slider does not move
//! the camera.
//!
//! Parameters: a comment line `-- param: <i> <name> <default> [<min> <max>]`
//! among the heading comments names `a[i]` and gives its slider. `<i>` is `1`
//! or `a[1]`. Without one, `a[i]` has default 0 and range
//! `default ± max(1, |default|)`.
//!
//! The graph hash is BLAKE3 over the declared dimensions and the outputs of
//! the value-and-attribute tape.
//! - Each node is hashed as a Merkle tree: its operation and constant bits,
//!   then its operands' hashes.
//! - Sources that compile to the same expressions share it, whatever the
//!   order the compiler created the nodes in.
//! - Comments, spacing, names, temporaries and folded constants do not
//!   count.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, OnceLock};

use frep_core::{CancelToken, CompileOptions, Inputs, Model, NodeId};
use frep_glsl::{shader_for_model, ShaderOptions};
use frep_mesh::poly::bounds::{model_box, BoxOrigin};
use frep_render::{Aabb, ImagePool, ModelCaster, RenderSettings};
use frep_wire::{CompileSummary, Diagnostic, ParamInfo};

use crate::config::CompileLimits;

/// A compiled model and what its artefacts need.
#[derive(Debug)]
pub struct Compiled {
    model: Model,
    source: String,
    bounds: [f64; 6],
    origin: BoxOrigin,
    params: Vec<ParamInfo>,
    graph_hash: String,
    summary: OnceLock<CompileSummary>,
}

/// Compiles `body` (default: `my_model`, else the first) of `source`, the box
/// detected at the default parameters.
pub fn compile(
    source: &str,
    body: Option<&str>,
    limits: &CompileLimits,
) -> Result<Arc<Compiled>, Vec<Diagnostic>> {
    compile_with_params(source, body, &[], limits)
}

/// [`compile`] with the extent detected at these parameter values (empty:
/// the defaults).
pub fn compile_with_params(
    source: &str,
    body: Option<&str>,
    params: &[f64],
    limits: &CompileLimits,
) -> Result<Arc<Compiled>, Vec<Diagnostic>> {
    if source.len() > limits.max_source_bytes {
        return Err(vec![whole_source(
            source,
            format!(
                "the source is {} bytes, over the limit of {}",
                source.len(),
                limits.max_source_bytes
            ),
        )]);
    }
    let options = CompileOptions {
        body: body.map(str::to_string),
        max_nodes: limits.max_nodes,
        max_iterations: limits.max_iterations,
        max_steps: limits.max_steps,
        ..CompileOptions::default()
    };
    let model =
        Model::compile_with(source, &options).map_err(|d| vec![to_wire_diagnostic(&d, source)])?;
    let infos = param_infos(source, model.a_dim);
    let values = if params.is_empty() {
        infos.iter().map(|p| p.default).collect()
    } else {
        params.to_vec()
    };
    let (bounds, origin) = model_box(source, &model, &Inputs::with_params(&values));
    let graph_hash = graph_hash(&model);
    Ok(Arc::new(Compiled {
        model,
        source: source.to_string(),
        bounds,
        origin,
        params: infos,
        graph_hash,
        summary: OnceLock::new(),
    }))
}

impl Compiled {
    /// The compiled model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// The source it was compiled from.
    pub fn source(&self) -> &str {
        &self.source
    }

    /// The compiled body's name.
    pub fn body(&self) -> &str {
        &self.model.body
    }

    /// The model box `[x0, y0, z0, x1, y1, z1]`.
    pub fn bounds(&self) -> [f64; 6] {
        self.bounds
    }

    /// The model box as the ray caster's [`Aabb`].
    pub fn aabb(&self) -> Aabb {
        let b = self.bounds;
        Aabb::new([b[0], b[1], b[2]], [b[3], b[4], b[5]])
    }

    /// Where the box came from.
    pub fn bounds_origin(&self) -> BoxOrigin {
        self.origin
    }

    /// The parameters `a[]` with their sliders.
    pub fn params(&self) -> &[ParamInfo] {
        &self.params
    }

    /// Parameter values: `given` where given, the defaults after.
    pub fn param_values(&self, given: &[f64]) -> Vec<f64> {
        let mut v = given.to_vec();
        v.extend(self.params.iter().skip(given.len()).map(|p| p.default));
        v
    }

    /// The evaluators' inputs for parameter values `given` ([`Self::param_values`]).
    pub fn inputs(&self, given: &[f64]) -> Inputs {
        Inputs::with_params(&self.param_values(given))
    }

    /// The content hash of the compiled graph (64 hex digits).
    pub fn graph_hash(&self) -> &str {
        &self.graph_hash
    }

    /// What the studio shows of the model; computed on first use (it
    /// generates the shader once to count its statements).
    pub fn summary(&self) -> &CompileSummary {
        self.summary.get_or_init(|| self.make_summary())
    }

    fn make_summary(&self) -> CompileSummary {
        let m = &self.model;
        let inputs = self.inputs(&[]);
        let b = self.bounds;
        let shader = shader_for_model(
            m,
            &ShaderOptions {
                box_min: [b[0], b[1], b[2]],
                box_max: [b[3], b[4], b[5]],
                params: inputs.params.clone(),
                ..Default::default()
            },
        );
        CompileSummary {
            body: m.body.clone(),
            bodies: m.bodies.clone(),
            nodes: m.graph.len() as u32,
            tape_len: m.tape().len() as u32,
            params: self.params.clone(),
            bounds: b,
            bounds_origin: self.origin.as_str().to_string(),
            attributes: if m.has_attributes { m.s_dim as u32 } else { 0 },
            closed_form: closed_form(m, &inputs, self.aabb()),
            shader_statements: shader.stats.statements as u32,
            graph_hash: self.graph_hash.clone(),
        }
    }
}

/// Whether the ray caster solves the model in closed form (a set expression
/// over quadrics). A 16² orthographic view is cast with the ray caster. The
/// answer is yes when every ray was settled exactly, with no sample taken.
/// frep-render keeps its set expression private, so this asks the caster
/// what it did.
fn closed_form(model: &Model, inputs: &Inputs, bounds: Aabb) -> bool {
    if model.has_attributes {
        return false;
    }
    let caster = ModelCaster::new(model, inputs.clone(), bounds);
    let settings = RenderSettings {
        size: (16, 16),
        fov: None,
        bounds,
        inputs: inputs.clone(),
        tile_size: 16,
        ..Default::default()
    };
    let (cancel, pool) = (CancelToken::new(), ImagePool::new(0));
    if frep_render::render_with(&caster, &settings, &settings.camera(), &cancel, &pool).is_err() {
        return false;
    }
    let s = caster.stats();
    s.exact_rays > 0 && s.point_evals == 0 && s.line_points == 0
}

/// BLAKE3 of the canonical listing of the model's graph (module docs).
pub fn graph_hash(model: &Model) -> String {
    let tape = model.tape_with_attributes();
    let mut h = blake3::Hasher::new();
    h.update(b"frep-graph-1\n");
    h.update(
        format!(
            "x{} a{} s{} attr{}\n",
            model.x_dim, model.a_dim, model.s_dim, model.has_attributes
        )
        .as_bytes(),
    );
    // Each node's hash covers its operation and its operands' hashes. The
    // operation is its Debug form with operand ids zeroed: the operation and
    // constant bits. So the order the compiler happened to create nodes in
    // does not count.
    let mut hashes: Vec<[u8; 32]> = Vec::with_capacity(tape.nodes.len());
    for n in &tape.nodes {
        let mut nh = blake3::Hasher::new();
        nh.update(format!("{:?}", n.map_children(|_| NodeId(0))).as_bytes());
        for c in n.children() {
            // Children come before their parents in a tape; an id out of
            // range cannot occur, and would only change the hash.
            nh.update(hashes.get(c.index()).map_or(&[0u8; 32], |x| x));
        }
        hashes.push(*nh.finalize().as_bytes());
    }
    for o in &tape.outputs {
        h.update(hashes.get(o.index()).map_or(&[0u8; 32], |x| x));
    }
    h.finalize().to_hex().to_string()
}

/// A `-- param:` line: name, default, range.
type ParamLine = (String, f64, Option<(f64, f64)>);

/// The `-- param:` lines' sliders for `a[1..=a_dim]` (module docs).
pub fn param_infos(source: &str, a_dim: usize) -> Vec<ParamInfo> {
    let mut named: HashMap<usize, ParamLine> = HashMap::new();
    for line in source
        .lines()
        .take_while(|l| l.trim_start().starts_with("--") || l.trim().is_empty())
    {
        let Some(rest) = line.trim_start().strip_prefix("-- param:") else {
            continue;
        };
        let words: Vec<&str> = rest.split_whitespace().collect();
        let index = words.first().and_then(|w| {
            let w = w.trim_start_matches("a[").trim_end_matches(']');
            w.parse::<usize>().ok()
        });
        let nums: Vec<f64> = words
            .iter()
            .skip(2)
            .filter_map(|w| w.parse::<f64>().ok().filter(|v| v.is_finite()))
            .collect();
        if let (Some(i), Some(name), Some(&d)) = (index, words.get(1), nums.first()) {
            let range = match nums.as_slice() {
                [_, lo, hi, ..] if lo < hi => Some((*lo, *hi)),
                _ => None,
            };
            named.insert(i, (name.to_string(), d, range));
        }
    }
    (1..=a_dim)
        .map(|i| {
            let (name, default, range) = named
                .remove(&i)
                .unwrap_or_else(|| (format!("a[{i}]"), 0.0, None));
            let span = default.abs().max(1.0);
            let (min, max) = range.unwrap_or((default - span, default + span));
            ParamInfo {
                index: i as u32,
                name,
                default,
                min,
                max,
            }
        })
        .collect()
}

/// A kernel diagnostic as the wire carries it: line, column, byte span and
/// the rendered text with the source line and a caret.
pub fn to_wire_diagnostic(d: &frep_core::Diagnostic, source: &str) -> Diagnostic {
    Diagnostic {
        message: d.to_string(),
        line: d.span.line,
        column: d.span.col,
        start: d.span.start as u32,
        end: d.span.end as u32,
        rendered: d.render(source, None),
    }
}

fn whole_source(source: &str, message: String) -> Diagnostic {
    Diagnostic {
        rendered: format!("error: 1:1: {message}\n"),
        message,
        line: 1,
        column: 1,
        start: 0,
        end: source.len().min(u32::MAX as usize) as u32,
    }
}

/// Compiled models by source hash (source, body and the extent's
/// parameters), at most `capacity`, the least recently used forgotten first.
/// Failed compiles are not kept.
#[derive(Debug)]
pub struct CompileCache {
    capacity: usize,
    inner: Mutex<CacheInner>,
}

#[derive(Debug, Default)]
struct CacheInner {
    clock: u64,
    map: HashMap<[u8; 32], (u64, Arc<Compiled>)>,
}

impl CompileCache {
    /// An empty cache holding at most `capacity` models.
    pub fn new(capacity: usize) -> CompileCache {
        CompileCache {
            capacity: capacity.max(1),
            inner: Mutex::new(CacheInner::default()),
        }
    }

    /// The cached model for this source, body and parameters, or a new
    /// compile ([`compile_with_params`]).
    pub fn get_or_compile(
        &self,
        source: &str,
        body: Option<&str>,
        params: &[f64],
        limits: &CompileLimits,
    ) -> Result<Arc<Compiled>, Vec<Diagnostic>> {
        let mut h = blake3::Hasher::new();
        h.update(&(source.len() as u64).to_le_bytes());
        h.update(source.as_bytes());
        h.update(body.unwrap_or("\0").as_bytes());
        for p in params {
            h.update(&p.to_bits().to_le_bytes());
        }
        let key = *h.finalize().as_bytes();
        if let Some(c) = self.lock().touch(&key) {
            return Ok(c);
        }
        // Compiled outside the lock: two threads may compile the same source
        // at once; both get a correct model and one is kept.
        let c = compile_with_params(source, body, params, limits)?;
        let mut inner = self.lock();
        inner.clock += 1;
        let now = inner.clock;
        inner.map.insert(key, (now, c.clone()));
        if inner.map.len() > self.capacity {
            let oldest = inner
                .map
                .iter()
                .min_by_key(|(_, (t, _))| *t)
                .map(|(k, _)| *k);
            if let Some(k) = oldest {
                inner.map.remove(&k);
            }
        }
        Ok(c)
    }

    /// Models cached now.
    pub fn len(&self) -> usize {
        self.lock().map.len()
    }

    /// Whether nothing is cached.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, CacheInner> {
        // A panic while holding the lock leaves a consistent map (every
        // update is one insert or remove), so a poisoned lock is used as is.
        self.inner.lock().unwrap_or_else(|p| p.into_inner())
    }
}

impl CacheInner {
    fn touch(&mut self, key: &[u8; 32]) -> Option<Arc<Compiled>> {
        self.clock += 1;
        let now = self.clock;
        let e = self.map.get_mut(key)?;
        e.0 = now;
        Some(e.1.clone())
    }
}
