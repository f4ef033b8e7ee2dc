/**
 * The studio's WebSocket session client (`/api/session`, frep-wire
 * session.rs).
 *
 * It says hello with the client's report, answers pings at once, times the
 * server's bandwidth probes and answers `probeDone`, forwards decisions,
 * artefact notices, progress and streamed frames to listeners, and sends
 * what the viewer measures (displays, frame acks, frame rates) and asks for
 * (open, camera, override, cancel). Camera messages are throttled to the
 * frame rhythm: one at most per `cameraIntervalMs`, at most
 * `maxCamerasInFlight` unanswered by a frame, the latest one always sent
 * last (a pending camera is replaced, never queued). The connection is
 * re-opened with backoff; on reconnect the hello, the open model and the
 * override are sent again. Messages sent while closed are dropped except
 * those three (the state a new connection needs).
 */
import type { BinaryHeader, CameraView, ClientMessage, ClientReport, Decision, Mode, ServerMessage, ArtefactRef, SectionPlane } from '../wire';
import { Backoff, type BackoffOptions, DEFAULT_BACKOFF } from './backoff';
import { parseBinary } from './binary';
import { Emitter } from './emitter';

/** The part of a WebSocket the session uses (a fake in tests). */
export interface SocketLike {
  binaryType: string;
  readyState: number;
  onopen: ((ev: unknown) => void) | null;
  onclose: ((ev: unknown) => void) | null;
  onerror: ((ev: unknown) => void) | null;
  onmessage: ((ev: { data: unknown }) => void) | null;
  send(data: string): void;
  close(): void;
}

/** A streamed frame as received. */
export interface ReceivedFrame {
  /** The frame's sequence number (the header's). */
  seq: number;
  /** Its header. */
  header: Extract<BinaryHeader, { type: 'frame' }>;
  /** The encoded image. */
  payload: Uint8Array;
  /** Arrival time (the session's clock, ms). */
  arrivedAt: number;
  /** When the camera message that asked for it was sent (null: unknown). */
  askedAt: number | null;
}

/** Connection states. */
export type SessionState = 'connecting' | 'open' | 'closed';

/** The session's events. */
export type SessionEvents = {
  state: [SessionState];
  welcome: [string];
  decision: [Decision];
  artefact: [string, ArtefactRef];
  progress: [string, number];
  modelChanged: [string, number, string];
  error: [string];
  frame: [ReceivedFrame];
  probe: [ProbeSample];
  ping: [number];
};

/** One bandwidth probe as the client saw it. */
export interface ProbeSample {
  /** The probe's id. */
  id: number;
  /** Bytes of payload. */
  bytes: number;
  /** ms from the previous message's arrival to this one's (the transfer, when the server precedes each probe with a message). */
  clientMs: number;
  /** bytes × 8 / clientMs, bits per second (null when clientMs is 0). */
  bps: number | null;
}

/** Session settings. */
export interface SessionOptions {
  /** `ws://…/api/session`. */
  url: string;
  /** The client's report (measured before the hello). */
  report: () => Promise<ClientReport> | ClientReport;
  /** Makes the socket (default: the browser's WebSocket). */
  socket?: (url: string) => SocketLike;
  /** The clock (ms). */
  now?: () => number;
  /** Reconnection delays. */
  backoff?: BackoffOptions;
  /** Minimum ms between camera messages (default 33: 30 a second). */
  cameraIntervalMs?: number;
  /** Camera messages allowed without a frame back (default 2). */
  maxCamerasInFlight?: number;
  /** Timers (tests inject fakes). */
  setTimer?: (cb: () => void, ms: number) => unknown;
  clearTimer?: (t: unknown) => void;
}

type CameraMsg = Extract<ClientMessage, { type: 'camera' }>;
type OpenMsg = Extract<ClientMessage, { type: 'open' }>;

/** The studio's session. */
export class Session {
  private ws: SocketLike | null = null;
  private readonly events = new Emitter<SessionEvents>();
  private readonly backoff: Backoff;
  private readonly now: () => number;
  private readonly setTimer: (cb: () => void, ms: number) => unknown;
  private readonly clearTimer: (t: unknown) => void;
  private reconnectTimer: unknown = null;
  private cameraTimer: unknown = null;
  private disposed = false;
  private lastArrival: number | null = null;
  private lastOpen: OpenMsg | null = null;
  private lastOverride: Mode | null | undefined = undefined;
  private pendingCamera: CameraMsg | null = null;
  private lastCameraSent = -Infinity;
  private camerasInFlight = 0;
  private readonly sentCameras: { camera: CameraView; at: number }[] = [];
  /** The connection state. */
  state: SessionState = 'closed';
  /** The session id from the welcome. */
  sessionId: string | null = null;
  /** The last decision. */
  decision: Decision | null = null;
  /** Probes received (newest last, at most 16). */
  readonly probes: ProbeSample[] = [];
  /** Pings answered. */
  pings = 0;
  /** Bytes received over the socket (text and binary). */
  bytesIn = 0;
  /** Bytes sent. */
  bytesOut = 0;

  constructor(private readonly opts: SessionOptions) {
    this.backoff = new Backoff(opts.backoff ?? DEFAULT_BACKOFF);
    this.now = opts.now ?? (() => performance.now());
    this.setTimer = opts.setTimer ?? ((cb, ms) => setTimeout(cb, ms));
    this.clearTimer = opts.clearTimer ?? ((t) => clearTimeout(t as ReturnType<typeof setTimeout>));
  }

  /** Adds a listener; returns the unsubscribe. */
  on<K extends keyof SessionEvents>(event: K, cb: (...args: SessionEvents[K]) => void): () => void {
    return this.events.on(event, cb);
  }

  /** Opens the connection (and keeps re-opening it until disposed). */
  connect(): void {
    if (this.disposed || this.ws) return;
    this.setState('connecting');
    let ws: SocketLike;
    try {
      ws = this.opts.socket ? this.opts.socket(this.opts.url) : (new WebSocket(this.opts.url) as unknown as SocketLike);
    } catch (e) {
      this.events.emit('error', `cannot open the session: ${(e as Error).message}`);
      this.scheduleReconnect();
      return;
    }
    ws.binaryType = 'arraybuffer';
    this.ws = ws;
    ws.onopen = () => void this.opened(ws);
    ws.onmessage = (ev) => this.received(ev.data);
    ws.onerror = () => {};
    ws.onclose = () => {
      if (this.ws !== ws) return;
      this.ws = null;
      this.camerasInFlight = 0;
      this.setState('closed');
      this.scheduleReconnect();
    };
  }

  /** Closes for good. */
  dispose(): void {
    this.disposed = true;
    if (this.reconnectTimer !== null) this.clearTimer(this.reconnectTimer);
    if (this.cameraTimer !== null) this.clearTimer(this.cameraTimer);
    const ws = this.ws;
    this.ws = null;
    ws?.close();
    this.setState('closed');
    this.events.clear();
  }

  /** The model shown now (re-sent on reconnect). */
  open(modelId: string | null, version: number | null, source: string | null, params: number[]): void {
    this.lastOpen = { type: 'open', modelId, version, source, params };
    this.sentCameras.length = 0;
    this.send(this.lastOpen);
  }

  /** The user's mode choice (null: automatic; re-sent on reconnect). */
  override(mode: Mode | null): void {
    this.lastOverride = mode;
    this.send({ type: 'override', mode });
  }

  /** A changed report. */
  report(report: ClientReport): void {
    this.send({ type: 'report', report });
  }

  /**
   * The camera moved (throttled; the latest always goes out). `section`:
   * the plane the streamed frames cut the model by (absent: none).
   */
  camera(camera: CameraView, moving: boolean, width: number, height: number, section?: SectionPlane): void {
    this.pendingCamera = { type: 'camera', camera, moving, width: Math.round(width), height: Math.round(height), ...(section ? { section } : {}) };
    this.flushCamera();
  }

  /** A streamed frame was displayed. */
  frameAck(seq: number, latencyMs: number): void {
    this.send({ type: 'frameAck', seq, latencyMs });
  }

  /** A mode's first display of a request. */
  displayed(mode: Mode, ms: number, bytes: number): void {
    this.send({ type: 'displayed', mode, ms, bytes });
  }

  /** The achieved frame rate while interacting. */
  frameRate(mode: Mode, fps: number, frameMs: number): void {
    this.send({ type: 'frameRate', mode, fps, frameMs });
  }

  /** Stops work on an artefact the client no longer waits for. */
  cancel(key: string): void {
    this.send({ type: 'cancel', key });
  }

  /** The median of the probes' client-side bandwidth (bits/s), null before any. */
  bandwidthBps(): number | null {
    const v = this.probes.map((p) => p.bps).filter((b): b is number => b !== null);
    if (!v.length) return null;
    v.sort((a, b) => a - b);
    return v[Math.floor(v.length / 2)];
  }

  private setState(s: SessionState): void {
    if (this.state === s) return;
    this.state = s;
    this.events.emit('state', s);
  }

  private async opened(ws: SocketLike): Promise<void> {
    if (this.ws !== ws) return;
    this.backoff.reset();
    this.setState('open');
    let report: ClientReport;
    try {
      report = await this.opts.report();
    } catch (e) {
      this.events.emit('error', `cannot measure the client: ${(e as Error).message}`);
      return;
    }
    if (this.ws !== ws) return;
    this.send({ type: 'hello', report });
    if (this.lastOverride !== undefined) this.send({ type: 'override', mode: this.lastOverride });
    if (this.lastOpen) this.send(this.lastOpen);
  }

  private scheduleReconnect(): void {
    if (this.disposed || this.reconnectTimer !== null) return;
    this.reconnectTimer = this.setTimer(() => {
      this.reconnectTimer = null;
      this.connect();
    }, this.backoff.next());
  }

  private send(msg: ClientMessage): void {
    const ws = this.ws;
    if (!ws || ws.readyState !== 1) return;
    const text = JSON.stringify(msg);
    this.bytesOut += text.length;
    ws.send(text);
  }

  private flushCamera(): void {
    const msg = this.pendingCamera;
    if (!msg || this.cameraTimer !== null) return;
    const now = this.now();
    const interval = this.opts.cameraIntervalMs ?? 33;
    const wait = this.lastCameraSent + interval - now;
    const full = this.camerasInFlight >= (this.opts.maxCamerasInFlight ?? 2);
    if (wait > 0 || full) {
      // A full pipe is re-checked at the interval too, so a lost frame cannot stall the camera forever.
      this.cameraTimer = this.setTimer(
        () => {
          this.cameraTimer = null;
          if (full) this.camerasInFlight = Math.max(0, this.camerasInFlight - 1);
          this.flushCamera();
        },
        Math.max(wait, full ? interval * 4 : 0),
      );
      return;
    }
    this.pendingCamera = null;
    this.lastCameraSent = now;
    if (this.ws && this.ws.readyState === 1) {
      this.camerasInFlight++;
      this.sentCameras.push({ camera: msg.camera, at: now });
      if (this.sentCameras.length > 32) this.sentCameras.shift();
    }
    this.send(msg);
  }

  private received(data: unknown): void {
    const now = this.now();
    const gap = this.lastArrival === null ? 0 : now - this.lastArrival;
    this.lastArrival = now;
    if (typeof data === 'string') {
      this.bytesIn += data.length;
      let msg: ServerMessage;
      try {
        msg = JSON.parse(data) as ServerMessage;
      } catch {
        this.events.emit('error', 'the server sent a message that is not JSON');
        return;
      }
      if (!msg || typeof msg !== 'object' || typeof (msg as { type?: unknown }).type !== 'string') {
        this.events.emit('error', 'the server sent a message without a type');
        return;
      }
      this.handle(msg);
      return;
    }
    if (data instanceof ArrayBuffer || data instanceof Uint8Array) {
      this.bytesIn += data.byteLength;
      this.binary(data, now, gap);
    }
  }

  private handle(msg: ServerMessage): void {
    switch (msg.type) {
      case 'welcome':
        this.sessionId = msg.sessionId;
        this.events.emit('welcome', msg.sessionId);
        break;
      case 'ping':
        this.pings++;
        this.send({ type: 'pong', id: msg.id });
        this.events.emit('ping', msg.id);
        break;
      case 'decision':
        this.decision = msg.decision;
        this.events.emit('decision', msg.decision);
        break;
      case 'artefact':
        this.events.emit('artefact', msg.role, msg.artefact);
        break;
      case 'progress':
        this.events.emit('progress', msg.key, msg.fraction);
        break;
      case 'modelChanged':
        this.events.emit('modelChanged', msg.modelId, msg.version, msg.author);
        break;
      case 'error':
        this.events.emit('error', msg.message);
        break;
    }
  }

  private binary(data: ArrayBuffer | Uint8Array, now: number, gap: number): void {
    let parsed;
    try {
      parsed = parseBinary(data);
    } catch (e) {
      this.events.emit('error', (e as Error).message);
      return;
    }
    const { header, payload } = parsed;
    if (header.type === 'probe') {
      const sample: ProbeSample = { id: header.id, bytes: payload.byteLength, clientMs: gap, bps: gap > 0 ? (payload.byteLength * 8 * 1000) / gap : null };
      this.probes.push(sample);
      if (this.probes.length > 16) this.probes.shift();
      this.send({ type: 'probeDone', id: header.id, bytes: payload.byteLength, clientMs: gap });
      this.events.emit('probe', sample);
      return;
    }
    this.camerasInFlight = Math.max(0, this.camerasInFlight - 1);
    const asked = this.askedAt(header.camera);
    // Nobody shows frames now (another mode): answer at once, so the
    // server's count of frames in flight does not stall its stream.
    if (!this.events.has('frame')) this.frameAck(header.seq, 0);
    else this.events.emit('frame', { seq: header.seq, header, payload, arrivedAt: now, askedAt: asked });
    // A frame frees the pipe: a camera waiting for it goes now (or at its interval).
    if (this.cameraTimer !== null) {
      this.clearTimer(this.cameraTimer);
      this.cameraTimer = null;
    }
    if (this.pendingCamera) this.flushCamera();
  }

  /** When the camera of a frame was sent (the newest matching message). */
  private askedAt(camera: CameraView): number | null {
    for (let i = this.sentCameras.length - 1; i >= 0; i--) {
      const c = this.sentCameras[i].camera;
      if (c.yaw === camera.yaw && c.pitch === camera.pitch && c.zoom === camera.zoom && (c.fov ?? null) === (camera.fov ?? null) && c.pan.every((v, k) => v === camera.pan[k]))
        return this.sentCameras[i].at;
    }
    return null;
  }
}

/** The session URL for the page's origin (or an API base). */
export function sessionUrl(base = ''): string {
  const origin = base && /^https?:/.test(base) ? base : typeof location !== 'undefined' ? location.origin + base : 'http://127.0.0.1';
  return origin.replace(/^http/, 'ws').replace(/\/$/, '') + '/api/session';
}
