// Generated from crates/frep-wire by `FREP_BLESS=1 cargo test -p frep-wire`.
// Do not edit: a test fails when this file differs from the Rust types.

export type ModelSummary = { 
/**
 * Opaque id, stable for the model's life.
 */
id: string, 
/**
 * Display name (unique per owner is not enforced).
 */
name: string, 
/**
 * Who created it.
 */
owner: string, 
/**
 * Creation time, ms since the epoch.
 */
created: number, 
/**
 * Time of the latest version, ms since the epoch.
 */
updated: number, 
/**
 * Number of the latest version (1 for a new model).
 */
latest: number, };

export type Version = { 
/**
 * The model it belongs to.
 */
modelId: string, 
/**
 * 1, 2, 3, … in the order they were saved.
 */
number: number, 
/**
 * HyperFun source.
 */
source: string, 
/**
 * Values of the parameters `a[1..]` saved with it.
 */
params: Array<number>, 
/**
 * Who saved it.
 */
author: string, 
/**
 * When it was committed, ms since the epoch.
 */
created: number, 
/**
 * The author's message.
 */
message: string, 
/**
 * The version it restores, when it was made by a restore.
 */
restoredFrom: number | null, 
/**
 * Content-addressed files the source refers to.
 */
assets: Array<AssetRef>, };

export type VersionSummary = { 
/**
 * 1, 2, 3, …
 */
number: number, 
/**
 * Who saved it.
 */
author: string, 
/**
 * When, ms since the epoch.
 */
created: number, 
/**
 * The author's message.
 */
message: string, 
/**
 * The version it restores, when it was made by a restore.
 */
restoredFrom: number | null, 
/**
 * Bytes of source.
 */
sourceBytes: number, };

export type ModelDetail = { 
/**
 * The model.
 */
model: ModelSummary, 
/**
 * Its version.
 */
version: Version, };

export type CreateModel = { 
/**
 * Display name.
 */
name: string, 
/**
 * HyperFun source of version 1.
 */
source: string, 
/**
 * Parameter values (empty: none saved).
 */
params: Array<number>, 
/**
 * Message of version 1.
 */
message: string, };

export type SaveVersion = { 
/**
 * HyperFun source.
 */
source: string, 
/**
 * Parameter values.
 */
params: Array<number>, 
/**
 * The author's message.
 */
message: string, 
/**
 * The version the edit started from. When given and no longer the
 * latest, the save is refused with 409 and the latest number, so that a
 * client never overwrites an edit it has not seen.
 */
base: number | null, 
/**
 * Hashes of assets (uploaded before) the source refers to.
 */
assets: Array<string>, };

export type RenameModel = { 
/**
 * The new name.
 */
name: string, };

export type RestoreVersion = { 
/**
 * The version to copy.
 */
version: number, 
/**
 * The author's message (default: "restore N").
 */
message: string, };

export type DuplicateModel = { 
/**
 * The copy's name.
 */
name: string, };

export type DiffLine = { 
/**
 * `same`, `added` or `removed`.
 */
kind: DiffKind, 
/**
 * Line number in the older version (1-based), if the line is there.
 */
oldLine: number | null, 
/**
 * Line number in the newer version (1-based), if the line is there.
 */
newLine: number | null, 
/**
 * The line's text, without its line ending.
 */
text: string, };

export type DiffKind = "same" | "added" | "removed";

export type SourceDiff = { 
/**
 * The older version.
 */
from: number, 
/**
 * The newer version.
 */
to: number, 
/**
 * The lines of both, in order.
 */
lines: Array<DiffLine>, 
/**
 * Whether the parameter values differ.
 */
paramsChanged: boolean, };

export type ChangeKind = "created" | "saved" | "restored" | "renamed" | "deleted";

export type Change = { 
/**
 * Position in the model's log: 1, 2, 3, … without gaps.
 */
seq: number, 
/**
 * The model.
 */
modelId: string, 
/**
 * What happened.
 */
kind: ChangeKind, 
/**
 * The version it made, if any.
 */
version: number | null, 
/**
 * The name after a rename (or at creation).
 */
name: string | null, 
/**
 * Who did it.
 */
author: string, 
/**
 * When, ms since the epoch.
 */
time: number, };

export type AssetRef = { 
/**
 * BLAKE3 of the content, hex (the asset's URL is `/api/assets/{hash}`).
 */
hash: string, 
/**
 * Bytes.
 */
size: number, 
/**
 * MIME type given at upload.
 */
mediaType: string, 
/**
 * The name the source uses for it.
 */
name: string, };

export type CompileRequest = { 
/**
 * HyperFun source.
 */
source: string, 
/**
 * Parameter values (for the detected extent).
 */
params: Array<number>, 
/**
 * The body to compile (default: `my_model`, else the first).
 */
body: string | null, };

export type Diagnostic = { 
/**
 * The message, e.g. "expected `;`".
 */
message: string, 
/**
 * 1-based line of the start.
 */
line: number, 
/**
 * 1-based column (in characters) of the start.
 */
column: number, 
/**
 * Byte offsets of the span in the source, `[start, end)`.
 */
start: number, 
/**
 * End byte offset.
 */
end: number, 
/**
 * The rendered text: message, the source line and a caret under the span.
 */
rendered: string, };

export type ParamInfo = { 
/**
 * 1-based index in `a[]`.
 */
index: number, 
/**
 * Display name (from a `-- param:` comment, else `a[i]`).
 */
name: string, 
/**
 * Default value.
 */
default: number, 
/**
 * Slider minimum.
 */
min: number, 
/**
 * Slider maximum.
 */
max: number, };

export type CompileSummary = { 
/**
 * The compiled body.
 */
body: string, 
/**
 * Every body in the file.
 */
bodies: Array<string>, 
/**
 * Nodes of the expression graph.
 */
nodes: number, 
/**
 * Operations of the value's tape (what an evaluator runs per point).
 */
tapeLen: number, 
/**
 * The model's parameters `a[]`.
 */
params: Array<ParamInfo>, 
/**
 * The model box `[x0, y0, z0, x1, y1, z1]`.
 */
bounds: [number, number, number, number, number, number], 
/**
 * Where the box came from: `comment`, `extent` or `default`.
 */
boundsOrigin: string, 
/**
 * Number of attributes `s[]` (0 when the header declares none).
 */
attributes: number, 
/**
 * Whether the ray caster solves it in closed form (quadric set
 * expressions): cheap to render.
 */
closedForm: boolean, 
/**
 * Statements per field flavour of the generated shader.
 */
shaderStatements: number, 
/**
 * Content hash of the compiled graph (the artefacts' key prefix).
 */
graphHash: string, };

export type CompileResponse = { 
/**
 * Whether the model compiled.
 */
ok: boolean, 
/**
 * Model errors (empty when `ok`).
 */
diagnostics: Array<Diagnostic>, 
/**
 * The summary (when `ok`).
 */
summary: CompileSummary | null, };

export type ApiError = { 
/**
 * e.g. `not_found`, `model_error`, `too_large`, `conflict`, `limit`.
 */
code: string, 
/**
 * What went wrong, in words.
 */
message: string, 
/**
 * Model errors with line and column (for `model_error`).
 */
diagnostics: Array<Diagnostic>, 
/**
 * The limit that was exceeded, by its configuration name.
 */
limit: string | null, 
/**
 * The model's latest version number (for `conflict`: the save's base
 * was stale).
 */
latest?: number, };

export type ModelRef = { "from": "version", 
/**
 * Model id.
 */
modelId: string, 
/**
 * Version number (`None`: the latest).
 */
version: number | null, } | { "from": "source", 
/**
 * HyperFun source.
 */
source: string, };

export type CameraView = { 
/**
 * Degrees around z.
 */
yaw: number, 
/**
 * Degrees above the horizon.
 */
pitch: number, 
/**
 * Vertical field of view in degrees; `None`: orthographic.
 */
fov: number | null, 
/**
 * 1 frames the box; 2 is twice as close.
 */
zoom: number, 
/**
 * Offset of the orbit's centre from the box's centre, world units.
 */
pan: [number, number, number], };

export type SectionPlane = { 
/**
 * Normal, world coordinates (z up); any non-zero length (the plane is
 * `normal · p = offset` as given).
 */
normal: [number, number, number], 
/**
 * Offset along the normal, world units (for a unit normal).
 */
offset: number, };

export type ImageEncoding = "jpeg" | "webp" | "png";

export type ExportFormat = "stl" | "obj" | "ply" | "glb" | "3mf";

export type ArtefactSpec = { "kind": "image", 
/**
 * The camera.
 */
camera: CameraView, 
/**
 * Pixels.
 */
width: number, 
/**
 * Pixels.
 */
height: number, 
/**
 * Encoding.
 */
format: ImageEncoding, 
/**
 * JPEG / WebP quality 1–100.
 */
quality: number, 
/**
 * A section plane cutting the model open (absent: none).
 */
section?: SectionPlane, } | { "kind": "viewSet", 
/**
 * Views per ring.
 */
views: number, 
/**
 * Pitch of each ring, degrees.
 */
elevations: Array<number>, 
/**
 * Pixels per view.
 */
width: number, 
/**
 * Pixels per view.
 */
height: number, 
/**
 * Encoding of the sheet.
 */
format: ImageEncoding, 
/**
 * Quality 1–100.
 */
quality: number, 
/**
 * Field of view (`None`: orthographic).
 */
fov: number | null, 
/**
 * A section plane cutting the model open (absent: none).
 */
section?: SectionPlane, } | { "kind": "viewSetIndex", 
/**
 * Views per ring.
 */
views: number, 
/**
 * Pitch of each ring, degrees.
 */
elevations: Array<number>, 
/**
 * Pixels per view.
 */
width: number, 
/**
 * Pixels per view.
 */
height: number, 
/**
 * Encoding of the sheet.
 */
format: ImageEncoding, 
/**
 * Quality 1–100.
 */
quality: number, 
/**
 * Field of view (`None`: orthographic).
 */
fov: number | null, 
/**
 * A section plane cutting the model open (absent: none).
 */
section?: SectionPlane, } | { "kind": "mesh", 
/**
 * Octree depth (cells along the longest side: 2^depth).
 */
depth: number, } | { "kind": "slices", 
/**
 * Samples per axis.
 */
grid: number, } | { "kind": "shader" } | { "kind": "export", 
/**
 * The file format.
 */
format: ExportFormat, 
/**
 * Octree depth.
 */
depth: number, };

export type ArtefactRequest = { 
/**
 * The model.
 */
model: ModelRef, 
/**
 * Parameter values (empty: the version's own).
 */
params: Array<number>, 
/**
 * What to compute.
 */
spec: ArtefactSpec, };

export type ArtefactRef = { 
/**
 * The content address: hash of graph, parameters and settings.
 */
key: string, 
/**
 * Its immutable URL (`/api/artefacts/{key}.{ext}`).
 */
url: string, 
/**
 * MIME type of the body.
 */
mediaType: string, 
/**
 * Whether it is already computed (then `bytes` and `serverMs` are set).
 */
ready: boolean, 
/**
 * Size in bytes, when ready.
 */
bytes: number | null, 
/**
 * Server time it took to compute, when ready.
 */
serverMs: number | null, };

export type ShaderArtefact = { 
/**
 * GLSL ES 3.00 fragment shader.
 */
source: string, 
/**
 * Every uniform with its default values.
 */
uniforms: Array<ShaderUniform>, 
/**
 * The box ray cast.
 */
bounds: [number, number, number, number, number, number], 
/**
 * Statements per field flavour.
 */
statements: number, };

export type ShaderUniform = { 
/**
 * GLSL name.
 */
name: string, 
/**
 * GLSL type with array size (`float[3]`, `mat4`, …).
 */
type: string, 
/**
 * Default values, flattened.
 */
values: Array<number>, 
/**
 * What it is.
 */
description: string, };

export type ViewSetLayout = { 
/**
 * Views per ring.
 */
viewsPerRing: number, 
/**
 * Pitch of each ring, degrees.
 */
elevations: Array<number>, 
/**
 * Yaw of the first view of each ring, degrees.
 */
startYaw: number, 
/**
 * Pixels per view.
 */
viewSize: [number, number], 
/**
 * Views per row of the sheet.
 */
columns: number, 
/**
 * The sheet's size in pixels.
 */
sheetSize: [number, number], };

export type VolumeLayout = { 
/**
 * Samples along x, y, z.
 */
dims: [number, number, number], 
/**
 * The sampled box.
 */
bounds: [number, number, number, number, number, number], 
/**
 * byte = 128 + 127 · f / scale, clamped: 128 is the surface.
 */
scale: number, };

export type Mode = "still" | "viewSet" | "serverMesh" | "gpuRaycast" | "wasmMesh" | "volume";

export type Screen = { 
/**
 * CSS pixels.
 */
width: number, 
/**
 * CSS pixels.
 */
height: number, 
/**
 * `devicePixelRatio`.
 */
pixelRatio: number, };

export type ClientReport = { 
/**
 * `navigator.userAgent`.
 */
userAgent: string, 
/**
 * WebGL2 context available.
 */
webgl2: boolean, 
/**
 * Unmasked renderer string (`WEBGL_debug_renderer_info`), if given.
 */
renderer: string | null, 
/**
 * `MAX_TEXTURE_SIZE`, `MAX_3D_TEXTURE_SIZE` (0 without WebGL2).
 */
maxTextureSize: number, 
/**
 * 3D texture limit.
 */
max3dTextureSize: number, 
/**
 * WebGPU adapter available.
 */
webgpu: boolean, 
/**
 * GPU micro-benchmark: ms per frame of a ray-marched reference field at
 * 256², after the first frame (`None`: not run or no WebGL2).
 */
gpuBenchMs: number | null, 
/**
 * WASM micro-benchmark: million point evaluations of a reference model
 * per second (`None`: not run).
 */
wasmBenchMeps: number | null, 
/**
 * JS main-thread speed: ms of a fixed reference loop (slow CPUs and
 * throttled pages show here).
 */
cpuBenchMs: number | null, 
/**
 * Screen.
 */
screen: Screen, 
/**
 * `navigator.userAgentData.mobile`, or guessed from the user agent.
 */
mobile: boolean, 
/**
 * `navigator.deviceMemory` (GiB, rounded by the browser).
 */
deviceMemoryGb: number | null, 
/**
 * `navigator.hardwareConcurrency`.
 */
cores: number | null, };

export type ModeSettings = { 
/**
 * Image or view size in pixels (modes 1, 2), or the client's render
 * resolution (4a, volume).
 */
width: number, 
/**
 * Pixels.
 */
height: number, 
/**
 * JPEG/WebP quality while still.
 */
quality: number, 
/**
 * Size divisor and quality while the user orbits (mode 1 streaming).
 */
movingScale: number, 
/**
 * Quality while moving.
 */
movingQuality: number, 
/**
 * Image encoding.
 */
format: ImageEncoding, 
/**
 * Views per ring and rings (mode 2).
 */
views: number, 
/**
 * Ring pitches (mode 2).
 */
elevations: Array<number>, 
/**
 * Mesh depth (modes 3, 4b); a coarse level first is `coarse_depth`.
 */
meshDepth: number, 
/**
 * Depth of the first, coarse mesh.
 */
coarseDepth: number, 
/**
 * Volume grid (volume mode).
 */
volumeGrid: number, };

export type ModePrediction = { 
/**
 * The mode.
 */
mode: Mode, 
/**
 * Whether the client can show it at all.
 */
feasible: boolean, 
/**
 * Why not, when not feasible.
 */
refusal: string | null, 
/**
 * Predicted ms from the request to the first displayed frame.
 */
firstDisplayMs: number, 
/**
 * Predicted ms per frame while orbiting.
 */
orbitMs: number, 
/**
 * Predicted ms from a parameter change to the updated display.
 */
editMs: number, 
/**
 * Bytes the first display transfers.
 */
bytes: number, 
/**
 * The engine's score (lower is better).
 */
cost: number, };

export type NetworkEstimate = { 
/**
 * Median round trip, ms.
 */
rttMs: number, 
/**
 * Throughput to the client, bits per second.
 */
bandwidthBps: number, 
/**
 * How many probes and pings it rests on.
 */
samples: number, };

export type Decision = { 
/**
 * The mode to use.
 */
mode: Mode, 
/**
 * Its settings.
 */
settings: ModeSettings, 
/**
 * Why, in plain words with the numbers.
 */
reason: string, 
/**
 * Whether the user's override chose it.
 */
overridden: boolean, 
/**
 * What the engine predicted for every mode.
 */
predictions: Array<ModePrediction>, 
/**
 * The network it assumed.
 */
network: NetworkEstimate, 
/**
 * What caused this decision (`connect`, `measurement`, `edit`,
 * `slowFrames`, `override`, `load`, `periodic`).
 */
trigger: string, 
/**
 * 1, 2, 3, … per session.
 */
seq: number, };

export type ClientMessage = { "type": "hello", 
/**
 * The report.
 */
report: ClientReport, } | { "type": "report", 
/**
 * The report.
 */
report: ClientReport, } | { "type": "open", 
/**
 * Model id, or `None` for an unsaved source.
 */
modelId: string | null, 
/**
 * Version (`None`: latest).
 */
version: number | null, 
/**
 * The source when unsaved or edited.
 */
source: string | null, 
/**
 * Parameter values.
 */
params: Array<number>, } | { "type": "pong", 
/**
 * The ping's id.
 */
id: number, } | { "type": "probeDone", 
/**
 * The probe's id.
 */
id: number, 
/**
 * Bytes received.
 */
bytes: number, 
/**
 * ms from the probe's header to its last byte, as the client saw it.
 */
clientMs: number, } | { "type": "camera", 
/**
 * The camera.
 */
camera: CameraView, 
/**
 * Whether the user is still dragging (lower resolution frames).
 */
moving: boolean, 
/**
 * Viewport in device pixels.
 */
width: number, 
/**
 * Viewport in device pixels.
 */
height: number, 
/**
 * The section plane the frames cut the model by (absent: none).
 */
section?: SectionPlane, } | { "type": "frameAck", 
/**
 * The frame's sequence number.
 */
seq: number, 
/**
 * ms from the camera message that asked for it to its display.
 */
latencyMs: number, } | { "type": "displayed", 
/**
 * The mode shown.
 */
mode: Mode, 
/**
 * ms from the request to the first displayed frame.
 */
ms: number, 
/**
 * Bytes transferred for it.
 */
bytes: number, } | { "type": "frameRate", 
/**
 * The mode.
 */
mode: Mode, 
/**
 * Frames per second.
 */
fps: number, 
/**
 * ms per frame (median of the window).
 */
frameMs: number, } | { "type": "override", 
/**
 * The mode, or automatic.
 */
mode: Mode | null, } | { "type": "cancel", 
/**
 * The artefact key.
 */
key: string, };

export type ServerMessage = { "type": "welcome", 
/**
 * The session's id.
 */
sessionId: string, 
/**
 * Server version.
 */
server: string, } | { "type": "ping", 
/**
 * Echoed in the pong.
 */
id: number, } | { "type": "decision", 
/**
 * The decision.
 */
decision: Decision, } | { "type": "artefact", 
/**
 * What it is for (`image`, `viewSet`, `mesh`, `meshCoarse`, …).
 */
role: string, 
/**
 * Where it is.
 */
artefact: ArtefactRef, } | { "type": "progress", 
/**
 * The artefact key.
 */
key: string, 
/**
 * 0 to 1.
 */
fraction: number, } | { "type": "modelChanged", 
/**
 * Model id.
 */
modelId: string, 
/**
 * The new latest version.
 */
version: number, 
/**
 * Who saved it.
 */
author: string, } | { "type": "error", 
/**
 * What went wrong.
 */
message: string, };

export type BinaryHeader = { "type": "probe", 
/**
 * Probe id.
 */
id: number, 
/**
 * Payload bytes.
 */
bytes: number, } | { "type": "frame", 
/**
 * Sequence number.
 */
seq: number, 
/**
 * The camera it shows.
 */
camera: CameraView, 
/**
 * Pixels.
 */
width: number, 
/**
 * Pixels.
 */
height: number, 
/**
 * Encoding of the payload.
 */
format: ImageEncoding, 
/**
 * Server ms to render and encode.
 */
serverMs: number, 
/**
 * Whether it was a moving (reduced) frame.
 */
moving: boolean, };

