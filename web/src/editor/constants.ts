/**
 * Numeric constants the user picked in the code for a slider.
 *
 * Each is a tracked range of the document (mapped through edits, so it
 * follows the number when text moves around it) with a highlight. A slider
 * rewrites the number's text with an effect that sets the new range
 * exactly. A constant whose text no longer reads as a number is reported
 * as lost by {@link constantValue}.
 */
import { type EditorState, StateEffect, StateField } from '@codemirror/state';
import { Decoration, type DecorationSet, EditorView } from '@codemirror/view';

/** A tracked constant. */
export interface TrackedConstant {
  id: number;
  from: number;
  to: number;
}

/** Starts or moves a tracked constant. */
export const setConstant = StateEffect.define<TrackedConstant>();
/** Stops tracking a constant. */
export const dropConstant = StateEffect.define<number>();

/** The tracked constants of an editor state. */
export const trackedConstants = StateField.define<TrackedConstant[]>({
  create: () => [],
  update(list, tr) {
    let out = tr.docChanged
      ? list.map((c) => {
          const from = tr.changes.mapPos(c.from, 1);
          return { ...c, from, to: Math.max(from, tr.changes.mapPos(c.to, -1)) };
        })
      : list;
    for (const e of tr.effects) {
      if (e.is(setConstant)) out = [...out.filter((c) => c.id !== e.value.id), e.value];
      if (e.is(dropConstant)) out = out.filter((c) => c.id !== e.value);
    }
    return out;
  },
  provide: (f) =>
    EditorView.decorations.from(f, (list): DecorationSet => {
      const marks = list
        .filter((c) => c.to > c.from)
        .sort((a, b) => a.from - b.from)
        .map((c) => Decoration.mark({ class: 'cm-tracked-constant' }).range(c.from, c.to));
      return Decoration.set(marks, true);
    }),
});

/** The value of a tracked constant now, or null when its text is not a number. */
export function constantValue(state: EditorState, c: TrackedConstant): number | null {
  const text = state.doc.sliceString(c.from, c.to);
  if (!/^(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$/.test(text)) return null;
  const v = Number(text);
  return Number.isFinite(v) ? v : null;
}

/** The text a slider writes for a value (no sign: HyperFun literals are unsigned). */
export function formatConstant(v: number, step: number): string {
  const digits = Math.max(0, Math.min(8, Math.ceil(-Math.log10(step))));
  const s = Math.abs(v).toFixed(digits);
  // Keep a literal the lexer reads as a number ("1." is fine, "-0" is not written).
  return s.includes('.') ? s.replace(/0+$/, '').replace(/\.$/, '.0') : s;
}
