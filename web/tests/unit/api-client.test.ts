import { describe, expect, it } from 'vitest';
import { Api } from '../../src/api/client';
import { ApiFailure, parseApiError } from '../../src/api/errors';

function answer(status: number, body: string, headers: Record<string, string> = {}) {
  const calls: { url: string; init?: RequestInit }[] = [];
  const api = new Api('http://h:1/', async (url, init) => {
    calls.push({ url, init });
    return new Response(body, { status, headers });
  });
  return { api, calls };
}

async function failure(p: Promise<unknown>): Promise<ApiFailure> {
  try {
    await p;
  } catch (e) {
    if (e instanceof ApiFailure) return e;
    throw e;
  }
  throw new Error('did not fail');
}

describe('API client', () => {
  it('parses an ApiError body with diagnostics', async () => {
    const body = JSON.stringify({
      code: 'model_error',
      message: 'expected `;`',
      diagnostics: [{ message: 'expected `;`', line: 3, column: 7, start: 30, end: 31, rendered: '' }],
      limit: null,
    });
    const { api } = answer(422, body, { 'content-type': 'application/json' });
    const e = await failure(api.createModel({ name: 'n', source: 's', params: [], message: '' }));
    expect(e.status).toBe(422);
    expect(e.code).toBe('model_error');
    expect(e.diagnostics[0].line).toBe(3);
    expect(e.isConflict).toBe(false);
  });

  it('recognises a save conflict', async () => {
    const { api } = answer(409, JSON.stringify({ code: 'conflict', message: 'version 3 is the latest', latest: 3 }));
    const e = await failure(api.saveVersion('m', { source: '', params: [], message: '', base: 2, assets: [] }));
    expect(e.isConflict).toBe(true);
    expect(e.latest).toBe(3);
    expect(e.error.diagnostics).toEqual([]);
    expect(e.error.limit).toBeNull();
  });

  it('makes an error from a body that is not an ApiError', async () => {
    const html = answer(502, '<html>bad gateway</html>');
    const e = await failure(html.api.listModels());
    expect(e.code).toBe('http_502');
    expect(e.message).toContain('502');
    const text = answer(404, 'no such model');
    expect((await failure(text.api.getModel('x'))).error).toEqual({
      code: 'not_found',
      message: 'no such model',
      diagnostics: [],
      limit: null,
    });
  });

  it('drops malformed diagnostics and keeps the limit', () => {
    const e = parseApiError(413, 'Payload Too Large', JSON.stringify({ code: 'too_large', message: 'm', diagnostics: [{ nope: 1 }], limit: 'max_source_bytes' }));
    expect(e).toEqual({ code: 'too_large', message: 'm', diagnostics: [], limit: 'max_source_bytes' });
  });

  it('turns a network failure into code network', async () => {
    const api = new Api('', async () => {
      throw new TypeError('Failed to fetch');
    });
    const e = await failure(api.listModels());
    expect(e.status).toBe(0);
    expect(e.code).toBe('network');
  });

  it('lets an abort through as an AbortError', async () => {
    const api = new Api('', async () => {
      throw new DOMException('aborted', 'AbortError');
    });
    await expect(api.listModels()).rejects.toMatchObject({ name: 'AbortError' });
  });

  it('sends typed bodies to the right routes', async () => {
    const { api, calls } = answer(200, '{"ok":true,"diagnostics":[],"summary":null}');
    await api.compile({ source: 'x', params: [1], body: null });
    expect(calls[0].url).toBe('http://h:1/api/compile');
    expect(calls[0].init?.method).toBe('POST');
    expect(JSON.parse(String(calls[0].init?.body))).toEqual({ source: 'x', params: [1], body: null });
    await api.diff('a/b', 1, 2);
    expect(calls[1].url).toBe('http://h:1/api/models/a%2Fb/diff?from=1&to=2');
  });

  it('a 2xx answer that is not JSON is an error', async () => {
    const { api } = answer(200, 'not json');
    expect((await failure(api.listModels())).code).toBe('bad_response');
  });

  it('downloads an artefact with progress', async () => {
    const bytes = new Uint8Array(1000).fill(7);
    const { api } = answer(200, '', {});
    const seen: number[] = [];
    const dl = new Api('', async () => new Response(bytes, { status: 200, headers: { 'content-length': '1000', 'content-type': 'model/stl' } }));
    const blob = await dl.fetchArtefact(
      { key: 'k', url: '/api/artefacts/k.stl', mediaType: 'model/stl', ready: true, bytes: 1000, serverMs: 1 },
      (loaded, total) => {
        seen.push(loaded);
        expect(total).toBe(1000);
      },
    );
    expect(blob.size).toBe(1000);
    expect(seen[seen.length - 1]).toBe(1000);
    expect(api).toBeDefined();
  });
});
