/// <reference types="node" />
/**
 * The palette's edits round-trip through the tree view: what addShape /
 * addTransform write is what constructionTree reads back, and the kernel
 * (`frep check`, when a built binary is present) accepts it.
 */
import { execFileSync } from 'node:child_process';
import { existsSync, mkdtempSync, readFileSync, writeFileSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';
import { describe, expect, it } from 'vitest';
import { constructionTree, primitives } from '../../src/editor/construction';
import { PRIMITIVES, TRANSFORMS, addShape, addTransform, negateResult } from '../../src/editor/palette-edits';
import { libraryFunction } from '../../src/editor/library';

const root = resolve(import.meta.dirname, '..', '..', '..');
const sphere = readFileSync(join(root, 'examples', 'sphere.hf'), 'utf8');
const frep = [join(root, 'target', 'release', 'frep'), join(root, 'target', 'debug', 'frep')].find(existsSync);

/** Runs the kernel's checker on a source; null when no binary is built. */
function kernelAccepts(src: string): boolean | null {
  if (!frep) return null;
  const dir = mkdtempSync(join(tmpdir(), 'frep-palette-'));
  const file = join(dir, 'm.hf');
  writeFileSync(file, src);
  try {
    execFileSync(frep, ['check', file], { stdio: 'pipe' });
    return true;
  } catch (e) {
    throw new Error(`frep check refused:\n${src}\n${String((e as { stderr?: Buffer }).stderr ?? e)}`);
  }
}

function ok(r: ReturnType<typeof addShape>): string {
  if (!r.ok) throw new Error(r.error);
  return r.source;
}

describe('palette', () => {
  it('every palette function is in the kernel library', () => {
    for (const p of Object.values(PRIMITIVES)) expect(libraryFunction(p.fn), p.fn).toBeDefined();
    for (const t of Object.values(TRANSFORMS)) {
      const f = libraryFunction(t.fn);
      expect(f, t.fn).toBeDefined();
      // xt plus the scalar arguments the template gives (stretch's x0 is an array).
      const scalars = f!.params.filter((p) => p.kind === 'scalar').length;
      const arrays = f!.params.filter((p) => p.kind === 'array').length;
      expect(t.args.length).toBe(scalars + (arrays - 1) * 3);
    }
  });

  it('the example reads as one primitive', () => {
    const tree = constructionTree(sphere);
    expect(tree?.kind).toBe('primitive');
    expect(tree?.label).toBe('hfSphere');
  });

  it('a union written by the palette reads back as a union', () => {
    const src = ok(addShape(sphere, PRIMITIVES.block, 'union'));
    const tree = constructionTree(src)!;
    expect(tree.kind).toBe('union');
    expect(tree.children.map((c) => c.label)).toEqual(['hfSphere', 'hfBlock']);
    expect(tree.children[1].variable).toBe('s1');
    expect(kernelAccepts(src)).not.toBe(false);
  });

  it('every combination reads back as its operation', () => {
    const want = {
      union: 'union',
      intersection: 'intersection',
      subtraction: 'subtraction',
      blendUnion: 'blendUnion',
      blendIntersection: 'blendIntersection',
    } as const;
    for (const [combine, kind] of Object.entries(want)) {
      const src = ok(addShape(sphere, PRIMITIVES.torus, combine as keyof typeof want));
      const tree = constructionTree(src)!;
      expect(tree.kind, combine).toBe(kind);
      expect(tree.children[1].label).toBe('hfTorusZ');
      expect(kernelAccepts(src)).not.toBe(false);
    }
  });

  it('a chain of edits keeps the structure (left-associative, no parentheses needed)', () => {
    let src = ok(addShape(sphere, PRIMITIVES.block, 'union'));
    src = ok(addShape(src, PRIMITIVES.cylinder, 'subtraction'));
    const tree = constructionTree(src)!;
    expect(tree.kind).toBe('subtraction');
    expect(tree.children[0].kind).toBe('union');
    expect(tree.children[1].label).toBe('hfCylinderZ');
    expect(src).toContain('array c1[3];');
    expect(src).toContain('array c2[3];');
    expect(kernelAccepts(src)).not.toBe(false);
  });

  it('transformations attach to their shape, in order', () => {
    let src = ok(addShape(sphere, PRIMITIVES.block, 'union'));
    src = ok(addTransform(src, 's1', TRANSFORMS.shift));
    src = ok(addTransform(src, 's1', TRANSFORMS.rotateZ));
    const prims = primitives(constructionTree(src));
    expect(prims.map((p) => p.label)).toEqual(['hfSphere', 'hfBlock']);
    expect(prims[0].transforms).toEqual([]);
    expect(prims[1].transforms).toEqual(['hfShift3D', 'hfRotate3DZ']);
    expect(src).toMatch(/s1 = hfBlock\(xt1, c1/);
    expect(kernelAccepts(src)).not.toBe(false);
  });

  it('the result itself can be transformed and negated', () => {
    let src = ok(addTransform(sphere, 'my_model', TRANSFORMS.scale));
    const prim = constructionTree(src)!;
    expect(prim.transforms).toEqual(['hfScale3D']);
    src = ok(negateResult(src));
    const tree = constructionTree(src)!;
    expect(tree.kind).toBe('negation');
    expect(tree.children[0].transforms).toEqual(['hfScale3D']);
    expect(kernelAccepts(src)).not.toBe(false);
  });

  it('an empty source gets a model', () => {
    const src = ok(addShape('', PRIMITIVES.sphere, 'union'));
    expect(constructionTree(src)?.label).toBe('hfSphere');
    expect(kernelAccepts(src)).not.toBe(false);
  });

  it('bad targets are errors, not exceptions', () => {
    const r = addTransform(sphere, 'nope', TRANSFORMS.shift);
    expect(r.ok).toBe(false);
  });
});
