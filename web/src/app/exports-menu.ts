/**
 * The exports menu: a mesh file (STL, OBJ, PLY with colours, GLB, 3MF) at
 * an octree depth chosen apart from the preview's, with a progress bar and
 * the download.
 *
 * `POST /api/artefacts` with an export spec gives the file's content
 * address at once; `GET` on it computes the file (or serves it cached).
 * Progress: the session's `progress` messages for the key when the viewer
 * relays them, else an indeterminate bar until the bytes flow, then the
 * download's own progress.
 */
import type { Api } from '../api/client';
import { describeError } from '../api/errors';
import type { ExportFormat, ModelRef } from '../wire';
import { notify } from './dialogs';
import { h } from './dom';

/** What the menu needs from the studio. */
export interface ExportHooks {
  /** The model to export (a saved version, or the editor's source). */
  model(): ModelRef | null;
  params(): number[];
  /** A file name without extension. */
  baseName(): string;
  /** Subscribes to the session's progress for artefacts, when available. */
  onProgress?(cb: (key: string, fraction: number) => void): () => void;
}

const FORMATS: [ExportFormat, string][] = [
  ['stl', 'STL (binary)'],
  ['obj', 'OBJ'],
  ['ply', 'PLY (with colours)'],
  ['glb', 'glTF binary (GLB)'],
  ['3mf', '3MF'],
];

/** The exports menu. */
export class ExportsMenu {
  readonly el: HTMLElement;
  private readonly format: HTMLSelectElement;
  private readonly depth: HTMLInputElement;
  private readonly bar: HTMLProgressElement;
  private readonly status: HTMLElement;
  private readonly go: HTMLButtonElement;

  constructor(
    private readonly api: Api,
    private readonly hooks: ExportHooks,
  ) {
    this.format = h('select', { 'aria-label': 'Export format' });
    for (const [v, label] of FORMATS) this.format.append(h('option', { value: v, text: label }));
    this.depth = h('input', { type: 'number', min: 3, max: 10, value: '6', 'aria-label': 'Export depth' });
    this.bar = h('progress', { class: 'export-progress', max: 1, hidden: true });
    this.status = h('span', { class: 'export-status', 'data-testid': 'export-status' });
    this.go = h('button', { type: 'button', class: 'primary', text: 'Download', onclick: () => void this.run() });
    const panel = h(
      'div',
      { class: 'menu-panel' },
      h('label', { class: 'field' }, h('span', { text: 'Format' }), this.format),
      h(
        'label',
        { class: 'field', title: 'Octree depth of the exported mesh: 2^depth cells along the longest side (the preview has its own)' },
        h('span', { text: 'Resolution (depth)' }),
        this.depth,
      ),
      h('div', { class: 'menu-row' }, this.go, this.bar, this.status),
    );
    this.el = h('details', { class: 'menu exports' }, h('summary', { text: 'Export' }), panel);
  }

  private async run(): Promise<void> {
    const model = this.hooks.model();
    if (!model) return;
    const format = this.format.value as ExportFormat;
    const depth = Math.max(3, Math.min(10, Math.round(Number(this.depth.value) || 6)));
    this.go.disabled = true;
    this.bar.hidden = false;
    this.bar.removeAttribute('value');
    this.status.textContent = 'computing…';
    let unsubscribe: (() => void) | undefined;
    try {
      const ref = await this.api.requestArtefact({ model, params: this.hooks.params(), spec: { kind: 'export', format, depth } });
      unsubscribe = this.hooks.onProgress?.((key, fraction) => {
        if (key === ref.key) this.bar.value = Math.max(0, Math.min(1, fraction));
      });
      const blob = await this.api.fetchArtefact(ref, (loaded, total) => {
        this.status.textContent = `downloading ${Math.round(loaded / 1024)} KiB`;
        if (total) this.bar.value = loaded / total;
      });
      this.save(blob, `${this.hooks.baseName()}.${format}`);
      this.status.textContent = `${format.toUpperCase()} ${Math.round(blob.size / 1024)} KiB`;
    } catch (e) {
      this.status.textContent = '';
      notify(`Export failed: ${describeError(e)}`, 'error');
    } finally {
      unsubscribe?.();
      this.bar.hidden = true;
      this.go.disabled = false;
    }
  }

  private save(blob: Blob, name: string): void {
    const url = URL.createObjectURL(blob);
    const a = h('a', { href: url, download: name, hidden: true });
    document.body.append(a);
    a.click();
    a.remove();
    setTimeout(() => URL.revokeObjectURL(url), 60_000);
  }
}
