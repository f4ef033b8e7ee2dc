/**
 * The WASM benchmark hook: the client-modes part of the studio (src/wasm)
 * may export `wasmBench(): Promise<number>` (million point evaluations per
 * second of a reference model) from `src/wasm/bench.ts`; it is loaded
 * lazily when present, or registered with {@link registerWasmBench}.
 * Without either the report's `wasmBenchMeps` stays null.
 */

/** Million point evaluations per second. */
export type WasmBench = () => Promise<number>;

let registered: WasmBench | null = null;

/** Registers the benchmark (the kernel calls this when it loads). */
export function registerWasmBench(fn: WasmBench | null): void {
  registered = fn;
}

type BenchModule = { wasmBench?: WasmBench };
const modules = import.meta.glob<BenchModule>('../wasm/bench.ts');

/** Runs the WASM benchmark if one is available (null: none, or it failed). */
export async function runWasmBench(timeoutMs = 3000): Promise<number | null> {
  let fn = registered;
  if (!fn) {
    const load = modules['../wasm/bench.ts'];
    if (load) {
      try {
        fn = (await load()).wasmBench ?? null;
      } catch {
        fn = null;
      }
    }
  }
  if (!fn) return null;
  try {
    const v = await Promise.race([fn(), new Promise<null>((ok) => setTimeout(() => ok(null), timeoutMs))]);
    return typeof v === 'number' && Number.isFinite(v) && v > 0 ? v : null;
  } catch {
    return null;
  }
}
