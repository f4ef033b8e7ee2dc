/**
 * Meshes made by the WebAssembly kernel equal the native mesher's for the
 * same settings: the packed bytes hash to the values in
 * web/tests/node/fixtures/meshes.json, which crates/frep-wasm's native test
 * writes from frep-mesh (rayon) and checks against the bindings.
 */
import { readFileSync } from 'node:fs';
import { join } from 'node:path';
import { beforeAll, describe, expect, it } from 'vitest';
import { type FrepKernel, KernelError, unpackMesh } from '../../src/wasm/kernel';
import { example, loadKernel, repoRoot, wasmAvailable } from './wasm-support';

interface Fixture {
  name: string;
  depth: number;
  bounds: number[];
  vertices: number;
  triangles: number;
  colors: boolean;
  fnv1a: string;
}

/** FNV-1a 64 as 16 hex digits (the Rust test's). */
function fnv1a(bytes: Uint8Array): string {
  let h = 0xcbf29ce484222325n;
  const p = 0x100000001b3n;
  const mask = (1n << 64n) - 1n;
  for (const b of bytes) {
    h ^= BigInt(b);
    h = (h * p) & mask;
  }
  return h.toString(16).padStart(16, '0');
}

const fixtures = (
  JSON.parse(readFileSync(join(repoRoot, 'web/tests/node/fixtures/meshes.json'), 'utf8')) as { meshes: Fixture[] }
).meshes;

describe.skipIf(!wasmAvailable())('WebAssembly meshes', () => {
  let kernel: FrepKernel;
  beforeAll(async () => {
    kernel = await loadKernel();
  });

  it.each(fixtures.map((f) => [f.name, f] as const))('%s equals the native mesh', (_, f) => {
    const c = kernel.compile(example(f.name));
    expect(c.ok).toBe(true);
    expect(c.bounds).toEqual(f.bounds);
    const bytes = kernel.polygonizeBytes(c.handle, { bounds: f.bounds, depth: f.depth });
    const mesh = unpackMesh(bytes);
    expect(mesh.vertices).toBe(f.vertices);
    expect(mesh.triangles).toBe(f.triangles);
    expect(mesh.colors !== null).toBe(f.colors);
    expect(mesh.indices.every((i) => i < mesh.vertices)).toBe(true);
    expect(fnv1a(bytes)).toBe(f.fnv1a);
    kernel.freeModel(c.handle);
  });

  it('refuses what the limits forbid, with a reason', () => {
    const c = kernel.compile(example('sphere'));
    expect(() => kernel.polygonize(c.handle, { bounds: c.bounds!, depth: 12 })).toThrow(/depth/);
    expect(() => kernel.polygonize(c.handle, { bounds: c.bounds!, depth: 6, maxTriangles: 100 })).toThrow(KernelError);
    expect(() => kernel.polygonize(999, { bounds: c.bounds!, depth: 3 })).toThrow(/no model/);
  });
});
