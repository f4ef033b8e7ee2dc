/**
 * Kernel diagnostics to editor positions.
 *
 * The kernel reports a 1-based line and a 1-based column counted in
 * characters (Unicode scalar values), and the span as UTF-8 byte offsets.
 * CodeMirror counts UTF-16 code units. We map the start from line and
 * column (robust to the byte/UTF-16 difference), and the end from the byte
 * length of the span, converted by walking the characters. A zero-length
 * span (an unexpected end of file) is widened to one character where
 * possible so the squiggle is visible. Results are clamped to the text.
 */
import type { Diagnostic } from '../wire';

/** An editor range and what to say there. */
export interface EditorDiagnostic {
  from: number;
  to: number;
  message: string;
  severity: 'error' | 'warning';
}

/** UTF-8 byte length of one code point. */
function utf8Len(cp: number): number {
  return cp < 0x80 ? 1 : cp < 0x800 ? 2 : cp < 0x10000 ? 3 : 4;
}

/** Start offsets (UTF-16) of each line of `text`. */
function lineStarts(text: string): number[] {
  const starts = [0];
  for (let i = 0; i < text.length; i++) if (text.charCodeAt(i) === 10) starts.push(i + 1);
  return starts;
}

/** Moves `chars` code points forward from `pos`, stopping at a line end. */
function advanceChars(text: string, pos: number, chars: number): number {
  let p = pos;
  for (let k = 0; k < chars && p < text.length && text.charCodeAt(p) !== 10; k++) {
    const cp = text.codePointAt(p) ?? 0;
    p += cp > 0xffff ? 2 : 1;
  }
  return p;
}

/** Moves forward from `pos` until `bytes` UTF-8 bytes are covered. */
function advanceBytes(text: string, pos: number, bytes: number): number {
  let p = pos;
  let b = 0;
  while (b < bytes && p < text.length) {
    const cp = text.codePointAt(p) ?? 0;
    b += utf8Len(cp);
    p += cp > 0xffff ? 2 : 1;
  }
  return p;
}

/** Maps one kernel diagnostic into `text` (the source that was checked). */
export function toEditorRange(text: string, d: Diagnostic): { from: number; to: number } {
  const starts = lineStarts(text);
  const line = Math.min(Math.max(1, d.line), starts.length);
  const from = advanceChars(text, starts[line - 1], Math.max(0, d.column - 1));
  let to = advanceBytes(text, from, Math.max(0, d.end - d.start));
  if (to <= from) {
    // Widen an empty span to the next character, or the previous one at the end.
    if (from < text.length && text.charCodeAt(from) !== 10) to = from + 1;
    else return { from: Math.max(0, from - (from > 0 && text.charCodeAt(from - 1) !== 10 ? 1 : 0)), to: from };
  }
  return { from, to: Math.min(to, text.length) };
}

/** Maps every diagnostic; the message says where, as the kernel counts. */
export function toEditorDiagnostics(text: string, diags: Diagnostic[]): EditorDiagnostic[] {
  return diags.map((d) => ({
    ...toEditorRange(text, d),
    message: `line ${d.line}, column ${d.column}: ${d.message}`,
    severity: 'error' as const,
  }));
}
