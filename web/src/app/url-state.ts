/**
 * The studio's state in the URL, so a link reopens the same view:
 * `#/model/{id}?v={version}&cam={yaw},{pitch},{zoom},{fov|o},{panX},{panY},{panZ}`.
 *
 * `v` absent means the latest version; `cam` absent means the default
 * camera. `fov` is `o` for an orthographic camera. Numbers are written with
 * at most 3 decimals (a camera a thousandth of a degree off is the same
 * view). Decoding never throws: anything unreadable is left out.
 */
import type { CameraView } from '../wire';

/** What the URL names. */
export interface UrlState {
  /** Model id (null: the model list only). */
  modelId: string | null;
  /** Version (null: latest). */
  version: number | null;
  /** Camera (null: the default). */
  camera: CameraView | null;
}

function n3(v: number): string {
  const r = Math.round(v * 1000) / 1000;
  return String(Object.is(r, -0) ? 0 : r);
}

/** The camera as `yaw,pitch,zoom,fov,px,py,pz`. */
export function encodeCamera(c: CameraView): string {
  return [c.yaw, c.pitch, c.zoom].map(n3).concat(c.fov === null ? 'o' : n3(c.fov), c.pan.map(n3)).join(',');
}

/** Reads a camera; null when malformed. */
export function decodeCamera(s: string): CameraView | null {
  const parts = s.split(',');
  if (parts.length !== 7) return null;
  const nums = parts.map((p, i) => (i === 3 && p === 'o' ? null : Number(p)));
  if (nums.some((v, i) => i !== 3 && (v === null || !Number.isFinite(v)))) return null;
  const fov = nums[3];
  if (fov !== null && (!Number.isFinite(fov) || fov <= 0 || fov >= 180)) return null;
  const zoom = nums[2] as number;
  if (zoom <= 0) return null;
  return {
    yaw: nums[0] as number,
    pitch: Math.max(-90, Math.min(90, nums[1] as number)),
    zoom,
    fov,
    pan: [nums[4] as number, nums[5] as number, nums[6] as number],
  };
}

/** The hash for a state (`#/` for the list). */
export function encodeState(s: UrlState): string {
  if (!s.modelId) return '#/';
  const q: string[] = [];
  if (s.version !== null) q.push(`v=${s.version}`);
  if (s.camera) q.push(`cam=${encodeCamera(s.camera)}`);
  return `#/model/${encodeURIComponent(s.modelId)}${q.length ? `?${q.join('&')}` : ''}`;
}

/** Reads a hash (with or without the leading `#`). */
export function decodeState(hash: string): UrlState {
  const none: UrlState = { modelId: null, version: null, camera: null };
  const h = hash.replace(/^#/, '');
  const m = /^\/model\/([^?]+)(?:\?(.*))?$/.exec(h);
  if (!m) return none;
  let modelId: string;
  try {
    modelId = decodeURIComponent(m[1]);
  } catch {
    return none;
  }
  const params = new URLSearchParams(m[2] ?? '');
  const v = Number(params.get('v'));
  const version = params.has('v') && Number.isInteger(v) && v >= 1 ? v : null;
  const cam = params.get('cam');
  return { modelId, version, camera: cam ? decodeCamera(cam) : null };
}
