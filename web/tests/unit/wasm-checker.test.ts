/**
 * The editor's checker with the WebAssembly kernel in front: errors are
 * answered locally (no server call), a source that compiles goes to the
 * server for its summary, and a kernel that cannot load leaves every
 * check to the server.
 */
import { describe, expect, it } from 'vitest';
import { KernelClient, type WorkerLike } from '../../src/wasm/client';
import { WasmChecker } from '../../src/wasm/checker';
import { KernelHost } from '../../src/wasm/host';
import type { KernelResponse } from '../../src/wasm/protocol';
import type { CompileResponse } from '../../src/wire';
import { example, loadKernel, wasmAvailable } from './wasm-support';

function fakeServer(): { calls: string[]; check: (s: string) => Promise<CompileResponse> } {
  const calls: string[] = [];
  return {
    calls,
    check: async (s: string) => {
      calls.push(s);
      return { ok: true, diagnostics: [], summary: null };
    },
  };
}

describe.skipIf(!wasmAvailable())('WasmChecker', () => {
  it('answers errors locally and asks the server only for good sources', async () => {
    const kernel = await loadKernel();
    const fake: WorkerLike = { onmessage: null, postMessage: (m) => void host.handle(m), terminate: () => undefined };
    const host = new KernelHost(kernel, (r) => fake.onmessage?.({ data: r } as MessageEvent<KernelResponse>));
    const client = new KernelClient(fake);
    const server = fakeServer();
    const checker = new WasmChecker(server, async () => client);
    const bad = await checker.check('my_model(x[3], a[1]) {\n  my_model = 1 +;\n}', []);
    expect(bad.ok).toBe(false);
    expect(bad.diagnostics[0]!.line).toBe(2);
    expect(server.calls).toEqual([]);
    expect(checker.localAnswers).toBe(1);
    const good = await checker.check(example('sphere'), []);
    expect(good.ok).toBe(true);
    expect(server.calls).toHaveLength(1);
  });

  it('starts the kernel only after its gate; until then the server checks', async () => {
    const kernel = await loadKernel();
    const fake: WorkerLike = { onmessage: null, postMessage: (m) => void host.handle(m), terminate: () => undefined };
    const host = new KernelHost(kernel, (r) => fake.onmessage?.({ data: r } as MessageEvent<KernelResponse>));
    const client = new KernelClient(fake);
    const server = fakeServer();
    let open = () => {};
    const gate = new Promise<void>((ok) => (open = ok));
    let started = 0;
    const checker = new WasmChecker(
      server,
      async () => {
        started++;
        return client;
      },
      gate,
    );
    const bad = 'my_model(x[3], a[1]) {\n  my_model = 1 +;\n}';
    await checker.check(bad, []);
    expect(started).toBe(0);
    expect(server.calls).toEqual([bad]);
    open();
    await gate;
    await new Promise((ok) => setTimeout(ok, 0));
    expect(started).toBe(1);
    const r = await checker.check(bad, []);
    expect(r.diagnostics[0]!.line).toBe(2);
    expect(server.calls).toHaveLength(1);
    expect(checker.localAnswers).toBe(1);
  });

  it('leaves every check to the server when the kernel cannot load', async () => {
    const server = fakeServer();
    const checker = new WasmChecker(server, () => Promise.reject(new Error('no wasm')));
    const r = await checker.check('my_model(x[3], a[1]) { my_model = ; }', []);
    expect(r.ok).toBe(true);
    expect(server.calls).toHaveLength(1);
  });
});
