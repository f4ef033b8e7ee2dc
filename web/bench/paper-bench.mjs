#!/usr/bin/env node
/**
 * The seed paper's experiment (Abdallah et al., ACHI 2014, Table I and
 * Figs. 9-10) reproduced in a real browser, and the adaptive choice
 * measured against the best technique. See docs/paper.md.
 *
 * For each client profile (web/bench/profiles.json: an emulated client and
 * an emulated link), each Table I example and each technique (the viewer's
 * modes forced: still, viewSet, serverMesh, gpuRaycast, wasmMesh; the
 * paper's baseline, uniform marching cubes in the browser; and auto), a
 * fresh browser context opens a page on the server's origin (through the
 * link's shaping proxy, paper-link.mjs), loads the harness
 * (paper-harness.ts) and measures in the page: request to first displayed
 * frame (then a screenshot checked not to be blank), bytes received (CDP
 * Network: HTTP encoded lengths plus WebSocket frames), main-thread CPU
 * time (CDP Performance: TaskDuration, ScriptDuration), and the time per
 * frame while orbiting (a scripted drag; the viewer's own frame-rate
 * reports sent on the session socket, or the baseline's frame gaps). In
 * auto, the session's decision (mode and per-mode predictions) is read
 * from the socket. A case that fails or times out is recorded with its
 * reason; the run goes on.
 *
 * Usage: node web/bench/paper-bench.mjs [--quick] [--reps N] [--models a,b]
 *   [--techs a,b] [--profiles FILE] [--base FILE] [--out DIR] (DIR gets paper.md,
 *   paper/*.svg and paper/results.json, every run with the engine's
 *   decisions and the client's report; default docs/, none with --quick
 *   unless --out is given).
 * Environment: FREP_BIN, FREP_CHROMIUM, FREP_BENCH_CASE_TIMEOUT_MS (60000).
 */
import { mkdirSync, readFileSync, writeFileSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { chromium } from 'playwright-core';
import { web, repo, CHROMIUM, CHROMIUM_ARGS, startServer, bundle, bounded } from './bench-common.mjs';
import { startLink } from './paper-link.mjs';
import { CLIENTS } from './paper-clients.mjs';
import { writeReport } from './paper-report.mjs';

const argv = process.argv.slice(2);
const opt = (name) => {
  const i = argv.indexOf(name);
  return i >= 0 ? argv[i + 1] : undefined;
};
const QUICK = argv.includes('--quick');
const REPS = QUICK ? 1 : Math.max(1, Number(opt('--reps') ?? 2));
const ALL_MODELS = ['sphere', 'semi_sphere', 'cylinder', 'closed_cylinder', 'android_robot', 'complex_hemisphere', 'sake_pot'];
const MODELS = opt('--models')?.split(',') ?? (QUICK ? ['sphere', 'android_robot'] : ALL_MODELS);
const PROFILES_FILE = resolve(opt('--profiles') ?? join(web, 'bench', 'profiles.json'));
const OUT = opt('--out') ? resolve(opt('--out')) : QUICK ? null : join(repo, 'docs');
const CASE_MS = Number(process.env.FREP_BENCH_CASE_TIMEOUT_MS ?? 60_000);
/** `--base FILE`: an earlier run's results.json; this run's cells replace its cells, the report covers both. */
const BASE = opt('--base') ? JSON.parse(readFileSync(resolve(opt('--base')), 'utf8')) : null;
/** Marching-cubes depth of the baseline: 2^5 = 32 cells a side (the paper's resolution is not known; docs/paper.md). */
const BASELINE_DEPTH = 5;
const ORBIT_MS = 2000;
/** Techniques that draw with WebGL2 (three.js or the generated shader). */
const NEEDS_WEBGL = new Set(['serverMesh', 'gpuRaycast', 'wasmMesh', 'baseline']);
const ALL_TECHNIQUES = ['still', 'viewSet', 'serverMesh', 'gpuRaycast', 'wasmMesh', 'baseline', 'auto'];
const TECHNIQUES = opt('--techs')?.split(',') ?? ALL_TECHNIQUES;
for (const t of TECHNIQUES) if (!ALL_TECHNIQUES.includes(t)) throw new Error(`--techs: unknown technique ${t} (${ALL_TECHNIQUES.join(', ')})`);

/**
 * Counts bytes received and reads the session socket (decisions, frame-rate
 * reports). `wire(path)`: the encoded size of a bench-served file (null for
 * others), counted instead of its raw body.
 */
async function meter(cdp, wire) {
  const m = { bytes: 0, decision: null, decisions: [], report: null, frameRates: [], seen: new Set(), urls: new Map(), received: [], socketBytes: 0 };
  await cdp.send('Network.enable');
  cdp.on('Network.requestWillBeSent', (e) => {
    m.seen.add(e.request.url);
    m.urls.set(e.requestId, e.request.url);
  });
  await cdp.send('Performance.enable');
  cdp.on('Network.loadingFinished', (e) => {
    // What the bytes were (results.json): the path and its encoded length.
    const url = m.urls.get(e.requestId);
    const path = url ? new URL(url).pathname : null;
    const n = (path && wire(path)) ?? e.encodedDataLength;
    m.bytes += n;
    if (path) m.received.push({ path, bytes: n });
  });
  cdp.on('Network.webSocketFrameReceived', (e) => {
    const p = e.response.payloadData ?? '';
    const n = e.response.opcode === 2 ? Math.floor((p.length * 3) / 4) : Buffer.byteLength(p);
    m.bytes += n;
    m.socketBytes += n;
    if (e.response.opcode === 2) return;
    if (p.startsWith('{"type":"decision"')) {
      try {
        m.decision = JSON.parse(p).decision ?? null;
        if (m.decision) m.decisions.push(m.decision);
      } catch {
        /* not JSON: not a decision */
      }
    }
  });
  cdp.on('Network.webSocketFrameSent', (e) => {
    const p = e.response.payloadData ?? '';
    // The client's last report: what the engine decided from.
    if (p.startsWith('{"type":"hello"') || p.startsWith('{"type":"report"')) {
      try {
        m.report = JSON.parse(p).report ?? m.report;
      } catch {
        /* not JSON */
      }
    }
    if (p.includes('"frameRate"')) {
      try {
        const msg = JSON.parse(p);
        if (msg.type === 'frameRate') m.frameRates.push({ ...msg, at: Date.now() });
      } catch {
        /* not JSON */
      }
    }
  });
  return m;
}

async function cpuMs(cdp) {
  const { metrics } = await cdp.send('Performance.getMetrics');
  const get = (n) => (metrics.find((x) => x.name === n)?.value ?? 0) * 1000;
  return { task: get('TaskDuration'), script: get('ScriptDuration') };
}

/** A scripted orbit: a horizontal drag across the viewer for ORBIT_MS. */
async function drag(page, box) {
  const y = box.y + box.height / 2;
  const x0 = box.x + box.width * 0.3;
  await page.mouse.move(x0, y);
  await page.mouse.down();
  const t0 = Date.now();
  let i = 0;
  while (Date.now() - t0 < ORBIT_MS) {
    i++;
    await page.mouse.move(x0 + ((i * 4) % (box.width * 0.4)), y + Math.sin(i / 10) * 10);
    await new Promise((r) => setTimeout(r, 16));
  }
  await page.mouse.up();
}

/** One case: a fresh context, the technique timed to its first non-blank frame, then an orbit. */
async function runCase(env, profile, link, model, source, params, tech) {
  const client = CLIENTS[profile.client];
  const browser = await env.browserFor(client);
  const size = client.size;
  let context = null;
  const run = async () => {
    context = await browser.newContext(client.context(size));
    const page = await context.newPage();
    await page.route('**/__bench/**', async (route) => {
      const name = new URL(route.request().url()).pathname.replace(/^\/__bench\//, '');
      const f = env.files.get(name);
      if (!f) return route.fulfill({ status: 404, body: name });
      // Bench-served code pays the link's cost as if it came over it, brotli-encoded like the studio's.
      if (link) await new Promise((r) => setTimeout(r, link.costMs(f.wire)));
      return route.fulfill({ body: f.body, contentType: f.type });
    });
    const cdp = await context.newCDPSession(page);
    const m = await meter(cdp, (path) => (path.startsWith('/__bench/') ? (env.files.get(path.slice('/__bench/'.length))?.wire ?? null) : null));
    // A dedicated worker's requests (frep.wasm for the kernel) are not in the
    // page's CDP Network domain: Playwright reports them, counted here once.
    page.on('requestfinished', async (req) => {
      if (m.seen.has(req.url())) return;
      const z = await req.sizes().catch(() => null);
      if (!z) return;
      m.bytes += z.responseBodySize + z.responseHeadersSize;
      m.received.push({ path: new URL(req.url()).pathname, bytes: z.responseBodySize + z.responseHeadersSize });
    });
    if (client.cpuRate) await cdp.send('Emulation.setCPUThrottlingRate', { rate: client.cpuRate });
    await page.goto(`${link ? link.url : env.url}/api/health`);
    await page.evaluate(async () => {
      document.body.replaceChildren();
      const s = document.createElement('script');
      s.type = 'module';
      s.src = '/__bench/harness.js';
      document.head.append(s);
      while (!('paperBench' in window)) await new Promise((r) => setTimeout(r, 5));
    });
    // A technique that draws with WebGL is not available on a client without it:
    // recorded as such at once, not after the case's timeout.
    if (NEEDS_WEBGL.has(tech) && !(await page.evaluate(() => !!document.createElement('canvas').getContext('webgl2')))) {
      throw new Error('not available: no WebGL2 on this client');
    }
    const forced = tech === 'auto' || tech === 'baseline' ? null : tech;
    if (tech !== 'baseline') await page.evaluate(([s, md]) => window.frepBench.mount(s, md), [size, forced]);
    m.bytes = 0;
    m.socketBytes = 0;
    m.received = [];
    const cpu0 = await cpuMs(cdp);
    const out = { tech };
    if (tech === 'baseline') {
      const r = await page.evaluate(([s, src, p, d]) => window.paperBench.baseline(s, src, p, d), [size, source, params, BASELINE_DEPTH]);
      Object.assign(out, { firstMs: r.ms, shown: 'baseline', triangles: r.triangles, meshMs: r.meshMs });
    } else {
      const r = await page.evaluate(([s, p, md, t]) => window.frepBench.open(s, p, md, t), [source, params, forced, CASE_MS - 10_000]);
      const d = r.decided ?? r.first;
      Object.assign(out, { firstMs: tech === 'auto' ? d.ms : r.first.ms, anyMs: r.first.ms, shown: d.mode, decidedReached: !!r.decided || tech !== 'auto' });
    }
    const cpu1 = await cpuMs(cdp);
    out.bytes = m.bytes;
    out.received = [...m.received, { path: '(session socket)', bytes: m.socketBytes }];
    out.cpuMs = cpu1.task - cpu0.task;
    out.scriptMs = cpu1.script - cpu0.script;
    const el = page.locator(tech === 'baseline' ? '[data-testid=baseline]' : '[data-testid=viewer]').first();
    const png = await el.screenshot({ timeout: 20_000 });
    out.pixels = await page.evaluate((b) => window.paperBench.pixels(b), png.toString('base64'));
    if (out.pixels.coverage < 0.005 || out.pixels.lumaStd < 2) throw new Error(`blank frame (coverage ${(100 * out.pixels.coverage).toFixed(2)} %, luma σ ${out.pixels.lumaStd.toFixed(1)})`);
    if (m.decision) out.decision = { mode: m.decision.mode, reason: m.decision.reason, predictions: m.decision.predictions, network: m.decision.network, trigger: m.decision.trigger };
    // Every decision and the client's report, for calibrating the engine (results.json).
    out.decisions = m.decisions.map((d) => ({ seq: d.seq, trigger: d.trigger, mode: d.mode, settings: d.settings, network: d.network, predictions: d.predictions }));
    out.report = m.report;
    // Orbit.
    if (tech === 'baseline') {
      const o = await page.evaluate((ms) => window.paperBench.orbitBaseline(ms), ORBIT_MS);
      out.orbitMs = o.meanMs;
      out.orbitMedianMs = o.frameMs;
    } else {
      m.frameRates = [];
      const box = await el.boundingBox();
      await drag(page, box);
      // The viewer reports its frame rate on the session every 2 s at most.
      await new Promise((r) => setTimeout(r, 1200));
      const mine = m.frameRates.filter((f) => f.mode === out.shown);
      // Time per frame is the mean interval (1000 / fps over the viewer's
      // window): pipelined server frames arrive in bursts, whose median gap
      // is far shorter than the time each new frame takes.
      const last = mine[mine.length - 1];
      out.orbitMs = last && last.fps > 0 ? 1000 / last.fps : null;
      out.orbitMedianMs = last ? last.frameMs : null;
    }
    return out;
  };
  try {
    return await bounded(run(), CASE_MS, `${profile.name} ${model} ${tech}`);
  } catch (e) {
    return { tech, error: String(e.message ?? e).split('\n')[0].slice(0, 200) };
  } finally {
    if (context) await context.close().catch(() => {});
  }
}

async function main() {
  const started = Date.now();
  const all = JSON.parse(readFileSync(PROFILES_FILE, 'utf8')).profiles;
  const profiles = QUICK ? all.filter((p) => p.quick) : all;
  for (const p of profiles) if (!CLIENTS[p.client]) throw new Error(`${PROFILES_FILE}: unknown client ${p.client} (${Object.keys(CLIENTS).join(', ')})`);
  const server = await startServer();
  const browsers = new Map();
  const links = new Map();
  const results = BASE ? [...BASE.results] : [];
  const shownProfiles = BASE ? [...BASE.profiles, ...profiles.filter((p) => !BASE.profiles.some((b) => b.name === p.name))] : profiles;
  const shownModels = BASE ? [...new Set([...BASE.models, ...MODELS])] : MODELS;
  // Each run a new a[1], also across a merged earlier run (no artefact from its cache).
  let counter = BASE ? BASE.results.reduce((n, c) => n + c.runs.length, 0) : 0;
  const save = (partial) => {
    if (!OUT) return;
    mkdirSync(join(OUT, 'paper'), { recursive: true });
    writeFileSync(join(OUT, 'paper', 'results.json'), JSON.stringify({ results, profiles: shownProfiles, models: shownModels, reps: REPS }, null, 1));
    writeReport(OUT, { results, profiles: shownProfiles, models: shownModels, reps: REPS, merged: !!BASE, quick: QUICK, caseMs: CASE_MS, baselineDepth: BASELINE_DEPTH, orbitMs: ORBIT_MS, elapsedS: (Date.now() - started) / 1000, partial, chromium: CHROMIUM });
  };
  try {
    const files = await bundle('paper-harness.ts');
    const env = {
      url: server.url,
      files,
      async browserFor(client) {
        const key = client.args.join(' ');
        if (!browsers.has(key)) browsers.set(key, await chromium.launch({ executablePath: CHROMIUM, args: [...CHROMIUM_ARGS, ...client.args], headless: true }));
        return browsers.get(key);
      },
    };
    // All links up front, models outermost: a run cut short still has every profile of the models done.
    for (const p of profiles) links.set(p.name, p.link ? await startLink(server.url, p.link) : null);
    for (const model of MODELS) {
      const source = readFileSync(join(repo, 'examples', `${model}.hf`), 'utf8');
      for (const profile of profiles) {
        const link = links.get(profile.name);
        for (const tech of TECHNIQUES) {
          const cell = { profile: profile.name, model, tech, runs: [] };
          for (let i = 0; i < REPS; i++) {
            // A new value of the unused a[1]: a new artefact (the server computes).
            const params = [1 + ++counter / 1000];
            cell.runs.push(await runCase(env, profile, link, model, source, params, tech));
          }
          const at = results.findIndex((c) => c.profile === cell.profile && c.model === cell.model && c.tech === cell.tech);
          if (at >= 0) results[at] = cell;
          else results.push(cell);
          const r = cell.runs[0];
          console.error(`[paper] ${profile.name} ${model} ${tech}: ${r.error ? `FAIL ${r.error}` : `${r.firstMs.toFixed(0)} ms shown ${r.shown}, ${(r.bytes / 1024).toFixed(0)} KB, cpu ${r.cpuMs.toFixed(0)} ms, orbit ${r.orbitMs?.toFixed?.(0) ?? '–'} ms/frame`}`);
        }
      }
      save(true);
    }
  } finally {
    for (const l of links.values()) if (l) await l.stop();
    for (const b of browsers.values()) await b.close().catch(() => {});
    await server.stop();
  }
  save(false);
  const failed = results.flatMap((c) => c.runs.filter((r) => r.error).map((r) => `${c.profile} ${c.model} ${c.tech}: ${r.error}`));
  console.error(`[paper] ${results.length} cells in ${((Date.now() - started) / 1000).toFixed(0)} s, ${failed.length} failed run(s)${OUT ? `; wrote ${join(OUT, 'paper.md')}` : ''}`);
  for (const f of failed) console.error(`[paper] FAILED ${f}`);
  // --quick is the CI check: every case must have shown a non-blank frame.
  if (QUICK && failed.length) process.exit(1);
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
