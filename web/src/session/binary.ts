/**
 * The session's binary messages (frep-wire session.rs): a 4-byte
 * little-endian header length `n`, `n` bytes of JSON {@link BinaryHeader},
 * then the payload. Parsing checks every length and the header's shape and
 * throws {@link BinaryFormatError} on bad input (a frame is never guessed).
 */
import type { BinaryHeader } from '../wire';

/** A malformed binary message. */
export class BinaryFormatError extends Error {
  override name = 'BinaryFormatError';
}

/** A parsed binary message. */
export interface BinaryMessage {
  /** The JSON header. */
  header: BinaryHeader;
  /** The payload (a view into the message's buffer). */
  payload: Uint8Array;
}

/** The largest header accepted (a header is a few hundred bytes). */
export const MAX_HEADER_BYTES = 64 * 1024;

/** Parses one binary message. */
export function parseBinary(data: ArrayBuffer | Uint8Array): BinaryMessage {
  const bytes = data instanceof Uint8Array ? data : new Uint8Array(data);
  if (bytes.byteLength < 4) throw new BinaryFormatError(`binary message of ${bytes.byteLength} bytes has no header length`);
  const n = new DataView(bytes.buffer, bytes.byteOffset, 4).getUint32(0, true);
  if (n > MAX_HEADER_BYTES) throw new BinaryFormatError(`binary header of ${n} bytes exceeds ${MAX_HEADER_BYTES}`);
  if (4 + n > bytes.byteLength) throw new BinaryFormatError(`binary header of ${n} bytes runs past the message (${bytes.byteLength} bytes)`);
  let header: unknown;
  try {
    header = JSON.parse(new TextDecoder().decode(bytes.subarray(4, 4 + n)));
  } catch (e) {
    throw new BinaryFormatError(`binary header is not JSON: ${(e as Error).message}`);
  }
  checkHeader(header);
  return { header, payload: bytes.subarray(4 + n) };
}

function checkHeader(h: unknown): asserts h is BinaryHeader {
  const o = h as Record<string, unknown> | null;
  if (!o || typeof o !== 'object') throw new BinaryFormatError('binary header is not an object');
  if (o.type === 'probe') {
    if (typeof o.id !== 'number' || typeof o.bytes !== 'number') throw new BinaryFormatError('probe header lacks id or bytes');
    return;
  }
  if (o.type === 'frame') {
    const cam = o.camera as Record<string, unknown> | null;
    if (typeof o.seq !== 'number' || typeof o.width !== 'number' || typeof o.height !== 'number')
      throw new BinaryFormatError('frame header lacks seq, width or height');
    if (!cam || typeof cam.yaw !== 'number' || typeof cam.pitch !== 'number' || typeof cam.zoom !== 'number')
      throw new BinaryFormatError('frame header lacks its camera');
    if (o.format !== 'jpeg' && o.format !== 'png' && o.format !== 'webp') throw new BinaryFormatError(`frame format ${String(o.format)} unknown`);
    return;
  }
  throw new BinaryFormatError(`binary header type ${String(o.type)} unknown`);
}

/** Builds a binary message (tests, and a loopback server double). */
export function encodeBinary(header: BinaryHeader, payload: Uint8Array): Uint8Array {
  const json = new TextEncoder().encode(JSON.stringify(header));
  const out = new Uint8Array(4 + json.byteLength + payload.byteLength);
  new DataView(out.buffer).setUint32(0, json.byteLength, true);
  out.set(json, 4);
  out.set(payload, 4 + json.byteLength);
  return out;
}

/** The MIME type of a frame's encoding. */
export function frameMime(format: 'jpeg' | 'png' | 'webp'): string {
  return format === 'jpeg' ? 'image/jpeg' : format === 'png' ? 'image/png' : 'image/webp';
}
