/// <reference types="node" />
/**
 * Starting and stopping a `frep serve` process for the end-to-end tests.
 *
 * The server listens on 127.0.0.1 at a port the OS hands out (we bind port
 * 0, read the number, close, and pass it on: the window in which another
 * process could take it is tiny and a clash fails loudly). Its data lives
 * in a fresh temporary directory removed on stop. Readiness is
 * `GET /api/health` answering 2xx, polled until a deadline.
 */
import { spawn, type ChildProcess } from 'node:child_process';
import { mkdtempSync, rmSync, existsSync } from 'node:fs';
import { createServer } from 'node:net';
import { tmpdir } from 'node:os';
import { join, resolve } from 'node:path';

/** The repository root (web/tests/e2e/support → ../../../..). */
export const repoRoot = resolve(import.meta.dirname, '..', '..', '..', '..');

/** A running server. */
export interface RunningServer {
  /** `http://127.0.0.1:PORT`. */
  url: string;
  /** Stops the process and removes its data directory. */
  stop(): Promise<void>;
}

/** Options of {@link startServer}. */
export interface ServerOptions {
  /** The `frep` binary (default: target/release/frep, env FREP_BIN). */
  bin?: string;
  /** Milliseconds to wait for /api/health (default 60 s). */
  readyTimeoutMs?: number;
  /** Extra arguments after `serve --addr … --data …`. */
  extraArgs?: string[];
}

/** A free TCP port on 127.0.0.1. */
export function freePort(): Promise<number> {
  return new Promise((ok, fail) => {
    const srv = createServer();
    srv.once('error', fail);
    srv.listen(0, '127.0.0.1', () => {
      const addr = srv.address();
      const port = typeof addr === 'object' && addr ? addr.port : 0;
      srv.close(() => (port ? ok(port) : fail(new Error('no port'))));
    });
  });
}

/** Polls `url/api/health` until it answers 2xx or the deadline passes. */
export async function waitHealthy(url: string, timeoutMs: number, child?: ChildProcess): Promise<void> {
  const deadline = Date.now() + timeoutMs;
  let last = '';
  while (Date.now() < deadline) {
    if (child && child.exitCode !== null) {
      throw new Error(`frep serve exited with ${child.exitCode} before it was ready`);
    }
    try {
      const r = await fetch(`${url}/api/health`);
      if (r.ok) return;
      last = `HTTP ${r.status}`;
    } catch (e) {
      last = String(e);
    }
    await new Promise((r) => setTimeout(r, 200));
  }
  throw new Error(`${url}/api/health not ready after ${timeoutMs} ms (${last})`);
}

/** Starts `frep serve` on a free port with a fresh data directory. */
export async function startServer(opts: ServerOptions = {}): Promise<RunningServer> {
  const bin = opts.bin ?? process.env.FREP_BIN ?? join(repoRoot, 'target', 'release', 'frep');
  if (!existsSync(bin)) {
    throw new Error(`${bin} not found: run \`cargo build --release -p frep-cli\` first (or set FREP_E2E_URL)`);
  }
  const port = await freePort();
  const data = mkdtempSync(join(tmpdir(), 'frep-e2e-'));
  const url = `http://127.0.0.1:${port}`;
  const args = ['serve', '--addr', `127.0.0.1:${port}`, '--data', data, ...(opts.extraArgs ?? [])];
  // cwd is the repository root, where the server finds web/dist and examples/.
  const child = spawn(bin, args, {
    cwd: repoRoot,
    env: { ...process.env, FREP_STATIC_DIR: join(repoRoot, 'web', 'dist') },
    stdio: ['ignore', 'pipe', 'pipe'],
  });
  const log: string[] = [];
  const keep = (b: Buffer) => {
    log.push(b.toString());
    if (log.length > 200) log.shift();
  };
  child.stdout?.on('data', keep);
  child.stderr?.on('data', keep);
  try {
    await waitHealthy(url, opts.readyTimeoutMs ?? 60_000, child);
  } catch (e) {
    child.kill('SIGKILL');
    rmSync(data, { recursive: true, force: true });
    throw new Error(`${String(e)}\n--- server output ---\n${log.join('')}`);
  }
  return {
    url,
    async stop() {
      if (child.exitCode === null) {
        const exited = new Promise((r) => child.once('exit', r));
        child.kill('SIGTERM');
        const timer = setTimeout(() => child.kill('SIGKILL'), 5000);
        await exited;
        clearTimeout(timer);
      }
      rmSync(data, { recursive: true, force: true });
    },
  };
}
