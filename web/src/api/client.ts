/**
 * The typed HTTP client of the frep server's API (`/api/...`).
 *
 * One method per route, bodies and answers typed by the generated
 * `wire.ts`. Failures throw {@link ApiFailure}. Requests can be cancelled
 * with an `AbortSignal` (an aborted call throws the browser's AbortError,
 * not an ApiFailure, so callers can ignore it).
 */
import type {
  ArtefactRef,
  ArtefactRequest,
  CompileRequest,
  CompileResponse,
  CreateModel,
  ModelDetail,
  ModelSummary,
  SaveVersion,
  SourceDiff,
  Version,
  VersionSummary,
} from '../wire';
import { ApiFailure, networkFailure, parseApiError } from './errors';

/** The `fetch` the client uses (injected in tests). */
export type FetchLike = (input: string, init?: RequestInit) => Promise<Response>;

/** Progress of a download: bytes so far and the total when known. */
export type DownloadProgress = (loaded: number, total: number | null) => void;

/** The API client. */
export class Api {
  private readonly base: string;
  private readonly fetchImpl: FetchLike;

  /** `base` is the server's origin ('' for the page's own). */
  constructor(base = '', fetchImpl?: FetchLike) {
    this.base = base.replace(/\/$/, '');
    this.fetchImpl = fetchImpl ?? ((i, init) => fetch(i, init));
  }

  /** The absolute URL of an API path (artefact URLs are served as given). */
  url(path: string): string {
    return /^https?:/.test(path) ? path : `${this.base}${path}`;
  }

  private async send(method: string, path: string, body?: unknown, signal?: AbortSignal): Promise<Response> {
    const init: RequestInit = { method, signal };
    if (body !== undefined) {
      init.headers = { 'content-type': 'application/json' };
      init.body = JSON.stringify(body);
    }
    let r: Response;
    try {
      r = await this.fetchImpl(this.url(path), init);
    } catch (e) {
      if (e instanceof DOMException && e.name === 'AbortError') throw e;
      throw networkFailure(e);
    }
    if (!r.ok) {
      const text = await r.text().catch(() => '');
      throw new ApiFailure(r.status, parseApiError(r.status, r.statusText, text));
    }
    return r;
  }

  private async json<T>(method: string, path: string, body?: unknown, signal?: AbortSignal): Promise<T> {
    const r = await this.send(method, path, body, signal);
    const text = await r.text();
    if (!text) return undefined as T;
    try {
      return JSON.parse(text) as T;
    } catch {
      throw new ApiFailure(r.status, {
        code: 'bad_response',
        message: `${method} ${path}: the answer is not JSON`,
        diagnostics: [],
        limit: null,
      });
    }
  }

  /** `GET /api/models`. */
  listModels(signal?: AbortSignal): Promise<ModelSummary[]> {
    return this.json('GET', '/api/models', undefined, signal);
  }

  /** `POST /api/models`. */
  createModel(body: CreateModel): Promise<ModelDetail> {
    return this.json('POST', '/api/models', body);
  }

  /** `GET /api/models/{id}`: the model with its latest version. */
  getModel(id: string, signal?: AbortSignal): Promise<ModelDetail> {
    return this.json('GET', `/api/models/${enc(id)}`, undefined, signal);
  }

  /** `GET /api/models/{id}/versions/{n}`. */
  getVersion(id: string, n: number, signal?: AbortSignal): Promise<Version> {
    return this.json('GET', `/api/models/${enc(id)}/versions/${n}`, undefined, signal);
  }

  /** `GET /api/models/{id}/versions`: the history, as the server orders it. */
  history(id: string, signal?: AbortSignal): Promise<VersionSummary[]> {
    return this.json('GET', `/api/models/${enc(id)}/versions`, undefined, signal);
  }

  /** `POST /api/models/{id}/versions`: 409 (`isConflict`) when `base` is stale. */
  saveVersion(id: string, body: SaveVersion): Promise<Version> {
    return this.json('POST', `/api/models/${enc(id)}/versions`, body);
  }

  /** `PATCH /api/models/{id}`. */
  rename(id: string, name: string): Promise<ModelSummary> {
    return this.json('PATCH', `/api/models/${enc(id)}`, { name });
  }

  /** `POST /api/models/{id}/duplicate`. */
  duplicate(id: string, name: string): Promise<ModelDetail> {
    return this.json('POST', `/api/models/${enc(id)}/duplicate`, { name });
  }

  /** `DELETE /api/models/{id}`. */
  async remove(id: string): Promise<void> {
    await this.send('DELETE', `/api/models/${enc(id)}`);
  }

  /** `POST /api/models/{id}/restore`: a new version equal to `version`. */
  restore(id: string, version: number, message = ''): Promise<Version> {
    return this.json('POST', `/api/models/${enc(id)}/restore`, { version, message });
  }

  /** `GET /api/models/{id}/diff?from&to`. */
  diff(id: string, from: number, to: number): Promise<SourceDiff> {
    return this.json('GET', `/api/models/${enc(id)}/diff?from=${from}&to=${to}`);
  }

  /** `POST /api/compile`: diagnostics or a summary (a model error is not a failure). */
  compile(body: CompileRequest, signal?: AbortSignal): Promise<CompileResponse> {
    return this.json('POST', '/api/compile', body, signal);
  }

  /** `POST /api/artefacts`: the artefact's content address, at once. */
  requestArtefact(body: ArtefactRequest, signal?: AbortSignal): Promise<ArtefactRef> {
    return this.json('POST', '/api/artefacts', body, signal);
  }

  /**
   * `GET` an artefact's URL (the server computes it if needed) as a Blob,
   * reporting download progress when the body streams.
   */
  async fetchArtefact(ref: ArtefactRef, onProgress?: DownloadProgress, signal?: AbortSignal): Promise<Blob> {
    const r = await this.send('GET', ref.url, undefined, signal);
    const type = r.headers.get('content-type') ?? ref.mediaType;
    const len = Number(r.headers.get('content-length'));
    const total = Number.isFinite(len) && len > 0 ? len : null;
    if (!r.body || !onProgress) return new Blob([await r.arrayBuffer()], { type });
    const reader = r.body.getReader();
    const parts: Uint8Array[] = [];
    let loaded = 0;
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      parts.push(value);
      loaded += value.byteLength;
      onProgress(loaded, total);
    }
    return new Blob(parts as BlobPart[], { type });
  }
}

function enc(id: string): string {
  return encodeURIComponent(id);
}
