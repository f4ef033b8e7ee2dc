/**
 * The studio: wires the model list, history, palette, tree, editor,
 * parameter panel, exports and the viewer around one open model.
 *
 * State: the open model, the version loaded into the editor, and `base`,
 * the latest version number known when it was loaded (a save sends it; the
 * server refuses with 409 when someone saved since). The editor's text is
 * the truth: every check that compiles updates the view (the viewer works
 * asynchronously, so rendering never blocks typing), a check that fails
 * leaves the last good display. The URL names model, version and camera.
 */
import { Api } from '../api/client';
import { ApiFailure, describeError } from '../api/errors';
import { type Checker, ServerChecker } from '../editor/checker';
import { constructionTree, primitives } from '../editor/construction';
import { formatConstant } from '../editor/constants';
import { CodeEditor } from '../editor/editor';
import type { CameraView, CompileResponse, CompileSummary, ModelDetail, ModelRef, ModelSummary, Version } from '../wire';
import { confirmAction, notify } from './dialogs';
import { h } from './dom';
import { ExportsMenu } from './exports-menu';
import { HistoryPanel } from './history-panel';
import { type Layout, buildLayout } from './layout';
import { ModelList } from './model-list';
import { PalettePanel } from './palette-panel';
import { ParamsPanel } from './params-panel';
import { writePreset } from './presets';
import { TreePanel } from './tree-panel';
import { type UrlState, decodeState, encodeState } from './url-state';
import { DEFAULT_CAMERA, type StudioViewer, mountViewer } from './viewer-port';
import { WasmChecker } from '../wasm/checker';
import { sharedKernelReady } from '../wasm/client';

/** The longest the kernel and thumbnails wait for the first display (ms). */
const START_WAIT_MS = 3000;

/** Options of {@link Studio.start}. */
export interface StudioOptions {
  /** API origin ('' for the page's own). */
  apiBase?: string;
  /** A checker other than the server's compiler (the WASM kernel). */
  checker?: Checker;
}

/** The studio application. */
export class Studio {
  private readonly api: Api;
  private readonly layout: Layout;
  private readonly editor: CodeEditor;
  private readonly list: ModelList;
  private readonly history: HistoryPanel;
  private readonly params: ParamsPanel;
  private readonly palette: PalettePanel;
  private readonly tree: TreePanel;
  private readonly exports: ExportsMenu;
  private readonly saveButton: HTMLButtonElement;
  private readonly message: HTMLInputElement;
  private viewer: StudioViewer | null = null;

  private model: ModelSummary | null = null;
  private version: Version | null = null;
  private base: number | null = null;
  private savedSource = '';
  private savedParams: number[] = [];
  private shownSource: string | null = null;
  private paramNames = '';
  private camera: CameraView = DEFAULT_CAMERA;
  private writtenHash = '';
  private treeTimer: ReturnType<typeof setTimeout> | null = null;
  private hashTimer: ReturnType<typeof setTimeout> | null = null;
  private loading = 0;
  /** Settles at the viewer's first display, or after START_WAIT_MS. */
  private readonly started: Promise<void>;
  private markStarted: () => void = () => {};
  /** The start's early fetch of the model the URL names. */
  private prefetched: { id: string; detail: Promise<ModelDetail> } | null = null;
  private shownCount = 0;

  private constructor(root: HTMLElement, opts: StudioOptions) {
    this.api = new Api(opts.apiBase ?? '');
    this.started = new Promise<void>((ok) => {
      this.markStarted = ok;
      setTimeout(ok, START_WAIT_MS);
    });
    // The kernel in the worker answers sources with errors at once (no
    // round trip); sources that compile go on to the server for their summary.
    // The kernel starts after the first display, as do the thumbnails:
    // both would take a core (or the server's renderers) it needs.
    const checker = opts.checker ?? new WasmChecker(new ServerChecker(this.api), sharedKernelReady, this.started);
    this.layout = buildLayout(root);
    this.editor = new CodeEditor(this.layout.editor, {
      checker,
      params: () => this.params.current,
      onChange: (src) => this.sourceChanged(src),
      onCheck: (r, src) => this.checked(r, src),
      onCheckError: (e) => this.setStatus(`cannot check: ${describeError(e)}`, 'error'),
      onSave: () => void this.save(),
    });
    this.list = new ModelList(this.api, {
      open: (id) => {
        // On a phone the list covers the view: fold it away once a model is chosen.
        if (window.matchMedia('(max-width: 900px)').matches) this.layout.root.classList.add('left-collapsed');
        this.navigate({ modelId: id, version: null, camera: null });
      },
      deleted: (id) => {
        if (this.model?.id === id) this.close();
      },
      renamed: (m) => {
        if (this.model?.id === m.id) {
          this.model = { ...this.model, name: m.name };
          this.updateTitle();
        }
      },
    });
    this.history = new HistoryPanel(this.api, {
      openVersion: (n) => this.model && this.navigate({ modelId: this.model.id, version: n, camera: this.camera }),
      restored: (n) => this.model && void this.open(this.model.id, n, true),
    });
    this.params = new ParamsPanel({
      onParams: (values) => {
        this.viewer?.setParams(values);
        // What the view was last told, visible to people inspecting the page and to tests.
        this.layout.viewer.dataset.params = values.join(',');
        this.updateDirty();
      },
      onConstant: (id, value, step) => this.editor.writeConstant(id, formatConstant(value, step)),
      dropConstant: (id) => {
        this.editor.dropConstant(id);
        this.refreshConstants();
      },
      pickConstant: () => {
        if (!this.editor.trackConstantAtCursor()) notify('Put the cursor on a number in the code first.', 'warning');
        this.refreshConstants();
      },
      savePreset: (p) => this.editor.replaceAll(writePreset(this.editor.source, p)),
    });
    this.palette = new PalettePanel({
      source: () => this.editor.source,
      apply: (r) => this.editor.replaceAll(r.source, { from: r.from, to: r.to }),
      shapes: () =>
        primitives(constructionTree(this.editor.source))
          .map((p) => p.variable)
          .filter((v): v is string => !!v),
    });
    this.tree = new TreePanel((from, to) => this.editor.select(from, to));
    this.exports = new ExportsMenu(this.api, {
      model: () => this.modelRef(),
      params: () => this.params.current,
      baseName: () => (this.model?.name ?? 'model').replace(/[^A-Za-z0-9._-]+/g, '_'),
      onProgress: (cb) => this.viewer?.onProgress?.(cb) ?? (() => {}),
    });
    this.message = h('input', { type: 'text', class: 'save-message', placeholder: 'message', 'aria-label': 'Save message' });
    this.saveButton = h('button', { type: 'button', class: 'primary', text: 'Save', 'aria-label': 'Save version', title: 'Save a new version (Ctrl-S)', onclick: () => void this.save() });
    this.layout.actions.append(
      h('button', { type: 'button', text: 'Undo', title: 'Undo (Ctrl-Z)', onclick: () => this.editor.undo() }),
      h('button', { type: 'button', text: 'Redo', title: 'Redo (Ctrl-Shift-Z)', onclick: () => this.editor.redo() }),
      this.message,
      this.saveButton,
      this.exports.el,
    );
    this.layout.tabs.models.append(this.list.el);
    this.layout.tabs.history.append(this.history.el);
    this.layout.tabs.palette.append(this.palette.el);
    this.layout.tabs.tree.append(this.tree.el);
    this.layout.params.append(this.params.el);
    this.params.setParams([], []);
    this.params.setSource('');
  }

  /** Builds the studio in `root` and opens what the URL names. */
  static async start(root: HTMLElement, opts: StudioOptions = {}): Promise<Studio> {
    const s = new Studio(root, opts);
    s.updateTitle();
    // The model the URL names is fetched while the viewer's code loads.
    const first = decodeState(location.hash).modelId;
    if (first) {
      const detail = s.api.getModel(first);
      // Its failure is reported where it is awaited (open).
      detail.catch(() => {});
      s.prefetched = { id: first, detail };
    }
    s.viewer = await mountViewer(s.layout.viewer, s.api, DEFAULT_CAMERA);
    s.list.holdThumbnails(s.started);
    if (first && s.viewer.firstDisplayed) void s.viewer.firstDisplayed().then(s.markStarted);
    else s.markStarted();
    s.viewer.onCameraChange((c) => {
      s.camera = c;
      s.scheduleHash();
    });
    window.addEventListener('hashchange', () => void s.route());
    window.addEventListener('beforeunload', (e) => {
      if (s.isDirty()) e.preventDefault();
    });
    // The list (its rendering takes tens of ms) follows the first display.
    void s.started.then(() => s.list.refresh());
    await s.route();
    return s;
  }

  // --- navigation ---------------------------------------------------------

  private navigate(state: UrlState): void {
    location.hash = encodeState(state);
  }

  private async route(): Promise<void> {
    if (location.hash === this.writtenHash && this.model) return;
    const st = decodeState(location.hash);
    if (st.camera) {
      this.camera = st.camera;
      this.viewer?.setCamera(st.camera);
    }
    if (!st.modelId) {
      if (this.model && this.isDirty() && !(await confirmAction('Discard the unsaved changes?', 'Discard'))) {
        this.writeHash();
        return;
      }
      if (this.model) this.close();
      return;
    }
    const sameVersion = this.model?.id === st.modelId && (st.version === null || st.version === this.version?.number);
    if (sameVersion) return;
    if (this.isDirty() && !(await confirmAction('Discard the unsaved changes?', 'Discard'))) {
      this.writeHash();
      return;
    }
    await this.open(st.modelId, st.version, false);
  }

  /** Loads a model's version (null: latest) into the editor and the view. */
  private async open(id: string, version: number | null, fromRestore: boolean): Promise<void> {
    const ticket = ++this.loading;
    try {
      const pre = this.prefetched?.id === id ? this.prefetched.detail : null;
      this.prefetched = null;
      const detail = await (pre ?? this.api.getModel(id));
      const v = version === null || version === detail.version.number ? detail.version : await this.api.getVersion(id, version);
      if (ticket !== this.loading) return;
      this.model = detail.model;
      this.version = v;
      this.base = detail.model.latest;
      this.savedSource = v.source;
      this.savedParams = [...v.params];
      this.shownSource = null;
      this.paramNames = '';
      this.editor.load(v.source);
      this.params.setParams([], v.params);
      this.params.setSource(v.source);
      this.refreshConstants();
      this.tree.show(constructionTree(v.source));
      this.palette.refreshTargets();
      this.list.setCurrent(id);
      this.updateTitle();
      this.updateDirty();
      this.setStatus('checking…', 'info');
      this.showInViewer(v.source);
      this.writeHash();
      void this.history.load(id, v.number);
      if (fromRestore) void this.list.refresh();
    } catch (e) {
      if (ticket !== this.loading) return;
      notify(`Could not open the model: ${describeError(e)}`, 'error');
      if (e instanceof ApiFailure && e.status === 404) this.close();
    }
  }

  private close(): void {
    this.model = null;
    this.version = null;
    this.base = null;
    this.savedSource = '';
    this.editor.load('');
    this.tree.show(null);
    this.list.setCurrent(null);
    void this.history.load(null, null);
    this.updateTitle();
    this.writtenHash = '#/';
    if (location.hash !== '#/' && location.hash !== '') history.replaceState(null, '', '#/');
  }

  private writeHash(): void {
    if (!this.model) return;
    const hash = encodeState({ modelId: this.model.id, version: this.version?.number ?? null, camera: this.camera });
    this.writtenHash = hash;
    if (location.hash !== hash) history.replaceState(null, '', hash);
  }

  private scheduleHash(): void {
    if (this.hashTimer) clearTimeout(this.hashTimer);
    this.hashTimer = setTimeout(() => this.writeHash(), 250);
  }

  // --- editing --------------------------------------------------------------

  private sourceChanged(src: string): void {
    this.updateDirty();
    this.params.setSource(src);
    if (this.treeTimer) clearTimeout(this.treeTimer);
    this.treeTimer = setTimeout(() => {
      this.tree.show(constructionTree(this.editor.source));
      this.palette.refreshTargets();
      this.refreshConstants();
    }, 120);
  }

  private checked(r: CompileResponse, src: string): void {
    if (!r.ok || !r.summary) {
      const n = r.diagnostics.length;
      const first = r.diagnostics[0];
      this.setStatus(first ? `${n} error${n > 1 ? 's' : ''}: line ${first.line}: ${first.message}` : 'does not compile', 'error');
      return;
    }
    const s = r.summary;
    this.setStatus(`compiled: ${s.nodes} nodes, ${s.params.length} parameters`, 'ok');
    const names = JSON.stringify(s.params);
    if (names !== this.paramNames) {
      this.paramNames = names;
      this.params.setParams(s.params, this.params.current);
    }
    this.showInViewer(src, s);
  }

  private showInViewer(src: string, summary: CompileSummary | null = null): void {
    if (!this.viewer || src === this.shownSource) return;
    this.shownSource = src;
    const saved = this.model && this.version && src === this.savedSource;
    this.viewer.show({
      modelId: this.model?.id ?? null,
      version: saved ? this.version!.number : null,
      source: src,
      params: this.params.current,
      summary,
    });
    this.layout.viewer.dataset.params = this.params.current.join(',');
    this.layout.viewer.dataset.shown = String(++this.shownCount);
  }

  private refreshConstants(): void {
    const doc = this.editor.view.state.doc;
    this.params.setConstants(
      this.editor.constants().map((c) => ({
        id: c.id,
        value: this.editor.constantValue(c.id),
        line: doc.lineAt(Math.min(c.from, doc.length)).number,
      })),
    );
  }

  private isDirty(): boolean {
    if (!this.model) return false;
    return this.editor.source !== this.savedSource || JSON.stringify(this.params.current) !== JSON.stringify(this.savedParams);
  }

  private updateDirty(): void {
    const dirty = this.isDirty();
    this.layout.root.classList.toggle('dirty', dirty);
    this.saveButton.disabled = !this.model;
    this.saveButton.textContent = dirty ? 'Save*' : 'Save';
  }

  private modelRef(): ModelRef | null {
    if (!this.model) return { from: 'source', source: this.editor.source };
    if (!this.isDirty() && this.version) return { from: 'version', modelId: this.model.id, version: this.version.number };
    return { from: 'source', source: this.editor.source };
  }

  // --- saving ---------------------------------------------------------------

  private async save(base = this.base): Promise<void> {
    if (!this.model) return;
    const id = this.model.id;
    const source = this.editor.source;
    const params = this.params.current;
    this.saveButton.disabled = true;
    try {
      const v = await this.api.saveVersion(id, { source, params, message: this.message.value.trim(), base, assets: [] });
      if (this.model?.id !== id) return;
      this.version = v;
      this.base = v.number;
      this.model = { ...this.model, latest: v.number, updated: v.created };
      this.savedSource = v.source;
      this.savedParams = [...v.params];
      this.message.value = '';
      this.updateTitle();
      this.updateDirty();
      this.writeHash();
      notify(`Saved version ${v.number}`);
      void this.history.load(id, v.number);
      void this.list.refresh();
    } catch (e) {
      if (e instanceof ApiFailure && e.isConflict) this.conflict(id, e.latest);
      else notify(`Could not save: ${describeError(e)}`, 'error');
    } finally {
      this.saveButton.disabled = !this.model;
    }
  }

  /** Someone else saved since this version was loaded: offer to reload or save on top. */
  private conflict(id: string, latest: number | null): void {
    const which = latest ? ` (version ${latest})` : '';
    notify(`Someone else saved this model${which} since you opened it.`, 'warning', [
      { label: 'Reload theirs', run: () => void this.open(id, null, false) },
      {
        label: 'Save mine on top',
        run: async () => {
          try {
            const latest = await this.api.getModel(id);
            await this.save(latest.model.latest);
          } catch (e) {
            notify(`Could not save: ${describeError(e)}`, 'error');
          }
        },
      },
    ]);
  }

  // --- chrome ---------------------------------------------------------------

  private updateTitle(): void {
    const m = this.model;
    this.layout.title.textContent = m ? `${m.name} · v${this.version?.number ?? m.latest}` : 'No model open';
    document.title = m ? `${m.name} — frep studio` : 'frep studio';
    this.saveButton.disabled = !m;
  }

  private setStatus(text: string, kind: 'ok' | 'error' | 'info'): void {
    this.layout.status.textContent = text;
    this.layout.status.dataset.kind = kind;
  }
}
