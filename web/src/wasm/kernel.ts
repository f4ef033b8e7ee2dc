/**
 * FrepKernel: the typed face of the frep kernel compiled to WebAssembly
 * (crates/frep-wasm, built by scripts/build-wasm.sh into /frep.wasm).
 *
 * The module has a raw ABI (no wasm-bindgen): inputs are written into
 * buffers from `frep_alloc`, each call leaves its output in one result
 * buffer (`frep_result_ptr` / `frep_result_len`) that is copied out at
 * once. Memory can grow during any call, so views of `memory.buffer` are
 * made fresh after every call, never kept. Works in a Web Worker, on the
 * main thread and in Node (the tests): no DOM, no fetch unless asked.
 */
import type { Diagnostic, ShaderArtefact } from '../wire';

/** The ABI version this loader speaks (crates/frep-wasm/src/abi.rs). */
export const ABI_VERSION = 1;

/** What compiling a source answers. */
export interface KernelCompiled {
  /** Whether the model compiled (then `handle` is set). */
  ok: boolean;
  /** The model's handle for the other calls (0 when not `ok`). */
  handle: number;
  /** Model errors (empty when `ok`). */
  diagnostics: Diagnostic[];
  /** The compiled body. */
  body: string;
  /** Every body of the file. */
  bodies: string[];
  /** Size of `a[]`. */
  params: number;
  /** Size of `s[]` when declared, else 0. */
  attributes: number;
  /** Nodes of the expression graph. */
  nodes: number;
  /** Operations of the value's tape. */
  tapeLen: number;
  /** The model box (null when asked for none). */
  bounds: number[] | null;
  /** `comment`, `extent`, `default` or `none`. */
  boundsOrigin: string;
  /** Set when the call itself was bad (not UTF-8, bad options). */
  error?: string;
}

/** Options of {@link FrepKernel.compile}. */
export interface CompileOptions {
  /** The body to compile (default: my_model, else the first). */
  body?: string;
  /** Parameter values for the detected extent. */
  params?: number[];
  /** Skip the box (diagnostics while typing: cheaper). */
  noBounds?: boolean;
}

/** Settings of {@link FrepKernel.polygonize}. */
export interface MeshRequest {
  /** The box `x0, y0, z0, x1, y1, z1`. */
  bounds: number[];
  /** Octree depth (2^depth cells along the longest side). */
  depth: number;
  /** `watertight` (default), `dc` or `mc`. */
  method?: 'watertight' | 'dc' | 'mc';
  /** Parameter values `a[]`. */
  params?: number[];
  /** Colours from `s[1..3]` (default true). */
  colors?: boolean;
  /** Most triangles (the module's default: 2,000,000). */
  maxTriangles?: number;
  /** Deepest octree (the module's default: 9). */
  maxDepth?: number;
}

/** A mesh made by the module (see crates/frep-wasm/src/buffers.rs). */
export interface KernelMesh {
  /** Vertices. */
  vertices: number;
  /** Triangles. */
  triangles: number;
  /** xyz per vertex. */
  positions: Float32Array;
  /** Unit normals per vertex, or null. */
  normals: Float32Array | null;
  /** RGB per vertex in [0, 1], or null. */
  colors: Float32Array | null;
  /** Three vertex indices per triangle. */
  indices: Uint32Array;
}

/** A call the module refused: bad handle, bad options, limits. */
export class KernelError extends Error {
  override name = 'KernelError';
}

/** A model that does not compile, with its diagnostics. */
export class ModelError extends KernelError {
  override name = 'ModelError';
  constructor(readonly diagnostics: Diagnostic[]) {
    super(diagnostics[0]?.message ?? 'the model does not compile');
  }
}

interface Exports {
  memory: WebAssembly.Memory;
  frep_abi_version(): number;
  frep_alloc(len: number): number;
  frep_dealloc(ptr: number, len: number): void;
  frep_result_ptr(): number;
  frep_result_len(): number;
  frep_compile(src: number, srcLen: number, opts: number, optsLen: number): number;
  frep_free_model(handle: number): number;
  frep_outputs(handle: number): number;
  frep_eval_points(handle: number, xyz: number, n: number, params: number, nParams: number): number;
  frep_eval_point(handle: number, x: number, y: number, z: number, params: number, nParams: number): number;
  frep_polygonize(handle: number, opts: number, optsLen: number): number;
  frep_shader(handle: number, opts: number, optsLen: number): number;
}

const MESH_MAGIC = 0x314d5246; // "FRM1" little-endian
const HAS_COLORS = 1;
const HAS_NORMALS = 2;

const encoder = new TextEncoder();
const decoder = new TextDecoder();

/** Unpacks the module's mesh buffer (copied views, safe to keep). */
export function unpackMesh(bytes: Uint8Array): KernelMesh {
  if (bytes.byteLength < 16) throw new KernelError('mesh buffer too short');
  const head = new DataView(bytes.buffer, bytes.byteOffset, 16);
  if (head.getUint32(0, true) !== MESH_MAGIC) throw new KernelError('not a frep mesh buffer');
  const vertices = head.getUint32(4, true);
  const triangles = head.getUint32(8, true);
  const flags = head.getUint32(12, true);
  // An aligned copy: the typed arrays need 4-byte alignment.
  const copy = bytes.slice().buffer;
  let at = 16;
  const floats = (n: number): Float32Array => {
    const a = new Float32Array(copy, at, n);
    at += 4 * n;
    return a;
  };
  const positions = floats(3 * vertices);
  const normals = flags & HAS_NORMALS ? floats(3 * vertices) : null;
  const colors = flags & HAS_COLORS ? floats(3 * vertices) : null;
  const indices = new Uint32Array(copy, at, 3 * triangles);
  if (at + 12 * triangles !== copy.byteLength) throw new KernelError('mesh buffer of the wrong size');
  return { vertices, triangles, positions, normals, colors, indices };
}

/**
 * Points kept in the module's memory (planar: all x, all y, all z) by
 * {@link FrepKernel.uploadPoints}: {@link FrepKernel.evalPoints} reads
 * them where they are, with no copy, as often as asked. It holds a
 * pointer, not a view, so memory growth does not invalidate it; free it
 * with {@link FrepKernel.freePoints}.
 */
export class KernelPoints {
  /** @internal */
  constructor(
    /** @internal The kernel that holds them. */
    readonly owner: FrepKernel,
    /** @internal Where they are in the module's memory. */
    readonly ptr: number,
    /** Number of points. */
    readonly n: number,
    /** @internal Whether they were freed. */
    public freed = false,
  ) {}
}

/**
 * Points per module call when {@link FrepKernel.evalPoints} copies points
 * in: the copy in, the evaluation and the copy out of one chunk stay in the
 * core's cache (384 KB of points, 128 KB of values per output), where one
 * call for 262,144 points sends 6 MB through main memory three times over
 * and evaluates a simple model at half the speed.
 */
export const EVAL_CHUNK_POINTS = 16_384;

/** The kernel: one WebAssembly instance (single-threaded; one call at a time). */
export class FrepKernel {
  private readonly x: Exports;
  /** The staging buffer of {@link evalPoints} (0: none yet) and its size in points. */
  private stagePtr = 0;
  private stagePoints = 0;
  /**
   * Points per module call when {@link evalPoints} copies them in (see
   * {@link EVAL_CHUNK_POINTS}); its staging buffer holds that many.
   */
  evalChunkPoints = EVAL_CHUNK_POINTS;

  private constructor(instance: WebAssembly.Instance) {
    this.x = instance.exports as unknown as Exports;
    const v = this.x.frep_abi_version();
    if (v !== ABI_VERSION) {
      throw new KernelError(`frep.wasm speaks ABI ${v}, this loader ${ABI_VERSION}: rebuild it (scripts/build-wasm.sh)`);
    }
  }

  /** From the module's bytes or a compiled module. */
  static async fromBytes(bytes: BufferSource | WebAssembly.Module): Promise<FrepKernel> {
    const module = bytes instanceof WebAssembly.Module ? bytes : await WebAssembly.compile(bytes);
    const instance = await WebAssembly.instantiate(module, {});
    return new FrepKernel(instance);
  }

  /** Fetches and instantiates the module (default `/frep.wasm`). */
  static async fromUrl(url = '/frep.wasm'): Promise<FrepKernel> {
    const res = await fetch(url);
    if (!res.ok) throw new KernelError(`cannot load ${url}: HTTP ${res.status}`);
    return FrepKernel.fromBytes(await res.arrayBuffer());
  }

  /** The module's memory in bytes (for reports). */
  get memoryBytes(): number {
    return this.x.memory.buffer.byteLength;
  }

  private put(bytes: Uint8Array): [number, number] {
    const ptr = this.x.frep_alloc(bytes.byteLength);
    if (ptr === 0) throw new KernelError(`cannot allocate ${bytes.byteLength} bytes in the module`);
    new Uint8Array(this.x.memory.buffer, ptr, bytes.byteLength).set(bytes);
    return [ptr, bytes.byteLength];
  }

  private putF64(values: ArrayLike<number>): [number, number] {
    const len = 8 * values.length;
    const ptr = this.x.frep_alloc(len);
    if (ptr === 0) throw new KernelError(`cannot allocate ${len} bytes in the module`);
    new Float64Array(this.x.memory.buffer, ptr, values.length).set(values);
    return [ptr, len];
  }

  private free(...bufs: [number, number][]): void {
    for (const [p, l] of bufs) this.x.frep_dealloc(p, l);
  }

  /** A copy of the last call's result. */
  private result(): Uint8Array {
    const ptr = this.x.frep_result_ptr();
    const len = this.x.frep_result_len();
    return new Uint8Array(this.x.memory.buffer, ptr, len).slice();
  }

  private text(): string {
    return decoder.decode(this.result());
  }

  private f64(): Float64Array {
    return new Float64Array(this.result().buffer);
  }

  /** Parses and compiles; on success the model stays in the module until {@link freeModel}. */
  compile(source: string, opts: CompileOptions = {}): KernelCompiled {
    const src = this.put(encoder.encode(source));
    const o = this.put(encoder.encode(JSON.stringify(opts)));
    try {
      this.x.frep_compile(src[0], src[1], o[0], o[1]);
    } finally {
      this.free(src, o);
    }
    const r = JSON.parse(this.text()) as KernelCompiled;
    if (r.error !== undefined) throw new KernelError(r.error);
    return r;
  }

  /** Forgets a model; false when the handle was unknown. */
  freeModel(handle: number): boolean {
    return this.x.frep_free_model(handle) === 1;
  }

  /** Outputs per point: the value, then the attributes. */
  outputs(handle: number): number {
    const k = this.x.frep_outputs(handle);
    if (k < 0) throw new KernelError(this.text());
    return k;
  }

  /**
   * Batch evaluation at `n` points given planar (all x, then all y, then
   * all z): output-major values, NaN where an error reaches an output.
   * The values are copied into `out` when it is long enough (returned as
   * its first `outputs·n` numbers), else into a new array: a caller that
   * evaluates again and again passes the last `values` back and allocates
   * nothing (a fresh array costs more than the copy). Points given as a
   * Float64Array are copied into the module chunk by chunk
   * ({@link EVAL_CHUNK_POINTS}); {@link KernelPoints} are read where they
   * are, in one call. The values do not depend on the chunks: each point's
   * are its own.
   */
  evalPoints(
    handle: number,
    xyz: Float64Array | KernelPoints,
    params: number[] = [],
    out?: Float64Array,
  ): { outputs: number; values: Float64Array } {
    const take = (len: number): Float64Array =>
      out && out.length >= len ? out.subarray(0, len) : new Float64Array(len);
    const a = this.putF64(params);
    try {
      if (xyz instanceof KernelPoints) {
        if (xyz.owner !== this) throw new KernelError('points uploaded to another kernel');
        if (xyz.freed) throw new KernelError('points already freed');
        const k = this.x.frep_eval_points(handle, xyz.ptr, xyz.n, a[0], params.length);
        if (k < 0) throw new KernelError(this.text());
        const values = take(k * xyz.n);
        values.set(new Float64Array(this.x.memory.buffer, this.x.frep_result_ptr(), k * xyz.n));
        return { outputs: k, values };
      }
      if (xyz.length % 3 !== 0) throw new KernelError('points: a multiple of 3 numbers (planar x, y, z)');
      const n = xyz.length / 3;
      const chunk = Math.max(1, Math.floor(this.evalChunkPoints));
      const stage = this.stage(Math.min(n, chunk));
      let values: Float64Array | null = null;
      let k = 0;
      let s = 0;
      // One call per chunk; at least one, which gives `k` when n is 0.
      do {
        const m = Math.min(chunk, n - s);
        // A fresh view: the last call may have grown the memory.
        const mem = new Float64Array(this.x.memory.buffer);
        for (let c = 0; c < 3; c++) mem.set(xyz.subarray(c * n + s, c * n + s + m), stage / 8 + c * m);
        const got = this.x.frep_eval_points(handle, stage, m, a[0], params.length);
        if (got < 0) throw new KernelError(this.text());
        if (!values) {
          k = got;
          values = take(k * n);
        }
        // The chunk's outputs are planes of m values: each goes to its
        // place in the output-major whole.
        const res = new Float64Array(this.x.memory.buffer, this.x.frep_result_ptr(), k * m);
        for (let o = 0; o < k; o++) values.set(res.subarray(o * m, (o + 1) * m), o * n + s);
        s += m;
      } while (s < n);
      return { outputs: k, values: values ?? take(0) };
    } finally {
      this.free(a);
    }
  }

  /** The staging buffer for `n` points (kept, grown when needed). */
  private stage(n: number): number {
    if (n > this.stagePoints || this.stagePtr === 0) {
      if (this.stagePtr !== 0) this.free([this.stagePtr, 24 * this.stagePoints]);
      this.stagePtr = 0;
      this.stagePoints = 0;
      const ptr = this.x.frep_alloc(24 * Math.max(1, n));
      if (ptr === 0) throw new KernelError(`cannot allocate ${24 * n} bytes in the module`);
      this.stagePtr = ptr;
      this.stagePoints = Math.max(1, n);
    }
    return this.stagePtr;
  }

  /**
   * Copies points (planar: all x, all y, all z) into the module once, for
   * repeated {@link evalPoints} with no copy in (see {@link KernelPoints}).
   */
  uploadPoints(xyz: Float64Array): KernelPoints {
    if (xyz.length % 3 !== 0) throw new KernelError('points: a multiple of 3 numbers (planar x, y, z)');
    const [ptr] = this.putF64(xyz);
    return new KernelPoints(this, ptr, xyz.length / 3);
  }

  /** Gives back the memory of uploaded points (once; later uses throw). */
  freePoints(points: KernelPoints): void {
    if (points.owner !== this) throw new KernelError('points uploaded to another kernel');
    if (points.freed) return;
    points.freed = true;
    this.free([points.ptr, 24 * points.n]);
  }

  /** One point with the reference interpreter's runtime errors. */
  evalPoint(
    handle: number,
    x: number,
    y: number,
    z: number,
    params: number[] = [],
  ): { ok: true; values: number[] } | { ok: false; error: string } {
    const a = this.putF64(params);
    let s: number;
    try {
      s = this.x.frep_eval_point(handle, x, y, z, a[0], params.length);
    } finally {
      this.free(a);
    }
    if (s === 0) return { ok: true, values: Array.from(this.f64()) };
    if (s === 1) return { ok: false, error: this.text() };
    throw new KernelError(this.text());
  }

  /** The packed mesh bytes (crates/frep-wasm/src/buffers.rs). */
  polygonizeBytes(handle: number, req: MeshRequest): Uint8Array {
    const o = this.put(encoder.encode(JSON.stringify(req)));
    let s: number;
    try {
      s = this.x.frep_polygonize(handle, o[0], o[1]);
    } finally {
      this.free(o);
    }
    if (s !== 0) throw new KernelError(this.text());
    return this.result();
  }

  /** Polygonizes (single-threaded frep-mesh). */
  polygonize(handle: number, req: MeshRequest): KernelMesh {
    return unpackMesh(this.polygonizeBytes(handle, req));
  }

  /** The ray-casting shader, as the server's `shader` artefact. */
  shader(handle: number, opts: { bounds?: number[]; params?: number[] } = {}): ShaderArtefact {
    const o = this.put(encoder.encode(JSON.stringify(opts)));
    let s: number;
    try {
      s = this.x.frep_shader(handle, o[0], o[1]);
    } finally {
      this.free(o);
    }
    if (s !== 0) throw new KernelError(this.text());
    return JSON.parse(this.text()) as ShaderArtefact;
  }
}
