/**
 * What checks a source while the user types. The server's `/api/compile`
 * today; the WASM kernel can replace it behind the same interface.
 */
import type { Api } from '../api/client';
import type { CompileResponse } from '../wire';

/** Checks a source: diagnostics, or the compiled model's summary. */
export interface Checker {
  check(source: string, params: number[], signal?: AbortSignal): Promise<CompileResponse>;
}

/** The server's compiler as a checker. */
export class ServerChecker implements Checker {
  constructor(private readonly api: Api) {}

  check(source: string, params: number[], signal?: AbortSignal): Promise<CompileResponse> {
    return this.api.compile({ source, params, body: null }, signal);
  }
}
