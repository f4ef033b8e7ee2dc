/**
 * The studio's code editor: CodeMirror 6 with HyperFun highlighting,
 * diagnostics while typing, completion, signature help, undo/redo, and
 * the constants tracked for sliders.
 *
 * Diagnostics: the linter runs the {@link Checker} 150 ms after the last
 * keystroke; a check still running when the text changes again is
 * aborted, and a result for text that has changed since is dropped by the
 * linter itself. Every result also goes to `onCheck` with the text it is
 * for, so the studio can update the view only for text that compiled (the
 * last good display stays while the code is broken).
 */
import { autocompletion, closeBrackets, closeBracketsKeymap, completionKeymap } from '@codemirror/autocomplete';
import { defaultKeymap, history, historyKeymap, indentWithTab, redo, undo } from '@codemirror/commands';
import { bracketMatching, indentOnInput } from '@codemirror/language';
import { type Diagnostic as CmDiagnostic, linter, lintGutter, lintKeymap } from '@codemirror/lint';
import { EditorState, type Extension } from '@codemirror/state';
import {
  EditorView,
  drawSelection,
  highlightActiveLine,
  highlightActiveLineGutter,
  keymap,
  lineNumbers,
} from '@codemirror/view';
import type { CompileResponse } from '../wire';
import type { Checker } from './checker';
import { hyperfunCompletions, signatureHelp } from './completion';
import { constantValue, dropConstant, setConstant, type TrackedConstant, trackedConstants } from './constants';
import { toEditorDiagnostics } from './diagnostics';
import { numberAt } from './hf-syntax';
import { hyperfun } from './language';

/** What the editor tells its owner. */
export interface EditorHooks {
  /** Checks sources while typing. */
  checker: Checker;
  /** The parameter values to check with. */
  params(): number[];
  /** Every document change (after the edit). */
  onChange?(source: string): void;
  /** A check's result, with the text it is for. */
  onCheck?(result: CompileResponse, source: string): void;
  /** The check itself failed (server unreachable…). */
  onCheckError?(error: unknown): void;
  /** Ctrl-S / Cmd-S. */
  onSave?(): void;
}

/** The editor. */
export class CodeEditor {
  readonly view: EditorView;
  private nextConstant = 1;
  private pending: AbortController | null = null;

  constructor(parent: HTMLElement, private readonly hooks: EditorHooks) {
    this.view = new EditorView({ parent, state: this.freshState('') });
  }

  private extensions(): Extension[] {
    const hooks = this.hooks;
    return [
      lineNumbers(),
      highlightActiveLineGutter(),
      history(),
      drawSelection(),
      indentOnInput(),
      bracketMatching(),
      closeBrackets(),
      highlightActiveLine(),
      hyperfun(),
      autocompletion({ override: [hyperfunCompletions] }),
      signatureHelp,
      trackedConstants,
      lintGutter(),
      linter((view) => this.lint(view), { delay: 150 }),
      keymap.of([
        { key: 'Mod-s', preventDefault: true, run: () => (hooks.onSave?.(), true) },
        ...closeBracketsKeymap,
        ...defaultKeymap,
        ...historyKeymap,
        ...completionKeymap,
        ...lintKeymap,
        indentWithTab,
      ]),
      EditorView.updateListener.of((u) => {
        if (u.docChanged) hooks.onChange?.(u.state.doc.toString());
      }),
      EditorView.contentAttributes.of({ 'aria-label': 'HyperFun source', spellcheck: 'false' }),
    ];
  }

  private freshState(doc: string): EditorState {
    return EditorState.create({ doc, extensions: this.extensions() });
  }

  private async lint(view: EditorView): Promise<CmDiagnostic[]> {
    const text = view.state.doc.toString();
    this.pending?.abort();
    const ctl = new AbortController();
    this.pending = ctl;
    try {
      const result = await this.hooks.checker.check(text, this.hooks.params(), ctl.signal);
      this.hooks.onCheck?.(result, text);
      return toEditorDiagnostics(text, result.diagnostics);
    } catch (e) {
      if (!(e instanceof DOMException && e.name === 'AbortError')) this.hooks.onCheckError?.(e);
      return [];
    } finally {
      if (this.pending === ctl) this.pending = null;
    }
  }

  /** The current text. */
  get source(): string {
    return this.view.state.doc.toString();
  }

  /** Replaces the document with a model's source (new undo history, no tracked constants). */
  load(source: string): void {
    this.view.setState(this.freshState(source));
  }

  /** Replaces the whole text as one undoable edit (palette, preset comments). */
  replaceAll(source: string, select?: { from: number; to: number }): void {
    const len = this.view.state.doc.length;
    this.view.dispatch({
      changes: { from: 0, to: len, insert: source },
      selection: select ? { anchor: Math.min(select.from, source.length), head: Math.min(select.to, source.length) } : undefined,
      scrollIntoView: true,
      userEvent: 'input.palette',
    });
  }

  /** Selects a range and scrolls to it. */
  select(from: number, to: number): void {
    const len = this.view.state.doc.length;
    this.view.dispatch({ selection: { anchor: Math.min(from, len), head: Math.min(to, len) }, scrollIntoView: true });
    this.view.focus();
  }

  undo(): boolean {
    return undo(this.view);
  }

  redo(): boolean {
    return redo(this.view);
  }

  /** Starts tracking the number under the cursor; null when there is none. */
  trackConstantAtCursor(): TrackedConstant | null {
    const pos = this.view.state.selection.main.head;
    const n = numberAt(this.source, pos);
    if (!n) return null;
    const existing = this.constants().find((c) => c.from === n.from);
    if (existing) return existing;
    const c = { id: this.nextConstant++, from: n.from, to: n.to };
    this.view.dispatch({ effects: setConstant.of(c) });
    return c;
  }

  /** The tracked constants now. */
  constants(): TrackedConstant[] {
    return this.view.state.field(trackedConstants);
  }

  /** A tracked constant's value (null: its text is no longer a number). */
  constantValue(id: number): number | null {
    const c = this.constants().find((k) => k.id === id);
    return c ? constantValue(this.view.state, c) : null;
  }

  /** Writes a tracked constant's new text (one undoable edit per call). */
  writeConstant(id: number, text: string): boolean {
    const c = this.constants().find((k) => k.id === id);
    if (!c) return false;
    this.view.dispatch({
      changes: { from: c.from, to: c.to, insert: text },
      effects: setConstant.of({ id, from: c.from, to: c.from + text.length }),
      userEvent: 'input.slider',
    });
    return true;
  }

  /** Stops tracking a constant. */
  dropConstant(id: number): void {
    this.view.dispatch({ effects: dropConstant.of(id) });
  }
}
