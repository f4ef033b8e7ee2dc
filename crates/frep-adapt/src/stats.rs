//! What the engine knows of a model and of the server:
//! - the compiled model's sizes ([`ModelStats`]);
//! - the server's measured costs of this model's artefacts, when it has made
//!   some ([`Measured`]);
//! - the server's load ([`ServerLoad`]).
//!
//! The server fills [`ModelStats`] from its compile summary
//! ([`ModelStats::from_summary`]). It adds a measured sample each time it
//! computes an artefact ([`ModelStats::record`]). The predictor prefers a
//! measured figure to an estimate (see `predict.rs` for the estimates).

use frep_wire::CompileSummary;
use serde::Serialize;

/// Sizes of the compiled model, and its measured artefact costs.
#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ModelStats {
    /// Operations of the value's tape (what an evaluator runs per point).
    pub tape_len: u32,
    /// Nodes of the expression graph.
    pub nodes: u32,
    /// Whether the server's ray caster solves it in closed form (cheap).
    pub closed_form: bool,
    /// Attribute outputs (colour); 0 without.
    pub attributes: u32,
    /// Primitives when the server counted them; `None`: estimated from the
    /// tape length ([`ModelStats::primitives_estimate`]).
    pub primitives: Option<u32>,
    /// Statements per field flavour of the generated shader (0: unknown,
    /// then the tape length stands in).
    pub shader_statements: u32,
    /// Costs the server measured for this model.
    pub measured: Measured,
}

/// Tape operations per primitive, for estimating a primitive count
/// (`examples/m2_spheres100.hf`: 100 spheres and their unions, 464
/// operations; constants are not operations).
pub const TAPE_OPS_PER_PRIMITIVE: u32 = 5;

impl ModelStats {
    /// Stats from the server's compile summary (nothing measured yet).
    pub fn from_summary(summary: &CompileSummary) -> ModelStats {
        ModelStats {
            tape_len: summary.tape_len,
            nodes: summary.nodes,
            closed_form: summary.closed_form,
            attributes: summary.attributes,
            primitives: None,
            shader_statements: summary.shader_statements,
            measured: Measured::default(),
        }
    }

    /// Primitives: the count when known, else tape length /
    /// [`TAPE_OPS_PER_PRIMITIVE`] (at least 1).
    pub fn primitives_estimate(&self) -> u32 {
        self.primitives
            .unwrap_or((self.tape_len / TAPE_OPS_PER_PRIMITIVE).max(1))
    }

    /// Statements of the generated shader's field function (the tape
    /// length when the summary had none).
    pub fn statements(&self) -> u32 {
        if self.shader_statements > 0 {
            self.shader_statements
        } else {
            self.tape_len
        }
    }

    /// Keeps a measured artefact cost (the latest of each kind wins: the
    /// server's state changes, old samples go stale).
    pub fn record(&mut self, sample: ServerSample) {
        if !sample.is_valid() {
            return;
        }
        match sample {
            ServerSample::Image(s) => self.measured.image = Some(s),
            ServerSample::Mesh(s) => self.measured.mesh = Some(s),
            ServerSample::Volume(s) => self.measured.volume = Some(s),
        }
    }
}

/// The server's measured costs of this model's artefacts.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Measured {
    /// A rendered and encoded image (a view set's views count as images).
    pub image: Option<ImageSample>,
    /// A polygonized and encoded mesh.
    pub mesh: Option<MeshSample>,
    /// Computed and encoded slices.
    pub volume: Option<VolumeSample>,
}

/// One image the server rendered and encoded.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ImageSample {
    /// Pixels of the image (all views of a view set together).
    pub pixels: u64,
    /// Encoder quality it used (1–100).
    pub quality: u8,
    /// Server ms to render and encode, with no queueing.
    pub server_ms: f64,
    /// Encoded bytes.
    pub bytes: u64,
}

/// One mesh the server polygonized and encoded.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct MeshSample {
    /// Octree depth.
    pub depth: u8,
    /// Triangles.
    pub triangles: u64,
    /// Server ms to polygonize and encode, with no queueing.
    pub server_ms: f64,
    /// Encoded bytes (the glb as sent).
    pub bytes: u64,
}

/// One volume (slices) the server computed and encoded.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct VolumeSample {
    /// Cells per side.
    pub grid: u32,
    /// Server ms to evaluate and encode, with no queueing.
    pub server_ms: f64,
    /// Encoded bytes.
    pub bytes: u64,
}

/// A measured artefact cost, as the server reports it to the engine.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "camelCase")]
pub enum ServerSample {
    /// An image or view set.
    Image(ImageSample),
    /// A mesh.
    Mesh(MeshSample),
    /// A volume.
    Volume(VolumeSample),
}

impl ServerSample {
    /// Whether the figures can be used (positive sizes, finite times).
    /// Invalid samples are ignored rather than poisoning the estimates.
    pub fn is_valid(&self) -> bool {
        let ok_ms = |ms: f64| ms.is_finite() && ms >= 0.0;
        match self {
            ServerSample::Image(s) => s.pixels > 0 && s.bytes > 0 && ok_ms(s.server_ms),
            ServerSample::Mesh(s) => s.depth > 0 && s.bytes > 0 && ok_ms(s.server_ms),
            ServerSample::Volume(s) => s.grid > 0 && s.bytes > 0 && ok_ms(s.server_ms),
        }
    }
}

/// The server's load as its job pool sees it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct ServerLoad {
    /// Workers busy now.
    pub busy_workers: u32,
    /// Workers in the pool.
    pub workers: u32,
    /// Jobs waiting for a worker.
    pub queued: u32,
}

impl Default for ServerLoad {
    /// An idle pool of one worker (the engine's assumption before the
    /// server reports its load).
    fn default() -> Self {
        ServerLoad {
            busy_workers: 0,
            workers: 1,
            queued: 0,
        }
    }
}

impl ServerLoad {
    /// How much longer a server job takes than on an idle server. A new
    /// job waits, on average, for the queue ahead of it, and shares the
    /// machine with the busy workers. `1 + (busy + queued) / workers`.
    pub fn factor(&self) -> f64 {
        let workers = f64::from(self.workers.max(1));
        1.0 + f64::from(self.busy_workers.saturating_add(self.queued)) / workers
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stats() -> ModelStats {
        ModelStats {
            tape_len: 120,
            nodes: 150,
            closed_form: false,
            attributes: 0,
            primitives: None,
            shader_statements: 0,
            measured: Measured::default(),
        }
    }

    #[test]
    fn estimates_from_the_tape_when_unknown() {
        let mut s = stats();
        assert_eq!(s.primitives_estimate(), 24);
        assert_eq!(s.statements(), 120);
        s.primitives = Some(3);
        s.shader_statements = 90;
        assert_eq!(s.primitives_estimate(), 3);
        assert_eq!(s.statements(), 90);
    }

    #[test]
    fn invalid_samples_are_ignored() {
        let mut s = stats();
        s.record(ServerSample::Image(ImageSample {
            pixels: 0,
            quality: 75,
            server_ms: 5.0,
            bytes: 100,
        }));
        s.record(ServerSample::Mesh(MeshSample {
            depth: 7,
            triangles: 10,
            server_ms: f64::NAN,
            bytes: 100,
        }));
        assert_eq!(s.measured, Measured::default());
        let v = VolumeSample {
            grid: 64,
            server_ms: 12.0,
            bytes: 30_000,
        };
        s.record(ServerSample::Volume(v));
        assert_eq!(s.measured.volume, Some(v));
    }

    #[test]
    fn load_factor_counts_busy_and_queued() {
        assert_eq!(ServerLoad::default().factor(), 1.0);
        let l = ServerLoad {
            busy_workers: 2,
            workers: 2,
            queued: 2,
        };
        assert_eq!(l.factor(), 3.0);
        let zero = ServerLoad {
            busy_workers: 0,
            workers: 0,
            queued: 0,
        };
        assert_eq!(zero.factor(), 1.0);
    }
}
