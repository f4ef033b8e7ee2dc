/**
 * The model list: every stored model (the examples included) as a card
 * with a server-rendered thumbnail, its name and version count, and the
 * actions new / rename / duplicate / delete.
 *
 * Thumbnails are image artefacts of each model's latest version at the
 * default camera; their URLs are content addresses, so the browser caches
 * them until the model changes. At most two are requested at a time.
 */
import type { Api } from '../api/client';
import { describeError } from '../api/errors';
import type { ModelSummary } from '../wire';
import { askText, confirmAction, notify } from './dialogs';
import { clear, h, shortTime } from './dom';
import { DEFAULT_CAMERA } from './viewer-port';

/** What the list asks of the studio. */
export interface ModelListHooks {
  open(id: string): void;
  /** A model was deleted (the studio leaves it if open). */
  deleted(id: string): void;
  /** A model was renamed. */
  renamed(model: ModelSummary): void;
}

/** The source of a new model. */
export const NEW_MODEL_SOURCE = `-- A new model: edit the code, or add shapes from the palette.
my_model(x[3], a[1])
{
  array c[3];
  c = [0, 0, 0];
  my_model = hfSphere(x, c, 0.8);
}
`;

/** The model list panel. */
export class ModelList {
  readonly el: HTMLElement;
  private readonly list: HTMLElement;
  private models: ModelSummary[] = [];
  private current: string | null = null;
  private thumbQueue: (() => Promise<void>)[] = [];
  private thumbsRunning = 0;
  private readonly thumbs = new Map<string, string>();
  /** Thumbnails wait for this (the first display: both need the server's renderers). */
  private held: Promise<unknown> = Promise.resolve();

  constructor(
    private readonly api: Api,
    private readonly hooks: ModelListHooks,
  ) {
    this.list = h('ul', { class: 'model-list', 'aria-label': 'Models' });
    this.el = h(
      'section',
      { class: 'panel-section models' },
      h(
        'div',
        { class: 'section-head' },
        h('h2', { text: 'Models' }),
        h('button', { type: 'button', class: 'primary', text: 'New', onclick: () => void this.create() }),
      ),
      this.list,
    );
  }

  /** Reloads the list from the server. */
  async refresh(): Promise<void> {
    try {
      this.models = await this.api.listModels();
      this.render();
    } catch (e) {
      notify(`Could not list the models: ${describeError(e)}`, 'error');
    }
  }

  /** Marks the open model. */
  setCurrent(id: string | null): void {
    this.current = id;
    for (const li of this.list.querySelectorAll<HTMLElement>('li[data-id]')) {
      li.classList.toggle('current', li.dataset.id === id);
    }
  }

  private render(): void {
    clear(this.list);
    const sorted = [...this.models].sort((a, b) => a.name.localeCompare(b.name));
    for (const m of sorted) this.list.append(this.card(m));
    if (sorted.length === 0) this.list.append(h('li', { class: 'empty', text: 'No models yet.' }));
  }

  private card(m: ModelSummary): HTMLElement {
    const img = h('img', { class: 'thumb', alt: '', width: 64, height: 64, loading: 'lazy' });
    this.thumbnail(m, img);
    const open = h(
      'button',
      { type: 'button', class: 'model-open', onclick: () => this.hooks.open(m.id), title: `Open ${m.name}` },
      img,
      h(
        'span',
        { class: 'model-meta' },
        h('span', { class: 'model-name', text: m.name }),
        h('span', { class: 'model-sub', text: `v${m.latest} · ${shortTime(m.updated)}` }),
      ),
    );
    const actions = h(
      'span',
      { class: 'model-actions' },
      h('button', { type: 'button', text: 'Rename', 'aria-label': `Rename ${m.name}`, onclick: () => void this.rename(m) }),
      h('button', { type: 'button', text: 'Duplicate', 'aria-label': `Duplicate ${m.name}`, onclick: () => void this.duplicate(m) }),
      h('button', { type: 'button', class: 'danger', text: 'Delete', 'aria-label': `Delete ${m.name}`, onclick: () => void this.remove(m) }),
    );
    return h('li', { 'data-id': m.id, class: m.id === this.current ? 'current' : '' }, open, actions);
  }

  private thumbnail(m: ModelSummary, img: HTMLImageElement): void {
    const key = `${m.id}@${m.latest}`;
    const known = this.thumbs.get(key);
    if (known) {
      img.src = known;
      return;
    }
    this.thumbQueue.push(async () => {
      try {
        const ref = await this.api.requestArtefact({
          model: { from: 'version', modelId: m.id, version: m.latest },
          params: [],
          spec: { kind: 'image', camera: DEFAULT_CAMERA, width: 128, height: 128, format: 'jpeg', quality: 75 },
        });
        const url = this.api.url(ref.url);
        await new Promise<void>((ok) => {
          img.onload = img.onerror = () => ok();
          img.src = url;
        });
        if (img.naturalWidth > 0) this.thumbs.set(key, url);
        else img.classList.add('thumb-failed');
      } catch {
        img.classList.add('thumb-failed');
      }
    });
    this.pump();
  }

  /** Holds thumbnail requests until `gate` settles. */
  holdThumbnails(gate: Promise<unknown>): void {
    this.held = gate.catch(() => {});
  }

  private pump(): void {
    while (this.thumbsRunning < 2 && this.thumbQueue.length) {
      const job = this.thumbQueue.shift()!;
      this.thumbsRunning++;
      void this.held.then(job).finally(() => {
        this.thumbsRunning--;
        this.pump();
      });
    }
  }

  private async create(): Promise<void> {
    const name = await askText('Name of the new model', 'untitled', 'Create');
    if (!name) return;
    try {
      const d = await this.api.createModel({ name, source: NEW_MODEL_SOURCE, params: [], message: 'new model' });
      await this.refresh();
      this.hooks.open(d.model.id);
    } catch (e) {
      notify(`Could not create the model: ${describeError(e)}`, 'error');
    }
  }

  private async rename(m: ModelSummary): Promise<void> {
    const name = await askText(`Rename ${m.name}`, m.name, 'Rename');
    if (!name || name === m.name) return;
    try {
      const s = await this.api.rename(m.id, name);
      await this.refresh();
      this.hooks.renamed(s && s.id ? s : { ...m, name });
    } catch (e) {
      notify(`Could not rename: ${describeError(e)}`, 'error');
    }
  }

  private async duplicate(m: ModelSummary): Promise<void> {
    const name = await askText(`Name of the copy of ${m.name}`, `${m.name} copy`, 'Duplicate');
    if (!name) return;
    try {
      const d = await this.api.duplicate(m.id, name);
      await this.refresh();
      if (d?.model?.id) this.hooks.open(d.model.id);
    } catch (e) {
      notify(`Could not duplicate: ${describeError(e)}`, 'error');
    }
  }

  private async remove(m: ModelSummary): Promise<void> {
    if (!(await confirmAction(`Delete ${m.name} and its history?`, 'Delete'))) return;
    try {
      await this.api.remove(m.id);
      await this.refresh();
      this.hooks.deleted(m.id);
    } catch (e) {
      notify(`Could not delete: ${describeError(e)}`, 'error');
    }
  }
}
