/**
 * Fetching artefacts for the server modes: `POST /api/artefacts`, then the
 * bytes at the returned URL, cancelled by the request's signal (and the
 * server told, through `abandon`, when the job was still running). Reports
 * progress when the server says how far a job is, and the bytes moved.
 */
import type { Api } from '../../api/client';
import type { ArtefactRequest, ArtefactSpec, ModelRef } from '../../wire';
import type { ModelShow } from '../types';

/** An artefact's bytes with what it cost. */
export interface FetchedArtefact {
  /** The body. */
  blob: Blob;
  /** Its content address. */
  key: string;
  /** Bytes transferred. */
  bytes: number;
}

/** The model reference of a show request: the stored version when one is named (the shell names none once edited), else the source. */
export function modelRef(show: ModelShow): ModelRef {
  if (show.modelId && show.version !== null && show.version !== undefined)
    return { from: 'version', modelId: show.modelId, version: show.version };
  return { from: 'source', source: show.source };
}

/** Requests and downloads one artefact. */
export async function fetchArtefact(
  api: Api,
  show: ModelShow,
  spec: ArtefactSpec,
  signal: AbortSignal,
  progress?: (key: string, fraction: number) => void,
  abandon?: (key: string) => void,
): Promise<FetchedArtefact> {
  const body: ArtefactRequest = { model: modelRef(show), params: show.params, spec };
  const ref = await api.requestArtefact(body, signal);
  progress?.(ref.key, ref.ready ? 1 : 0);
  try {
    const blob = await api.fetchArtefact(ref, (loaded, total) => progress?.(ref.key, total ? loaded / total : 0.5), signal);
    progress?.(ref.key, 1);
    return { blob, key: ref.key, bytes: blob.size };
  } catch (e) {
    // A superseded request tells the server it no longer waits (it may stop the job).
    if (signal.aborted && !ref.ready) abandon?.(ref.key);
    throw e;
  }
}

/** Whether an error is a cancellation (superseded request). */
export function isAbort(e: unknown): boolean {
  return (e instanceof DOMException && e.name === 'AbortError') || (e as { name?: string } | null)?.name === 'AbortError';
}

/** Decodes an image blob to something drawable. */
export async function decodeImage(blob: Blob): Promise<ImageBitmap | HTMLImageElement> {
  if (typeof createImageBitmap === 'function') return createImageBitmap(blob);
  const url = URL.createObjectURL(blob);
  try {
    const img = new Image();
    img.src = url;
    await img.decode();
    return img;
  } finally {
    URL.revokeObjectURL(url);
  }
}
