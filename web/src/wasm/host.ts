/**
 * KernelHost: the worker side of the kernel protocol (protocol.ts), apart
 * from the Worker glue so that Node tests drive it directly.
 *
 * Supersession: each request on a channel becomes that channel's latest;
 * the host yields to the event loop before starting and between passes
 * (coarse mesh, then refined), and a job that is no longer the latest
 * answers `cancelled` there. A WebAssembly call itself cannot be
 * interrupted, so the granularity is one pass.
 *
 * Compiled models are cached by (source, body, parameters), a few at a
 * time; an evicted model is freed in the module and compiled again when
 * needed.
 */
import type { Channel, KernelRequest, KernelResponse, ProbeHit } from './protocol';

import { channelOf } from './protocol';
import type { FrepKernel, KernelCompiled } from './kernel';
import { KernelError, ModelError } from './kernel';

/** How many compiled models the host keeps. */
export const MODEL_CACHE_SIZE = 6;

/** Posts an answer (with buffers to transfer). */
export type Post = (r: KernelResponse, transfer?: Transferable[]) => void;

const now = (): number => (typeof performance !== 'undefined' ? performance.now() : Date.now());

const tick = (): Promise<void> => new Promise((r) => setTimeout(r, 0));

/** Deterministic points in a box, planar (x…, y…, z…): the benchmark's. */
export function benchPoints(bounds: number[], n: number): Float64Array {
  const xyz = new Float64Array(3 * n);
  let s = 0x9e3779b9;
  const rnd = (): number => {
    // xorshift32: the same points on every run.
    s ^= s << 13;
    s ^= s >>> 17;
    s ^= s << 5;
    return (s >>> 0) / 4294967296;
  };
  for (let a = 0; a < 3; a++) {
    const lo = bounds[a] ?? -1;
    const hi = bounds[a + 3] ?? 1;
    for (let i = 0; i < n; i++) xyz[a * n + i] = lo + (hi - lo) * rnd();
  }
  return xyz;
}

/** Samples along a probed ray before bisection. */
export const PROBE_SAMPLES = 1024;

/** Value and attributes at a point (the point evaluator; NaN for an error). */
export function probeAt(kernel: FrepKernel, handle: number, p: [number, number, number], params: number[]): ProbeHit {
  const r = kernel.evalPoint(handle, p[0], p[1], p[2], params);
  if (r.ok) return { point: p, value: r.values[0]!, attributes: r.values.slice(1) };
  return { point: p, value: Number.NaN, attributes: [] };
}

/**
 * The first point of a ray inside `bounds` where the field is >= 0:
 * {@link PROBE_SAMPLES} samples along the clipped ray, then bisection to
 * float precision between the last outside and first inside sample.
 */
export function marchRay(
  kernel: FrepKernel,
  handle: number,
  ray: { origin: [number, number, number]; dir: [number, number, number]; bounds: number[] },
  params: number[],
): [number, number, number] | null {
  const { origin: o, dir: d, bounds: b } = ray;
  let t0 = 0;
  let t1 = Number.POSITIVE_INFINITY;
  for (let a = 0; a < 3; a++) {
    const inv = 1 / (d[a] === 0 ? 1e-30 : d[a]!);
    const ta = (b[a]! - o[a]!) * inv;
    const tb = (b[a + 3]! - o[a]!) * inv;
    t0 = Math.max(t0, Math.min(ta, tb));
    t1 = Math.min(t1, Math.max(ta, tb));
  }
  if (!(t0 < t1)) return null;
  const n = PROBE_SAMPLES;
  const xyz = new Float64Array(3 * n);
  const tAt = (i: number): number => t0 + ((t1 - t0) * i) / (n - 1);
  for (let i = 0; i < n; i++) for (let a = 0; a < 3; a++) xyz[a * n + i] = o[a]! + d[a]! * tAt(i);
  const { values } = kernel.evalPoints(handle, xyz, params);
  let first = -1;
  for (let i = 0; i < n; i++) {
    if (values[i]! >= 0) {
      first = i;
      break;
    }
  }
  if (first < 0) return null;
  const at = (t: number): [number, number, number] => [o[0] + d[0] * t, o[1] + d[1] * t, o[2] + d[2] * t];
  if (first === 0) return at(t0);
  let lo = tAt(first - 1);
  let hi = tAt(first);
  const one = new Float64Array(3);
  for (let k = 0; k < 48 && hi - lo > 1e-12 * Math.max(1, Math.abs(hi)); k++) {
    const m = 0.5 * (lo + hi);
    one.set(at(m));
    if (kernel.evalPoints(handle, one, params).values[0]! >= 0) hi = m;
    else lo = m;
  }
  return at(hi);
}

/** Largest colour volume sampled (samples per axis). */
export const MAX_COLOR_GRID = 128;

/**
 * The attributes `s[1..3]` at the voxel centres of a `grid`³ lattice over
 * `bounds` (x fastest), as RGBA bytes: alpha 255 where the three are
 * numbers, 0 elsewhere (no attributes, or an error there).
 */
export function colorVolume(
  kernel: FrepKernel,
  handle: number,
  bounds: number[],
  grid: number,
  params: number[],
): Uint8Array {
  const n = Math.max(1, Math.min(MAX_COLOR_GRID, Math.floor(grid)));
  const rgba = new Uint8Array(4 * n * n * n);
  const row = n * n;
  // One z slice per call: n² points.
  const xyz = new Float64Array(3 * row);
  // The values of each slice go where the last slice's went.
  let out: Float64Array | undefined;
  const c = (a: number, i: number): number => bounds[a]! + ((i + 0.5) / n) * (bounds[a + 3]! - bounds[a]!);
  for (let k = 0; k < n; k++) {
    for (let j = 0; j < n; j++) {
      for (let i = 0; i < n; i++) {
        const q = j * n + i;
        xyz[q] = c(0, i);
        xyz[row + q] = c(1, j);
        xyz[2 * row + q] = c(2, k);
      }
    }
    const { outputs, values } = kernel.evalPoints(handle, xyz, params, out);
    out = values;
    if (outputs < 4) return rgba;
    for (let q = 0; q < row; q++) {
      const s = [values[row + q]!, values[2 * row + q]!, values[3 * row + q]!];
      const o = 4 * (k * row + q);
      if (s.every((v) => Number.isFinite(v))) {
        for (let a = 0; a < 3; a++) rgba[o + a] = Math.round(255 * Math.max(0, Math.min(1, s[a]!)));
        rgba[o + 3] = 255;
      }
    }
  }
  return rgba;
}

export class KernelHost {
  private readonly latest = new Map<Channel, number>();
  private loading: Promise<FrepKernel> | null = null;
  private readonly models: { key: string; compiled: KernelCompiled }[] = [];

  constructor(
    private kernel: FrepKernel | null,
    private readonly post: Post,
    private readonly load?: (url: string) => Promise<FrepKernel>,
  ) {}

  /** Whether `id` is still its channel's newest request. */
  private current(channel: Channel, id: number): boolean {
    return this.latest.get(channel) === id;
  }

  /** A compiled model for a source (cached); throws with its diagnostics. */
  private model(source: string, body: string | undefined, params: number[]): KernelCompiled {
    const k = this.need();
    const key = JSON.stringify([source, body ?? null, params]);
    const hit = this.models.findIndex((m) => m.key === key);
    if (hit >= 0) {
      const [m] = this.models.splice(hit, 1);
      this.models.push(m!);
      return m!.compiled;
    }
    const opts = body === undefined ? { params } : { body, params };
    const compiled = k.compile(source, opts);
    if (!compiled.ok) throw new ModelError(compiled.diagnostics);
    this.models.push({ key, compiled });
    while (this.models.length > MODEL_CACHE_SIZE) {
      const old = this.models.shift();
      if (old) k.freeModel(old.compiled.handle);
    }
    return compiled;
  }

  private need(): FrepKernel {
    if (!this.kernel) throw new KernelError('the kernel is not loaded yet');
    return this.kernel;
  }

  /** Handles one request; answers through `post`. */
  async handle(req: KernelRequest): Promise<void> {
    const channel = channelOf(req.kind);
    if (channel) this.latest.set(channel, req.id);
    try {
      await this.run(req, channel);
    } catch (e) {
      const message = e instanceof Error ? e.message : String(e);
      this.post(
        e instanceof ModelError
          ? { id: req.id, kind: 'error', message, diagnostics: e.diagnostics }
          : { id: req.id, kind: 'error', message },
      );
    }
  }

  private async run(req: KernelRequest, channel: Channel | null): Promise<void> {
    if (req.kind === 'init') {
      if (!this.kernel && !this.loading) {
        if (!this.load) throw new KernelError('no loader');
        this.loading = this.load(req.wasmUrl);
      }
      if (this.loading) this.kernel = await this.loading;
      this.post({ id: req.id, kind: 'ready' });
      return;
    }
    // Requests sent right after `init` wait for the module.
    if (!this.kernel && this.loading) this.kernel = await this.loading;
    if (req.kind === 'cancel') {
      // A fresh id no job has: the running one stops at its next pass.
      this.latest.set(req.channel, -req.id);
      return;
    }
    // Let a burst of requests arrive: only the newest of a channel runs.
    await tick();
    if (channel && !this.current(channel, req.id)) {
      this.post({ id: req.id, kind: 'cancelled' });
      return;
    }
    const t0 = now();
    switch (req.kind) {
      case 'diagnose': {
        const k = this.need();
        const c = k.compile(req.source, req.body === undefined ? { noBounds: true } : { body: req.body, noBounds: true });
        if (c.ok) k.freeModel(c.handle);
        this.post({ id: req.id, kind: 'diagnostics', ok: c.ok, diagnostics: c.diagnostics, ms: now() - t0 });
        return;
      }
      case 'compile': {
        const c = this.model(req.source, req.opts?.body, req.opts?.params ?? []);
        this.post({ id: req.id, kind: 'compiled', compiled: c, ms: now() - t0 });
        return;
      }
      case 'shader': {
        const c = this.model(req.source, req.body, req.params);
        const bounds = req.bounds ?? c.bounds ?? undefined;
        const shader = this.need().shader(c.handle, bounds ? { bounds, params: req.params } : { params: req.params });
        this.post({ id: req.id, kind: 'shader', shader, ms: now() - t0 });
        return;
      }
      case 'bench': {
        const c = this.model(req.source, undefined, []);
        const xyz = benchPoints(c.bounds ?? [-1, -1, -1, 1, 1, 1], req.points);
        const t1 = now();
        this.need().evalPoints(c.handle, xyz);
        const ms = now() - t1;
        const evalsPerSecond = ms > 0 ? (req.points / ms) * 1000 : Number.POSITIVE_INFINITY;
        this.post({ id: req.id, kind: 'bench', evalsPerSecond, points: req.points, ms });
        return;
      }
      case 'mesh':
        await this.mesh(req);
        return;
      case 'probe': {
        const c = this.model(req.source, undefined, req.params);
        const k = this.need();
        const at = req.point ?? (req.ray ? marchRay(k, c.handle, req.ray, req.params) : null);
        const hit = at ? probeAt(k, c.handle, at, req.params) : null;
        this.post({ id: req.id, kind: 'probe', hit, ms: now() - t0 });
        return;
      }
      case 'colorVolume': {
        const c = this.model(req.source, undefined, req.params);
        const rgba = colorVolume(this.need(), c.handle, req.bounds, req.grid, req.params);
        this.post({ id: req.id, kind: 'colorVolume', rgba, grid: req.grid, ms: now() - t0 }, [rgba.buffer as ArrayBuffer]);
        return;
      }
    }
  }

  private async mesh(req: Extract<KernelRequest, { kind: 'mesh' }>): Promise<void> {
    const depths = req.depths.length > 0 ? req.depths : [6];
    for (let i = 0; i < depths.length; i++) {
      if (i > 0) {
        await tick();
        if (!this.current('mesh', req.id)) {
          this.post({ id: req.id, kind: 'cancelled' });
          return;
        }
      }
      const t0 = now();
      const c = this.model(req.source, req.body, req.params);
      const bounds = req.bounds ?? c.bounds ?? [-10, -10, -10, 10, 10, 10];
      const depth = depths[i]!;
      const mesh = this.need().polygonize(c.handle, {
        bounds,
        depth,
        params: req.params,
        ...(req.method ? { method: req.method } : {}),
      });
      this.post(
        { id: req.id, kind: 'mesh', mesh, depth, final: i === depths.length - 1, bounds, ms: now() - t0 },
        [mesh.positions.buffer as ArrayBuffer],
      );
    }
  }
}
