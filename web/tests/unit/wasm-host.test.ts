/**
 * The kernel worker's protocol (src/wasm/host.ts) driven in Node with the
 * built module: diagnostics while typing, a newer mesh request cancelling
 * an older one between its passes, coarse-then-refined passes, the shader
 * generated in the browser, and the client (src/wasm/client.ts) over a
 * fake worker.
 */
import { beforeAll, describe, expect, it } from 'vitest';
import type { FrepKernel } from '../../src/wasm/kernel';
import { KernelHost } from '../../src/wasm/host';
import type { KernelRequest, KernelResponse } from '../../src/wasm/protocol';
import { KernelCancelled, KernelClient, KernelWorkerError, type WorkerLike } from '../../src/wasm/client';
import { example, loadKernel, wasmAvailable } from './wasm-support';

const settle = (): Promise<void> => new Promise((r) => setTimeout(r, 20));

describe.skipIf(!wasmAvailable())('kernel worker protocol', () => {
  let kernel: FrepKernel;
  beforeAll(async () => {
    kernel = await loadKernel();
  });

  function host(): { host: KernelHost; out: KernelResponse[] } {
    const out: KernelResponse[] = [];
    return { host: new KernelHost(kernel, (r) => out.push(r)), out };
  }

  it('reports diagnostics with their place', async () => {
    const { host: h, out } = host();
    await h.handle({ id: 1, kind: 'diagnose', source: 'my_model(x[3], a[1]) {\n  my_model = hfSpere(x, 1);\n}' });
    const r = out[0]!;
    expect(r.kind).toBe('diagnostics');
    if (r.kind !== 'diagnostics') return;
    expect(r.ok).toBe(false);
    expect(r.diagnostics[0]!.line).toBe(2);
    expect(r.diagnostics[0]!.message).toMatch(/hfspere/i);
    await h.handle({ id: 2, kind: 'diagnose', source: example('sphere') });
    expect(out[1]).toMatchObject({ kind: 'diagnostics', ok: true, diagnostics: [] });
  });

  it('meshes coarse then refined; a newer request cancels the older between passes', async () => {
    const { host: h, out } = host();
    const req = (id: number, source: string): KernelRequest => ({
      id,
      kind: 'mesh',
      source,
      params: [],
      bounds: null,
      depths: [3, 5],
    });
    const first = h.handle(req(1, example('sphere')));
    // Arrives while the first is between its passes (or before it starts).
    const second = h.handle(req(2, example('m3_gyroid')));
    await Promise.all([first, second]);
    const of1 = out.filter((r) => r.id === 1).map((r) => r.kind);
    expect(of1[of1.length - 1]).toBe('cancelled');
    expect(of1.filter((k) => k === 'mesh').length).toBeLessThan(2);
    const of2 = out.filter((r) => r.id === 2);
    expect(of2.map((r) => r.kind)).toEqual(['mesh', 'mesh']);
    const [coarse, fine] = of2 as Extract<KernelResponse, { kind: 'mesh' }>[];
    expect([coarse!.depth, coarse!.final, fine!.depth, fine!.final]).toEqual([3, false, 5, true]);
    expect(fine!.mesh.triangles).toBeGreaterThan(coarse!.mesh.triangles);
    expect(fine!.bounds).toEqual([-1, -1, -1, 1, 1, 1]);
  });

  it('a model with errors answers its diagnostics', async () => {
    const { host: h, out } = host();
    await h.handle({ id: 5, kind: 'shader', source: 'my_model(x[3], a[1]) { my_model = ; }', params: [], bounds: null });
    expect(out[0]).toMatchObject({ kind: 'error' });
    if (out[0]!.kind === 'error') expect(out[0]!.diagnostics?.length).toBe(1);
  });

  it('generates the same shader as the server would', async () => {
    const { host: h, out } = host();
    await h.handle({ id: 7, kind: 'shader', source: example('sphere'), params: [], bounds: null });
    const r = out[0]!;
    expect(r.kind).toBe('shader');
    if (r.kind !== 'shader') return;
    expect(r.shader.source.startsWith('#version 300 es')).toBe(true);
    expect(r.shader.bounds).toEqual([-1.2, -1.2, -1.2, 1.2, 1.2, 1.2]);
    expect(r.shader.uniforms.map((u) => u.name)).toContain('u_consts');
  });

  it('probes a point and the first surface along a ray', async () => {
    const { host: h, out } = host();
    // The unit sphere (f = 1 - |p|^2), from +x towards the origin.
    await h.handle({
      id: 9,
      kind: 'probe',
      source: example('sphere'),
      params: [],
      ray: { origin: [3, 0, 0], dir: [-1, 0, 0], bounds: [-1.2, -1.2, -1.2, 1.2, 1.2, 1.2] },
    });
    const r = out[0]!;
    expect(r.kind).toBe('probe');
    if (r.kind !== 'probe') return;
    expect(r.hit!.point[0]).toBeCloseTo(1, 9);
    expect(Math.abs(r.hit!.value)).toBeLessThan(1e-9);
    await h.handle({ id: 10, kind: 'probe', source: example('android_robot'), params: [], point: [0, 0, 0] });
    const p = out[1]!;
    if (p.kind !== 'probe') throw new Error(p.kind);
    expect(p.hit!.value).toBeGreaterThan(0);
    [0.64, 0.78, 0.22].forEach((v, i) => expect(p.hit!.attributes[i]).toBeCloseTo(v, 12));
    await h.handle({
      id: 11,
      kind: 'probe',
      source: example('sphere'),
      params: [],
      ray: { origin: [3, 3, 0], dir: [0, 0, 1], bounds: [-1.2, -1.2, -1.2, 1.2, 1.2, 1.2] },
    });
    expect(out[2]).toMatchObject({ kind: 'probe', hit: null });
  });

  it('the client resolves answers and rejects superseded requests', async () => {
    const h = new KernelHost(kernel, (r) => fake.onmessage?.({ data: r } as MessageEvent<KernelResponse>));
    const fake: WorkerLike = {
      onmessage: null,
      postMessage: (m) => void h.handle(m),
      terminate: () => undefined,
    };
    const client = new KernelClient(fake);
    await client.whenReady();
    const a = client.compile(example('sphere'));
    const b = client.compile(example('m1_sphere'));
    await expect(a).rejects.toBeInstanceOf(KernelCancelled);
    expect((await b).bounds).toEqual([-1, -1, -1, 1, 1, 1]);
    await expect(client.shader('x(', [])).rejects.toBeInstanceOf(KernelWorkerError);
    const passes: number[] = [];
    const last = await client.mesh({ source: example('sphere'), params: [], bounds: null, depths: [2, 4] }, (p) =>
      passes.push(p.depth),
    );
    expect(passes).toEqual([2, 4]);
    expect(last.final).toBe(true);
    expect(await client.bench(example('sphere'), 1000)).toBeGreaterThan(0);
    await settle();
  });
});
