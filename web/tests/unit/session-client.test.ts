import { describe, expect, it } from 'vitest';
import { encodeBinary } from '../../src/session/binary';
import { Session, type SocketLike } from '../../src/session/session';
import { Backoff } from '../../src/session/backoff';
import type { ClientMessage, ClientReport, Decision } from '../../src/wire';

class FakeSocket implements SocketLike {
  binaryType = 'blob';
  readyState = 0;
  onopen: ((ev: unknown) => void) | null = null;
  onclose: ((ev: unknown) => void) | null = null;
  onerror: ((ev: unknown) => void) | null = null;
  onmessage: ((ev: { data: unknown }) => void) | null = null;
  sent: ClientMessage[] = [];
  send(data: string): void {
    this.sent.push(JSON.parse(data) as ClientMessage);
  }
  close(): void {
    this.readyState = 3;
    this.onclose?.({});
  }
  open(): void {
    this.readyState = 1;
    this.onopen?.({});
  }
  text(msg: unknown): void {
    this.onmessage?.({ data: JSON.stringify(msg) });
  }
  binary(bytes: Uint8Array): void {
    this.onmessage?.({ data: bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength) });
  }
}

const report: ClientReport = {
  userAgent: 'test',
  webgl2: true,
  renderer: 'SwiftShader',
  maxTextureSize: 8192,
  max3dTextureSize: 2048,
  webgpu: false,
  gpuBenchMs: 3,
  wasmBenchMeps: null,
  cpuBenchMs: 4,
  screen: { width: 1280, height: 800, pixelRatio: 1 },
  mobile: false,
  deviceMemoryGb: 8,
  cores: 2,
};

/** A session over fake sockets, a manual clock and manual timers. */
function harness() {
  const sockets: FakeSocket[] = [];
  let now = 0;
  const timers: { at: number; cb: () => void; id: number }[] = [];
  let nextId = 1;
  const s = new Session({
    url: 'ws://x/api/session',
    report: () => report,
    socket: () => {
      const f = new FakeSocket();
      sockets.push(f);
      return f;
    },
    now: () => now,
    backoff: { baseMs: 100, maxMs: 1000, random: () => 1 },
    setTimer: (cb, ms) => {
      const t = { at: now + ms, cb, id: nextId++ };
      timers.push(t);
      return t.id;
    },
    clearTimer: (id) => {
      const i = timers.findIndex((t) => t.id === id);
      if (i >= 0) timers.splice(i, 1);
    },
  });
  const advance = (ms: number) => {
    now += ms;
    for (;;) {
      timers.sort((a, b) => a.at - b.at);
      const t = timers[0];
      if (!t || t.at > now) break;
      timers.shift();
      t.cb();
    }
  };
  return { s, sockets, advance, setNow: (t: number) => (now = t), get now() { return now; } };
}

const flush = () => new Promise((r) => setTimeout(r, 0));
const decision: Decision = {
  mode: 'serverMesh',
  settings: { width: 512, height: 512, quality: 80, movingScale: 2, movingQuality: 50, format: 'jpeg', views: 24, elevations: [0, 30], meshDepth: 6, coarseDepth: 4, volumeGrid: 64 },
  reason: 'fast link',
  overridden: false,
  predictions: [],
  network: { rttMs: 2, bandwidthBps: 1e8, samples: 3 },
  trigger: 'connect',
  seq: 1,
};

describe('session client', () => {
  it('says hello with the report, answers pings and forwards decisions', async () => {
    const h = harness();
    const decisions: Decision[] = [];
    h.s.on('decision', (d) => decisions.push(d));
    h.s.connect();
    const ws = h.sockets[0];
    expect(ws.binaryType).toBe('arraybuffer');
    ws.open();
    await flush();
    expect(ws.sent[0]).toEqual({ type: 'hello', report });
    ws.text({ type: 'welcome', sessionId: 's1', server: 'frep' });
    ws.text({ type: 'ping', id: 42 });
    expect(ws.sent[1]).toEqual({ type: 'pong', id: 42 });
    ws.text({ type: 'decision', decision });
    expect(decisions).toEqual([decision]);
    expect(h.s.decision).toEqual(decision);
    expect(h.s.sessionId).toBe('s1');
  });

  it('times a probe from the previous message and answers probeDone', async () => {
    const h = harness();
    h.s.connect();
    const ws = h.sockets[0];
    ws.open();
    await flush();
    h.setNow(1000);
    ws.text({ type: 'ping', id: 1 });
    h.setNow(1080);
    ws.binary(encodeBinary({ type: 'probe', id: 5, bytes: 100_000 }, new Uint8Array(100_000)));
    const done = ws.sent.find((m) => m.type === 'probeDone');
    expect(done).toEqual({ type: 'probeDone', id: 5, bytes: 100_000, clientMs: 80 });
    expect(h.s.bandwidthBps()).toBeCloseTo(10_000_000, 3);
  });

  it('throttles camera messages and always sends the latest last', async () => {
    const h = harness();
    h.s.connect();
    const ws = h.sockets[0];
    ws.open();
    await flush();
    h.setNow(100);
    const cam = (yaw: number) => ({ yaw, pitch: 0, fov: 30, zoom: 1, pan: [0, 0, 0] as [number, number, number] });
    h.s.camera(cam(1), true, 100, 100);
    h.s.camera(cam(2), true, 100, 100);
    h.s.camera(cam(3), true, 100, 100);
    const cams = () => ws.sent.filter((m) => m.type === 'camera').map((m) => (m as { camera: { yaw: number } }).camera.yaw);
    expect(cams()).toEqual([1]);
    h.advance(40);
    expect(cams()).toEqual([1, 3]);
    // Two in flight without frames: the next waits for a frame.
    h.s.camera(cam(4), false, 100, 100);
    h.advance(40);
    expect(cams()).toEqual([1, 3]);
    const frame = encodeBinary(
      { type: 'frame', seq: 1, camera: cam(1), width: 50, height: 50, format: 'jpeg', serverMs: 3, moving: true },
      new Uint8Array([1, 2]),
    );
    const frames: { askedAt: number | null }[] = [];
    h.s.on('frame', (f) => frames.push(f));
    ws.binary(frame);
    expect(cams()).toEqual([1, 3, 4]);
    expect(frames[0].askedAt).toBe(100);
  });

  it('answers frames at once when nobody shows them', async () => {
    const h = harness();
    h.s.connect();
    const ws = h.sockets[0];
    ws.open();
    await flush();
    const cam = { yaw: 0, pitch: 0, fov: 30, zoom: 1, pan: [0, 0, 0] as [number, number, number] };
    ws.binary(encodeBinary({ type: 'frame', seq: 9, camera: cam, width: 8, height: 8, format: 'jpeg', serverMs: 1, moving: false }, new Uint8Array([1])));
    expect(ws.sent.find((m) => m.type === 'frameAck')).toEqual({ type: 'frameAck', seq: 9, latencyMs: 0 });
  });

  it('reconnects with backoff and sends hello, override and open again', async () => {
    const h = harness();
    h.s.connect();
    h.sockets[0].open();
    await flush();
    h.s.override('viewSet');
    h.s.open('m1', 2, 'src', [1]);
    h.sockets[0].close();
    expect(h.s.state).toBe('closed');
    h.advance(99);
    expect(h.sockets.length).toBe(1);
    h.advance(1);
    expect(h.sockets.length).toBe(2);
    h.sockets[1].open();
    await flush();
    expect(h.sockets[1].sent.map((m) => m.type)).toEqual(['hello', 'override', 'open']);
    expect(h.sockets[1].sent[2]).toEqual({ type: 'open', modelId: 'm1', version: 2, source: 'src', params: [1] });
  });

  it('reports a malformed binary message instead of throwing', async () => {
    const h = harness();
    const errors: string[] = [];
    h.s.on('error', (e) => errors.push(e));
    h.s.connect();
    h.sockets[0].open();
    await flush();
    h.sockets[0].binary(new Uint8Array([200, 0, 0, 0, 1]));
    h.sockets[0].onmessage?.({ data: 'not json{' });
    h.sockets[0].text({ nothing: 1 });
    expect(errors.length).toBe(3);
  });

  it('dispose stops reconnecting', () => {
    const h = harness();
    h.s.connect();
    h.s.dispose();
    h.advance(10_000);
    expect(h.sockets.length).toBe(1);
  });
});

describe('backoff', () => {
  it('doubles up to the cap with jitter in the upper half, and resets', () => {
    let r = 0;
    const b = new Backoff({ baseMs: 100, maxMs: 800, random: () => r });
    expect(b.next()).toBe(50);
    expect(b.next()).toBe(100);
    r = 1;
    expect(b.next()).toBe(400);
    expect(b.next()).toBe(800);
    expect(b.next()).toBe(800);
    b.reset();
    expect(b.next()).toBe(100);
  });
});
