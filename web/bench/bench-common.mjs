/**
 * Shared pieces of the browser benches (studio-bench.mjs, paper-bench.mjs):
 * Debian's Chromium and its flags, a `frep serve` on a free loopback port
 * with a fresh data directory, a page harness bundled with Vite (served to
 * the page through page.route), a per-case timeout, statistics and the
 * machine description.
 */
import { spawn, execSync } from 'node:child_process';
import { mkdtempSync, readFileSync, rmSync, existsSync } from 'node:fs';
import { brotliCompressSync, constants as zlib } from 'node:zlib';
import { createServer } from 'node:net';
import { tmpdir, cpus } from 'node:os';
import { join, resolve } from 'node:path';
import { build } from 'vite';

export const web = resolve(import.meta.dirname, '..');
export const repo = resolve(web, '..');
export const CHROMIUM = process.env.FREP_CHROMIUM ?? '/usr/lib/chromium/chromium';
/** The same flags as web/tests/e2e/support/env.ts. */
export const CHROMIUM_ARGS = ['--headless', '--no-sandbox', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync', '--disable-quic', '--enable-unsafe-swiftshader'];

// ---------------------------------------------------------------- server

export function freePort() {
  return new Promise((ok, fail) => {
    const s = createServer();
    s.once('error', fail);
    s.listen(0, '127.0.0.1', () => {
      const a = s.address();
      s.close(() => ok(a.port));
    });
  });
}

async function waitHealthy(url, ms, child) {
  const end = Date.now() + ms;
  while (Date.now() < end) {
    if (child && child.exitCode !== null) throw new Error(`frep serve exited with ${child.exitCode}`);
    try {
      if ((await fetch(`${url}/api/health`)).ok) return;
    } catch {
      /* not up yet */
    }
    await new Promise((r) => setTimeout(r, 200));
  }
  throw new Error(`${url}/api/health not ready after ${ms} ms`);
}

/** Starts `frep serve` on a free loopback port with a fresh data directory. */
export async function startServer() {
  if (process.env.FREP_BENCH_URL) return { url: process.env.FREP_BENCH_URL.replace(/\/$/, ''), stop: async () => {} };
  const bin = process.env.FREP_BIN ?? join(repo, 'target', 'release', 'frep');
  if (!existsSync(bin)) throw new Error(`${bin} not found: run \`cargo build --release -p frep-cli\` (or set FREP_BENCH_URL)`);
  const port = await freePort();
  const data = mkdtempSync(join(tmpdir(), 'frep-bench-'));
  const url = `http://127.0.0.1:${port}`;
  const child = spawn(bin, ['serve', '--addr', `127.0.0.1:${port}`, '--data', data, '--static', join(web, 'dist')], { cwd: repo, stdio: ['ignore', 'ignore', 'pipe'] });
  let log = '';
  child.stderr.on('data', (b) => (log = (log + b).slice(-4000)));
  try {
    await waitHealthy(url, 60_000, child);
  } catch (e) {
    child.kill('SIGKILL');
    rmSync(data, { recursive: true, force: true });
    throw new Error(`${e}\n${log}`);
  }
  return {
    url,
    async stop() {
      if (child.exitCode === null) {
        const gone = new Promise((r) => child.once('exit', r));
        child.kill('SIGTERM');
        const t = setTimeout(() => child.kill('SIGKILL'), 5000);
        await gone;
        clearTimeout(t);
      }
      rmSync(data, { recursive: true, force: true });
    },
  };
}

// ---------------------------------------------------------------- harness bundle

/**
 * Bundles `entry` (a file under web/bench) for /__bench/; `harness.js` is
 * the entry chunk. Each file also gets `wire`: its brotli size (quality 11,
 * as web/build/precompress.ts writes the studio's), what the server would
 * send. page.route cannot serve an encoded body, so the benches charge
 * links and count bytes by `wire` instead of the raw body.
 */
export async function bundle(entry = 'bench-harness.ts') {
  const out = await build({
    configFile: false,
    root: web,
    base: '/__bench/',
    logLevel: 'warn',
    build: {
      write: false,
      minify: true,
      target: 'es2022',
      modulePreload: false,
      rollupOptions: { input: join(web, 'bench', entry), output: { entryFileNames: 'harness.js', format: 'es' } },
    },
    worker: { format: 'es' },
  });
  const files = new Map();
  for (const r of Array.isArray(out) ? out : [out])
    for (const o of r.output) {
      const body = o.type === 'chunk' ? Buffer.from(o.code ?? '') : Buffer.from(o.source ?? '');
      const type = o.fileName.endsWith('.js') ? 'text/javascript' : o.fileName.endsWith('.wasm') ? 'application/wasm' : 'application/octet-stream';
      const wire = brotliCompressSync(body, { params: { [zlib.BROTLI_PARAM_QUALITY]: 11 } }).length;
      files.set(o.fileName, { body, type, wire });
    }
  return files;
}

/** Races `p` against the case timeout. */
export function bounded(p, ms, what) {
  let timer;
  const t = new Promise((_, fail) => (timer = setTimeout(() => fail(new Error(`timeout after ${ms} ms: ${what}`)), ms)));
  return Promise.race([p, t]).finally(() => clearTimeout(timer));
}

export const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  const n = s.length;
  return n === 0 ? NaN : n % 2 ? s[(n - 1) / 2] : (s[n / 2 - 1] + s[n / 2]) / 2;
};
export const f0 = (x) => (Number.isFinite(x) ? x.toFixed(0) : '–');
/** "median (min–max)" of a field over the successful runs, and a failure count. */
export function stat(runs, get) {
  const ok = runs.filter((r) => !r.error && get(r) !== undefined).map(get);
  const bad = runs.length - runs.filter((r) => !r.error).length;
  if (!ok.length) return bad ? `FAIL×${bad}` : '–';
  const s = ok.length > 1 ? `${f0(median(ok))} (${f0(Math.min(...ok))}–${f0(Math.max(...ok))})` : f0(ok[0]);
  return bad ? `${s} FAIL×${bad}` : s;
}
export const firstErr = (runs) => runs.find((r) => r.error)?.error;

export function machine() {
  const sh = (c) => {
    try {
      return execSync(c, { cwd: repo, stdio: ['ignore', 'pipe', 'ignore'] }).toString().trim();
    } catch {
      return '?';
    }
  };
  const cpu = (readFileSync('/proc/cpuinfo', 'utf8').match(/model name\s*:\s*(.*)/) ?? [])[1] ?? cpus()[0]?.model ?? '?';
  return { nproc: sh('nproc'), cpu, commit: sh('git rev-parse --short HEAD'), dirty: sh('git status --porcelain -- crates web/src web/bench') ? ' (+ uncommitted changes)' : '', date: new Date().toISOString().replace(/\.\d+Z$/, 'Z'), chromium: sh(`${CHROMIUM} --version`), node: process.version };
}

