/**
 * FrepKernel.evalPoints's two ways in and its way out: points copied in
 * per call (chunk by chunk) or kept in the module (KernelPoints), values
 * into a fresh array or into the caller's. Checked against the sphere's
 * closed form and against each other.
 */
import { describe, expect, it } from 'vitest';
import { benchPoints } from '../../src/wasm/host';
import { KernelError } from '../../src/wasm/kernel';
import { example, loadKernel, wasmAvailable } from './wasm-support';

/** hfSphere(x, [0, 0, 0], 1) = 1 - |p|², planar points. */
function sphere(xyz: Float64Array): number[] {
  const n = xyz.length / 3;
  return Array.from({ length: n }, (_, i) => 1 - xyz[i]! ** 2 - xyz[n + i]! ** 2 - xyz[2 * n + i]! ** 2);
}

describe.skipIf(!wasmAvailable())('WebAssembly point evaluation', () => {
  it('fills the caller array when it is long enough, else a new one', async () => {
    const k = await loadKernel();
    const c = k.compile(example('sphere'));
    const xyz = benchPoints(c.bounds!, 300);
    const want = sphere(xyz);
    const fresh = k.evalPoints(c.handle, xyz).values;
    want.forEach((w, i) => expect(fresh[i]!).toBeCloseTo(w, 12));
    const out = new Float64Array(500).fill(Number.NaN);
    const into = k.evalPoints(c.handle, xyz, [], out);
    expect(into.values.buffer).toBe(out.buffer);
    expect(Array.from(into.values)).toEqual(Array.from(fresh));
    // Too short: a new array, the caller's untouched.
    const short = new Float64Array(10);
    const other = k.evalPoints(c.handle, xyz, [], short).values;
    expect(other.buffer).not.toBe(short.buffer);
    expect(Array.from(short)).toEqual(new Array(10).fill(0));
    expect(Array.from(other)).toEqual(Array.from(fresh));
  });

  it('gives the same values whatever the chunks, outputs in their planes', async () => {
    const k = await loadKernel();
    const c = k.compile(example('android_robot'));
    const n = 1001;
    const xyz = benchPoints(c.bounds!, n);
    const kept = k.uploadPoints(xyz);
    const whole = k.evalPoints(c.handle, kept);
    expect(whole.outputs).toBeGreaterThan(1);
    expect(whole.values.length).toBe(whole.outputs * n);
    for (const chunk of [1, 7, 1000, 1001, 5000]) {
      k.evalChunkPoints = chunk;
      const r = k.evalPoints(c.handle, xyz, [], new Float64Array(whole.values.length).fill(-1));
      expect(r.outputs).toBe(whole.outputs);
      expect(Array.from(r.values)).toEqual(Array.from(whole.values));
    }
    // No points: no values, still the number of outputs.
    expect(k.evalPoints(c.handle, new Float64Array(0))).toEqual({ outputs: whole.outputs, values: new Float64Array(0) });
    expect(() => k.evalPoints(c.handle + 100, xyz)).toThrow(/no model/);
  });

  it('keeps points in the module across calls and memory growth', async () => {
    const k = await loadKernel();
    const c = k.compile(example('sphere'));
    const xyz = benchPoints(c.bounds!, 1000);
    const kept = k.uploadPoints(xyz);
    expect(kept.n).toBe(1000);
    const first = Array.from(k.evalPoints(c.handle, kept).values);
    expect(first).toEqual(Array.from(k.evalPoints(c.handle, xyz).values));
    // A large evaluation grows the module's memory: the kept points are
    // found by address, not through a view of the old buffer.
    const bytes = k.memoryBytes;
    k.evalPoints(c.handle, benchPoints(c.bounds!, 1 << 20));
    expect(k.memoryBytes).toBeGreaterThan(bytes);
    expect(Array.from(k.evalPoints(c.handle, kept).values)).toEqual(first);
    k.freePoints(kept);
    expect(() => k.evalPoints(c.handle, kept)).toThrow(KernelError);
    k.freePoints(kept); // a second free does nothing
    const k2 = await loadKernel();
    const elsewhere = k2.uploadPoints(xyz);
    expect(() => k.evalPoints(c.handle, elsewhere)).toThrow(/another kernel/);
    expect(() => k.uploadPoints(new Float64Array(4))).toThrow(KernelError);
  });
});
