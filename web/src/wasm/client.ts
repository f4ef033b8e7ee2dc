/**
 * KernelClient: the page's handle on the kernel worker. Each method posts
 * a request (protocol.ts) and resolves with its answer; a request
 * superseded by a newer one on its channel rejects with
 * {@link KernelCancelled}. One worker serves the whole studio (editor
 * diagnostics, mode 4a's shader, mode 4b's meshes): {@link sharedKernel}.
 */
import type { Diagnostic, ShaderArtefact } from '../wire';
import type { CompileOptions, KernelCompiled, KernelMesh } from './kernel';
import type { Channel, KernelRequest, KernelResponse, ProbeHit } from './protocol';

/** A request superseded by a newer one, or cancelled. */
export class KernelCancelled extends Error {
  override name = 'KernelCancelled';
}

/** An error from the worker (with the model's diagnostics when it does not compile). */
export class KernelWorkerError extends Error {
  override name = 'KernelWorkerError';
  constructor(
    message: string,
    readonly diagnostics: Diagnostic[] = [],
  ) {
    super(message);
  }
}

/** A mesh pass delivered by {@link KernelClient.mesh}. */
export interface MeshPass {
  mesh: KernelMesh;
  depth: number;
  final: boolean;
  bounds: number[];
  ms: number;
}

/** What the client needs of a Worker (a fake in tests). */
export interface WorkerLike {
  postMessage(msg: KernelRequest): void;
  onmessage: ((ev: MessageEvent<KernelResponse>) => void) | null;
  terminate(): void;
}

type Pending = {
  resolve: (r: KernelResponse) => void;
  reject: (e: Error) => void;
  onPass?: (p: MeshPass) => void;
};

type Without<T> = T extends unknown ? Omit<T, 'id'> : never;

export class KernelClient {
  private nextId = 1;
  private readonly pending = new Map<number, Pending>();
  private readonly ready: Promise<void>;

  constructor(
    private readonly worker: WorkerLike,
    wasmUrl = defaultWasmUrl(),
  ) {
    worker.onmessage = (ev) => this.receive(ev.data);
    this.ready = this.send({ kind: 'init', wasmUrl }).then(() => undefined);
  }

  /** Resolves once the module is loaded (rejects when it cannot be). */
  whenReady(): Promise<void> {
    return this.ready;
  }

  private receive(r: KernelResponse): void {
    const p = this.pending.get(r.id);
    if (!p) return;
    if (r.kind === 'mesh' && !r.final) {
      p.onPass?.({ mesh: r.mesh, depth: r.depth, final: false, bounds: r.bounds, ms: r.ms });
      return;
    }
    this.pending.delete(r.id);
    if (r.kind === 'cancelled') p.reject(new KernelCancelled('superseded'));
    else if (r.kind === 'error') p.reject(new KernelWorkerError(r.message, r.diagnostics ?? []));
    else {
      if (r.kind === 'mesh') p.onPass?.({ mesh: r.mesh, depth: r.depth, final: true, bounds: r.bounds, ms: r.ms });
      p.resolve(r);
    }
  }

  private send(req: Without<KernelRequest>, onPass?: (p: MeshPass) => void): Promise<KernelResponse> {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, onPass ? { resolve, reject, onPass } : { resolve, reject });
      this.worker.postMessage({ ...req, id } as KernelRequest);
    });
  }

  /** Diagnostics of a source while typing (no box, nothing kept). */
  async diagnose(source: string, body?: string): Promise<{ ok: boolean; diagnostics: Diagnostic[]; ms: number }> {
    const r = await this.send(body === undefined ? { kind: 'diagnose', source } : { kind: 'diagnose', source, body });
    if (r.kind !== 'diagnostics') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return { ok: r.ok, diagnostics: r.diagnostics, ms: r.ms };
  }

  /** Compiles (and keeps) a model: its summary. */
  async compile(source: string, opts: CompileOptions = {}): Promise<KernelCompiled> {
    const r = await this.send({ kind: 'compile', source, opts });
    if (r.kind !== 'compiled') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return r.compiled;
  }

  /** The ray-casting shader generated in the browser. */
  async shader(source: string, params: number[], bounds: number[] | null = null): Promise<ShaderArtefact> {
    const r = await this.send({ kind: 'shader', source, params, bounds });
    if (r.kind !== 'shader') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return r.shader;
  }

  /**
   * Meshes coarse to fine (`depths`), each pass to `onPass`; resolves with
   * the final pass. A newer mesh request cancels this one between passes.
   */
  async mesh(
    req: { source: string; params: number[]; bounds: number[] | null; depths: number[]; body?: string; method?: 'watertight' | 'dc' | 'mc' },
    onPass: (p: MeshPass) => void,
  ): Promise<MeshPass> {
    const r = await this.send({ kind: 'mesh', ...req }, onPass);
    if (r.kind !== 'mesh') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return { mesh: r.mesh, depth: r.depth, final: true, bounds: r.bounds, ms: r.ms };
  }

  /** Evaluations per second of the WebAssembly batch evaluator on a model. */
  async bench(source: string, points = 65536): Promise<number> {
    const r = await this.send({ kind: 'bench', source, points });
    if (r.kind !== 'bench') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return r.evalsPerSecond;
  }

  /** The attributes s[1..3] as an RGBA volume (alpha 0 where absent). */
  async colorVolume(source: string, params: number[], bounds: number[], grid: number): Promise<Uint8Array> {
    const r = await this.send({ kind: 'colorVolume', source, params, bounds, grid });
    if (r.kind !== 'colorVolume') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return r.rgba;
  }

  /** The value and attributes at a point, or the first surface point along a ray. */
  async probe(req: {
    source: string;
    params: number[];
    point?: [number, number, number];
    ray?: { origin: [number, number, number]; dir: [number, number, number]; bounds: number[] };
  }): Promise<ProbeHit | null> {
    const r = await this.send({ kind: 'probe', ...req });
    if (r.kind !== 'probe') throw new KernelWorkerError(`unexpected answer ${r.kind}`);
    return r.hit;
  }

  /** Stops the running request of a channel at its next pass. */
  cancel(channel: Channel): void {
    this.worker.postMessage({ id: this.nextId++, kind: 'cancel', channel });
  }

  /** Stops the worker; pending requests reject. */
  dispose(): void {
    this.worker.terminate();
    for (const p of this.pending.values()) p.reject(new KernelCancelled('the kernel was stopped'));
    this.pending.clear();
  }
}

/**
 * `/frep.wasm` on the page's origin, absolute: a worker loaded from a blob
 * or another path resolves it the same.
 */
export function defaultWasmUrl(): string {
  return typeof location !== 'undefined' ? new URL('/frep.wasm', location.href).href : '/frep.wasm';
}

let shared: KernelClient | null = null;

/** The studio's one kernel worker, started on first use. */
export function sharedKernel(): KernelClient {
  if (!shared) {
    const worker = new Worker(new URL('./kernel.worker.ts', import.meta.url), { type: 'module' });
    shared = new KernelClient(worker as unknown as WorkerLike);
  }
  return shared;
}

/** The shared kernel once its module is loaded (rejects when it cannot load). */
export async function sharedKernelReady(): Promise<KernelClient> {
  const k = sharedKernel();
  await k.whenReady();
  return k;
}
