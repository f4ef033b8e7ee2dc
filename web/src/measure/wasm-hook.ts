/**
 * The WASM benchmark hook, in order: a function registered with
 * {@link registerWasmBench}; `wasmBench(): Promise<number>` (million point
 * evaluations per second) from `src/wasm/bench.ts` when that exists; else
 * the kernel worker's own `bench` (src/wasm/client.ts) on
 * {@link BENCH_SOURCE}. All are loaded lazily; without any, or when the
 * kernel fails (no /frep.wasm), the report's `wasmBenchMeps` stays null.
 */

/** Million point evaluations per second. */
export type WasmBench = () => Promise<number>;

let registered: WasmBench | null = null;

/** Registers the benchmark (the kernel calls this when it loads). */
export function registerWasmBench(fn: WasmBench | null): void {
  registered = fn;
}

type BenchModule = { wasmBench?: WasmBench };
type KernelModule = { sharedKernel?: () => { whenReady(): Promise<void>; bench(source: string, points?: number): Promise<number> } };
const modules = import.meta.glob<BenchModule>('../wasm/bench.ts');
const kernels = import.meta.glob<KernelModule>('../wasm/client.ts');

/** The reference model: a blend of a sphere and a torus (a few dozen operations a point). */
export const BENCH_SOURCE = [
  'my_model(x[3], a[1])',
  '{',
  '  array c[3];',
  '  c = [0, 0, 0];',
  '  my_model = hfBlendUni(hfSphere(x, c, 1), hfTorusZ(x, c, 0.8, 0.3), 0.2, 1, 1);',
  '}',
  '',
].join('\n');

/** Points evaluated by the kernel's benchmark. */
export const BENCH_POINTS = 65536;

async function kernelBench(): Promise<WasmBench | null> {
  const load = kernels['../wasm/client.ts'];
  if (!load) return null;
  const mod = await load();
  if (!mod.sharedKernel) return null;
  const k = mod.sharedKernel();
  return async () => {
    await k.whenReady();
    return (await k.bench(BENCH_SOURCE, BENCH_POINTS)) / 1e6;
  };
}

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
  if (!fn) fn = await kernelBench().catch(() => null);
  if (!fn) return null;
  try {
    const v = await Promise.race([fn(), new Promise<null>((ok) => setTimeout(() => ok(null), timeoutMs))]);
    return typeof v === 'number' && Number.isFinite(v) && v > 0 ? v : null;
  } catch {
    return null;
  }
}
