/**
 * The editor's checker (src/editor/checker.ts's `Checker`) with the
 * WebAssembly kernel in front: a source with errors gets its diagnostics
 * from the kernel in the worker, with no round trip; a source that
 * compiles goes on to the server for its summary (parameter names and
 * ranges, the graph hash, the decision's figures), which only the server
 * has. When the kernel cannot load, every check goes to the server.
 *
 * The kernel can be started late (`after`): compiling it takes a core
 * that the first display needs. Until it starts, checks go to the server.
 */
import type { Checker } from '../editor/checker';
import type { CompileResponse } from '../wire';
import type { KernelClient } from './client';
import { KernelCancelled } from './client';

export class WasmChecker implements Checker {
  private kernel: Promise<KernelClient | null> | null = null;
  /** Checks answered by the kernel alone (for the tests and the panel). */
  localAnswers = 0;

  constructor(
    private readonly server: Checker,
    kernel: () => Promise<KernelClient>,
    after?: Promise<unknown>,
  ) {
    const start = () => (this.kernel = kernel().catch(() => null));
    if (after) void after.catch(() => {}).then(start);
    else start();
  }

  async check(source: string, params: number[], signal?: AbortSignal): Promise<CompileResponse> {
    const k = this.kernel ? await this.kernel : null;
    if (k) {
      try {
        const d = await k.diagnose(source);
        if (signal?.aborted) throw new DOMException('superseded', 'AbortError');
        if (!d.ok) {
          this.localAnswers++;
          return { ok: false, diagnostics: d.diagnostics, summary: null };
        }
      } catch (e) {
        if (e instanceof KernelCancelled) throw new DOMException('superseded', 'AbortError');
        if (e instanceof DOMException && e.name === 'AbortError') throw e;
        // The kernel failed on this source: the server decides.
      }
    }
    return this.server.check(source, params, signal);
  }
}

/**
 * The studio's checker: the shared kernel worker in front of `server`
 * (`new WasmChecker(server, sharedKernelReady)` is the same, synchronously).
 */
export async function wasmChecker(server: Checker): Promise<WasmChecker> {
  const { sharedKernelReady } = await import('./client');
  return new WasmChecker(server, sharedKernelReady);
}
