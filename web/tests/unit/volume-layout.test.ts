/**
 * The volume mode's pieces in Node: the grids fetched coarse then fine,
 * the `x-frep-volume` header checked against the body, and the colour
 * volume the WebAssembly kernel samples from the attributes.
 */
import { describe, expect, it } from 'vitest';
import { DEFAULT_VOLUME, parseVolumeLayout, volumeGrids } from '../../src/viewer/modes/volume';
import { colorVolume } from '../../src/wasm/host';
import { example, loadKernel, wasmAvailable } from './wasm-support';

describe('volume mode', () => {
  it('fetches a coarse grid first, then the decided one', () => {
    expect(volumeGrids(undefined)).toEqual([64, 128]);
    expect(volumeGrids(96)).toEqual([64, 96]);
    expect(volumeGrids(48)).toEqual([48]);
    expect(volumeGrids(128, { ...DEFAULT_VOLUME, coarseGrid: 0 })).toEqual([128]);
  });

  it('reads the layout header and checks it against the bytes', () => {
    const h = JSON.stringify({ dims: [4, 4, 2], bounds: [-1, -1, -1, 1, 1, 1], scale: 0.5 });
    expect(parseVolumeLayout(h, 32).dims).toEqual([4, 4, 2]);
    expect(() => parseVolumeLayout(h, 31)).toThrow(/31 bytes/);
    expect(() => parseVolumeLayout(null, 32)).toThrow(/x-frep-volume/);
  });

  it.skipIf(!wasmAvailable())('samples the attributes as colours where the model has them', async () => {
    const k = await loadKernel();
    const robot = k.compile(example('android_robot'));
    const rgba = colorVolume(k, robot.handle, robot.bounds!, 16, []);
    expect(rgba.length).toBe(4 * 16 ** 3);
    const opaque = rgba.filter((_, i) => i % 4 === 3 && rgba[i] === 255).length;
    expect(opaque).toBe(16 ** 3);
    // The robot is green: green dominates somewhere.
    let green = 0;
    for (let i = 0; i < rgba.length; i += 4) if (rgba[i + 1]! > rgba[i]! + 20 && rgba[i + 1]! > rgba[i + 2]! + 100) green++;
    expect(green).toBeGreaterThan(0);
    const sphere = k.compile(example('sphere'));
    expect(colorVolume(k, sphere.handle, sphere.bounds!, 8, []).every((b) => b === 0)).toBe(true);
  });
});
