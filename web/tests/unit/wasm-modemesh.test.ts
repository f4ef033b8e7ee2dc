/**
 * Mode 4b's pieces in Node: depths coarse then refined from a decision's
 * settings, and the three.js geometry of a mesh from the WebAssembly kernel
 * (indices, normals, sRGB attribute colours turned linear).
 */
import { describe, expect, it } from 'vitest';
import { DEFAULT_DEPTHS, MAX_BROWSER_DEPTH, meshDepths, meshGeometry } from '../../src/viewer/modes/wasmmesh';
import { example, loadKernel, wasmAvailable } from './wasm-support';

describe('mode 4b', () => {
  it('meshes coarse first, then at the decided depth, within the browser limit', () => {
    expect(meshDepths(null)).toEqual([DEFAULT_DEPTHS.coarse, DEFAULT_DEPTHS.fine]);
    expect(meshDepths({ meshDepth: 6, coarseDepth: 4 })).toEqual([4, 6]);
    expect(meshDepths({ meshDepth: 11, coarseDepth: 5 })).toEqual([5, MAX_BROWSER_DEPTH]);
    expect(meshDepths({ meshDepth: 5, coarseDepth: 5 })).toEqual([5]);
  });

  it.skipIf(!wasmAvailable())('turns a kernel mesh into a three.js geometry', async () => {
    const k = await loadKernel();
    const c = k.compile(example('android_robot'));
    const m = k.polygonize(c.handle, { bounds: c.bounds!, depth: 4 });
    const g = meshGeometry(m);
    expect(g.getAttribute('position').count).toBe(m.vertices);
    expect(g.getIndex()!.count).toBe(3 * m.triangles);
    expect(g.getAttribute('normal').count).toBe(m.vertices);
    const col = g.getAttribute('color');
    expect(col.count).toBe(m.vertices);
    // sRGB 0.5 is linear ~0.214: the colours were converted.
    const i = Array.from(m.colors!).findIndex((v) => v > 0.2 && v < 0.9);
    if (i >= 0) expect(col.array[i]!).toBeLessThan(m.colors![i]!);
    expect(g.boundingSphere!.radius).toBeGreaterThan(0.5);
  });
});
