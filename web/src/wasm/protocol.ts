/**
 * The messages between the studio and the kernel worker
 * (kernel.worker.ts). Every request has an id; requests on the same
 * channel supersede each other: the newest wins, an older one still
 * running stops at its next pass and answers `cancelled`.
 */
import type { Diagnostic, ShaderArtefact } from '../wire';
import type { CompileOptions, KernelCompiled, KernelMesh } from './kernel';

/** Requests to the worker. */
export type KernelRequest =
  | { id: number; kind: 'init'; wasmUrl: string }
  | { id: number; kind: 'diagnose'; source: string; body?: string }
  | { id: number; kind: 'compile'; source: string; opts?: CompileOptions }
  | {
      id: number;
      kind: 'mesh';
      source: string;
      body?: string;
      params: number[];
      /** The box; null: the model's own (comment, extent or ±10). */
      bounds: number[] | null;
      /** Depths meshed in turn, coarse first (e.g. [5, 7]). */
      depths: number[];
      method?: 'watertight' | 'dc' | 'mc';
    }
  | { id: number; kind: 'shader'; source: string; body?: string; params: number[]; bounds: number[] | null }
  | { id: number; kind: 'bench'; source: string; points: number }
  | {
      id: number;
      kind: 'colorVolume';
      source: string;
      params: number[];
      /** The sampled box. */
      bounds: number[];
      /** Samples per axis (voxel centres, x fastest). */
      grid: number;
    }
  | {
      id: number;
      kind: 'probe';
      source: string;
      params: number[];
      /** A point to evaluate, or a ray to march (first surface inside `bounds`). */
      point?: [number, number, number];
      ray?: { origin: [number, number, number]; dir: [number, number, number]; bounds: number[] };
    }
  | { id: number; kind: 'cancel'; channel: Channel };

/** A probed point: where, the field value there, and the attributes. */
export interface ProbeHit {
  point: [number, number, number];
  /** NaN where the reference interpreter reports an error. */
  value: number;
  attributes: number[];
}

/** Requests that supersede each other share a channel. */
export type Channel = 'diagnose' | 'compile' | 'mesh' | 'shader' | 'bench' | 'colorVolume' | 'probe';

/** Answers from the worker. */
export type KernelResponse =
  | { id: number; kind: 'ready' }
  | { id: number; kind: 'diagnostics'; ok: boolean; diagnostics: Diagnostic[]; ms: number }
  | { id: number; kind: 'compiled'; compiled: KernelCompiled; ms: number }
  | {
      id: number;
      kind: 'mesh';
      mesh: KernelMesh;
      depth: number;
      /** Whether this is the last (finest) pass. */
      final: boolean;
      bounds: number[];
      ms: number;
    }
  | { id: number; kind: 'shader'; shader: ShaderArtefact; ms: number }
  | { id: number; kind: 'bench'; evalsPerSecond: number; points: number; ms: number }
  | {
      id: number;
      kind: 'colorVolume';
      /** RGBA per voxel (alpha 0 where the attributes failed or are absent), x fastest. */
      rgba: Uint8Array;
      grid: number;
      ms: number;
    }
  | { id: number; kind: 'probe'; hit: ProbeHit | null; ms: number }
  | { id: number; kind: 'cancelled' }
  | { id: number; kind: 'error'; message: string; diagnostics?: Diagnostic[] };

/** The channel of a request kind. */
export function channelOf(kind: KernelRequest['kind']): Channel | null {
  switch (kind) {
    case 'diagnose':
    case 'compile':
    case 'mesh':
    case 'shader':
    case 'bench':
    case 'colorVolume':
    case 'probe':
      return kind;
    default:
      return null;
  }
}
