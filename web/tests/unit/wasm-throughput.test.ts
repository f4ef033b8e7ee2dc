/**
 * Throughput of the WebAssembly kernel, printed to set beside the native
 * figures of `cargo run --release -p frep-wasm --example throughput` (same
 * models, points and depth). A benchmark, not a timed assertion: it only
 * checks the work was done. The full measurement (best of 6 evaluations,
 * 3 meshes) runs with FREP_BENCH=1; otherwise one round of each.
 */
import { describe, expect, it } from 'vitest';
import { benchPoints } from '../../src/wasm/host';
import { example, loadKernel, wasmAvailable } from './wasm-support';

const MODELS = ['sphere', 'm2_spheres100', 'm3_gyroid', 'm4_rblend10'];
const POINTS = 262_144;
const FULL = !!process.env.FREP_BENCH;

describe.skipIf(!wasmAvailable())('WebAssembly throughput', () => {
  it('evaluates and meshes the benchmark models', async () => {
    const kernel = await loadKernel();
    for (const name of MODELS) {
      const c = kernel.compile(example(name));
      const xyz = benchPoints(c.bounds!, POINTS);
      let best = Infinity;
      for (let r = 0; r < (FULL ? 6 : 1); r++) {
        const t = performance.now();
        const { values } = kernel.evalPoints(c.handle, xyz);
        best = Math.min(best, performance.now() - t);
        expect(values.length).toBeGreaterThanOrEqual(POINTS);
      }
      let meshBest = Infinity;
      for (let r = 0; r < (FULL ? 3 : 1); r++) {
        const t = performance.now();
        const m = kernel.polygonize(c.handle, { bounds: c.bounds!, depth: 7 });
        meshBest = Math.min(meshBest, performance.now() - t);
        expect(m.triangles).toBeGreaterThan(0);
      }
      console.log(`${name}: ${(POINTS / best / 1e3).toFixed(1)} M evals/s, depth-7 mesh ${meshBest.toFixed(1)} ms (wasm)`);
    }
  }, 120_000);
});
