/**
 * The history of the open model: every saved version, newest first, with
 * its message, author and time; for each, open it, show what it changed
 * (the server's line diff from the version before), or restore it (a new
 * version equal to it).
 */
import type { Api } from '../api/client';
import { describeError } from '../api/errors';
import type { SourceDiff, VersionSummary } from '../wire';
import { notify } from './dialogs';
import { clear, h, shortTime } from './dom';

/** What the history asks of the studio. */
export interface HistoryHooks {
  /** Opens a version in the editor. */
  openVersion(n: number): void;
  /** A restore made a new latest version. */
  restored(n: number): void;
}

/** The history panel. */
export class HistoryPanel {
  readonly el: HTMLElement;
  private readonly list: HTMLElement;
  private readonly diffView: HTMLElement;
  private modelId: string | null = null;
  private shown: number | null = null;

  constructor(
    private readonly api: Api,
    private readonly hooks: HistoryHooks,
  ) {
    this.list = h('ol', { class: 'history-list', 'aria-label': 'Versions' });
    this.diffView = h('div', { class: 'diff-view', hidden: true, 'aria-label': 'Diff' });
    this.el = h('section', { class: 'panel-section history' }, h('h2', { text: 'History' }), this.list, this.diffView);
  }

  /** Shows a model's history, marking the version on screen. */
  async load(modelId: string | null, shown: number | null): Promise<void> {
    this.modelId = modelId;
    this.shown = shown;
    clear(this.list);
    this.diffView.hidden = true;
    if (!modelId) return;
    try {
      const versions = await this.api.history(modelId);
      if (this.modelId !== modelId) return;
      const newestFirst = [...versions].sort((a, b) => b.number - a.number);
      for (const v of newestFirst) this.list.append(this.row(v));
    } catch (e) {
      notify(`Could not read the history: ${describeError(e)}`, 'error');
    }
  }

  private row(v: VersionSummary): HTMLElement {
    const label = v.message || (v.restoredFrom ? `restore ${v.restoredFrom}` : 'saved');
    return h(
      'li',
      { 'data-version': v.number, class: v.number === this.shown ? 'current' : '' },
      h(
        'div',
        { class: 'history-meta' },
        h('strong', { text: `v${v.number}` }),
        h('span', { class: 'history-message', text: label }),
        h('span', { class: 'history-sub', text: `${v.author} · ${shortTime(v.created)}` }),
      ),
      h(
        'div',
        { class: 'history-actions' },
        h('button', { type: 'button', text: 'Open', onclick: () => this.hooks.openVersion(v.number) }),
        v.number > 1 ? h('button', { type: 'button', text: 'Diff', onclick: () => void this.showDiff(v.number - 1, v.number) }) : null,
        h('button', { type: 'button', text: 'Restore', onclick: () => void this.restore(v.number) }),
      ),
    );
  }

  /** Shows the changes between two versions. */
  async showDiff(from: number, to: number): Promise<void> {
    if (!this.modelId) return;
    try {
      const d = await this.api.diff(this.modelId, from, to);
      this.renderDiff(d);
    } catch (e) {
      notify(`Could not diff: ${describeError(e)}`, 'error');
    }
  }

  private renderDiff(d: SourceDiff): void {
    clear(this.diffView);
    const lines = h('pre', { class: 'diff-lines' });
    for (const l of d.lines) {
      const sign = l.kind === 'added' ? '+' : l.kind === 'removed' ? '-' : ' ';
      lines.append(h('div', { class: `diff-${l.kind}`, text: `${sign} ${l.text}` }));
    }
    this.diffView.append(
      h(
        'div',
        { class: 'section-head' },
        h('h3', { text: `v${d.from} → v${d.to}${d.paramsChanged ? ' (parameters changed)' : ''}` }),
        h('button', { type: 'button', text: 'Close', onclick: () => (this.diffView.hidden = true) }),
      ),
      lines,
    );
    this.diffView.hidden = false;
  }

  private async restore(n: number): Promise<void> {
    if (!this.modelId) return;
    try {
      const v = await this.api.restore(this.modelId, n);
      notify(`Restored v${n} as v${v.number}`);
      this.hooks.restored(v.number);
    } catch (e) {
      notify(`Could not restore: ${describeError(e)}`, 'error');
    }
  }
}
