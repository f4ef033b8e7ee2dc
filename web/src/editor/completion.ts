/**
 * Completion and signature help for HyperFun.
 *
 * Completion offers the kernel's library functions (as snippets with their
 * parameter names as fields), the built-in functions, the reserved words
 * and the names the document already uses. Signature help shows, while the
 * cursor is inside a library call's parentheses, the call's parameters with
 * the current one highlighted and the function's doc: the innermost open
 * `(` before the cursor preceded by a name, its argument index being the
 * count of top-level commas since it.
 */
import { type Completion, type CompletionContext, type CompletionResult, snippetCompletion } from '@codemirror/autocomplete';
import { type EditorState, StateField } from '@codemirror/state';
import { type Tooltip, showTooltip } from '@codemirror/view';
import { BUILTINS, KEYWORDS, tokenize } from './hf-syntax';
import { LIBRARY, type LibFunction, libraryFunction, signatureText } from './library';

const libraryOptions: Completion[] = LIBRARY.map((f) =>
  snippetCompletion(`${f.display}(${f.params.map((p) => `\${${p.name}}`).join(', ')})`, {
    label: f.display,
    type: 'function',
    detail: signatureText(f).slice(f.display.length),
    info: f.doc,
    boost: 1,
  }),
);
const builtinOptions: Completion[] = BUILTINS.map((b) => ({ label: b, type: 'function', detail: 'built-in' }));
const keywordOptions: Completion[] = KEYWORDS.filter((k) => k !== 'xor').map((k) => ({ label: k, type: 'keyword' }));

/** The completion source. */
export function hyperfunCompletions(ctx: CompletionContext): CompletionResult | null {
  const word = ctx.matchBefore(/[A-Za-z][A-Za-z0-9_]*/);
  if (!word || (word.from === word.to && !ctx.explicit)) return null;
  // No completion inside a comment.
  const line = ctx.state.doc.lineAt(ctx.pos);
  if (line.text.slice(0, ctx.pos - line.from).includes('--')) return null;
  const known = new Set([...LIBRARY.map((f) => f.name), ...BUILTINS, ...KEYWORDS]);
  const names = new Set<string>();
  for (const t of tokenize(ctx.state.doc.toString())) {
    if (t.kind === 'ident' && !known.has(t.text.toLowerCase()) && t.to !== word.to) names.add(t.text);
  }
  const variables: Completion[] = [...names].map((n) => ({ label: n, type: 'variable' }));
  return {
    from: word.from,
    options: [...libraryOptions, ...builtinOptions, ...keywordOptions, ...variables],
    validFor: /^[A-Za-z0-9_]*$/,
  };
}

/** The library call around a position and the index of the argument there. */
export interface CallContext {
  fn: LibFunction;
  arg: number;
  /** Offset of the call's name. */
  from: number;
}

/** Finds the innermost open library call before `pos` (looks back at most `window` characters). */
export function callAt(text: string, pos: number, window = 4000): CallContext | null {
  const start = Math.max(0, pos - window);
  const toks = tokenize(text.slice(start, pos));
  const stack: { name: string | null; from: number; commas: number }[] = [];
  for (let i = 0; i < toks.length; i++) {
    const t = toks[i];
    if (t.text === '(' && t.kind === 'punct') {
      const prev = toks[i - 1];
      stack.push({ name: prev?.kind === 'ident' ? prev.text : null, from: (prev?.from ?? 0) + start, commas: 0 });
    } else if (t.text === ')' && stack.length) stack.pop();
    else if (t.text === ',' && stack.length) stack[stack.length - 1].commas++;
    else if (t.text === ';') stack.length = 0;
  }
  for (let k = stack.length - 1; k >= 0; k--) {
    const s = stack[k];
    const fn = s.name ? libraryFunction(s.name) : undefined;
    if (fn) return { fn, arg: s.commas, from: s.from };
    if (s.name === null) continue;
    return null;
  }
  return null;
}

function signatureTooltip(state: EditorState): Tooltip | null {
  // A snippet's field is selected while the user fills it: read from the selection's start.
  const pos = state.selection.main.from;
  const call = callAt(state.doc.sliceString(0, pos), pos);
  if (!call) return null;
  return {
    pos,
    above: true,
    strictSide: false,
    create: () => {
      const dom = document.createElement('div');
      dom.className = 'cm-signature';
      const sig = document.createElement('div');
      sig.className = 'cm-signature-line';
      sig.append(`${call.fn.display}(`);
      call.fn.params.forEach((p, i) => {
        if (i > 0) sig.append(', ');
        const span = document.createElement('span');
        span.textContent = p.kind === 'array' ? `${p.name}[]` : p.name;
        if (i === call.arg) span.className = 'cm-signature-current';
        sig.append(span);
      });
      sig.append(')');
      const doc = document.createElement('div');
      doc.className = 'cm-signature-doc';
      doc.textContent = call.fn.doc;
      dom.append(sig, doc);
      if (call.arg >= call.fn.params.length) {
        const warn = document.createElement('div');
        warn.className = 'cm-signature-warn';
        warn.textContent = `${call.fn.display} takes ${call.fn.params.length} arguments`;
        dom.append(warn);
      }
      return { dom };
    },
  };
}

/** Signature help: a tooltip above the cursor inside a library call. */
export const signatureHelp = StateField.define<Tooltip | null>({
  create: signatureTooltip,
  update(value, tr) {
    return tr.docChanged || tr.selection ? signatureTooltip(tr.state) : value;
  },
  provide: (f) => showTooltip.from(f),
});
