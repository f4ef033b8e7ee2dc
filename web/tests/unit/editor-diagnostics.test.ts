import { describe, expect, it } from 'vitest';
import { toEditorDiagnostics, toEditorRange } from '../../src/editor/diagnostics';
import type { Diagnostic } from '../../src/wire';

function diag(line: number, column: number, start: number, end: number): Diagnostic {
  return { message: 'm', line, column, start, end, rendered: '' };
}

/** UTF-8 byte offset of a UTF-16 index. */
function byteAt(text: string, i: number): number {
  return new TextEncoder().encode(text.slice(0, i)).length;
}

describe('diagnostics → editor positions', () => {
  it('maps line and column on ASCII text', () => {
    const text = 'my_model(x[3], a[1])\n{\n  my_model = hfSphere(x, c 1);\n}\n';
    const at = text.indexOf('1);');
    const d = diag(3, at - text.indexOf('  my_model') + 1, byteAt(text, at), byteAt(text, at) + 1);
    expect(toEditorRange(text, d)).toEqual({ from: at, to: at + 1 });
  });

  it('counts columns in characters and spans in bytes (non-ASCII before and inside)', () => {
    // "é" is 2 UTF-8 bytes and 1 UTF-16 unit; "𝑥" is 4 bytes and 2 units.
    const text = '-- é\nf = 𝑥𝑥 + 1;\n';
    const at = text.indexOf('𝑥');
    const d = diag(2, 5, byteAt(text, at), byteAt(text, at + 4));
    expect(toEditorRange(text, d)).toEqual({ from: at, to: at + 4 });
  });

  it('widens an empty span to one character', () => {
    const text = 'abc\ndef';
    expect(toEditorRange(text, diag(2, 2, 5, 5))).toEqual({ from: 5, to: 6 });
  });

  it('an empty span at the end of the text marks the last character', () => {
    const text = 'abc';
    expect(toEditorRange(text, diag(1, 4, 3, 3))).toEqual({ from: 2, to: 3 });
  });

  it('clamps positions outside the text', () => {
    const text = 'ab\ncd';
    const r = toEditorRange(text, diag(9, 40, 100, 120));
    expect(r.from).toBeLessThanOrEqual(text.length);
    expect(r.to).toBeLessThanOrEqual(text.length);
    expect(r.from).toBeGreaterThanOrEqual(text.indexOf('cd'));
  });

  it('keeps the message and marks errors', () => {
    const [d] = toEditorDiagnostics('x', [{ ...diag(1, 1, 0, 1), message: 'expected `;`' }]);
    expect(d).toEqual({ from: 0, to: 1, message: 'line 1, column 1: expected `;`', severity: 'error' });
  });
});
