#!/usr/bin/env node
/**
 * The studio's performance bench: headless Chromium (Debian's, SwiftShader
 * WebGL) against a `frep serve` on loopback.
 *
 * For each Table I example and each mode (the six forced through the
 * viewer's override, and auto), a fresh browser context (no HTTP cache)
 * opens a page on the server's origin, mounts the adaptive viewer
 * (bench-harness.ts, bundled here with Vite) and times `show()` to the
 * first display. The server's artefact cache is cold or warm by design:
 * each repetition uses a new value of the (unused) parameter a[1], so the
 * artefact key is new (cold); then a second fresh context repeats the same
 * value (warm). Per case it records the page clock, the viewer's own
 * figure, the server's compute time (sum of `x-frep-server-ms` headers),
 * the time spent waiting on the network (union of /api/ resource
 * intervals), bytes received (CDP: HTTP encoded lengths plus WebSocket
 * frames) and the studio's own overhead (total minus the network wait,
 * which itself holds the server time). Then a slider move in modes 1 and 4a:
 * `setParams` with a new a[1], timed to the updated display. Last, the
 * studio itself: navigation to `#/model/ID` to the first display.
 *
 * Every case runs under a timeout (FREP_BENCH_CASE_TIMEOUT_MS, default
 * 60 s): a case that misses it is recorded as a failure, never a hang.
 * Usage: node web/bench/studio-bench.mjs [--quick] [--out FILE]
 * Environment: FREP_BENCH_REPS (3), FREP_BENCH_URL (use a running server),
 * FREP_BIN, FREP_CHROMIUM, FREP_BENCH_SIZE (viewer box, 512 px).
 */
import { readFileSync, writeFileSync, existsSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { chromium } from 'playwright-core';
import { web, repo, CHROMIUM, CHROMIUM_ARGS, startServer, bundle, bounded, stat, firstErr, machine, f0 } from './bench-common.mjs';

const argv = process.argv.slice(2);
const QUICK = argv.includes('--quick');
const outArg = argv.indexOf('--out');
const OUT = outArg >= 0 ? resolve(argv[outArg + 1]) : QUICK ? null : join(repo, 'docs', 'bench-studio.md');
const REPS = QUICK ? 1 : Math.max(1, Number(process.env.FREP_BENCH_REPS ?? 3));
const CASE_MS = Number(process.env.FREP_BENCH_CASE_TIMEOUT_MS ?? 60_000);
const SIZE = Number(process.env.FREP_BENCH_SIZE ?? 512);
const ALL_EXAMPLES = ['sphere', 'semi_sphere', 'cylinder', 'closed_cylinder', 'android_robot', 'complex_hemisphere', 'sake_pot'];
const EXAMPLES = QUICK ? ['sphere', 'android_robot'] : ALL_EXAMPLES;
const MODES = QUICK ? ['still', 'auto'] : ['still', 'viewSet', 'serverMesh', 'gpuRaycast', 'wasmMesh', 'volume', 'auto'];
/** The modes whose slider moves are timed. */
const SLIDER_MODES = ['still', 'gpuRaycast'];

// ---------------------------------------------------------------- one case

/** Counts bytes received (HTTP encoded lengths, WebSocket frames) and server times, resettable. */
async function meter(page, context) {
  const m = { bytes: 0, serverMs: 0, reset() { this.bytes = 0; this.serverMs = 0; } };
  const cdp = await context.newCDPSession(page);
  await cdp.send('Network.enable');
  cdp.on('Network.loadingFinished', (e) => (m.bytes += e.encodedDataLength));
  cdp.on('Network.webSocketFrameReceived', (e) => {
    const p = e.response.payloadData ?? '';
    m.bytes += e.response.opcode === 2 ? Math.floor((p.length * 3) / 4) : Buffer.byteLength(p);
  });
  page.on('response', async (r) => {
    const v = (await r.allHeaders().catch(() => ({})))['x-frep-server-ms'];
    if (v !== undefined && Number.isFinite(Number(v))) m.serverMs += Number(v);
  });
  return m;
}

/** Union length of [start, end] intervals (parallel requests count once). */
function unionMs(iv) {
  const s = iv.filter((x) => x.end > x.start).sort((a, b) => a.start - b.start);
  let total = 0;
  let cs = -Infinity;
  let ce = -Infinity;
  for (const x of s) {
    if (x.start > ce) {
      if (ce > cs) total += ce - cs;
      cs = x.start;
      ce = x.end;
    } else ce = Math.max(ce, x.end);
  }
  if (ce > cs) total += ce - cs;
  return total;
}

/** A fresh context and page on the server's origin with the harness mounted. */
async function harnessPage(browser, url, files, wasm, mode) {
  const context = await browser.newContext({ viewport: { width: SIZE + 64, height: SIZE + 64 } });
  const page = await context.newPage();
  await page.route('**/__bench/**', (route) => {
    const name = new URL(route.request().url()).pathname.replace(/^\/__bench\//, '');
    const f = files.get(name);
    return f ? route.fulfill({ body: f.body, contentType: f.type }) : route.fulfill({ status: 404, body: name });
  });
  if (wasm) await page.route('**/frep.wasm', (route) => route.fulfill({ body: wasm, contentType: 'application/wasm' }));
  const m = await meter(page, context);
  // The document comes from the server itself (Chromium's local-network
  // checks refuse a WebSocket from a route-fulfilled page to 127.0.0.1).
  await page.goto(`${url}/api/health`);
  const pageMs = await page.evaluate(async (size) => {
    document.body.replaceChildren();
    const t0 = performance.now();
    const s = document.createElement('script');
    s.type = 'module';
    s.src = '/__bench/harness.js';
    document.head.append(s);
    while (!('frepBench' in window)) await new Promise((r) => setTimeout(r, 5));
    return performance.now() - t0;
  }, SIZE);
  await page.evaluate(([s, md]) => window.frepBench.mount(s, md), [SIZE, mode === 'auto' ? null : mode]);
  return { context, page, m, pageMs };
}

/** Splits a step's time into network wait (server inside it) and the studio's own part. */
async function account(page, m, step) {
  const res = await page.evaluate((t0) => window.frepBench.resources(t0), step.t0);
  const api = res.filter((r) => new URL(r.name).pathname.startsWith('/api/') && r.end <= step.t0 + step.ms + 1);
  const netMs = unionMs(api);
  return { ms: step.ms, viewerMs: step.viewerMs, mode: step.mode, serverMs: m.serverMs, netMs, ownMs: Math.max(0, step.ms - netMs), bytes: m.bytes };
}

/** Opens `source` in `mode` in a fresh context; with `moves`, also times slider moves. */
async function openCase(env, source, params, mode, moves = []) {
  const { browser, url, files, wasm } = env;
  let ctx = null;
  const run = async () => {
    ctx = await harnessPage(browser, url, files, wasm, mode);
    const { page, m } = ctx;
    m.reset();
    const r = await page.evaluate(([s, p, md, t]) => window.frepBench.open(s, p, md, t), [source, params, mode === 'auto' ? null : mode, CASE_MS - 5000]);
    const first = await account(page, m, r.first);
    const out = { pageMs: ctx.pageMs, first, decided: r.decided ? { ms: r.decided.ms, mode: r.decided.mode } : null, moves: [] };
    for (const p of moves) {
      m.reset();
      const s = await page.evaluate(([pp, md, t]) => window.frepBench.move(pp, md, t), [p, mode, 20_000]);
      out.moves.push(await account(page, m, s));
    }
    return out;
  };
  try {
    return await bounded(run(), CASE_MS, `${mode}`);
  } catch (e) {
    return { error: String(e.message ?? e).split('\n')[0].slice(0, 160) };
  } finally {
    if (ctx) await ctx.context.close().catch(() => {});
  }
}

/** The studio itself: `#/model/ID` in a fresh context, navigation start to the first display. */
async function studioCase(env, id) {
  const { browser, url } = env;
  let context = null;
  const run = async () => {
    context = await browser.newContext({ viewport: { width: 1280, height: 800 } });
    const page = await context.newPage();
    const m = await meter(page, context);
    await page.goto(`${url}/#/model/${encodeURIComponent(id)}`);
    const h = await page.waitForFunction(() => {
      const r = document.querySelector('[data-testid=viewer]');
      return r && r.dataset.state === 'displayed' && Number(r.dataset.displays ?? 0) > 0
        ? { ms: performance.now(), viewerMs: Number(r.dataset.lastDisplayMs ?? NaN), mode: r.dataset.mode ?? '' }
        : null;
    }, undefined, { polling: 'raf', timeout: CASE_MS - 5000 });
    const v = await h.jsonValue();
    const res = await page.evaluate(() => performance.getEntriesByType('resource').map((e) => ({ name: e.name, start: e.startTime, end: e.responseEnd })));
    const netMs = unionMs(res.filter((r) => new URL(r.name).pathname.startsWith('/api/') && r.end <= v.ms + 1));
    return { first: { ...v, serverMs: m.serverMs, netMs, ownMs: Math.max(0, v.ms - netMs), bytes: m.bytes } };
  };
  try {
    return await bounded(run(), CASE_MS, 'studio');
  } catch (e) {
    return { error: String(e.message ?? e).split('\n')[0].slice(0, 160) };
  } finally {
    if (context) await context.close().catch(() => {});
  }
}

// ---------------------------------------------------------------- statistics and report

function report(results, studio, errors, elapsedS, partial = false) {
  const mc = machine();
  const L = [];
  L.push('# Studio performance bench');
  L.push('');
  if (partial) {
    L.push('**PARTIAL: the run had not finished when this was written (cells below are the ones done).**');
    L.push('');
  }
  L.push(`Measured ${mc.date} on ${mc.nproc} cores (${mc.cpu}), commit ${mc.commit}${mc.dirty}, ${mc.chromium}, Node ${mc.node};`);
  L.push(`${REPS} repetition(s) per cell, viewer box ${SIZE}² CSS px, case timeout ${CASE_MS / 1000} s, whole run ${elapsedS.toFixed(0)} s${QUICK ? ' (--quick)' : ''}.`);
  L.push('The machine is shared (other jobs build on the same cores) and WebGL is SwiftShader, a software');
  L.push('renderer on the CPU: every GPU mode here draws on the same two cores as the server. Read the figures');
  L.push('as an upper bound for a desktop with a real GPU, and compare rows with each other rather than with a');
  L.push('faster machine.');
  L.push('');
  L.push('Rerun: `cargo build --release -p frep-cli && scripts/build-wasm.sh && (cd web && npx vite build) && scripts/bench-studio.sh`');
  L.push('(`--quick`: two models, still and auto, one repetition; `FREP_BENCH_REPS=N`; see the method below).');
  L.push('');
  L.push('## Open a model → first display (viewer harness, ms, median (min–max))');
  L.push('');
  L.push('Cold: the server has never computed this artefact (a new parameter value); warm: the same request');
  L.push('again from a fresh browser context (no HTTP cache, server cache hit). "viewer" is the viewer\'s own');
  L.push('`data-last-display-ms`; "server" the summed `x-frep-server-ms`; "own" the studio\'s share: total');
  L.push('minus the time waiting on /api/ requests (page, parsing, decoding, drawing, the WebSocket session);');
  L.push('"own %" its share of the total (goal ≤ 50 %). KB: bytes received for the display. Auto: first display');
  L.push('of any mode, then (→) of the mode the server decided.');
  L.push('');
  L.push('| model | mode | cold total | cold server | cold own % | warm total | warm viewer | warm server | warm own | warm own % | KB (warm) | shown |');
  L.push('|---|---|---|---|---|---|---|---|---|---|---|---|');
  for (const r of results) {
    const pct = (x) => (x.first.ms > 0 ? (100 * x.first.ownMs) / x.first.ms : undefined);
    const shown = [...new Set(r.warm.filter((x) => !x.error).map((x) => x.first.mode + (x.decided && x.decided.mode !== x.first.mode ? ` → ${x.decided.mode} ${f0(x.decided.ms)}` : '')))].join(', ');
    L.push(`| ${r.example} | ${r.mode} | ${stat(r.cold, (x) => x.first.ms)} | ${stat(r.cold, (x) => x.first.serverMs)} | ${stat(r.cold, pct)} | ${stat(r.warm, (x) => x.first.ms)} | ${stat(r.warm, (x) => x.first.viewerMs)} | ${stat(r.warm, (x) => x.first.serverMs)} | ${stat(r.warm, (x) => x.first.ownMs)} | ${stat(r.warm, pct)} | ${stat(r.warm, (x) => x.first.bytes / 1024)} | ${shown || '–'} |`);
  }
  L.push('');
  L.push('## Slider move → updated display (modes 1 and 4a; ms)');
  L.push('');
  L.push('Each move sets a[1] to a value not seen before. Mode 1: a new artefact the server renders; the first');
  L.push('updated display is the reduced still (a quarter of the pixels, as while orbiting), the full one follows');
  L.push('200 ms after the values rest. Mode 4a: `u_params` only (no shader request, no compile), the next frame.');
  L.push('');
  L.push('| model | mode | total | viewer | server | own | own % | KB |');
  L.push('|---|---|---|---|---|---|---|---|');
  for (const r of results.filter((x) => SLIDER_MODES.includes(x.mode))) {
    const mv = r.warm.flatMap((x) => (x.error ? [{ error: x.error }] : x.moves.map((m) => ({ first: m }))));
    L.push(`| ${r.example} | ${r.mode} | ${stat(mv, (x) => x.first.ms)} | ${stat(mv, (x) => x.first.viewerMs)} | ${stat(mv, (x) => x.first.serverMs)} | ${stat(mv, (x) => x.first.ownMs)} | ${stat(mv, (x) => (100 * x.first.ownMs) / x.first.ms)} | ${stat(mv, (x) => x.first.bytes / 1024)} |`);
  }
  L.push('');
  L.push('## The studio: navigation to `#/model/ID` → first display (auto, ms)');
  L.push('');
  L.push('From navigation start (page load, scripts, the model\'s fetch, session, decision) to the first');
  L.push('display in the full studio at 1280×800; cold: a stored model never rendered, warm: opened again.');
  L.push('');
  L.push('| model | cold total | warm total | warm viewer | warm server | warm own % | KB (warm) | shown |');
  L.push('|---|---|---|---|---|---|---|---|');
  for (const s of studio) {
    const shown = [...new Set(s.warm.filter((x) => !x.error).map((x) => x.first.mode))].join(', ');
    L.push(`| ${s.example} | ${stat(s.cold, (x) => x.first.ms)} | ${stat(s.warm, (x) => x.first.ms)} | ${stat(s.warm, (x) => x.first.viewerMs)} | ${stat(s.warm, (x) => x.first.serverMs)} | ${stat(s.warm, (x) => (100 * x.first.ownMs) / x.first.ms)} | ${stat(s.warm, (x) => x.first.bytes / 1024)} | ${shown || '–'} |`);
  }
  if (errors.length) {
    L.push('');
    L.push('## Failures');
    L.push('');
    for (const e of errors) L.push(`- ${e}`);
  }
  return L.join('\n') + '\n';
}

// ---------------------------------------------------------------- main

async function main() {
  const started = Date.now();
  const server = await startServer();
  const files = await bundle();
  const wasmPath = join(web, 'public', 'frep.wasm');
  const wasm = existsSync(wasmPath) ? readFileSync(wasmPath) : null;
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, headless: true });
  const env = { browser, url: server.url, files, wasm };
  const results = [];
  const studio = [];
  const errors = [];
  let counter = 0;
  // Written after every cell (marked partial) so an interrupted run leaves its figures.
  const save = (partial) => {
    const md = report(results, studio, errors, (Date.now() - started) / 1000, partial);
    if (OUT) {
      const method = existsSync(OUT) ? (readFileSync(OUT, 'utf8').split('\n## Method')[1] ?? null) : null;
      writeFileSync(OUT, md + (method ? `\n## Method${method}` : ''));
    }
    return md;
  };
  // Distinct values of the unused a[1]: each a new artefact key (cold).
  const fresh = () => [1 + ++counter / 1000];
  const note = (what, runs) => {
    const e = firstErr(runs);
    if (e) errors.push(`${what}: ${e}`);
  };
  try {
    for (const example of EXAMPLES) {
      const source = readFileSync(join(repo, 'examples', `${example}.hf`), 'utf8');
      for (const mode of MODES) {
        const cell = { example, mode, cold: [], warm: [] };
        for (let i = 0; i < REPS; i++) {
          const p = fresh();
          cell.cold.push(await openCase(env, source, p, mode));
          const moves = SLIDER_MODES.includes(mode) ? [fresh()] : [];
          cell.warm.push(await openCase(env, source, p, mode, moves));
        }
        note(`${example} ${mode} cold`, cell.cold);
        note(`${example} ${mode} warm`, cell.warm);
        results.push(cell);
        save(true);
        const w = cell.warm[0];
        console.error(`[bench] ${example} ${mode}: cold ${stat(cell.cold, (x) => x.first.ms)} warm ${stat(cell.warm, (x) => x.first.ms)} ms${w.error ? ` (${w.error})` : ` shown ${w.first.mode}`}`);
      }
      const s = { example, cold: [], warm: [] };
      for (let i = 0; i < REPS; i++) {
        const body = { name: `bench-${example}-${Date.now().toString(36)}-${i}`, source, params: fresh(), message: 'bench' };
        const r = await fetch(`${server.url}/api/models`, { method: 'POST', headers: { 'content-type': 'application/json' }, body: JSON.stringify(body) });
        if (!r.ok) {
          s.cold.push({ error: `create model: HTTP ${r.status}` });
          continue;
        }
        const id = (await r.json()).model.id;
        s.cold.push(await studioCase(env, id));
        s.warm.push(await studioCase(env, id));
      }
      note(`${example} studio cold`, s.cold);
      note(`${example} studio warm`, s.warm);
      studio.push(s);
      save(true);
      console.error(`[bench] ${example} studio: cold ${stat(s.cold, (x) => x.first.ms)} warm ${stat(s.warm, (x) => x.first.ms)} ms`);
    }
  } finally {
    await browser.close().catch(() => {});
    await server.stop();
  }
  const md = save(false);
  process.stdout.write(md);
  if (OUT) console.error(`[bench] wrote ${OUT}`);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
