import { describe, expect, it } from 'vitest';
import { BinaryFormatError, encodeBinary, parseBinary } from '../../src/session/binary';
import type { BinaryHeader } from '../../src/wire';

const frame: BinaryHeader = {
  type: 'frame',
  seq: 7,
  camera: { yaw: 30, pitch: 20, fov: 30, zoom: 1, pan: [0, 0, 0] },
  width: 128,
  height: 96,
  format: 'jpeg',
  serverMs: 4.5,
  moving: true,
};

describe('binary session messages', () => {
  it('round-trips a frame header and its payload', () => {
    const payload = new Uint8Array([0xff, 0xd8, 1, 2, 3]);
    const msg = parseBinary(encodeBinary(frame, payload).buffer as ArrayBuffer);
    expect(msg.header).toEqual(frame);
    expect([...msg.payload]).toEqual([...payload]);
  });

  it('reads the header length little-endian', () => {
    const json = new TextEncoder().encode(JSON.stringify({ type: 'probe', id: 3, bytes: 2 }));
    const buf = new Uint8Array(4 + json.length + 2);
    buf[0] = json.length & 0xff;
    buf[1] = json.length >> 8;
    buf.set(json, 4);
    buf.set([9, 8], 4 + json.length);
    const msg = parseBinary(buf);
    expect(msg.header).toEqual({ type: 'probe', id: 3, bytes: 2 });
    expect([...msg.payload]).toEqual([9, 8]);
  });

  it('parses a message that is a view into a larger buffer', () => {
    const inner = encodeBinary({ type: 'probe', id: 1, bytes: 3 }, new Uint8Array([1, 2, 3]));
    const outer = new Uint8Array(inner.length + 10);
    outer.set(inner, 5);
    const msg = parseBinary(outer.subarray(5, 5 + inner.length));
    expect(msg.header).toEqual({ type: 'probe', id: 1, bytes: 3 });
    expect([...msg.payload]).toEqual([1, 2, 3]);
  });

  it('rejects truncated, oversized and malformed headers', () => {
    expect(() => parseBinary(new Uint8Array([1, 0]))).toThrow(BinaryFormatError);
    const long = new Uint8Array(8);
    new DataView(long.buffer).setUint32(0, 100, true);
    expect(() => parseBinary(long)).toThrow(/runs past/);
    const huge = new Uint8Array(8);
    new DataView(huge.buffer).setUint32(0, 1 << 30, true);
    expect(() => parseBinary(huge)).toThrow(/exceeds/);
    const bad = encodeBinary({ type: 'probe', id: 1, bytes: 0 }, new Uint8Array());
    bad[5] = 0x7b; // corrupt the JSON
    bad[6] = 0x7b;
    expect(() => parseBinary(bad)).toThrow(BinaryFormatError);
    const unknown = new TextEncoder().encode('{"type":"video"}');
    const u = new Uint8Array(4 + unknown.length);
    new DataView(u.buffer).setUint32(0, unknown.length, true);
    u.set(unknown, 4);
    expect(() => parseBinary(u)).toThrow(/unknown/);
    const noCam = encodeBinary({ ...frame, camera: undefined } as unknown as BinaryHeader, new Uint8Array());
    expect(() => parseBinary(noCam)).toThrow(/camera/);
  });
});
