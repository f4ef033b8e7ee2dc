/**
 * Errors of the HTTP API as the studio sees them.
 *
 * Every failing call of the server answers with an {@link ApiError} body.
 * {@link ApiFailure} carries it with the HTTP status; a body that is not an
 * `ApiError` (a proxy's HTML page, an empty body) and a network failure are
 * turned into one too, so callers handle a single shape.
 */
import type { ApiError, Diagnostic } from '../wire';

/** A failed API call: the HTTP status (0: no answer) and the error body. */
export class ApiFailure extends Error {
  /** HTTP status, 0 when the request never got an answer. */
  readonly status: number;
  /** The server's error (or one made up from what came back). */
  readonly error: ApiError;

  constructor(status: number, error: ApiError) {
    super(error.message);
    this.name = 'ApiFailure';
    this.status = status;
    this.error = error;
  }

  /** The machine-readable code (`not_found`, `conflict`, `network`, …). */
  get code(): string {
    return this.error.code;
  }

  /** Whether this is a save refused because someone else saved first. */
  get isConflict(): boolean {
    return this.status === 409 || this.error.code === 'conflict';
  }

  /** The latest version number a conflict reports, when given. */
  get latest(): number | null {
    return this.error.latest ?? null;
  }

  /** Model diagnostics, for `model_error`. */
  get diagnostics(): Diagnostic[] {
    return this.error.diagnostics;
  }
}

function isDiagnostic(d: unknown): d is Diagnostic {
  if (typeof d !== 'object' || d === null) return false;
  const o = d as Record<string, unknown>;
  return typeof o.message === 'string' && typeof o.line === 'number' && typeof o.column === 'number';
}

/**
 * Reads an error body: an `ApiError` when it is one (missing optional
 * fields filled in), else an error made from the status and the text.
 */
export function parseApiError(status: number, statusText: string, body: string): ApiError {
  try {
    const v: unknown = JSON.parse(body);
    if (typeof v === 'object' && v !== null) {
      const o = v as Record<string, unknown>;
      if (typeof o.code === 'string' && typeof o.message === 'string') {
        const diags = Array.isArray(o.diagnostics) ? o.diagnostics.filter(isDiagnostic) : [];
        const limit = typeof o.limit === 'string' ? o.limit : null;
        const err: ApiError = { code: o.code, message: o.message, diagnostics: diags, limit };
        if (typeof o.latest === 'number' && Number.isInteger(o.latest)) err.latest = o.latest;
        return err;
      }
    }
  } catch {
    // Not JSON: fall through to a made-up error.
  }
  const text = body.trim().slice(0, 300);
  const code = status === 404 ? 'not_found' : status === 409 ? 'conflict' : `http_${status}`;
  const message = text && !text.startsWith('<') ? text : `${status} ${statusText}`.trim();
  return { code, message, diagnostics: [], limit: null };
}

/** The error for a request that got no answer (server down, offline). */
export function networkFailure(cause: unknown): ApiFailure {
  const message = cause instanceof Error ? cause.message : String(cause);
  return new ApiFailure(0, {
    code: 'network',
    message: `the server did not answer (${message})`,
    diagnostics: [],
    limit: null,
  });
}

/** A short sentence for the user from any error. */
export function describeError(e: unknown): string {
  if (e instanceof ApiFailure) return e.message;
  if (e instanceof Error) return e.message;
  return String(e);
}
