/**
 * Small HTTP helpers for end-to-end tests: set up and inspect server state
 * directly (create a model, read its versions) without going through the UI.
 */
import type { CreateModel, ModelDetail, ModelSummary, VersionSummary } from '../../../src/wire';
import { serverUrl } from './env';

async function call<T>(method: string, path: string, body?: unknown): Promise<T> {
  const r = await fetch(`${serverUrl()}${path}`, {
    method,
    headers: body === undefined ? {} : { 'content-type': 'application/json' },
    body: body === undefined ? undefined : JSON.stringify(body),
  });
  const text = await r.text();
  if (!r.ok) throw new Error(`${method} ${path}: HTTP ${r.status} ${text}`);
  return (text ? JSON.parse(text) : undefined) as T;
}

/** Creates a model; returns its detail (id, version 1). */
export function createModel(name: string, source: string, params: number[] = []): Promise<ModelDetail> {
  const body: CreateModel = { name, source, params, message: 'e2e' };
  return call<ModelDetail>('POST', '/api/models', body);
}

/** Every model. */
export function listModels(): Promise<ModelSummary[]> {
  return call<ModelSummary[]>('GET', '/api/models');
}

/** A model's latest version (or `version`). */
export function getModel(id: string, version?: number): Promise<ModelDetail> {
  return version === undefined
    ? call<ModelDetail>('GET', `/api/models/${encodeURIComponent(id)}`)
    : call<ModelDetail>('GET', `/api/models/${encodeURIComponent(id)}/versions/${version}`).then(
        (v) => v as unknown as ModelDetail,
      );
}

/** A model's history, as the server lists it. */
export function history(id: string): Promise<VersionSummary[]> {
  return call<VersionSummary[]>('GET', `/api/models/${encodeURIComponent(id)}/versions`);
}

/** A small sphere model (cheap to render and mesh), radius a[1]. */
export function sphereSource(radius = 'a[1]'): string {
  return [
    'my_model(x[3], a[1])',
    '{',
    '  array c[3];',
    '  c = [0, 0, 0];',
    `  my_model = hfSphere(x, c, ${radius});`,
    '}',
    '',
  ].join('\n');
}

/** A unique name for a test's model. */
export function uniqueName(prefix: string): string {
  return `${prefix}-${Date.now().toString(36)}-${Math.floor(Math.random() * 1e6).toString(36)}`;
}
