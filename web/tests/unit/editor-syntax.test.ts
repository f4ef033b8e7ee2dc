/// <reference types="node" />
import { readFileSync, readdirSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { describe, expect, it } from 'vitest';
import { callAt } from '../../src/editor/completion';
import { constructionTree } from '../../src/editor/construction';
import { formatConstant } from '../../src/editor/constants';
import { mainBody, numberAt, parseProgram, tokenize } from '../../src/editor/hf-syntax';
import { LIBRARY, libraryFunction, roleOf, signatureText } from '../../src/editor/library';

const root = resolve(import.meta.dirname, '..', '..', '..');

describe('HyperFun reader', () => {
  it('tokenizes numbers, names, comments and two-character operators', () => {
    const toks = tokenize('a = .5e1 /= 2 -- note\n b <= 3;');
    expect(toks.map((t) => t.text)).toEqual(['a', '=', '.5e1', '/=', '2', 'b', '<=', '3', ';', '']);
    expect(toks[2]).toMatchObject({ kind: 'num', from: 4, to: 8 });
  });

  it('reads every example without losing its result', () => {
    for (const f of readdirSync(join(root, 'examples')).filter((n) => n.endsWith('.hf'))) {
      const src = readFileSync(join(root, 'examples', f), 'utf8');
      const body = mainBody(parseProgram(src));
      expect(body?.result, f).not.toBeNull();
      expect(constructionTree(src), f).not.toBeNull();
    }
  });

  it('reads the result of the rblend example as unions inside a loop', () => {
    const src = readFileSync(join(root, 'examples', 'm4_rblend10.hf'), 'utf8');
    const body = mainBody(parseProgram(src))!;
    expect(body.stmts.some((s) => s.type === 'block' && s.keyword === 'while')).toBe(true);
  });

  it('finds the number under the cursor', () => {
    const src = 'f = hfSphere(x, c, 0.75);';
    expect(numberAt(src, src.indexOf('0.75') + 2)).toEqual({ from: 19, to: 23, value: 0.75 });
    expect(numberAt(src, 1)).toBeNull();
  });

  it('never throws on garbage', () => {
    for (const s of ['', '(((', 'my_model(x[3]) { f = ;', '}}}', 'a(x[3]){ if then loop', '"unterminated']) {
      expect(() => constructionTree(s)).not.toThrow();
    }
  });

  it('formats slider values as unsigned literals', () => {
    expect(formatConstant(0.5, 0.01)).toBe('0.5');
    expect(formatConstant(2, 0.01)).toBe('2.0');
    expect(formatConstant(3, 1)).toBe('3');
    expect(Number(formatConstant(0.123456, 0.001))).toBe(0.123);
  });
});

describe('library table and signature help', () => {
  it('comes from the kernel table', () => {
    expect(LIBRARY.length).toBeGreaterThan(50);
    const s = libraryFunction('HFSPHERE')!;
    expect(signatureText(s)).toBe('hfSphere(x[], center[], R)');
    expect(roleOf(s)).toBe('primitive');
    expect(roleOf(libraryFunction('hfRotate3DZ')!)).toBe('transform');
    expect(roleOf(libraryFunction('hfBlendUni')!)).toBe('blend');
  });

  it('finds the call and argument at the cursor', () => {
    const text = 'f = hfBlendUni(hfSphere(x, c, 1), g, ';
    expect(callAt(text, text.length)).toMatchObject({ arg: 2 });
    expect(callAt(text, text.length)?.fn.display).toBe('hfBlendUni');
    const inner = 'f = hfBlendUni(hfSphere(x, c';
    expect(callAt(inner, inner.length)?.fn.display).toBe('hfSphere');
    expect(callAt(inner, inner.length)?.arg).toBe(1);
    expect(callAt('f = sqrt(1, ', 12)).toBeNull();
    expect(callAt('f = hfSphere(x, c, 1); g = (', 28)).toBeNull();
    // Parentheses inside an argument do not count as calls.
    const nested = 'f = hfSphere(x, c, (1 + 2) * ';
    expect(callAt(nested, nested.length)?.arg).toBe(2);
  });
});
