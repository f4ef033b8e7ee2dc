/**
 * Throughput of the WebAssembly kernel, printed to set beside the native
 * figures of `cargo run --release -p frep-wasm --example throughput` (same
 * models, points and depth). A benchmark, not a timed assertion: it only
 * checks the work was done. The full measurement (best of 6 evaluations,
 * 3 meshes) runs with FREP_BENCH=1; otherwise one round of each.
 *
 * Two figures per model: the points copied into the module on each call
 * (a Float64Array), and the points kept there (KernelPoints), which is
 * what the native example does (its points stay in one Vec). Both copy
 * the values out into the last call's array, as the native example fills
 * its kept Vec: neither allocates per call.
 */
import { describe, expect, it } from 'vitest';
import { benchPoints } from '../../src/wasm/host';
import type { KernelPoints } from '../../src/wasm/kernel';
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
      const resident = kernel.uploadPoints(xyz);
      let out: Float64Array | undefined;
      const bestOf = (points: Float64Array | KernelPoints): number => {
        let best = Infinity;
        for (let r = 0; r < (FULL ? 6 : 1); r++) {
          const t = performance.now();
          const { values } = kernel.evalPoints(c.handle, points, [], out);
          best = Math.min(best, performance.now() - t);
          expect(values.length).toBe(POINTS);
          out = values;
        }
        return best;
      };
      const copied = bestOf(xyz);
      const kept = bestOf(resident);
      // The same values either way.
      const again = kernel.evalPoints(c.handle, xyz).values;
      expect(kernel.evalPoints(c.handle, resident).values).toEqual(again);
      kernel.freePoints(resident);
      let meshBest = Infinity;
      for (let r = 0; r < (FULL ? 3 : 1); r++) {
        const t = performance.now();
        const m = kernel.polygonize(c.handle, { bounds: c.bounds!, depth: 7 });
        meshBest = Math.min(meshBest, performance.now() - t);
        expect(m.triangles).toBeGreaterThan(0);
      }
      const rate = (ms: number): string => (POINTS / ms / 1e3).toFixed(1);
      console.log(
        `${name}: ${rate(copied)} M evals/s (points copied in), ${rate(kept)} M evals/s (points kept), depth-7 mesh ${meshBest.toFixed(1)} ms (wasm)`,
      );
    }
  }, 120_000);
});
